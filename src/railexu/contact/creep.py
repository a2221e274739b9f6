"""Registry of creep-force laws, selected by name (FLORIS-style), and their dispatchers.

=========  ==================  ===============================================================
code       name                law
=========  ==================  ===============================================================
0          ``kalker_linear``   Kalker's linear theory (no saturation), :mod:`.kalker`
1          ``polach``          Polach 1999 with spin, constant friction, :mod:`.polach`
2          ``polach_2005``     Polach 2005: falling friction, reduction factors ``k_A, k_S``
3          ``fastsim``         Kalker's FASTSIM with spin, Hertz traction bound, :mod:`.fastsim`
4          ``polach_fastsim``  default: Polach 1999 where spin is small, FASTSIM where spin
                               saturates the patch, blended smoothly (below)
=========  ==================  ===============================================================

``polach_fastsim``, the default (a per-contact-point choice by spin)
--------------------------------------------------------------------
Polach's spin term is an empirical fit that is good while spin alone would not saturate the patch
but fails when it does: on CONTACT's ``conformal`` case (Vollebregt 2018; a flange-like contact
with large spin near saturation) it gives Fx 13 % and Fy 37 % of mu Q below the exact half-space
result, where FASTSIM is within 5 %. Which law applies is decided per contact point by the
*spin saturation ratio*, Kalker's linear spin force over the friction limit,

    ``r = G (ab)^(3/2) c23 |phi| / (mu Q)``

(0 without spin; 1.0 on CONTACT's ``fastsim`` spin case, 2.7 on ``conformal``; on S1002 / UIC60
1:40 most tread points stay below 0.3, while flange contacts and tread points near the flange root
exceed it: 36 % of the loaded points of ``benchmarks/contact.py``'s states, every flange contact of
the Manchester benchmark). Below ``r = SPIN_BLEND_LOW`` the law is Polach's (cheap, closed-form);
above ``SPIN_BLEND_HIGH`` FASTSIM's (``BLEND_FASTSIM_CELLS`` = 10 x 10 cells); between, the forces
are blended with the weight ``w = 3 t^2 - 2 t^3``, ``t = (r - low)/(high - low)``, so the force is
a continuous, once differentiable function of the creepages (Newton's method needs that). Without
spin both laws give the same creep curve (FASTSIM's elliptic bound makes Polach's assumptions, 1.7
% apart), so the blend only matters where spin is large.

All laws return the tangential force **on the wheel** in the contact frame ``(t_x, t_y)`` [N]
(docs/conventions.md) and tend to Kalker's linear theory for small creepage (Polach 2005 to the
linear theory scaled by ``(k_A + k_S)/2``).

:func:`creep_forces` is the Python dispatcher; :func:`creep_forces_nb` the compiled one the
contact kernel calls with an integer code from :func:`creep_model_code`. In both, FASTSIM uses
``FASTSIM_KERNEL_STRIPS x FASTSIM_KERNEL_POINTS`` cells (20 x 20: linear ``xi``/``eta`` exact,
saturation 0.3 % above ``mu Q``, within 1.7 % of Polach's curve without spin; see
:mod:`.fastsim`), so the two dispatchers agree for every law.
"""

from __future__ import annotations

import math

import numba

from railexu.contact.fastsim import fastsim3_nb, fastsim_nb
from railexu.contact.kalker import kalker_linear_nb
from railexu.contact.parameters import (
    CREEP_MODELS,
    UnknownCreepModelError,
    creep_model_code,
    creep_model_name,
)
from railexu.contact.polach import (
    POLACH_2005_PRESETS,
    Polach2005Parameters,
    polach_2005_preset,
    polach_nb,
)
from railexu.runtime.compiled_cache import announce_compilation

announce_compilation()  # one line when numba compiles (the first run: about 2 minutes)

__all__ = [
    "CREEP_MODELS",
    "FASTSIM_KERNEL_STRIPS",
    "FASTSIM_KERNEL_POINTS",
    "BLEND_FASTSIM_CELLS",
    "SPIN_BLEND_HIGH",
    "SPIN_BLEND_LOW",
    "UnknownCreepModelError",
    "creep_model_code",
    "creep_model_name",
    "creep_forces",
    "creep_forces_nb",
    "spin_blend_weight",
    "spin_moment",
]

