"""Building the station tables of an S&C zone faster and in less memory (issue 29, speed):
the same tables as the definitions, and the rule that places stations where the rail changes.

Checked against definitions written out here (not against earlier output of the code):

- the section's spline (``variable_tables._cubic_spline_on``) against SciPy's
  ``CubicSpline`` (not-a-knot), within round-off;
- the effective section (the first largest of section minus circle drop over ``x``) against
  the loop over ``x`` of its definition, to the last bit;
- the station store (each station's table with the bounds of its pair) against the stacked
  per-station tables, to the last bit;
- ``station_spacing.adaptive_stations``: slices that do not change keep the zone's two ends;
  a rail that only rises (linear along the track) is linear in ``s`` and needs no station
  between; where stations are dropped the blend of the kept neighbours' effective sections
  lies within the stated ``2 tol`` of the effective section at every dropped station.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from railexu.contact.placement import symmetric_wheelset
from railexu.contact.station_spacing import adaptive_stations
from railexu.contact.variable_tables import (
    _circle_drop,
    _cubic_spline_on,
    _section_surface,
    section_rail_arrays,
    station_table_set,
    table_grid,
)
from railexu.model.sc_tables import envelope_rows, pair_envelope_bounds
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.slcs import _read_profile_points
from railexu.profiles.variable.slices import ProfileSlices

DATA = Path(__file__).parent / "data" / "switches_crossings" / "profiles"
PACKAGED = Path(__file__).parents[1] / "src" / "railexu" / "data" / "profiles"
RAIL_ORIGIN = (0.75, 0.0)


@pytest.fixture(scope="module")
def pair():
    """The left wheel-rail pair of the Manchester S1002 on UIC60 (test_sc_kernel.py's)."""
    return symmetric_wheelset(
        "MBench_S1002", "MBench_UIC60", nominal_radius_m=0.46, inclination="1:40",
        gauge_m=1.435, flange_back_distance_m=1.36,
    ).left  # fmt: skip


@pytest.fixture(scope="module")
def nose():
    """CONTACT's nose rising 1:10 (``cross_nose.slcs``, s = -100 ... 100 mm)."""
    return VariableProfile(read_slcs(DATA / "cross_nose.slcs"))


def _uic60_points() -> np.ndarray:
    pts = _read_profile_points(PACKAGED / "x", 0, "MBench_UIC60_v3.prr", 1.0)
    pts = pts[::-1] if pts[0, 0] > pts[-1, 0] else pts
    return pts[np.concatenate(([True], np.diff(pts[:, 0]) > 0))]


def test_spline_is_scipys_cubic_spline(nose):
    """Value, slope and curvature of the section's spline equal SciPy's not-a-knot
    ``CubicSpline`` within round-off, on a curve of the nose (hundreds of points) and on 4 and 5
    points (the smallest systems)."""
    curve = nose.curves_at(0.0)[0]
    cases = [(curve[:, 0], -curve[:, 1])]
    x5, y5 = np.array([0.0, 1e-3, 2.5e-3, 4e-3, 6e-3]), np.array([0, 2, 1, 3, 0.5]) * 1e-4
    cases += [(x5[:n], y5[:n]) for n in (4, 5)]
    for x, y in cases:
        at = np.linspace(x[0], x[-1], 777)
        ref = CubicSpline(x, y)
        val, d1, d2 = _cubic_spline_on(x, y, at)
        for got, want in ((val, ref(at)), (d1, ref(at, 1)), (d2, ref(at, 2))):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.max(np.abs(want)))


def test_effective_section_is_its_definition(nose, pair):
    """The table's height, slope and curvature columns at s = 20 mm: at each ``y`` those of
    the first ``x`` (|x| <= 60 mm, 0.5 mm steps) where section minus circle drop is largest,
    computed here by the loop of the definition: to the last bit."""
    tab, info = section_rail_arrays(nose, 0.02, pair, rail_origin_m=RAIL_ORIGIN, x_max_m=0.06)
    grid = info[0] + info[1] * np.arange(int(info[2]))
    xs = np.arange(-0.06, 0.06 + 2.5e-4, 5e-4)
    drop = _circle_drop(pair, grid, xs)
    z = np.full(grid.size, -np.inf)
    dz, d2z = np.zeros(grid.size), np.zeros(grid.size)
    for k, x in enumerate(xs):
        cant = pair.rail_cant_rad
        zx, dzx, d2zx = _section_surface(nose, 0.02 + x, cant, RAIL_ORIGIN, grid, None)
        zx = zx - drop[k]
        higher = zx > z
        z[higher], dz[higher], d2z[higher] = zx[higher], dzx[higher], d2zx[higher]
    rail = np.isfinite(z)
    assert np.array_equal(tab[rail, 0], z[rail])
    assert np.array_equal(tab[rail, 1], dz[rail])
    assert np.array_equal(tab[rail, 2], d2z[rail])


