"""Outputs per rail in a switch-and-crossing zone (issue 29): which rail of a side carries each
contact point, and the wheel-rail forces, contact position and wear number per rail.

A side with a variable profile has two rails per panel in railexu's S&C zones: rail 1 on the
gauge side and rail 2 on the field side in the rail's own axes (field side positive), named by
the slices (``ProfileSlices.rail_names``): in a common crossing rail 1 the **nose** and rail 2
the **wing rail**, in a switch panel the **blade** and the **stock rail**, on the other side of a
crossing the **check rail** and the **stock rail**; between a zone's panels the plain rail
counts as rail 2 (the running rail). A point's rail is the one that carries it in the slices:
each point of the slices' curves is labelled with its rail (:func:`labelled_curves`: the parts
before and after a *boundary feature*, which parts a side's two rails along the whole panel;
else separate curves, or the two sides of a single curve's deepest point), and a contact point
belongs to the rail whose surface is the top one at its lateral position, at the station along
the effective section (``|x| <= x_max``) where the wheel's circle meets the rails
(:func:`carrier_rails`). So past the wing rail's end the nose's widened field side is the
nose's, and a rising nose touched ahead of the axle is the nose's.

Approximations (stated): the stations searched lie on a 5 mm grid along the track and the top
surface is read every 0.1 mm laterally (a point within 0.05 mm of where two rails meet may be
given to the other); the contact's lateral position is taken in the placed rail's axes without
undoing the rail's cant (exact for the S&C benchmark's pre-canted and upright rails; < 1 mm at
1:40 for points up to 40 mm below the top).
"""

from __future__ import annotations

import functools

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.placement import WheelsetGeometry
from railexu.profiles.variable import VariableProfile
from railexu.profiles.variable.zoned import ZonedProfile
from railexu.track.variable_rails import VariableRails

#: Rails per side and panel in an S&C zone's outputs (rail 1 gauge side, rail 2 field side).
N_RAILS = 2
_SIDES = ("left", "right")


#: Names of the rails of the plain rail between a zone's panels (no second rail there; its load
#: is the running rail's, rail 2, as the crossing's wing rail and the switch's stock rail).
PLAIN_NAMES = ("none", "plain rail")
#: Names where the slices do not name their rails.
DEFAULT_NAMES = ("rail 1", "rail 2")
#: Step along the track of the stations searched for the one that carries a point [m].
CARRIER_STEP_M = 0.005
#: Lateral step at which the carrier search reads the rails' top surface [m].
CARRIER_DY_M = 1.0e-4


def rail_index(profile: VariableProfile | ZonedProfile, s_m: float, y_m: np.ndarray) -> np.ndarray:
    """Index (0, 1) of the rail whose surface is the top one at lateral positions ``y_m`` [m]
    (the profile's axes) at the profile's position ``s_m`` [m] (:func:`labelled_curves`: each
    point of the slices' curves labelled with its rail); where no rail lies over ``y``, the
    rail nearest laterally."""
    y = np.atleast_1d(np.asarray(y_m, dtype=float))
    curves = labelled_curves(profile, float(s_m))
    _, which = _top(curves, y)
    return np.where(which < 0, _nearest(curves, y), which)


