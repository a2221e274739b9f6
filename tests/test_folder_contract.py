"""Issue 26 (parts 1 and 6): a run's output folder is complete or says it is not.

The contract (docs/architecture.md, "Output folders"): the manifest ``.railexu-files.json`` is
written with ``"complete": false`` before the first file of a job changes, and with
``"complete": true`` and every file's size after the last one (``summary.json`` after the data it
describes). Each test stops or damages a writer in one way and checks that the folder does not
claim more than it holds and that ``report``, ``plot`` and ``animate`` refuse it with one line
(exit code 2), never a traceback. What is checked is outside the code under test: the files on
disk, the exit codes and the processes the operating system still lists.
"""

from __future__ import annotations

import errno
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from railexu.cli import main
from railexu.cli.common import Terminated, stop_on_sigterm
from railexu.report.folder import MANIFEST, OutputFolder
from railexu.report.folder_check import (
    DamagedFolderError,
    IncompleteFolderError,
    check_output_folder,
)
from railexu.report.run_files import write_run

ROOT = Path(__file__).resolve().parents[1]
WHEELSET = ROOT / "vehicles" / "wheelset.yaml"
READERS = (["report"], ["plot"], ["animate", "--view", "plan", "--fps", "2"])


@pytest.fixture(scope="module")
def result():
    """The single wheelset over 0.3 m (a fraction of a second of integration)."""
    from railexu.results.run import RunSettings, run
    from railexu.track.track import ideal_straight_track
    from railexu.vehicle.vehicle import load_vehicle

    settings = RunSettings(speed_m_per_s=10.0, distance_m=0.3, initial_lateral_m=0.002)
    return run(load_vehicle(WHEELSET), ideal_straight_track(), settings)


@pytest.fixture(scope="module")
def complete(result, tmp_path_factory) -> Path:
    """A complete run folder (data only), copied by the tests that change it."""
    out = tmp_path_factory.mktemp("complete") / "run"
    write_run(result, out, plots=False)
    return out


def _copy(folder: Path, to: Path) -> Path:
    import shutil

    shutil.copytree(folder, to)
    return to


def _manifest(folder: Path) -> dict:
    return json.loads((folder / MANIFEST).read_text())


def _refused(folder: Path, capsys, what: str) -> None:
    """Every reader exits with 2 and one line naming ``what``."""
    for command in READERS:
        assert main([*command, str(folder)]) == 2, command
        err = capsys.readouterr().err.strip()
        assert what in err and "Traceback" not in err, (command, err)
        assert len(err.splitlines()) == 1, err


def _no_temporary_files(folder: Path) -> None:
    assert not [p.name for p in folder.iterdir() if ".tmp" in p.name]


def test_a_complete_folder_says_so_with_every_size(complete):
    manifest = _manifest(complete)
    assert manifest["complete"] is True and manifest["kind"] == "run"
    names = {"summary.json", "timeseries.csv", "state.npz"}
    assert set(manifest["files"]) == names
    for name in names:  # the sizes on disk, measured here
        assert manifest["sizes"][name] == (complete / name).stat().st_size
    assert check_output_folder(complete, "run", tuple(names))["complete"] is True


