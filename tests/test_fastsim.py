"""Kalker's FASTSIM: linear limit, saturation, agreement with Polach, sign."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railexu.contact.fastsim import FASTSIM_POINTS, FASTSIM_STRIPS, fastsim_forces, fastsim_nb
from railexu.contact.hertz import effective_modulus, hertz_contact
from railexu.contact.kalker import kalker_coefficients, kalker_linear_forces
from railexu.contact.polach import polach_forces

G = 8.1e10
Q = 1.0e5
MU = 0.3
_HC = hertz_contact(0.8, 1.0 / 0.6, Q, effective_modulus(210e9, 0.3))  # docs/theory.md 3.1 example
A_M, B_M = _HC.a_m, _HC.b_m
C11, C22, C23 = kalker_coefficients(A_M / B_M, 0.28)
GEOM = (A_M, B_M, G, C11, C22, C23)


def fastsim(xi, eta, phi, n=None, mu=MU, q=Q):
    if n is None:
        return fastsim_forces(xi, eta, phi, q, mu, *GEOM)
    return fastsim_forces(xi, eta, phi, q, mu, *GEOM, n_strips=n, n_points=n)


def kalker(xi, eta, phi):
    return kalker_linear_forces(xi, eta, phi, *GEOM)


@pytest.mark.parametrize("n", [1, 3, 10, 50])
def test_linear_limit_pure_xi_eta_exact(n):
    """Pure xi / eta: exact for any discretisation (strip half-lengths and cell centres chosen
    so; module doc). Tolerance: rounding."""
    s = 1e-9  # far below the traction bound
    assert fastsim(s, 0.0, 0.0, n)[0] == pytest.approx(kalker(s, 0.0, 0.0)[0], rel=1e-12)
    assert fastsim(0.0, -s, 0.0, n)[1] == pytest.approx(kalker(0.0, -s, 0.0)[1], rel=1e-12)
    assert fastsim(s, 0.0, 0.0, n)[1] == pytest.approx(0.0, abs=1e-12 * abs(kalker(s, 0, 0)[0]))


def test_linear_limit_pure_spin_converges():
    """Pure spin tends to -G (ab)^1.5 c23 phi; discretisation error measured 1.7e-4 (20 x 20),
    4e-5 (50 x 50), 1.2e-5 (100 x 100)."""
    phi = 1e-6
    ref = kalker(0.0, 0.0, phi)[1]
    errors = [abs(fastsim(0.0, 0.0, phi, n)[1] / ref - 1.0) for n in (20, 50, 100)]
    assert errors[0] < 3e-4
    assert errors[1] < 1e-4
    assert errors[2] < errors[1] < errors[0]
    # spin produces no net longitudinal force (antisymmetric in y)
    assert abs(fastsim(0.0, 0.0, phi)[0]) < 1e-9 * abs(ref)


@pytest.mark.parametrize(
    ("xi", "eta", "phi"), [(0.5, 0.0, 0.0), (0.0, -0.3, 0.0), (0.3, 0.4, 0.0), (0.0, 0.5, 0.3)]
)
def test_saturation_at_mu_q(xi, eta, phi):
    """Full sliding: |F| -> mu Q along the creepage. The midpoint rule on the sqrt-shaped
    bound overshoots by 0.09 % with 50 x 50 cells (measured); 0.2 % tolerance."""
    f = np.array(fastsim(xi, eta, phi))
    assert np.hypot(*f) == pytest.approx(MU * Q, rel=2e-3)
    s = math.hypot(xi, eta)
    assert -(f[0] * xi + f[1] * eta) / (s * np.hypot(*f)) > 0.999


def test_saturation_converges():
    over = [np.hypot(*fastsim(0.3, 0.4, 0.0, n)) / (MU * Q) - 1.0 for n in (20, 50, 100)]
    assert over[0] > over[1] > over[2] > 0.0
    assert over[2] < 5e-4


def test_agreement_with_polach_without_spin():
    """Without spin, FASTSIM with the ellipsoidal bound makes Polach's assumptions, so it
    converges to Polach's curve (like 1/n). Measured largest relative difference in |F| over
    s = 1e-5 .. 0.05 and five directions: 1.7 % (20 x 20), 0.65 % (50 x 50), 0.30 % (100 x 100).
    """

    def worst(n):
        w = 0.0
        for t in np.radians([0.0, 30.0, 60.0, 90.0, 200.0]):
            for s in np.geomspace(1e-5, 0.05, 25):
                xi, eta = s * math.cos(t), s * math.sin(t)
                fs = math.hypot(*fastsim(xi, eta, 0.0, n))
                po = math.hypot(*polach_forces(xi, eta, 0.0, Q, MU, *GEOM))
                w = max(w, abs(fs / po - 1.0))
        return w

    w20, w50 = worst(20), worst(FASTSIM_STRIPS)
    assert w50 < 1e-2
    assert w20 < 2.5e-2
    assert w50 < w20


@pytest.mark.parametrize(("phi", "limit"), [(0.02, 0.06), (0.1, 0.12)])
def test_agreement_with_polach_with_spin(phi, limit):
    """With spin the models differ: Polach's spin treatment (eta_C, F_yS) is an approximation.

    Measured largest |F_fastsim - F_polach| / (mu Q) over s = 0 .. 0.05 in five directions for
    this contact (a/b = 1.63): 0.043 at phi = 0.02 1/m, 0.094 at 0.1 1/m, 0.33 at 0.5 1/m, 0.50
    at 2 1/m (largest in the transition, eps ~ 1; the curves agree in the linear range and in
    full sliding). Tread contacts have phi ~ 0.1 1/m, flange contacts ~ 1.5 1/m.
    """
    worst = 0.0
    for t in np.radians([0.0, 45.0, 90.0, 180.0, 270.0]):
        for s in np.concatenate([[0.0], np.geomspace(1e-5, 0.05, 25)]):
            xi, eta = s * math.cos(t), s * math.sin(t)
            fs = np.array(fastsim(xi, eta, phi))
            po = np.array(polach_forces(xi, eta, phi, Q, MU, *GEOM))
            worst = max(worst, np.hypot(*(fs - po)) / (MU * Q))
    assert worst < limit
    # linear range with spin: both are Kalker's linear theory (Polach: for pure eta + spin; with
    # xi too its creep force points along the creepage, not along Kalker's force)
    small = (1e-8, 2e-8, 1e-6)
    np.testing.assert_allclose(fastsim(*small), kalker(*small), rtol=1e-4)
    small = (0.0, 2e-8, 1e-6)
    np.testing.assert_allclose(fastsim(*small), kalker(*small), rtol=1e-4, atol=1e-12)
    np.testing.assert_allclose(
        polach_forces(*small, Q, MU, *GEOM), kalker(*small), rtol=1e-6, atol=1e-12
    )


@pytest.mark.parametrize("s", [1e-6, 1e-4, 2e-3, 0.05])
def test_sign_and_symmetry(s):
    """Force on the wheel opposes the creepage; odd symmetry; lateral mirror."""
    assert fastsim(s, 0.0, 0.0)[0] < 0.0
    assert fastsim(0.0, s, 0.0)[1] < 0.0
    assert fastsim(0.0, 0.0, s * 100)[1] < 0.0  # spin pushes like a positive eta
    fx, fy = fastsim(s, -0.5 * s, 20 * s)
    assert fastsim(-s, 0.5 * s, -20 * s) == pytest.approx((-fx, -fy), rel=1e-12, abs=1e-9)
    assert fastsim(s, 0.5 * s, -20 * s) == pytest.approx((fx, -fy), rel=1e-12, abs=1e-9)


def test_zero_and_degenerate_input():
    assert fastsim(0.0, 0.0, 0.0) == (0.0, 0.0)
    assert fastsim(1e-3, 0.0, 0.0, q=0.0) == (0.0, 0.0)
    assert fastsim(1e-3, 2e-3, 0.5, mu=0.0) == (0.0, 0.0)
    with pytest.raises(ValueError):
        fastsim_forces(1e-3, 0.0, 0.0, Q, MU, *GEOM, n_strips=0)


def test_python_wrapper_equals_numba():
    args = (1.3e-3, -0.7e-3, 0.4, Q, MU, *GEOM)
    assert fastsim_forces(*args) == fastsim_nb(*args, FASTSIM_STRIPS, FASTSIM_POINTS)
    assert fastsim_forces(*args, n_strips=7, n_points=11) == fastsim_nb(*args, 7, 11)
