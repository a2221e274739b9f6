"""Strict reading of input files: YAML with line numbers, units, schemas, dotted overrides.

Every error names the file, the line, the dotted key and what was expected::

    vehicles/eu07.yaml:42: bodies.car_body.mas: unknown key. Did you mean 'mass'?

- :mod:`.reader`: :func:`load_yaml` / :func:`parse_yaml` keep the line of every key and refuse
  hostile files (folders, binary, YAML bombs, tags, deep nesting).
- :mod:`.overrides`: :func:`apply_overrides` applies ``dotted.key=value`` settings (``--set``,
  study parameters) to the raw data before validation, remembering where each came from.
- :mod:`.section`: :class:`Section` reads one mapping with typed getters.
- :mod:`.schema`: :class:`Schema` and :class:`Field` declare each key once (unit, range,
  default, doc); :mod:`.docs` renders them as the tables of ``docs/*-format.md``.
"""

from __future__ import annotations

from pathlib import Path

from railexu.errors import InputError
from railexu.inputs.overrides import (
    Override,
    apply_overrides,
    as_override_list,
    load_yaml_with_overrides,
)
from railexu.inputs.reader import KeyPath, LineMap, load_yaml, parse_yaml, read_text
from railexu.inputs.schema import OPTIONAL, REQUIRED, Field, Schema
from railexu.inputs.section import Section

__all__ = [
    "OPTIONAL",
    "REQUIRED",
    "Field",
    "InputError",
    "KeyPath",
    "LineMap",
    "Override",
    "Schema",
    "Section",
    "apply_overrides",
    "as_override_list",
    "load_yaml",
    "load_yaml_with_overrides",
    "parse_yaml",
    "read_text",
    "resolve_file",
]


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
