"""Critical speed: the linear analysis against Klingel and against the textbook equations of a
bogie, the nonlinear bisection (deterministic) and the ramp."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from railexu.cli import main
from railexu.contact.hertz import hertz_contact
from railexu.contact.kalker import kalker_coefficients
from railexu.stability import (
    CriticalSpeedSettings,
    bisection_critical_speed,
    critical_speed_settings_from_dict,
    linear_stability,
    profile_equivalent_conicity,
    ramp_critical_speed,
)
from railexu.track import Track
from railexu.vehicle import load_vehicle

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"
CONE = 0.05
RAIL_RADIUS = 0.05
ROUND_RAIL = Track(name="round rail", rail_profile=f"round:{RAIL_RADIUS}", inclination="none")


def _cone_vehicle(name: str):
    vehicle = load_vehicle(VEHICLES / f"{name}.yaml")
    wheelsets = tuple(replace(w, wheel_profile=f"cone:{CONE}") for w in vehicle.wheelsets)
    return replace(vehicle, wheelsets=wheelsets)


def test_linear_free_wheelset_hunts_at_klingel_frequency_and_at_every_speed():
    """A free wheelset: the hunting frequency at low speed is V / L with Klingel's L (within 3 %,
    the roll-rate creepage lengthens it by ~2 %), and it is unstable at every speed (Wickens:
    without suspension nothing damps the kinematic oscillation)."""
    vehicle = _cone_vehicle("wheelset")
    settings = CriticalSpeedSettings(
        methods=("linear",), speed_min_m_per_s=2.0, speed_max_m_per_s=30.0, linear_points=5,
        linearization="profiles",
    )  # fmt: skip
    result = linear_stability(vehicle, ROUND_RAIL, settings)
    klingel = 2.0 * np.pi * np.sqrt(0.75 * 0.625 / CONE)
    f_low = result["frequency_Hz"][0]
    assert f_low == pytest.approx(2.0 / klingel, rel=0.03)
    assert all(z <= 0.0 for z in result["damping_ratio"])
    assert result["critical_speed_m_per_s"] is None and result["unstable_in_range"]


def _textbook_bogie_critical_speed(vehicle, gamma_e: float) -> float:
    """Critical speed of the textbook linear bogie (Wickens): two wheelsets (lateral, yaw) in a
    frame (lateral, yaw) on primary springs, Kalker's linear creep with conicity gamma_e, plus
    the two effects a 3-D model of a rolling wheelset contains: the roll-rate part of the
    lateral creepage (factor 1 + gamma r0 / e0) and the gyroscopic yaw moment of the spinning
    wheelset (I_spin V / r0) (gamma / e0) y'. scipy eigenvalues, bisection on the damping."""
    r0, e0 = 0.625, 0.75
    ws = vehicle.wheelsets[0]
    frame = vehicle.bodies[0]
    primary = next(el for el in vehicle.suspension if el.name == "primary_ws1_left")
    kx, ky = primary.stiffness_N_per_m[0], primary.stiffness_N_per_m[1]
    b = primary.position_m[1]
    a = ws.position_x_m
    # static wheel load: weight plus the car-body share, over four wheels
    load = (vehicle.total_mass_kg * 9.81 - sum(p.force_N[2] for p in vehicle.loads)) / 4
    G, nu = vehicle.contact.shear_modulus_Pa, vehicle.contact.poisson
    h = hertz_contact(0.5 / r0, 0.5 / RAIL_RADIUS, load, G / (1 - nu))
    c11, c22, _ = kalker_coefficients(h.a_m / h.b_m, nu)
    f11 = G * h.a_m * h.b_m * c11
    f22 = G * h.a_m * h.b_m * c22
    mw, iw, i_spin = ws.mass_kg, ws.inertia_kg_m2[1], ws.inertia_kg_m2[2]
    mb, ib = frame.mass_kg, frame.inertia_kg_m2[2]

    def damping(v: float) -> float:
        n = 6  # y1, psi1, y2, psi2, y_frame, psi_frame
        m = np.diag([mw, iw, mw, iw, mb, ib])
        k = np.zeros((n, n))
        c = np.zeros((n, n))
        for i, x in enumerate((a, -a)):
            iy, ip = 2 * i, 2 * i + 1
            c[iy, iy] += 2 * f22 * (1 + gamma_e * r0 / e0) / v
            k[iy, ip] -= 2 * f22
            c[ip, ip] += 2 * f11 * e0**2 / v
            k[ip, iy] += 2 * f11 * e0 * gamma_e / r0
            c[ip, iy] += i_spin * v / r0 * gamma_e / e0
            t = np.zeros(n)
            t[[iy, 4, 5]] = (1.0, -1.0, -x)
            k += 2 * ky * np.outer(t, t)
            t = np.zeros(n)
            t[[ip, 5]] = (1.0, -1.0)
            k += 2 * kx * b * b * np.outer(t, t)
        first = np.block([[np.zeros((n, n)), np.eye(n)],
                          [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]])  # fmt: skip
        lam = [e for e in np.linalg.eigvals(first) if e.imag > 1e-3]
        return min(-e.real / abs(e) for e in lam)

    return brentq(damping, 40.0, 150.0, xtol=0.01)


