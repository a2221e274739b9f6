"""The quasi-static acceptance tests (EN 14363:2016 6.1 and 6.2) against hand calculations.

- Twist: a two-axle wagon with a rigid body on four vertical springs cannot follow the warp of
  a twisted track; the warp compresses its springs and moves load between diagonal wheels.
  With the wheelsets rolled by the cant of the rails under them (roll angle ``c / s``, ``s``
  the cant base), the spring seats ``b_s`` off the centre and the contact points ``b_w``, the
  spring force changes by ``k w`` with the warp ``w = (phi_1 - phi_2) b_s / 2`` at each
  corner, and each wheel's load by ``Delta Q = k w b_s / b_w``: with ``phi_1 - phi_2 =
  g 2a / s`` (twist ``g`` over the wheelbase ``2a``)

      Delta Q = k b_s^2 g 2a / (2 b_w s).

- Yaw resistance: a bogie turned by ``psi`` against linear springs ``k_x`` at ``+-b`` and a
  torsion spring ``k_t`` needs ``M = (k_t + 2 k_x b^2) psi``; against two dry-friction sliders
  of force ``F_c`` at ``+-b`` a constant ``M = 2 F_c b`` once they slide, of the turn's sign.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from railexu.assessment.acceptance.twist import (
    twist_limit_per_mille,
    twist_test,
    twist_track,
    vehicle_wheelbase_m,
)
from railexu.assessment.acceptance.yaw_resistance import yaw_resistance_test
from railexu.errors import InputError
from railexu.vehicle.parts import Damper, Friction
from railexu.vehicle.vehicle import load_vehicle

G = 9.81


# -- twist -------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def wagon_on_twist():
    """The loaded Hbbins on a straight track twisted by the default g_lim (4 per mille for its
    10 m wheelbase), the cant passing 0 under the wagon's centre (no mean cant)."""
    vehicle = load_vehicle("hbbins_loaded")
    return vehicle, twist_test(vehicle, radius_m=None, centred=True)


def test_wheel_unloading_on_a_twist_matches_the_suspension_by_hand(wagon_on_twist):
    """Loaded, each leaf spring works on its second stage: 1 / (0.55 mm/kN) = 1.818 MN/m
    (hbbins_loaded.yaml). Springs at b_s = 1.0 m, contact points at b_w = 0.75 m (S1002 on
    60E1 1:40 centred: the tape circles), cant base 1.5 m, 2a = 10 m, g = 4 per mille:
    Delta Q = 1.818e6 x 1.0^2 x 0.004 x 10 / (2 x 0.75 x 1.5) = 32.3 kN. Within 5 %: the
    contact points move off the tape circles as the wheelsets roll, and the wagon still sways a
    little after its start (the UIC links' friction leaves its lateral motion lightly damped);
    the Hertz contacts in series with the springs (about 1 GN/m) soften it by 0.2 %."""
    vehicle, result = wagon_on_twist
    assert result.status["state"] == "completed"
    k = (193.0e3 - 38.8e3) / (0.150 - 0.06518)  # N/m, the table's second stage
    expected = k * 1.0**2 * 0.004 * 10.0 / (2.0 * 0.75 * 1.5)
    ts = result.run.timeseries
    inside = (ts["distance_m"] >= result.window_m[0]) & (ts["distance_m"] <= result.window_m[1])
    q = {f"{w}{s}": float(np.mean(ts[f"ws{w}_{side}_Q_N"][inside]))
         for w in (1, 2) for s, side in (("L", "left"), ("R", "right"))}  # fmt: skip
    # the warp's share: opposite on the two wheelsets (a mean cant would shift both alike)
    twist_share = ((q["1L"] - q["1R"]) - (q["2L"] - q["2R"])) / 4.0
    assert abs(twist_share) == pytest.approx(expected, rel=0.05)
    q0 = float(np.mean(result.run.model.statics.wheel_loads_N))
    assert q0 == pytest.approx(44800.0 * G / 4.0, rel=0.01)  # 44.8 t on four wheels
    # The twist's share above is the hand value within 5 % (32.14 kN measured, 0.5 %). The
    # whole unloading of the most unloaded wheel also holds a small load shift of the same sign
    # on both wheelsets (0.6 kN: the wheelsets 0.3 mm off centre; 3 kN and 5 mm while the
    # start strained the UIC links' stick springs, docs/acceptance-quasistatic.md), and the
    # reported value (the largest 2 m mean) the wagon's residual sway: both bounded here, not
    # matched.
    mean_unloading = max((q0 - v) / q0 for v in q.values())
    assert expected / q0 * 0.95 <= mean_unloading <= expected / q0 * 1.2
    assert mean_unloading * 0.99 <= result.unloading <= expected / q0 * 1.25
    assert result.twist_per_mille == pytest.approx(4.0)
    assert result.twist_base_m == pytest.approx(10.0)
    assert result.passed and result.unloading < 0.6


