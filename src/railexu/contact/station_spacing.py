"""Stations of a switch-and-crossing zone placed where the rail changes (issue 29).

The dynamics blends the kernel tables of two neighbouring stations linearly
(:mod:`railexu.model.forces`). Where the rail does not change along the track (the plain rail
before and after a crossing, a check rail's straight middle) or changes linearly (a nose
rising at a constant rate, a wing rail moving away at 1:9.25), the blend of two stations far
apart is as good as that of close ones; where it changes abruptly (a rail's start, a slice
where the rate of change jumps) they must be close. :func:`adaptive_stations` keeps, of a
zone's uniform stations (``station_step``), only those needed for a stated tolerance.

**The rule and its bound.** Let ``z(u, y)`` be the top surface of the section at ``u`` (the
sections the effective section is made of, :mod:`railexu.contact.variable_tables`). Stations
``a < b`` may be neighbours if over the whole window ``[a - x_max, b + x_max]`` that the
effective sections of the stations between them read, the surface is within ``tol`` of the
linear function ``L(u, y)`` through the sections at ``a`` and ``b`` along the surface's
normal (a height difference of ``tol sqrt(1 + m^2)`` on a slope ``m``: on a steep flank a
lateral shift of micrometres is a large height difference at one ``y``, not a large
approach) and within ``slope_tolerance`` in slope angle, with the same number of
separate rails (no rail starts or ends; compared where all three sections have a rail: a
curve's lateral end moving with its rail is no change of the surface under the wheel, and
within ``REACH_M`` of the section's top: deeper, no flange reaches). Then the effective section
``z_eff(s, y) = max_x (z(s + x, y) - c(x, y))`` (``c`` the wheel circle's drop) is within
``tol`` of ``max_x (L(s + x, y) - c(x, y)) = A(y) + s B(y) + max_x (x B(y) - c(x, y))``, which
is linear in ``s``; so the blend of the stations' effective sections lies within ``2 tol``
(along the normal; the same argument on heights with ``tol sqrt(1 + m^2)``) of the effective
section at every ``s`` between them (slopes and curvatures follow where the surface is smooth:
checked, not bounded).
The window is checked on the sections at every half station step and at every slice position
(where the surface's rate of change along the track may jump); between these samples the
surface of one slice interval is a ruled surface (its points move linearly), whose deviation
from the line through two samples half a station step apart is of second order.
``tests/test_sc_table_build.py`` checks the bound at every dropped station of a rail rising
along the track with a kink (its stations around the kink kept).

Measured on the shipped crossing (docs/performance.md, "Issue 29"): the rule drops no station
inside the crossing's slices and 47 of 285 on the check rail's straight middle; halfway
between the crossing's 20 mm stations the surface is 70-120 um off the line through them
within 5 mm of the top (rails moving laterally), so the rule is not used by the dynamics.

Cost: the sections at every half station step (a fortieth of the effective sections' 0.5 mm
sampling) and a comparison per window; the build then computes the kept stations' tables
only (:func:`railexu.contact.variable_tables.station_table_set`).
"""

from __future__ import annotations

import numpy as np

from railexu.contact.placement import WheelRailPair
from railexu.contact.variable_tables import _placed_curves, _top_surface
from railexu.profiles.variable import VariableProfile

#: Default tolerance ``tol`` of the rule [m, normal distance]: the blend lies within
#: ``2 tol`` (0.5 um) of the effective section. At a static wheel load of 50-110 kN the Hertz
#: approach is 80-150 um, so 0.5 um changes the normal force by at most 1 % (F ~ delta^1.5).
DEFAULT_TOLERANCE_M = 2.5e-7
#: Depth below a section's top beyond which no wheel reaches [m]: a flange is 28-32 mm high
#: (S1002, P8); deeper, the check rail's flangeway and the rails' extended flanks.
REACH_M = 0.035
#: Largest slope difference from the linear function [rad] in the same window.
DEFAULT_SLOPE_TOLERANCE = 1.0e-3


def slice_positions(rail) -> np.ndarray:
    """The positions [m] of a variable or zoned profile's slices (where the surface's rate of
    change along the track may jump), in the profile's ``s``."""
    panels = getattr(rail, "panels", None)
    if panels is None:
        return np.asarray(rail.positions_m, dtype=float)
    return np.concatenate([p.s0_m + np.asarray(p.profile.positions_m) for p in panels])