@pytest.mark.parametrize("where", ["timeseries", "summary"])
def test_sigterm_between_two_files_leaves_a_folder_marked_incomplete(
    result, complete, tmp_path, monkeypatch, capsys, where
):
    """SIGTERM while the data files are written (after the time series, before the state file)
    or just before the summary: the folder keeps the older run's summary and state beside the
    new time series, and says it is incomplete. (On main the new summary was written first,
    the signal ended the process at once and the folder claimed a completed run.)"""
    import railexu.report.run_files as run_files

    out = _copy(complete, tmp_path / "run")
    old_summary = (out / "summary.json").read_bytes()

    def kill_myself(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(2.0)  # the handler raises in the meantime
        raise AssertionError("SIGTERM was not handled")

    if where == "timeseries":
        monkeypatch.setattr(run_files, "_state_writer", lambda *a: kill_myself)
    else:
        monkeypatch.setattr(run_files, "write_summary", kill_myself)
    with pytest.raises(Terminated), stop_on_sigterm():
        write_run(result, out, plots=False)
    assert _manifest(out)["complete"] is False
    assert (out / "summary.json").read_bytes() == old_summary  # not a new claim
    _no_temporary_files(out)
    with pytest.raises(IncompleteFolderError, match="incomplete"):
        check_output_folder(out, "run")
    _refused(out, capsys, "incomplete")
    # the next job into the folder makes it complete again
    monkeypatch.undo()
    write_run(result, out, plots=False)
    assert _manifest(out)["complete"] is True


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EROFS, errno.EACCES])
def test_a_failed_write_leaves_the_folder_incomplete_with_a_clear_error(
    result, complete, tmp_path, monkeypatch, capsys, code
):
    """A full disk (ENOSPC), a file system remounted read-only (EROFS) or a folder made
    read-only (EACCES) while the time series is written: an InputError naming the file and the
    cause, no temporary file left, the folder marked incomplete."""
    from railexu.errors import InputError
    from railexu.simulation.timeseries import TimeSeries

    out = _copy(complete, tmp_path / "run")

    def fail(self, path, *a, **k):
        Path(path).write_bytes(b"half a row")  # what the disk took before it was full
        raise OSError(code, os.strerror(code), str(path))

    monkeypatch.setattr(TimeSeries, "to_csv", fail)
    with pytest.raises(InputError, match=os.strerror(code)) as info:
        write_run(result, out, plots=False)
    assert "marked incomplete" in str(info.value)
    assert _manifest(out)["complete"] is False
    _no_temporary_files(out)
    _refused(out, capsys, "incomplete")


def test_a_folder_that_cannot_be_marked_is_left_as_it_was(result, complete, tmp_path, monkeypatch):
    """The disk is full before the first byte: the manifest saying "incomplete" cannot be
    written, so nothing else is touched and the older, complete run stays readable."""
    import railexu.report.folder as folder_module
    from railexu.errors import InputError

    out = _copy(complete, tmp_path / "run")
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}

    def full(path: Path, manifest: dict) -> None:
        raise InputError(f"cannot write {path / MANIFEST}: {os.strerror(errno.ENOSPC)}")

    monkeypatch.setattr(folder_module, "_write_manifest", full)
    with pytest.raises(InputError, match="No space left"):
        write_run(result, out, plots=False)
    after = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    assert after == before
    monkeypatch.undo()
    assert check_output_folder(out, "run", ("timeseries.csv",))["complete"] is True


def test_a_folder_being_written_is_refused_by_readers_and_writers(complete, tmp_path, capsys):
    """Two processes on one folder: while one holds it (here: this process, through another
    open file, as a second process would), a reader and a second writer are refused."""
    out = _copy(complete, tmp_path / "run")
    writer = OutputFolder(out, "run").prepare()
    try:
        _refused(out, capsys, "another railexu process is writing")
        code = (
            "from railexu.report.folder import OutputFolder\n"
            f"OutputFolder({str(out)!r}, 'run').prepare()\n"
        )
        other = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        assert other.returncode != 0 and "another railexu process" in other.stderr
    finally:
        writer.release()
    assert check_output_folder(out, "run")["complete"] is True


# -- damaged folders ----------------------------------------------------------------------------


def _damage(folder: Path, name: str, data: bytes | str) -> None:
    path = folder / name
    if isinstance(data, str):
        path.write_text(data)
    else:
        path.write_bytes(data)


