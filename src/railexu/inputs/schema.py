"""Declare each field of an input once: key, unit, range or choices, default, one line of doc.

A :class:`Schema` is an ordered set of :class:`Field` objects. The same declaration gives

- the allowed and the required keys of a mapping, with did-you-mean (:meth:`Schema.section`),
- reading a value with its unit and range checks (:meth:`Schema.read`, :meth:`Schema.read_all`),
- the defaults (:meth:`Schema.default`), used by the dataclasses too,
- the unit of a dotted override path (:meth:`Schema.field_at`), for ``--set`` and studies,
- the markdown tables of ``docs/*-format.md`` (:func:`markdown_table`).

Model choices are a :class:`Field` of kind ``"model"``: the value names a model of a registry
(``{model: hunt_crossley, coefficient: 3 s/m}``, or just ``hunt_crossley`` for its defaults), and
each model has its own schema for the parameters nested under it. A *sided* field
(``kind="sided"``) takes one value for both wheels or ``{left: ..., right: ...}``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from railexu.inputs.section import Section

KINDS = (
    "quantity", "vector", "text", "integer", "boolean", "text_list", "section", "named",
    "model", "sided", "inclination", "number_list",
)  # fmt: skip


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


#: The default of a field that must be given.
REQUIRED: Any = _Required()
#: The default of an optional field that has no value when absent.
OPTIONAL: Any = None


@dataclass(frozen=True)
class Field:
    """One key of an input mapping.

    Attributes:
        key: the key as written in the file.
        doc: one line of documentation (what it is; the unit and range are added by the docs).
        kind: one of :data:`KINDS`.
        unit: SI unit of a quantity, vector or sided quantity (``"N/m"``; ``"1"`` for a ratio).
        default: the value when absent (SI), :data:`REQUIRED` or :data:`OPTIONAL`.
        minimum, maximum: allowed range (inclusive, SI); ``positive`` means > 0.
        choices: allowed text values (a tuple, or a function giving them, for registries).
        components: names of a vector's components (``("x", "y", "z")``).
        schema: the schema of a ``section``, or of each entry of a ``named`` mapping.
        models: name -> schema of each model of a ``model`` field.
        selector: the key naming the model (``model``; ``type`` for irregularities).
    """

    key: str
    doc: str
    kind: str = "quantity"
    unit: str = ""
    default: Any = REQUIRED
    minimum: float | None = None
    maximum: float | None = None
    positive: bool = False
    choices: tuple[str, ...] | Callable[[], Sequence[str]] = ()
    components: tuple[str, ...] = ("x", "y", "z")
    schema: Schema | None = None
    models: Mapping[str, Schema] | None = None
    selector: str = "model"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"field {self.key!r}: unknown kind {self.kind!r}")

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def allowed_choices(self) -> tuple[str, ...]:
        if self.models is not None:
            return tuple(self.models)
        return tuple(self.choices() if callable(self.choices) else self.choices)

    def check(self, value: float, fail: Callable[[str], None], written: Any = None) -> float:
        """Check a number (SI) against the field's range; ``fail(message)`` raises. The
        message shows ``written`` (the value as written) if given."""
        unit = "" if self.unit in ("", "1") else f" {self.unit}"
        shown = repr(written) if written is not None else f"{value:g}"
        if not math.isfinite(value):
            fail(f"expected a finite value{unit}, got {shown}")
        if self.positive and not value > 0.0:
            fail(f"must be > 0{unit}, got {shown}")
        if self.minimum is not None and value < self.minimum:
            fail(f"must be >= {self.minimum:g}{unit}, got {shown}")
        if self.maximum is not None and value > self.maximum:
            fail(f"must be <= {self.maximum:g}{unit}, got {shown}")
        return value


@dataclass(frozen=True)
class Schema:
    """The fields of one mapping of an input file, in the order the docs list them."""

    name: str
    fields: tuple[Field, ...]
    doc: str = ""
    extra_keys: tuple[str, ...] = ()
    by_key: dict[str, Field] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        keys = [f.key for f in self.fields]
        if len(set(keys)) != len(keys):
            raise ValueError(f"schema {self.name!r}: a key is declared twice")
        object.__setattr__(self, "by_key", {f.key: f for f in self.fields})

    def keys(self) -> tuple[str, ...]:
        return (*self.by_key, *self.extra_keys)

    def __getitem__(self, key: str) -> Field:
        return self.by_key[key]

    def default(self, key: str) -> Any:
        """The declared default of ``key`` (SI)."""
        value = self.by_key[key].default
        if value is REQUIRED:
            raise KeyError(f"{self.name}.{key} has no default")
        return value

    # -- reading --------------------------------------------------------------------------------
    def section(self, parent: Section, key: str, required: bool = False) -> Section:
        """``parent[key]`` as a :class:`Section` that allows this schema's keys only."""
        return parent.section(key, self.keys(), required=required)

    def wrap(self, data: Any, source: str, lines, path: tuple = ()) -> Section:
        """``data`` as a :class:`Section` that allows this schema's keys only."""
        return Section(data, source, lines, path, self.keys())

    def read(self, sec: Section, key: str) -> Any:
        """The value of ``key`` in ``sec``, converted to SI and checked as declared."""
        f = self.by_key[key]
        return _READERS[f.kind](sec, f)

    def read_all(self, sec: Section, keys: Iterable[str] | None = None) -> dict[str, Any]:
        """``{key: value}`` of every field (or of ``keys``) of kinds that read to plain values."""
        wanted = self.by_key if keys is None else keys
        return {k: self.read(sec, k) for k in wanted if self.by_key[k].kind not in ("named",)}

    def check(self, key: str, value: float, error: type[Exception]) -> float:
        """Check an SI ``value`` of ``key`` against the declared range; raise ``error``."""

        def fail(message: str) -> None:
            raise error(f"{key}: {message}")

        return self.by_key[key].check(value, fail)

    # -- paths ----------------------------------------------------------------------------------
    def field_at(self, parts: Sequence[str]) -> tuple[Field | None, str]:
        """The field a dotted override path ends in and its SI unit (``""`` if unknown).

        ``suspension.primary_ws1.stiffness.x`` -> the stiffness field, ``"N/m"``. Names of
        ``named`` entries and model parameters are followed; patterns match any name.
        """
        schema: Schema | None = self
        f: Field | None = None
        i = 0
        while i < len(parts) and schema is not None:
            f = schema.by_key.get(parts[i])
            if f is None:
                return None, ""
            i += 1
            if f.kind == "named" and i < len(parts):
                i += 1  # the entry's name
                schema = f.schema
                if f.models and i < len(parts):
                    schema = _union(f.models.values())
            elif f.kind == "section":
                schema = f.schema
            elif f.kind == "model":
                schema = _union(f.models.values()) if f.models else None
            else:
                schema = None
        if i < len(parts) and not (f and f.kind in ("vector", "sided") and i == len(parts) - 1):
            return None, ""
        return f, (f.unit if f is not None else "")


