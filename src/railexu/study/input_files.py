"""The files a study's cases read, and a digest of their contents.

A study's case hash covers its settings and the parsed vehicle and track files; the files those
name (wheel and rail profiles, measured irregularities, a track geometry CSV) and the varied
values that are file paths are read by the cases too. :func:`input_file_digests` finds every
such file and hashes its bytes, so that a resumed study notices when one of them changed since
its cases ran and runs those cases again instead of reusing stale results.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import yaml

# file extensions of inputs that can be named inside vehicle and track files
_INPUT_SUFFIXES = {".yaml", ".yml", ".prw", ".prr", ".txt", ".csv", ".dat", ".prf"}


def _strings(data: Any) -> Iterator[str]:
    if isinstance(data, str):
        yield data
    elif isinstance(data, dict):
        for value in data.values():
            yield from _strings(value)
    elif isinstance(data, list | tuple):
        for value in data:
            yield from _strings(value)


def referenced_files(data: Any, base_dir: Path) -> list[Path]:
    """Every string in ``data`` (nested mappings and lists) that names an existing input file,
    taken relative to ``base_dir`` unless absolute."""
    found = []
    for text in _strings(data):
        path = Path(text)
        if path.suffix.lower() not in _INPUT_SUFFIXES:
            continue
        candidate = path if path.is_absolute() else base_dir / path
        if candidate.is_file():
            found.append(candidate.resolve())
    return found


def _yaml_or_none(path: Path) -> Any:
    try:
        return yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError):
        return None


def study_input_files(
    vehicle: Path, track: Path | None, values: Iterable[Any], study_dir: Path
) -> list[Path]:
    """The vehicle and track files, the files they name, and the files named by varied values
    (relative to the study file's folder or to the vehicle's or track's folder)."""
    files: list[Path] = []
    for top in (vehicle, track):
        if top is None or not Path(top).is_file():
            continue
        top = Path(top).resolve()
        files.append(top)
        files += referenced_files(_yaml_or_none(top), top.parent)
    for base in {study_dir, Path(vehicle).parent, *([Path(track).parent] if track else [])}:
        files += referenced_files(list(values), Path(base))
    return sorted(set(files))


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes (hex)."""
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def input_file_digests(
    vehicle: Path, track: Path | None, values: Iterable[Any], study_dir: Path
) -> dict[str, str]:
    """``{absolute path: SHA-256}`` of every file the study's cases read."""
    return {str(p): file_digest(p) for p in study_input_files(vehicle, track, values, study_dir)}


def changed_files(old: dict[str, str], new: dict[str, str]) -> list[str]:
    """The files whose digest differs, that appeared or that disappeared."""
    return sorted(p for p in set(old) | set(new) if old.get(p) != new.get(p))