#: FASTSIM discretisation used by both dispatchers (strips across, cells along the ellipse).
FASTSIM_KERNEL_STRIPS = 20
FASTSIM_KERNEL_POINTS = 20


#: FASTSIM discretisation inside ``polach_fastsim`` (strips, cells): 10 x 10 costs a quarter of
#: 20 x 20; measured on CONTACT's cases it changes the forces by < 2 % of mu Q (``conformal``:
#: Fx -1.8, Fy -3.1 % of mu Q against exact; ``fastsim`` spin: +0.6 %) and full slip reaches
#: 1.0 % above mu Q (20 x 20: 0.34 %).
BLEND_FASTSIM_CELLS = 10

#: Spin saturation ratio below which ``polach_fastsim`` is Polach's law alone (module doc).
SPIN_BLEND_LOW = 0.3
#: Spin saturation ratio above which ``polach_fastsim`` is FASTSIM alone (module doc).
SPIN_BLEND_HIGH = 0.6


def _resolve_2005(params: Polach2005Parameters | str | None) -> Polach2005Parameters:
    if params is None:
        return POLACH_2005_PRESETS["dry"]
    if isinstance(params, str):
        return polach_2005_preset(params)
    if isinstance(params, Polach2005Parameters):
        return params
    raise TypeError("polach_2005_params must be Polach2005Parameters, a preset name or None")


def creep_forces(
    model: str | int,
    xi: float,
    eta: float,
    phi: float,
    Q: float,
    a: float,
    b: float,
    G: float,
    c11: float,
    c22: float,
    c23: float,
    friction: float,
    speed_m_per_s: float,
    polach_2005_params: Polach2005Parameters | str | None = None,
) -> tuple[float, float]:
    """Creep forces on the wheel [N] by the named law (Python dispatcher).

    Args:
        model: a name from :data:`CREEP_MODELS` (or its integer code).
        xi: longitudinal creepage [-].
        eta: lateral creepage [-].
        phi: spin creepage [1/m].
        Q: normal force [N].
        a: semi-axis along the rolling direction [m].
        b: lateral semi-axis [m].
        G: shear modulus [Pa].
        c11: Kalker coefficient [-].
        c22: Kalker coefficient [-].
        c23: Kalker coefficient [-].
        friction: friction coefficient (``mu0``, the maximum, for ``polach_2005``) [-]; not used
            by ``kalker_linear``.
        speed_m_per_s: rolling speed [m/s]; used by ``polach_2005`` only.
        polach_2005_params: :class:`~railexu.contact.polach.Polach2005Parameters`, a preset name
            (``"dry"``, ``"wet"``) or ``None`` (``"dry"``); used by ``polach_2005`` only. Its
            ``mu0`` field is ignored in favour of ``friction``.

    Returns:
        ``(Fx, Fy)`` on the wheel in the contact frame [N].
    """
    code = creep_model_code(creep_model_name(model) if isinstance(model, int) else model)
    if code == 2:
        p = _resolve_2005(polach_2005_params)
        k_a, k_s, fric_a, fric_b = p.k_a, p.k_s, p.friction_ratio_A, p.friction_decay_B_s_per_m
    else:
        k_a, k_s, fric_a, fric_b = 1.0, 1.0, 1.0, 0.0
    fx, fy = creep_forces_nb(
        code, float(xi), float(eta), float(phi), float(Q), float(a), float(b), float(G),
        float(c11), float(c22), float(c23), float(friction), k_a, k_s, fric_a, fric_b,
        float(speed_m_per_s),
    )  # fmt: skip
    return float(fx), float(fy)


