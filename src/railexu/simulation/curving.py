"""Curving quantities of a run: track data along the run, quasi-static values in each curve.

- :func:`track_columns`: curvature, cant, cant deficiency and uncompensated lateral acceleration
  at the leading wheelset, as time-series columns;
- :func:`curving_statistics`: for every constant-radius part of the track, the quasi-static
  values of each wheelset (the 50 % value over the samples while the wheelset runs through it,
  as EN 14363:2016, 7.6, defines them for the quasi-static assessment) and the maxima.

Definitions (EN 13803:2017, 3 and 6): with the cant base ``b`` (1.5 m), the cant ``D`` and the
radius ``R``, the cant deficiency is ``I = b V^2 / (g R) - D`` and the uncompensated lateral
acceleration in the track plane ``a_q = V^2 / R cos(phi) - g sin(phi)``, ``sin(phi) = D / b``;
both are positive when the vehicle runs faster than the balance speed (towards the outside of the
curve), negative for a cant excess, zero on straight track.

Sign of the forces in the curve statistics: ``Y`` is the lateral force of the rail on the wheel
in the track plane, positive **towards the centre of the curve**; ``Q`` the vertical force;
``outer`` and ``inner`` are the wheels on the outer and inner rail.
"""

from __future__ import annotations

import numpy as np

from railexu.track.alignment import Alignment


def track_columns(
    alignment: Alignment, s_m: np.ndarray, speed_m_per_s: np.ndarray, gravity_m_per_s2: float
) -> dict[str, np.ndarray]:
    """Time-series columns of the track at the distances ``s_m`` (the leading wheelset's)."""
    kappa = alignment.curvature(s_m)
    cant = alignment.cant(s_m)
    sign = np.sign(kappa)
    v2k = np.asarray(speed_m_per_s) ** 2 * np.abs(kappa)
    sin_phi = np.clip(np.abs(cant) / alignment.cant_base_m, 0.0, 1.0)
    return {
        "track_curvature_1_per_m": kappa,
        "track_cant_m": cant,
        "cant_deficiency_m": np.where(
            sign != 0.0,
            alignment.cant_base_m * v2k / gravity_m_per_s2 - np.abs(cant),
            0.0,
        ),
        "uncompensated_lateral_acceleration_m_per_s2": np.where(
            sign != 0.0, v2k * np.sqrt(1.0 - sin_phi**2) - gravity_m_per_s2 * sin_phi, 0.0
        ),
    }


_RULE = (
    "per wheelset and constant-radius curve: quasi_static is the 50 % value (median) of the "
    "unfiltered samples while the wheelset is on the constant-radius part and inside the "
    "evaluation window (EN 14363:2016, 7.6); max and min are the extremes of the same samples"
)


def _stats(values: np.ndarray) -> dict[str, float]:
    return {"quasi_static": float(np.median(values)), "max": float(np.max(values)),
            "min": float(np.min(values))}  # fmt: skip


