"""Outputs per rail in a switch-and-crossing zone (issue 29): which rail of a side carries each
contact point, and the wheel-rail forces, contact position and wear number per rail.

A side with a variable profile has two rails in railexu's S&C zones: rail 1 and rail 2 in lateral
order in the rail's own axes (field side positive), i.e. for the through route of a common
crossing rail 1 the **nose** (gauge side of the flangeway) and rail 2 the **wing rail**. A contact
point belongs to the rail on its side of the flangeway's bottom at the wheelset's track position:
the rails are the profile's separate curves there, or the two sides of the deepest point of its
one curve (CONTACT's files give nose and wing rail as one curve through the flangeway;
:func:`railexu.contact.variable_rail.patches_at` attributes its patches the same way).

Approximations (stated): the attribution uses the section at the wheelset's axle, while a patch
may lie up to the effective section's half-length ahead of it (46 mm on a 1:10 nose: the
flangeway moves ~5 mm laterally over that at 1:9.25, against a flangeway ~40 mm wide); the
contact's lateral position is taken in the placed rail's axes without undoing the rail's cant
(exact for the S&C benchmark's pre-canted rail; < 1 mm at 1:40 for points up to 40 mm below the
top).
"""

from __future__ import annotations

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.placement import WheelsetGeometry
from railexu.profiles.variable import VariableProfile
from railexu.track.variable_rails import VariableRails

#: Rails per side in an S&C zone's outputs (nose and wing rail; a check rail is not yet modelled).
N_RAILS = 2
_SIDES = ("left", "right")


def rail_index(profile: VariableProfile, s_m: float, y_m: np.ndarray) -> np.ndarray:
    """Index (0, 1) of the rail under lateral positions ``y_m`` [m] (the profile's axes) at the
    profile's position ``s_m`` [m]: with a boundary feature (:func:`boundary_feature`: the
    nose's end and the wing rail's start of a whole crossing), the parts before it are rail 0
    and those after it rail 1 (a slice with the wing rail or the nose alone is that rail);
    else separate curves in lateral order (0 the first, 1 any later one), or the two sides of
    the deepest point (z down) of a single curve."""
    y = np.asarray(y_m, dtype=float)
    k = boundary_feature(profile)
    if k is not None:
        after = [pts[0, 0] for p, pts in profile.parts_at(s_m) if p >= k]
        return (y >= (min(after) if after else np.inf)).astype(np.int64)
    curves = profile.curves_at(s_m)
    if len(curves) > 1:
        split = 0.5 * (curves[0][-1, 0] + curves[1][0, 0])
    else:
        c = curves[0]
        split = c[int(np.argmax(c[:, 1]))][0]
    return (y > split).astype(np.int64)


def boundary_feature(profile: VariableProfile) -> int | None:
    """The feature that parts a side's two rails along the whole zone, or None: one present
    in every slice, with parts before and after it somewhere, and some slice without any part
    before it or without any part after it (in either direction of travel: the wing rail alone
    before a crossing's nose starts, the nose alone after the wing rail ends:
    ``tracks/uk_crossing/uk_crossing_full.yaml``, CONTACT's ``uk_interrupt_v2.slcs``)."""
    f = profile.slices.features_m
    if f is None:
        return None
    have = np.isfinite(f)
    for k in range(1, f.shape[1] - 1):
        before, after = have[:, :k], have[:, k + 1 :]
        parts = have[:, k].all() and before.any() and after.any()
        if parts and (not before.any(axis=1).all() or not after.any(axis=1).all()):
            return k
    return None


