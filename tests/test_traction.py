"""Traction and braking with the forward motion free: a driven wheelset's force balance below
adhesion, its slip above the adhesion maximum of Polach's (2005) falling friction, braking, and
the input checks (docs/traction-and-braking.md)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from railexu.contact.kalker import kalker_coefficients
from railexu.contact.parameters import ContactParameters
from railexu.contact.polach import polach_2005_forces
from railexu.errors import InputError
from railexu.inputs.catalog import find_input
from railexu.operation.run_settings import RunSettings, run_settings_from_dict
from railexu.operation.traction import Schedule, Traction
from railexu.simulation.simulate import POINT_FIELDS, simulate
from railexu.vehicle.vehicle import load_vehicle

#: Polach (2005), Wear 258, dry rail: mu0 and (k_A, k_S, A, B) of the set railexu ships as its
#: default (railexu.contact.polach.POLACH_2005_PRESETS["dry"]).
MU0_DRY = 0.55
KA, KS, A_RATIO, B_DECAY = 1.0, 0.4, 0.4, 0.6
RADIUS_M = 0.625  # vehicles/wheelset.yaml
MASS_KG = 4250.0
SPIN_INERTIA = 800.0


def _wheelset():
    veh = load_vehicle(find_input("vehicle", "wheelset"))
    contact = ContactParameters(
        creep_model="polach_2005", friction=MU0_DRY, polach_2005=(KA, KS, A_RATIO, B_DECAY)
    )
    return dataclasses.replace(veh, contact=contact)


def _run(traction: Traction, speed=10.0, distance=500.0):
    settings = RunSettings(
        speed_m_per_s=speed, distance_m=distance, initial_lateral_m=0.0, traction=traction,
        output_interval_s=0.002,
    )  # fmt: skip
    result = simulate(_wheelset(), None, settings)
    assert result.status["state"] == "completed", result.status
    return result


@pytest.fixture(scope="module")
def below_adhesion():
    # 0 -> 30 kN m in 1 s, then held: F r = 30 kN m is 24 % of the wheel loads, below the
    # adhesion maximum (about 38 %, test below)
    torque = Schedule(((0.0, 0.0), (1.0, 30.0e3)))
    return _run(Traction(torque_N_m=torque, time_limit_s=2.0))


def test_driven_wheelset_force_balance(below_adhesion):
    """J dw/dt = T - F r and m dv/dt = F: the creep forces carry the torque to the rail."""
    ts = below_adhesion.timeseries
    t = np.asarray(ts["time_s"])
    fx = np.asarray(ts["ws1_left_Fx_N"]) + np.asarray(ts["ws1_right_Fx_N"])
    torque = np.asarray(ts["ws1_axle_torque_N_m"])
    spin = np.asarray(ts["ws1_spin_rad_per_s"])
    acc = np.asarray(ts["achieved_acceleration_m_per_s2"])
    spin_dot = np.gradient(spin, t)
    window = (t > 0.3) & (t < 1.9)
    # spin: the creep force's lever is the rolling radius at the contact (centred wheelset on
    # the tape circle: the nominal radius, to 0.1 %); 1 % of the torque allows for it and the
    # finite-difference derivative of the recorded spin
    residual = torque - fx * RADIUS_M - SPIN_INERTIA * spin_dot
    assert np.max(np.abs(residual[window])) < 0.01 * np.max(torque)
    # translation: nothing but the creep forces acts along the track (1 %: the numerical
    # damping of generalized-alpha in the recorded acceleration)
    assert np.max(np.abs(MASS_KG * acc - fx)[window]) < 0.01 * np.max(np.abs(fx))
    # and the rolling wheelset's acceleration follows T / r / (m + J / r^2) in the held phase
    held = t > 1.2
    expected = 30.0e3 / RADIUS_M / (MASS_KG + SPIN_INERTIA / RADIUS_M**2)
    assert np.allclose(acc[held], expected, rtol=0.01)
    # the speed is the integral of the acceleration (achieved motion, not a prescribed one)
    speed = np.asarray(ts["achieved_speed_m_per_s"])
    assert speed[-1] == pytest.approx(10.0 + np.trapezoid(acc, t), rel=1e-3)
    assert np.asarray(ts["distance_m"])[-1] == pytest.approx(np.trapezoid(speed, t), rel=1e-3)


@pytest.fixture(scope="module")
def slipping():
    # 0 -> 90 kN m over 3 s: the adhesion limit (about 0.38 x 196 kN x 0.625 m = 47 kN m) is
    # passed at about 1.5 s and the wheelset slips
    torque = Schedule(((0.0, 0.0), (3.0, 90.0e3)))
    return _run(Traction(torque_N_m=torque, time_limit_s=3.0))


def _polach_curve_max(result, k: int) -> tuple[float, float]:
    """Maximum of F/Q of railexu's Polach 2005 function over the longitudinal creepage, at the
    load, contact ellipse and speed of output row ``k`` (left wheel, its main contact point;
    a second point near the flange root carries about 0.1 % of the load)."""
    pts = result.contact_points[k, 0, 0]  # wheelset 1, left wheel, (points, fields)
    f = list(POINT_FIELDS)
    p = pts[int(np.argmax(pts[:, f.index("N_N")]))]
    normal, a, b = p[f.index("N_N")], p[f.index("a_m")], p[f.index("b_m")]
    c11, c22, c23 = kalker_coefficients(a / b, 0.28)
    speed = float(result.timeseries["achieved_speed_m_per_s"][k])

    def ratio(xi):
        fx, _ = polach_2005_forces(xi, 0.0, 0.0, normal, MU0_DRY, a, b, 82.0e9, c11, c22, c23,
                                   speed, KA, KS, A_RATIO, B_DECAY)  # fmt: skip
        return -fx / normal  # minimised: the largest F/Q

    best = minimize_scalar(ratio, bounds=(-0.05, -1e-5), method="bounded",
                           options={"xatol": 1e-7})  # fmt: skip
    return -best.fun, -best.x


def test_slipping_wheelset_reaches_the_polach_maximum(slipping):
    ts = slipping.timeseries
    fx = np.asarray(ts["ws1_left_Fx_N"])
    q = np.asarray(ts["ws1_left_Q_N"])
    xi = np.asarray(ts["ws1_left_creep_x"])
    ratio = fx / q
    k = int(np.argmax(ratio))
    curve_max, curve_xi = _polach_curve_max(slipping, k)
    # the simulated maximum is the curve's (sampled every 2 ms while the creepage sweeps through
    # it; the curve is flat there, 0.5 %)
    assert ratio[k] == pytest.approx(curve_max, rel=0.005)
    assert -xi[k] == pytest.approx(curve_xi, rel=0.25)
    # beyond it the wheelset slips: the creepage keeps growing, the adhesion falls
    assert -xi[-1] > 20.0 * -xi[k]
    assert ratio[-1] < 0.95 * ratio[k]
    assert slipping.summary["longitudinal"]["max_adhesion_ratio"] == pytest.approx(
        max(ratio.max(), (np.asarray(ts["ws1_right_Fx_N"]) / ts["ws1_right_Q_N"]).max())
    )


def test_slipping_adhesion_follows_polachs_friction_law(slipping):
    """Independent of railexu's creep function: at full slip the creep force is the friction
    force, F/Q -> mu(w) = mu0 ((1 - A) exp(-B w) + A) with the slip velocity w = |xi| V
    (Polach 2005, eq. for the friction coefficient); with k_S = 0.4 the saturation is
    2/pi (k_A e/(1 + (k_A e)^2) + atan(k_S e)), within 3 % of 1 once e > 50."""
    ts = slipping.timeseries
    xi = np.abs(np.asarray(ts["ws1_left_creep_x"]))
    speed = np.asarray(ts["achieved_speed_m_per_s"])
    ratio = np.asarray(ts["ws1_left_Fx_N"]) / np.asarray(ts["ws1_left_Q_N"])
    w = xi * speed
    mu = MU0_DRY * ((1.0 - A_RATIO) * np.exp(-B_DECAY * w) + A_RATIO)
    full_slip = xi > 0.1
    assert np.count_nonzero(full_slip) > 20
    assert np.allclose(ratio[full_slip], mu[full_slip], rtol=0.03)


def test_tread_brake_decelerates():
    """A brake force per wheel below adhesion: the wheelset decelerates at 2 F_B r / r /
    (m + J / r^2) (the brake torque 2 F_B r against the spin), the creep forces push
    backwards."""
    brake = 10.0e3  # N per wheel: 20 kN per wheelset, 10 % of the load
    applied = Schedule(((0.0, 0.0), (0.1, brake)))  # applied over 0.1 s
    result = _run(Traction(brake_force_N=applied, time_limit_s=1.0))
    ts = result.timeseries
    t = np.asarray(ts["time_s"])
    acc = np.asarray(ts["achieved_acceleration_m_per_s2"])
    expected = -2.0 * brake / (MASS_KG + SPIN_INERTIA / RADIUS_M**2)
    # 1 %: the rolling radius at the contact vs the nominal radius (brake lever), numerics
    assert np.allclose(acc[t > 0.2], expected, rtol=0.01)
    assert np.all(np.asarray(ts["ws1_left_Fx_N"])[t > 0.2] < 0.0)
    assert result.summary["longitudinal"]["max_deceleration_m_per_s2"] == pytest.approx(
        -expected, rel=0.02
    )


def test_free_run_stops_at_standstill():
    """Braking to a stop ends the run, with the reason in the summary."""
    brake = 30.0e3
    result = _run(Traction(brake_force_N=Schedule.constant(brake)), speed=3.0, distance=100.0)
    decel = 2.0 * brake / (MASS_KG + SPIN_INERTIA / RADIUS_M**2)
    assert "stopped" in result.summary["longitudinal"]
    # stops (below 0.5 m/s) after (3 - 0.5) / a
    assert result.status["time_s"] == pytest.approx((3.0 - 0.5) / decel, abs=0.01)


def test_free_run_ends_at_its_distance():
    result = _run(Traction(torque_N_m=Schedule.constant(0.0)), speed=10.0, distance=5.0)
    # the step under way when the distance is reached, and the one Exudyn computes after the
    # pre-step function said stop: at most two steps of 10 m/s x 2 ms beyond
    assert 5.0 <= result.status["distance_m"] <= 5.0 + 2.0 * 10.0 * 0.002 + 1e-9
    assert result.status["time_s"] == pytest.approx(0.5, abs=0.005)


# -- input ---------------------------------------------------------------------------------------
def test_traction_from_a_mapping():
    s = run_settings_from_dict(
        {"speed": "36 km/h", "traction_torque": [["0 s", "0 N m"], ["5 s", "20 kN m"]],
         "driven_wheelsets": ["ws1"], "brake_force": "1 kN", "time_limit": "1 min"}
    )  # fmt: skip
    assert s.free_motion and s.speed_varies
    assert s.traction.torque_N_m.value(2.5, 0.0) == pytest.approx(10.0e3)
    assert s.traction.brake_force_N.value(0.0, 0.0) == 1.0e3
    assert s.traction.wheelsets == ("ws1",) and s.duration_s == 60.0
    by_distance = run_settings_from_dict(
        {"traction_torque": [["0 m", "0 N m"], ["100 m", "1 kN m"]]}
    )
    assert by_distance.traction.torque_N_m.basis == "distance"
    assert by_distance.traction.torque_N_m.value(0.0, 50.0) == pytest.approx(500.0)


@pytest.mark.parametrize(
    "data, words",
    [
        ({"traction_torque": "3 N"}, ["traction_torque", "N m"]),
        ({"traction_torqe": "3 N m"}, ["traction_torqe", "Did you mean 'traction_torque'"]),
        ({"brake_force": "-1 kN"}, ["brake_force", ">= 0"]),
        ({"brake_force": [["0 s", "0 N"], ["1 s", "-1 N"]]}, ["brake_force", ">= 0"]),
        ({"traction_torque": "5 MN m"}, ["traction_torque", "unit"]),
        ({"traction_torque": [["2 s", "0 N m"], ["1 s", "1 N m"]]},
         ["traction_torque", "increase"]),
        ({"traction_torque": [["0 kg", "0 N m"]]}, ["traction_torque.0", "s"]),
        ({"time_limit": "3 s"}, ["time_limit", "only used with"]),
    ],
)  # fmt: skip
def test_bad_traction_is_refused_with_its_key(data, words):
    with pytest.raises(InputError) as info:
        run_settings_from_dict(data, "study.yaml")
    text = str(info.value)
    assert text.startswith("study.yaml")
    for w in words:
        assert w in text


def test_traction_excludes_a_prescribed_speed():
    with pytest.raises(InputError, match="traction"):
        run_settings_from_dict(
            {"traction_torque": "1 kN m", "speed_profile": [["0 m", "10 m/s"], ["1 km", "10 m/s"]]}
        )


def test_unknown_driven_wheelset_is_refused():
    with pytest.raises(InputError, match="driven_wheelsets: unknown wheelset 'ws9'"):
        simulate(_wheelset(), None, RunSettings(distance_m=1.0, traction=Traction(
            wheelsets=("ws9",))))  # fmt: skip


def test_dry_polach_set_is_railexus_default():
    """The parameters used here are the shipped default set (so the test checks what users
    get)."""
    assert ContactParameters().polach_2005 == (KA, KS, A_RATIO, B_DECAY)
    assert math.isclose(MU0_DRY, 0.55)


def test_free_motion_on_a_curve_matches_the_prescribed_speed():
    """Curved track: the vehicle frame follows the free wheelset (model.begin_step). Coasting
    through the R 600 m curve at its balance speed (no torque), the wheelset runs as at the same
    prescribed constant speed: the coordinates relative to the frame mean the same whatever
    the frame's motion, so the quasi-static curving agrees (the speed changes by 0.1 % from
    curving resistance; transients at the curve's ends differ in phase)."""
    from railexu.track.track import load_track

    track = load_track(find_input("track", "curve_r600"))
    vehicle = load_vehicle(find_input("vehicle", "wheelset"))  # the shipped contact: Polach 1999
    runs = {}
    for name, traction in (("prescribed", None), ("free", Traction())):
        settings = RunSettings(speed_m_per_s=19.8, distance_m=500.0, initial_lateral_m=0.0,
                               traction=traction)  # fmt: skip
        runs[name] = simulate(vehicle, track, settings)
        assert runs[name].status["state"] == "completed"
    a, b = runs["prescribed"].timeseries, runs["free"].timeseries
    n = min(len(a), len(b))
    s = np.asarray(a["distance_m"])[:n]
    body = runs["free"].model._speed_body_state()[0]
    assert abs(runs["free"].model.kernel.frame[0] - body) < 0.01  # m: the frame is on the body
    speed = np.asarray(b["achieved_speed_m_per_s"])
    assert np.max(np.abs(speed - 19.8)) < 0.03
    curve = (s > 200.0) & (s < 440.0)
    for column, tol in (("ws1_lateral_m", 2e-5), ("ws1_left_Y_N", 5.0), ("ws1_right_Y_N", 5.0)):
        mean_a = np.mean(np.asarray(a[column])[:n][curve])
        mean_b = np.mean(np.asarray(b[column])[:n][curve])
        assert mean_b == pytest.approx(mean_a, abs=tol), column
