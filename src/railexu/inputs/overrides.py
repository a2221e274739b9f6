"""``dotted.key=value`` overrides (the command line's ``--set``, study parameters) applied to raw
input data before validation, so that an override is checked like a value in the file."""

from __future__ import annotations

import copy
from collections.abc import Iterable
from fnmatch import fnmatchcase
from pathlib import Path
from typing import Any

from railexu.errors import InputError, did_you_mean
from railexu.inputs.reader import KeyPath, LineMap, load_yaml


class Override(str):
    """A ``dotted.key=value`` text that remembers where it was written (``source``, ``line``):
    an error in the value it sets names that place, e.g. the line of a study parameter, not
    the line of the vehicle file it overrides."""

    source: str
    line: int | None

    def __new__(cls, text: str, source: str = "", line: int | None = None) -> Override:
        obj = super().__new__(cls, text)
        obj.source = source
        obj.line = line
        return obj

    def __reduce__(self):
        return (Override, (str(self), self.source, self.line))


def as_override_list(overrides: str | Iterable[str] | None) -> list[str]:
    """Overrides as a list: one string is one override (never read character by character)."""
    if overrides is None:
        return []
    if isinstance(overrides, str):
        return [overrides]
    return list(overrides)


def load_yaml_with_overrides(
    path: str | Path, overrides: str | Iterable[str] = ()
) -> tuple[Any, LineMap]:
    """:func:`load_yaml` followed by :func:`apply_overrides` (``dotted.key=value`` items; one
    string is one item). The returned lines record, in ``lines.origins``, which key paths the
    overrides set and where each override came from."""
    data, lines = load_yaml(path)
    items = as_override_list(overrides)
    if items:
        data = apply_overrides(data, items, origins=lines.origins)
    return data, lines


def _is_pattern(part: str) -> bool:
    return "*" in part or "?" in part


class _Assigner:
    def __init__(self, source: str, value: Any, origin, origins) -> None:
        self.source = source
        self.value = value
        self.origin = origin
        self.origins = origins

    def fail(self, message: str, here: str) -> None:
        raise InputError(message, source=self.source, key=here)

    def set(self, node: Any, key: Any, path: KeyPath) -> None:
        node[key] = copy.deepcopy(self.value)
        if self.origins is not None and self.origin is not None:
            self.origins[(*path, key)] = self.origin

    def assign(self, node: Any, parts: list[str], done: list[Any]) -> None:
        part = parts[len(done)]
        last = len(done) == len(parts) - 1
        here = ".".join(str(p) for p in [*done, part])
        if not isinstance(node, dict | list):
            self.fail(f"{'.'.join(str(d) for d in done)} is a value, not a section", here)
        if _is_pattern(part):
            self._pattern(node, parts, done, part, last, here)
        elif isinstance(node, list):
            try:
                index = int(part)
                node[index]  # noqa: B018 - index check
            except (ValueError, IndexError):
                self.fail(f"no list item {part!r} (the list has {len(node)} items)", here)
            self._step(node, index, parts, done, last)
        elif last or part in node:
            self._step(node, part, parts, done, last)
        else:
            close = did_you_mean(part, node)
            message = f"no key {part!r} here.{close}"
            if not close.startswith(" Did you mean"):  # not a misspelling: a new section
                message = message.rstrip(".") + "." + self._whole(parts, done)
            self.fail(message, here)

    def _whole(self, parts: list[str], done: list[Any]) -> str:
        """The hint for a key the file lacks in the middle of the path: only the path's last
        part may be new, so such a section is set whole (``track_model={type: elastic}``)."""
        inner = str(self.value) if isinstance(self.value, str | int | float | bool) else "..."
        for p in reversed(parts[len(done) + 1 :]):
            inner = f"{{{p}: {inner}}}"
        here = ".".join(str(p) for p in [*done, parts[len(done)]])
        return (
            f" A key the file lacks can only be the path's last part: set it whole, {here}={inner}"
        )

    def _step(self, node, key, parts, done, last) -> None:
        if last:
            self.set(node, key, tuple(done))
        else:
            self.assign(node[key], parts, [*done, key])

    def _pattern(self, node, parts, done, part, last, here) -> None:
        names = list(node) if isinstance(node, dict) else list(range(len(node)))
        matches = [k for k in names if fnmatchcase(str(k), part)]
        if not matches:
            what = "key" if isinstance(node, dict) else "list index"
            known = ", ".join(str(k) for k in names) or "nothing"
            self.fail(f"pattern {part!r} matches no {what} here (there are: {known})", here)
        for k in matches:
            self._step(node, k, parts, done, last)