def test_station_store_is_the_stacked_tables(nose, pair):
    """The store written row by row (no padded copy, no stacked list): each station reads its
    own table with the bound columns of its pair with the next station, as the stacked
    per-station tables with :func:`pair_envelope_bounds` give them: to the last bit."""
    stations = np.arange(-0.3, 0.1, 0.02)  # s <= -0.18 m: before the first slice, shared
    tabs, index, _ = station_table_set(nose, pair, stations, rail_origin_m=RAIL_ORIGIN)
    assert tabs.shape[0] < stations.size  # the stations before the first slice share one
    store, rows = envelope_rows([(0, tabs, index)], tabs.shape[1], stations.size)
    per_station = tabs[index][:, None].copy()
    pair_envelope_bounds(per_station)
    for i in range(stations.size):
        assert np.array_equal(store[rows[i, 0]], per_station[i, 0])
    assert np.all(rows[:, 1] == -1)


def test_unchanging_slices_keep_the_ends(pair):
    """Slices that are all the same rail: the surface does not change, two stations."""
    pts = _uic60_points()
    uniform = VariableProfile(ProfileSlices("uniform", np.array([0.0, 100.0]), (pts, pts), None,
                                            (None, None), ("UIC60", "UIC60")))  # fmt: skip
    stations = np.arange(0.0, 0.4001, 0.02)
    grid = table_grid(uniform, pair, stations, x_max_m=0.06)
    kept = adaptive_stations(uniform, pair, stations, grid, x_max_m=0.06)
    assert kept.tolist() == [0, stations.size - 1]


def test_dropped_stations_within_the_bound(pair):
    """A UIC60 rising 1 mm over 100 mm, then constant (a kink along the track at s = 100 mm):
    the rule keeps the stations around the kink and drops those where the surface is linear
    in s; at every dropped station the blend of its kept neighbours' effective sections lies
    within 2 tol of its own effective section (heights, in the wheel's reach: 35 mm)."""
    pts = _uic60_points()
    risen = pts - np.array([0.0, 1e-3])  # z down: 1 mm higher
    rail = VariableProfile(ProfileSlices("rising", np.array([0.0, 0.1, 0.3]),
                                         (pts, risen, risen), None, (None,) * 3,
                                         ("UIC60", "UIC60 +1 mm", "UIC60 +1 mm")))  # fmt: skip
    stations = np.arange(-0.02, 0.32, 0.02)
    grid = table_grid(rail, pair, stations, x_max_m=0.06)
    tol = 2.5e-7
    kept = adaptive_stations(rail, pair, stations, grid, tolerance_m=tol, x_max_m=0.06)
    assert kept.size < stations.size - 4  # the linear rise and the constant part need few
    near_kink = np.flatnonzero(np.abs(stations - 0.1) < 0.06)
    assert np.all(np.isin(near_kink[1:-1], kept))  # the kink's window keeps its stations
    tabs, index, _ = station_table_set(rail, pair, stations, x_max_m=0.06, grid=grid)
    full = tabs[index]
    for a, b in zip(kept[:-1], kept[1:], strict=True):
        for i in range(a + 1, b):
            w = (stations[i] - stations[a]) / (stations[b] - stations[a])
            blend = full[a, :, 0] + w * (full[b, :, 0] - full[a, :, 0])
            own = full[i, :, 0]
            reach = own > own.max() - 0.035
            slope = np.maximum(np.abs(full[i, :, 1]), np.abs(full[a, :, 1]))
            normal = np.abs(blend - own)[reach] / np.sqrt(1.0 + slope[reach] ** 2)
            assert normal.max() <= 2 * tol, (stations[i], normal.max())


def test_sections_between_equal_slices_computed_once(pair):
    """Slices 0.1 m and 0.2 m apart that are the same rail (a UIC60 1 mm higher between two
    plain ones): every section between them is computed once (the cache holds one entry for
    the interval) and the station's table is the same, to the last bit, as with every section
    computed at its own position (no cache)."""
    pts = _uic60_points()
    risen = pts - np.array([0.0, 1e-3])
    rail = VariableProfile(ProfileSlices("plateau", np.array([0.0, 0.1, 0.3, 0.4]),
                                         (pts, risen, risen, pts), None, (None,) * 4,
                                         ("UIC60", "+1 mm", "+1 mm", "UIC60")))  # fmt: skip
    grid = table_grid(rail, pair, np.array([0.2]), x_max_m=0.06)
    cache: dict = {}
    shared, _ = section_rail_arrays(rail, 0.2, pair, x_max_m=0.06, grid=grid, cache=cache)
    assert len(cache) == 1  # the window 0.14 ... 0.26 m lies inside the plateau
    xs = np.arange(-0.06, 0.06 + 2.5e-4, 5e-4)
    grid_y = grid[0] + pair.rail_table.step_m * np.arange(grid[1])
    own = [_section_surface(rail, 0.2 + x, pair.rail_cant_rad, pair.rail_origin_track_m, grid_y,
                            None) for x in xs]  # fmt: skip
    for z, dz, d2z in own:
        assert np.array_equal(z, own[0][0]) and np.array_equal(dz, own[0][1])
        assert np.array_equal(d2z, own[0][2])
    alone, _ = section_rail_arrays(rail, 0.2, pair, x_max_m=0.06, grid=grid)
    assert np.array_equal(shared, alone)
