"""The coefficients of the wear and RCF models, from ``railexu/data/wear_rcf.yaml``.

Each block of the file names its source (Jendel 2002; Lewis and Dwyer-Joyce 2004; Ekberg, Kabo
and Andersson 2002; Burstow 2004) and marks railexu's assumptions where the source gives a range
or no public value (docs/wear.md, "Models and sources").
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from railexu.errors import InputError

#: the shipped coefficients file
COEFFICIENTS_FILE = Path(__file__).resolve().parents[2] / "data" / "wear_rcf.yaml"


@dataclass(frozen=True)
class JendelMap:
    """Archard's wear coefficients by sliding velocity and pressure (Jendel, Wear 253 (2002)
    89-99): ``k1`` where ``p > pressure_ratio H``, else ``k2`` (``v < v1``), ``k3``
    (``v1 <= v <= v2``), ``k4`` (``v > v2``); ``hardness_Pa`` is ``H``."""

    pressure_ratio: float
    v1_m_per_s: float
    v2_m_per_s: float
    k1: float
    k2: float
    k3: float
    k4: float
    hardness_Pa: float


@dataclass(frozen=True)
class USFDFunction:
    """The University of Sheffield wear function for R8T wheel steel (Lewis and Dwyer-Joyce,
    Proc. IMechE J 218 (2004) 467-478): wear rate [ug/(m mm^2)] of ``T gamma / A`` [N/mm^2]."""

    boundary_1_N_per_mm2: float
    boundary_2_N_per_mm2: float
    slope_1: float
    severe: float
    slope_3: float
    offset_3: float
    density_kg_per_m3: float


@dataclass(frozen=True)
class FISurfParameters:
    """Ekberg's surface fatigue index (FFEMS 25 (2002) 899-909): the shear yield ``k`` [Pa]."""

    shear_yield_Pa: float


@dataclass(frozen=True)
class WLRMFunction:
    """Burstow's Whole Life Rail Model damage function of ``T gamma`` [N] (AEATR-ES-2004-880):
    zero below ``threshold_N``, linear to ``peak_damage`` at ``peak_N``, linear to zero at
    ``zero_N`` and zero beyond (wear removes the cracks)."""

    threshold_N: float
    peak_N: float
    zero_N: float
    peak_damage: float


@dataclass(frozen=True)
class Coefficients:
    """All blocks of the coefficients file."""

    archard_jendel: JendelMap
    energy_usfd: USFDFunction
    fi_surf: FISurfParameters
    wlrm: WLRMFunction
    path: str


def _block(data: dict, key: str, cls, path: Path):
    block = data.get(key)
    if not isinstance(block, dict):
        raise InputError("missing block (a mapping expected)", source=str(path), key=key)
    values = {}
    for name in cls.__dataclass_fields__:
        value = block.get(name)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError("expected a number", source=str(path), key=f"{key}.{name}")
        if not (math.isfinite(value) and value >= 0.0):
            raise InputError(
                f"{value!r}: expected a finite number >= 0", source=str(path), key=f"{key}.{name}"
            )
        values[name] = float(value)
    return cls(**values)


@lru_cache(maxsize=4)
def load_coefficients(path: str | None = None) -> Coefficients:
    """The coefficients of ``path`` (default the shipped :data:`COEFFICIENTS_FILE`).

    Raises:
        InputError: a missing block or key, a value that is not a finite number >= 0, or
            boundaries out of order (naming the file and the key).
    """
    import yaml

    p = Path(path) if path else COEFFICIENTS_FILE
    try:
        data = yaml.safe_load(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"cannot read the file ({exc.strerror})", source=str(p)) from exc
    except yaml.YAMLError as exc:
        raise InputError(f"not valid YAML ({exc})", source=str(p)) from exc
    if not isinstance(data, dict):
        raise InputError("expected a mapping of blocks", source=str(p))
    coef = Coefficients(
        archard_jendel=_block(data, "archard_jendel", JendelMap, p),
        energy_usfd=_block(data, "energy_usfd", USFDFunction, p),
        fi_surf=_block(data, "fi_surf", FISurfParameters, p),
        wlrm=_block(data, "wlrm", WLRMFunction, p),
        path=str(p),
    )
    j, u, w = coef.archard_jendel, coef.energy_usfd, coef.wlrm
    for ok, key, what in (
        (j.v1_m_per_s < j.v2_m_per_s, "archard_jendel.v2_m_per_s", "v1 < v2"),
        (j.hardness_Pa > 0.0, "archard_jendel.hardness_Pa", "a hardness > 0"),
        (u.boundary_1_N_per_mm2 < u.boundary_2_N_per_mm2, "energy_usfd.boundary_2_N_per_mm2",
         "boundary_1 < boundary_2"),
        (u.density_kg_per_m3 > 0.0, "energy_usfd.density_kg_per_m3", "a density > 0"),
        (w.threshold_N < w.peak_N < w.zero_N, "wlrm.peak_N", "threshold < peak < zero"),
    ):  # fmt: skip
        if not ok:
            raise InputError(f"expected {what}", source=str(p), key=key)
    return coef