def apply_overrides(
    data: dict,
    overrides: str | Iterable[str],
    source: str = "--set",
    origins: dict | None = None,
) -> dict:
    """Apply ``dotted.key=value`` overrides to raw input data (a deep copy is returned).

    The value is parsed as YAML (``1.5e6``, ``"52 t"``, ``[0, 1, 2]``, ``polach``). Every key on the
    path must exist, except the last one of a mapping, which may be new (it is then validated
    like any key of the file); list items are addressed by their index. One string is one
    override.

    A path part containing ``*`` or ``?`` is a pattern (:func:`fnmatch.fnmatchcase`): it stands
    for every existing key of that mapping (or index of that list) it matches, so
    ``suspension.primary_ws*.stiffness.x=8e6`` sets the longitudinal stiffness of every element
    named ``primary_ws...``. A pattern never creates keys; one that matches nothing is an error,
    and so is a matched entry that lacks the rest of the path.

    ``origins``, if given, receives the concrete key path of every value set by an
    :class:`Override`, mapped to the ``(source, line)`` it carries; errors in those values are
    then reported there. Plain strings (``--set``) record nothing: their errors name the file
    and the line of the section they change, as before.

    Raises:
        InputError: malformed item, unparsable value, a key or list item that does not exist
            (with did-you-mean), a pattern that matches nothing, or a path through a value.
    """
    out = copy.deepcopy(data)
    for item in as_override_list(overrides):
        item_source = getattr(item, "source", "") or source
        line = getattr(item, "line", None)
        origin = (item_source, line) if isinstance(item, Override) else None
        if "=" not in item:
            raise InputError(f"expected dotted.key=value, got {str(item)!r}", source=item_source,
                             line=line)  # fmt: skip
        key, _, text = item.partition("=")
        parts = [p for p in key.strip().split(".") if p]
        if not parts:
            raise InputError(f"empty key in {str(item)!r}", source=item_source, line=line)
        try:
            value, _ = _parse_value(text, item_source)
        except InputError as exc:
            raise InputError(f"cannot parse value {text!r}: {exc.detail}", source=item_source,
                             line=line, key=key) from None  # fmt: skip
        _Assigner(item_source, value, origin, origins).assign(out, parts, [])
    return out


def set_values(data: dict, pairs: Iterable[tuple[str, Any]], source: str = "replace") -> dict:
    """Like :func:`apply_overrides` with ``(dotted path, Python value)`` pairs: the values are
    set as given (a text like ``"4 MN/m"`` stays text, validated by the loader)."""
    out = copy.deepcopy(data)
    for key, value in pairs:
        parts = [p for p in str(key).strip().split(".") if p]
        if not parts:
            raise InputError(f"empty path {key!r}", source=source)
        _Assigner(source, value, (source, None), None).assign(out, parts, [])
    return out


def _parse_value(text: str, source: str) -> tuple[Any, LineMap]:
    from railexu.inputs.reader import parse_yaml

    if not text.strip():
        return None, LineMap()
    return parse_yaml(text, source)


def origin_of(lines: dict | None, path: KeyPath) -> tuple[str, int | None] | None:
    """The ``(source, line)`` of the override that set ``path`` or a section containing it."""
    origins = getattr(lines, "origins", None)
    if not origins:
        return None
    for n in range(len(path), 0, -1):
        if path[:n] in origins:
            return origins[path[:n]]
    return None
