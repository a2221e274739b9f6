"""Which rail of a side carries a point: the rails of switch-and-crossing slices labelled
(issue 29).

A side's variable profile holds two rails per panel: rail 0 on the gauge side and rail 1 on
the field side in the rail's own axes (field side positive), named by the slices
(``ProfileSlices.rail_names``): in a common crossing the nose and the wing rail, in a switch
panel the blade and the stock rail, beside a crossing the check rail and the stock rail;
between a zone's panels the plain rail counts as rail 1 (the running rail). Each point of the
slices' curves is labelled with its rail (:func:`labelled_curves`), and a point belongs to the
rail whose surface is the top one at its lateral position (:func:`rail_index`), at the station
along the effective section where a wheel's circle meets the rails (:func:`carrier_rails`).
Used by the outputs per rail (``railexu.simulation.sc_outputs``) and the quasi-static contact
(``railexu.contact.variable_rail``).
"""

from __future__ import annotations

import functools

import numpy as np

from railexu.profiles.variable.interpolate import VariableProfile
from railexu.profiles.variable.zoned import ZonedProfile

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
    with_station: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Index (0, 1) of the rail that carries each contact point of a wheel: axle at the
    profile's position ``s_m`` [m], point at lateral ``y_m`` [m] (the profile's axes), wheel
    radius there ``radius_m`` [m] (arrays of one length). The wheel's circle over ``y`` meets
    the rails' top surface (:func:`rail_index`) at the station ``s + x``, ``|x| <= x_max_m``,
    where that surface rises highest above the circle's drop ``r - sqrt(r^2 - x^2)``: the
    effective section's envelope (``railexu.contact.variable_tables``, the table the kernel
    found the point on; a rising nose is touched ~ 46 mm ahead of the axle). The stations are
    those of a grid every :data:`CARRIER_STEP_M` along the track, the top surface is read every
    :data:`CARRIER_DY_M` laterally (the point's nearest); where no rail lies over ``y`` at any
    station searched, the rail nearest laterally at the station nearest the axle.
    ``with_station``: also the carrying station's position [m] (the profile's ``s``), whose
    panel names the rail (a point carried past a panel's last slice is the plain rail's)."""
    s = np.asarray(s_m, dtype=float).ravel()
    y = np.asarray(y_m, dtype=float).ravel()
    r = np.asarray(radius_m, dtype=float).ravel()
    if s.size == 0:
        empty = np.zeros(0, dtype=np.int64)
        return (empty, np.zeros(0)) if with_station else empty
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
    found = np.isfinite(score[rows, k])
    rail = np.where(found, which, axle).astype(np.int64)
    if not with_station:
        return rail
    carrying = np.where(found, station[rows, k], station[rows, n]) * CARRIER_STEP_M
    return rail, carrying


def panel_at(profile: VariableProfile | ZonedProfile, s_m: np.ndarray) -> np.ndarray:
    """The panel each position ``s_m`` [m] (any shape) lies in: 1, 2, ... in the order of
    :func:`panel_names` (a plain variable profile is one panel), 0 outside every panel (the
    plain rail) and at NaN."""
    s = np.asarray(s_m, dtype=float)
    ranges = ([p.range_m for p in profile.panels] if isinstance(profile, ZonedProfile)
              else [profile.s_range_m])  # fmt: skip
    out = np.zeros(s.shape, dtype=np.int64)
    for k, (lo, hi) in reversed(list(enumerate(ranges))):  # the first panel wins a shared end
        out[(s >= lo) & (s <= hi)] = k + 1
    return out


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