def curving_statistics(
    ts,
    alignment: Alignment,
    wheelset_names: list[str],
    window: tuple[float, float, str] | None = None,
) -> dict:
    """Quasi-static values (50 %) and extremes of each wheelset in each constant-radius curve.

    Only the samples in the run's evaluation window count (the window of every other statistic
    of the run: by default the start-up transient of the first 20 m is left out), so that a run
    started inside a curve does not mix its start-up into the curve's quasi-static values.

    Args:
        ts: the run's :class:`railexu.results.TimeSeries` (columns ``distance_m``,
            ``ws{i}_s_m``, ``..._Y_N``, ``..._Q_N``, ``..._Tgamma_N``, ``ws{i}_yaw_rad``,
            ``ws{i}_lateral_m``).
        alignment: the track's design geometry.
        wheelset_names: names of ``ws1``, ``ws2``, ... (front to rear).
        window: the evaluation window ``(from_m, to_m, rule)`` in distance travelled [m]; None
            for the whole run.

    Returns:
        ``{"curves": [{start_m, end_m, radius_m, cant_m, direction, cant_deficiency_m,
        wheelsets: [{name, samples, covered_m, Y_outer_N, Y_inner_N, Q_outer_N, Q_inner_N, sum_Y_N,
        Y_over_Q_outer, Tgamma_outer_N, Tgamma_inner_N, angle_of_attack_rad, lateral_m}]}],
        geometry}`` where each quantity is ``{quasi_static, max, min}``; a curve the run did
        not reach has no wheelset entries; ``covered_m`` is the length of the curve's
        constant-radius part the counted samples cover; ``geometry`` is
        :meth:`Alignment.to_dict`; ``window`` and ``rule`` say which samples and which rule.
    """
    cols = ts.columns
    speed = cols.get("speed_m_per_s")
    travelled = cols["distance_m"]
    if window is None:
        counted = np.ones(travelled.size, dtype=bool)
        window_dict = {"from_m": None, "to_m": None, "rule": "the whole run"}
    else:
        counted = (travelled >= window[0]) & (travelled <= window[1])
        window_dict = {"from_m": float(window[0]), "to_m": float(window[1]), "rule": window[2]}
    curves = []
    for sec in alignment.constant_curves():
        left = sec.curvature_1_per_m > 0.0
        inward = 1.0 if left else -1.0  # +y is towards the centre of a left curve
        outer, inner = ("right", "left") if left else ("left", "right")
        entry = {
            "start_m": sec.start_m,
            "end_m": sec.end_m,
            "radius_m": sec.radius_m,
            "cant_m": abs(sec.cant_m),
            "direction": "left" if left else "right",
            "wheelsets": [],
        }
        for i, name in enumerate(wheelset_names, start=1):
            s = cols[f"ws{i}_s_m"]
            inside = (s >= sec.start_m) & (s <= sec.end_m) & counted
            if not np.any(inside):
                continue
            y_out = inward * cols[f"ws{i}_{outer}_Y_N"][inside]
            y_in = inward * cols[f"ws{i}_{inner}_Y_N"][inside]
            q_out = cols[f"ws{i}_{outer}_Q_N"][inside]
            q_in = cols[f"ws{i}_{inner}_Q_N"][inside]
            entry["wheelsets"].append(
                {
                    "name": name,
                    "samples": int(np.sum(inside)),
                    "covered_m": float(np.max(s[inside]) - np.min(s[inside])),
                    "Y_outer_N": _stats(y_out),
                    "Y_inner_N": _stats(y_in),
                    "Q_outer_N": _stats(q_out),
                    "Q_inner_N": _stats(q_in),
                    "sum_Y_N": _stats(y_out + y_in),
                    "Y_over_Q_outer": _stats(np.abs(y_out) / np.maximum(q_out, 1.0)),
                    "Tgamma_outer_N": _stats(cols[f"ws{i}_{outer}_Tgamma_N"][inside]),
                    "Tgamma_inner_N": _stats(cols[f"ws{i}_{inner}_Tgamma_N"][inside]),
                    "angle_of_attack_rad": _stats(-inward * cols[f"ws{i}_yaw_rad"][inside]),
                    "lateral_m": _stats(-inward * cols[f"ws{i}_lateral_m"][inside]),
                }
            )
        if entry["wheelsets"]:
            mask = (cols["ws1_s_m"] >= sec.start_m) & (cols["ws1_s_m"] <= sec.end_m) & counted
            if not np.any(mask):  # the leading wheelset left the curve before the window
                mask = (cols["ws1_s_m"] >= sec.start_m) & (cols["ws1_s_m"] <= sec.end_m)
            v = float(np.median(speed[mask])) if speed is not None else None
            entry["cant_deficiency_m"] = float(np.median(cols["cant_deficiency_m"][mask]))
            if v is not None:
                entry["speed_m_per_s"] = v
        curves.append(entry)
    return {
        "sign_convention": "Y towards the curve centre, lateral towards the outer rail, "
        "angle of attack positive when the wheelset points to the outside",
        "window": window_dict,
        "rule": _RULE,
        "curves": curves,
        # the design geometry itself, so that `railexu plot` redraws the track and curving
        # figures from the run folder alone (railexu.track.alignment.alignment_from_record)
        "geometry": alignment.to_dict(),
    }