@numba.njit(cache=True)
def creep_forces_nb(
    model_code: int,
    xi: float,
    eta: float,
    phi: float,
    Q: float,
    a: float,
    b: float,
    G: float,
    c11: float,
    c22: float,
    c23: float,
    mu0: float,
    k_a: float,
    k_s: float,
    fric_A: float,
    fric_B: float,
    V: float,
) -> tuple[float, float]:
    """Compiled dispatcher: creep forces on the wheel [N]; scalars, allocation-free.

    ``model_code`` from :func:`creep_model_code` (4, ``polach_fastsim``: module doc).
    ``k_a, k_s, fric_A, fric_B, V`` are used by
    ``polach_2005`` (code 2) only; ``polach`` (1) uses ``mu0`` with 1999's law, ``fastsim`` (3)
    uses ``mu0`` and ``FASTSIM_KERNEL_STRIPS x FASTSIM_KERNEL_POINTS`` cells, ``kalker_linear``
    (0) uses neither friction nor speed. Raises ``ValueError`` for an unknown code.

    Returns:
        ``(Fx, Fy)`` on the wheel in the contact frame [N].
    """
    if model_code == 1:
        return polach_nb(xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23, 1.0, 1.0, 1.0, 0.0, V)
    if model_code == 2:
        return polach_nb(xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23, k_a, k_s, fric_A, fric_B, V)
    if model_code == 0:
        return kalker_linear_nb(xi, eta, phi, a, b, G, c11, c22, c23)
    if model_code == 3:
        return fastsim_nb(
            xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23,
            FASTSIM_KERNEL_STRIPS, FASTSIM_KERNEL_POINTS,
        )  # fmt: skip
    if model_code == 4:
        w = spin_blend_weight(phi, Q, mu0, a, b, G, c23)
        if w <= 0.0:
            return polach_nb(xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23, 1.0, 1.0, 1.0, 0.0, V)
        fx_f, fy_f = fastsim_nb(
            xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23, BLEND_FASTSIM_CELLS, BLEND_FASTSIM_CELLS
        )
        if w >= 1.0:
            return fx_f, fy_f
        fx_p, fy_p = polach_nb(xi, eta, phi, Q, mu0, a, b, G, c11, c22, c23, 1.0, 1.0, 1.0, 0.0, V)
        return fx_p + w * (fx_f - fx_p), fy_p + w * (fy_f - fy_p)
    raise ValueError("unknown creep model code (valid: 0..4)")


@numba.njit(cache=True)
def spin_blend_weight(
    phi: float, Q: float, mu: float, a: float, b: float, G: float, c23: float
) -> float:
    """Weight of FASTSIM in ``polach_fastsim`` (0: Polach alone, 1: FASTSIM alone) [-].

    From the spin saturation ratio ``r = G (ab)^(3/2) c23 |phi| / (mu Q)`` with the smooth step
    ``3 t^2 - 2 t^3`` between :data:`SPIN_BLEND_LOW` and :data:`SPIN_BLEND_HIGH` (module doc).
    """
    if not (Q > 0.0 and mu > 0.0 and a > 0.0 and b > 0.0):
        return 0.0
    ab = a * b
    r = G * ab * math.sqrt(ab) * c23 * abs(phi) / (mu * Q)
    t = (r - SPIN_BLEND_LOW) / (SPIN_BLEND_HIGH - SPIN_BLEND_LOW)
    if t <= 0.0:
        return 0.0
    if t >= 1.0:
        return 1.0
    return t * t * (3.0 - 2.0 * t)


def spin_moment(
    model: str | int,
    xi: float,
    eta: float,
    phi: float,
    Q: float,
    a: float,
    b: float,
    G: float,
    c11: float,
    c22: float,
    c23: float,
    friction: float,
) -> float:
    """Spin moment on the wheel about the contact normal [N m] for a creep law.

    Polach's method gives no moment, so for every saturating law (``polach``, ``polach_2005``,
    ``fastsim``, ``polach_fastsim``) this is FASTSIM's moment of the tractions,
    ``int (x p_y - y p_x) dA`` with the same flexibilities and traction bound
    (:func:`railexu.contact.fastsim.fastsim_moment`). ``kalker_linear`` gives the moment of
    the same simplified theory without a traction bound (friction taken as infinite). The
    moment is reported, not fed back into the wheelset's equations (docs/contact-model.md).

    Args: as :func:`creep_forces` (``friction`` is the friction coefficient [-]).

    Returns:
        ``Mz`` on the wheel [N m].
    """
    code = creep_model_code(creep_model_name(model) if isinstance(model, int) else model)
    mu = 1.0e12 if code == 0 else float(friction)
    _, _, mz = fastsim3_nb(
        float(xi), float(eta), float(phi), float(Q), mu, float(a), float(b), float(G),
        float(c11), float(c22), float(c23), FASTSIM_KERNEL_STRIPS, FASTSIM_KERNEL_POINTS,
    )  # fmt: skip
    return float(mz)
