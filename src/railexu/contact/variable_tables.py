"""The compiled kernel's rail table of a variable rail profile at one track position.

The kernel (:mod:`railexu.contact.kernel`) reads a rail as one graph ``z(y)`` in track axes on a
uniform grid, with slope, curvature, smoothed curvature and curvature-bound columns. Several
rails of one side (wing rail and nose, a check rail) become one such graph: the topmost surface
of their curves at ``y`` (between separate curves a straight bridge from one curve's end to the
next one's start, below both rails' running surfaces, so that it carries no contact). The kernel
then finds a local minimum of the gap on each rail: up to ``MAX_POINTS`` contact points per wheel,
one patch per rail, as on plain track with tread and flange.

Placement: the section's curves (``y`` field side positive, ``z`` down, the rail's own axes as in
its files) are turned by the placed rail's cant and shifted by ``rail_origin_m`` (default the
placed rail's origin: a uniform variable profile equal to the track's rail gives the plain
table), exactly as :func:`railexu.contact.placement.place_wheel_rail` places a rail.
Each curve is a cubic interpolating spline in ``y`` (C2) through the surface's points (0.2 mm
apart), so slope and curvature are continuous on each rail.

*Effective section* (``x_max_m > 0``). The kernel sees the rail at the wheelset's position
only, but a wheel touches a rail that rises along the track ahead of its axle (CONTACT's
``two_patches``: the nose patch 4.2 mm ahead, where the wheel's circle has risen 19 um and the
nose more). The effective section is the envelope that the wheel's circles feel::

    z_eff(y) = max over |x| <= x_max of ( z(s + x, y) - (r(y) - sqrt(r(y)^2 - x^2)) ),

``r(y) = r0 + F(y - tape)`` the radius of the wheel's circle above ``y`` with the wheelset
centred, with the slope and curvature of the maximising ``x`` (the envelope theorem: the
envelope's slope is the surface's at the touching point). The exact circle matters: at
x = 46 mm (CONTACT's ``cross_brute``) ``x^2 / 2r`` is 5.7 um short, a sixth of the approach.
On a rail that does not change along the track the maximum is at ``x = 0`` and the table is the
section's. Errors: ``x_step^2 / (8 r)`` from the sampling of ``x`` (0.07 um at 0.5 mm), and
``x^2 / (2 r^2) F' dy`` from a lateral displacement ``dy`` of the wheelset (on the tread,
``F' = 1/40``: 0.3 um at x = 46 mm and dy = 5 mm; in the flange root more).
"""

from __future__ import annotations

import weakref

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.linalg import solve_banded

from railexu.contact import kernel as K
from railexu.contact.evaluation import _smoothed
from railexu.contact.placement import WheelRailPair, _rotate
from railexu.errors import ComputationError
from railexu.profiles.variable import VariableProfile


