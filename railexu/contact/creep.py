"""Registry of creep-force laws, selected by name (FLORIS-style), and their dispatchers.

=========  ==================  ===============================================================
code       name                law
=========  ==================  ===============================================================
0          ``kalker_linear``   Kalker's linear theory (no saturation), :mod:`.kalker`
1          ``polach``          Polach 1999 with spin, constant friction, :mod:`.polach`
2          ``polach_2005``     Polach 2005: falling friction, reduction factors ``k_A, k_S``
3          ``fastsim``         Kalker's FASTSIM with spin, Hertz traction bound, :mod:`.fastsim`
=========  ==================  ===============================================================

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

import difflib

import numba

from ..errors import InputError
from .fastsim import fastsim_nb
from .kalker import kalker_linear_nb
from .polach import POLACH_2005_PRESETS, Polach2005Parameters, polach_2005_preset, polach_nb

__all__ = [
    "CREEP_MODELS",
    "FASTSIM_KERNEL_STRIPS",
    "FASTSIM_KERNEL_POINTS",
    "UnknownCreepModelError",
    "creep_model_code",
    "creep_model_name",
    "creep_forces",
    "creep_forces_nb",
]

#: Registered creep laws; the index is the code used by :func:`creep_forces_nb`.
CREEP_MODELS: tuple[str, ...] = ("kalker_linear", "polach", "polach_2005", "fastsim")

#: FASTSIM discretisation used by both dispatchers (strips across, cells along the ellipse).
FASTSIM_KERNEL_STRIPS = 20
FASTSIM_KERNEL_POINTS = 20


class UnknownCreepModelError(InputError):
    """Raised for a creep-law name (or code) that is not registered."""


def _normalise(name: str) -> str:
    return name.strip().lower().replace("-", "_").replace(" ", "_")


def creep_model_code(name: str) -> int:
    """Integer code (0..3) of a creep law for :func:`creep_forces_nb`.

    Names are case-insensitive; ``-`` and blanks count as ``_``.

    Args:
        name: one of :data:`CREEP_MODELS`.

    Returns:
        0 ``kalker_linear``, 1 ``polach``, 2 ``polach_2005``, 3 ``fastsim``.

    Raises:
        UnknownCreepModelError: for an unknown name, with a did-you-mean suggestion and the list
            of valid names.
    """
    if not isinstance(name, str):
        raise UnknownCreepModelError(
            f"creep model must be given by name, got {name!r}; valid: {', '.join(CREEP_MODELS)}"
        )
    key = _normalise(name)
    if key in CREEP_MODELS:
        return CREEP_MODELS.index(key)
    close = difflib.get_close_matches(key, CREEP_MODELS, n=1, cutoff=0.5)
    hint = f" Did you mean {close[0]!r}?" if close else ""
    raise UnknownCreepModelError(
        f"unknown creep model {name!r}.{hint} Valid creep models: {', '.join(CREEP_MODELS)}."
    )


def creep_model_name(code: int) -> str:
    """Inverse of :func:`creep_model_code`."""
    if isinstance(code, bool) or not isinstance(code, int) or not 0 <= code < len(CREEP_MODELS):
        raise UnknownCreepModelError(
            f"unknown creep model code {code!r}; valid codes 0..{len(CREEP_MODELS) - 1} "
            f"({', '.join(CREEP_MODELS)})"
        )
    return CREEP_MODELS[code]


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

    ``model_code`` from :func:`creep_model_code`. ``k_a, k_s, fric_A, fric_B, V`` are used by
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
    raise ValueError("unknown creep model code (valid: 0..3)")
