"""Contact parameters and the names of the contact laws, without the compiled layer.

Vehicle files build a :class:`ContactParameters` while they are read; this module therefore
imports neither numba nor the compiled kernel (``railexu.contact.kernel`` reads the ``P_*``
indices of the parameter vector from here). The old import paths
(``railexu.contact.evaluation.ContactParameters``, ``railexu.contact.creep.creep_model_code``)
keep working by re-export.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railexu.errors import InputError, did_you_mean

__all__ = [
    "CREEP_MODELS",
    "DAMPING_MODELS",
    "NORMAL_MODELS",
    "ContactParameterError",
    "ContactParameters",
    "UnknownCreepModelError",
    "creep_model_code",
    "creep_model_name",
]

#: Registered creep laws; the index is the integer code the compiled dispatcher reads.
#: ``polach_fastsim`` (the default) is Polach's law where spin is small and FASTSIM where it
#: saturates the patch (:mod:`railexu.contact.creep`).
CREEP_MODELS: tuple[str, ...] = (
    "kalker_linear",
    "polach",
    "polach_2005",
    "fastsim",
    "polach_fastsim",
)

#: Damping laws of the normal force, selected by name.
DAMPING_MODELS = {
    # seed eq. (2): N = K delta^1.5 + D delta_dot, D in N s/m
    "linear": 0,
    # Hunt-Crossley: N = K delta^1.5 (1 + chi delta_dot), chi in s/m
    "hunt_crossley": 1,
}

#: Normal contact models, selected by name (only Hertz is implemented).
NORMAL_MODELS = ("hertz",)

# Entries of the parameter vector the compiled kernel reads.
P_ESTAR = 0  # effective modulus E* [Pa]
P_SHEAR = 1  # combined shear modulus G [Pa]
P_MU = 2  # friction coefficient (mu0 for Polach 2005)
P_KA = 3  # Polach 2005 reduction factors
P_KS = 4
P_FRIC_A = 5  # Polach 2005 friction ratio mu_inf / mu0
P_FRIC_B = 6  # Polach 2005 exponential friction decrease [s/m]
P_SPEED = 7  # rolling (forward) speed V [m/s]
P_DAMP_MODEL = 8  # 0: N = K d^1.5 + D d_dot ; 1: Hunt-Crossley N = K d^1.5 (1 + chi d_dot)
P_DAMP = 9  # D [N s/m] or chi [s/m]
P_CREEP = 10  # creep model code (railexu.contact.creep)
P_SCAN = 11  # scan step along the wheel profile [m]
P_TANGENTIAL = 12  # 1.0: compute creep forces, 0.0: normal forces only
N_PARAMS = 13


class ContactParameterError(InputError):
    """Invalid contact parameters."""


class UnknownCreepModelError(ContactParameterError):
    """Raised for a creep-law name (or code) that is not registered."""


def _normalise(name: str) -> str:
    return name.strip().lower().replace("-", "_").replace(" ", "_")


def creep_model_code(name: str) -> int:
    """Integer code of a creep law for the compiled dispatcher.

    Names are case-insensitive; ``-`` and blanks count as ``_``.

    Args:
        name: one of :data:`CREEP_MODELS`.

    Returns:
        0 ``kalker_linear``, 1 ``polach``, 2 ``polach_2005``, 3 ``fastsim``,
        4 ``polach_fastsim``.

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
    hint = did_you_mean(key, CREEP_MODELS, cutoff=0.5)
    hint = hint if hint.startswith(" Did") else ""
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


def _choice(kind: str, name: str, valid) -> str:
    if name in valid:
        return name
    raise ContactParameterError(
        f"unknown {kind} {name!r}.{did_you_mean(name, sorted(valid))} "
        f"Valid: {', '.join(sorted(valid))}"
    )