def carrier_rails(
    profile: VariableProfile | ZonedProfile,
    s_m: np.ndarray,
    y_m: np.ndarray,
    radius_m: np.ndarray,
    x_max_m: float,
) -> np.ndarray:
    """Index (0, 1) of the rail that carries each contact point of a wheel: axle at the
    profile's position ``s_m`` [m], point at lateral ``y_m`` [m] (the profile's axes), wheel
    radius there ``radius_m`` [m] (arrays of one length). The wheel's circle over ``y`` meets
    the rails' top surface (:func:`rail_index`) at the station ``s + x``, ``|x| <= x_max_m``,
    where that surface rises highest above the circle's drop ``r - sqrt(r^2 - x^2)``: the
    effective section's envelope (``railexu.contact.variable_tables``, the table the kernel
    found the point on; a rising nose is touched ~ 46 mm ahead of the axle). The stations are
    those of a grid every :data:`CARRIER_STEP_M` along the track, the top surface is read every
    :data:`CARRIER_DY_M` laterally (the point's nearest); where no rail lies over ``y`` at any
    station searched, the rail nearest laterally at the station nearest the axle."""
    s = np.asarray(s_m, dtype=float).ravel()
    y = np.asarray(y_m, dtype=float).ravel()
    r = np.asarray(radius_m, dtype=float).ravel()
    if s.size == 0:
        return np.zeros(0, dtype=np.int64)
    y_grid = np.arange(y.min() - CARRIER_DY_M, y.max() + 1.5 * CARRIER_DY_M, CARRIER_DY_M)
    j = np.clip(np.rint((y - y_grid[0]) / CARRIER_DY_M).astype(np.int64), 0, y_grid.size - 1)
    n = int(np.floor(x_max_m / CARRIER_STEP_M + 1e-9))
    station = np.rint(s / CARRIER_STEP_M).astype(np.int64)[:, None] + np.arange(-n, n + 1)
    unique, inverse = np.unique(station, return_inverse=True)
    inverse = inverse.reshape(station.shape)
    z_tab = np.empty((unique.size, y_grid.size))
    lab_tab = np.empty((unique.size, y_grid.size), dtype=np.int8)
    for u, g in enumerate(unique):
        curves = labelled_curves(profile, float(g) * CARRIER_STEP_M)
        z_tab[u], lab = _top(curves, y_grid)
        lab_tab[u] = np.where(lab < 0, _nearest(curves, y_grid), lab) if np.any(lab < 0) else lab
    x = station * CARRIER_STEP_M - s[:, None]
    rr = r[:, None]
    drop = rr - np.sqrt(np.maximum(rr * rr - x * x, 0.0))
    score = z_tab[inverse, j[:, None]] + drop  # z down: smallest = highest above the circle
    score = np.where(np.abs(x) <= x_max_m + 0.5 * CARRIER_STEP_M, score, np.inf)
    k = np.argmin(score, axis=1)
    rows = np.arange(s.size)
    which = lab_tab[inverse[rows, k], j]
    axle = lab_tab[inverse[rows, n], j]  # the station nearest the axle (x within a half step)
    return np.where(np.isfinite(score[rows, k]), which, axle).astype(np.int64)


def panel_at(profile: VariableProfile | ZonedProfile, s_m: float) -> int:
    """The panel a position ``s_m`` [m] lies in: 1, 2, ... in the order of
    :func:`panel_names` (a plain variable profile is one panel), 0 outside every panel (the
    plain rail)."""
    if isinstance(profile, ZonedProfile):
        for k, p in enumerate(profile.panels):
            lo, hi = p.range_m
            if lo <= s_m <= hi:
                return k + 1
        return 0
    lo, hi = profile.s_range_m
    return 1 if lo <= s_m <= hi else 0


def panel_names(profile: VariableProfile | ZonedProfile) -> list[dict[str, object]]:
    """Per panel (index 0: the plain rail outside the panels) its source, its range in the
    profile's ``s`` [m] and the names of its two rails (rail 1 = gauge side, rail 2)."""
    panels = profile.panels if isinstance(profile, ZonedProfile) else (None,)
    out: list[dict[str, object]] = [{"source": "plain rail", "range_m": None,
                                     "rails": list(PLAIN_NAMES)}]  # fmt: skip
    for p in panels:
        prof = profile if p is None else p.profile
        names = prof.slices.rail_names or DEFAULT_NAMES
        rng = prof.s_range_m if p is None else p.range_m
        out.append({"source": prof.slices.source, "range_m": [float(rng[0]), float(rng[1])],
                    "rails": list(names)})  # fmt: skip
    return out


