"""What the recorder adds to the time series: accelerations at measurement points (ride
comfort) and, on request, every contact point."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.inputs import load_yaml
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import CONTACT_FIELDS, point_accelerations
from railexu.track.track import load_track
from railexu.vehicle.vehicle import vehicle_from_dict

ROOT = Path(__file__).resolve().parents[1]


def test_point_accelerations_of_rigid_body_rotations():
    """a = a_cg + alpha x r, by hand: yaw acceleration 2 rad/s^2 at 3 m ahead gives 6 m/s^2
    lateral; roll acceleration 1 rad/s^2 at 1.2 m above gives -1.2 m/s^2 lateral and, at
    0.5 m to the left, +0.5 m/s^2 vertical; pitch 0.5 rad/s^2 at 4 m ahead gives -2 m/s^2."""
    qtt = np.array(
        [
            [0.0, 0.1, 0.0, 0.0, 0.0, 2.0],
            [0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 0.3, 0.0, 0.5, 0.0],
        ]
    )
    lever = np.array([[3.0, 0.0, 0.0], [0.0, 0.5, 1.2], [4.0, 0.0, 0.0]])
    a = point_accelerations(qtt, lever)
    assert a[0] == pytest.approx([0.1 + 6.0, 0.0])
    assert a[1] == pytest.approx([-1.2, 0.5])
    assert a[2] == pytest.approx([0.0, 0.3 - 2.0])


@pytest.fixture(scope="module")
def bogie_run():
    """The EU07 bogie on ideal straight track from a 3 mm offset, with a point at its centre of
    gravity (on ideal track the recorded lateral position is the body's own coordinate)."""
    data, lines = load_yaml(ROOT / "vehicles" / "eu07_bogie.yaml")
    centre = data["bodies"]["bogie_1"]["position"]
    data["measurement_points"] = {"cg": {"body": "bogie_1", "position": centre}}
    vehicle = vehicle_from_dict(data, "eu07_bogie.yaml", lines, ROOT / "vehicles")
    settings = RunSettings(
        speed_m_per_s=20.0,
        distance_m=40.0,
        initial_lateral_m=0.003,
        output_interval_s=0.002,
        contact_outputs=True,
    )
    return run(vehicle, load_track(ROOT / "tracks" / "straight.yaml"), settings)


def test_acceleration_at_the_centre_of_gravity_is_the_second_derivative_of_its_position(
    bogie_run,
):
    """Kinematics, independent of the recorder's formula: the recorded lateral acceleration at
    the centre of gravity (an accelerometer's reading, docs/conventions.md) equals the second
    difference of the recorded lateral position plus g times the recorded roll (the
    accelerometer tilts with the body and reads that share of gravity)."""
    ts = bogie_run.timeseries
    t, y = ts.time_s, ts["bogie_1_lateral_m"]
    ok = t > 0.3  # after the start-up
    y_dd = np.gradient(np.gradient(y, t), t) + 9.81 * np.sin(ts["bogie_1_roll_rel_track_rad"])
    a = ts["cg_acc_y_m_per_s2"]
    centre = ok & (t < t[-1] - 0.05)
    scale = np.max(np.abs(a[centre]))
    assert scale > 0.05  # the offset excites the bogie
    # central differences at 2 ms of a signal with content up to ~20 Hz: a few % of the peak
    assert np.max(np.abs(y_dd[centre] - a[centre])) < 0.05 * scale


def test_on_straight_track_the_quasi_static_readings_are_zero(bogie_run):
    """An accelerometer on level straight track reads 0 on average (docs/conventions.md: the
    vertical reading has 1 g removed): the bogie's oscillation from its 3 mm offset averages
    out to within 0.01 m/s^2 (its amplitude is some 0.1-1 m/s^2)."""
    ts = bogie_run.timeseries
    ok = ts.time_s > 0.3
    assert abs(float(np.mean(ts["cg_acc_z_m_per_s2"][ok]))) < 0.01
    assert abs(float(np.mean(ts["cg_acc_y_m_per_s2"][ok]))) < 0.01


def test_contact_points_carry_the_wheel_load(bogie_run):
    """Per wheel, the vertical components of the points' normal forces add up to the wheel
    load Q: within 2 % on the tread, where the creep forces' vertical share is below
    mu Q sin(3 deg)."""
    ts = bogie_run.timeseries
    for side in ("left", "right"):
        q = ts[f"ws1_{side}_Q_N"]
        n = sum(
            ts[f"ws1_{side}_p{k}_N_N"] * np.cos(ts[f"ws1_{side}_p{k}_angle_rad"]) for k in (1, 2, 3)
        )
        assert n == pytest.approx(q, rel=0.02)
    assert {f"ws2_right_p3_{f}" for f in CONTACT_FIELDS} <= set(ts.columns)


def test_the_summary_evaluates_ride_comfort_from_the_recorded_accelerations(bogie_run):
    comfort = bogie_run.summary["comfort"]["points"]
    assert set(comfort) == {"cg"}


def test_recorded_contact_state_is_that_of_the_recorded_coordinates():
    """The recorder keeps the force function's last evaluation of each step instead of
    evaluating the contact again (issue 11). That is right only if Exudyn's Newton iteration ends
    every step with the residual of the accepted state: check it by evaluating the compiled
    forces afresh at the recorded state of every output sample, on a curved track (vehicle
    frame in motion) where a stale evaluation would also show in the track-relative pose."""
    from railexu.simulation.simulate import simulate

    data, lines = load_yaml(ROOT / "vehicles" / "eu07_bogie.yaml")
    vehicle = vehicle_from_dict(data, "eu07_bogie.yaml", lines, ROOT / "vehicles")
    track = load_track(ROOT / "tracks" / "curve_r600.yaml")
    settings = RunSettings(speed_m_per_s=15.0, distance_m=6.0, initial_lateral_m=0.002)
    checked = []
    import railexu.simulation.recorder as recorder_module

    original = recorder_module.Recorder.record

    def record_and_check(self, t, q, qt, qtt=None):
        status = original(self, t, q, qt, qtt)
        model = self.model
        kept_points = model.points.copy()
        kept_pose = model.kernel.ws_local.copy()
        out = np.zeros_like(model._out)
        points = np.zeros_like(model.points)
        ws_force = np.zeros_like(model.ws_force)
        model.evaluate(q, qt, t, out, points, ws_force)
        # the same compiled code on the same numbers: equal to rounding
        checked.append(
            (
                np.max(np.abs(points - kept_points)),
                np.max(np.abs(model.kernel.ws_local - kept_pose)),
            )
        )
        return status

    recorder_module.Recorder.record = record_and_check
    try:
        result = simulate(vehicle, track, settings)
    finally:
        recorder_module.Recorder.record = original
    assert result.status["state"] == "completed"
    assert len(checked) > 50
    assert np.max(checked) <= 1e-9 * 1e5  # forces up to 1e5 N: equal to 1e-9 relative
