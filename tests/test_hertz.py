"""Hertz normal contact: exact solution, classical tables, compiled table lookup, clamping."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from railexu.contact.hertz import (
    HERTZ_BETA_MIN,
    effective_modulus,
    hertz_coefficients_nb,
    hertz_contact,
    hertz_m_n,
    hertz_stiffness,
    hertz_table,
    solve_axis_ratio,
)

E_STEEL = 210e9
NU_STEEL = 0.3
E_STAR = E_STEEL / (2.0 * (1.0 - NU_STEEL**2))


@pytest.fixture(scope="module")
def table() -> np.ndarray:
    return hertz_table()


def test_effective_modulus_steel_on_steel():
    assert effective_modulus(E_STEEL, NU_STEEL) == pytest.approx(E_STAR, rel=1e-15)
    assert effective_modulus(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL) == pytest.approx(E_STAR)
    # a rigid second body leaves (1 - nu^2)/E of the first
    rigid = effective_modulus(E_STEEL, NU_STEEL, 1e30, 0.0)
    assert rigid == pytest.approx(E_STEEL / (1.0 - NU_STEEL**2), rel=1e-12)
    with pytest.raises(ValueError):
        effective_modulus(-1.0, 0.3)


@pytest.mark.parametrize("radius", [0.01, 0.3, 5.0])
@pytest.mark.parametrize("force", [1.0, 1e4, 2e5])
def test_sphere_on_plane(radius, force):
    """A = B = 1/(2R): a = (3NR/(4E*))^(1/3), delta = a^2/R, p0 = 3N/(2 pi a^2).

    Closed form (Johnson 1985 eq. (4.22)); the circular case goes through the g = 1 branch, so
    agreement is to rounding.
    """
    A = B = 0.5 / radius
    hc = hertz_contact(A, B, force, E_STAR)
    a_ref = (3.0 * force * radius / (4.0 * E_STAR)) ** (1.0 / 3.0)
    assert hc.a_m == pytest.approx(a_ref, rel=1e-12)
    assert hc.b_m == pytest.approx(a_ref, rel=1e-12)
    assert hc.delta_m == pytest.approx(a_ref**2 / radius, rel=1e-12)
    assert hc.p0_Pa == pytest.approx(3.0 * force / (2.0 * math.pi * a_ref**2), rel=1e-12)
    assert hc.stiffness_N_per_m15 == pytest.approx(4.0 / 3.0 * E_STAR * math.sqrt(radius))
    assert hc.g == 1.0


def test_nearly_circular_contact_is_continuous():
    """beta -> 1 goes through the series branch; the solution must approach the sphere's."""
    radius = 0.3
    A = 0.5 / radius
    sphere = hertz_contact(A, A, 1e4, E_STAR)
    for eps in (1e-12, 1e-9, 1e-6):
        hc = hertz_contact(A, A * (1.0 - eps), 1e4, E_STAR)
        # the semi-axes move by O(eps) (dg/dbeta is finite at beta = 1)
        assert hc.a_m == pytest.approx(sphere.a_m, rel=10 * eps + 1e-12)
        assert hc.delta_m == pytest.approx(sphere.delta_m, rel=10 * eps + 1e-12)


@pytest.mark.parametrize(
    ("theta_deg", "m_ref", "n_ref"),
    [
        (30.0, 2.7306, 0.4931),
        (45.0, 1.9265, 0.6038),
        (60.0, 1.4858, 0.7171),
        (75.0, 1.2020, 0.8448),
        (90.0, 1.0, 1.0),
    ],
)
def test_timoshenko_m_n_table(theta_deg, m_ref, n_ref):
    """Classical Hertz coefficients (Timoshenko): the table is printed to 4 decimals."""
    m, n = hertz_m_n(math.radians(theta_deg))
    assert m == pytest.approx(m_ref, abs=5e-5)
    assert n == pytest.approx(n_ref, abs=5e-5)


def test_m_n_consistent_with_contact():
    """a = m [3N/(4 E* (A+B))]^(1/3), b = n [...]^(1/3) with cos(theta) = (B-A)/(A+B)."""
    A, B, N = 0.8, 1.0 / 0.6, 1e5
    m, n = hertz_m_n(math.acos((B - A) / (A + B)))
    hc = hertz_contact(A, B, N, E_STAR)
    scale = (3.0 * N / (4.0 * E_STAR * (A + B))) ** (1.0 / 3.0)
    assert max(hc.a_m, hc.b_m) == pytest.approx(m * scale, rel=1e-12)
    assert min(hc.a_m, hc.b_m) == pytest.approx(n * scale, rel=1e-12)


