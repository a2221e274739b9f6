"""Names, constants and the error type shared by the irregularity modules."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from railexu.errors import InputError, did_you_mean

FloatArray = NDArray[np.float64]

#: The four irregularity signals, in the order used for random phases and stacked arrays.
COMPONENTS: tuple[str, ...] = ("lateral", "vertical", "cross_level", "gauge")

#: Distance between the nominal contact points of the two rails, ``2 b`` (m).
RAIL_DISTANCE_M = 1.5

# German (ERRI B176) spectrum constants, ERRI B176 (1989), docs/theory.md.
GERMAN_OMEGA_C = 0.8246  # rad/m
GERMAN_OMEGA_R = 0.0206  # rad/m
GERMAN_OMEGA_S = 0.4380  # rad/m
GERMAN_HALF_RAIL_DISTANCE_M = 0.75  # b, m

# US FRA vertical spectrum constants, ERRI B176 (1989), docs/theory.md.
FRA_K = 0.25
FRA_OMEGA_C = 0.8245  # rad/m
FRA_A_V_CM2 = (1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339)  # cm^2 rad/m, classes 1..6
FRA_VALID_WAVELENGTH_M = (1.524, 304.8)

_FADE_DEFAULT_M = 10.0
_CZT_BLOCK = 1 << 15
_UNIFORM_RTOL = 1e-6

#: Column names (without unit suffix) of irregularity CSV files.
_CSV_BASES = ("distance", "lateral", "vertical", "cross_level", "gauge")


class IrregularityError(InputError):
    """Invalid irregularity data or arguments (bad CSV file, unknown name, bad grid)."""


def _did_you_mean(name: str, choices: Iterable[str]) -> str:
    hint = did_you_mean(name, list(choices), cutoff=0.5)
    return hint if hint.startswith(" Did you mean") else ""


def _check_component(component: str) -> str:
    if component not in COMPONENTS:
        raise IrregularityError(
            f"unknown irregularity component {component!r}; expected one of "
            f"{', '.join(COMPONENTS)}.{_did_you_mean(str(component), COMPONENTS)}"
        )
    return component
