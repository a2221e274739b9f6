"""Polach's creep forces (1999 with spin, 2005 extension): limits, symmetry, sign, numba."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railexu.contact.hertz import effective_modulus, hertz_contact
from railexu.contact.kalker import kalker_coefficients, kalker_linear_forces
from railexu.contact.polach import (
    POLACH_2005_PRESETS,
    Polach2005Parameters,
    polach_2005_forces,
    polach_2005_preset,
    polach_forces,
    polach_nb,
)

G = 8.1e10
Q = 1.0e5
MU = 0.3
# the typical contact of docs/theory.md section 3.1: 1250 mm wheel on the R300 crown, 100 kN
_HC = hertz_contact(0.8, 1.0 / 0.6, Q, effective_modulus(210e9, 0.3))
A_M, B_M = _HC.a_m, _HC.b_m
C11, C22, C23 = kalker_coefficients(A_M / B_M, 0.28)
GEOM = (A_M, B_M, G, C11, C22, C23)


def polach(xi, eta, phi, q=Q, mu=MU):
    return polach_forces(xi, eta, phi, q, mu, *GEOM)


def kalker(xi, eta, phi):
    return kalker_linear_forces(xi, eta, phi, *GEOM)


def eps_of(s):
    """Polach's stress gradient for a creepage s (upper bound over directions: c_jj <= c22)."""
    return G * math.pi * A_M * B_M * max(C11, C22) * s / (4.0 * Q * MU)


# The small-creepage expansion: eps/(1+eps^2) + atan(eps) = 2 eps (1 - (2/3) eps^2 + ...), so the
# relative deviation from the linear theory is (2/3) eps^2 (and 2 eps_S^2 for the spin term).
S_SMALL = 1e-8


def test_small_creepage_pure_longitudinal_and_lateral():
    tol = eps_of(S_SMALL) ** 2 + 1e-12
    fx, fy = polach(S_SMALL, 0.0, 0.0)
    assert fx == pytest.approx(kalker(S_SMALL, 0.0, 0.0)[0], rel=tol)
    assert fy == 0.0
    fx, fy = polach(0.0, -S_SMALL, 0.0)
    assert fx == 0.0
    assert fy == pytest.approx(kalker(0.0, -S_SMALL, 0.0)[1], rel=tol)


def test_small_creepage_pure_spin():
    """F_yS -> G (ab)^(3/2) c23 phi, i.e. Kalker's spin term (on the wheel: minus)."""
    phi = 1e-6  # phi a ~ 1e-8, eps_S ~ 1e-5
    fx, fy = polach(0.0, 0.0, phi)
    assert fx == 0.0
    assert fy == pytest.approx(kalker(0.0, 0.0, phi)[1], rel=1e-9)


@pytest.mark.parametrize("xi_over_phi_a", [0.0, 0.3, 1.0, 10.0, 100.0])
def test_spin_limit_independent_of_longitudinal_creepage(xi_over_phi_a):
    """The eps_S decision: with s_C in eps_S the linear spin force does not depend on xi.

    With |eta_C| instead of s_C it would be scaled by |eta_C|/s_C = 1/sqrt(1 + (xi/(phi a))^2),
    i.e. by 0.01 for the last case.
    """
    phi = 1e-8  # eps and eps_S stay below 1e-6: the nonlinear terms are < 1e-11
    xi = xi_over_phi_a * phi * A_M
    fx, fy = polach(xi, 0.0, phi)
    assert fy == pytest.approx(kalker(0.0, 0.0, phi)[1], rel=1e-10)
    assert fx == pytest.approx(kalker(xi, 0.0, 0.0)[0], rel=1e-10)


@pytest.mark.parametrize("angle_deg", [10.0, 45.0, 80.0, 135.0, 250.0])
def test_small_combined_creepage_magnitude_equals_kalker(angle_deg):
    """For combined xi, eta the magnitude is G a b c_jj s = Kalker's; the direction is s's."""
    t = math.radians(angle_deg)
    xi, eta = S_SMALL * math.cos(t), S_SMALL * math.sin(t)
    f = np.array(polach(xi, eta, 0.0))
    k = np.array(kalker(xi, eta, 0.0))
    assert np.hypot(*f) == pytest.approx(np.hypot(*k), rel=eps_of(S_SMALL) ** 2 + 1e-14)
    # parallel and opposite to the creepage
    assert f[0] * eta - f[1] * xi == pytest.approx(0.0, abs=1e-12 * np.hypot(*f) * S_SMALL)
    assert f[0] * xi + f[1] * eta < 0.0