class _Sections:
    """The top surface's heights and slopes on the table grid at sample positions, computed
    once each and dropped behind the window (float32: the tolerances are 1e-7 m on heights
    of a few centimetres, 1e-9 m resolution)."""

    def __init__(self, rail, pair, origin, grid_y):
        self.rail, self.pair, self.origin, self.grid_y = rail, pair, origin, grid_y
        self.cache: dict[int, tuple[np.ndarray, np.ndarray, int]] = {}

    def at(self, u: float) -> tuple[np.ndarray, np.ndarray, int]:
        """Heights, slopes and the number of separate curves (rails) at ``u``."""
        key = round(u * 1e9)
        if key not in self.cache:
            curves = _placed_curves(self.rail, u, self.pair.rail_cant_rad, self.origin)
            z, dz, _ = _top_surface(curves, self.grid_y)
            self.cache[key] = (z.astype(np.float32), dz.astype(np.float32), len(curves))
        return self.cache[key]

    def drop_before(self, u: float) -> None:
        for key in [k for k in self.cache if k < round(u * 1e9) - 1]:
            del self.cache[key]


def adaptive_stations(
    rail: VariableProfile,
    pair: WheelRailPair,
    stations_m: np.ndarray,
    grid: tuple[float, int],
    *,
    tolerance_m: float = DEFAULT_TOLERANCE_M,
    slope_tolerance: float = DEFAULT_SLOPE_TOLERANCE,
    rail_origin_m: tuple[float, float] | None = None,
    x_max_m: float = 0.06,
    reach_m: float = REACH_M,
) -> np.ndarray:
    """Indices of the uniform ``stations_m`` [m] (the profile's ``s``, ascending, equal steps)
    to keep, the first and the last always: each next station is the farthest for which the
    rule of the module holds (found by doubling, then bisection; every accepted pair is
    checked over its whole window). ``grid = (y0, n)``: the tables' rows
    (:func:`railexu.contact.variable_tables.table_grid`)."""
    stations_m = np.asarray(stations_m, dtype=float)
    n = stations_m.size
    if n <= 2 or tolerance_m <= 0.0:
        return np.arange(n, dtype=np.int64)
    origin = pair.rail_origin_track_m if rail_origin_m is None else rail_origin_m
    step = pair.rail_table.step_m
    grid_y = grid[0] + step * np.arange(int(grid[1]))
    sections = _Sections(rail, pair, origin, grid_y)
    half = 0.5 * (stations_m[1] - stations_m[0])
    kinks = np.sort(slice_positions(rail))

    def samples(a: int, b: int) -> np.ndarray:
        lo, hi = stations_m[a] - x_max_m, stations_m[b] + x_max_m
        base = stations_m[a] + half * np.arange(
            int(np.floor((lo - stations_m[a]) / half)),
            int(np.ceil((hi - stations_m[a]) / half)) + 1,
        )
        inside = kinks[(kinks > lo) & (kinks < hi)]
        return np.concatenate([base, inside])

    def linear(a: int, b: int) -> bool:
        za, sa, na = sections.at(stations_m[a])
        zb, sb, nb = sections.at(stations_m[b])
        if na != nb:
            return False
        both = np.isfinite(za) & np.isfinite(zb)
        span = stations_m[b] - stations_m[a]
        for u in samples(a, b):
            z, s, nu = sections.at(float(u))
            if nu != na:
                return False
            rails = both & np.isfinite(z)
            rails &= z > np.max(z[rails]) - reach_m  # within the flange's reach
            w = (u - stations_m[a]) / span
            if _off_line(z[rails], s[rails], za[rails], sa[rails], zb[rails], sb[rails], w,
                         tolerance_m, slope_tolerance):  # fmt: skip
                return False
        return True

    kept = [0]
    a = 0
    while a < n - 1:
        good, bad = a + 1, n  # a + 1: the uniform step, the finest there is
        while good < n - 1:  # doubling
            nxt = min(a + 2 * (good - a), n - 1)
            if not linear(a, nxt):
                bad = nxt
                break
            good = nxt
        while bad - good > 1 and bad < n:  # bisection between the last good and the first bad
            mid = (good + bad) // 2
            if linear(a, mid):
                good = mid
            else:
                bad = mid
        kept.append(good)
        a = good
        sections.drop_before(stations_m[a] - x_max_m - half)
    return np.asarray(kept, dtype=np.int64)


def _off_line(z, dz, za, dza, zb, dzb, w, tolerance_m, slope_tolerance) -> bool:
    """Whether the section ``(z, dz)`` lies off the line ``(1 - w) a + w b`` by more than the
    tolerances: its distance along the surface's normal (the height difference times the
    cosine of the slope: on a steep flank a lateral shift of a few micrometres is a large
    height difference at one ``y``, not a large approach) and its slope angle."""
    lz = za + w * (zb - za)
    ls = dza + w * (dzb - dza)
    if np.max(np.abs(z - lz) / np.sqrt(1.0 + np.maximum(dz * dz, ls * ls))) > tolerance_m:
        return True
    return bool(np.max(np.abs(np.arctan(dz) - np.arctan(ls))) > slope_tolerance)
