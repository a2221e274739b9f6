"""The loaded wagon's wheel on the filtered wing rail where it climbs onto the raised top (issue 29,
docs/switches-and-crossings.md, the turnout's "Cost": the one named window not within 2 % at
5 mm stations).

The turnout's diverging route, facing, the crossing side: at the slices' ``s = -0.70 ..
-0.68 m`` the loaded Hbbins' leading wheel moves from a contact on the wing rail's gauge side
(``y`` ~ 743 mm in the table's axes) to its raised top (~ 765-775 mm). That takeover is the max
of two surfaces, so the wheel's path along the track has a slope jump there (15-22 mm/m for
lateral positions of -4 .. +2 mm) that no filter at a fixed lateral position removes.

References outside the code under test: the same effective sections at stations 1 mm apart,
box-filtered over the same 12 mm (the filter's interpolant converges as ``step^2``: at 1 mm
within 1/25 of the 5 mm stations' error), and the wheel's own profile. Checked: the height the
wheel feels (``max_y (z_rail(y) + wheel_height(y - tape - dy))``, the quasi-static approach of a
rigid wheel, ``dy`` its lateral shift) from 5 mm and 2.5 mm stations against 1 mm, and the
takeover's position and slope jump. Measured (2026-12-08): the felt height within 2.9-3.4 um
at 5 mm and 0.6-0.8 um at 2.5 mm of the 1 mm stations' (``dy`` = -2, 0, +2 mm; against 0.5 mm
stations over ``dy`` = -6 .. +6 mm: 3.7 and 0.9 um), the takeover within 0.09 mm of its
position and its slope jump within 1 % (18.27 against 18.13 mm/m at ``dy = 0``).
Bounds asserted: 6 um and 1.5 um (a Hertz contact's ~1.5e9 N/m makes 6 um about
9 kN on a ~220 kN peak: 4 %, and the 2.5 mm stations' quarter of it as ``step^2``); 0.3 mm; 3 %.
The dynamic runs' 247.7 kN at 5 mm is a one-step dip and rebound at this takeover at some
phases of the time steps (223.4 kN with the run started 1 mm later; 2.5 mm stations 223.7-224.0
kN at every phase tried): docs/switches-and-crossings.md, the turnout's "Cost".
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest

from railexu.contact.variable_tables import station_table_set, table_grid
from railexu.model.assembly import wheelset_geometry
from railexu.model.forces import filter_weight
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
FILTER_M = 0.012  # the turnout's contact filter (its track file)
SIDE = 1  # the crossing (nose and wing rail) on the right on the diverging route
GAUGE_SIDE_MAX_Y_M = 0.755  # table y below: the wing rail's gauge side; above: its raised top
S_LO, S_HI = -0.705, -0.675  # the slices' s [m] of the takeover


@cache
def _setup():
    track = load_track(ROOT / "tracks" / "turnout_uk_r245_diverging_facing.yaml", [])
    rails = track.variable_rails
    vehicle = load_vehicle(ROOT / "vehicles" / "hbbins_loaded.yaml")
    pair = wheelset_geometry(vehicle.wheelsets[0], track).pairs[SIDE]
    profile = rails.sides()[SIDE]
    panel = profile.panels[1]  # the whole crossing's slices
    assert "uk_crossing_full" in str(panel.profile.slices.source)
    # the zone's s (the profile's own) of the crossing slices' s = 0
    zero = panel.range_m[0] - panel.profile.positions_m[0]
    stations = rails.stations_m() - rails.start_m  # the shipped 5 mm crossing stations
    near = stations[(stations > zero + S_LO - 0.02) & (stations < zero + S_HI + 0.02)]
    assert np.allclose(np.diff(near), 0.005)
    grid = table_grid(profile, pair, near, rail_origin_m=rails.rail_origin_m, x_max_m=rails.x_max_m)
    s = zero + np.arange(S_LO, S_HI + 1e-9, 2.5e-4)
    felt = {}
    for step_mm, sub in ((5.0, 1), (2.5, 2), (1.0, 5)):
        x = near[0] + (near[1] - near[0]) / sub * np.arange(sub * (near.size - 1) + 1)
        tabs, index, info = station_table_set(
            profile, pair, x, rail_origin_m=rails.rail_origin_m, x_max_m=rails.x_max_m,
            grid=grid,
        )  # fmt: skip
        heights = tabs[index][:, :, 0]
        z = np.array([
            sum(filter_weight(x, j, si, FILTER_M) * heights[j] for j in range(x.size))
            for si in s
        ])  # fmt: skip
        felt[step_mm] = z
    y = info[0] + info[1] * np.arange(int(info[2]))
    return s - zero, y, felt, pair


def _felt(z: np.ndarray, y: np.ndarray, pair, dy: float, where: np.ndarray | None = None):
    """The height the rigid wheel shifted by ``dy`` [m] feels [m], per row of ``z``."""
    wheel = pair.wheel
    w = y - pair.tape_circle_lateral_m - dy
    h = np.where((w >= wheel.y_min) & (w <= wheel.y_max), wheel.height(np.clip(w, wheel.y_min,
                 wheel.y_max)), np.nan)  # fmt: skip
    g = z + h
    if where is not None:
        g = np.where(where, g, np.nan)
    return np.nanmax(g, axis=1)


@pytest.mark.parametrize("dy_m", [-0.002, 0.0, 0.002])
def test_wing_rail_takeover_from_5_mm_stations_is_the_converged_surface(dy_m):
    s, y, felt, pair = _setup()
    ref = _felt(felt[1.0], y, pair, dy_m)
    err5 = np.max(np.abs(_felt(felt[5.0], y, pair, dy_m) - ref))
    err25 = np.max(np.abs(_felt(felt[2.5], y, pair, dy_m) - ref))
    assert err5 < 6e-6
    assert err25 < 1.5e-6
    # the takeover: where the raised top's branch overtakes the gauge side's, and the slope
    # jump of the wheel's path there
    out = {}
    for step_mm in (5.0, 1.0):
        a = _felt(felt[step_mm], y, pair, dy_m, y < GAUGE_SIDE_MAX_Y_M)
        b = _felt(felt[step_mm], y, pair, dy_m, y >= GAUGE_SIDE_MAX_Y_M)
        d = b - a
        k = int(np.flatnonzero((d[:-1] < 0) & (d[1:] >= 0))[0])
        at = s[k] - d[k] * (s[k + 1] - s[k]) / (d[k + 1] - d[k])
        jump = np.gradient(b, s)[k] - np.gradient(a, s)[k]
        out[step_mm] = (at, jump)
    assert 0.010 < out[1.0][1] < 0.030  # a slope jump of the wheel's path (15-22 mm/m)
    assert abs(out[5.0][0] - out[1.0][0]) < 3e-4
    assert abs(out[5.0][1] / out[1.0][1] - 1.0) < 0.03