@pytest.mark.parametrize(
    "name, data, readers, what",
    [
        ("state.npz", b"", ["animate"], "state.npz"),
        ("state.npz", "cut", ["animate"], "state.npz"),
        ("summary.json", "{not json", ["report", "plot"], "summary.json"),
        ("summary.json", "[1, 2]", ["report", "plot"], "summary.json"),
        ("summary.json", "typed", ["report", "plot"], "status.distance_m"),
        ("timeseries.csv", "cut", ["report", "plot"], "timeseries.csv"),
        ("timeseries.csv", None, ["report", "plot"], "missing"),
        (MANIFEST, "{not json", ["report", "plot", "animate"], MANIFEST),
        (MANIFEST, '{"files": 3}', ["report", "plot", "animate"], MANIFEST),
    ],
)
def test_a_damaged_run_folder_is_refused_naming_the_file(
    complete, tmp_path, capsys, name, data, readers, what
):
    out = _copy(complete, tmp_path / "run")
    if data is None:
        (out / name).unlink()
    elif data == "cut":  # a file cut short: the first half of it
        raw = (out / name).read_bytes()
        _damage(out, name, raw[: len(raw) // 2])
    elif data == "typed":  # JSON, but a distance that is text
        summary = json.loads((out / name).read_text())
        summary["status"]["distance_m"] = "far"
        _damage(out, name, json.dumps(summary))
    else:
        _damage(out, name, data)
    if name in (MANIFEST, "timeseries.csv"):  # found by the folder's check itself
        with pytest.raises(DamagedFolderError, match=what):
            check_output_folder(out, "run", ("timeseries.csv",))
    commands = {c[0]: c for c in READERS}
    for reader in readers:
        assert main([*commands[reader], str(out)]) == 2, reader
        err = capsys.readouterr().err.strip()
        assert what in err and "Traceback" not in err, (reader, err)
        assert len(err.splitlines()) == 1, err


def test_a_damaged_state_file_is_an_input_error(complete, tmp_path):
    from railexu.errors import InputError
    from railexu.report.state_file import load_state

    for data in (b"", b"PK\x03\x04 not a zip", (complete / "state.npz").read_bytes()[:1000]):
        path = tmp_path / "state.npz"
        path.write_bytes(data)
        with pytest.raises(InputError, match="state.npz"):
            load_state(path)


STUDY = """\
format_version: 1
name: damaged
base:
  vehicle: {vehicle}
  run: {{distance: 0.3 m}}
vary:
  parameters:
    run.speed: [8 m/s, 12 m/s]
"""


@pytest.mark.parametrize(
    "table",
    [
        b"\xff\xfe\x00garbage\x00\x81",  # not text
        "case_id,status,case_hash\nc1,completed,abc\nthis,row,has,too,many\nc2,completed,d\n",
    ],
)
def test_a_garbage_results_table_is_refused_by_report_and_resume(tmp_path, capsys, table):
    """A study's results.csv that is not text, or has a damaged row in its middle (not a last
    line cut by an interrupted write, which resume repairs): report, plot and resume refuse it."""
    spec = tmp_path / "study.yaml"
    spec.write_text(textwrap.dedent(STUDY.format(vehicle=WHEELSET)))
    out = tmp_path / "out"
    out.mkdir()
    (out / "study.json").write_text("{}")
    if isinstance(table, bytes):
        (out / "results.csv").write_bytes(table)
    else:
        (out / "results.csv").write_text(table)
    for command in (["report"], ["plot"]):
        assert main([*command, str(out)]) == 2, command
        err = capsys.readouterr().err
        assert "results.csv" in err and "Traceback" not in err, err
    assert main(["study", str(spec), "--out", str(out), "--workers", "0", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "results.csv" in err and "Traceback" not in err


def test_the_next_job_removes_temporary_files_a_killed_one_left(complete, tmp_path):
    out = _copy(complete, tmp_path / "run")
    left = [out / ".timeseries.4242.tmp.csv", out / ".state.4243.tmp.npz"]
    for path in left:
        path.write_bytes(b"half")
    OutputFolder(out, "run").prepare().release()
    assert not any(p.exists() for p in left)
    assert (out / "timeseries.csv").exists()


# -- a real `railexu run` killed while it writes --------------------------------------------------

_KILLED_RUN = """\
import os, signal, sys, time
signal.signal(signal.SIGINT, signal.default_int_handler)
MAIN = os.getpid()
import railexu.report.run_files as run_files

def kill_main():
    os.kill(MAIN, signal.{signal})
    time.sleep(20)  # ended by the signal (or its parent's)

if {in_figure}:  # in a figure job: the warm process or its fork (both children of MAIN)
    original = run_files._save
    def _save(stem, build, formats):
        if stem.name == "wheel_load":
            kill_main()
        original(stem, build, formats)
    _save.__qualname__ = _save.__name__ = "_save"
    run_files._save = _save
else:  # in this process, after the time series, before the state file
    def _state_writer(result, path):
        return kill_main
    run_files._state_writer = _state_writer
from railexu.cli import entry_point
sys.argv = ["railexu", "run", {vehicle!r}, "--distance", "0.3", "--out", {out!r}, "--quiet"]
entry_point()
"""


def _group_gone(pgid: int, within_s: float) -> bool:
    deadline = time.monotonic() + within_s
    while time.monotonic() < deadline:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


@pytest.mark.parametrize(
    "sig, in_figure",
    [("SIGTERM", False), ("SIGINT", False), ("SIGTERM", True), ("SIGKILL", True)],
)
def test_railexu_run_killed_while_writing(complete, tmp_path, capsys, sig, in_figure):
    """``railexu run`` gets SIGTERM, SIGINT or SIGKILL while it writes its files (in its own
    writing, or sent from a figure job in the warm process): exit code 1 (interrupted; -9 for
    SIGKILL), no process of the command left within 10 s, the folder marked incomplete and
    refused by the readers. (On main: SIGTERM exited with 143 beside a summary that said
    completed, and a forked writer could outlive the command.)"""
    out = _copy(complete, tmp_path / "run")
    code = _KILLED_RUN.format(signal=sig, in_figure=in_figure, vehicle=str(WHEELSET), out=str(out))
    proc = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        start_new_session=True,
    )  # fmt: skip
    stdout, stderr = proc.communicate(timeout=300)
    expected = -signal.SIGKILL if sig == "SIGKILL" else 1
    assert proc.returncode == expected, stderr.decode()[-3000:]
    assert _group_gone(proc.pid, 10.0), "a child of railexu run outlived it"
    if sig != "SIGKILL":
        assert b"marked incomplete" in stderr and b"Traceback" not in stderr
        _no_temporary_files(out)
    assert _manifest(out)["complete"] is False
    _refused(out, capsys, "incomplete")


def test_railexu_run_terminated_while_integrating_writes_a_complete_folder(tmp_path, capsys):
    """SIGTERM during the integration: the run stops as interrupted, keeps its results and
    writes them; that folder is complete (it holds what its summary says: an interrupted run)
    and the readers accept it."""
    import re

    out = tmp_path / "run"
    args = ["railexu", "run", str(WHEELSET), "--distance", "1000", "--out", str(out)]
    code = f"import sys\nfrom railexu.cli import entry_point\nsys.argv = {args!r}\nentry_point()\n"
    proc = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        start_new_session=True,
    )  # fmt: skip
    progress = b""
    deadline = time.monotonic() + 300.0
    while time.monotonic() < deadline:
        chunk = proc.stderr.read1(4096)
        if not chunk:
            break
        progress += chunk
        done = [float(m) for m in re.findall(rb"(\d+\.\d) / 1000\.0 m", progress)]
        if done and done[-1] > 2.0:
            proc.send_signal(signal.SIGTERM)
            break
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 1, (progress + stderr).decode()[-3000:]
    assert _group_gone(proc.pid, 10.0)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"]["state"] == "interrupted"
    assert 2.0 < summary["status"]["distance_m"] < 1000.0
    assert _manifest(out)["complete"] is True
    _no_temporary_files(out)
    assert main(["report", str(out), "--quiet"]) == 0


def test_a_refused_run_leaves_no_folder_behind(tmp_path, capsys):
    """Bad input found after the folder was prepared (a vehicle file with an unknown key) is
    refused with exit 2, and the folder the job created for it, with its parents, is gone; an
    existing folder stays."""
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nunknown_key: 1\n", encoding="utf-8")
    out = tmp_path / "new" / "run"
    assert main(["run", str(bad), "--out", str(out), "--quiet", "--no-plots"]) == 2
    assert "unknown_key" in capsys.readouterr().err
    assert not (tmp_path / "new").exists()
    kept = tmp_path / "kept"
    kept.mkdir()
    assert main(["run", str(bad), "--out", str(kept), "--quiet", "--no-plots"]) == 2
    assert kept.is_dir()


def test_a_folder_prepared_and_released_untouched_is_removed_only_if_created(tmp_path):
    made = tmp_path / "a" / "b"
    OutputFolder(made, "run").prepare().release()
    assert not (tmp_path / "a").exists()
    with OutputFolder(made, "run") as folder:  # a job that writes: kept and complete
        folder.write_text("x.txt", "1")
    assert (made / "x.txt").is_file() and _manifest(made)["complete"] is True