def _union(schemas: Iterable[Schema]) -> Schema:
    fields: dict[str, Field] = {}
    for s in schemas:
        for f in s.fields:
            fields.setdefault(f.key, f)
    return Schema("union", tuple(fields.values()))


# -- readers of each kind -------------------------------------------------------------------------
def _quantity(sec: Section, f: Field) -> float | None:
    if f.default is OPTIONAL and f.key not in sec.data:
        return None
    default = None if f.default in (REQUIRED, OPTIONAL) else f.default
    return sec.quantity(f.key, f.unit, default=default, required=f.required, minimum=f.minimum,
                        maximum=f.maximum, positive=f.positive)  # fmt: skip


def _vector(sec: Section, f: Field) -> tuple[float, ...] | None:
    if f.default is OPTIONAL and f.key not in sec.data:
        return None
    default = None if f.default in (REQUIRED, OPTIONAL) else f.default
    n = len(f.components)
    value = sec.vector(f.key, f.unit, n=n, default=default, components=f.components)
    if f.key in sec.data:
        raw = sec.data[f.key]
        for i, (c, v) in enumerate(zip(f.components, value, strict=True)):
            sub = c if isinstance(raw, dict) else i
            written = raw.get(c) if isinstance(raw, dict) else raw[i]
            where = Section({sub: None}, sec.source, sec.lines, (*sec.path, f.key))
            f.check(v, lambda m, where=where, sub=sub: where.fail(m, key=sub), written)
    return value


def _text(sec: Section, f: Field) -> str | None:
    choices = f.allowed_choices() or None
    if f.default is OPTIONAL and f.key not in sec.data:
        return None
    if f.required and choices and f.key not in sec.data:
        sec.fail(f"missing key {f.key!r} ({f.doc}): expected one of {', '.join(choices)}")
    default = None if f.default is REQUIRED else f.default
    return sec.string(f.key, default=default, choices=choices)


def _integer(sec: Section, f: Field) -> int | None:
    if f.default is OPTIONAL and f.key not in sec.data:
        return None
    default = None if f.default is REQUIRED else f.default
    minimum = None if f.minimum is None else int(f.minimum)
    value = sec.integer(f.key, default=default, minimum=minimum)
    if f.maximum is not None and value > f.maximum:
        sec.fail(f"must be <= {f.maximum:g}, got {value}", key=f.key)
    choices = f.allowed_choices()
    if choices and value not in choices and f.key == "format_version":
        sec.fail(f"format_version {value} is not supported (this railexu reads "
                 f"{', '.join(str(c) for c in choices)})", key=f.key)  # fmt: skip
    if choices and value not in choices:
        sec.fail(f"must be one of {', '.join(str(c) for c in choices)}, got {value}", key=f.key)
    return value


def _boolean(sec: Section, f: Field) -> bool:
    if f.required and f.key not in sec.data:
        sec.missing(f.key, "true or false")
    return sec.boolean(f.key, default=bool(f.default) if not f.required else False)