def _paper_spin_force(xi, eta, phi, mu=MU):
    """Polach 1999's spin force written literally (creepage-direction sign), with s_C."""
    eta_c = eta + phi * A_M if abs(eta + phi * A_M) > abs(eta) else eta
    s_c = math.hypot(xi, eta_c)
    k_m = 1.0 + 6.3 * (1.0 - math.exp(-A_M / B_M))
    e = 8.0 / 3.0 * G * B_M * math.sqrt(A_M * B_M) * C23 * s_c / (Q * mu * k_m)
    d = (e * e - 1.0) / (e * e + 1.0)
    K_M = abs(e) * (d**3 / 3.0 - d**2 / 2.0 + 1.0 / 6.0) - math.sqrt((1.0 - d * d) ** 3) / 3.0
    return -9.0 / 16.0 * A_M * Q * mu * K_M * k_m * phi / s_c


@pytest.mark.parametrize(
    ("xi", "eta", "phi"),
    [(0.0, 0.0, 0.3), (0.0, 0.0, 5.0), (1e-3, 0.0, 0.8), (0.0, 2e-3, 1.5), (3e-3, -1e-3, -0.4)],
)
def test_spin_term_equals_the_paper_formula(xi, eta, phi):
    """The code's K_M = -(2/3) eps_S/(1 + eps_S^2)^2 is the paper's K_M, rewritten exactly.

    Tolerance 1e-9 relative to mu Q: the literal formula loses digits by cancellation.
    """
    f_eta = 0.0
    if eta != 0.0:  # isolate the spin part: subtract the creepage part computed without spin
        eta_c = eta + phi * A_M if abs(eta + phi * A_M) > abs(eta) else eta
        s_c = math.hypot(xi, eta_c)
        cjj = math.hypot(C11 * xi, C22 * eta) / math.hypot(xi, eta)
        e = G * math.pi * A_M * B_M * cjj * s_c / (4.0 * Q * MU)
        f_eta = 2.0 * Q * MU / math.pi * (e / (1.0 + e * e) + math.atan(e)) * eta / s_c
    fy = polach(xi, eta, phi)[1]
    assert -fy - f_eta == pytest.approx(_paper_spin_force(xi, eta, phi), abs=1e-9 * MU * Q)


@pytest.mark.parametrize(("xi", "eta"), [(0.5, 0.0), (0.0, -0.5), (0.3, 0.4), (-0.05, 0.02)])
def test_saturation_at_mu_q(xi, eta):
    """eps -> inf: |F| = mu Q (1 - 4/(3 pi eps^3) + ...), from below."""
    f = np.array(polach(xi, eta, 0.0))
    eps = eps_of(math.hypot(xi, eta)) * min(C11, C22) / max(C11, C22)  # lower bound
    deficit = 4.0 / (3.0 * math.pi * eps**3)
    assert 0.0 < 1.0 - np.hypot(*f) / (MU * Q) <= 1.01 * deficit
    assert f[0] * eta - f[1] * xi == pytest.approx(0.0, abs=1e-9 * MU * Q)


def test_never_exceeds_mu_q_with_spin():
    """Spin only enlarges s_C (less room for F_eta), so |F| <= mu Q holds with spin too."""
    grid = np.concatenate([[0.0], np.geomspace(1e-5, 1.0, 15)])
    spins = np.concatenate([[0.0], np.geomspace(1e-3, 50.0, 12)])
    worst = 0.0
    for xi in grid:
        for eta in np.concatenate([grid, -grid]):
            for phi in np.concatenate([spins, -spins]):
                worst = max(worst, math.hypot(*polach(xi, eta, phi)) / (MU * Q))
    assert worst <= 1.0 + 1e-12


