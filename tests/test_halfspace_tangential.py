"""The exact steady rolling tangential solution (railexu.contact.halfspace_tangential) against
results from outside the code: Kalker's linear theory, Coulomb's full sliding and Carter's 2-D
solution. CONTACT's S&C cases with it are in tests/test_sc_contact_creep.py.

Tolerances and their reasons:

- **Kalker's coefficients** (``c11, c22, c23``, Kalker 1990, Table E.3, for a circle and
  nu = 0.28: 4.226, 3.705, 1.488; the table's 3 digits are 0.1-0.3 %) on a Hertz circle
  discretised by 32 elements across its diameter: within 3 % (measured +1.6, +2.0, -0.9 %:
  the staircase edge, whose loaded area is 1.0 % above pi a^2, and the first-order slip
  difference at the leading edge's singular traction); the error of ``c11`` and ``c22`` falls
  with refinement (16 elements: +5.0, +5.5 %; 48: +1.5, +1.8 %; 64: +1.3, +1.5 %).
- **full sliding**: every element at ``mu p`` against its slip, so ``|F| = mu N`` (1e-5
  asserted: the bound is met exactly) and along ``-(xi, eta)`` within 2e-3 rad (the elastic
  part of the slip, displacement gradients of order ``mu p / G`` ~ 7e-3 against the creepage
  0.05, turns it: 6e-4 rad measured for (0.03, 0.04)).
- **Carter** (1926; Johnson 1985, sec. 8.2): on a strip, per unit length,
  ``F / (mu N) = -(1 - (1 - k)^2)``, ``k = xi E* / (2 mu p0)`` (``E* = G / (1 - nu)``, both
  bodies), full sliding beyond ``k = 1``. The middle of a strip 8 half-widths long with 20
  elements across: within 2 % of mu N (measured 0.8, 1.4, 1.5 % at k = 0.25, 0.5, 0.75; 40
  elements: 0.5, 0.8, 0.9 %, asserted to fall).
"""

from __future__ import annotations

import math

import halfspace as reference_halfspace
import numpy as np
import pytest

from railexu.contact.halfspace import solve_normal
from railexu.contact.halfspace_tangential import influence_coefficients, solve_tangential
from railexu.contact.kalker import kalker_coefficients
from railexu.contact.variable_creep import PatchCreepage, WheelMotion, tangential_forces
from railexu.errors import ComputationError

G, NU, MU = 82e9, 0.28, 0.3


def _hertz(n: int):
    """A Hertz circle (sphere R = 0.3 m on a plane, approach 50 um) with ``n`` elements across
    its diameter: pressure [Pa], element centres [m], radius a [m], element size [m]."""
    r, d = 0.3, 50e-6
    a = math.sqrt(r * d)
    h = 2.0 * a / n
    x = (np.arange(n + 4) - 0.5 * (n + 3)) * h
    xx, yy = np.meshgrid(x, x, indexing="ij")
    p = solve_normal(d - (xx**2 + yy**2) / (2.0 * r), h, h, G / (1.0 - NU))
    return p, x, a, h


def _linear_errors(n: int) -> tuple[float, float, float]:
    """Relative errors of the forces against Kalker's ``-G a^2 c11 xi``, ``-G a^2 c22 eta``
    and ``-G a^3 c23 phi`` (Kalker's signs; force on the rail) at small creepages."""
    p, x, a, h = _hertz(n)
    c11, c22, c23 = kalker_coefficients(1.0, NU)
    fx = solve_tangential(p, x, x, 1e-6, 0.0, 0.0, MU, G, NU)[0].sum() * h * h
    fs = solve_tangential(p, x, x, 0.0, 1e-6, 0.0, MU, G, NU)[1].sum() * h * h
    fp = solve_tangential(p, x, x, 0.0, 0.0, 1e-4, MU, G, NU)[1].sum() * h * h
    return (
        fx / (-G * a * a * c11 * 1e-6) - 1.0,
        fs / (-G * a * a * c22 * 1e-6) - 1.0,
        fp / (-G * a**3 * c23 * 1e-4) - 1.0,
    )


def test_small_creepages_give_kalkers_coefficients():
    """32 elements across a Hertz circle: c11, c22, c23 within 3 %; c11 and c22's errors
    fall from 16 elements (module doc)."""
    fine = _linear_errors(32)
    coarse = _linear_errors(16)
    for e in fine:
        assert abs(e) < 0.03
    assert abs(fine[0]) < abs(coarse[0])
    assert abs(fine[1]) < abs(coarse[1])


def test_full_sliding_gives_mu_n_against_the_creepage():
    """Creepage 0.05 (~30 times saturation): ``|F| = mu N`` along ``-(xi, eta)`` (on the rail);
    no creepage gives no traction; via ``tangential_forces`` with ``tangential="exact"``."""
    p, x, _, h = _hertz(20)
    n = float(p.sum()) * h * h
    motion = WheelMotion(2.0, -4.0, friction=MU, tangential="exact")
    for xi, eta in ((0.05, 0.0), (0.0, -0.05), (0.03, 0.04)):
        fx, fs = tangential_forces(p, x, x, PatchCreepage(xi, eta, 0.0, 2.0, 0.0), motion, G, NU)
        assert math.hypot(fx, fs) == pytest.approx(MU * n, rel=1e-5)
        assert math.atan2(-fs, -fx) == pytest.approx(math.atan2(eta, xi), abs=2e-3)
    rest = tangential_forces(p, x, x, PatchCreepage(0.0, 0.0, 0.0, 2.0, 0.0), motion, G, NU)
    assert rest == (0.0, 0.0)


