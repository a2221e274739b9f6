"""Reading YAML input files safely: line numbers of every key, limits against hostile files.

:func:`load_yaml` returns plain data and a :class:`LineMap` (the line of every key). It refuses,
with an :class:`~railexu.errors.InputError` naming the file, everything that is not a small,
plain YAML document: folders, binary or UTF-16 files, files over :data:`MAX_FILE_BYTES`, alias
"bombs" (more than :data:`MAX_VALUES` values once aliases and merge keys are expanded),
nesting deeper than :data:`MAX_DEPTH`, tags other than YAML's plain types, keys that are not
plain values, and bad merge keys.

YAML 1.1 reads an unquoted ``1:40`` as the sexagesimal number 100 (1 x 60 + 40). No railexu input
means that: such a value is read as the text written (``"1:40"``), so an inclination ``1:40`` is
the ratio it means and a number field given ``1:40`` is refused as not a number.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import yaml

from railexu.errors import InputError

KeyPath = tuple[Any, ...]

#: Largest input file read [bytes]: the biggest shipped file is ~6 kB.
MAX_FILE_BYTES = 2_000_000
#: Most values (scalars, lists, mappings) a document may expand to (aliases and merges counted
#: at every use): a vehicle has a few hundred.
MAX_VALUES = 100_000
#: Deepest nesting of lists and mappings.
MAX_DEPTH = 40

_SEXAGESIMAL = re.compile(r"^[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+(?:\.[0-9_]*)?$")
_PLAIN_TAGS = {
    "tag:yaml.org,2002:" + t
    for t in ("str", "int", "float", "bool", "null", "map", "seq", "timestamp", "merge")
}


class LineMap(dict):
    """Key path -> line (1-based) of an input file, plus ``origins``: key paths whose value was
    set by an override, with the ``(source, line)`` of that override (for error messages)."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.origins: dict[KeyPath, tuple[str, int | None]] = {}

    def copy(self) -> LineMap:
        out = LineMap(self)
        out.origins = dict(self.origins)
        return out


def dotted(path: KeyPath) -> str:
    """``("a", "b", 0)`` -> ``"a.b.0"``."""
    return ".".join(str(p) for p in path)


def read_text(path: str | Path, what: str = "input") -> str:
    """The text of a small UTF-8 file, or an :class:`InputError` naming it.

    Raises:
        InputError: missing, a folder, unreadable, too large, binary, UTF-16 or not UTF-8.
    """
    path = Path(path)
    source = str(path)
    if path.is_dir():
        raise InputError(f"is a folder; an {what} file (YAML) was expected", source=source)
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise InputError(
                f"{size} bytes: larger than {MAX_FILE_BYTES} bytes, too large for an {what} file",
                source=source,
            )
        data = path.read_bytes()
    except FileNotFoundError as exc:
        raise InputError("file not found", source=source) from exc
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", source=source) from exc
    return decode_text(data, source)


def decode_text(data: bytes, source: str) -> str:
    """UTF-8 text of ``data`` (a UTF-8 byte order mark is dropped).

    Raises:
        InputError: UTF-16/32 or binary content, or invalid UTF-8 (with the byte offset).
    """
    if data[:2] in (b"\xff\xfe", b"\xfe\xff") or data[:4] in (b"\x00\x00\xfe\xff",):
        raise InputError("is UTF-16 or UTF-32 text: save it as UTF-8", source=source)
    if b"\x00" in data[:8192]:
        raise InputError("is a binary file (NUL bytes), not YAML text", source=source)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(
            f"is not UTF-8 text (byte {exc.start}): save it as UTF-8", source=source
        ) from exc


def load_yaml(path: str | Path) -> tuple[Any, LineMap]:
    """Read a YAML file; return the data (plain dicts, lists, scalars) and the line of each key.

    Raises:
        InputError: missing file, a folder, not UTF-8 text, YAML syntax error (with its line),
            or a document outside the limits of this module.
    """
    return parse_yaml(read_text(path), str(path))


def parse_yaml(text: str, source: str = "<string>") -> tuple[Any, LineMap]:
    """Parse YAML text; see :func:`load_yaml`."""
    if len(text) > MAX_FILE_BYTES:
        raise InputError(f"document larger than {MAX_FILE_BYTES} characters", source=source)
    node = _compose(text, source)
    lines = LineMap()
    if node is None:
        return {}, lines
    _check_size(node, source)
    return _Builder(source, lines).build(node, ()), lines


def _check_depth(text: str, source: str) -> None:
    """Refuse nesting deeper than :data:`MAX_DEPTH` from the parser's events (iterative, so a
    file of ten thousand ``[`` costs no recursion and little time)."""
    depth = 0
    try:
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            if isinstance(event, yaml.CollectionStartEvent):
                depth += 1
                if depth > MAX_DEPTH:
                    raise InputError(f"nesting deeper than {MAX_DEPTH} levels", source=source,
                                     line=event.start_mark.line + 1)  # fmt: skip
            elif isinstance(event, yaml.CollectionEndEvent):
                depth -= 1
    except yaml.YAMLError:
        return  # reported with its line by the composer


