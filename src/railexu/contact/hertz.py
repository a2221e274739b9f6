"""Hertz's normal contact between two elastic bodies (wheel and rail).

The undeformed gap near the initial contact point is ``h(x, y) = A x^2 + B y^2 - delta`` with
``A`` and ``B`` half the sums of the principal relative curvatures of wheel and rail along the
rolling direction ``x`` and the lateral direction ``y`` [1/m]; ``delta`` [m] is the approach
(penetration) of the two bodies. Hertz's solution (Johnson, *Contact Mechanics*, 1985, section 4.2,
eqs. (4.39)-(4.41); docs/theory.md 3.1) gives an elliptical contact patch with semi-axes ``a``
(along ``x``) and ``b`` (along ``y``) and the ellipsoidal pressure ``p0 sqrt(1 - x^2/a^2 -
y^2/b^2)``.

With ``g = min(a, b) / max(a, b)``, ``k = sqrt(1 - g^2)`` and the complete elliptic integrals
``K(k)``, ``E(k)``:

* curvature ratio ``beta = min(A, B) / max(A, B) = g^2 (K - E) / (E - g^2 K)`` (solved for ``g``);
* ``rho = 2 / (A + B)``, ``c = sqrt(a b) = [3 N rho E / (4 pi E* sqrt(g))]^(1/3)``;
* the semi-axis along the direction of larger curvature is the shorter one;
* approach ``delta = 2 g c^2 K / (rho E)``, peak pressure ``p0 = 3 N / (2 pi a b)``;
* ``N = K_H delta^(3/2)`` with ``K_H = (sqrt(2) pi E* / 3) sqrt(rho E) / (g K^(3/2))``.

Note that :func:`scipy.special.ellipk` and :func:`scipy.special.ellipe` take the *parameter*
``m = k^2``, not the modulus ``k``. Near ``g -> 0`` we use :func:`scipy.special.ellipkm1`
(argument ``1 - m = g^2``) to keep ``K`` accurate, and near ``g -> 1`` a series in ``m`` to avoid
the cancellation in ``K - E`` and ``E - g^2 K``.

Two APIs are provided:

* plain Python: :func:`effective_modulus`, :func:`hertz_contact`, :func:`hertz_stiffness`,
  :func:`hertz_m_n`, :func:`solve_axis_ratio` (exact, solving the transcendental equation);
* compiled: :func:`hertz_table` builds a table over ``beta`` once, and the numba function
  :func:`hertz_coefficients_nb` returns ``(K_H, alpha_a, alpha_b)`` such that for a penetration
  ``delta``: ``N = K_H delta^1.5``, ``a = alpha_a sqrt(delta)``, ``b = alpha_b sqrt(delta)``.

Accuracy of the table (measured against the exact solution, ``beta`` in ``[1e-4, 1]``, 20 000
random log-uniform samples plus all midpoints between nodes, both orientations): the largest
relative error in ``K_H``, ``alpha_a`` and ``alpha_b`` is 1.8e-4 for ``n = 128``, 4.5e-5 for
256, 1.1e-5 for 512 and 2.8e-6 for the default ``n = 1024`` (linear interpolation in
``log(beta)`` of smooth functions, so the error falls as ``1/n^2``; it is largest for
``beta > 0.5``, nearly circular contacts). Interpolating the logarithms of the functions instead
is slightly more accurate (1.7e-6) but costs three ``exp`` per call.
``tests/test_hertz.py`` checks ``< 5e-6`` for the default table.

Non-Hertzian situations: where a curvature sum is zero or negative (flat or conformal contact,
e.g. a hollow-worn tread or the flange root against the gauge corner) Hertz's theory breaks down.
The compiled and Python functions then clamp the smaller curvature sum to
``HERTZ_BETA_MIN = 1e-4`` times the larger one (the end of the table; the ellipse is then about
240 times longer than wide), and the larger one to at least ``HERTZ_MIN_CURVATURE = 1e-3 1/m``
(radius 500 m, flatter than any wheel or rail surface in the rolling direction). They never
return NaN for finite input.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numba
import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipkm1

__all__ = [
    "HERTZ_BETA_MIN",
    "HERTZ_MIN_CURVATURE",
    "HertzContact",
    "effective_modulus",
    "solve_axis_ratio",
    "hertz_contact",
    "hertz_stiffness",
    "hertz_m_n",
    "hertz_table",
    "hertz_coefficients_nb",
]

#: Smallest curvature ratio ``min(A, B) / max(A, B)`` handled; smaller (or negative) ratios are
#: clamped to it. It is also the lower end of :func:`hertz_table`.
HERTZ_BETA_MIN = 1.0e-4

#: Smallest accepted value of the larger curvature sum ``max(A, B)`` [1/m].
HERTZ_MIN_CURVATURE = 1.0e-3

# Below this elliptic parameter m = k^2 = 1 - g^2 the curvature ratio is computed from its series.
_SERIES_M = 1.0e-3


@dataclass(frozen=True)
class HertzContact:
    """Hertz's solution for one contact.

    Attributes:
        a_m: semi-axis of the contact ellipse along the rolling direction ``x`` [m].
        b_m: semi-axis along the lateral direction ``y`` [m].
        delta_m: approach (penetration) of the two bodies [m].
        p0_Pa: peak (central) pressure [Pa].
        stiffness_N_per_m15: ``K_H`` in ``N = K_H delta^1.5`` [N/m^1.5].
        g: semi-axis ratio ``min(a, b) / max(a, b)`` [-].
    """

    a_m: float
    b_m: float
    delta_m: float
    p0_Pa: float  # noqa: N815 (unit suffix)
    stiffness_N_per_m15: float  # noqa: N815 (unit suffix)
    g: float


def effective_modulus(
    young1_Pa: float,
    poisson1: float,
    young2_Pa: float | None = None,
    poisson2: float | None = None,
) -> float:
    """Effective (contact) modulus ``E*`` [Pa] of two elastic bodies.

    ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` (Johnson 1985, eq. (4.22); docs/theory.md 3.1).
    When the second body's data are omitted it is made of the same material.

    Args:
        young1_Pa: Young's modulus of body 1 [Pa].
        poisson1: Poisson's ratio of body 1 [-].
        young2_Pa: Young's modulus of body 2 [Pa]; defaults to ``young1_Pa``.
        poisson2: Poisson's ratio of body 2 [-]; defaults to ``poisson1``.

    Returns:
        ``E*`` [Pa]. Steel on steel (210 GPa, 0.3): 115.4 GPa.
    """
    if young2_Pa is None:
        young2_Pa = young1_Pa
    if poisson2 is None:
        poisson2 = poisson1
    if young1_Pa <= 0.0 or young2_Pa <= 0.0:
        raise ValueError("Young's moduli must be positive")
    for nu in (poisson1, poisson2):
        if not -1.0 < nu <= 0.5:
            raise ValueError(f"Poisson's ratio {nu} outside (-1, 0.5]")
    return 1.0 / ((1.0 - poisson1**2) / young1_Pa + (1.0 - poisson2**2) / young2_Pa)


def _elliptic_k_e(g: float) -> tuple[float, float]:
    """``K(k)``, ``E(k)`` for ``k = sqrt(1 - g^2)`` (accurate also for tiny ``g``)."""
    p = g * g
    return float(ellipkm1(p)), float(ellipe(1.0 - p))


def _curvature_ratio(g: float) -> float:
    """``beta(g) = g^2 (K - E) / (E - g^2 K)``, monotonic from 0 (g = 0) to 1 (g = 1)."""
    if g >= 1.0:
        return 1.0
    p = g * g
    m = 1.0 - p
    if m < _SERIES_M:
        # K - E = (pi/2)(m/2 + 3m^2/16 + 15m^3/128 + 175m^4/2048 + ...),
        # E - (1-m) K = (pi/2)(m/2 + m^2/16 + 3m^3/128 + 25m^4/2048 + ...); the common factor
        # (pi/2) m cancels. Truncation error ~ m^4 < 1e-12.
        num = 0.5 + m * (3.0 / 16.0 + m * (15.0 / 128.0 + m * 175.0 / 2048.0))
        den = 0.5 + m * (1.0 / 16.0 + m * (3.0 / 128.0 + m * 25.0 / 2048.0))
        return p * num / den
    K, E = _elliptic_k_e(g)
    return p * (K - E) / (E - p * K)


def solve_axis_ratio(curvature_ratio: float) -> float:
    """Semi-axis ratio ``g = min(a, b)/max(a, b)`` for ``beta = min(A, B)/max(A, B)``.

    Solves ``beta = g^2 (K - E) / (E - g^2 K)`` (Johnson 1985, eq. (4.39); docs/theory.md 3.1)
    by Brent's method to ~1e-15 relative accuracy.

    Args:
        curvature_ratio: ``beta`` in ``(0, 1]``; values above 1 are reciprocated.

    Returns:
        ``g`` in ``(0, 1]``.
    """
    beta = float(curvature_ratio)
    if not beta > 0.0:
        raise ValueError(f"curvature ratio must be positive, got {beta}")
    if beta > 1.0:
        beta = 1.0 / beta
    if beta >= 1.0 - 1e-15:
        return 1.0
    # beta(g) ~ g^2 (ln(4/g) - 1) for small g, so g > sqrt(beta)/10 for beta > 1e-300.
    lo = max(math.sqrt(beta) * 1e-3, 1e-300)
    return float(brentq(lambda g: _curvature_ratio(g) - beta, lo, 1.0, xtol=1e-300, rtol=1e-15))


def _clamp_curvatures(A: float, B: float) -> tuple[float, float]:
    """Apply the documented clamp: ``max >= HERTZ_MIN_CURVATURE``, ``min >= HERTZ_BETA_MIN max``."""
    if not (math.isfinite(A) and math.isfinite(B)):
        raise ValueError(f"curvature sums must be finite, got A={A}, B={B}")
    big = max(A, B, HERTZ_MIN_CURVATURE)
    if A >= B:
        return big, max(B, HERTZ_BETA_MIN * big)
    return max(A, HERTZ_BETA_MIN * big), big


def _shape(A: float, B: float) -> tuple[float, float, float, float]:
    """``(g, K, E, rho)`` for clamped curvature sums."""
    beta = min(A, B) / max(A, B)
    g = solve_axis_ratio(beta)
    if g >= 1.0:
        K = E = 0.5 * math.pi
    else:
        K, E = _elliptic_k_e(g)
    return g, K, E, 2.0 / (A + B)


def hertz_stiffness(A: float, B: float, e_star_Pa: float) -> float:
    """Hertz contact stiffness ``K_H`` [N/m^1.5] with ``N = K_H delta^1.5``.

    ``K_H = (sqrt(2) pi E* / 3) sqrt(rho E) / (g K^(3/2))``, ``rho = 2/(A + B)`` (docs/theory.md
    section 3.1, from Johnson 1985 eqs. (4.39)-(4.41)).

    Args:
        A: half the sum of the principal curvatures along ``x`` (rolling) [1/m].
        B: half the sum along ``y`` (lateral) [1/m]. ``A, B <= 0`` are clamped (module doc).
        e_star_Pa: effective modulus ``E*`` [Pa], see :func:`effective_modulus`.
    """
    A, B = _clamp_curvatures(A, B)
    g, K, E, rho = _shape(A, B)
    return math.sqrt(2.0) * math.pi * e_star_Pa / 3.0 * math.sqrt(rho * E) / (g * K**1.5)


def hertz_contact(A: float, B: float, normal_force_N: float, e_star_Pa: float) -> HertzContact:
    """Hertz's solution for the normal force ``N`` (exact, via elliptic integrals).

    Johnson 1985, section 4.2, eqs. (4.39)-(4.41); docs/theory.md 3.1. The semi-axis along the
    direction of larger curvature is the shorter one.

    Args:
        A: half the sum of the principal curvatures along ``x`` (rolling) [1/m].
        B: half the sum along ``y`` (lateral) [1/m]. ``A, B <= 0`` are clamped (module doc).
        normal_force_N: normal force ``N >= 0`` [N].
        e_star_Pa: effective modulus ``E*`` [Pa].

    Returns:
        :class:`HertzContact` with ``a`` along ``x``, ``b`` along ``y``.
    """
    if normal_force_N < 0.0:
        raise ValueError(f"normal force must be >= 0, got {normal_force_N}")
    if e_star_Pa <= 0.0:
        raise ValueError(f"effective modulus must be positive, got {e_star_Pa}")
    A, B = _clamp_curvatures(A, B)
    g, K, E, rho = _shape(A, B)
    k_h = math.sqrt(2.0) * math.pi * e_star_Pa / 3.0 * math.sqrt(rho * E) / (g * K**1.5)
    c = (3.0 * normal_force_N * rho * E / (4.0 * math.pi * e_star_Pa * math.sqrt(g))) ** (1.0 / 3.0)
    short, long_ = c * math.sqrt(g), c / math.sqrt(g)
    a, b = (short, long_) if A >= B else (long_, short)
    delta = 2.0 * g * c * c * K / (rho * E)
    p0 = 3.0 * normal_force_N / (2.0 * math.pi * a * b) if normal_force_N > 0.0 else 0.0
    return HertzContact(a_m=a, b_m=b, delta_m=delta, p0_Pa=p0, stiffness_N_per_m15=k_h, g=g)


def hertz_m_n(theta_rad: float) -> tuple[float, float]:
    """Classical Hertz coefficients ``(m, n)`` (Timoshenko & Goodier, *Theory of Elasticity*).

    With ``cos(theta) = (B - A)/(A + B)`` (``B >= A``) and ``k_i = (1 - nu_i^2)/(pi E_i)``, the
    semi-major and semi-minor axes are ``m [3 pi N (k1 + k2) / (4 (A + B))]^(1/3)`` and
    ``n [...]^(1/3)``, i.e. ``m [3 N / (4 E* (A + B))]^(1/3)``. Comparing with Johnson's form
    (module doc) gives ``m = (2 E(k) / (pi g^2))^(1/3)`` and ``n = g m``, with ``g`` solved from
    ``A/B = tan^2(theta/2)``. Table values: 30 deg 2.731/0.493, 60 deg 1.486/0.717, 90 deg 1/1.

    Args:
        theta_rad: the auxiliary angle ``theta`` in ``(0, pi/2]`` [rad] (values in
            ``(pi/2, pi)`` are mapped to ``pi - theta``, the same ellipse turned by 90 deg).

    Returns:
        ``(m, n)``, ``m >= 1 >= n``.
    """
    cos_t = abs(math.cos(theta_rad))
    if cos_t >= 1.0:
        raise ValueError("theta must lie strictly between 0 and pi")
    beta = (1.0 - cos_t) / (1.0 + cos_t)
    g = solve_axis_ratio(beta)
    E = 0.5 * math.pi if g >= 1.0 else _elliptic_k_e(g)[1]
    m = (2.0 * E / (math.pi * g * g)) ** (1.0 / 3.0)
    return m, g * m


@functools.lru_cache(maxsize=8)
def hertz_table(n: int = 1024, beta_min: float = HERTZ_BETA_MIN) -> np.ndarray:
    """Table for :func:`hertz_coefficients_nb`, uniform in ``log(beta)``; built once per process
    and argument pair and shared by every model and wheelset (do not modify it; it is not
    flagged read-only because numba compiles read-only arrays into different machine code).

    Columns: ``log(beta)``, ``f_K``, ``f_short``, ``f_long`` with ``f_K = sqrt(E)/(g K^1.5)``,
    ``f_short = sqrt(E/(2K))``, ``f_long = f_short/g``, so that
    ``K_H = (sqrt(2) pi E*/3) sqrt(rho) f_K`` and the short / long semi-axes are
    ``sqrt(rho delta) f_short`` / ``sqrt(rho delta) f_long`` (from ``delta = 2 g c^2 K/(rho E)``).
    Rows run from ``beta = beta_min`` to ``beta = 1``.

    Args:
        n: number of nodes (>= 2); the default 1024 gives a relative error below 3e-6 (module
            doc). Building it takes about 15 ms.
        beta_min: lower end of the table (default :data:`HERTZ_BETA_MIN`); the compiled function
            clamps smaller ratios to it.

    Returns:
        ``(n, 4)`` float64 array.
    """
    if n < 2:
        raise ValueError("the table needs at least two nodes")
    if not 0.0 < beta_min < 1.0:
        raise ValueError("beta_min must lie in (0, 1)")
    log_beta = np.linspace(math.log(beta_min), 0.0, n)
    table = np.empty((n, 4))
    for i, lb in enumerate(log_beta):
        beta = math.exp(lb) if i < n - 1 else 1.0
        g = solve_axis_ratio(beta)
        if g >= 1.0:
            K = E = 0.5 * math.pi
        else:
            K, E = _elliptic_k_e(g)
        f_short = math.sqrt(E / (2.0 * K))
        table[i, 0] = lb
        table[i, 1] = math.sqrt(E) / (g * K**1.5)
        table[i, 2] = f_short
        table[i, 3] = f_short / g
    table[-1, 0] = 0.0
    return table


@numba.njit(cache=True)
def hertz_coefficients_nb(
    table: np.ndarray, A: float, B: float, e_star: float
) -> tuple[float, float, float]:
    """Compiled Hertz coefficients from a :func:`hertz_table`.

    For a penetration ``delta`` [m]: ``N = K_H delta^1.5``, ``a = alpha_a sqrt(delta)`` (along the
    rolling direction ``x``), ``b = alpha_b sqrt(delta)`` (lateral). Linear interpolation in
    ``log(beta)`` (accuracy: module doc). ``A, B <= 0`` or a ratio
    below the table are clamped as documented in the module doc (never NaN for finite input).

    Args:
        table: output of :func:`hertz_table`.
        A: half the sum of the principal curvatures along ``x`` [1/m].
        B: half the sum along ``y`` [1/m].
        e_star: effective modulus ``E*`` [Pa].

    Returns:
        ``(K_H [N/m^1.5], alpha_a [m^0.5], alpha_b [m^0.5])``.
    """
    n = table.shape[0]
    lb0 = table[0, 0]
    big = A if A >= B else B
    small = B if A >= B else A
    if not big >= 1.0e-3:  # HERTZ_MIN_CURVATURE; also catches NaN
        big = 1.0e-3
    if small > big:
        small = big
    lr = math.log(small / big) if small > 0.0 else lb0 - 1.0
    if not lr >= lb0:  # below the table, zero, negative or NaN: clamp to beta_min
        lr = lb0
        small = big * math.exp(lb0)
    rho = 2.0 / (big + small)
    # position in the uniform log(beta) grid
    t = (lr - lb0) / (table[1, 0] - lb0)
    i = int(t)
    if i > n - 2:
        i = n - 2
    w = t - i
    if w > 1.0:
        w = 1.0
    f_k = table[i, 1] + w * (table[i + 1, 1] - table[i, 1])
    f_short = table[i, 2] + w * (table[i + 1, 2] - table[i, 2])
    f_long = table[i, 3] + w * (table[i + 1, 3] - table[i, 3])
    sqrt_rho = math.sqrt(rho)
    k_h = math.sqrt(2.0) * math.pi / 3.0 * e_star * sqrt_rho * f_k
    alpha_short = sqrt_rho * f_short
    alpha_long = sqrt_rho * f_long
    if A >= B:  # larger curvature along x: a is the short semi-axis
        return k_h, alpha_short, alpha_long
    return k_h, alpha_long, alpha_short