def test_typical_wheel_on_r300_crown():
    """docs/theory.md section 3.1: 1250 mm wheel (conical tread) on the R300 crown, 100 kN.

    A = 1/(2 * 0.625 m) (rolling), B = 1/(2 * 0.3 m) (lateral). Tolerances: half a unit in the
    last quoted digit.
    """
    A, B = 0.5 / 0.625, 0.5 / 0.3
    hc = hertz_contact(A, B, 100e3, effective_modulus(E_STEEL, NU_STEEL))
    assert hc.a_m * 1e3 == pytest.approx(8.30, abs=0.005)
    assert hc.b_m * 1e3 == pytest.approx(5.10, abs=0.005)
    assert hc.delta_m * 1e3 == pytest.approx(0.098, abs=0.0005)
    assert hc.p0_Pa / 1e6 == pytest.approx(1128, abs=0.5)
    assert hc.stiffness_N_per_m15 == pytest.approx(1.02e11, abs=0.005e11)


def test_orientation_short_axis_along_larger_curvature():
    hc1 = hertz_contact(2.0, 0.5, 5e4, E_STAR)
    hc2 = hertz_contact(0.5, 2.0, 5e4, E_STAR)
    assert hc1.a_m < hc1.b_m
    assert hc2.a_m == pytest.approx(hc1.b_m, rel=1e-14)
    assert hc2.b_m == pytest.approx(hc1.a_m, rel=1e-14)
    assert hc2.delta_m == pytest.approx(hc1.delta_m, rel=1e-14)


@pytest.mark.parametrize("beta", [1e-4, 1e-3, 0.05, 0.3, 0.7, 0.999])
def test_load_penetration_and_scaling(beta):
    """N = K_H delta^1.5; a, b ~ N^(1/3); delta ~ N^(2/3); N = (2/3) pi a b p0."""
    A, B = 1.3, 1.3 * beta
    k_h = hertz_stiffness(A, B, E_STAR)
    hc1 = hertz_contact(A, B, 1e4, E_STAR)
    hc8 = hertz_contact(A, B, 8e4, E_STAR)
    assert hc1.stiffness_N_per_m15 == pytest.approx(k_h, rel=1e-14)
    assert k_h * hc1.delta_m**1.5 == pytest.approx(1e4, rel=1e-12)
    assert hc8.a_m == pytest.approx(2.0 * hc1.a_m, rel=1e-12)
    assert hc8.delta_m == pytest.approx(4.0 * hc1.delta_m, rel=1e-12)
    assert 2.0 / 3.0 * math.pi * hc1.a_m * hc1.b_m * hc1.p0_Pa == pytest.approx(1e4, rel=1e-12)
    g = min(hc1.a_m, hc1.b_m) / max(hc1.a_m, hc1.b_m)
    assert g == pytest.approx(hc1.g, rel=1e-12)


def _boussinesq_displacement(x0, y0, a, b, p0, e_star):
    """Sum of the normal surface displacements of both bodies under the Hertz pressure.

    u(r0) = 1/(pi E*) int p(r)/|r - r0| dA, in polar coordinates about r0 (the 1/r singularity
    cancels with the area element), evaluated by adaptive quadrature.
    """

    def ray(theta):
        c, s = math.cos(theta), math.sin(theta)
        # |(x0 + t c)/a, (y0 + t s)/b| = 1 -> quadratic in t
        qa = (c / a) ** 2 + (s / b) ** 2
        qb = 2.0 * (x0 * c / a**2 + y0 * s / b**2)
        qc = (x0 / a) ** 2 + (y0 / b) ** 2 - 1.0
        t_max = (-qb + math.sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa)

        def p(t):
            r = 1.0 - ((x0 + t * c) / a) ** 2 - ((y0 + t * s) / b) ** 2
            return p0 * math.sqrt(max(r, 0.0))

        return quad(p, 0.0, t_max, epsabs=0.0, epsrel=1e-11, limit=200)[0]

    total = quad(ray, 0.0, 2.0 * math.pi, epsabs=0.0, epsrel=1e-10, limit=200)[0]
    return total / (math.pi * e_star)


