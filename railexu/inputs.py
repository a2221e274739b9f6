"""Strict reading of YAML input files: line numbers, units, did-you-mean, dotted overrides.

Every error names the file, the line, the dotted key and what was expected::

    vehicles/eu07.yaml:42: bodies.car_body.mas: unknown key. Did you mean 'mass'?

:func:`load_yaml` keeps the line of every key; :class:`Section` reads one mapping of it with typed
getters (quantities with units via :mod:`railexu.units`), refuses unknown keys and reports missing
ones. :func:`apply_overrides` applies ``dotted.key=value`` settings (the CLI's ``--set``) to the
raw data before validation, so an override is checked like a value in the file.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import yaml

from .errors import InputError
from .units import UnitError, to_si

KeyPath = tuple[Any, ...]


def _dotted(path: KeyPath) -> str:
    return ".".join(str(p) for p in path)


def load_yaml(path: str | Path) -> tuple[Any, dict[KeyPath, int]]:
    """Read a YAML file; return the data (plain dicts, lists, scalars) and the line of each key.

    Raises:
        InputError: missing file or YAML syntax error (with its line).
    """
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError as exc:
        raise InputError("file not found", source=str(path)) from exc
    return parse_yaml(text, str(path))


def parse_yaml(text: str, source: str = "<string>") -> tuple[Any, dict[KeyPath, int]]:
    """Parse YAML text; see :func:`load_yaml`."""
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        problem = getattr(exc, "problem", None) or str(exc)
        raise InputError(f"YAML syntax error: {problem}", source=source, line=line) from exc
    finally:
        loader.dispose()
    lines: dict[KeyPath, int] = {}
    if node is None:
        return {}, lines
    constructor = yaml.SafeLoader("")

    def build(n: yaml.Node, path: KeyPath) -> Any:
        lines.setdefault(path, n.start_mark.line + 1)
        if isinstance(n, yaml.MappingNode):
            explicit = set()
            for key_node, _ in n.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = constructor.construct_object(key_node, deep=True)
                if key in explicit:
                    raise InputError(
                        "duplicate key",
                        source=source,
                        line=key_node.start_mark.line + 1,
                        key=_dotted((*path, key)),
                    )
                explicit.add(key)
            # resolve YAML merge keys (<<: *anchor): merged entries first, explicit ones win
            constructor.flatten_mapping(n)
            out: dict = {}
            for key_node, value_node in n.value:
                key = constructor.construct_object(key_node, deep=True)
                lines[(*path, key)] = key_node.start_mark.line + 1
                out[key] = build(value_node, (*path, key))
            return out
        if isinstance(n, yaml.SequenceNode):
            return [build(v, (*path, i)) for i, v in enumerate(n.value)]
        return constructor.construct_object(n, deep=True)

    return build(node, ()), lines


def load_yaml_with_overrides(
    path: str | Path, overrides: Iterable[str] = ()
) -> tuple[Any, dict[KeyPath, int]]:
    """:func:`load_yaml` followed by :func:`apply_overrides` (``dotted.key=value`` items)."""
    data, lines = load_yaml(path)
    overrides = list(overrides)
    if overrides:
        data = apply_overrides(data, overrides)
    return data, lines


def resolve_file(name: str, base_dir: Path | None) -> str:
    """A name that looks like a relative file path (has a suffix or a '/') is taken relative to
    the folder of the file that names it, if such a file exists there; anything else (a built-in
    name, an absolute path) is returned unchanged."""
    p = Path(name)
    if base_dir is not None and (p.suffix or "/" in name) and not p.is_absolute():
        candidate = base_dir / p
        if candidate.exists():
            return str(candidate)
    return name


def apply_overrides(data: dict, overrides: Iterable[str], source: str = "--set") -> dict:
    """Apply ``dotted.key=value`` overrides to raw input data (a deep copy is returned).

    The value is parsed as YAML (``1.5e6``, ``"52 t"``, ``[0, 1, 2]``, ``polach``). Every key on the
    path must exist, except the last one of a mapping, which may be new (it is then validated
    like any key of the file); list items are addressed by their index.

    A path part containing ``*`` or ``?`` is a pattern (:func:`fnmatch.fnmatchcase`): it stands
    for every existing key of that mapping (or index of that list) it matches, so
    ``suspension.primary_ws*.stiffness.x=8e6`` sets the longitudinal stiffness of every element
    named ``primary_ws...``. A pattern never creates keys; one that matches nothing is an error,
    and so is a matched entry that lacks the rest of the path.

    Raises:
        InputError: malformed item, unparsable value, a key or list item that does not exist
            (with did-you-mean), a pattern that matches nothing, or a path through a value.
    """
    import copy
    from fnmatch import fnmatchcase

    def is_pattern(part: str) -> bool:
        return "*" in part or "?" in part

    def assign(node: Any, parts: list[str], done: list[str], value: Any) -> None:
        part = parts[len(done)]
        last = len(done) == len(parts) - 1
        here = ".".join([*done, part])
        if not isinstance(node, dict | list):
            raise InputError(f"{'.'.join(done)} is a value, not a section", source=source, key=here)
        if is_pattern(part):
            names = list(node) if isinstance(node, dict) else list(range(len(node)))
            matches = [k for k in names if fnmatchcase(str(k), part)]
            if not matches:
                what = "key" if isinstance(node, dict) else "list index"
                known = ", ".join(str(k) for k in names) or "nothing"
                raise InputError(
                    f"pattern {part!r} matches no {what} here (there are: {known})",
                    source=source,
                    key=here,
                )
            for k in matches:
                if last:
                    node[k] = copy.deepcopy(value)
                else:
                    assign(node[k], parts, [*done, str(k)], value)
            return
        if isinstance(node, list):
            try:
                index = int(part)
                node[index]  # noqa: B018 - index check
            except (ValueError, IndexError) as exc:
                raise InputError(
                    f"no list item {part!r} (the list has {len(node)} items)",
                    source=source,
                    key=here,
                ) from exc
            if last:
                node[index] = value
            else:
                assign(node[index], parts, [*done, part], value)
        elif last:
            node[part] = value
        elif part in node:
            assign(node[part], parts, [*done, part], value)
        else:
            raise InputError(
                f"no key {part!r} here.{_suggest(part, node)}", source=source, key=here
            )

    out = copy.deepcopy(data)
    for item in overrides:
        if "=" not in item:
            raise InputError(f"expected dotted.key=value, got {item!r}", source=source)
        key, _, text = item.partition("=")
        parts = [p for p in key.strip().split(".") if p]
        if not parts:
            raise InputError(f"empty key in {item!r}", source=source)
        try:
            value = yaml.safe_load(text)
        except yaml.YAMLError as exc:
            raise InputError(f"cannot parse value {text!r}", source=source, key=key) from exc
        assign(out, parts, [], value)
    return out


def _suggest(name: str, candidates: Iterable[str]) -> str:
    close = difflib.get_close_matches(str(name), [str(c) for c in candidates], n=1, cutoff=0.6)
    return f" Did you mean {close[0]!r}?" if close else ""


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
                    self.fail(
                        f"unknown key.{_suggest(key, allowed)} Allowed here: {', '.join(allowed)}",
                        key=key,
                    )

    # -- errors ---------------------------------------------------------------------------------
    def line(self, key: Any = None) -> int | None:
        path = self.path if key is None else (*self.path, key)
        while path and path not in self.lines:
            path = path[:-1]
        return self.lines.get(path)

    def fail(self, message: str, key: Any = None) -> None:
        path = self.path if key is None else (*self.path, key)
        raise InputError(message, source=self.source, line=self.line(key), key=_dotted(path))

    # -- access ---------------------------------------------------------------------------------
    def has(self, key: str) -> bool:
        return key in self.data

    def _required(self, key: str, what: str) -> Any:
        if key not in self.data:
            self.fail(f"missing key {key!r}: expected {what}")
        return self.data[key]

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
                self.fail(f"missing key {key!r}: expected a value in {unit}")
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
                self.fail(f"missing key {key!r}: expected {n} values in {unit}")
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
                self.fail(f"missing key {key!r}: expected a text value")
            return default
        value = self.data[key]
        if isinstance(value, int | float) and not isinstance(value, bool) and choices is None:
            value = str(value)
        if not isinstance(value, str):
            self.fail(f"expected a text value, got {_kind(value)} {value!r}", key=key)
        if choices is not None and value not in choices:
            self.fail(
                f"{value!r} is not one of {', '.join(choices)}.{_suggest(value, choices)}", key=key
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
                self.fail(f"missing key {key!r}: expected an integer")
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