def _text_list(sec: Section, f: Field) -> tuple[str, ...]:
    default = () if f.default in (REQUIRED, OPTIONAL) else f.default
    if f.required and f.key not in sec.data:
        sec.missing(f.key, "a list of text values")
    values = sec.string_list(f.key, default=default)
    choices = f.allowed_choices()
    for v in values:
        if choices and v not in choices:
            sec.fail(f"unknown value {v!r}; expected some of {', '.join(choices)}", key=f.key)
    return values


def _section(sec: Section, f: Field) -> dict[str, Any]:
    assert f.schema is not None
    sub = sec.section(f.key, f.schema.keys(), required=f.required)
    return f.schema.read_all(sub)


def _named(sec: Section, f: Field) -> list[tuple[str, Any]]:
    return sec.items(f.key, required=f.required)


def _model(sec: Section, f: Field) -> tuple[str, dict[str, Any]]:
    """``(model name, {parameter: SI value})`` of a model choice."""
    assert f.models is not None
    raw = sec.data.get(f.key, f.default)
    if raw is REQUIRED:
        sec.missing(f.key, f"one of {', '.join(f.models)}")
    if isinstance(raw, str):
        raw = {f.selector: raw}
    if raw is None:
        raw = {}
    holder = Section({f.key: raw}, sec.source, sec.lines, sec.path)
    kind_sec = holder.section(f.key)
    name = kind_sec.string(f.selector, choices=tuple(f.models))
    schema = f.models[name]
    params = Section(raw, sec.source, sec.lines, (*sec.path, f.key), (f.selector, *schema.keys()))
    return name, schema.read_all(params)


def _sided(sec: Section, f: Field) -> tuple[Any, Any]:
    """``(left, right)`` of a value given once for both wheels or as ``{left:, right:}``."""
    plain = replace(f, kind="quantity" if f.unit else "text")
    raw = sec.data.get(f.key)
    if isinstance(raw, dict):
        sub = Section(raw, sec.source, sec.lines, (*sec.path, f.key), ("left", "right"))
        left, right = (
            _READERS[plain.kind](sub, replace(plain, key=side, default=REQUIRED))
            for side in ("left", "right")
        )
        return left, right
    value = _READERS[plain.kind](sec, plain)
    return value, value


def _inclination(sec: Section, f: Field) -> tuple[Any, float]:
    """``(value as written, angle in rad)`` of a rail inclination: ``"1:40"``, ``"1/40"``,
    ``"none"``, ``"0.025 rad"``, ``"1.4 deg"`` or a number in rad."""
    from railexu.units import to_si

    raw = sec.data.get(f.key, f.default)
    if raw is REQUIRED:
        sec.missing(f.key, "a ratio like '1:40' or an angle")
    angle = _ratio_angle(raw)
    if angle is None:
        try:
            angle = to_si(raw, "rad")
        except ValueError:
            sec.fail(f"expected a ratio like '1:40' or '1:20', 'none', or an angle ('0.025 rad', "
                     f"'1.4 deg'), got {raw!r}", key=f.key)  # fmt: skip
    f.check(angle, lambda m: sec.fail(f"{m} (as an angle in rad, from {raw!r})", key=f.key))
    return raw, angle


def _number_list(sec: Section, f: Field) -> tuple[float, ...]:
    """A list of at least two numbers (a table column), each with the field's unit and range."""
    if f.key not in sec.data:
        if f.required:
            sec.missing(f.key, f"a list of values in {f.unit}")
        return () if f.default in (REQUIRED, OPTIONAL) else tuple(f.default)
    raw = sec.data[f.key]
    if not isinstance(raw, list | tuple) or len(raw) < 2:
        sec.fail(f"expected a list of at least 2 values in {f.unit}, got {raw!r}", key=f.key)
    sub = Section(dict(enumerate(raw)), sec.source, sec.lines, (*sec.path, f.key))
    values = []
    for i, v in enumerate(raw):
        value = sub.quantity(i, f.unit)
        f.check(value, lambda m, i=i: sub.fail(m, key=i), v)
        values.append(value)
    return tuple(values)


def _ratio_angle(raw: Any) -> float | None:
    from fractions import Fraction

    if raw is None:
        return 0.0
    if not isinstance(raw, str):
        return None
    text = raw.strip().lower()
    if text in ("none", "vertical", "upright"):
        return 0.0
    for sep in (":", "/"):
        if sep in text and not any(c.isalpha() for c in text):
            num, den = text.split(sep, 1)
            try:
                ratio = Fraction(num.strip()) / Fraction(den.strip())
            except (ValueError, ZeroDivisionError):
                return math.nan
            return math.atan(float(ratio))
    return None


_READERS: dict[str, Callable[[Section, Field], Any]] = {
    "quantity": _quantity,
    "vector": _vector,
    "text": _text,
    "integer": _integer,
    "boolean": _boolean,
    "text_list": _text_list,
    "section": _section,
    "named": _named,
    "model": _model,
    "sided": _sided,
    "inclination": _inclination,
    "number_list": _number_list,
}
