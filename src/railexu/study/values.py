"""Values of varied parameters: lists and ranges of numbers or quantities with units, their SI
values and units, and each value as override text."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from typing import Any

import yaml

from railexu.inputs import Field, Schema, Section
from railexu.units import UnitError, to_si, unit_dimension

RANGE = Schema(
    "range",
    (
        Field("from", "first value, a number or '<number> <unit>'", "text"),
        Field("to", "last value (included when the steps reach it), same kind of unit", "text"),
        Field("step", "increment, > 0, same kind of unit", "text"),
    ),
    f"A range of values `{{from, to, step}}`: at most {10_000} values, all finite.",
)
RANGE_KEYS = RANGE.keys()
MAX_VALUES = 10_000

# readable SI units of dimensions (kg, m, s)
_DIMENSION_NAMES = {
    (0, 0, 0): "-",
    (0, 1, 0): "m",
    (1, 0, 0): "kg",
    (0, 0, 1): "s",
    (0, 1, -1): "m/s",
    (0, 1, -2): "m/s^2",
    (1, 1, -2): "N",
    (1, 0, -2): "N/m",
    (1, 0, -1): "N s/m",
    (1, 2, -2): "N m",
    (1, 2, -1): "N m s",
    (1, 2, 0): "kg m^2",
    (1, -1, -2): "Pa",
    (0, 0, -1): "1/s",
    (1, 2, -3): "W",
}
_NUMBER_UNIT = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*")


def _yaml_text(value: Any) -> str:
    """``value`` as YAML text that reads back as the same value (for ``key=value`` overrides)."""
    text = yaml.safe_dump(value, default_flow_style=True, width=10**9, allow_unicode=True)
    text = text.strip()
    if text.endswith("\n..."):
        text = text[: -len("\n...")].strip()
    elif text.endswith("..."):
        text = text[:-3].strip()
    return text


def _split_quantity(value: Any) -> tuple[float, str] | None:
    """``(number, unit text)`` of a number or a ``"<number> <unit>"`` string; None otherwise."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        return float(value), ""
    if isinstance(value, str):
        m = _NUMBER_UNIT.fullmatch(value)
        if m:
            return float(m.group(1)), m.group(2)
    return None


def _dimension_unit(dim: tuple[int, int, int]) -> str:
    """A unit string of dimension ``dim`` (kg, m, s) with factor 1, for :func:`to_si`."""
    parts = [f"{s}^{e}" for s, e in zip(("kg", "m", "s"), dim, strict=True) if e]
    return " ".join(parts) or "1"


def _unit_label(dim: tuple[int, int, int], units: Iterable[str]) -> str:
    if dim == (0, 0, 0):
        return "rad" if any("rad" in u or "deg" in u for u in units) else "-"
    return _DIMENSION_NAMES.get(dim, _dimension_unit(dim))


def _number_text(x: float, integer: bool = False) -> Any:
    """A value of a range as written: 12 significant digits, an int if ``integer``."""
    x = float(f"{x:.12g}")
    if integer and x.is_integer():
        return int(x)
    return x


def _range_values(raw: dict, sec: Section) -> tuple[tuple, tuple, bool, str]:
    for k in RANGE_KEYS:
        if k not in raw:
            sec.fail(f"missing key {k!r}: a range needs from, to and step")
    parsed = {}
    for k in RANGE_KEYS:
        q = _split_quantity(raw[k])
        if q is None:
            sec.fail(f"expected a number or '<number> <unit>', got {raw[k]!r}", key=k)
        parsed[k] = q
    units = {k: q[1] for k, q in parsed.items()}
    dims = {}
    for k, u in units.items():
        if u:
            try:
                dims[k] = unit_dimension(u)
            except UnitError as exc:
                sec.fail(str(exc), key=k)
    if dims and (len(dims) != 3 or len(set(dims.values())) != 1):
        sec.fail(
            "from, to and step must all carry units of the same kind (or all be plain numbers), "
            f"got {raw['from']!r}, {raw['to']!r}, {raw['step']!r}"
        )
    dim = next(iter(dims.values())) if dims else (0, 0, 0)
    si_unit = _dimension_unit(dim)
    si = {k: to_si(raw[k], si_unit) if dims else parsed[k][0] for k in RANGE_KEYS}
    for k in RANGE_KEYS:
        if not math.isfinite(si[k]):
            sec.fail(f"expected a finite value, got {raw[k]!r}", key=k)
    if not si["step"] > 0.0:
        sec.fail(f"step must be > 0, got {raw['step']!r}", key="step")
    if si["to"] < si["from"]:
        sec.fail(f"to ({raw['to']!r}) must be >= from ({raw['from']!r})", key="to")
    count = (si["to"] - si["from"]) / si["step"]
    if not count < MAX_VALUES:
        sec.fail(f"{count:.3g} values is more than {MAX_VALUES}: is the step or a unit wrong?",
                 key="step")  # fmt: skip
    n = int(math.floor(count + 0.5)) + 1
    if n > MAX_VALUES:
        sec.fail(f"{n} values is more than {MAX_VALUES}: is the step or a unit wrong?", key="step")
    unit = units["from"]
    if dims:
        factor = to_si(f"1 {unit}", si_unit)
        numbers = [_number_text((si["from"] + i * si["step"]) / factor) for i in range(n)]
        values = tuple(f"{x:.12g} {unit}" for x in numbers)
        si_values = tuple(to_si(v, si_unit) for v in values)
        return values, si_values, True, _unit_label(dim, [unit])
    integer = all(
        isinstance(raw[k], int) and not isinstance(raw[k], bool) for k in ("from", "step")
    )
    values = tuple(_number_text(si["from"] + i * si["step"], integer) for i in range(n))
    return values, tuple(float(v) for v in values), False, ""


def _list_si(values: tuple, fail) -> tuple[tuple, bool, str]:
    parsed = [_split_quantity(v) for v in values]
    if any(p is None for p in parsed):
        return tuple(None for _ in values), False, ""
    for i, p in enumerate(parsed):
        if not math.isfinite(p[0]):
            fail(f"expected a finite value, got {values[i]!r}", i)
    units = [p[1] for p in parsed if p[1]]
    if not units:
        return tuple(p[0] for p in parsed), False, ""
    dims = {}
    for u in units:
        try:
            dims[u] = unit_dimension(u)
        except UnitError:
            return tuple(None for _ in values), False, ""  # not a quantity ("1:40")
    if len(set(dims.values())) > 1:
        fail(f"the values carry units of different kinds: {', '.join(dims)}")
    dim = next(iter(dims.values()))
    si_unit = _dimension_unit(dim)
    return tuple(to_si(v, si_unit) for v in values), True, _unit_label(dim, units)
