"""Output folders: checked before the work starts, locked while written, files replaced atomically.

Every job that writes a folder (``railexu run``, ``contact``, ``critical-speed``, ``study``) goes
through :class:`OutputFolder`:

- :meth:`OutputFolder.prepare` is called *before* the computation: a path that is a file, lies
  inside a file or cannot be written is an input error found in a second, not after an hour of
  simulation;
- the folder is locked (POSIX ``flock``; released by the operating system if the process dies),
  so two processes writing the same folder at once get a clear error instead of a mixture;
- each file is written under a temporary name and renamed into place (:func:`atomic_path`), so a
  reader never sees half a file;
- a manifest (``.railexu-files.json``) lists the files the last job wrote; the next job into the
  same folder removes those it does not write again (no plots of an older run beside new data),
  and a folder that holds another kind of output (a study's folder given to ``railexu run``) is
  refused;
- the manifest is also the folder's completion marker: before the first file of a job is written
  it says ``"complete": false`` (with every file an older job or this one may have left), and
  only :meth:`OutputFolder.finish`, after the last data file, writes ``"complete": true`` with
  the size of each file. A job stopped while writing (a signal, a full disk, a crash) leaves a
  folder that says it is incomplete; readers check it with
  :func:`railexu.report.folder_check.check_output_folder`;
- temporary files a killed job left (``.NAME.PID.tmp.EXT``) are removed by the next job.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
from collections.abc import Iterable, Iterator
from pathlib import Path

from railexu.errors import InputError

MANIFEST = ".railexu-files.json"
LOCK_FILE = ".railexu.lock"
#: the temporary names of :func:`atomic_path` (and of a study's ``.NAME.tmp``)
_TEMPORARY = re.compile(r"^\..+\.(\d+\.)?tmp(\.[^.]+)?$")
_TEMPORARY_NAME = re.compile(r"^\.(.+)\.\d+\.tmp(\.[^.]+)?$")  # -> the name and suffix
# files that mark the output of each kind of job, to refuse writing one kind over another
_MARKERS = {
    "run": ("summary.json", "timeseries.csv"),
    "contact": ("contact.csv",),
    "critical_speed": ("critical_speed.json",),
    "study": ("study.json", "results.csv"),
}


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success rename it to ``path`` (atomic on
    POSIX and Windows), on failure remove it."""
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def check_writable_folder(path: str | Path, what: str = "--out") -> Path:
    """Create ``path`` (with its parents) if needed and check that files can be written in it.

    Raises:
        InputError: the path is a file, lies below a file, or is not writable.
    """
    out = Path(path)
    for parent in (out, *out.parents):
        if parent.exists() and not parent.is_dir():
            where = "is a file" if parent == out else f"lies inside the file {parent}"
            raise InputError(f"{out} {where}; an output folder was expected", key=what)
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / f".railexu-write-test.{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise InputError(f"cannot write into {out}: {exc.strerror or exc}", key=what) from None
    return out


