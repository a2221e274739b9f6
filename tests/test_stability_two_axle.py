"""Critical speed of a two-axle vehicle with linear creep on cones (issue 28), checked against the
textbook model: Wickens (2003), Fundamentals of Rail Vehicle Dynamics, ch. 5, the two-axle
vehicle (two wheelsets with lateral and yaw freedom in a car body with lateral and yaw freedom,
primary springs, Kalker's linear creep, conicity lambda), solved here by its own small eigenvalue
code (numpy), independent of railexu's linearisation (Exudyn's ``ComputeLinearizedSystem`` of the
full 3-D model). Reference values and sources: ``tests/data/two_axle/README.md``.

Both railexu analyses are compared with it: the linear critical speed within 2 %, and the
nonlinear one from the limit-cycle branch within the branch's stated resolution. With cones and
linear creep nothing limits the motion's amplitude (no flange, no saturation): there is no limit
cycle and so no subcritical branch, and the nonlinear critical speed is the linear one, up to
what the growth-rate classification can tell apart (+-1 % amplitude change per period counts as
sustained) and the step of the branch."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from wickens import add_wheelset

from railexu.contact.hertz import hertz_contact
from railexu.contact.kalker import kalker_coefficients
from railexu.stability import CriticalSpeedSettings, branch_critical_speed, linear_stability
from railexu.track.track import Track
from railexu.vehicle.vehicle import load_vehicle

DATA = Path(__file__).resolve().parent / "data" / "two_axle"
REFERENCE = json.loads((DATA / "reference.json").read_text())
CONE = 0.05
RAIL_RADIUS_M = 0.05
ROUND_RAIL = Track(name="round rail", rail_profile=f"round:{RAIL_RADIUS_M}", inclination="none")
#: Half the distance between the contact points and the rolling radius of the test's wheelsets
#: on the test's track (cones on 1435 mm gauge, round heads): e0 and r0 of the textbook.
E0_M, R0_M = 0.75, 0.625
#: Amplitude change per period that the growth-rate classification counts as sustained
#: (railexu.assessment.oscillation.GROWTH_PER_PERIOD).
SUSTAINED_PER_PERIOD = 0.01


def cone_on_round_rails_conicity(y_m: float = 1e-3) -> float:
    """Effective conicity ``(r_L - r_R) / (2 y)`` of cones of slope ``CONE`` on round rail heads
    (radius ``RAIL_RADIUS_M``), by plane geometry (the textbook's, Wickens ch. 2): the wheelset
    shifted by ``y_m`` finds the height and roll at which each wheel's straight generatrix touches
    its rail's circle (the circles placed so that the centred wheelset touches at +-e0); the
    rolling radius is ``r0 - CONE u`` at the touching point ``u`` (outward from the nominal
    point). A cone on a curved head rolls with a larger conicity than its slope: the roll of the
    wheelset moves the contact across the head (here 0.05 -> 0.0523)."""
    d, rr = CONE, RAIL_RADIUS_M
    normal = np.array([-d, 1.0]) / math.hypot(1.0, d)
    centre_left = np.array([E0_M, -R0_M]) - rr * normal
    centres = {1: centre_left, -1: np.array([-centre_left[0], centre_left[1]])}

    def line(side: int, zc: float, phi: float):
        c, s = math.cos(phi), math.sin(phi)
        rot = np.array([[c, -s], [s, c]])
        point = np.array([y_m, zc]) + rot @ np.array([side * E0_M, -R0_M])
        return point, rot @ (np.array([side, d]) / math.hypot(1.0, d))

    def gaps(v):
        """Distance of each rail's circle centre from its wheel's generatrix, minus the radius
        (the centre lies below the left generatrix's direction, above the right one's)."""
        out = []
        for side, centre in centres.items():
            p, t = line(side, *v)
            w = centre - p
            out.append(side * (w[0] * t[1] - w[1] * t[0]) - rr)
        return out

    v = np.zeros(2)  # Newton's method on (height, roll), central-difference Jacobian
    for _ in range(20):
        g = np.asarray(gaps(v))
        jac = np.column_stack([(np.asarray(gaps(v + h)) - np.asarray(gaps(v - h))) / 2e-7
                               for h in np.eye(2) * 1e-7])  # fmt: skip
        v = v - np.linalg.solve(jac, g)
    zc, phi = v
    assert max(abs(g) for g in gaps(v)) < 1e-14
    radii = []
    for side, centre in centres.items():
        p, t = line(side, zc, phi)
        radii.append(R0_M - d * float((centre - p) @ t) / math.hypot(1.0, d))
    return (radii[0] - radii[1]) / (2.0 * y_m)


CONICITY = cone_on_round_rails_conicity()


@pytest.fixture(scope="module")
def vehicle():
    return load_vehicle(DATA / "two_axle_linear.yaml")


def creep_coefficients(vehicle) -> tuple[float, float]:
    """Kalker's f11 and f22 [N] at the static wheel load: Hertz ellipse of the cone (transverse
    curvature 0, rolling radius r0) on the round rail head, Kalker's coefficients c11, c22
    (Kalker 1967 table, as railexu's tested ``kalker_coefficients``); f = G a b c."""
    load = vehicle.total_mass_kg * 9.81 / 4.0
    G, nu = vehicle.contact.shear_modulus_Pa, vehicle.contact.poisson
    h = hertz_contact(0.5 / R0_M, 0.5 / RAIL_RADIUS_M, load, G / (1 - nu))
    c11, c22, _ = kalker_coefficients(h.a_m / h.b_m, nu)
    return G * h.a_m * h.b_m * c11, G * h.a_m * h.b_m * c22


def textbook_matrices(vehicle, speed: float, conicity: float):
    """Mass, damping and stiffness matrices of Wickens' two-axle vehicle at ``speed`` (m/s), in
    the coordinates (y1, psi1, y2, psi2, y_body, psi_body); per wheelset at x = +-a:

        m_w y'' + 2 f22 (1 + lambda r0 / e0) y' / V - 2 f22 psi + 2 k_y (y - y_b - x psi_b) = 0
        I_w psi'' + 2 f11 e0^2 psi' / V + 2 f11 e0 lambda y / r0 + I_spin (V / r0)(lambda / e0) y'
            + 2 k_x b^2 (psi - psi_b) = 0

    the car body carrying the reactions of the springs. Beyond the plane textbook model, two
    effects a 3-D rolling wheelset has (as in test_stability's bogie check): the roll-rate part of
    the lateral creepage (the factor ``1 + lambda r0 / e0``) and the gyroscopic yaw moment of the
    spinning wheelset (``I_spin V / r0`` times the roll rate ``lambda y' / e0``)."""
    f11, f22 = creep_coefficients(vehicle)
    ws, body = vehicle.wheelsets, vehicle.bodies[0]
    primary = next(el for el in vehicle.suspension if el.name.startswith("primary_ws1"))
    kx, ky = primary.stiffness_N_per_m[0], primary.stiffness_N_per_m[1]
    b = abs(primary.position_m[1])
    mw, iw, i_spin = ws[0].mass_kg, ws[0].inertia_kg_m2[1], ws[0].inertia_kg_m2[2]
    n = 6
    m = np.diag([mw, iw, mw, iw, body.mass_kg, body.inertia_kg_m2[2]])
    c = np.zeros((n, n))
    k = np.zeros((n, n))
    for i, w in enumerate(ws):
        add_wheelset(c, k, i, w.position_x_m, speed, conicity, (f11, f22), (R0_M, E0_M),
                     i_spin, (kx, ky, b))  # fmt: skip
    return m, c, k


def least_damping_ratio(vehicle, speed: float, conicity: float) -> float:
    """The smallest damping ratio of the oscillatory eigenvalues of the textbook model."""
    m, c, k = textbook_matrices(vehicle, speed, conicity)
    n = m.shape[0]
    first = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]])  # fmt: skip
    lam = [e for e in np.linalg.eigvals(first) if e.imag > 1e-3]
    return min(-e.real / abs(e) for e in lam)