def test_elliptic_solution_satisfies_the_contact_condition():
    """Independent check: Hertz's pressure on the computed ellipse closes the gap.

    Inside the patch the displacements must equal delta - A x^2 - B y^2 (Johnson 1985 eq.
    (4.37)); we integrate Boussinesq's solution numerically at a few points. Tolerance 1e-7 of
    delta: quadrature accuracy.
    """
    A, B, N = 0.8, 1.0 / 0.6, 1e5
    hc = hertz_contact(A, B, N, E_STAR)
    a, b = hc.a_m, hc.b_m
    for x0, y0 in [(0.0, 0.0), (0.5 * a, 0.0), (0.0, -0.6 * b), (0.3 * a, 0.4 * b)]:
        u = _boussinesq_displacement(x0, y0, a, b, hc.p0_Pa, E_STAR)
        assert u == pytest.approx(hc.delta_m - A * x0**2 - B * y0**2, abs=1e-7 * hc.delta_m)


def test_solve_axis_ratio_limits():
    assert solve_axis_ratio(1.0) == 1.0
    assert solve_axis_ratio(4.0) == solve_axis_ratio(0.25)
    g = solve_axis_ratio(HERTZ_BETA_MIN)
    assert 0.0 < g < 0.01
    with pytest.raises(ValueError):
        solve_axis_ratio(0.0)


def test_table_coefficients_match_exact_solution(table):
    """Compiled table lookup vs the exact solution over beta in [1e-4, 1], both orientations.

    Measured largest relative error 2.8e-6 for the default 1024-node table (hertz.py doc);
    checked against 5e-6.
    """
    rng = np.random.default_rng(12345)
    lb = table[:, 0]
    betas = np.concatenate(
        [
            np.exp(rng.uniform(math.log(HERTZ_BETA_MIN), 0.0, 300)),
            np.exp(0.5 * (lb[1:] + lb[:-1]))[::7],
            [1.0],
        ]
    )
    worst = 0.0
    for beta in betas:
        for A, B in ((1.7, 1.7 * beta), (1.7 * beta, 1.7)):
            k_h, alpha_a, alpha_b = hertz_coefficients_nb(table, A, B, E_STAR)
            hc = hertz_contact(A, B, 3e4, E_STAR)
            sd = math.sqrt(hc.delta_m)
            worst = max(
                worst,
                abs(k_h / hc.stiffness_N_per_m15 - 1.0),
                abs(alpha_a * sd / hc.a_m - 1.0),
                abs(alpha_b * sd / hc.b_m - 1.0),
            )
    assert worst < 5e-6


def test_table_typical_case(table):
    """N = K_H delta^1.5 and the semi-axes from the compiled coefficients, typical case."""
    A, B = 0.8, 1.0 / 0.6
    k_h, alpha_a, alpha_b = hertz_coefficients_nb(table, A, B, E_STAR)
    delta = 0.098e-3
    assert k_h * delta**1.5 == pytest.approx(1.02e11 * delta**1.5, rel=5e-3)
    hc = hertz_contact(A, B, k_h * delta**1.5, E_STAR)
    assert hc.delta_m == pytest.approx(delta, rel=5e-6)
    assert alpha_a * math.sqrt(delta) == pytest.approx(hc.a_m, rel=5e-6)
    assert alpha_b * math.sqrt(delta) == pytest.approx(hc.b_m, rel=5e-6)


@pytest.mark.parametrize(
    ("A", "B"),
    [(0.8, 0.0), (0.8, -0.5), (-3.0, 0.8), (0.8, 1e-9), (0.0, 0.0), (-1.0, -2.0), (0.8, math.nan)],
)
def test_non_hertzian_curvatures_are_clamped(table, A, B):
    """A, B <= 0 (conformal/concave) clamp min(A,B) to HERTZ_BETA_MIN max(A,B): finite output."""
    k_h, alpha_a, alpha_b = hertz_coefficients_nb(table, A, B, E_STAR)
    for v in (k_h, alpha_a, alpha_b):
        assert math.isfinite(v) and v > 0.0


def test_clamp_value_and_python_agreement(table):
    A = 0.8
    clamped = hertz_coefficients_nb(table, A, HERTZ_BETA_MIN * A, E_STAR)
    for B in (0.0, -0.5, -1e3, 1e-12):
        assert hertz_coefficients_nb(table, A, B, E_STAR) == pytest.approx(clamped, rel=1e-14)
        hc = hertz_contact(A, B, 1e4, E_STAR)
        assert hc.stiffness_N_per_m15 == pytest.approx(clamped[0], rel=5e-6)
        assert hc.a_m < hc.b_m  # long in y: the lateral curvature was the smaller one
    with pytest.raises(ValueError):
        hertz_contact(A, 0.5, -1.0, E_STAR)


def test_zero_load():
    hc = hertz_contact(0.8, 1.6, 0.0, E_STAR)
    assert hc.a_m == hc.b_m == hc.delta_m == hc.p0_Pa == 0.0
    assert hc.stiffness_N_per_m15 > 0.0
