"""Local wear laws, chosen by name like the creep laws (docs/wear.md).

=====  =================  ======================================================================
code   name               local wear rate ``w`` (volume removed per unit patch area per metre
                          rolled, [m^3/(m^2 m)] = [-])
=====  =================  ======================================================================
0      ``archard_jendel`` Archard: ``w = k(p, v) p |s| / H`` with Jendel's wear map ``k`` by
                          pressure ``p`` and sliding velocity ``v = V |s|`` (Jendel, Wear 253
                          (2002) 89-99; ``s`` the slip per metre rolled)
1      ``energy_usfd``    University of Sheffield, R8T: ``w = K(T gamma / A) 1e-3 / rho`` with
                          ``K`` [ug/(m mm^2)] of the local frictional power density
                          ``|q| |s|`` [N/mm^2] (Lewis and Dwyer-Joyce, Proc. IMechE J 218 (2004)
                          467-478; Braghin et al., Wear 261 (2006) 1253-1264)
=====  =================  ======================================================================

Both are applied cell by cell over FASTSIM's patch (:mod:`.patch`); the vectorised functions
here are the reference the compiled patch code is tested against. The coefficients are in
``railexu/data/wear_rcf.yaml`` (:mod:`.coefficients`).
"""

from __future__ import annotations

import numpy as np

from railexu.contact.wear.coefficients import Coefficients, JendelMap, USFDFunction
from railexu.errors import InputError, did_you_mean

#: the wear laws by name and their codes in the compiled patch function
WEAR_LAWS = {"archard_jendel": 0, "energy_usfd": 1}
#: the default law
DEFAULT_WEAR_LAW = "archard_jendel"

#: length of the coefficient vector the compiled code reads
N_LAW_PARAMS = 8


class UnknownWearLawError(InputError):
    """A wear law name that railexu does not know."""


def wear_law_code(name: str) -> int:
    """The code of the wear law ``name`` (case-insensitive; ``-`` and spaces as ``_``).

    Raises:
        UnknownWearLawError: naming the law, with did-you-mean and the known names.
    """
    key = str(name).strip().lower().replace("-", "_").replace(" ", "_")
    if key not in WEAR_LAWS:
        raise UnknownWearLawError(
            f"unknown wear law {name!r}.{did_you_mean(key, WEAR_LAWS)} Known: "
            f"{', '.join(WEAR_LAWS)}",
            key="wear_law",
        )
    return WEAR_LAWS[key]


def jendel_k(pressure_Pa, sliding_velocity_m_per_s, m: JendelMap) -> np.ndarray:
    """Jendel's wear coefficient ``k`` [-] at pressure [Pa] and sliding velocity [m/s]."""
    p = np.asarray(pressure_Pa, dtype=float)
    v = np.asarray(sliding_velocity_m_per_s, dtype=float)
    k = np.where(v < m.v1_m_per_s, m.k2, np.where(v <= m.v2_m_per_s, m.k3, m.k4))
    return np.where(p > m.pressure_ratio * m.hardness_Pa, m.k1, k)


def usfd_rate(tgamma_per_area_N_per_mm2, f: USFDFunction) -> np.ndarray:
    """The USFD R8T wear rate [ug/(m mm^2)] at ``T gamma / A`` [N/mm^2] (published regimes:
    mild, severe, catastrophic; module doc)."""
    x = np.asarray(tgamma_per_area_N_per_mm2, dtype=float)
    mild = f.slope_1 * x
    catastrophic = f.slope_3 * x - f.offset_3
    rate = np.where(
        x < f.boundary_1_N_per_mm2,
        mild,
        np.where(x <= f.boundary_2_N_per_mm2, f.severe, catastrophic),
    )
    return np.maximum(rate, 0.0)


def usfd_regime(tgamma_per_area_N_per_mm2, f: USFDFunction) -> np.ndarray:
    """The regime name (``mild``, ``severe``, ``catastrophic``) at ``T gamma / A`` [N/mm^2]."""
    x = np.asarray(tgamma_per_area_N_per_mm2, dtype=float)
    return np.where(
        x < f.boundary_1_N_per_mm2,
        "mild",
        np.where(x <= f.boundary_2_N_per_mm2, "severe", "catastrophic"),
    )


def local_wear_rate(
    law: str,
    pressure_Pa,
    traction_Pa,
    slip,
    speed_m_per_s: float,
    coef: Coefficients,
) -> np.ndarray:
    """Local wear rate ``w`` [-] (volume per patch area per metre rolled; module doc).

    Args:
        law: a name of :data:`WEAR_LAWS`.
        pressure_Pa: normal pressure ``p``.
        traction_Pa: magnitude of the tangential traction ``|q|``.
        slip: magnitude of the local slip per metre rolled ``|s|`` [-].
        speed_m_per_s: rolling speed ``V`` (sliding velocity ``V |s|``).
        coef: the coefficients (:func:`~.coefficients.load_coefficients`).
    """
    code = wear_law_code(law)
    p = np.asarray(pressure_Pa, dtype=float)
    s = np.abs(np.asarray(slip, dtype=float))
    if code == 0:
        m = coef.archard_jendel
        return jendel_k(p, speed_m_per_s * s, m) * p * s / m.hardness_Pa
    f = coef.energy_usfd
    power = np.abs(np.asarray(traction_Pa, dtype=float)) * s * 1e-6  # N/mm^2
    return usfd_rate(power, f) * 1e-3 / f.density_kg_per_m3


def law_vector(law: str, coef: Coefficients) -> np.ndarray:
    """The coefficient vector of ``law`` that :func:`~.patch.patch_wear_nb` reads
    (:data:`N_LAW_PARAMS` values)."""
    code = wear_law_code(law)
    v = np.zeros(N_LAW_PARAMS)
    if code == 0:
        m = coef.archard_jendel
        v[:] = (m.pressure_ratio * m.hardness_Pa, m.v1_m_per_s, m.v2_m_per_s, m.k1, m.k2, m.k3,
                m.k4, 1.0 / m.hardness_Pa)  # fmt: skip
    else:
        f = coef.energy_usfd
        v[:7] = (f.boundary_1_N_per_mm2, f.boundary_2_N_per_mm2, f.slope_1, f.severe, f.slope_3,
                 f.offset_3, 1e-3 / f.density_kg_per_m3)  # fmt: skip
    return v
