"""One mapping of an input file, read with typed getters that report errors precisely.

Every error names the file, the line, the dotted key and what was expected::

    vehicles/eu07.yaml:42: bodies.car_body.mas: unknown key. Did you mean 'mass'?
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NoReturn

from railexu.errors import InputError, did_you_mean
from railexu.inputs.overrides import origin_of
from railexu.inputs.reader import KeyPath, dotted
from railexu.units import UnitError, to_si


def suggest(name: Any, choices: Sequence[Any]) -> str:
    """`` Did you mean 'x'?`` if one of ``choices`` is close to ``name``, else nothing."""
    hint = did_you_mean(name, choices)
    return hint if hint.startswith(" Did you mean") else ""


#: Keys of older formats, by their old name: (the new key, its new form). The error for an old
#: key where the new one is allowed shows the new form (vehicle format 2, docs/vehicle-format.md).
RENAMED_KEYS = {
    "creep_model": ("creep", "'creep: {model: NAME}' (format 2; 'creep_model' was format 1)"),
    "polach_2005": ("creep", "'creep: {model: polach_2005, k_a: ..., k_s: ..., A: ..., B: ...}' "
                    "(format 2; the parameters nest under creep)"),
    "damping_model": ("normal_damping", "'normal_damping: {model: NAME, coefficient: VALUE}' "
                      "(format 2; 'damping_model' was format 1)"),
}  # fmt: skip


class Section:
    """One mapping of an input file, read with typed getters that report errors precisely.

    Args:
        data: the mapping.
        source: file name (for messages).
        lines: line numbers from :func:`load_yaml`.
        path: the key path of this mapping in the file.
        allowed: the keys this mapping may contain; anything else is refused (with did-you-mean).
    """

    def __init__(
        self,
        data: Any,
        source: str,
        lines: dict[KeyPath, int] | None,
        path: KeyPath = (),
        allowed: Sequence[str] | None = None,
    ) -> None:
        self.source = source
        self.lines = lines or {}
        self.path = path
        if not isinstance(data, dict):
            self.fail(f"expected a mapping (key: value lines), got {_kind(data)}")
        self.data = data
        if allowed is not None:
            for key in data:
                if key not in allowed:
                    if key in RENAMED_KEYS and RENAMED_KEYS[key][0] in allowed:
                        self.fail(f"renamed key: write {RENAMED_KEYS[key][1]}", key=key)
                    self.fail(
                        f"unknown key.{suggest(key, allowed)} Allowed here: {', '.join(allowed)}",
                        key=key,
                    )

    # -- errors ---------------------------------------------------------------------------------
    def line(self, key: Any = None) -> int | None:
        path = self.path if key is None else (*self.path, key)
        while path and path not in self.lines:
            path = path[:-1]
        return self.lines.get(path)

    def fail(self, message: str, key: Any = None) -> NoReturn:
        """Raise an :class:`InputError` at ``key`` (this section if None). A value that an
        override set (``--set``, a study parameter) is reported where the override was written.
        """
        path = self.path if key is None else (*self.path, key)
        origin = origin_of(self.lines, path)
        if origin is not None:
            raise InputError(message, source=origin[0], line=origin[1], key=dotted(path))
        raise InputError(message, source=self.source, line=self.line(key), key=dotted(path))

    def missing(self, key: str, expected: str) -> NoReturn:
        """Raise the error for a required ``key`` that is absent. Where a key written in this
        mapping looks like a misspelling of it (``tpye`` for ``type``), the error names that key
        and its line: such a section is often one whose other keys depend on the missing one, so
        the unknown-key check has not run yet."""
        for written in self.data:
            if isinstance(written, str) and written != key and suggest(written, [key]):
                self.fail(
                    f"missing key {key!r}: expected {expected}. {written!r} is written here: "
                    f"a misspelling of {key!r}?",
                    key=written,
                )
        self.fail(f"missing key {key!r}: expected {expected}")

    # -- access ---------------------------------------------------------------------------------
    def has(self, key: str) -> bool:
        return key in self.data

    def section(self, key: str, allowed: Sequence[str] | None = None, required: bool = True):
        """A nested mapping as a :class:`Section` (an empty one if optional and absent)."""
        if key not in self.data:
            if required:
                self.fail(f"missing section {key!r}")
            return Section({}, self.source, self.lines, (*self.path, key), allowed)
        return Section(self.data[key], self.source, self.lines, (*self.path, key), allowed)

    def items(self, key: str, required: bool = True) -> list[tuple[str, Any]]:
        """``(name, value)`` pairs of a mapping keyed by names (bodies, wheelsets, ...)."""
        if key not in self.data:
            if required:
                self.fail(f"missing section {key!r}")
            return []
        value = self.data[key]
        if value is None:
            return []
        if not isinstance(value, dict):
            self.fail(f"expected a mapping of names to entries, got {_kind(value)}", key=key)
        return list(value.items())

    def child(self, key: str, name: str, allowed: Sequence[str] | None = None) -> Section:
        """Entry ``name`` of the named mapping ``key`` as a :class:`Section`."""
        return Section(
            self.data[key][name], self.source, self.lines, (*self.path, key, name), allowed
        )

    def quantity(
        self,
        key: str,
        unit: str,
        *,
        default: float | None = None,
        minimum: float | None = None,
        maximum: float | None = None,
        positive: bool = False,
        required: bool | None = None,
    ) -> float:
        """A scalar quantity in SI (``unit`` is its SI unit, e.g. ``"N/m"``)."""
        if required is None:
            required = default is None
        if key not in self.data:
            if required:
                self.missing(key, f"a value in {unit}")
            return float(default) if default is not None else math.nan
        return self._check_number(self.data[key], key, unit, minimum, maximum, positive)

    def _check_number(self, raw, key, unit, minimum, maximum, positive) -> float:
        try:
            value = to_si(raw, unit)
        except UnitError as exc:
            self.fail(str(exc), key=key)
        if not math.isfinite(value):
            self.fail(f"expected a finite value in {unit}, got {raw!r}", key=key)
        if positive and not value > 0.0:
            self.fail(f"must be > 0 {unit}, got {raw!r}", key=key)
        if minimum is not None and value < minimum:
            self.fail(f"must be >= {minimum:g} {unit}, got {raw!r}", key=key)
        if maximum is not None and value > maximum:
            self.fail(f"must be <= {maximum:g} {unit}, got {raw!r}", key=key)
        return value

    def vector(
        self,
        key: str,
        unit: str,
        n: int = 3,
        *,
        default: Sequence[float] | None = None,
        components: Sequence[str] = ("x", "y", "z"),
        nonnegative: bool = False,
    ) -> tuple[float, ...]:
        """A vector as a list ``[a, b, c]`` or a mapping ``{x: a, y: b, z: c}`` (missing
        components of a mapping are 0)."""
        if key not in self.data:
            if default is None:
                self.missing(key, f"{n} values in {unit}")
            return tuple(float(v) for v in default)
        raw = self.data[key]
        minimum = 0.0 if nonnegative else None
        if isinstance(raw, dict):
            sub = Section(raw, self.source, self.lines, (*self.path, key), list(components[:n]))
            return tuple(
                sub._check_number(raw[c], c, unit, minimum, None, False) if c in raw else 0.0
                for c in components[:n]
            )
        if not isinstance(raw, list | tuple) or len(raw) != n:
            self.fail(
                f"expected {n} values in {unit} as [{', '.join(components[:n])}] or a mapping, "
                f"got {raw!r}",
                key=key,
            )
        sub = Section({i: v for i, v in enumerate(raw)}, self.source, self.lines, (*self.path, key))
        return tuple(sub._check_number(v, i, unit, minimum, None, False) for i, v in enumerate(raw))

    def string(
        self, key: str, *, default: str | None = None, choices: Sequence[str] | None = None
    ) -> str:
        if key not in self.data:
            if default is None:
                self.missing(key, "a text value")
            return default
        value = self.data[key]
        if isinstance(value, int | float) and not isinstance(value, bool) and choices is None:
            value = str(value)
        if not isinstance(value, str):
            self.fail(f"expected a text value, got {_kind(value)} {value!r}", key=key)
        if choices is not None and value not in choices:
            self.fail(
                f"{value!r} is not one of {', '.join(choices)}.{suggest(value, choices)}", key=key
            )
        return value

    def boolean(self, key: str, *, default: bool) -> bool:
        if key not in self.data:
            return default
        value = self.data[key]
        if not isinstance(value, bool):
            self.fail(f"expected true or false, got {value!r}", key=key)
        return value

    def integer(self, key: str, *, default: int | None = None, minimum: int | None = None) -> int:
        if key not in self.data:
            if default is None:
                self.missing(key, "an integer")
            return default
        value = self.data[key]
        if isinstance(value, bool) or not isinstance(value, int):
            self.fail(f"expected an integer, got {value!r}", key=key)
        if minimum is not None and value < minimum:
            self.fail(f"must be >= {minimum}, got {value}", key=key)
        return value

    def string_list(self, key: str, *, default: Sequence[str] = ()) -> tuple[str, ...]:
        if key not in self.data:
            return tuple(default)
        value = self.data[key]
        if isinstance(value, str):
            return (value,)
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            self.fail(f"expected a list of text values, got {value!r}", key=key)
        return tuple(value)


def _kind(value: Any) -> str:
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if value is None:
        return "nothing"
    return type(value).__name__