def test_a_twist_the_other_way_mirrors_the_unloading(wagon_on_twist):
    """The wagon is symmetric: the ramp lowering the other rail unloads the mirrored wheel by
    as much (1 %: the start-up sway need not be mirrored to the last newton)."""
    vehicle, left = wagon_on_twist
    right = twist_test(vehicle, radius_m=None, centred=True, direction="right")
    assert right.unloading == pytest.approx(left.unloading, rel=0.01)
    mirror = {"left": "right", "right": "left"}
    ws, side = left.unloading_wheel.split("_")
    assert right.unloading_wheel == f"{ws}_{mirror[side]}"


def test_the_twist_verdict_says_what_it_used(wagon_on_twist):
    _, result = wagon_on_twist
    d = result.to_dict()
    assert d["clause"].startswith("EN 14363:2016, 6.1")
    assert d["radius_m"] is None and d["speed_m_per_s"] == pytest.approx(1.5)
    assert d["window_m"][1] > d["window_m"][0]
    assert "2 m sliding mean" in d["rule"] and d["y_over_q_limit"] == 1.2
    assert d["unloading_limit"] == 0.6 and d["status"]["state"] == "completed"


def test_the_twist_limit_is_continuous_and_bounded():
    """g_lim = 20 / 2a* + 2 per mille between 4 and 20 m, 7 and 3 per mille beyond."""
    assert twist_limit_per_mille(3.0) == 7.0
    assert twist_limit_per_mille(4.0) == pytest.approx(7.0)
    assert twist_limit_per_mille(10.0) == pytest.approx(4.0)
    assert twist_limit_per_mille(20.0) == pytest.approx(3.0)
    assert twist_limit_per_mille(30.0) == 3.0
    assert vehicle_wheelbase_m(load_vehicle("eu07")) == pytest.approx(7.9)  # bogie centres
    assert vehicle_wheelbase_m(load_vehicle("hbbins_empty")) == pytest.approx(10.0)


def test_the_twist_track_has_the_asked_gradient():
    track = twist_track(150.0, 4.0, 25.0, "left", entry_m=25.0, lead_m=12.0)
    al = track.alignment
    s = np.array([40.0, 45.0])  # inside the ramp (37 to 62 m)
    assert al.curvature(s) == pytest.approx([1.0 / 150.0] * 2)
    assert -np.diff(al.cant(s))[0] / 5.0 == pytest.approx(0.004)  # 4 mm per metre, falling
    assert al.cant(80.0) == pytest.approx(0.0)


@pytest.mark.parametrize(
    "kwargs",
    [{"radius_m": 30.0}, {"radius_m": math.nan}, {"twist_per_mille": 0.0},
     {"twist_per_mille": math.inf}, {"speed_m_per_s": 20.0}, {"speed_m_per_s": -1.0},
     {"direction": "up"}, {"twist_per_mille": 40.0}],
)  # fmt: skip
def test_absurd_twist_arguments_are_refused_before_running(kwargs):
    with pytest.raises(InputError):
        twist_test(load_vehicle("hbbins_empty"), **kwargs)


@pytest.fixture(scope="module")
def wagon_in_twisted_curve():
    """The loaded Hbbins through the R 150 m left curve with the 4 per mille exit ramp, at
    3 m/s (still quasi-static: 0.06 m/s^2 of centripetal acceleration) to keep the test short."""
    vehicle = load_vehicle("hbbins_loaded")
    return vehicle, twist_test(vehicle, speed_m_per_s=3.0)


def test_the_twisted_curve_loads_the_rails_as_newton_says(wagon_in_twisted_curve):
    """Quasi-static in the window: the rails carry the wagon's centripetal force and the
    weight's component in the track plane, sum Y = m (V^2/R cos(phi) - g sin(phi)), phi the
    cant angle under the wagon's centre (the cant is linear in s and the wagon symmetric, so
    its mean over the bodies is the centre's). 3 %: what is left of the sway after the run-in."""
    vehicle, result = wagon_in_twisted_curve
    assert result.status["state"] == "completed"
    ts = result.run.timeseries
    inside = (ts["distance_m"] >= result.window_m[0]) & (ts["distance_m"] <= result.window_m[1])
    centre = 0.5 * (ts["ws1_s_m"] + ts["ws2_s_m"])[inside]
    phi = np.arcsin(np.abs(result.run.track.alignment.cant(centre)) / 1.5)
    mass = sum(b.mass_kg for b in vehicle.bodies) + sum(w.mass_kg for w in vehicle.wheelsets)
    expected = mass * (3.0**2 / 150.0 * np.cos(phi) - G * np.sin(phi))
    sum_y = sum(ts[f"ws{w}_{side}_Y_N"] for w in (1, 2) for side in ("left", "right"))[inside]
    assert float(np.mean(sum_y)) == pytest.approx(float(np.mean(expected)), rel=0.03)


