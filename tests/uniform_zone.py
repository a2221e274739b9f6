"""A switch-and-crossing zone whose slices are all the track's own rail (issue 29): run on it,
the dynamics must give the plain track's results (tests/test_sc_dynamics.py on rigid track,
tests/test_sc_elastic.py on elastic track)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from railexu.profiles import rail_profile
from railexu.profiles.variable import VariableProfile
from railexu.profiles.variable.slices import ProfileSlices
from railexu.results.run import RunSettings, run
from railexu.track.variable_rails import VariableRails
from railexu.vehicle.vehicle import load_vehicle

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"


def uniform_zone(track, start_m: float = 5.0, station_step_m: float = 0.25) -> VariableRails:
    """A 1 m zone from ``start_m`` [m] whose two slices on both sides are the track's rail
    profile (60E1 upright on the shipped straight track), sampled every 0.05 mm (the slices'
    convention: z down)."""
    rail = rail_profile(track.rail_profile)
    y = np.arange(rail.y_min, rail.y_max, 5e-5)
    points = np.column_stack([y, -rail.height(y)])
    profile = VariableProfile(
        ProfileSlices("uniform 60E1", np.array([0.0, 1.0]), (points, points), None,
                      (None, None), ("60E1", "60E1"))
    )  # fmt: skip
    return VariableRails(left=profile, right=profile, start_m=start_m,
                         station_step_m=station_step_m)  # fmt: skip


def plain_and_zoned_timeseries(plain):
    """The wheelset, 8 m at 5 m/s from a 2 mm offset, on the track ``plain`` and on the same
    track with :func:`uniform_zone`: both runs completed, their time series ``(plain, zoned)``."""
    vehicle = load_vehicle(VEHICLES / "wheelset.yaml")
    settings = RunSettings(speed_m_per_s=5.0, distance_m=8.0, initial_lateral_m=0.002)
    a = run(vehicle, plain, settings)
    b = run(vehicle, replace(plain, variable_rails=uniform_zone(plain)), settings)
    assert a.status["state"] == b.status["state"] == "completed"
    return a.timeseries, b.timeseries
