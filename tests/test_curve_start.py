"""A run started inside a curve: the bodies on the chord of what carries them (issue 29,
``railexu.model.curve_start``).

The loaded Hbbins (10 m wheelbase) started inside the turnout's R 245 m circle used to stand
with its car body on the centre line under its centre, 51 mm off the chord of its wheelsets: its
links and axle-guard stops pushed each wheelset sideways (364 kN), one wheel of each carried
40 kN of 110 kN at t = 0 and the wagon derailed in its first metre (the diverging route,
trailing, started inside the circle).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from railexu.model.curve_start import Support, chord_placements, rz
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


def circle_pose(radius_m: float):
    """The local track frame of a left-hand circle at arc length ``x`` from the origin, in the
    frame tangent there (exact geometry)."""

    def pose(x: float):
        theta = x / radius_m
        origin = np.array([radius_m * math.sin(theta), radius_m * (1.0 - math.cos(theta)), 0.0])
        return origin, rz(theta)

    return pose


def test_a_two_axle_body_stands_on_the_chord_of_its_wheelsets():
    """Wheelsets at +-a on a circle of radius R: the body between them lies on their chord,
    R (1 - cos(a / R)) inside the tangent at its centre (51.0 mm for a = 5 m, R = 245 m), and
    parallel to the tangent there; a wheelset's own lateral offset moves the chord with it."""
    r, a = 245.0, 5.0
    supports = [Support(("body", w), x) for w, x in (("ws1", a), ("ws2", -a)) for _ in (0, 1)]
    out = chord_placements({"ws1": (a, 0.0), "ws2": (-a, 0.0)}, {"body": 0.0}, supports,
                           circle_pose(r))  # fmt: skip
    dy, dpsi = out["body"]
    assert dy == pytest.approx(r * (1.0 - math.cos(a / r)), abs=1e-9)
    assert dy == pytest.approx(0.0510, abs=1e-4)
    assert dpsi == pytest.approx(0.0, abs=1e-12)
    shifted = chord_placements({"ws1": (a, 0.003), "ws2": (-a, 0.003)}, {"body": 0.0},
                               supports, circle_pose(r))  # fmt: skip
    assert shifted["body"][0] == pytest.approx(dy + 0.003 * math.cos(a / r), abs=1e-9)


def test_a_bogie_vehicle_stands_on_its_chords():
    """Bogie frames on the chord of their wheelsets (c: half the bogie's wheelbase), the car
    body on the chord of its bogie frames' centres (d: half the bogie distance): the frame
    R (1 - cos(c / R)) inside its tangent, the car body R - (R - dy_frame) cos(d / R) inside
    its own; a body placed off-centre between unequal supports gets a yaw."""
    r, c, d = 300.0, 1.5, 5.0
    wheelsets = {"w1": (d + c, 0.0), "w2": (d - c, 0.0), "w3": (-d + c, 0.0),
                 "w4": (-d - c, 0.0)}  # fmt: skip
    supports = [Support(("f1", "w1"), d + c), Support(("f1", "w2"), d - c),
                Support(("f2", "w3"), -d + c), Support(("f2", "w4"), -d - c),
                Support(("car", "f1"), d), Support(("car", "f2"), -d)]  # fmt: skip
    out = chord_placements(wheelsets, {"car": 0.0, "f1": d, "f2": -d}, supports, circle_pose(r))
    frame = r * (1.0 - math.cos(c / r))
    assert out["f1"][0] == pytest.approx(frame, abs=1e-9)
    assert out["f2"][0] == pytest.approx(frame, abs=1e-9)
    assert out["car"][0] == pytest.approx(r - (r - frame) * math.cos(d / r), abs=1e-9)
    assert out["car"][1] == pytest.approx(0.0, abs=1e-12)
    # a body at the front wheelset's end of the chord: yawed by half the chord's angle
    one = chord_placements({"w1": (0.0, 0.0), "w2": (-2 * d, 0.0)}, {"b": 0.0},
                           [Support(("b", "w1"), 0.0), Support(("b", "w2"), -2 * d)],
                           circle_pose(r))  # fmt: skip
    assert one["b"][1] == pytest.approx(-d / r, rel=1e-6)
    assert one["b"][0] == pytest.approx(0.0, abs=1e-9)


def test_the_loaded_hbbins_started_inside_the_turnout_circle_starts_at_its_static_loads():
    """The loaded Hbbins started inside the diverging route's R 245 m circle (cant 0, the
    plain rail: the turnout's geometry alone), 10 m/s, 6 m. At t = 0 each wheel carries the
    straight-track static load Q0 = 22.4 t g / 2 = 109.9 kN within 0.5 % (before: 180 and
    40 kN) and the lateral wheel forces are those of a centred wheelset's spin creep (< 3 kN;
    before: 92 kN within 6 ms): the car body's centrifugal force m V^2 / R = 17.1 kN reaches the
    wheelsets through the links as the body moves, not as a deflection imposed at the start.
    The run completes and no wheel falls below 70 % of Q0 over the 6 m: the centrifugal
    force acts on the body as a step at the start, and a step's response reaches at most twice
    its quasi-static value, here dQ = (17.1 kN x 1.975 m + 4.8 kN m) / (2 x 1.5 m) = 12.9 kN per
    wheel (the body's moment about the rails; 4.8 kN m from its weight displaced 8 mm by its
    sway on the links' pendulum stiffness 4 W / L = 2.1 MN/m and 3.6 mm by its roll on the
    springs): 2 dQ leaves 76 % of Q0; 6 % of Q0 for the wheelsets' own motion (measured: 75 %).
    Before, the wheels were unloaded within 10 ms."""
    vehicle = load_vehicle(ROOT / "vehicles" / "hbbins_loaded.yaml")
    file = ROOT / "tracks" / "turnout_uk_r245_diverging_trailing.yaml"
    # trailing, the circle runs from 42.9 to 69.3 m; the rear wheelset 1 m beyond the start,
    # the front one at 59 to 65 m
    track = replace(load_track(file, ["turnout.panels=switch", "start=48 m"]), variable_rails=None)
    assert not track.alignment.is_straight
    result = run(vehicle, track, RunSettings(speed_m_per_s=10.0, distance_m=6.0,
                                             initial_lateral_m=0.0))  # fmt: skip
    assert result.status["state"] in COMPLETED_STATES, result.status
    ts = result.timeseries
    q0 = 22.4e3 * vehicle.gravity_m_per_s2 / 2.0
    for i in (1, 2):
        for side in ("left", "right"):
            q = np.asarray(ts[f"ws{i}_{side}_Q_N"])
            assert q[0] == pytest.approx(q0, rel=0.005)
            assert abs(float(ts[f"ws{i}_{side}_Y_N"][0])) < 3.0e3
            assert float(np.min(q)) > 0.7 * q0