def test_the_leading_outer_wheel_flanges_and_is_unloaded_on_the_exit_ramp(wagon_in_twisted_curve):
    """The leading outer (right) wheel is the flanging one: contact near the S1002 flange
    angle (70 deg), Y/Q positive and below Nadal's limit (tan 70 - 0.3)/(1 + 0.3 tan 70) = 1.34
    (it does not climb); the ramp lowers its rail ahead of the trailing wheelset: unloaded."""
    _, result = wagon_in_twisted_curve
    assert result.wheel == "ws1_right"
    ts = result.run.timeseries
    inside = ts["distance_m"] >= result.window_m[0]
    assert np.median(ts["ws1_right_max_angle_rad"][inside]) > math.radians(50.0)
    nadal = (math.tan(math.radians(70.0)) - 0.3) / (1.0 + 0.3 * math.tan(math.radians(70.0)))
    assert 0.2 < result.y_over_q < nadal
    assert result.unloading_wheel == "ws1_right" and result.unloading > 0.1
    assert result.passed is (result.y_over_q <= 1.2 and result.unloading <= 0.6)


# -- yaw resistance ----------------------------------------------------------------------------
def test_yaw_resistance_of_linear_springs_is_the_hand_calculation():
    """EU07 bogie_1 against the car body: secondary springs k_x = 2 MN/m at +-1.0 m (their
    lateral stiffness acts at the bogie centre's x: no moment) and the pivot's torsion spring
    100 kN m/rad; turned to asin(3.95 / 150) for R 150 m. X with 2a* = 3.0 m and Q0 = the
    weight / 8. The rotation is exact in the model, hence 0.1 %."""
    vehicle = load_vehicle("eu07")
    result = yaw_resistance_test(vehicle)
    psi = math.asin(3.95 / 150.0)
    k_yaw = 100.0e3 + 2.0 * 2.0e6 * 1.0**2
    assert result.max_moment_N_m == pytest.approx(k_yaw * psi, rel=1e-3)
    mass = sum(b.mass_kg for b in vehicle.bodies) + sum(w.mass_kg for w in vehicle.wheelsets)
    q0 = mass * vehicle.gravity_m_per_s2 / 8.0
    assert result.static_wheel_load_N == pytest.approx(q0, rel=1e-6)
    assert result.x_factor == pytest.approx(k_yaw * psi / (3.0 * q0), rel=1e-3)
    assert result.passed is (result.x_factor <= 0.1)
    # elastic: the moment is odd in the angle and retraces itself
    k = int(np.argmax(result.angle_rad))
    assert result.moment_N_m[k] == pytest.approx(-np.min(result.moment_N_m), rel=1e-6)


def _friction_bogie(stick_stiffness_N_per_m: float | None):
    """EU07 with bogie_1 held to the body only by two longitudinal dry-friction sliders of
    20 kN at y = +-1.0 m (the secondary springs' x stiffness and the pivot spring removed)."""
    vehicle = load_vehicle("eu07").replace("suspension.secondary_*.stiffness.x", "0 N/m")
    # the pivot springs removed (a vehicle file may not give an element without stiffness and
    # damping)
    kept = tuple(el for el in vehicle.suspension if not el.name.startswith("pivot_yaw"))
    vehicle = dataclasses.replace(vehicle, suspension=kept)
    sliders = tuple(
        Friction(f"slider_{side}", ("car_body", "bogie_1"), (3.95, y, 0.95), "x", 20.0e3,
                 stick_stiffness_N_per_m=stick_stiffness_N_per_m)
        for side, y in (("left", 1.0), ("right", -1.0))
    )  # fmt: skip
    return dataclasses.replace(vehicle, suspension=vehicle.suspension + sliders)


def test_yaw_resistance_of_stick_slip_friction_is_a_constant_moment():
    """Sliders behind a stick stiffness of 10 MN/m: they stick for 2 mm (0.002 rad) and then
    carry 2 x 20 kN x 1.0 m = 40 kN m, turning sign with the turn; the viscoplastic flow at
    1 mm/s adds 0.01 % (docs/suspension.md)."""
    result = yaw_resistance_test(_friction_bogie(10.0e6), angular_speed_rad_per_s=1.0e-3)
    assert result.max_moment_N_m == pytest.approx(40.0e3, rel=1e-3)
    n = (result.angle_rad.size - 1) // 4
    turning_up, turning_down = result.moment_N_m[n - 5 : n], result.moment_N_m[2 * n : 2 * n + 5]
    assert turning_up == pytest.approx(40.0e3, rel=1e-3)
    assert turning_down == pytest.approx(-40.0e3, rel=1e-3)  # hysteresis: the sign of the turn