def section_rail_arrays(
    rail: VariableProfile,
    s_m: float,
    pair: WheelRailPair,
    *,
    rail_origin_m: tuple[float, float] | None = None,
    curvature_smoothing_m: float = 5.0e-4,
    x_max_m: float = 0.0,
    x_step_m: float = 5.0e-4,
    grid: tuple[float, int] | None = None,
    cache: dict | None = None,
    circle_drop: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Kernel table ``[z, z', z'', z''_smooth, bounds...]`` and info ``(y0, step, n)`` of the
    variable rail at ``s`` [m], placed like ``pair``'s rail (track axes, z up).

    ``grid = (y0, n)`` fixes the table's rows (stations blended in the dynamics share one grid);
    default: the curves' extent. Beyond a curve's end the table continues flat. ``cache``: the
    top surfaces of sections already computed on the same grid, by position (shared between
    neighbouring stations, whose effective sections overlap; :func:`station_tables`).
    ``circle_drop``: :func:`_circle_drop` on this grid (computed once for many stations).

    Raises:
        ComputationError: a curve that is no longer a graph after the cant's rotation.
    """
    origin = pair.rail_origin_track_m if rail_origin_m is None else rail_origin_m
    step = pair.rail_table.step_m
    xs = np.arange(-x_max_m, x_max_m + 0.5 * x_step_m, x_step_m) if x_max_m > 0 else np.zeros(1)
    if grid is None:
        sections = [_placed_curves(rail, s_m + x, pair.rail_cant_rad, origin) for x in xs]
        y0 = min(c[0][0] for cs in sections for c in cs)
        y1 = max(c[0][-1] for cs in sections for c in cs)
        n = int(np.floor((y1 - y0) / step)) + 1
    else:
        y0, n = float(grid[0]), int(grid[1])
    grid = y0 + step * np.arange(n)
    if circle_drop is None:
        circle_drop = _circle_drop(pair, grid, xs)
    # the envelope over x: the first largest of (section at s + x) - (the circle's drop at x)
    surfaces = [_section_surface(rail, s_m + x, pair.rail_cant_rad, origin, grid, cache)
                for x in xs]  # fmt: skip
    heights = np.stack([zx for zx, _, _ in surfaces]) - circle_drop
    best = np.argmax(heights, axis=0)
    rows = np.arange(n)
    z = heights[best, rows]
    dz = np.stack([dzx for _, dzx, _ in surfaces])[best, rows]
    d2z = np.stack([d2zx for _, _, d2zx in surfaces])[best, rows]
    gap = ~np.isfinite(z)
    if np.all(gap):
        raise ComputationError(f"{rail.slices.source}: no rail at s = {s_m:.4f} m on the grid")
    if np.any(gap):  # straight bridges between separate curves, flat beyond the ends
        z[gap] = np.interp(grid[gap], grid[~gap], z[~gap])
        dz[gap] = np.gradient(z, step)[gap]
        d2z[gap] = 0.0
    smooth = _smoothed(d2z, step, curvature_smoothing_m)
    tab = K.with_block_bounds(np.column_stack([z, dz, d2z, smooth]), step)
    return tab, np.array([y0, step, float(n)])


def _circle_drop(pair: WheelRailPair, grid: np.ndarray, xs: np.ndarray) -> np.ndarray:
    """``(len(xs), len(grid))``: how far the centred wheel's circle above each ``y`` lies above
    its lowest point at ``x`` along the track, ``r - sqrt(r^2 - x^2)`` [m]."""
    wheel = pair.wheel
    s_w = np.clip(grid - pair.tape_circle_lateral_m, wheel.y_min, wheel.y_max)
    radius = pair.nominal_radius_m + wheel.height(s_w)
    return radius - np.sqrt(radius * radius - (xs * xs)[:, None])


def _section_surface(rail, s_m, cant, origin, grid, cache) -> tuple:
    """:func:`_top_surface` of the section at ``s`` (from ``cache`` if computed: keyed by ``s``
    in nanometres; positions that differ by rounding alone share a key or are recomputed).
    Inside a slice interval whose two slices are the same curves (a check rail's straight
    middle, the plain rail at a crossing's ends), before the first slice and after the last,
    every section is the same: computed once under one key (:func:`_unchanging_key`)."""
    if cache is None:
        return _top_surface(_placed_curves(rail, s_m, cant, origin), grid)
    key = _unchanging_key(rail, s_m)
    if key is None:
        key = round(s_m * 1e9)
    if key not in cache:
        cache[key] = _top_surface(_placed_curves(rail, s_m, cant, origin), grid)
    return cache[key]


#: per variable profile: which slice intervals have the same curves at both ends
_UNCHANGING: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _unchanging_key(rail, s_m: float) -> int | None:
    """A cache key shared by every section of a slice interval whose two slices are the same
    resampled curves (the same points, the same parts present), or of the stretch before the
    first slice or after the last (where ``VariableProfile`` clamps ``s``): all these sections
    are the same numbers to the last bit (``a + w (b - a)`` with ``b = a`` is ``a + 0`` for
    every ``w``). ``None`` elsewhere, and within 1 nm of a slice, where positions keep their
    own keys (which positions closer than 0.5 nm share: as before). The keys are negative
    (``-2^60 + interval``), never a position's, and dropped with the cache's old entries (then
    computed once more). Only for a :class:`~railexu.profiles.variable.VariableProfile`."""
    samples = getattr(rail, "_samples", None)
    present = getattr(rail, "_present", None)
    if samples is None or present is None:
        return None
    same = _UNCHANGING.get(rail)
    if same is None:
        same = np.array([
            np.array_equal(samples[i], samples[i + 1], equal_nan=True)
            and np.array_equal(present[i], present[i + 1])
            for i in range(samples.shape[0] - 1)
        ], dtype=bool)  # fmt: skip
        _UNCHANGING[rail] = same
    pos = rail.positions_m
    if s_m < pos[0] - 1e-9:
        return -(1 << 60) - 1
    if s_m > pos[-1] + 1e-9:
        return -(1 << 60) + same.size
    i = int(np.searchsorted(pos, s_m, side="right")) - 1
    if 0 <= i < same.size and same[i] and pos[i] + 1e-9 < s_m < pos[i + 1] - 1e-9:
        return -(1 << 60) + i
    return None


def _placed_curves(rail, s_m, cant, origin) -> list[tuple[np.ndarray, np.ndarray]]:
    """The curves at ``s`` turned by the cant and shifted to track axes (z up)."""
    y_off, z_off = origin
    curves = []
    for c in rail.curves_at(s_m):
        y, z = _rotate(c[:, 0], -c[:, 1], cant)
        if np.any(np.diff(y) <= 0.0):
            raise ComputationError(
                f"{rail.slices.source}: at s = {s_m:.4f} m a curve is not a graph z(y) once "
                f"turned by the rail's cant ({cant:.4f} rad)"
            )
        curves.append((y + y_off, z + z_off))
    return curves


def _top_surface(curves, grid) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Height, slope, curvature of the topmost curve on the grid (``-inf`` where none)."""
    n = grid.size
    z = np.full(n, -np.inf)
    dz = np.zeros(n)
    d2z = np.zeros(n)
    for y, zc in curves:
        inside = np.flatnonzero((grid >= y[0]) & (grid <= y[-1]))
        val, d1, d2 = _cubic_spline_on(y, zc, grid[inside])
        top = val > z[inside]
        rows = inside[top]
        z[rows] = val[top]
        dz[rows] = d1[top]
        d2z[rows] = d2[top]
    return z, dz, d2z


def _cubic_spline_on(x: np.ndarray, y: np.ndarray, at: np.ndarray) -> tuple:
    """Value, slope and curvature at ``at`` of the C2 cubic spline through ``(x, y)`` with
    not-a-knot ends: SciPy's ``CubicSpline(x, y)`` (the same tridiagonal system for the
    slopes, solved by the same ``solve_banded``, the same Hermite coefficients), without its
    input checks and array-API dispatch, which cost 70 % of a section's build (issue 29: a
    crossing's tables are made of some 10 000 sections); equal to it within round-off
    (tests/test_sc_table_build.py). Fewer than 4 points: ``CubicSpline`` itself."""
    n = x.size
    if n < 4:
        spline = CubicSpline(x, y)
        return spline(at), spline(at, 1), spline(at, 2)
    dx = np.diff(x)
    slope = np.diff(y) / dx
    a = np.zeros((3, n))
    b = np.empty(n)
    a[1, 1:-1] = 2 * (dx[:-1] + dx[1:])
    a[0, 2:] = dx[:-1]
    a[-1, :-2] = dx[1:]
    b[1:-1] = 3 * (dx[1:] * slope[:-1] + dx[:-1] * slope[1:])
    a[1, 0] = dx[1]
    a[0, 1] = x[2] - x[0]
    d = x[2] - x[0]
    b[0] = ((dx[0] + 2 * d) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / d
    a[1, -1] = dx[-2]
    a[-1, -2] = x[-1] - x[-3]
    d = x[-1] - x[-3]
    b[-1] = (dx[-1] ** 2 * slope[-2] + (2 * d + dx[-1]) * dx[-2] * slope[-1]) / d
    s = solve_banded((1, 1), a, b, overwrite_ab=True, overwrite_b=True, check_finite=False)
    t = (s[:-1] + s[1:] - 2 * slope) / dx
    c0 = t / dx
    c1 = (slope - s[:-1]) / dx - t
    i = np.clip(np.searchsorted(x, at, side="right") - 1, 0, n - 2)
    h = at - x[i]
    c0, c1, c2 = c0[i], c1[i], s[:-1][i]
    val = ((c0 * h + c1) * h + c2) * h + y[:-1][i]
    return val, (3.0 * c0 * h + 2.0 * c1) * h + c2, 6.0 * c0 * h + 2.0 * c1


def station_tables(
    rail: VariableProfile,
    pair: WheelRailPair,
    stations_m: np.ndarray,
    *,
    rail_origin_m: tuple[float, float] | None = None,
    x_max_m: float = 0.06,
    curvature_smoothing_m: float = 5.0e-4,
    share_plain: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Kernel tables ``(n_stations, n, columns)`` of the variable rail at the stations ``s``
    [m] (the profile's own ``s``) on one common grid, and its info ``(y0, step, n)``: one
    table per station (:func:`station_table_set` keeps the plain rail's once).

    Blending two neighbouring tables linearly gives the table of the blended surface; its
    curvature-bound columns stay valid bounds (a bound of a convex combination is at most the
    combination of the bounds), so the kernel's search stays exact on the blend.
    """
    tabs, index, info = station_table_set(
        rail, pair, stations_m, rail_origin_m=rail_origin_m, x_max_m=x_max_m,
        curvature_smoothing_m=curvature_smoothing_m, share_plain=share_plain,
    )  # fmt: skip
    return np.ascontiguousarray(tabs[index]), info


def station_table_set(
    rail: VariableProfile,
    pair: WheelRailPair,
    stations_m: np.ndarray,
    *,
    rail_origin_m: tuple[float, float] | None = None,
    x_max_m: float = 0.06,
    curvature_smoothing_m: float = 5.0e-4,
    share_plain: bool = True,
    grid: tuple[float, int] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The distinct kernel tables ``(n_tables, n, columns)`` of the stations, which table each
    station has (``(n_stations,)`` int64) and the grid's info ``(y0, step, n)``.

    ``grid = (y0, n)``: the tables' rows (default :func:`table_grid` of these stations; give
    the grid of every station of the zone when these are a subset, :func:`adaptive_stations`).

    Stations before the profile's first slice, after its last, and those whose effective
    section lies on the plain rail between a zoned profile's panels (``rail.is_plain_over``,
    :class:`~railexu.profiles.variable.zoned.ZonedProfile`) have the same table as every other
    such station: it is computed and kept once (``share_plain``; the same numbers as computing
    each, to the last bit: the same curves on the same grid). A turnout's 20 m of plain rail
    between its panels is one table instead of ~400.
    """
    origin = pair.rail_origin_track_m if rail_origin_m is None else rail_origin_m
    if grid is None:
        grid = table_grid(rail, pair, stations_m, rail_origin_m=origin, x_max_m=x_max_m)
    lo, n = float(grid[0]), int(grid[1])
    index = station_table_plan(rail, stations_m, x_max_m=x_max_m, share_plain=share_plain)
    count = int(index.max()) + 1 if index.size else 0
    tabs = np.empty((count, n, K.N_TABLE_COLUMNS))  # written once each: no list stacked
    for number, table in station_tables_in_order(
        rail, pair, stations_m, index, (lo, n), rail_origin_m=origin, x_max_m=x_max_m,
        curvature_smoothing_m=curvature_smoothing_m,
    ):  # fmt: skip
        tabs[number] = table
    return tabs, index, np.array([lo, pair.rail_table.step_m, float(n)])


def station_table_plan(
    rail: VariableProfile, stations_m: np.ndarray, *, x_max_m: float = 0.06,
    share_plain: bool = True,
) -> np.ndarray:  # fmt: skip
    """Which distinct table each station has (``(n_stations,)`` int64, numbered in the order
    of their first station), from the positions alone: stations before the first slice, after
    the last and (``share_plain``) on a zoned profile's plain stretches share one table each
    (:func:`station_table_set`), every other station has its own."""
    index = np.zeros(len(stations_m), dtype=np.int64)
    first, last = rail.s_range_m
    constant: dict = {}  # before the first / after the last slice the profile does not change
    plain_over = getattr(rail, "is_plain_over", None)  # a zoned profile's plain stretches
    count = 0
    for j, s in enumerate(stations_m):
        side = "before" if s + x_max_m < first else "after" if s - x_max_m > last else None
        if side is None and share_plain and plain_over is not None:
            side = "plain" if plain_over(s - x_max_m, s + x_max_m) else None
        if side in constant:
            index[j] = constant[side]
            continue
        index[j] = count
        count += 1
        if side is not None:
            constant[side] = index[j]
    return index


def station_tables_in_order(
    rail: VariableProfile,
    pair: WheelRailPair,
    stations_m: np.ndarray,
    index: np.ndarray,
    grid: tuple[float, int],
    *,
    rail_origin_m: tuple[float, float] | None = None,
    x_max_m: float = 0.06,
    curvature_smoothing_m: float = 5.0e-4,
):
    """Yield ``(number, table)`` for each distinct table of :func:`station_table_plan`'s
    ``index``, computed once at its first station, in station order: the sections behind the
    effective section are dropped from the shared cache as the stations advance, and a caller
    that writes each table where it belongs holds no list of them (the station store,
    :func:`railexu.model.sc_tables.envelope_rows`)."""
    origin = pair.rail_origin_track_m if rail_origin_m is None else rail_origin_m
    lo, n = float(grid[0]), int(grid[1])
    step = pair.rail_table.step_m
    x_step = 5.0e-4  # section_rail_arrays' default
    xs = np.arange(-x_max_m, x_max_m + 0.5 * x_step, x_step) if x_max_m > 0 else np.zeros(1)
    drop = _circle_drop(pair, lo + step * np.arange(n), xs)
    cache: dict = {}
    done = -1
    for j, s in enumerate(stations_m):  # in order: sections behind the effective section dropped
        if index[j] <= done:
            continue
        done = int(index[j])
        yield done, section_rail_arrays(
            rail, float(s), pair, rail_origin_m=origin, x_max_m=x_max_m,
            curvature_smoothing_m=curvature_smoothing_m, grid=(lo, n), cache=cache,
            circle_drop=drop,
        )[0]  # fmt: skip
        for key in [k for k in cache if k < round((s - x_max_m) * 1e9) - 1]:
            del cache[key]


def table_grid(
    rail: VariableProfile,
    pair: WheelRailPair,
    stations_m: np.ndarray,
    *,
    rail_origin_m: tuple[float, float] | None = None,
    x_max_m: float = 0.06,
) -> tuple[float, int]:
    """The common grid ``(y0, n)`` of the stations' tables: every curve at each station and
    the ends of its effective section, on the placed rail table's step."""
    origin = pair.rail_origin_track_m if rail_origin_m is None else rail_origin_m
    lo, hi = np.inf, -np.inf
    for s in stations_m:
        for x in (-x_max_m, 0.0, x_max_m):
            for y, _ in _placed_curves(rail, s + x, pair.rail_cant_rad, origin):
                lo, hi = min(lo, y[0]), max(hi, y[-1])
    return float(lo), int(np.floor((hi - lo) / pair.rail_table.step_m)) + 1