def labelled_curves(
    profile: VariableProfile | ZonedProfile, s_m: float
) -> list[tuple[np.ndarray, np.ndarray]]:
    """The rail curves at ``s_m`` [m], each ``(points (m, 2), rail of each point (m,))``.

    A point's rail: with a boundary feature (:func:`boundary_feature`) the slices' parts before
    it are rail 0 and those after it rail 1 (a slice with one rail alone is that rail, whatever
    its lateral extent: the nose widened on the field side past the wing rail's end); else
    separate curves in lateral order (0 the first, 1 any later one), or the two sides of the
    deepest point (z down) of a single curve (a check rail and its stock rail joined by the
    flangeway; CONTACT's files without features). In a :class:`ZonedProfile` the panel's
    curves, shifted into the zone's axes; between panels the plain rail, rail 1 (the running
    rail, :data:`PLAIN_NAMES`)."""
    if isinstance(profile, ZonedProfile):
        panel = profile.panel_at(float(s_m))
        if panel is None:
            return [(profile.plain_m, np.ones(profile.plain_m.shape[0], dtype=np.int64))]
        shift = np.asarray(panel.offset_m, dtype=float)
        inner = labelled_curves(panel.profile, float(s_m) - panel.s0_m)
        return [(c + shift, lab) for c, lab in inner]
    s = min(max(float(s_m), profile.s_range_m[0]), profile.s_range_m[1])
    k = boundary_feature(profile)
    if k is not None:
        out: list[tuple[np.ndarray, np.ndarray]] = []
        last = -2
        for p, pts in profile.parts_at(s):
            lab = np.full(pts.shape[0], int(p >= k), dtype=np.int64)
            if p == last + 1 and out:
                out[-1] = (np.vstack((out[-1][0], pts[1:])), np.concatenate((out[-1][1], lab[1:])))
            else:
                out.append((pts, lab))
            last = p
        return out
    curves = profile.curves_at(s)
    if len(curves) > 1:
        return [(c, np.full(c.shape[0], min(i, 1), dtype=np.int64)) for i, c in enumerate(curves)]
    c = curves[0]
    split = c[int(np.argmax(c[:, 1])), 0]
    return [(c, (c[:, 0] > split).astype(np.int64))]


def _top(curves: list[tuple[np.ndarray, np.ndarray]], y: np.ndarray):
    """Height ``z`` (down; ``inf`` where no curve lies) of the top surface at ``y`` and the rail
    of the curve on top (-1 where none)."""
    z = np.full(y.shape, np.inf)
    lab = np.full(y.shape, -1, dtype=np.int64)
    for c, rails in curves:
        inside = (y >= c[0, 0]) & (y <= c[-1, 0])
        if not np.any(inside):
            continue
        zc = np.full(y.shape, np.inf)
        zc[inside] = np.interp(y[inside], c[:, 0], c[:, 1])
        j = np.clip(np.searchsorted(c[:, 0], y, side="right") - 1, 0, c.shape[0] - 1)
        on = zc < z
        z = np.where(on, zc, z)
        lab = np.where(on, rails[j], lab)
    return z, lab


def _nearest(curves: list[tuple[np.ndarray, np.ndarray]], y: np.ndarray) -> np.ndarray:
    """The rail of the curve point nearest laterally to each ``y``."""
    pts = np.concatenate([c[:, 0] for c, _ in curves])
    order = np.argsort(pts, kind="stable")
    pts, rails = pts[order], np.concatenate([lab for _, lab in curves])[order]
    j = np.clip(np.searchsorted(pts, y), 1, pts.size - 1)
    left = np.abs(y - pts[j - 1]) <= np.abs(pts[j] - y)
    return rails[np.where(left, j - 1, j)]


@functools.lru_cache(maxsize=64)
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
        ``ws{i}_{side}_rail{r}_{Q_N, Y_N, Tgamma_N, contact_y_m}`` for ``r`` = 1 (nose, blade,
        check rail), 2 (wing rail, stock rail; the plain rail between panels): the vertical and
        lateral force of the rail on the wheel (track axes), the wear number
        ``sum |Fx xi + Fy eta|`` (Pearce and Sherratt 1991) and the vertical-force-weighted
        lateral contact position in the profile's axes (0 where the rail carries no load: read
        it where ``..._Q_N > 0``); ``ws{i}_{side}_in_zone``: 1 where the wheelset is in the
        zone (its first to last slice, where the model reads the stations' tables), 0 outside,
        where every per-rail column is 0 and the side's totals (``..._Q_N``) on the track's
        plain rail apply; ``ws{i}_{side}_panel``: the panel the wheelset's axle is in (1, 2,
        ... as :func:`panel_names`; 0 outside the panels or the zone). No NaN: a non-finite
        value marks a diverged run
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
        ask = loaded[:, :, side] & inside[:, :, None]
        s_pts = np.broadcast_to(s_rel[:, :, None], ask.shape)[ask]
        radius = points[:, :, side, :, K.PF_RADIUS][ask]
        which[ask] = carrier_rails(profile, s_pts, y_rail[ask], radius, rails.x_max_m)
        panel = np.array([[panel_at(profile, float(v)) for v in row] for row in s_rel])
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
    - with ``panels`` (per side :func:`panel_names`) and the ``..._panel`` column: ``rails``,
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