def _carter_errors(nx: int) -> list[float]:
    """``F / (mu N)`` of the middle column of a strip against Carter's, k = 0.25, 0.5, 0.75,
    1.5 (module doc): a = 4 mm, p0 = 1 GPa, 8 a long in 16 elements, ``nx`` across."""
    a, p0 = 4e-3, 1e9
    dx = 2.0 * a / nx
    x = (np.arange(nx + 2) - 0.5 * (nx + 1)) * dx
    s = (np.arange(16) - 7.5) * (0.5 * a)
    p = np.outer(p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None)), np.ones(s.size))
    xi_sat = 2.0 * MU * p0 * (1.0 - NU) / G
    errors = []
    for k in (0.25, 0.5, 0.75, 1.5):
        qx, _ = solve_tangential(p, x, s, k * xi_sat, 0.0, 0.0, MU, G, NU)
        ratio = qx[:, 8].sum() / (MU * p[:, 8].sum())
        errors.append(ratio + 1.0 - (1.0 - min(k, 1.0)) ** 2)
    return errors


def test_carters_two_dimensional_solution():
    """The middle of a long strip: within 2 % of mu N at 20 elements across, falling at 40;
    full sliding exact (module doc)."""
    coarse = _carter_errors(20)
    fine = _carter_errors(40)
    for e in coarse[:3]:
        assert abs(e) < 0.02
    for c, f in zip(coarse[:3], fine[:3], strict=True):
        assert abs(f) < abs(c)
    assert abs(coarse[3]) < 1e-5


def test_influence_coefficients_are_cerrutis():
    """Far from the loaded element the coefficients are Cerruti's point load (two bodies):
    ``u_x = (1 / (pi G)) ((1 - nu) / r + nu x^2 / r^3)``, ``u_s = nu x s / (pi G r^3)``, within
    1e-3 at 20 elements (the element's second moment, (h / r)^2 / 24); ``Axx`` and ``Ass``
    equal the tests' own independent integral (tests/halfspace.py) on a 1:2 grid to 1e-12."""
    h = 1e-4
    axx, ass, axs = influence_coefficients(20, 20, h, h, G, NU)
    x, s = 20 * h, 12 * h
    r = math.hypot(x, s)
    c = h * h / (math.pi * G)
    assert axx[40, 32] == pytest.approx(c * ((1 - NU) / r + NU * x * x / r**3), rel=1e-3)
    assert ass[40, 32] == pytest.approx(c * ((1 - NU) / r + NU * s * s / r**3), rel=1e-3)
    assert axs[40, 32] == pytest.approx(c * NU * x * s / r**3, rel=1e-3)
    assert axs[20, 20] == 0.0
    # the tests' own independent reference (tests/halfspace.py) on every offset, the loaded
    # element itself included, and with x and s swapped for Ass
    off = np.arange(-20, 21) * h
    X, S = np.meshgrid(off, off, indexing="ij")
    axx2, ass2, _ = influence_coefficients(20, 20, h, 2 * h, G, NU)
    assert np.allclose(axx2, reference_halfspace.tangential_rectangle_integral(
        X, 2 * S, h, 2 * h, NU) / (np.pi * G), rtol=1e-12, atol=0.0)  # fmt: skip
    assert np.allclose(ass2, reference_halfspace.tangential_rectangle_integral(
        2 * S, X, 2 * h, h, NU) / (np.pi * G), rtol=1e-12, atol=0.0)  # fmt: skip


def test_no_convergence_is_reported():
    """A sweep limit too small to converge raises a ComputationError naming the patch."""
    p, x, _, _ = _hertz(16)
    with pytest.raises(ComputationError, match="no convergence in 2 sweeps"):
        solve_tangential(p, x, x, 1e-6, 0.0, 0.0, MU, G, NU, max_sweeps=2)


def test_adhesion_equals_the_direct_solution():
    """Full adhesion (mu = 1e6) on the 16-element Hertz circle: the Gauss-Seidel solution's
    force equals the dense direct solve of the same steady rolling equations in the tests' own
    reference (tests/halfspace.py: longitudinal tractions only, its sign convention opposite)
    within 1e-4 for nu = 0, where the lateral coupling vanishes (measured 3e-6: the solver's
    tolerance), and within 1e-3 for nu = 0.28 (measured 3e-4: the coupling the reference
    leaves out)."""
    p, x, _, h = _hertz(16)
    ii, jj = np.nonzero(p > 0.0)
    creep = np.full((ii.size, 1), 1e-6)
    for nu, rel in ((0.0, 1e-4), (NU, 1e-3)):
        direct = reference_halfspace.linear_theory_forces(x[ii], x[jj], h, h, creep, G, nu)[0]
        qx, _ = solve_tangential(p, x, x, 1e-6, 0.0, 0.0, 1e6, G, nu)
        assert float(qx.sum()) * h * h == pytest.approx(-direct, rel=rel)
