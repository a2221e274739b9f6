"""Variable rails in the dynamic model (issue 29): a zone whose slices are all the track's own
rail gives the run of the plain track.

The wheelset (vehicles/wheelset.yaml) runs 8 m at 5 m/s from a 2 mm offset over straight track,
once plain and once with a 1 m zone of uniform slices of the track's rail (60E1 upright, turned
1:40 by the placement) on both sides. The kernel reads the stations' effective-section tables
inside the zone (blended, model/forces.py) and the plain tables outside. Tolerances: the two
tables are two interpolations of one rail (the profile's quintic graph; the slices resampled at
0.2 mm and a cubic spline) and differ by < 0.08 um at the arcs' junctions and ~1e-11 m on the
tread, so the wheel loads agree within 5 N of 100 kN (Hertz stiffness ~1.5e9 N/m: 1 nm is
1.5 N) and the lateral motion within 0.05 um.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
from uniform_zone import uniform_zone

from railexu.results.run import RunSettings, run
from railexu.track.track import ideal_straight_track
from railexu.vehicle.vehicle import load_vehicle

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"


def test_uniform_zone_runs_as_plain_track():
    vehicle = load_vehicle(VEHICLES / "wheelset.yaml")
    plain = ideal_straight_track()
    zone = uniform_zone(plain)
    settings = RunSettings(speed_m_per_s=5.0, distance_m=8.0, initial_lateral_m=0.002)
    a = run(vehicle, plain, settings)
    b = run(vehicle, replace(plain, variable_rails=zone), settings)
    assert a.status["state"] == b.status["state"] == "completed"
    ta, tb = a.timeseries, b.timeseries
    for column, tol in (("ws1_left_Q_N", 5.0), ("ws1_right_Q_N", 5.0), ("ws1_left_Y_N", 5.0),
                        ("ws1_right_Y_N", 5.0), ("ws1_lateral_m", 5e-8)):  # fmt: skip
        diff = np.max(np.abs(np.asarray(ta[column]) - np.asarray(tb[column])))
        assert diff < tol, (column, diff)
    # the zone was entered: the kernel read the stations (differences are not all zero there)
    assert np.max(np.abs(np.asarray(ta["ws1_left_Q_N"]) - np.asarray(tb["ws1_left_Q_N"]))) > 0.0