class OutputFolder:
    """An output folder of one job (``kind``: run, contact, critical_speed, study).

    Use as a context manager around the whole job::

        with OutputFolder(out, "run") as folder:   # checked and locked before the work
            result = run(...)
            folder.write_text("summary.json", text)  # the manifest says "complete": false
        # the files of an older job that were not written again are removed, and the manifest
        # says "complete": true; an exception leaves it saying false

    Raises:
        InputError: not writable, locked by another process, or holding another kind of output.
    """

    def __init__(self, path: str | Path, kind: str, option: str = "--out") -> None:
        if kind not in _MARKERS:
            raise ValueError(f"kind must be one of {tuple(_MARKERS)}")
        self.path = Path(path)
        self.kind = kind
        self.option = option
        self.written: list[Path] = []
        self._lock = None
        self._listed: set[str] = set()  # the files of the incomplete manifest
        self._marked = False
        self._previous: bytes | None = None  # the manifest before this job marked the folder
        self._created: list[Path] = []  # the folders prepare() made, deepest first

    def prepare(self) -> OutputFolder:
        """Check, create and lock the folder; refuse one that holds another kind of output."""
        self._created = [p for p in (self.path, *self.path.parents) if not p.exists()]
        check_writable_folder(self.path, self.option)
        self._refuse_other_kinds()
        self._lock = _lock(self.path)
        remove_temporary_files(self.path)
        return self

    def __enter__(self) -> OutputFolder:
        return self.prepare() if self._lock is None else self

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:  # a job that failed leaves the folder marked incomplete
                self.finish()
        finally:
            self.release()

    def file(self, name: str) -> Path:
        """The path of an output file (recorded as written by this job); the first call marks
        the folder incomplete (:meth:`mark_incomplete`), before anything in it changes.

        Raises:
            InputError: the manifest cannot be written (a full disk, a read-only folder).
        """
        path = self.path / name
        self.mark_incomplete([name])
        path.parent.mkdir(parents=True, exist_ok=True)
        self.written.append(path)
        return path

    def mark_incomplete(self, names: Iterable[str] = ()) -> None:
        """Write the manifest with ``"complete": false``, listing the files of the older job
        and ``names`` (those this job is about to write), so that a stopped job leaves a folder
        that says so and the next job still knows what to remove. Written again only when a
        file not yet listed is added."""
        if not self._marked:
            self._listed = set(_read_manifest(self.path))
            self._previous = _read_bytes(self.path / MANIFEST)
        new = set(names) - self._listed
        if self._marked and not new:
            return
        self._listed |= new
        manifest = {"kind": self.kind, "complete": False, "files": sorted(self._listed)}
        _write_manifest(self.path, manifest)
        self._marked = True

    def unmark_if_untouched(self) -> None:
        """Put back the manifest this job replaced by its incomplete one (or remove that one)
        if the job has not recorded a file yet: a job that failed before writing anything (bad
        input found late, no equilibrium) leaves the older job's folder as it was."""
        if not self._marked or self.written:
            return
        manifest = self.path / MANIFEST
        if self._previous is None:
            manifest.unlink(missing_ok=True)
        else:
            with atomic_path(manifest) as tmp:
                tmp.write_bytes(self._previous)
        self._marked = False

    def write_text(self, name: str, text: str) -> Path:
        """Write a text file atomically."""
        path = self.file(name)
        with atomic_path(path) as tmp:
            tmp.write_text(text, encoding="utf-8")
        return path

    def finish(self) -> None:
        """Remove the files an older job wrote here that this one did not, then record ours
        with their sizes and ``"complete": true``: the last write of a job.

        Raises:
            InputError: a file of this job is missing, or the manifest cannot be written.
        """
        mine = {p.resolve() for p in self.written}
        for name in _read_manifest(self.path):
            old = (self.path / name).resolve()
            if old not in mine and old.is_file() and self.path.resolve() in old.parents:
                with contextlib.suppress(OSError):
                    old.unlink()
        names = sorted({p.relative_to(self.path).as_posix() for p in self.written})
        sizes = {}
        for name in names:
            try:
                sizes[name] = (self.path / name).stat().st_size
            except OSError:
                raise InputError(
                    f"{self.path / name}: not written; the folder stays marked incomplete"
                ) from None
        manifest = {"kind": self.kind, "complete": True, "files": names, "sizes": sizes}
        _write_manifest(self.path, manifest)

    def release(self) -> None:
        """Unlock the folder. A folder this job created and left untouched (its input was
        refused before anything was written) is removed again, with the parents it created:
        a refused job leaves no empty folder behind."""
        if self._lock is not None:
            _unlock(self._lock)
            self._lock = None
        if self._created and not self._marked and not self.written:
            (self.path / LOCK_FILE).unlink(missing_ok=True)
            for folder in self._created:
                try:
                    folder.rmdir()  # only if empty: never a file another process put there
                except OSError:
                    break
        self._created = []

    def _refuse_other_kinds(self) -> None:
        recorded = _read_manifest_kind(self.path)
        kinds = {recorded} if recorded else set()
        if not recorded:
            kinds = {
                k for k, names in _MARKERS.items() if all((self.path / n).exists() for n in names)
            }
        others = sorted(kinds - {self.kind})
        if others:
            raise InputError(
                f"{self.path} holds the output of a {others[0].replace('_', '-')} job; "
                f"choose another folder for this {self.kind.replace('_', '-')} output",
                key=self.option,
            )


