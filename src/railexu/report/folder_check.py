"""Checks before reading an output folder: is it complete, and are its files what it says?

The contract (docs/architecture.md, "Output folders"): an output folder's manifest
(``.railexu-files.json``, written by :class:`~railexu.report.folder.OutputFolder`) is its
completion marker. ``"complete": false`` means a job began writing the folder and did not finish
(it was interrupted, killed, or a write failed): its files may be half of this job's and half of
an older one's, so no command reads it. ``"complete": true`` comes with the size of every file,
written after the last one. ``railexu report``, ``animate``, ``plot`` and a study's resume call
:func:`check_output_folder` first:

- a folder being written by another process, or marked incomplete:
  :class:`IncompleteFolderError`;
- a manifest that is not JSON or has wrong types, a data file it names that is missing, or a
  data file whose size differs from the recorded one (cut short): :class:`DamagedFolderError`
  (figures, animations and report pages may be deleted: they are drawn again from the data).

Both are :class:`~railexu.errors.InputError`: the command line prints one line and exits with 2.
A folder without a manifest (written by hand, or by a script without railexu's writers) is read
as it is; a manifest without ``complete`` (railexu before issue 26) is checked for its files.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
from pathlib import Path

from railexu.errors import InputError
from railexu.report.folder import LOCK_FILE, MANIFEST

#: the files whose size is compared with the manifest's (the JSON files are checked by parsing
#: them, and may be edited by hand)
SIZE_CHECKED = (".csv", ".npz")
#: the files that hold data (the others, figures and pages, can be drawn again from them)
DATA_FILES = (".csv", ".npz", ".json")


class IncompleteFolderError(InputError):
    """An output folder whose writing did not finish, or that another process is writing."""


class DamagedFolderError(InputError):
    """An output folder whose files are not what its manifest says, or cannot be read."""


def check_output_folder(folder: str | Path, kind: str, reads: tuple[str, ...] = ()) -> dict:
    """Check ``folder`` before a command reads the output of a ``kind`` job from it; returns
    the manifest (empty when there is none).

    Args:
        kind: run, contact, critical_speed or study.
        reads: the files the caller will read; their size is compared with the manifest's
            (``.csv`` and ``.npz`` files).

    Raises:
        IncompleteFolderError: another process is writing the folder, or its writing stopped.
        DamagedFolderError: the manifest is damaged, a file it names is missing or cut short.
    """
    folder = Path(folder)
    if _being_written(folder):
        raise IncompleteFolderError(
            f"{folder}: another railexu process is writing this folder; wait for it to finish"
        )
    manifest = _read(folder)
    if manifest is None:
        return {}
    if manifest.get("kind", kind) != kind:
        raise DamagedFolderError(
            f"{folder} holds the output of a {str(manifest['kind']).replace('_', '-')} job, "
            f"not of a {kind.replace('_', '-')} job"
        )
    if manifest.get("complete") is False:
        raise IncompleteFolderError(
            f"{folder}: incomplete: the job writing it was stopped before it finished "
            f"(interrupted, killed or out of disk space; {MANIFEST} says so); its files may be "
            "partly an older job's: run the job again into this folder"
        )
    _check_files(folder, manifest, reads)
    return manifest


def _read(folder: Path) -> dict | None:
    """The manifest, checked for its types; None when there is none."""
    path = folder / MANIFEST
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise DamagedFolderError(f"{path}: cannot read: {exc.strerror or exc}") from None
    try:
        data = json.loads(text)
    except ValueError as exc:
        raise DamagedFolderError(f"{path}: not JSON ({exc}); the folder is damaged") from None
    problem = ""
    if not isinstance(data, dict):
        problem = f"expected a JSON object, got {type(data).__name__}"
    elif not isinstance(data.get("files", []), list) or not all(
        isinstance(n, str) for n in data.get("files", [])
    ):
        problem = "'files' must be a list of file names"
    elif not isinstance(data.get("complete", True), bool):
        problem = "'complete' must be true or false"
    elif not isinstance(data.get("kind", ""), str):
        problem = "'kind' must be a text"
    elif not isinstance(data.get("sizes", {}), dict) or not all(
        isinstance(v, int) and not isinstance(v, bool) for v in data.get("sizes", {}).values()
    ):
        problem = "'sizes' must map file names to byte counts"
    if problem:
        raise DamagedFolderError(f"{path}: {problem}; the folder is damaged")
    return data


def _check_files(folder: Path, manifest: dict, reads: tuple[str, ...]) -> None:
    """Every data file the manifest names is there (figures, animations and report pages may
    be deleted: they are drawn again from the data), and those in ``reads`` have the size the
    manifest recorded."""
    sizes = manifest.get("sizes", {})
    for name in manifest.get("files", []):
        path = folder / name
        if (name in reads or name.endswith(DATA_FILES)) and not path.is_file():
            raise DamagedFolderError(f"{path}: missing (the folder's {MANIFEST} lists it)")
    for name in reads:
        path = folder / name
        if name not in sizes or not name.endswith(SIZE_CHECKED) or not path.is_file():
            continue
        size = path.stat().st_size
        if size != sizes[name]:
            raise DamagedFolderError(
                f"{path}: {size} bytes, but {sizes[name]} were written (cut short or changed "
                "since); the folder is damaged: run the job again"
            )


def _being_written(folder: Path) -> bool:
    """Another process holds the folder's lock (POSIX ``flock``; False where there is none)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows: no lock
        return False
    try:
        fd = os.open(folder / LOCK_FILE, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError as exc:  # held by another process; anything else (no locks here): not known
        return exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN)
    else:
        with contextlib.suppress(OSError):
            fcntl.flock(fd, fcntl.LOCK_UN)
        return False
    finally:
        os.close(fd)
