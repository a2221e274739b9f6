"""Critical speed: the linear analysis against Klingel and against the textbook equations of a
bogie, the nonlinear bisection (deterministic) and the ramp."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from wickens import add_wheelset

from railexu.cli import main
from railexu.contact.hertz import hertz_contact
from railexu.contact.kalker import kalker_coefficients
from railexu.report.stability_figures import critical_speed_figures
from railexu.stability import (
    CriticalSpeedSettings,
    bisection_critical_speed,
    body_roles,
    compare_linear_nonlinear,
    critical_speed_settings_from_dict,
    linear_stability,
    name_mode,
    profile_equivalent_conicity,
    ramp_critical_speed,
)
from railexu.stability.modes import mac, track_branches, unstable_bands
from railexu.track.track import Track
from railexu.vehicle.vehicle import load_vehicle

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
            add_wheelset(c, k, i, x, v, gamma_e, (f11, f22), (r0, e0), i_spin, (kx, ky, b))
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
        tolerance_m_per_s=5.0, distance_m=300.0, initial_lateral_m=0.004,
    )  # fmt: skip


def test_bisection_is_deterministic_and_says_where_a_bounded_cycle_is_sustained(
    bisection_settings,
):
    """The EU07 bogie (S1002 on UIC60 1:40) from a 4 mm offset, runs of 300 m: the same runs
    twice give the same amplitudes; at 20 m/s the motion ends on a sustained small cycle (0.4 mm
    measured, docs/validation.md; after 150 m it was still growing towards it with the contact
    force at the patch's load centroid), which is unstable whatever its amplitude (no threshold
    decides), so
    the bisection says that it is unstable down to the range's lowest speed and that a bounded
    cycle of that amplitude exists there."""
    vehicle = load_vehicle(VEHICLES / "eu07_bogie.yaml")
    first = bisection_critical_speed(vehicle, None, bisection_settings)
    second = bisection_critical_speed(vehicle, None, bisection_settings)
    assert first["critical_speed_m_per_s"] == second["critical_speed_m_per_s"]
    assert [r["amplitude_m"] for r in first["runs"]] == [r["amplitude_m"] for r in second["runs"]]
    assert first["unstable_in_range"] and first["critical_speed_m_per_s"] is None
    low = first["critical_run"]
    assert low["speed_m_per_s"] == 20.0 and low["classification"] == "small limit cycle"
    assert 0.1e-3 < low["amplitude_m"] < 1e-3
    assert "sustained cycle of" in first["note"] and "bounded cycle" in first["note"]
    assert first["sustained_cycles"][0]["speed_m_per_s"] == 20.0


class _RampSeries:
    """A ramp's time series with a known branch: settle at ``v0`` for 12 s, then decelerate at
    ``a``; a 3 Hz oscillation of 3 mm (ws1) that holds while the speed is at least ``fold`` and
    then decays at 1.5 /s (ws2 the same at half the amplitude)."""

    def __init__(self, v0: float, a: float, fold: float, v_end: float):
        t_settle = 12.0
        t_end = t_settle + (v0 - v_end) / a
        self.time_s = np.arange(0.0, t_end, 0.01)
        t = self.time_s
        speed = np.where(t < t_settle, v0, v0 - a * (t - t_settle))
        self.distance_m = np.cumsum(speed) * 0.01 - speed[0] * 0.01
        t_fold = t_settle + (v0 - fold) / a
        envelope = 3e-3 * np.exp(-1.5 * np.clip(t - t_fold, 0.0, None))
        y = envelope * np.sin(2 * np.pi * 3.0 * t)
        self.columns = {"speed_m_per_s": speed, "ws1_lateral_m": y, "ws2_lateral_m": 0.5 * y}
        self.settle_m = float(v0 * t_settle)

    def wheelset_indices(self):
        return [1, 2]

    def __getitem__(self, name):
        return self.columns[name]


@pytest.mark.parametrize("a", [1.0, 0.5])
def test_ramp_classifies_windows_by_growth_rate(a):
    """A synthetic ramp over a fold at 33 m/s: windows of 16 periods (5.33 s) are classified
    by the fitted envelope's growth rate; the critical speed is the end of the last window with
    the cycle, within one window's speed change (the stated resolution, a x 5.33 s) of the fold,
    at both rates."""
    from railexu.stability.ramp import classify_ramp

    ts = _RampSeries(45.0, a, 33.0, 25.0)
    settings = CriticalSpeedSettings(methods=("ramp",))
    out = classify_ramp(ts, ts.settle_m, a, settings)
    assert out["plateau"]["classification"] == "limit cycle"
    assert out["window_s"] == pytest.approx(16.0 / 3.0, rel=0.01)
    res = out["resolution_m_per_s"]
    assert res == pytest.approx(a * 16.0 / 3.0, rel=0.01)
    assert 33.0 - res <= out["critical_speed_m_per_s"] <= 33.0 + res
    classes = [w["classification"] for w in out["windows"]]
    assert classes[0] == "limit cycle" and classes[-1] in ("decaying", "below floor")
    # the cycle followed from the plateau ends at the fold, within one window's speed change
    assert 33.0 - res <= out["fold_m_per_s"] <= 33.0 + res
    assert out["drift_within_band"]  # a constant 3 mm: no drift


def test_ramp_budget_cuts_the_ramp_and_says_so():
    """A ramp that needs more distance than its budget is cut there (the speed at the cut from
    v^2 = v0^2 - 2 a s); one that fits is not."""
    from railexu.stability.ramp import ramp_profile

    profile, distance, v_end, cut = ramp_profile(50.0, 20.0, 0.5, 200.0, 1000.0)
    assert cut and distance == 1000.0
    assert v_end == pytest.approx(np.sqrt(50.0**2 - 2 * 0.5 * 800.0))
    assert profile.points[-1] == pytest.approx((1000.0, v_end))
    _, distance, v_end, cut = ramp_profile(50.0, 20.0, 0.5, 200.0, 10000.0)
    assert not cut and v_end == 20.0 and distance == pytest.approx(200.0 + 2100.0)
    with pytest.raises(ValueError, match="ramp_budget"):
        CriticalSpeedSettings(ramp_budget_m=100.0, ramp_settle_m=200.0)


@pytest.mark.slow
def test_ramp_runs_at_two_rates_within_its_budget():
    """The EU07 bogie decelerating from 40 m/s (5 mm disturbance, 60 m settling) at 2 and
    4 m/s^2 (the requested rate and twice it): both ramps are run and recorded with their
    windows, each classified by growth rate, with their measured drift;
    a speed found lies within the ramp (the EU07 bogie's cycle shrinks steadily with speed,
    docs/validation.md, so at these rates the windows may call the branch decaying early: the
    result then says the rates disagree and gives no verdict); with a budget of 300 m the
    requested ramp is cut at it and the faster one fits."""
    vehicle = load_vehicle(VEHICLES / "eu07_bogie.yaml")
    settings = CriticalSpeedSettings(
        methods=("ramp",), speed_min_m_per_s=22.0, speed_max_m_per_s=40.0,
        ramp_deceleration_m_per_s2=2.0, ramp_settle_m=60.0, initial_lateral_m=0.005,
        ramp_budget_m=300.0,
    )  # fmt: skip
    result = ramp_critical_speed(vehicle, None, settings)
    slow, fast = result["ramps"]
    assert [slow["deceleration_m_per_s2"], fast["deceleration_m_per_s2"]] == [2.0, 4.0]
    assert slow["distance_m"] == pytest.approx(300.0) and slow["cut"]
    # twice the rate fits the budget: 60 m + (40^2 - 22^2) / (2 x 4) = 199.5 m
    assert fast["distance_m"] == pytest.approx(199.5) and not fast["cut"]
    # 139.5 m of ramp at about 31 m/s is 4.5 s, about one window of 16 periods at 3.5-4 Hz
    assert fast["windows"] or "shorter than one window" in fast["note"]
    assert slow["windows"]
    for r in (fast, slow):
        assert r["status"] in ("converged", "budget exhausted", "not found"), r
        assert all("growth_per_period" in w for w in r["windows"])
        assert "drift_per_period" in r and "fold_m_per_s" in r
        v = r["critical_speed_m_per_s"]
        assert v is None or r["end_speed_m_per_s"] - 1e-9 <= v <= 40.0
    if result["rate_independent"] is False:  # no verdict where the two rates disagree
        assert "rate-dependent" in result["note"]
        # the requested ramp was cut at its budget: that status says why they differ
        assert result["status"] in ("rate-dependent", "budget exhausted")
        assert result["critical_speed_m_per_s"] is None


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
    # the EU07's lowest zero-damping speed is that of its bogie hunting mode, as before the modes
    # were named; the car-body modes stay damped over the range
    assert data["linear_mode"] == "bogie hunting"
    modes = data["linear"]["modes"]
    assert modes["bogie hunting"]["critical_speed_m_per_s"] == pytest.approx(data["linear_m_per_s"])
    for name in ("car-body lateral", "car-body yaw", "car-body roll"):
        assert modes[name]["critical_speed_m_per_s"] is None and modes[name]["stable_in_range"]
    assert data["comparison"] is None  # no nonlinear method run
    for name in ("linear_stability", "root_locus"):
        assert (out / f"{name}.png").exists() and (out / f"{name}.svg").exists()
    text = capsys.readouterr().out
    assert "linear:" in text and "bogie hunting mode" in text
    # figure content: one damping line per followed mode, each crossing starred; the root locus
    # has one scatter per mode, damping ratio against frequency, and a speed colour bar
    figs = critical_speed_figures(data)
    ax = figs["linear_stability"].axes[0]
    assert ax.get_ylabel() == "damping ratio [-]"
    crossing = [m for m in modes.values() if m["critical_speed_m_per_s"] is not None]
    assert len([ln for ln in ax.get_lines() if ln.get_marker() == "*"]) == len(crossing)
    assert len(ax.get_legend().get_texts()) == len(modes)
    rl = figs["root_locus"].axes
    assert rl[0].get_xlabel() == "frequency [Hz]" and rl[0].get_ylabel() == "damping ratio [-]"
    assert len(rl[0].collections) == len(modes) and rl[1].get_ylabel() == "speed [m/s]"


def test_modes_are_named_by_their_participation():
    eu07 = load_vehicle(VEHICLES / "eu07.yaml")
    roles = body_roles(eu07)
    assert roles["car_body"] == "car_body" and roles["bogie_1"] == "bogie"
    assert roles["ws1"] == "wheelset"
    bogie = load_vehicle(VEHICLES / "eu07_bogie.yaml")
    assert set(body_roles(bogie).values()) == {"bogie", "wheelset"}
    assert name_mode({"wheelset:lateral": 0.5, "wheelset:yaw": 0.2, "bogie:lateral": 0.2}) == (
        "wheelset hunting"
    )
    assert name_mode({"wheelset:lateral": 0.2, "bogie:yaw": 0.3, "bogie:lateral": 0.3}) == (
        "bogie hunting"
    )
    assert name_mode({"car_body:yaw": 0.6, "car_body:lateral": 0.2, "bogie:lateral": 0.1}) == (
        "car-body yaw"
    )
    assert name_mode({"car_body:roll": 0.5, "car_body:lateral": 0.4}) == "car-body roll"
    assert name_mode({"car_body:other": 0.8, "car_body:lateral": 0.2}) is None  # vertical
    # the frames' yaw alone: not hunting; a vehicle without a car body gets no car-body name
    assert name_mode({"bogie:yaw": 0.9, "wheelset:lateral": 0.05}) == "bogie yaw"
    assert name_mode({"bogie:roll": 0.6, "bogie:lateral": 0.2, "wheelset:lateral": 0.1}) == (
        "bogie roll"
    )
    settings = CriticalSpeedSettings(methods=("linear",), speed_min_m_per_s=20.0,
                                     speed_max_m_per_s=40.0, linear_points=2)  # fmt: skip
    names = {m["name"] for m in linear_stability(bogie, None, settings)["modes"].values()}
    assert names and not any(n.startswith("car-body") for n in names)


def test_soft_secondary_damping_reports_the_car_body_mode():
    """The EU07 with almost no secondary lateral and yaw damping (0.2 kN s/m per side, 1 kN m s/rad
    at the pivots instead of 15 kN s/m and 60 kN m s/rad): the car body's yaw mode on the
    secondary suspension (0.87 Hz) is destabilised where the wheelsets' kinematic frequency
    V / L meets it, near 11 m/s (L about 17 m with the equivalent conicity): the classical
    car-body instability at low speed. The analysis names that mode; the bogie hunting mode
    stays damped at these speeds."""
    vehicle = load_vehicle(
        VEHICLES / "eu07.yaml",
        [
            "suspension.secondary_1.damping.y=0.2 kN s/m",
            "suspension.secondary_2.damping.y=0.2 kN s/m",
            "suspension.pivot_yaw_1.damping=1 kN m s/rad",
            "suspension.pivot_yaw_2.damping=1 kN m s/rad",
        ],
    )
    settings = CriticalSpeedSettings(
        methods=("linear",), speed_min_m_per_s=5.0, speed_max_m_per_s=25.0, linear_points=3
    )
    result = linear_stability(vehicle, None, settings)
    assert result["critical_mode"] == "car-body yaw"
    # where V / L = 0.87 Hz for L = 2 pi sqrt(e0 r0 / gamma_e) of the equivalent conicity
    gamma = result["equivalent_conicity"]
    kinematic = 0.87 * 2 * np.pi * np.sqrt(0.75 * 0.625 / gamma)
    assert 5.0 < result["critical_speed_m_per_s"] < 20.0
    assert result["critical_speed_m_per_s"] == pytest.approx(kinematic, rel=0.5)
    assert result["modes"]["bogie hunting"]["stable_in_range"]
    assert result["hunting_critical_speed_m_per_s"] is None
    # a nonlinear value far above it gets an explanation naming the car-body mode
    data = {"linear_m_per_s": result["critical_speed_m_per_s"], "linear": result,
            "nonlinear_bisection_m_per_s": 60.0, "nonlinear_ramp_m_per_s": None}  # fmt: skip
    note = compare_linear_nonlinear(data, settings)
    # in the vehicle's own words: its suspension elements joined to the car body by name
    assert "car-body yaw" in note and "secondary_1" in note and "secondary suspension" not in note


def test_comparison_words():
    settings = CriticalSpeedSettings()
    lin = {"critical_mode": "bogie hunting", "hunting_critical_speed_m_per_s": 50.0}

    def compare(linear, bisection):
        data = {"linear_m_per_s": linear, "linear": lin, "nonlinear_bisection_m_per_s": bisection}
        return compare_linear_nonlinear(data, settings)

    assert compare(50.0, 45.0) is None  # 11 %: within 25 %
    assert "subcritical" in compare(50.0, 35.0)
    assert "equivalent conicity" in compare(50.0, 70.0)
    assert compare(None, 35.0) is None and compare(50.0, None) is None


class _FakeMode:
    """A mode with a shape, frequency and damping ratio (for the tracking tests)."""

    def __init__(self, shape, frequency_Hz, damping_ratio, name="car-body yaw"):
        self.shape = np.asarray(shape, dtype=complex)
        self.frequency_Hz = frequency_Hz
        self.damping_ratio = damping_ratio
        self.name = name


def test_modes_are_followed_by_shape_not_by_frequency_order():
    """Two modes whose frequencies cross between speeds (3 Hz rising to 9 Hz, 6 Hz staying):
    MAC links each to its own shape, so the branch of shape a goes 3 -> 5 -> 9 Hz although at
    the second speed it is the lower and at the third the higher one; MAC of orthogonal shapes
    is 0, of equal ones 1, of a shape turned by a complex factor 1."""
    a, b = np.array([1.0, 0.1, 0.0]), np.array([0.0, 0.2, 1.0])
    assert mac(a, 2j * a) == pytest.approx(1.0) and mac(a, np.array([0.0, 0.0, 1.0])) == 0.0
    per_speed = [
        [_FakeMode(a, 3.0, 0.1), _FakeMode(b, 6.0, 0.2)],
        [_FakeMode(b, 6.0, 0.15), _FakeMode(a + 0.05, 5.0, 0.05)],
        [_FakeMode(a, 9.0, -0.01), _FakeMode(b + 0.1, 6.1, 0.1)],
    ]
    branches = track_branches(per_speed)
    freqs = sorted([[b.modes[k].frequency_Hz for k in sorted(b.modes)] for b in branches])
    assert freqs == [[3.0, 5.0, 9.0], [6.0, 6.0, 6.1]]


def test_a_narrow_unstable_band_is_reported_as_a_band():
    """A branch unstable only between 12.5 and 17.5 m/s (damping -0.001 at 15 m/s, as the
    wagon's car-body yaw): one band with both ends refined (linear in between here, so the
    secant steps land on the exact zeros 13.75 and 15.83 m/s) and not "stays unstable"."""
    speeds = [10.0, 12.5, 15.0, 17.5, 20.0]
    zeta = {10.0: 0.01, 12.5: 0.001, 15.0: -0.001, 17.5: 0.002, 20.0: 0.02}

    def z_of(v):  # piecewise linear through the points
        return float(np.interp(v, speeds, [zeta[s] for s in speeds]))

    shape = np.array([1.0, 0.0])
    branch = track_branches([[_FakeMode(shape, 1.0, zeta[v])] for v in speeds])[0]

    def modes_at(v):
        return [_FakeMode(shape, 1.0, z_of(v))]

    bands = unstable_bands(speeds, branch, modes_at, 0.1)
    assert len(bands) == 1
    lo, hi = bands[0]
    assert lo == pytest.approx(12.5 + 2.5 * 0.001 / 0.002, abs=0.01)
    assert hi == pytest.approx(15.0 + 2.5 * 0.001 / 0.003, abs=0.01)


def _fake_stages(monkeypatch, fold: float):
    """Replace each stage's run by a limit-cycle branch that exists above ``fold`` m/s (amplitude
    ``1 mm sqrt(v - fold)``) and, once lost down the staircase, stays lost; returns the list of
    stages (their speeds)."""
    import railexu.stability.branch as br

    stages = []

    def fake(vehicle, track, speeds, settings):
        stages.append(list(speeds))
        out, lost = [], False
        for v in speeds:
            lost = lost or v < fold
            amp = 0.2e-3 if lost else 1e-3 * np.sqrt(v - fold)
            out.append({"speed_m_per_s": v, "stable": lost, "amplitude_m": amp,
                        "classification": "decaying" if lost else "limit cycle",
                        "growth_per_period": -0.05 if lost else 0.0,
                        "frequency_Hz": 3.0})  # fmt: skip
        return out

    monkeypatch.setattr(br, "run_stage", fake)
    return stages


def test_branch_follows_the_limit_cycle_down_to_its_fold(monkeypatch):
    """Stepping down from 60 m/s by 5 m/s, then in quarter steps from the last speed with the
    cycle, brackets the fold (33.3 m/s) within the 1 m/s tolerance; each stage is one run down a
    staircase (every plateau starts from the state of the one above), a refining stage settles
    at the top speed and decelerates to the last speed with the cycle; with a budget of 10
    plateaus the branch says so."""
    from railexu.stability import branch_critical_speed

    stages = _fake_stages(monkeypatch, 33.3)
    settings = CriticalSpeedSettings(methods=("branch",), speed_min_m_per_s=20.0,
                                     speed_max_m_per_s=60.0, tolerance_m_per_s=1.0)  # fmt: skip
    result = branch_critical_speed(None, None, settings)
    lo, hi = result["bracket_m_per_s"]
    assert result["converged"] and result["status"] == "converged"
    assert lo < 33.3 <= hi and hi - lo <= 1.0 and result["resolution_m_per_s"] == hi - lo
    assert result["critical_speed_m_per_s"] == hi
    assert stages[0] == [60.0, 55.0, 50.0, 45.0, 40.0, 35.0, 30.0, 25.0, 20.0]
    assert stages[1] == [60.0, 35.0, 33.75, 32.5, 31.25]
    assert result["plateaus_run"] == sum(len(s) for s in stages)
    assert "growth rate" in result["judged_by"] and "last state" in result["disturbance"]
    stages.clear()
    short = branch_critical_speed(None, None, replace(settings, max_runs=10))
    assert not short["converged"] and short["status"] == "budget exhausted"
    assert "budget exhausted" in short["note"] and short["bracket_m_per_s"] == [30.0, 35.0]


def test_staircase_profile():
    """Plateaus of the given length at each speed, 2 m/s^2 between them."""
    from railexu.stability.branch import staircase

    profile, plateaus = staircase([40.0, 30.0], 100.0)
    assert plateaus[0] == (40.0, 0.0, 100.0)
    ramp = (40.0**2 - 30.0**2) / (2 * 2.0)
    assert plateaus[1] == pytest.approx((30.0, 100.0 + ramp, 200.0 + ramp))
    assert profile.points[-1] == pytest.approx((200.0 + ramp, 30.0))


def test_growth_rate_classification_of_a_bogie_branch(monkeypatch):
    """The EU07 bogie on S1002/UIC60 1:40, from a 5 mm disturbance at 45 m/s, stepping down by
    10 m/s (one run, plateaus of 300 m, each starting from the state of the one above; 150 m
    left the 45 m/s plateau still settling onto its cycle from above with the patch-centroid
    kernel): the large cycle (7.2 mm at 45, 6.6 mm at 35 m/s measured) is lost between 35 and
    25 m/s, below the linear critical speed of the bogie alone (44.4 m/s, docs/validation.md):
    hunting of these profiles is subcritical (True 1999). The fold is reported with its bracket
    (the first stage's largest fall, not refined at this tolerance) and what the motion does
    below it (the small cycle, 0.4 mm at 25 m/s: another branch); a cycle is sustained down to
    the lowest speed, so the critical speed lies below the range, with the amplitude there
    reported. The same runs classified with the 1 mm label floor at 3 mm give the same verdicts
    (no threshold decides; only labels change). Runs classified as limit cycles change by less
    than 1 % per period."""
    import railexu.stability.branch as br

    runs: dict = {}

    def cached(vehicle, track, settings):  # the physics once, the classification twice
        key = settings.speed_profile.points
        if key not in runs:
            runs[key] = run(vehicle, track, settings)
        return runs[key]

    run = br.run
    monkeypatch.setattr(br, "run", cached)
    vehicle = load_vehicle(VEHICLES / "eu07_bogie.yaml")
    settings = CriticalSpeedSettings(
        methods=("branch",), speed_min_m_per_s=25.0, speed_max_m_per_s=45.0,
        branch_step_m_per_s=10.0, tolerance_m_per_s=10.0, distance_m=300.0,
        initial_lateral_m=0.005, max_runs=3,
    )  # fmt: skip
    result = br.branch_critical_speed(vehicle, None, settings)
    assert result["converged"] and result["unstable_in_range"], result
    fold = result["fold"]
    assert fold["bracket_m_per_s"] == [25.0, 35.0] and fold["below"]["branch"] == 1
    assert fold["discontinuity"] == "not refined"
    assert fold["amplitude_m"] > 5e-3 > 1e-3 > fold["below"]["amplitude_m"]
    low = result["lowest_cycle"]
    assert low["speed_m_per_s"] == 25.0 and 0.1e-3 < low["amplitude_m"] < 1e-3
    for p in result["branch"]:
        assert p["classification"] in ("limit cycle", "small limit cycle", "growing"), p
        if p["classification"] in ("limit cycle", "small limit cycle"):
            assert abs(p["growth_per_period"]) <= 0.01
    high_floor = br.branch_critical_speed(
        vehicle, None, replace(settings, limit_cycle_floor_m=3e-3)
    )
    assert len(runs) == 1
    for key in ("critical_speed_m_per_s", "lowest_cycle", "status"):
        assert high_floor[key] == result[key], key
    assert high_floor["fold"]["bracket_m_per_s"] == [25.0, 35.0]
    assert [p["stable"] for p in high_floor["branch"]] == [p["stable"] for p in result["branch"]]
    assert high_floor["branch"][-1]["classification"] == "small limit cycle"


def test_bifurcation_diagram_marks_the_branch_and_the_linear_speed(tmp_path):
    """The figure of the branch: amplitude in mm against speed in m/s, one marker per run,
    the branch's and the linear critical speeds as vertical lines; the JSON is written."""
    from railexu.report.stability_files import write_critical_speed

    points = [{"speed_m_per_s": v, "classification": c, "amplitude_m": a, "stable": s}
              for v, c, a, s in ((45.0, "limit cycle", 7e-3, False), (35.0, "limit cycle", 3e-3,
                                  False), (25.0, "decaying", 1e-4, True))]  # fmt: skip
    result = {"vehicle": "v", "branch": {"branch": points, "critical_speed_m_per_s": 35.0,
                                         "converged": False},
              "linear": None, "nonlinear_branch_m_per_s": 35.0}  # fmt: skip
    result["linear"] = {"critical_speed_m_per_s": 44.0, "persistent_critical_speed_m_per_s": 44.0}
    fig = critical_speed_figures({**result, "linear": None})["bifurcation_diagram"]
    ax = fig.axes[0]
    assert ax.get_xlabel() == "speed [m/s]" and "[mm]" in ax.get_ylabel()
    assert "NOT CONVERGED" in ax.get_title()
    fig = critical_speed_figures({**result, "linear": {**result["linear"], "speeds_m_per_s": [],
                                                       "modes": {"a": {"damping_ratio": [],
                                                       "frequency_Hz": []}}}})  # fmt: skip
    labels = fig["bifurcation_diagram"].axes[0].get_legend_handles_labels()[1]
    assert "linear: 44.0 m/s" in labels and "nonlinear (branch): 35.0 m/s" in labels
    # the branches found as lines, the fold of the first as a shaded bracket
    branches = [{"index": 0, "speeds_m_per_s": [45.0, 35.0], "amplitude_m": [7e-3, 3e-3]}]
    fold = {"bracket_m_per_s": [25.0, 35.0], "speed_m_per_s": 35.0}
    with_fold = {**result, "linear": None,
                 "branch": {**result["branch"], "branches": branches, "fold": fold}}  # fmt: skip
    ax = critical_speed_figures(with_fold)["bifurcation_diagram"].axes[0]
    labels = ax.get_legend_handles_labels()[1]
    assert "branch 1" in labels and "fold of branch 1: 25.00-35.00 m/s" in labels, labels
    written = write_critical_speed({**result, "linear": None}, tmp_path, plots=False)
    assert json.loads(written[0].read_text())["nonlinear_branch_m_per_s"] == 35.0


def test_bisection_records_its_disturbance_and_run_duration(monkeypatch):
    """Bisection states the disturbance, the distance of its runs and their duration at the
    highest and lowest speed (distance / speed), and judges by the growth rate."""
    import railexu.stability.nonlinear as nl

    def fake(vehicle, track, speed, settings, offset_m=None):
        return {"speed_m_per_s": speed, "stable": speed < 33.0, "amplitude_m": 2e-3,
                "classification": "decaying" if speed < 33.0 else "limit cycle",
                "growth_per_period": 0.0, "frequency_Hz": 3.0}  # fmt: skip

    monkeypatch.setattr(nl, "nonlinear_run_is_stable", fake)
    settings = CriticalSpeedSettings(methods=("bisection",), speed_min_m_per_s=20.0,
                                     speed_max_m_per_s=50.0, distance_m=150.0)  # fmt: skip
    out = bisection_critical_speed(None, None, settings)
    assert out["bracket_m_per_s"][0] < 33.0 <= out["bracket_m_per_s"][1]
    assert out["run_distance_m"] == 150.0 and "4 mm" in out["disturbance"]
    assert "3.00 s at the highest speed" in out["run_duration"]
    assert "7.50 s at the lowest" in out["run_duration"]
    assert "growth rate" in out["judged_by"] and "railexu's assumptions" in out["judged_by"]


def test_summary_says_whether_the_ramp_converged_within_its_budget():
    """The printed summary of a ramp: its status (budget exhausted), both rates with what each
    found, and whether they agree; of a branch: its status and resolution, its fold and the
    sustained cycle at its lowest speed."""
    from railexu.cli.critical_speed import summary_lines

    ramps = [{"deceleration_m_per_s2": a, "distance_m": 5000.0, "status": "budget exhausted",
              "critical_speed_m_per_s": None, "note": "budget exhausted: still hunting"}
             for a in (0.5, 0.25)]  # fmt: skip
    result = {"ramp": {"status": "budget exhausted", "ramps": ramps, "note": "budget exhausted",
                       "resolution_m_per_s": 1.2},
              "branch": {"status": "converged", "resolution_m_per_s": 1.25, "branch": [],
                         "fold": {"bracket_m_per_s": [31.25, 32.5], "amplitude_m": 6.13e-3},
                         "lowest_cycle": {"speed_m_per_s": 20.0, "amplitude_m": 0.43e-3}},
              "nonlinear_ramp_m_per_s": None, "nonlinear_branch_m_per_s": 31.25}  # fmt: skip
    text = "\n".join(summary_lines(result, ("ramp", "branch")))
    assert "nonlinear, ramp: not found in range  [budget exhausted]" in text
    assert "status: budget exhausted, resolution 1.20 m/s" in text
    assert "ramp at 0.25 m/s^2 over 5000 m" in text
    assert "status: converged, resolution 1.25 m/s" in text
    assert "fold of the branch followed from the top: between 31.25 and 32.50 m/s" in text
    assert "(6.13 mm at 32.50 m/s)" in text
    assert "a sustained cycle at the lowest speed run, 20.00 m/s: 0.43 mm" in text