def test_linear_bogie_critical_speed_matches_the_textbook_equations():
    """The EU07 bogie on cones (0.05 on a 50 mm rail head, Kalker's linear creep): the critical
    speed from Exudyn's linearisation of the full 3-D model agrees with the textbook equations
    within 2 % (what remains: frame roll, vertical coupling, spin creep, gravitational
    stiffness, all small here)."""
    vehicle = _cone_vehicle("eu07_bogie")
    settings = CriticalSpeedSettings(
        methods=("linear",), speed_min_m_per_s=60.0, speed_max_m_per_s=110.0, linear_points=6,
        linearization="profiles", tolerance_m_per_s=0.5,
    )  # fmt: skip
    result = linear_stability(vehicle, ROUND_RAIL, settings)
    ours = result["critical_speed_m_per_s"]
    gamma_e = profile_equivalent_conicity(vehicle, ROUND_RAIL, 0.002)
    textbook = _textbook_bogie_critical_speed(vehicle, gamma_e)
    assert ours == pytest.approx(textbook, rel=0.02)


@pytest.fixture(scope="module")
def bisection_settings():
    return CriticalSpeedSettings(
        methods=("bisection",), speed_min_m_per_s=20.0, speed_max_m_per_s=60.0,
        tolerance_m_per_s=5.0, distance_m=150.0, initial_lateral_m=0.004,
    )  # fmt: skip


def test_bisection_is_deterministic_and_brackets_a_change(bisection_settings):
    vehicle = load_vehicle(VEHICLES / "eu07_bogie.yaml")
    first = bisection_critical_speed(vehicle, None, bisection_settings)
    second = bisection_critical_speed(vehicle, None, bisection_settings)
    assert first["critical_speed_m_per_s"] == second["critical_speed_m_per_s"]
    assert [r["amplitude_m"] for r in first["runs"]] == [r["amplitude_m"] for r in second["runs"]]
    lo, hi = first["bracket_m_per_s"]
    assert hi - lo <= 5.0
    runs = {r["speed_m_per_s"]: r for r in first["runs"]}
    assert runs[lo]["stable"] and not runs[hi]["stable"]


def test_ramp_finds_where_the_limit_cycle_vanishes():
    """Decelerating from a hunting state, the limit cycle vanishes at a speed inside the range,
    below the linear critical speed (44 m/s for the bogie alone): hunting of S1002 on 1:40 rails
    is subcritical."""
    vehicle = load_vehicle(VEHICLES / "eu07_bogie.yaml")
    settings = CriticalSpeedSettings(
        methods=("ramp",), speed_min_m_per_s=20.0, speed_max_m_per_s=55.0,
        ramp_deceleration_m_per_s2=2.0, ramp_settle_m=60.0, initial_lateral_m=0.005,
    )  # fmt: skip
    result = ramp_critical_speed(vehicle, None, settings)
    v = result["critical_speed_m_per_s"]
    assert v is not None and 20.0 < v < 44.0


def test_settings_from_dict_and_cli(tmp_path, capsys):
    settings = critical_speed_settings_from_dict(
        {"methods": ["linear"], "speed_min": "36 km/h", "speed_max": "30 m/s"}
    )
    assert settings.speed_min_m_per_s == pytest.approx(10.0)
    with pytest.raises(ValueError, match="Did you mean 'speed_max'"):
        critical_speed_settings_from_dict({"speed_mx": 3})
    out = tmp_path / "cs"
    status = main(
        ["critical-speed", str(VEHICLES / "eu07.yaml"), "--methods", "linear", "--speed-min",
         "30", "--speed-max", "70", "--linear-points", "5", "--out", str(out), "--quiet"]
    )  # fmt: skip
    assert status == 0
    data = json.loads((out / "critical_speed.json").read_text())
    for key in ("linear_m_per_s", "nonlinear_bisection_m_per_s", "nonlinear_ramp_m_per_s",
                "settings"):  # fmt: skip
        assert key in data
    assert 40.0 < data["linear_m_per_s"] < 70.0
    assert (out / "linear_stability.png").exists() and (out / "linear_stability.svg").exists()
    assert "linear:" in capsys.readouterr().out
