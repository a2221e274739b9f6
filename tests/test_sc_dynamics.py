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

import numpy as np
from uniform_zone import plain_and_zoned_timeseries

from railexu.track.track import ideal_straight_track


def test_uniform_zone_runs_as_plain_track():
    ta, tb = plain_and_zoned_timeseries(ideal_straight_track())
    for column, tol in (("ws1_left_Q_N", 5.0), ("ws1_right_Q_N", 5.0), ("ws1_left_Y_N", 5.0),
                        ("ws1_right_Y_N", 5.0), ("ws1_lateral_m", 5e-8)):  # fmt: skip
        diff = np.max(np.abs(np.asarray(ta[column]) - np.asarray(tb[column])))
        assert diff < tol, (column, diff)
    # the zone was entered: the kernel read the stations (differences are not all zero there)
    assert np.max(np.abs(np.asarray(ta["ws1_left_Q_N"]) - np.asarray(tb["ws1_left_Q_N"]))) > 0.0
