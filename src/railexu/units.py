"""Quantities with units in input files: ``"12 mm"``, ``"80 t"``, ``"1220 kN/m"``, ``"4 kN s/m"``.

Everything inside railexu is SI. A file may give a plain number (taken as SI in the field's
documented unit) or a string ``"<number> <unit>"``; :func:`to_si` converts it and checks that the
unit has the dimension the field expects. Units are products of the symbols below with optional
integer exponents (``m^2``, ``s^-1``), joined by spaces or ``*``, with at most one ``/``:
``kN s/m``, ``kg m^2``, ``N m/rad``, ``km/h``.
"""

from __future__ import annotations

import math
import re

from railexu.errors import InputError

# symbol -> (factor to SI, dimension exponents (kg, m, s))
_BASE: dict[str, tuple[float, tuple[int, int, int]]] = {
    "kg": (1.0, (1, 0, 0)),
    "g": (1e-3, (1, 0, 0)),
    "t": (1e3, (1, 0, 0)),
    "m": (1.0, (0, 1, 0)),
    "mm": (1e-3, (0, 1, 0)),
    "cm": (1e-2, (0, 1, 0)),
    "km": (1e3, (0, 1, 0)),
    "um": (1e-6, (0, 1, 0)),
    "s": (1.0, (0, 0, 1)),
    "ms": (1e-3, (0, 0, 1)),
    "min": (60.0, (0, 0, 1)),
    "h": (3600.0, (0, 0, 1)),
    "N": (1.0, (1, 1, -2)),
    "kN": (1e3, (1, 1, -2)),
    "MN": (1e6, (1, 1, -2)),
    "Pa": (1.0, (1, -1, -2)),
    "kPa": (1e3, (1, -1, -2)),
    "MPa": (1e6, (1, -1, -2)),
    "GPa": (1e9, (1, -1, -2)),
    "J": (1.0, (1, 2, -2)),
    "W": (1.0, (1, 2, -3)),
    "kW": (1e3, (1, 2, -3)),
    "Hz": (1.0, (0, 0, -1)),
    "rad": (1.0, (0, 0, 0)),
    "mrad": (1e-3, (0, 0, 0)),
    "deg": (math.pi / 180.0, (0, 0, 0)),
    "%": (1e-2, (0, 0, 0)),
    "1": (1.0, (0, 0, 0)),
}


class UnitError(InputError):
    """A value whose unit is unknown or has the wrong dimension (an :class:`InputError`)."""


def _parse_unit(text: str) -> tuple[float, tuple[int, int, int]]:
    text = text.strip()
    if text in ("", "-"):
        return 1.0, (0, 0, 0)
    if text.count("/") > 1:
        raise UnitError(f"unit {text!r}: use at most one '/'")
    num, _, den = text.partition("/")
    factor = 1.0
    dim = [0, 0, 0]
    for part, sign in ((num, 1), (den, -1)):
        for token in re.split(r"[\s*·]+", part.strip()):
            if not token:
                continue
            match = re.fullmatch(r"([A-Za-z%]+|1)(?:\^?(-?\d+))?", token)
            if not match or match.group(1) not in _BASE:
                known = ", ".join(sorted(_BASE))
                raise UnitError(f"unknown unit {token!r} in {text!r} (known: {known})")
            f, d = _BASE[match.group(1)]
            exp = int(match.group(2) or 1) * sign
            factor *= f**exp
            for i in range(3):
                dim[i] += d[i] * exp
    return factor, (dim[0], dim[1], dim[2])


def unit_dimension(unit: str) -> tuple[int, int, int]:
    """Dimension exponents (kg, m, s) of a unit string."""
    return _parse_unit(unit)[1]


def to_si(value: object, unit: str) -> float:
    """Convert ``value`` to SI, checking it against the expected ``unit`` (an SI unit string).

    A number is returned unchanged (it is taken to be in the field's SI unit), and so is a
    string holding only a number (YAML 1.1 reads ``1e9`` without a decimal point as text); a
    string ``"<number> <unit>"`` is converted. ``unit`` is the field's SI unit, e.g. ``"N/m"``.

    Raises:
        UnitError: unknown unit, wrong dimension, or not a number.
    """
    if isinstance(value, bool):
        raise UnitError(f"expected a number in {unit}, got {value!r}")
    if isinstance(value, int | float):
        return float(value)
    if not isinstance(value, str):
        raise UnitError(f"expected a number in {unit} or a string like '12 {unit}', got {value!r}")
    if re.fullmatch(r"\s*[-+]?[0-9_]+(?::[0-9_]+)+(?:\.[0-9_]*)?\s*", value):
        raise UnitError(
            f"{value!r} is a ratio or a sexagesimal number (YAML 1.1 would read 1:30 as 90), "
            f"not a value in {unit}: write the number, e.g. '12 {unit}'"
        )
    match = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*", value)
    if not match:
        raise UnitError(f"expected '<number> <unit>' (e.g. '12 {unit}'), got {value!r}")
    number = float(match.group(1))
    given = match.group(2)
    if not given:
        return number  # a bare number in quotes (YAML reads 1e9 as text): SI like any number
    factor, dim = _parse_unit(given)
    expected = unit_dimension(unit)
    if dim != expected:
        wanted = "a plain number (dimensionless)" if unit == "1" else f"a value in {unit}"
        raise UnitError(f"{value!r} has the wrong dimension: expected {wanted}")
    return number * factor / _parse_unit(unit)[0]