def textbook_critical_speed(vehicle, conicity: float, zeta: float = 0.0) -> float:
    """The speed at which the least damping ratio of the textbook model is ``zeta``."""
    return brentq(lambda v: least_damping_ratio(vehicle, v, conicity) - zeta, 5.0, 140.0,
                  xtol=1e-3)  # fmt: skip


def test_textbook_reference_values(vehicle):
    """The cone's conicity on the round heads and the textbook model's critical speed of the test
    vehicle are those recorded in tests/data/two_axle/reference.json (README beside it); the
    conicity is that of railexu's EN 15302 evaluation (tested on its own against EN 15302)."""
    from railexu.stability import profile_equivalent_conicity

    conicity = cone_on_round_rails_conicity()
    assert conicity == pytest.approx(REFERENCE["conicity"], rel=1e-5)
    assert profile_equivalent_conicity(vehicle, ROUND_RAIL, 0.002) == pytest.approx(
        CONICITY, rel=1e-4
    )
    v = textbook_critical_speed(vehicle, CONICITY)
    assert v == pytest.approx(REFERENCE["textbook_critical_speed_m_per_s"], abs=0.01)


def test_linear_critical_speed_matches_the_textbook_two_axle_vehicle(vehicle):
    """railexu's linear critical speed (Exudyn's linearisation of the 3-D model, modes followed
    by shape) within 2 % of the textbook model's (what remains: the body's and wheelsets' roll
    and vertical motion, spin creep, gravitational stiffness, all small with cones on round
    heads); the critical mode is the body's lateral-yaw oscillation on the wheelsets."""
    textbook = textbook_critical_speed(vehicle, CONICITY)
    settings = CriticalSpeedSettings(
        methods=("linear",), speed_min_m_per_s=0.6 * textbook, speed_max_m_per_s=1.3 * textbook,
        linear_points=6, linearization="profiles", tolerance_m_per_s=0.1,
    )  # fmt: skip
    result = linear_stability(vehicle, ROUND_RAIL, settings)
    assert result["critical_speed_m_per_s"] == pytest.approx(textbook, rel=0.02)
    assert result["critical_mode_stays_unstable"]
    assert result["critical_mode"] == "car-body lateral"  # the body on the wheelsets, 1.6 Hz


