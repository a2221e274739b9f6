"""Outputs per rail in a switch-and-crossing zone (issue 29): which rail of a side carries each
contact point, and the wheel-rail forces, contact position and wear number per rail.

A side with a variable profile has two rails per panel in railexu's S&C zones: rail 1 on the
gauge side and rail 2 on the field side in the rail's own axes (field side positive), named by
the slices (``ProfileSlices.rail_names``): in a common crossing rail 1 the **nose** and rail 2
the **wing rail**, in a switch panel the **blade** and the **stock rail**, on the other side of a
crossing the **check rail** and the **stock rail**; between a zone's panels the plain rail
counts as rail 2 (the running rail). A point's rail is the one that carries it in the slices
(:mod:`railexu.profiles.variable.rails`): each point of the slices' curves is labelled with its
rail (the parts before and after a *boundary feature*, which parts a side's two rails along the
whole panel; else separate curves, or the two sides of a single curve's deepest point), and a
contact point belongs to the rail whose surface is the top one at its lateral position, at the
station along the effective section (``|x| <= x_max``) where the wheel's circle meets the
rails (``carrier_rails``). So past the wing rail's end the nose's widened field side is the
nose's, and a rising nose touched ahead of the axle is the nose's.

Approximations (stated): the stations searched lie on a 5 mm grid along the track and the top
surface is read every 0.1 mm laterally (a point within 0.05 mm of where two rails meet may be
given to the other); the contact's lateral position is taken in the placed rail's axes without
undoing the rail's cant (exact for the S&C benchmark's pre-canted and upright rails; < 1 mm at
1:40 for points up to 40 mm below the top).
"""

from __future__ import annotations

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.placement import WheelsetGeometry
from railexu.profiles.variable.rails import PLAIN_NAMES, carrier_rails, panel_at
from railexu.track.variable_rails import VariableRails

#: Rails per side and panel in an S&C zone's outputs (rail 1 gauge side, rail 2 field side).
N_RAILS = 2
_SIDES = ("left", "right")


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
        ``ws{i}_{side}_rail{r}_{Q_N, Y_N, Tgamma_N, contact_y_m}`` for ``r`` = 1 (nose, blade,
        check rail), 2 (wing rail, stock rail; the plain rail between panels): the vertical and
        lateral force of the rail on the wheel (track axes), the wear number
        ``sum |Fx xi + Fy eta|`` (Pearce and Sherratt 1991) and the vertical-force-weighted
        lateral contact position in the profile's axes (0 where the rail carries no load: read
        it where ``..._Q_N > 0``); ``ws{i}_{side}_in_zone``: 1 where the wheelset is in the
        zone (its first to last slice, where the model reads the stations' tables), 0 outside,
        where every per-rail column is 0 and the side's totals (``..._Q_N``) on the track's
        plain rail apply; ``ws{i}_{side}_panel``: the panel the wheelset's axle is in (1, 2,
        ... as ``railexu.profiles.variable.rails.panel_names``; 0 outside the panels or the
        zone). No NaN: a non-finite value marks a diverged run
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
        # every station_step, the last at or before the side's last slice; with parts of their
        # own step, the zone's last station at or before the side's last slice: the zone's
        # stations serve both sides, whose slices may end apart); the plain rail outside
        last = lo + max(np.floor((hi - lo) / rails.station_step_m), 1.0) * rails.station_step_m
        if not rails.uniform:
            stations = rails.stations_m() - rails.start_m
            last = float(stations[stations <= hi + 1e-9][-1])
        inside = (s_rel >= lo) & (s_rel <= last)
        which = np.zeros((n, n_ws, K.MAX_POINTS), dtype=np.int64)
        ask = loaded[:, :, side] & inside[:, :, None]
        s_pts = np.broadcast_to(s_rel[:, :, None], ask.shape)[ask]
        radius = points[:, :, side, :, K.PF_RADIUS][ask]
        which[ask], carried_at = carrier_rails(profile, s_pts, y_rail[ask], radius,
                                               rails.x_max_m, with_station=True)  # fmt: skip
        # the panel whose rails carry the wheel: the carrying station's of its most loaded
        # point (a point carried past a panel's last slice is the plain rail's), else the axle's
        station = np.full(ask.shape, np.nan)
        station[ask] = carried_at
        load = np.where(ask, points[:, :, side, :, K.PF_FTZ], -np.inf)
        top = np.argmax(load, axis=-1)[..., None]
        has = np.isfinite(np.take_along_axis(load, top, axis=-1)[..., 0])
        top_s = np.take_along_axis(station, top, axis=-1)[..., 0]
        panel = panel_at(profile, np.where(has, top_s, s_rel))
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
            cols[f"ws{i + 1}_{_SIDES[side]}_panel"] = np.where(inside[:, i], panel[:, i], 0.0)
    return cols


def crossing_summary(
    columns,
    zone_m: tuple[float, float] | None,
    n_ws: int,
    panels: dict[str, list[dict[str, object]]] | None = None,
) -> dict[str, object]:
    """The S&C quantities of a run per wheelset and side with outputs per rail
    (``columns``: a :class:`~railexu.simulation.timeseries.TimeSeries` or a dict of arrays):

    - ``max_Q_N``, ``max_Q_at_m``, ``max_Q_rail``: the largest vertical force of one rail on
      the wheel (the impact at the crossing), the wheelset's track distance there and the rail
      (1 the gauge side's: nose, blade, check rail; 2 the other: wing rail, stock rail);
    - ``transfer_at_m``: where rail 1's share of the side's vertical force first crosses
      50 % (the nose's), interpolated linearly between outputs (None where it does not);
    - ``Tgamma_max_N``: the largest wear number per rail (rails 1, 2);
    - with ``panels`` (per side ``railexu.profiles.variable.rails.panel_names``) and the
      ``..._panel`` column: ``rails``,
      per panel the wheel passed and per rail of it its name, the largest Q on it [N] and the
      wheelset's track distance there [m]; ``max_Q_rail_name`` the name of the rail with the
      largest Q.

    Window: the output times at which the per-rail columns are defined (the wheelset between the
    zone's first and last slice: ``window``); per panel, the times the wheelset is in it.
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
            if panels is not None and side in panels and f"{key}_panel" in names:
                panel = np.rint(np.asarray(columns[f"{key}_panel"])[win]).astype(np.int64)
                out[key].update(_per_rail(panels[side], panel, q, s[win], int(k[0]), k[1]))
    return out


def _per_rail(panels, panel, q, s, r_max: int, t_max: int) -> dict[str, object]:
    """Per panel the wheel passed and per named rail: its name, largest Q [N] and where [m]."""
    rails = []
    for p in np.unique(panel):
        at = panel == p
        for r, name in enumerate(panels[p]["rails"]):
            if name == PLAIN_NAMES[0]:
                continue
            j = int(np.argmax(np.where(at, q[r], -np.inf)))
            rails.append({"panel": int(p), "source": panels[p]["source"], "rail": name,
                          "column": f"rail{r + 1}", "max_Q_N": float(q[r, j]),
                          "max_Q_at_m": float(s[j])})  # fmt: skip
    return {"rails": rails, "max_Q_rail_name": panels[panel[t_max]]["rails"][r_max]}


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
