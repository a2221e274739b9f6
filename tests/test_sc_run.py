"""A run through the shipped UK crossing (issue 29) and its outputs per rail.

Checked against things outside the code: which rail a contact point belongs to, against the
slices' own geometry (the nose's and the wing rail's tops on either side of the flangeway's
bottom, read from the profile points in the test); the 50 % transfer point of a prescribed
linear load transfer (analytic: the middle of the ramp); and in a dynamic run the bookkeeping
(the rails' vertical forces sum to the wheel's, to rounding) and the rail that carries the wheel
inside slices 41-60 against the quasi-static kernel's answer for a centred wheel (the wing rail:
the nose is still below the wheel's tread there, tests/test_sc_kernel.py's mbench_intrup case).
"""

from __future__ import annotations

import numpy as np
import pytest

from railexu.results.run import RunSettings, run
from railexu.simulation.sc_outputs import crossing_summary, rail_index
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle


@pytest.fixture(scope="module")
def facing():
    return load_track("uk_crossing_facing", overrides="variable_rails.start=3 m")


def test_rail_index_against_the_slices_geometry(facing):
    profile = facing.variable_rails.left
    (curve,) = profile.curves_at(0.16)  # nose and wing rail on one curve through the flangeway
    y, z = curve[:, 0], curve[:, 1]
    bottom = y[int(np.argmax(z))]
    nose_top = y[y < bottom][int(np.argmin(z[y < bottom]))]
    wing_top = y[y > bottom][int(np.argmin(z[y > bottom]))]
    assert nose_top < bottom < wing_top
    assert list(rail_index(profile, 0.16, np.array([nose_top, wing_top]))) == [0, 1]
    # before the nose starts (118.94 mm) the side has the wing rail only: every point on rail 2
    (before,) = profile.curves_at(0.05)
    top = before[int(np.argmin(before[:, 1])), 0]
    assert rail_index(profile, 0.05, np.array([top, top + 0.01])).tolist() == [1, 1]


def test_transfer_point_of_a_linear_ramp():
    """The nose's share rising linearly from 0 at 1.0 m to 1 at 2.0 m crosses 50 % at 1.5 m
    (to rounding); the largest force and its place are the ramp's end."""
    s = np.linspace(0.0, 3.0, 301)
    share = np.clip(s - 1.0, 0.0, 1.0)
    load = 1.0e5 * (1.0 + 0.2 * (np.abs(s - 2.5) < 1e-9))
    cols = {
        "ws1_s_m": s,
        "ws1_left_in_zone": ((s >= 0.5) & (s <= 2.8)).astype(float),
        "ws1_left_rail1_Q_N": share * load,
        "ws1_left_rail2_Q_N": (1.0 - share) * load,
        "ws1_left_rail1_Tgamma_N": 10.0 * share,
        "ws1_left_rail2_Tgamma_N": 20.0 * (1.0 - share),
    }
    out = crossing_summary(cols, (1.0, 2.0), 1)["ws1_left"]
    assert out["transfer_at_m"] == pytest.approx(1.5, abs=1e-9)
    assert out["max_Q_N"] == pytest.approx(1.2e5) and out["max_Q_at_m"] == pytest.approx(2.5)
    assert out["max_Q_rail"] == 1
    assert out["Tgamma_max_N"] == pytest.approx([10.0, 20.0])


def test_wheelset_through_the_facing_crossing(facing):
    """The wheelset, 3 m at 2 m/s over the crossing (zone at 2.91-3.18 m)."""
    result = run(load_vehicle("wheelset"), facing,
                 RunSettings(speed_m_per_s=2.0, distance_m=3.0, initial_lateral_m=0.0))  # fmt: skip
    assert result.status["state"] == "completed"
    ts = result.timeseries
    q = np.asarray(ts["ws1_left_Q_N"])
    r1, r2 = np.asarray(ts["ws1_left_rail1_Q_N"]), np.asarray(ts["ws1_left_rail2_Q_N"])
    inside = np.asarray(ts["ws1_left_in_zone"]) > 0.5
    for name in ts.names:  # no NaN: a non-finite value would mark a diverged run
        assert np.all(np.isfinite(np.asarray(ts[name]))), name
    s = np.asarray(ts["ws1_s_m"])
    lo, hi = facing.variable_rails.zone_m()
    # defined where the model reads the zone's station tables (every 10 mm from the first slice)
    last = lo + np.floor((hi - lo) / 0.01) * 0.01
    assert np.all(inside == ((s >= lo) & (s <= last)))
    assert np.count_nonzero(inside) >= int((last - lo) / (2.0 * 0.008))  # outputs every 8 mm
    # bookkeeping: every loaded point is on one of the two rails
    assert np.max(np.abs(r1[inside] + r2[inside] - q[inside])) < 1e-6 * 1e5
    # inside slices 41-60 (before the wheel passes the last slice) the centred wheel runs on the
    # wing rail: the nose carries nothing
    assert np.all(r1[inside] == 0.0)
    summary = result.summary["switches_crossings"]["ws1_left"]
    assert summary["max_Q_rail"] == 2 and lo <= summary["max_Q_at_m"] <= hi
    assert summary["transfer_at_m"] is None