def sc_columns(
    rails: VariableRails | None,
    geometry: WheelsetGeometry,
    points: np.ndarray,
    s_ws_m: np.ndarray,
) -> dict[str, np.ndarray]:
    """Time-series columns per rail of the sides with a variable profile (none without a zone).

    Args:
        rails: the track's S&C zone.
        geometry: the wheelsets' placement (the placed rail's origin when the zone gives none).
        points: the kernel's contact points, ``(n, n_ws, 2, MAX_POINTS, N_POINT_FIELDS)``.
        s_ws_m: the wheelsets' track distances, ``(n, n_ws)`` [m].

    Returns:
        ``ws{i}_{side}_rail{r}_{Q_N, Y_N, Tgamma_N, contact_y_m}`` for ``r`` = 1 (nose), 2 (wing
        rail): the vertical and lateral force of the rail on the wheel (track axes), the wear
        number ``sum |Fx xi + Fy eta|`` (Pearce and Sherratt 1991) and the vertical-force-weighted
        lateral contact position in the profile's axes (0 where the rail carries no load: read
        it where ``..._Q_N > 0``); and ``ws{i}_{side}_in_zone``: 1 where the wheelset is in the
        zone (its first to last slice, where the model reads the stations' tables), 0 outside,
        where every per-rail column is 0 and the side's totals (``..._Q_N``) on the track's
        plain rail apply. No NaN: a non-finite value marks a diverged run
        (:func:`railexu.results.evaluate._finite_rows` ends the summary's window there).
    """
    if rails is None:
        return {}
    n, n_ws = s_ws_m.shape
    loaded = points[..., K.PF_N] > 0.0
    power = (
        points[..., K.PF_FX] * points[..., K.PF_XI] + points[..., K.PF_FY] * points[..., K.PF_ETA]
    )
    cols: dict[str, np.ndarray] = {}
    for side, profile in enumerate(rails.sides()):
        if profile is None:
            continue
        pair = geometry.pairs[side]
        origin_y = (
            pair.rail_origin_track_m if rails.rail_origin_m is None else rails.rail_origin_m
        )[0]
        lo, hi = profile.s_range_m
        y_rail = points[:, :, side, :, K.PF_YRAIL] - origin_y
        s_rel = s_ws_m - rails.start_m
        # where the model reads the stations' tables (model/sc_tables.py: first slice onwards,
        # every station_step, the last at or before the last slice); the plain rail outside
        last = lo + max(np.floor((hi - lo) / rails.station_step_m), 1.0) * rails.station_step_m
        inside = (s_rel >= lo) & (s_rel <= last)
        which = np.zeros((n, n_ws, K.MAX_POINTS), dtype=np.int64)
        for t in range(n):
            for i in range(n_ws):
                s = min(max(float(s_rel[t, i]), lo), hi)
                which[t, i] = rail_index(profile, s, y_rail[t, i])
        for r in range(N_RAILS):
            on = loaded[:, :, side] & (which == r)
            q = np.where(on, points[:, :, side, :, K.PF_FTZ], 0.0)
            y = np.where(on, points[:, :, side, :, K.PF_FTY], 0.0)
            tg = np.abs(np.where(on, power[:, :, side], 0.0))
            q_sum = q.sum(axis=-1)
            with np.errstate(invalid="ignore", divide="ignore"):
                pos = np.where(q_sum > 0.0, (q * y_rail).sum(axis=-1) / q_sum, 0.0)
            for i in range(n_ws):
                key = f"ws{i + 1}_{_SIDES[side]}_rail{r + 1}"
                out = inside[:, i]
                cols[f"{key}_Q_N"] = np.where(out, q_sum[:, i], 0.0)
                cols[f"{key}_Y_N"] = np.where(out, y.sum(axis=-1)[:, i], 0.0)
                cols[f"{key}_Tgamma_N"] = np.where(out, tg.sum(axis=-1)[:, i], 0.0)
                cols[f"{key}_contact_y_m"] = np.where(out & (q_sum[:, i] > 0.0), pos[:, i], 0.0)
        for i in range(n_ws):
            cols[f"ws{i + 1}_{_SIDES[side]}_in_zone"] = inside[:, i].astype(float)
    return cols


def crossing_summary(columns, zone_m: tuple[float, float] | None, n_ws: int) -> dict[str, object]:
    """The S&C quantities of a run per wheelset and side with outputs per rail
    (``columns``: a :class:`~railexu.simulation.timeseries.TimeSeries` or a dict of arrays):

    - ``max_Q_N``, ``max_Q_at_m``, ``max_Q_rail``: the largest vertical force of one rail on
      the wheel (the impact at the crossing), the wheelset's track distance there and the rail
      (1 nose, 2 wing rail);
    - ``transfer_at_m``: where the nose's share of the side's vertical force first crosses
      50 %, interpolated linearly between outputs (None where it does not);
    - ``Tgamma_max_N``: the largest wear number per rail (rails 1, 2).

    Window: the output times at which the per-rail columns are defined (the wheelset between the
    zone's first and last slice: ``window``).
    """
    if zone_m is None:
        return {}
    lo, hi = zone_m
    names = set(columns.names if hasattr(columns, "names") else columns)
    out: dict[str, object] = {
        "zone_m": [lo, hi],
        "window": "wheelset between the zone's first and last slice",
    }
    for i in range(n_ws):
        for side in _SIDES:
            key = f"ws{i + 1}_{side}"
            if f"{key}_in_zone" not in names:
                continue
            s = np.asarray(columns[f"ws{i + 1}_s_m"])
            win = np.asarray(columns[f"{key}_in_zone"]) > 0.5
            if not np.any(win):
                continue
            q = np.stack([np.asarray(columns[f"{key}_rail{r + 1}_Q_N"])[win] for r in range(2)])
            k = np.unravel_index(int(np.argmax(q)), q.shape)
            total = q.sum(axis=0)
            with np.errstate(invalid="ignore", divide="ignore"):
                share = np.where(total > 0.0, q[0] / total, np.nan)
            out[key] = {
                "max_Q_N": float(q[k]),
                "max_Q_at_m": float(s[win][k[1]]),
                "max_Q_rail": int(k[0]) + 1,
                "transfer_at_m": _crossing_point(s[win], share),
                "Tgamma_max_N": [
                    float(np.max(np.asarray(columns[f"{key}_rail{r + 1}_Tgamma_N"])[win]))
                    for r in range(2)
                ],
            }
    return out


def _crossing_point(s: np.ndarray, share: np.ndarray) -> float | None:
    """Track distance where ``share`` crosses 0.5 (the first crossing), interpolated."""
    ok = np.isfinite(share)
    s, share = s[ok], share[ok]
    above = share >= 0.5
    change = np.nonzero(above[1:] != above[:-1])[0]
    if change.size == 0:
        return None
    j = int(change[0])
    a, b = share[j], share[j + 1]
    return float(s[j] + (0.5 - a) / (b - a) * (s[j + 1] - s[j]))
