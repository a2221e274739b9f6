"""A switch-and-crossing zone whose slices are all the track's own rail (issue 29): run on it,
the dynamics must give the plain track's results (tests/test_sc_dynamics.py on rigid track,
tests/test_sc_elastic.py on elastic track)."""

from __future__ import annotations

import numpy as np

from railexu.profiles import rail_profile
from railexu.profiles.variable import VariableProfile
from railexu.profiles.variable.slices import ProfileSlices
from railexu.track.variable_rails import VariableRails


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
