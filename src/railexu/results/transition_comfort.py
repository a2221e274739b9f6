"""EN 12299 comfort on curve transitions (P_CT) of a run, per transition of its track.

A transition is a piece of the track's design geometry whose curvature or cant changes
(:class:`~railexu.track.alignment.Alignment`: ``dk`` or ``dc`` non-zero). For each transition
and each measurement point on the car body, the point's times of passing the transition's
start and end (its distance along the track: the leading wheelset's ``ws1_s_m`` less the
point's distance behind it) set the windows of
:func:`railexu.assessment.curve_transition.transition_comfort`. The lateral acceleration is the
point's accelerometer reading (``{point}_acc_y_m_per_s2``); the roll velocity is the time
derivative of the body's absolute roll, its roll relative to the track
(``{body}_roll_rel_track_rad``) plus the track's cant angle under its centre. A transition that
a point does not pass completely (with the 1.6 s after it) within the record is left out, with
a note.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railexu.assessment.curve_transition import PCT_CLAUSE, PctParameters, transition_comfort
from railexu.track.alignment import Alignment


@dataclass(frozen=True)
class PointPlacement:
    """Where a measurement point sits: its body and the distances (m) of the point and of the
    body's centre behind the leading wheelset, along the track."""

    point: str
    body: str
    point_behind_m: float
    body_behind_m: float


def transitions(alignment: Alignment) -> list[tuple[float, float]]:
    """``(start_m, end_m)`` of every piece of ``alignment`` whose curvature or cant changes."""
    out = []
    for i in range(alignment.start.size):
        if alignment.dk[i] != 0.0 or alignment.dc[i] != 0.0:
            start = float(alignment.start[i])
            out.append((start, start + float(alignment.length[i])))
    return out


def _passing_time(t: np.ndarray, s: np.ndarray, s_m: float) -> float | None:
    """Time at which the distance ``s`` (non-decreasing) reaches ``s_m``; None outside."""
    if s.size == 0 or s_m < s[0] or s_m > s[-1]:
        return None
    return float(np.interp(s_m, s, t))


def curve_transition_comfort(
    ts,
    alignment: Alignment,
    placements: list[PointPlacement],
    parameters: PctParameters | None = None,
) -> dict:
    """P_CT per transition of ``alignment`` and per placed point of the time series ``ts``
    (rows up to the first non-finite value). Returns ``{"transitions": [...], "clause",
    "assumption", "notes"}``; each transition has ``start_m``, ``end_m``, ``points`` and the
    largest ``P_CT_standing_percent`` / ``P_CT_seated_percent`` over its points."""
    p = parameters or PctParameters()
    out: dict = {"transitions": [], "clause": PCT_CLAUSE, "assumption": p.assumption,
                 "notes": []}  # fmt: skip
    if "ws1_s_m" not in ts:
        out["notes"].append("no ws1_s_m column: the transitions cannot be located")
        return out
    t_all, s_all = np.asarray(ts.time_s, float), np.asarray(ts["ws1_s_m"], float)
    finite = np.isfinite(t_all) & np.isfinite(s_all)
    n = int(np.argmin(finite)) if not np.all(finite) else t_all.size
    t, s_lead = t_all[:n], s_all[:n]
    for start_m, end_m in transitions(alignment):
        entry = {"start_m": start_m, "end_m": end_m, "points": {}}
        for pl in placements:
            acc, roll = f"{pl.point}_acc_y_m_per_s2", f"{pl.body}_roll_rel_track_rad"
            if acc not in ts or roll not in ts:
                continue
            s_point = s_lead - pl.point_behind_m
            t0, t1 = _passing_time(t, s_point, start_m), _passing_time(t, s_point, end_m)
            if t0 is None or t1 is None or t1 + p.after_end_s > t[-1]:
                out["notes"].append(
                    f"{pl.point} does not pass the transition {start_m:g}-{end_m:g} m (and "
                    f"{p.after_end_s:g} s after it) within the record: left out"
                )
                continue
            s_body = s_lead - pl.body_behind_m
            absolute_roll = np.asarray(ts[roll], float)[:n] + alignment.cant_angle(s_body)
            result = transition_comfort(
                pl.point, t, np.asarray(ts[acc], float)[:n], np.gradient(absolute_roll, t),
                t0, t1, p,
            )  # fmt: skip
            entry["points"][pl.point] = result.to_dict()
        if entry["points"]:
            for key in ("P_CT_standing_percent", "P_CT_seated_percent"):
                entry[key] = max(v[key] for v in entry["points"].values())
            out["transitions"].append(entry)
    return out