def add_to_manifest(folder: str | Path, names: list[str]) -> None:
    """Add files written later into an output folder (figures redrawn, animations, a report
    page) to its list of written files (with their sizes), so that the next job into the folder
    replaces them too. A folder without a readable manifest (not written by railexu) is left
    alone; the manifest's completion is not changed."""
    folder = Path(folder)
    try:
        data = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        files = set(data.get("files", []))
    except (OSError, ValueError, AttributeError, TypeError):
        return
    data["files"] = sorted(files | set(names))
    if isinstance(data.get("sizes"), dict):
        for name in names:
            with contextlib.suppress(OSError):
                data["sizes"][name] = (folder / name).stat().st_size
    _write_manifest(folder, data)


@contextlib.contextmanager
def writing_errors(folder: OutputFolder) -> Iterator[None]:
    """Turn a failed write into the folder (``OSError``: a full disk, a folder made read-only,
    a quota) into an :class:`~railexu.errors.InputError` naming the file and the folder, which
    stays marked incomplete."""
    try:
        yield
    except OSError as exc:
        where = folder.path
        if exc.filename:  # the file, not its temporary name
            name = Path(exc.filename).name
            real = _TEMPORARY_NAME.match(name)
            where = Path(exc.filename).with_name("".join(real.groups(""))) if real else name
        raise InputError(
            f"cannot write {where}: {exc.strerror or exc}; {folder.path} is marked incomplete",
            key=folder.option,
        ) from None


def remove_temporary_files(folder: str | Path) -> list[Path]:
    """Remove the temporary files (``.NAME.PID.tmp.EXT``) that a job killed while writing left
    in ``folder`` (call it holding the folder's lock: no other job is writing them)."""
    removed = []
    with contextlib.suppress(OSError):
        for path in Path(folder).iterdir():
            if _TEMPORARY.match(path.name) and path.is_file():
                with contextlib.suppress(OSError):
                    path.unlink()
                    removed.append(path)
    return removed


def _write_manifest(folder: Path, manifest: dict) -> None:
    """Write the manifest atomically; a failure (a full disk) is an error naming the folder."""
    try:
        with atomic_path(folder / MANIFEST) as tmp:
            tmp.write_text(json.dumps(manifest, indent=1) + "\n", encoding="utf-8")
    except OSError as exc:
        raise InputError(
            f"cannot write {folder / MANIFEST}: {exc.strerror or exc}", key="--out"
        ) from None


def _read_bytes(path: Path) -> bytes | None:
    try:
        return path.read_bytes()
    except OSError:
        return None


def _read_manifest(path: Path) -> list[str]:
    try:
        data = json.loads((path / MANIFEST).read_text(encoding="utf-8"))
        return [str(n) for n in data.get("files", [])]
    except (OSError, ValueError, AttributeError, TypeError):
        return []


def _read_manifest_kind(path: Path) -> str:
    try:
        return str(json.loads((path / MANIFEST).read_text(encoding="utf-8")).get("kind", ""))
    except (OSError, ValueError, AttributeError):
        return ""


def _lock(path: Path):
    """An exclusive, non-blocking lock on the folder (POSIX ``flock``; none on Windows)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows: no lock
        return None
    fh = (path / LOCK_FILE).open("w")
    try:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        fh.close()
        raise InputError(
            f"{path}: another railexu process is writing this folder; wait for it or choose "
            "another folder"
        ) from None
    return fh


def _unlock(fh) -> None:
    import fcntl

    with contextlib.suppress(OSError):
        fcntl.flock(fh, fcntl.LOCK_UN)
    fh.close()