@pytest.mark.slow
def test_branch_critical_speed_is_the_linear_one_without_a_subcritical_branch(vehicle):
    """The branch method on the same vehicle (linear creep, cones: no limit cycle exists), from
    a 3 mm disturbance, plateaus of 200 m (the body's hunting at 1.6 Hz: the fit over the last
    60 % needs four periods), a first step of 4 m/s refined to 1 m/s: its critical
    speed lies where the textbook model says the classification must change, within the
    branch's resolution. The classification counts +-1 % amplitude change per period as
    sustained, i.e. damping ratios between +-0.01 / (2 pi), and the envelope fit over N periods
    resolves the growth to about 0.13 / N per period; sustained motion above the 0.1 mm floor
    counts as a limit cycle (unstable, whatever its amplitude). So the lowest speed the branch
    calls
    unstable lies between the speeds where the textbook damping ratio is +zeta and -zeta,
    zeta = (0.01 + 0.13 / N) / (2 pi), widened by the branch's resolution (its last step)."""
    v_cr = textbook_critical_speed(vehicle, CONICITY)
    top = math.floor(v_cr) + 3.0
    settings = CriticalSpeedSettings(
        methods=("branch",), speed_min_m_per_s=top - 12.0, speed_max_m_per_s=top,
        branch_step_m_per_s=4.0, tolerance_m_per_s=1.0, distance_m=200.0,
        initial_lateral_m=0.003, max_runs=12, fit_fraction=0.6,
    )  # fmt: skip
    result = branch_critical_speed(vehicle, ROUND_RAIL, settings)
    assert result["status"] == "converged", result.get("note")
    # the band: +-1 % per period, widened by the fit's resolution over the plateaus' windows
    # (0.13 / N per period over N periods, measured on steady sines: railexu.stability.ramp)
    periods = min(p["fit_periods"] for p in result["branch"] if p.get("fit_periods"))
    zeta = (SUSTAINED_PER_PERIOD + 0.13 / periods) / (2.0 * math.pi)
    v_low = textbook_critical_speed(vehicle, CONICITY, +zeta)
    v_high = textbook_critical_speed(vehicle, CONICITY, -zeta)
    v = result["critical_speed_m_per_s"]
    res = result["resolution_m_per_s"]
    assert res <= 1.0 + 1e-9
    assert v_low - res <= v <= v_high + res, (v, v_low, v_cr, v_high)
    # every plateau restarted from the state of the one above: one run per stage
    assert len(result["stages"]) >= 2 and result["plateaus_run"] <= settings.max_runs
    assert all(p["amplitude_m"] is not None for p in result["branch"])
