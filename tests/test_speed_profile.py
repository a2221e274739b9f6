"""A prescribed speed profile: constant acceleration between (distance, speed) points, exact
times; the vehicle follows it and the speed constraint's force is the traction m a
(docs/run-settings-format.md, docs/traction-and-braking.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railexu.errors import InputError
from railexu.inputs.catalog import find_input
from railexu.operation.run_settings import RunSettings, run_settings_from_dict
from railexu.operation.speed_profile import SpeedProfile, SpeedProfileError
from railexu.simulation.simulate import simulate
from railexu.vehicle.vehicle import load_vehicle


# -- the profile alone ---------------------------------------------------------------------------
def test_constant_acceleration_segment_is_exact():
    """One segment 10 -> 20 m/s over 150 m: a = (v1^2 - v0^2) / (2 s) = 1 m/s^2, reached after
    (v1 - v0) / a = 10 s (kinematics of constant acceleration)."""
    p = SpeedProfile(((0.0, 10.0), (150.0, 20.0)))
    a = (20.0**2 - 10.0**2) / (2.0 * 150.0)
    assert p.times_s[-1] == pytest.approx(10.0 / a, rel=1e-14)
    for t in np.linspace(0.0, 10.0, 11):
        assert p.speed_at(t) == pytest.approx(10.0 + a * t, rel=1e-14)
        assert p.distance_at(t) == pytest.approx(10.0 * t + 0.5 * a * t * t, rel=1e-14, abs=1e-12)
        assert p.acceleration_at(t) == pytest.approx(a) or t == 10.0
    # time at a distance: the root of s = v0 t + a t^2 / 2
    for s in (0.0, 37.0, 100.0, 150.0):
        t = (-10.0 + math.sqrt(100.0 + 2.0 * a * s)) / a
        assert p.time_at_distance(s) == pytest.approx(t, rel=1e-13, abs=1e-13)
    # beyond the last point: constant speed
    assert p.speed_at(12.0) == 20.0
    assert p.distance_at(12.0) == pytest.approx(150.0 + 2.0 * 20.0)


def test_piecewise_profile_is_continuous_and_consistent():
    p = SpeedProfile(((0.0, 20.0), (100.0, 20.0), (300.0, 10.0), (400.0, 15.0)))
    times = p.times_s
    for i, t in enumerate(times):
        assert p.distance_at(t) == pytest.approx(p.points[i][0], abs=1e-9)
        assert p.speed_at(t) == pytest.approx(p.points[i][1], abs=1e-12)
        assert p.time_at_distance(p.points[i][0]) == pytest.approx(t, abs=1e-12)
    # distance is the integral of speed, speed the integral of acceleration
    t = np.linspace(0.0, times[-1], 20001)
    v = np.array([p.speed_at(x) for x in t])
    a = np.array([p.acceleration_at(x) for x in t])
    s = np.array([p.distance_at(x) for x in t])
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    assert np.allclose(s, integral, atol=1e-6)
    dv = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(t))])
    assert np.allclose(v, 20.0 + dv, atol=2e-3)  # the acceleration jumps at the points


def test_the_deceleration_ramp_is_a_special_case():
    old = RunSettings(speed_m_per_s=40.0, distance_m=500.0, time_step_s=0.002,
                      deceleration_m_per_s2=0.5)  # fmt: skip
    profile = SpeedProfile.ramp(40.0, -0.5, 500.0)
    new = RunSettings(distance_m=500.0, time_step_s=0.002, speed_profile=profile)
    assert new.duration_s == pytest.approx(old.duration_s, rel=1e-12)
    for t in np.linspace(0.0, old.duration_s, 7):
        assert new.speed_at(t) == pytest.approx(old.speed_at(t), rel=1e-12)
        assert new.distance_at(t) == pytest.approx(old.distance_at(t), rel=1e-12, abs=1e-12)


def test_constant_speed_settings_are_unchanged():
    s = RunSettings(speed_m_per_s=12.0, distance_m=60.0)
    assert not s.speed_varies and s.speed_profile is None
    assert s.duration_s == 5.0 and s.distance_at(2.0) == 24.0 and s.speed_at(3.0) == 12.0


# -- input ---------------------------------------------------------------------------------------
def test_profile_from_a_mapping_with_units():
    s = run_settings_from_dict({
        "distance": "1 km",
        "speed_profile": [["0 m", "72 km/h"], ["0.5 km", "108 km/h"],
                          {"distance": "1 km", "speed": "108 km/h"}],
    })  # fmt: skip
    assert s.speed_m_per_s == 20.0 and s.speed_varies
    assert s.speed_profile.points == ((0.0, 20.0), (500.0, 30.0), (1000.0, 30.0))
    assert s.duration_s == pytest.approx(500.0 / 25.0 + 500.0 / 30.0)


@pytest.mark.parametrize(
    "profile, words",
    [
        ([["0 m", "10 m/s"], ["100 m", "0 m/s"]], ["speed_profile", "> 0"]),
        ([["0 m", "10 m/s"], ["0 m", "12 m/s"]], ["speed_profile", "increase"]),
        ([["5 m", "10 m/s"], ["200 m", "12 m/s"]], ["speed_profile", "first point"]),
        ([["0 m", "10 m/s"], ["100 m", "12 m/s"]], ["speed_profile", "cover"]),
        ([["0 m", "10 m/s"], ["200 m", "150 m/s"]], ["speed_profile", "m/s^2", "unit"]),
        ([["0 m", "10 m/s"], ["200 m", "12 km"]], ["speed_profile.1", "m/s"]),
        ([["0 m"]], ["speed_profile.0", "pair"]),
        ("fast", ["speed_profile", "list"]),
    ],
)
def test_bad_profiles_are_refused_with_the_key(profile, words):
    with pytest.raises(InputError) as info:
        run_settings_from_dict({"distance": "200 m", "speed_profile": profile}, "study.yaml")
    text = str(info.value)
    assert text.startswith("study.yaml")
    for w in words:
        assert w in text


def test_speed_and_profile_together_are_refused():
    with pytest.raises(InputError, match="either speed or speed_profile"):
        run_settings_from_dict({"speed": "10 m/s", "speed_profile": [["0 m", "10 m/s"]]})


def test_step_is_checked_against_the_profiles_top_speed():
    with pytest.raises(InputError, match="time_step"):
        RunSettings(distance_m=1000.0, time_step_s=0.01,
                    speed_profile=SpeedProfile(((0.0, 20.0), (1000.0, 40.0))))  # fmt: skip


def test_profile_error_is_an_input_error():
    assert issubclass(SpeedProfileError, InputError)


# -- the vehicle follows it ----------------------------------------------------------------------
@pytest.fixture(scope="module")
def eu07_accelerating():
    """The EU07 on ideal straight track: 10 m/s for 10 m, then 1 m/s^2 to 90 m; the run ends at
    80 m, while it accelerates. The speed constraint's force (its Lagrange multiplier) is read
    at the start of every step."""
    import exudyn as exu

    from railexu.model.assembly import VehicleModel

    vehicle = load_vehicle(find_input("vehicle", "eu07"))
    v1 = math.sqrt(10.0**2 + 2.0 * 1.0 * 80.0)
    profile = SpeedProfile(((0.0, 10.0), (10.0, 10.0), (90.0, v1)))
    settings = RunSettings(distance_m=80.0, initial_lateral_m=0.0, speed_profile=profile)
    forces = []
    begin_step = VehicleModel.begin_step

    def spy(self, t, h, distance_m=math.inf):
        out = self.mbs.GetObjectOutput(self.speed_constraint, exu.OutputVariableType.Force)
        forces.append((t - h, -float(np.ravel(out)[0])))
        return begin_step(self, t, h, distance_m)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(VehicleModel, "begin_step", spy)
        result = simulate(vehicle, None, settings)
    assert result.status["state"] == "completed"
    return result, profile, np.array(forces)


def test_the_vehicle_follows_the_profile(eu07_accelerating):
    result, profile, _ = eu07_accelerating
    ts = result.timeseries
    t = np.asarray(ts["time_s"])
    expected = np.array([profile.speed_at(x) for x in t])
    # the car body's speed is held by the constraint (to the solver's tolerance)
    assert np.allclose(ts["achieved_speed_m_per_s"], expected, atol=1e-6)
    assert np.allclose(ts["speed_m_per_s"], expected, atol=1e-12)
    assert np.allclose(ts["distance_m"], [profile.distance_at(x) for x in t], atol=1e-9)
    acc = np.asarray(ts["achieved_acceleration_m_per_s2"])
    late = t > profile.times_s[1] + 0.1
    assert np.allclose(acc[late], 1.0, atol=1e-3)
    assert result.summary["longitudinal"]["max_acceleration_m_per_s2"] == pytest.approx(
        1.0, abs=0.01
    )


def test_traction_force_is_mass_times_acceleration(eu07_accelerating):
    """The speed constraint's force accelerates every mass, and the spin of every wheelset
    (J / r^2 each); the wheels' longitudinal creep forces are what spins the (undriven)
    wheelsets up: sum F = -sum J a / r^2 (Newton-Euler)."""
    result, profile, forces = eu07_accelerating
    vehicle = result.vehicle
    mass = sum(b.mass_kg for b in vehicle.bodies) + sum(w.mass_kg for w in vehicle.wheelsets)
    spin = sum(w.inertia_kg_m2[2] / w.nominal_radius_m**2 for w in vehicle.wheelsets)
    # the step to 1 m/s^2 sets the car body and bogies swinging on their longitudinal links
    # (2.2 Hz, +-30 kN, lightly damped): the mean over 10 cycles; 2 % for the part-cycle left
    # in the mean and the rolling radii at the contacts vs the nominal ones
    t, force = forces[:, 0], forces[:, 1]
    accelerating = t > profile.times_s[1] + 0.5
    assert np.mean(force[accelerating]) == pytest.approx((mass + spin) * 1.0, rel=0.02)
    assert np.max(np.abs(force[t < profile.times_s[1] - 0.1])) < 10.0  # N, at constant speed
    ts = result.timeseries
    t = np.asarray(ts["time_s"])
    late = t > profile.times_s[1] + 0.5
    fx = sum(np.asarray(ts[c]) for c in ts.columns if c.endswith("_Fx_N") and c.count("_") == 3)
    # the wheelsets swing with the bogies: their mean (2 %, as above)
    assert np.mean(fx[late]) == pytest.approx(-spin * 1.0, rel=0.02)


# -- command line --------------------------------------------------------------------------------
def test_cli_speed_profile_and_traction(tmp_path, capsys):
    import json

    from railexu.cli import main
    from railexu.results import TimeSeries

    csv = tmp_path / "profile.csv"
    csv.write_text("distance,speed\n0 m, 36 km/h\n10, 12\n20 m, 12 m/s\n")
    out = tmp_path / "profile"
    args = ["run", "wheelset", "--distance", "20", "--initial-lateral", "0", "--quiet",
            "--no-plots"]  # fmt: skip
    assert main([*args, "--speed-profile", str(csv), "--out", str(out)]) == 0
    ts = TimeSeries.from_csv(out / "timeseries.csv")
    a = (12.0**2 - 10.0**2) / (2.0 * 10.0)
    t1 = 2.0 / a
    assert ts["speed_m_per_s"][-1] == pytest.approx(12.0)
    assert ts["time_s"][-1] == pytest.approx(t1 + 10.0 / 12.0, abs=0.002)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["longitudinal"]["max_acceleration_m_per_s2"] == pytest.approx(a, rel=1e-3)
    assert summary["settings"]["speed_profile"]["points"][1] == [10.0, 12.0]

    out = tmp_path / "free"
    assert main([*args, "--traction-torque", "5 kN m", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["longitudinal"]["free_motion"] is True
    assert summary["settings"]["traction"]["torque_N_m"]["points"] == [[0.0, 5000.0]]
    capsys.readouterr()
    # a profile with --speed, or a bad file, is refused naming the problem
    assert main([*args, "--speed-profile", str(csv), "--speed", "3", "--out",
                 str(tmp_path / "x")]) != 0  # fmt: skip
    assert "--speed-profile" in capsys.readouterr().err
    csv.write_text("0 m, 10 m/s\n100 m, 3 kg\n")
    assert main([*args, "--speed-profile", str(csv), "--out", str(tmp_path / "y")]) != 0
    err = capsys.readouterr().err
    assert "profile.csv" in err and ":2" in err


def test_profile_on_a_curve_moves_the_frame():
    """Curved track: the vehicle frame runs with the profile (set_time: FR_S, FR_V, FR_VDOT). A
    two-point profile at a constant speed takes the profile's code path and must reproduce the
    constant-speed run; an accelerating one moves the frame with its distance, speed and
    acceleration."""
    from railexu.model.forces import FR_S, FR_V, FR_VDOT
    from railexu.track.track import load_track

    track = load_track(find_input("track", "curve_r600"))
    vehicle = load_vehicle(find_input("vehicle", "wheelset"))

    def run(**kw):
        result = simulate(
            vehicle, track, RunSettings(distance_m=300.0, initial_lateral_m=0.0, **kw)
        )
        assert result.status["state"] == "completed"
        return result

    constant = run(speed_m_per_s=19.8).timeseries
    flat = run(speed_profile=SpeedProfile(((0.0, 19.8), (300.0, 19.8)))).timeseries
    for column in ("ws1_lateral_m", "ws1_left_Y_N", "ws1_right_Q_N", "ws1_yaw_rad"):
        # the same motion by another code path: the same to rounding (1e-6 of the range)
        scale = np.max(np.abs(constant[column]))
        assert np.max(np.abs(np.asarray(flat[column]) - constant[column])) < 1e-6 * scale
    profile = SpeedProfile(((0.0, 15.0), (300.0, 22.0)))
    accelerating = run(speed_profile=profile)
    ts = accelerating.timeseries
    t = np.asarray(ts["time_s"])
    assert np.allclose(ts["achieved_speed_m_per_s"], [profile.speed_at(x) for x in t], atol=1e-6)
    frame, model = accelerating.model.kernel.frame, accelerating.model
    model.set_time(5.0)
    assert frame[FR_S] - model.frame_start_m == pytest.approx(profile.distance_at(5.0))
    assert frame[FR_V] == pytest.approx(profile.speed_at(5.0))
    assert frame[FR_VDOT] == pytest.approx((22.0**2 - 15.0**2) / 600.0)
    # the last step ends just beyond the profile's last point: constant speed there
    assert ts["speed_m_per_s"][-1] == pytest.approx(22.0)