def _compose(text: str, source: str) -> yaml.Node | None:
    loader = None
    try:
        _check_depth(text, source)
        loader = yaml.SafeLoader(text)
        return loader.get_single_node()
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        problem = getattr(exc, "problem", None) or str(exc)
        raise InputError(f"YAML syntax error: {problem}", source=source, line=line) from exc
    except RecursionError as exc:
        raise InputError(f"nesting deeper than {MAX_DEPTH} levels", source=source) from exc
    finally:
        if loader is not None:
            loader.dispose()


def _check_size(root: yaml.Node, source: str) -> None:
    """Refuse deep nesting and documents that expand to more than :data:`MAX_VALUES` values
    (an alias counts its whole target each time it is used), before anything is built."""
    sizes: dict[int, int] = {}

    def size(n: yaml.Node, depth: int) -> int:
        if depth > MAX_DEPTH:
            raise InputError(
                f"nesting deeper than {MAX_DEPTH} levels",
                source=source,
                line=n.start_mark.line + 1,
            )
        if id(n) in sizes:
            return sizes[id(n)]
        sizes[id(n)] = 1  # a cycle (recursive alias) counts once here, refused when built
        total = 1
        if isinstance(n, yaml.MappingNode):
            total += sum(size(k, depth + 1) + size(v, depth + 1) for k, v in n.value)
        elif isinstance(n, yaml.SequenceNode):
            total += sum(size(v, depth + 1) for v in n.value)
        if total > MAX_VALUES:
            raise InputError(
                f"the document expands to more than {MAX_VALUES} values (aliases counted at "
                "every use): an input file is never that large",
                source=source,
                line=n.start_mark.line + 1,
            )
        sizes[id(n)] = total
        return total

    size(root, 0)


class _Builder:
    """Nodes -> plain data, recording the line of each key path."""

    def __init__(self, source: str, lines: LineMap) -> None:
        self.source = source
        self.lines = lines
        self.constructor = yaml.SafeLoader("")
        self.active: set[int] = set()

    def fail(self, message: str, node: yaml.Node, path: KeyPath) -> None:
        raise InputError(message, source=self.source, line=node.start_mark.line + 1,
                         key=dotted(path))  # fmt: skip

    def build(self, n: yaml.Node, path: KeyPath) -> Any:
        self.lines.setdefault(path, n.start_mark.line + 1)
        if n.tag not in _PLAIN_TAGS:
            self.fail(f"unsupported YAML tag {n.tag!r}: only plain values are read", n, path)
        if id(n) in self.active:
            self.fail("an alias refers to its own parent (a recursive structure)", n, path)
        self.active.add(id(n))
        try:
            if isinstance(n, yaml.MappingNode):
                return self._mapping(n, path)
            if isinstance(n, yaml.SequenceNode):
                return [self.build(v, (*path, i)) for i, v in enumerate(n.value)]
            return self._scalar(n, path)
        finally:
            self.active.discard(id(n))

    def _scalar(self, n: yaml.ScalarNode, path: KeyPath) -> Any:
        if n.style is None and n.tag.endswith((":int", ":float")) and ":" in n.value:
            return n.value  # YAML 1.1 sexagesimal (1:40 -> 100): keep the text as written
        try:
            return self.constructor.construct_object(n, deep=True)
        except (yaml.YAMLError, ValueError, OverflowError) as exc:
            shown = n.value if len(n.value) <= 40 else n.value[:40] + "..."
            self.fail(f"cannot read value {shown!r}: {str(exc)[:200]}", n, path)

    def _key(self, key_node: yaml.Node, path: KeyPath) -> Any:
        if not isinstance(key_node, yaml.ScalarNode) or key_node.tag not in _PLAIN_TAGS:
            self.fail("a key must be a plain name, not a list, mapping or tagged value",
                      key_node, path)  # fmt: skip
        return self._scalar(key_node, path)

    def _mapping(self, n: yaml.MappingNode, path: KeyPath) -> dict:
        explicit = set()
        merges = 0
        for key_node, _ in n.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                merges += 1
                if merges > 1:  # YAML's merge spec allows one: later ones are silently dropped
                    self.fail(
                        "a second merge key (<<) in one mapping; merge several anchors with "
                        "one key: '<<: [*a, *b]'",
                        key_node,
                        path,
                    )
                continue
            key = self._key(key_node, path)
            if key in explicit:
                self.fail("duplicate key", key_node, (*path, key))
            explicit.add(key)
        # resolve YAML merge keys (<<: *anchor): merged entries first, explicit ones win
        try:
            self.constructor.flatten_mapping(n)
        except yaml.YAMLError as exc:
            problem = getattr(exc, "problem", None) or str(exc)
            self.fail(f"bad merge key (<<): {problem}", n, path)
        out: dict = {}
        for key_node, value_node in n.value:
            key = self._key(key_node, path)
            self.lines[(*path, key)] = key_node.start_mark.line + 1
            out[key] = self.build(value_node, (*path, key))
        return out
