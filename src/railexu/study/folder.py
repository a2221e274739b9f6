"""The output folder of a study: its file names, its lock, and writing files into it."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from railexu.study.errors import StudyError

RESULTS_CSV = "results.csv"
STUDY_JSON = "study.json"
CASES_DIR = "cases"
PLOTS_DIR = "plots"
_LOCK_FILE = ".railexu-study.lock"


def _write_json(path: Path, data: Any) -> None:
    text = json.dumps(data, indent=2, default=str, allow_nan=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text + "\n", encoding="utf-8")
    os.replace(tmp, path)


def _write_files(case_dir: Path, files: Mapping[str, bytes]) -> None:
    """Write a case's files sent back by a Dask worker; the manifest that marks the case's
    folder complete (``.railexu-files.json``) last, so that a study stopped meanwhile leaves a
    folder that says it is incomplete."""
    from railexu.report.folder import MANIFEST

    if case_dir.exists():
        shutil.rmtree(case_dir)
    if MANIFEST in files:  # incomplete until the manifest's own content replaces this
        case_dir.mkdir(parents=True, exist_ok=True)
        _write_json(case_dir / MANIFEST, {"kind": "run", "complete": False, "files": []})
    for name in sorted(files, key=lambda n: n == MANIFEST):
        path = case_dir / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(files[name])
    case_dir.mkdir(parents=True, exist_ok=True)


@contextlib.contextmanager
def _locked(out: Path):
    """Hold an exclusive lock on the output folder (POSIX; released if the process dies)."""
    try:
        import fcntl
    except ImportError:  # Windows: no lock
        yield
        return
    fh = (out / _LOCK_FILE).open("w")
    try:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        fh.close()
        raise StudyError(f"{out}: another railexu study is running in this folder") from None
    try:
        yield
    finally:
        fcntl.flock(fh, fcntl.LOCK_UN)
        fh.close()


def is_study_folder(path: str | Path) -> bool:
    """``path`` holds a study's output (``study.json`` and ``results.csv``)."""
    p = Path(path)
    return (p / STUDY_JSON).is_file() and (p / RESULTS_CSV).is_file()