@dataclass(frozen=True)
class ContactParameters:
    """Material, friction, damping and creep-law settings of the wheel-rail contact.

    Attributes:
        shear_modulus_Pa: combined shear modulus G of wheel and rail steel [Pa].
        poisson: Poisson's ratio of both bodies [-].
        friction: friction coefficient mu (mu0 of Polach 2005) [-].
        creep_model: ``"polach_fastsim"`` (default: Polach 1999 where spin is small, FASTSIM
            where spin saturates the patch, blended smoothly; docs/contact-model.md),
            ``"polach"`` (1999, with spin), ``"polach_2005"`` (falling friction),
            ``"kalker_linear"`` or ``"fastsim"``.
        polach_2005: ``(k_a, k_s, A, B)`` of Polach 2005 (B in s/m); dry rail by default
            (Polach 2005, Table 2).
        damping_model: ``"hunt_crossley"`` (default): the seed's eq. (2) with the hysteresis
            damping ``D = chi K delta^1.5``, i.e. ``N = K d^1.5 (1 + chi d_dot)``, which starts
            from zero at first touch and dissipates the energy of the impact; or ``"linear"``,
            ``N = K d^1.5 + D d_dot`` with a constant D, which jumps to ``D d_dot`` at first
            touch (a discontinuity Newton's method dislikes).
        damping: chi [s/m] for ``hunt_crossley`` (default 3 s/m: about 10 % of critical damping
            for a wheel of ~2 t on its Hertz contact at 100 kN), D [N s/m] for ``linear``.
        scan_step_m: step of the coarse scan for contact points along the wheel profile [m].
        curvature_smoothing_m: width (standard deviation of a Gaussian) over which the profiles'
            lateral curvature is averaged for Hertz's ellipse [m]. A contact patch is several mm
            wide on the tread (0.4 mm at a flange), so the curvature at one point, which jumps
            where two arcs of a profile meet, would make the normal stiffness jump as the point
            crosses the junction; averaged over 0.5 mm it varies continuously and the flange's
            narrow ellipse is kept (the Manchester comparison holds from 0.3 to 0.5 mm). The
            geometry itself (gap, contact angle) is not smoothed.
        tangential: compute creep forces (False: normal forces only).
        normal_model: normal contact model; only ``"hertz"`` is implemented.
    """

    shear_modulus_Pa: float = 82.0e9
    poisson: float = 0.28
    friction: float = 0.3
    creep_model: str = "polach_fastsim"
    polach_2005: tuple[float, float, float, float] = (1.0, 0.4, 0.4, 0.6)
    damping_model: str = "hunt_crossley"
    damping: float = 3.0
    scan_step_m: float = 1.0e-3
    curvature_smoothing_m: float = 5.0e-4
    tangential: bool = True
    normal_model: str = "hertz"

    def __post_init__(self) -> None:
        if not self.shear_modulus_Pa > 0:
            raise ContactParameterError(
                f"shear modulus must be > 0 Pa, got {self.shear_modulus_Pa}"
            )
        if not 0.0 <= self.poisson < 0.5:
            raise ContactParameterError(f"Poisson's ratio must be in [0, 0.5), got {self.poisson}")
        if not self.friction >= 0.0:
            raise ContactParameterError(f"friction must be >= 0, got {self.friction}")
        if not self.damping >= 0.0:
            raise ContactParameterError(f"contact damping must be >= 0, got {self.damping}")
        if not 0.0 <= self.curvature_smoothing_m <= 5.0e-3:
            raise ContactParameterError(
                f"curvature smoothing must be within 0 .. 5 mm, got {self.curvature_smoothing_m} m"
            )
        if not 1.0e-5 <= self.scan_step_m <= 5.0e-3:
            raise ContactParameterError(
                f"scan step must be within 0.01 .. 5 mm, got {self.scan_step_m} m"
            )
        _choice("damping model", self.damping_model, DAMPING_MODELS)
        _choice("normal contact model", self.normal_model, NORMAL_MODELS)
        creep_model_code(self.creep_model)  # raises with did-you-mean

    @property
    def young_modulus_Pa(self) -> float:
        """Young's modulus E = 2 G (1 + nu) [Pa]."""
        return 2.0 * self.shear_modulus_Pa * (1.0 + self.poisson)

    @property
    def effective_modulus_Pa(self) -> float:
        """Hertz's E* for two bodies of the same steel: E / (2 (1 - nu^2)) = G / (1 - nu) [Pa]."""
        return self.shear_modulus_Pa / (1.0 - self.poisson)

    def kernel_vector(self, speed_m_per_s: float) -> np.ndarray:
        """The parameter vector the compiled kernel reads (``P_*`` indices)."""
        if not speed_m_per_s > 0.0:
            raise ContactParameterError(f"rolling speed must be > 0 m/s, got {speed_m_per_s}")
        p = np.zeros(N_PARAMS)
        p[P_ESTAR] = self.effective_modulus_Pa
        p[P_SHEAR] = self.shear_modulus_Pa
        p[P_MU] = self.friction
        k_a, k_s, fric_a, fric_b = self.polach_2005
        code = creep_model_code(self.creep_model)
        if CREEP_MODELS[code] == "polach_2005":
            p[P_KA], p[P_KS], p[P_FRIC_A], p[P_FRIC_B] = k_a, k_s, fric_a, fric_b
        else:
            p[P_KA], p[P_KS], p[P_FRIC_A], p[P_FRIC_B] = 1.0, 1.0, 1.0, 0.0
        p[P_SPEED] = speed_m_per_s
        p[P_DAMP_MODEL] = DAMPING_MODELS[self.damping_model]
        p[P_DAMP] = self.damping
        p[P_CREEP] = code
        p[P_SCAN] = self.scan_step_m
        p[P_TANGENTIAL] = 1.0 if self.tangential else 0.0
        return p