def test_odd_symmetry():
    rng = np.random.default_rng(7)
    for _ in range(50):
        xi, eta = rng.normal(0.0, 3e-3, 2)
        phi = rng.normal(0.0, 1.0)
        fx, fy = polach(xi, eta, phi)
        assert polach(-xi, -eta, -phi) == pytest.approx((-fx, -fy), rel=1e-14, abs=1e-9)
        # mirror in the lateral direction: (xi, -eta, -phi) -> (Fx, -Fy)
        assert polach(xi, -eta, -phi) == pytest.approx((fx, -fy), rel=1e-14, abs=1e-9)
        # reversing xi alone reverses Fx only
        assert polach(-xi, eta, phi) == pytest.approx((-fx, fy), rel=1e-14, abs=1e-9)


@pytest.mark.parametrize("s", [1e-6, 1e-4, 3e-3, 0.05, 1.0])
def test_force_on_wheel_opposes_creepage(s):
    assert polach(s, 0.0, 0.0)[0] < 0.0
    assert polach(-s, 0.0, 0.0)[0] > 0.0
    assert polach(0.0, s, 0.0)[1] < 0.0
    assert polach(0.0, 0.0, s)[1] < 0.0  # spin pushes like a positive eta (Kalker's sign)
    fx, fy = polach(s, 2 * s, 0.0)
    assert fx * s + fy * 2 * s < 0.0


def test_zero_creepage_and_degenerate_input():
    assert polach(0.0, 0.0, 0.0) == (0.0, 0.0)
    assert polach(1e-3, 0.0, 0.0, q=0.0) == (0.0, 0.0)
    assert polach(1e-3, 0.0, 0.0, q=-5.0) == (0.0, 0.0)
    assert polach(1e-3, 1e-3, 0.1, mu=0.0) == (0.0, 0.0)
    # s = 0 with spin (c_jj falls back to c22): finite
    assert all(math.isfinite(v) for v in polach(0.0, 0.0, 2.0))
    # tiny creepage: no underflow trouble
    assert all(math.isfinite(v) for v in polach(1e-300, -1e-300, 1e-300))
    for args in [(0.0, 0.0, 0.0), (0.0, 0.0, 2.0), (1e-3, 0.0, 0.0)]:
        assert polach_nb(*args, 0.0, MU, *GEOM, 1.0, 1.0, 1.0, 0.0, 30.0) == (0.0, 0.0)
        assert all(
            math.isfinite(v) for v in polach_nb(*args, Q, MU, *GEOM, 0.3, 0.1, 0.4, 0.2, 30.0)
        )


def test_array_input():
    xi = np.linspace(-0.01, 0.01, 11)
    fx, fy = polach_forces(xi, 0.0, 0.2, Q, MU, *GEOM)
    assert fx.shape == fy.shape == (11,)
    for k in range(11):
        assert (fx[k], fy[k]) == pytest.approx(polach(xi[k], 0.0, 0.2), rel=1e-14)


def test_2005_reduces_exactly_to_1999():
    """k_A = k_S = 1 and A = 1 (or B = 0): mu == mu0 and the 1999 law, bit for bit."""
    for xi, eta, phi in [(1e-3, 0.0, 0.0), (2e-3, -1e-3, 0.5), (0.0, 0.0, 1.0), (0.2, 0.1, 0.0)]:
        ref = polach(xi, eta, phi)
        assert polach_2005_forces(xi, eta, phi, Q, MU, *GEOM, 30.0, 1.0, 1.0, 1.0, 0.6) == ref
        assert polach_2005_forces(xi, eta, phi, Q, MU, *GEOM, 30.0, 1.0, 1.0, 0.4, 0.0) == ref
        nb1 = polach_nb(xi, eta, phi, Q, MU, *GEOM, 1.0, 1.0, 1.0, 0.6, 30.0)
        nb2 = polach_nb(xi, eta, phi, Q, MU, *GEOM, 1.0, 1.0, 0.4, 0.0, 30.0)
        nb3 = polach_nb(xi, eta, phi, Q, MU, *GEOM, 1.0, 1.0, 1.0, 0.0, 0.0)
        assert nb1 == nb2 == nb3
        assert nb1 == pytest.approx(ref, rel=1e-13, abs=1e-12)


def test_2005_small_creepage_slope():
    """F -> (k_A + k_S)/2 x Kalker for small creepage (reduced initial slope, Polach 2005)."""
    p = POLACH_2005_PRESETS["wet"]
    fx, _ = polach_2005_forces(
        S_SMALL, 0.0, 0.0, Q, p.mu0, *GEOM, 30.0, p.k_a, p.k_s, p.friction_ratio_A,
        p.friction_decay_B_s_per_m,
    )  # fmt: skip
    assert fx == pytest.approx(0.5 * (p.k_a + p.k_s) * kalker(S_SMALL, 0.0, 0.0)[0], rel=1e-6)