def test_yaw_resistance_of_regularised_friction_follows_its_law():
    """Without a stick stiffness the slider's force is F_c tanh(v / v_s), v = omega b: at
    omega = 1 mrad/s and v_s = 1 mm/s the moment is 2 x 20 kN x 1.0 m x tanh(1) = 30.5 kN m."""
    result = yaw_resistance_test(_friction_bogie(None), angular_speed_rad_per_s=1.0e-3)
    assert result.max_moment_N_m == pytest.approx(40.0e3 * math.tanh(1.0), rel=1e-3)


@pytest.mark.parametrize("series_stiffness", [None, 5.0e6], ids=["linear", "maxwell"])
def test_yaw_resistance_of_yaw_dampers_is_their_viscous_moment(series_stiffness):
    """Two longitudinal dampers of c = 200 kN s/m at +-1.0 m, alone (the secondary springs,
    whose lateral stiffness adds k_y psi^3 b^2 at the second order, and the pivot removed),
    turned at 1 mrad/s: M = 2 c omega b^2 cos^2(psi) = 400 N m, the same behind a bush of
    5 MN/m once its transient (c / k_s = 40 ms) is over. 0.2 %: cos^2(psi) is 0.9993 at the
    end of the turn."""
    vehicle = _friction_bogie(10.0e6)
    dampers = tuple(
        Damper(f"yaw_damper_{side}", ("car_body", "bogie_1"), (3.95, y, 0.95), "x",
               (-1.0, 1.0), (-200.0e3, 200.0e3), series_stiffness_N_per_m=series_stiffness,
               damping_N_s_per_m=200.0e3)
        for side, y in (("left", 1.0), ("right", -1.0))
    )  # fmt: skip
    plain = tuple(
        el
        for el in vehicle.suspension
        if not isinstance(el, Friction) and not el.name.startswith("secondary_1")
    )
    vehicle = dataclasses.replace(vehicle, suspension=plain + dampers)
    result = yaw_resistance_test(vehicle, angular_speed_rad_per_s=1.0e-3)
    n = (result.angle_rad.size - 1) // 4
    assert result.moment_N_m[n - 5 : n] == pytest.approx(400.0, rel=0.002)
    assert result.moment_N_m[3 * n - 5 : 3 * n] == pytest.approx(-400.0, rel=0.002)
    d = result.to_dict()
    assert d["clause"].startswith("EN 14363:2016, 6.2") and d["limit"] == 0.1
    assert d["elements"] == [*(el.name for el in plain if "bogie_1" in el.bodies
                               and "car_body" in el.bodies), "yaw_damper_left",
                             "yaw_damper_right"]  # fmt: skip


def test_a_two_axle_wagon_turns_its_wheelset_in_its_links_and_guards():
    """The loaded Hbbins' ws1 turned by asin(5 / 150) = 33.3 mrad: per side the UIC link's
    pendulum W / L = 103.0 kN / 0.16 m over 33.3 mm plus its sliding friction 0.2 W, and the
    axle guard's 5 MN/m beyond its 25 mm of play; M = 2 x 1.0 m x (sum). W is the spring's
    static load from the statics (W = Q0 - the wheelset's weight / 2 on each side)."""
    vehicle = load_vehicle("hbbins_loaded")
    result = yaw_resistance_test(vehicle)
    assert result.running_gear == "ws1" and result.body == "car_body"
    psi = math.asin(5.0 / 150.0)
    dx = math.sin(psi) * 1.0
    w = result.static_wheel_load_N - 1400.0 * G / 2.0
    per_side = w / 0.16 * dx + 0.2 * w + 5.0e6 * (dx - 0.025)
    assert result.max_moment_N_m == pytest.approx(2.0 * 1.0 * per_side, rel=0.01)
    assert result.wheelbase_m == pytest.approx(10.0)


@pytest.mark.parametrize(
    "kwargs",
    [{"running_gear": "nonexistent"}, {"running_gear": "car_body"},
     {"max_angle_rad": 2.0}, {"max_angle_rad": math.nan}, {"radius_m": 2.0},
     {"angular_speed_rad_per_s": 0.0}, {"limit": -0.1}],
)  # fmt: skip
def test_absurd_yaw_arguments_are_refused(kwargs):
    with pytest.raises(InputError):
        yaw_resistance_test(load_vehicle("eu07"), **kwargs)
