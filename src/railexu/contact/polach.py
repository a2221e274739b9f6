r"""Polach's creep-force method, 1999 (with spin) and the 2005 extension for large creepage.

Sources:

* O. Polach, "A fast wheel-rail forces calculation computer code", Vehicle System Dynamics
  Suppl. 33 (1999) 728-739 ("1999" below);
* O. Polach, "Creep forces in simulations of traction vehicles running on adhesion limit",
  Wear 258 (2005) 992-1000 ("2005" below);
* docs/theory.md sections 4.3 and 4.4 (formulas re-derived here, not copied from a port).

Notation: creepages ``xi`` (longitudinal), ``eta`` (lateral) [-], spin ``phi`` [1/m], normal
force ``Q`` [N], friction ``mu``, semi-axes ``a`` (rolling direction) and ``b`` [m], shear
modulus ``G`` [Pa], Kalker's ``c11, c22, c23``.

Method (forces first written in the direction of the creepage, then turned onto the wheel):

1. ``s = sqrt(xi^2 + eta^2)``; Kalker's coefficient in the direction of the creepage
   ``c_jj = sqrt((c11 xi/s)^2 + (c22 eta/s)^2)`` (``c22`` for ``s = 0``).
2. Spin-modified lateral creepage ``eta_C = eta + phi a`` if ``|eta + phi a| > |eta|``, else
   ``eta``; ``s_C = sqrt(xi^2 + eta_C^2)`` (1999, eqs. for ``s_yC`` and ``s_C``). Spin only ever
   *adds* to the lateral creepage that feeds the saturation.
3. Friction: 1999 uses ``mu = mu0``; 2005 lets it fall with the slip velocity ``w = s_C |V|``:
   ``mu = mu0 ((1 - A) exp(-B w) + A)``, evaluated as ``mu0 (1 - (1 - A)(1 - exp(-B w)))``
   (same value; it is exactly ``mu0`` when ``A = 1`` or ``B w = 0``).
4. Gradient of the tangential stress ``eps = G pi a b c_jj s_C / (4 Q mu)``;
   ``F = (2 Q mu / pi) (k_A eps / (1 + (k_A eps)^2) + atan(k_S eps))`` (2005 eq. (9);
   ``k_A = k_S = 1`` gives the 1999 law ``eps/(1 + eps^2) + atan(eps)``). Components along the
   creepage: ``F xi / s_C`` and ``F eta / s_C``. For ``eps -> 0`` with ``k_A = k_S = 1``,
   ``F -> (4 Q mu / pi) eps = G a b c_jj s_C`` so the components tend to ``G a b c_jj xi`` and
   ``G a b c_jj eta``: exactly Kalker's linear theory for pure ``xi`` or pure ``eta``, and for a
   combined creepage the magnitude ``G a b c_jj s`` equals Kalker's
   ``G a b sqrt(c11^2 xi^2 + c22^2 eta^2)`` (the direction is the creepage direction, not
   Kalker's). For ``eps -> inf``, ``F -> mu Q``.
5. Spin force (1999): ``k_M = 1 + 6.3 (1 - exp(-a/b))`` (called ``k_s`` in the paper; renamed
   here to avoid a clash with the 2005 ``k_S``),
   ``eps_S = (8/3) G b sqrt(ab) c23 s_C / (Q mu k_M)``, ``delta = (eps_S^2 - 1)/(eps_S^2 + 1)``,
   ``K_M = |eps_S| (delta^3/3 - delta^2/2 + 1/6) - (1/3) sqrt((1 - delta^2)^3)``,
   ``F_yS = -(9/16) a Q mu K_M k_M phi / s_C``.

The spin gradient uses ``s_C``, not ``|eta_C|`` (decision)
------------------------------------------------------------
Secondary texts write ``eps_S`` with ``|eta_C|``; Polach's paper writes it with ``s_C``. The paper's
form is the one that reproduces Kalker's linear spin term, for any ``xi``:

* Simplify ``K_M`` first. With ``delta = (e^2 - 1)/(e^2 + 1)`` one has ``1 - delta = 2/(1 + e^2)``,
  ``1 - delta^2 = 4 e^2/(1 + e^2)^2`` and ``delta^3/3 - delta^2/2 + 1/6 = (1/6)(delta - 1)^2
  (2 delta + 1) = (2/3)(3 e^2 - 1)/(1 + e^2)^3``, hence exactly

  ``K_M = (|e|/(1 + e^2)^3) [(2/3)(3 e^2 - 1) - (8/3) e^2] = -(2/3) |e| / (1 + e^2)^2``.

* Therefore ``F_yS = (9/16)(2/3) a Q mu k_M phi |eps_S| / (s_C (1 + eps_S^2)^2)``. Inserting
  ``eps_S = (8/3) G b sqrt(ab) c23 X / (Q mu k_M)`` with ``X`` = ``s_C`` or ``|eta_C|``:
  ``F_yS = (9/16)(2/3)(8/3) G (ab)^(3/2) c23 phi (X / s_C) / (1 + eps_S^2)^2``.
  The factors give 1, so for small creepage ``F_yS -> G (ab)^(3/2) c23 phi (X / s_C)``.
* With ``X = s_C`` this is Kalker's ``G (ab)^(3/2) c23 phi`` whatever ``xi`` is. With
  ``X = |eta_C|`` it carries the factor ``|eta_C| / s_C = |eta_C| / sqrt(xi^2 + eta_C^2) < 1``:
  the spin force would vanish under a longitudinal creepage even in the linear range, which
  contradicts Kalker's linear theory (where the spin term is independent of ``xi``).

So ``eps_S`` uses ``s_C`` (as in Polach 1999), and the code evaluates the algebraically identical,
division-free form ``F_yS = G (ab)^(3/2) c23 phi / (1 + eps_S^2)^2``: no ``0/0`` at ``s_C -> 0``,
no cancellation for large ``eps_S``. The literal paper formula is checked against it in
``tests/test_polach.py``. (For pure spin at full sliding ``F_yS -> 0`` like ``1/eps_S^4``: a
spinning, fully sliding ellipse carries a moment but no net lateral force.)

2005 and spin (railexu's choice, docs/theory.md section 4.4): the reduction
factors ``k_A``, ``k_S`` act on the creep force of step 4 only; the spin term keeps the 1999
form, evaluated with the falling friction ``mu(w)``. So the 2005 spin force still tends to
Kalker's unreduced linear spin term for small creepage.

On the wheel (docs/conventions.md) the forces oppose the creepage::

    Fx = -F xi / s_C,    Fy = -(F eta / s_C + F_yS)

and ``xi = eta = phi = 0`` (``s_C = 0``) gives zero force, as do ``Q <= 0`` or ``mu <= 0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

__all__ = [
    "Polach2005Parameters",
    "POLACH_2005_PRESETS",
    "polach_2005_preset",
    "polach_forces",
    "polach_2005_forces",
    "polach_nb",
]


@dataclass(frozen=True)
class Polach2005Parameters:
    """Parameters of Polach's 2005 extension (Wear 258 (2005) 992-1000, Table 2).

    Attributes:
        k_a: reduction factor in the area of adhesion ``k_A`` [-], ``k_S <= k_A <= 1``.
        k_s: reduction factor in the area of slip ``k_S`` [-].
        friction_ratio_A: ratio ``A = mu_inf / mu0`` of limit friction at infinite slip velocity
            to maximum friction [-].
        friction_decay_B_s_per_m: exponential friction decrease rate ``B`` [s/m].
        mu0: maximum friction coefficient the set was fitted with [-] (a suggestion: the force
            functions take the friction as a separate argument).
    """

    k_a: float
    k_s: float
    friction_ratio_A: float  # noqa: N815 (Polach's symbol A)
    friction_decay_B_s_per_m: float  # noqa: N815 (Polach's symbol B)
    mu0: float

    def __post_init__(self) -> None:
        if not 0.0 < self.k_s <= self.k_a <= 1.0:
            raise ValueError(f"need 0 < k_s <= k_a <= 1, got k_a={self.k_a}, k_s={self.k_s}")
        if not 0.0 <= self.friction_ratio_A <= 1.0:
            raise ValueError(f"friction_ratio_A must lie in [0, 1], got {self.friction_ratio_A}")
        if self.friction_decay_B_s_per_m < 0.0:
            raise ValueError("friction_decay_B_s_per_m must be >= 0")


#: Parameter sets of Polach 2005, Table 2, as quoted by a secondary source (docs/theory.md 4.4;
#: check against the paper): dry and wet rail, measured on a locomotive.
POLACH_2005_PRESETS: dict[str, Polach2005Parameters] = {
    "dry": Polach2005Parameters(
        k_a=1.0, k_s=0.4, friction_ratio_A=0.4, friction_decay_B_s_per_m=0.6, mu0=0.55
    ),
    "wet": Polach2005Parameters(
        k_a=0.3, k_s=0.1, friction_ratio_A=0.4, friction_decay_B_s_per_m=0.2, mu0=0.30
    ),
}


def polach_2005_preset(name: str) -> Polach2005Parameters:
    """Return a named :data:`POLACH_2005_PRESETS` entry (``"dry"`` or ``"wet"``)."""
    key = name.strip().lower()
    if key not in POLACH_2005_PRESETS:
        valid = ", ".join(sorted(POLACH_2005_PRESETS))
        raise ValueError(f"unknown Polach 2005 parameter set {name!r}; valid: {valid}")
    return POLACH_2005_PRESETS[key]


def _polach_numpy(xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23, k_a, k_s, fric_A, fric_B, V):
    """Vectorised Polach (2005 form; 1999 with k_a = k_s = fric_A = 1). Force on the wheel."""
    args = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23))
    )
    xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23 = args
    eta_plus = eta + phi * a
    eta_c = np.where(np.abs(eta_plus) > np.abs(eta), eta_plus, eta)
    s_c = np.sqrt(xi * xi + eta_c * eta_c)
    s = np.sqrt(xi * xi + eta * eta)
    w = s_c * abs(float(V))
    mu = mu0 * (1.0 - (1.0 - fric_A) * (-np.expm1(-fric_B * w)))
    valid = (Q > 0.0) & (mu > 0.0) & (s_c > 0.0) & (a > 0.0) & (b > 0.0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        s_safe = np.where(s > 0.0, s, 1.0)
        cjj = np.where(s > 0.0, np.sqrt((c11 * xi / s_safe) ** 2 + (c22 * eta / s_safe) ** 2), c22)
        qmu = np.where(valid, Q * mu, 1.0)
        s_c_safe = np.where(valid, s_c, 1.0)
        eps = G * math.pi * a * b * cjj * s_c / (4.0 * qmu)
        kae = k_a * eps
        F = 2.0 * qmu / math.pi * (kae / (1.0 + kae * kae) + np.arctan(k_s * eps))
        spin_factor = 1.0 + 6.3 * (1.0 - np.exp(-a / np.where(valid, b, 1.0)))
        eps_s = 8.0 / 3.0 * G * b * np.sqrt(a * b) * c23 * s_c / (qmu * spin_factor)
        t = 1.0 + eps_s * eps_s
        f_ys = G * a * b * np.sqrt(a * b) * c23 * phi / (t * t)
        fx = np.where(valid, -F * xi / s_c_safe, 0.0)
        fy = np.where(valid, -(F * eta / s_c_safe + f_ys), 0.0)
    if fx.ndim == 0:
        return float(fx), float(fy)
    return fx, fy


def polach_forces(
    xi,
    eta,
    spin_per_m,
    normal_force_N: float,
    friction: float,
    a_m: float,
    b_m: float,
    shear_modulus_Pa: float,
    c11: float,
    c22: float,
    c23: float,
):
    """Polach's 1999 creep forces with spin, on the wheel [N] (VSD Suppl. 33, 728-739).

    Constant friction. Formulas, the choice of ``s_C`` in the spin gradient and its reasoning:
    module doc. Creepages (and any other argument) may be numpy arrays; they broadcast.

    Args:
        xi: longitudinal creepage [-].
        eta: lateral creepage [-].
        spin_per_m: spin creepage ``phi`` [1/m].
        normal_force_N: normal force ``Q`` [N]; ``Q <= 0`` gives zero force.
        friction: friction coefficient ``mu`` [-].
        a_m: semi-axis along the rolling direction [m].
        b_m: lateral semi-axis [m].
        shear_modulus_Pa: shear modulus ``G`` [Pa].
        c11: Kalker coefficient [-].
        c22: Kalker coefficient [-].
        c23: Kalker coefficient [-].

    Returns:
        ``(Fx, Fy)`` on the wheel in the contact frame [N] (floats for scalar input).
    """
    return _polach_numpy(
        xi, eta, spin_per_m, normal_force_N, friction, a_m, b_m, shear_modulus_Pa,
        c11, c22, c23, 1.0, 1.0, 1.0, 0.0, 0.0,
    )  # fmt: skip


def polach_2005_forces(
    xi,
    eta,
    spin_per_m,
    normal_force_N: float,
    friction: float,
    a_m: float,
    b_m: float,
    shear_modulus_Pa: float,
    c11: float,
    c22: float,
    c23: float,
    speed_m_per_s: float,
    k_a: float = POLACH_2005_PRESETS["dry"].k_a,
    k_s: float = POLACH_2005_PRESETS["dry"].k_s,
    friction_ratio_A: float = POLACH_2005_PRESETS["dry"].friction_ratio_A,
    friction_decay_B_s_per_m: float = POLACH_2005_PRESETS["dry"].friction_decay_B_s_per_m,
):
    """Polach's 2005 creep forces (falling friction, reduced adhesion), on the wheel [N].

    Wear 258 (2005) 992-1000: ``mu = mu0 ((1 - A) exp(-B w) + A)`` with the slip velocity
    ``w = s_C |V|`` and ``F = (2 Q mu/pi)(k_A eps/(1 + (k_A eps)^2) + atan(k_S eps))``; the spin
    term as in 1999 with ``mu(w)``. Defaults: the ``"dry"`` set of
    :data:`POLACH_2005_PRESETS` (see :func:`polach_2005_preset` for ``"wet"``). With
    ``k_a = k_s = 1`` and ``friction_ratio_A = 1`` (or ``B = 0``) this is :func:`polach_forces`.

    Args:
        xi: longitudinal creepage [-].
        eta: lateral creepage [-].
        spin_per_m: spin creepage ``phi`` [1/m].
        normal_force_N: normal force ``Q`` [N].
        friction: maximum friction coefficient ``mu0`` [-].
        a_m: semi-axis along the rolling direction [m].
        b_m: lateral semi-axis [m].
        shear_modulus_Pa: shear modulus ``G`` [Pa].
        c11: Kalker coefficient [-].
        c22: Kalker coefficient [-].
        c23: Kalker coefficient [-].
        speed_m_per_s: rolling (vehicle) speed ``V`` [m/s].
        k_a: reduction factor in the adhesion area [-].
        k_s: reduction factor in the slip area [-].
        friction_ratio_A: ``mu_inf / mu0`` [-].
        friction_decay_B_s_per_m: friction decay rate ``B`` [s/m].

    Returns:
        ``(Fx, Fy)`` on the wheel in the contact frame [N].
    """
    return _polach_numpy(
        xi, eta, spin_per_m, normal_force_N, friction, a_m, b_m, shear_modulus_Pa,
        c11, c22, c23, k_a, k_s, friction_ratio_A, friction_decay_B_s_per_m, speed_m_per_s,
    )  # fmt: skip


@numba.njit(cache=True)
def polach_nb(
    xi: float,
    eta: float,
    phi: float,
    Q: float,
    mu0: float,
    a: float,
    b: float,
    G: float,
    c11: float,
    c22: float,
    c23: float,
    k_a: float,
    k_s: float,
    fric_A: float,
    fric_B: float,
    V: float,
) -> tuple[float, float]:
    """Compiled Polach 2005 (and 1999) creep forces on the wheel [N]; scalars, no allocation.

    Same formulas and operation order as :func:`polach_2005_forces`. With ``k_a = k_s = 1`` and
    ``fric_A = 1`` or ``fric_B = 0`` the friction is exactly ``mu0`` and the law is exactly the
    1999 one (:func:`polach_forces`).

    Args:
        xi, eta: longitudinal and lateral creepage [-].
        phi: spin creepage [1/m].
        Q: normal force [N].
        mu0: (maximum) friction coefficient [-].
        a, b: semi-axes, rolling direction and lateral [m].
        G: shear modulus [Pa].
        c11, c22, c23: Kalker coefficients [-].
        k_a, k_s: 2005 reduction factors [-].
        fric_A: ``mu_inf / mu0`` [-].
        fric_B: friction decay rate [s/m].
        V: rolling speed [m/s].

    Returns:
        ``(Fx, Fy)``.
    """
    if not (Q > 0.0 and mu0 > 0.0 and a > 0.0 and b > 0.0):
        return 0.0, 0.0
    eta_plus = eta + phi * a
    eta_c = eta_plus if abs(eta_plus) > abs(eta) else eta
    s_c = math.sqrt(xi * xi + eta_c * eta_c)
    if not s_c > 0.0:
        return 0.0, 0.0
    s = math.sqrt(xi * xi + eta * eta)
    cjj = math.sqrt((c11 * xi / s) ** 2 + (c22 * eta / s) ** 2) if s > 0.0 else c22
    w = s_c * abs(V)
    mu = mu0 * (1.0 - (1.0 - fric_A) * (-math.expm1(-fric_B * w)))
    if not mu > 0.0:
        return 0.0, 0.0
    qmu = Q * mu
    eps = G * math.pi * a * b * cjj * s_c / (4.0 * qmu)
    kae = k_a * eps
    F = 2.0 * qmu / math.pi * (kae / (1.0 + kae * kae) + math.atan(k_s * eps))
    spin_factor = 1.0 + 6.3 * (1.0 - math.exp(-a / b))
    eps_s = 8.0 / 3.0 * G * b * math.sqrt(a * b) * c23 * s_c / (qmu * spin_factor)
    t = 1.0 + eps_s * eps_s
    f_ys = G * a * b * math.sqrt(a * b) * c23 * phi / (t * t)
    return -F * xi / s_c, -(F * eta / s_c + f_ys)