@pytest.mark.parametrize("preset", ["dry", "wet"])
def test_2005_curve_has_a_maximum_then_falls(preset):
    """Traction (adhesion) curve: rises, peaks, then falls as the friction drops with w = s V.

    Once the friction has decayed to mu0 A the force creeps back up towards mu0 A Q (the
    atan(k_S eps) term still grows), so "falls" is checked from the peak to the minimum, which
    must be well below the peak.
    """
    p = polach_2005_preset(preset)
    V = 30.0
    xi = np.geomspace(1e-5, 1.0, 400)
    fx, fy = polach_2005_forces(
        xi, 0.0, 0.0, Q, p.mu0, *GEOM, V, p.k_a, p.k_s, p.friction_ratio_A,
        p.friction_decay_B_s_per_m,
    )  # fmt: skip
    assert np.all(fy == 0.0)
    f = -fx
    k = int(np.argmax(f))
    assert 0 < k < len(xi) - 1
    m = k + int(np.argmin(f[k:]))
    assert np.all(np.diff(f[: k + 1]) > 0.0)
    assert np.all(np.diff(f[k : m + 1]) < 0.0)
    assert f[k] < p.mu0 * Q
    assert f[m] < 0.7 * f[k]  # measured: 0.57 (dry), 0.56 (wet)
    # at xi = 1 (w = 30 m/s) the friction is mu0 (A + (1 - A) exp(-B w)); the force is below
    # mu Q by about 2/(pi k_S eps) (measured 0.16 % dry, 0.39 % wet): 1.5 % tolerance
    decay = math.exp(-p.friction_decay_B_s_per_m * V)
    mu_w = p.mu0 * (p.friction_ratio_A + (1 - p.friction_ratio_A) * decay)
    assert f[-1] == pytest.approx(mu_w * Q, rel=1.5e-2)
    assert f[-1] < mu_w * Q


def test_2005_default_parameters_are_dry():
    args = (2e-3, 1e-3, 0.3, Q, 0.5, *GEOM, 20.0)
    p = POLACH_2005_PRESETS["dry"]
    assert polach_2005_forces(*args) == polach_2005_forces(
        *args, p.k_a, p.k_s, p.friction_ratio_A, p.friction_decay_B_s_per_m
    )


def test_presets():
    assert polach_2005_preset(" Wet ") is POLACH_2005_PRESETS["wet"]
    with pytest.raises(ValueError, match="dry, wet"):
        polach_2005_preset("icy")
    with pytest.raises(ValueError):
        Polach2005Parameters(0.2, 0.4, 0.4, 0.6, 0.5)  # k_s > k_a
    with pytest.raises(ValueError):
        Polach2005Parameters(1.0, 0.4, 1.4, 0.6, 0.5)  # A > 1


@pytest.mark.parametrize("preset", [None, "dry", "wet"])
def test_numba_equals_python(preset):
    """Same formulas, same order: agreement to a few ulps (numpy vs libm atan/exp)."""
    if preset is None:
        k_a, k_s, fa, fb = 1.0, 1.0, 1.0, 0.0
    else:
        p = POLACH_2005_PRESETS[preset]
        k_a, k_s, fa, fb = p.k_a, p.k_s, p.friction_ratio_A, p.friction_decay_B_s_per_m
    rng = np.random.default_rng(3)
    for _ in range(300):
        xi, eta = rng.normal(0.0, 5e-3, 2) * rng.choice([0.0, 1.0, 1e-3, 50.0], 2)
        phi = rng.normal(0.0, 1.0) * rng.choice([0.0, 1.0, 1e-4])
        V = rng.uniform(0.0, 60.0)
        py = polach_2005_forces(xi, eta, phi, Q, MU, *GEOM, V, k_a, k_s, fa, fb)
        nb = polach_nb(xi, eta, phi, Q, MU, *GEOM, k_a, k_s, fa, fb, V)
        assert nb == pytest.approx(py, rel=1e-13, abs=1e-9)
