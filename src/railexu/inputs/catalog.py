"""The vehicles, tracks, studies and acceptance programmes that ship with railexu, by name.

They live in ``vehicles/``, ``tracks/``, ``studies/`` and ``programmes/`` at the top of the
repository and are installed with the package (as ``railexu.vehicles``, ``railexu.tracks``,
``railexu.studies``, ``railexu.programmes``), so
``railexu run eu07`` works from any folder after ``pip install``. Wherever a name is accepted, a
path works too: :func:`find_input` takes an existing file first, then a shipped name.
"""

from __future__ import annotations

import importlib.resources
from dataclasses import dataclass
from pathlib import Path

from railexu.errors import InputError, did_you_mean

KINDS = ("vehicle", "track", "study", "programme")
_PACKAGES = {
    "vehicle": "railexu.vehicles",
    "track": "railexu.tracks",
    "study": "railexu.studies",
    "programme": "railexu.programmes",
}


@dataclass(frozen=True)
class ShippedFile:
    """One shipped input file: its name (the file name without ``.yaml``), path and one-line
    description (the file's ``description`` or ``name``, else its first comment line)."""

    kind: str
    name: str
    path: Path
    description: str


def _folder(kind: str) -> Path:
    if kind not in _PACKAGES:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    # resolved: in a source checkout src/railexu/vehicles is a link to the top-level vehicles/,
    # and messages and results name the file where the user finds it
    return Path(str(importlib.resources.files(_PACKAGES[kind]))).resolve()


def shipped_names(kind: str) -> list[str]:
    """The names of the shipped files of one kind (one of :data:`KINDS`)."""
    return sorted(p.stem for p in _folder(kind).glob("*.yaml"))


def shipped_path(kind: str, name: str) -> Path:
    """The path of a shipped file by name.

    Raises:
        InputError: no shipped file of that kind has this name (with did-you-mean).
    """
    path = _folder(kind) / f"{name}.yaml"
    if not path.is_file():
        raise InputError(
            f"no file or shipped {kind} named {name!r}.{did_you_mean(name, shipped_names(kind))}"
            f" (`railexu list` shows them)"
        )
    return path


def find_input(kind: str, name_or_path: str | Path) -> Path:
    """An existing file (a path), else the shipped file of that name.

    A name with a ``.yaml`` suffix or a ``/`` that does not exist is reported as a missing file,
    not looked up by name.
    """
    path = Path(name_or_path)
    text = str(name_or_path)
    looks_like_path = bool(path.suffix) or "/" in text or "\\" in text
    if path.is_file():
        return path
    if path.is_dir() and (looks_like_path or not (_folder(kind) / f"{text}.yaml").is_file()):
        raise InputError(f"{path} is a folder; a {kind} file was expected")
    if looks_like_path:
        raise InputError("file not found", source=text)
    # a bare name: the shipped file, also when a folder of that name is here (`--out eu07`)
    return shipped_path(kind, text)


def describe(path: Path) -> str:
    """A one-line description of a shipped YAML file, read without validating it."""
    import yaml

    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError):
        data = None
    if isinstance(data, dict):
        for key in ("description", "name"):
            value = data.get(key)
            if isinstance(value, str) and value.strip():
                return " ".join(value.split())
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("#"):
            return line.lstrip("# ").strip()
    return ""


def shipped_files(kind: str) -> list[ShippedFile]:
    """Every shipped file of one kind with its description."""
    return [
        ShippedFile(kind, name, path, describe(path))
        for name, path in ((n, _folder(kind) / f"{n}.yaml") for n in shipped_names(kind))
    ]
