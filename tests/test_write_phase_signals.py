"""Issue 26 (part 3): a signal between the end of the integration and the complete manifest.

``railexu run`` marks its folder incomplete before the run starts; a SIGTERM or SIGINT after the
integration (in the assessment), while the files are written, or while the manifest is
finished leaves ``"complete": false`` and exit code 1 (README: 1 for a stopped run); one after
the complete manifest leaves the complete folder of the run and exit code 1. A SIGKILL there
leaves ``"complete": false``. A run that fails before writing anything leaves the older
folder as it was. What is checked is outside the code: the files on disk, the manifest, the
exit codes, what the readers accept.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from railexu.cli import main
from railexu.report.folder import MANIFEST

ROOT = Path(__file__).resolve().parents[1]
WHEELSET = str(ROOT / "vehicles" / "wheelset.yaml")
RUN = ["run", WHEELSET, "--distance", "0.3", "--quiet", "--no-plots", "--no-helper-processes"]


@pytest.fixture(scope="module")
def older(tmp_path_factory) -> Path:
    """The complete folder of an older run, copied by each test (so that a stop that left it
    claiming complete would be seen)."""
    out = tmp_path_factory.mktemp("older") / "run"
    assert main([*RUN, "--out", str(out)]) == 0
    return out


def _manifest(folder: Path) -> dict:
    return json.loads((folder / MANIFEST).read_text())


def _kill_myself(sig=signal.SIGTERM):
    def hook(*args, **kwargs):
        os.kill(os.getpid(), sig)
        time.sleep(5.0)  # the handler raises meanwhile
        raise AssertionError("the signal was not handled")

    return hook


def _run(out: Path, capsys) -> tuple[int, str]:
    # Ctrl-C as a terminal delivers it: a process started in the background of a
    # non-interactive shell inherits SIGINT ignored, and then Python raises nothing for it
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        status = main([*RUN, "--out", str(out)])
    finally:
        signal.signal(signal.SIGINT, previous)
    return status, capsys.readouterr().err


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_in_the_assessment_leaves_the_folder_marked_incomplete(
    older, tmp_path, monkeypatch, capsys, sig
):
    """After the integration, before any file: the older complete folder must not keep
    claiming to be complete (it is not this run's)."""
    import railexu.results.run as results_run

    out = shutil.copytree(older, tmp_path / "run")
    old_summary = (out / "summary.json").read_bytes()
    monkeypatch.setattr(results_run, "assess", _kill_myself(sig))
    status, err = _run(out, capsys)
    assert status == 1, err
    assert "before the results were written" in err and "marked incomplete" in err
    assert "Traceback" not in err
    assert _manifest(out)["complete"] is False
    assert (out / "summary.json").read_bytes() == old_summary  # nothing claimed
    assert main(["report", str(out), "--quiet"]) == 2
    assert "incomplete" in capsys.readouterr().err


def test_a_signal_while_the_manifest_is_finished_leaves_it_incomplete(
    older, tmp_path, monkeypatch, capsys
):
    from railexu.report.folder import OutputFolder

    out = shutil.copytree(older, tmp_path / "run")
    monkeypatch.setattr(OutputFolder, "finish", _kill_myself())
    status, err = _run(out, capsys)
    assert status == 1 and "while writing the results" in err, err
    assert _manifest(out)["complete"] is False


def test_a_signal_after_the_complete_manifest_keeps_the_complete_run(
    older, tmp_path, monkeypatch, capsys
):
    """The folder holds what it says (this run, completed); the command says it was
    terminated and exits with 1."""
    import railexu.cli.run as cli_run

    out = shutil.copytree(older, tmp_path / "run")
    (out / "summary.json").unlink()  # so that the new one is seen to be written
    monkeypatch.setattr(cli_run, "format_summary", _kill_myself())
    status, err = _run(out, capsys)
    assert status == 1 and "terminated (SIGTERM)" in err, err
    manifest = _manifest(out)
    assert manifest["complete"] is True
    for name, size in manifest["sizes"].items():
        assert (out / name).stat().st_size == size, name
    assert json.loads((out / "summary.json").read_text())["status"]["state"] == "completed"
    assert main(["report", str(out), "--quiet"]) == 0


def test_a_run_failing_before_writing_leaves_the_older_folder_as_it_was(older, tmp_path, capsys):
    """An initial offset of 30 mm puts a wheel up its flange: refused after the folder was
    marked; nothing was written, so the older complete folder is put back as it was."""
    out = shutil.copytree(older, tmp_path / "run")
    before = (out / MANIFEST).read_bytes()
    status = main([*RUN, "--initial-lateral", "30 mm", "--out", str(out)])
    err = capsys.readouterr().err
    assert status in (1, 2) and "Traceback" not in err, err
    assert (out / MANIFEST).read_bytes() == before


_SIGNALLED_RUN = """\
import os, signal, sys, time
signal.signal(signal.SIGINT, signal.default_int_handler)
MAIN = os.getpid()
import railexu.results.run as results_run
import railexu.report.run_files as run_files

def kill_main(*args, **kwargs):
    os.kill(MAIN, signal.{signal})
    time.sleep(20)

if {where!r} == "assessment":  # after the integration, before the files
    results_run.assess = kill_main
else:  # in this process's own writing: after the time series, before the state file
    run_files._state_writer = lambda result, path: kill_main
from railexu.cli import entry_point
sys.argv = ["railexu", "run", {vehicle!r}, "--distance", "0.3", "--out", {out!r}, "--quiet"]
entry_point()
"""


@pytest.mark.parametrize(
    ("sig", "where"),
    [("SIGTERM", "assessment"), ("SIGINT", "assessment"), ("SIGKILL", "assessment"),
     ("SIGKILL", "writing")],
)  # fmt: skip
def test_railexu_run_signalled_after_the_integration(older, tmp_path, sig, where):
    """The command as users start it (with its helper processes): exit 1 (-9 for SIGKILL),
    the folder marked incomplete, no process of the command left within 10 s. (SIGTERM and
    SIGINT while writing: tests/test_folder_contract.py.)"""
    out = shutil.copytree(older, tmp_path / "run")
    code = _SIGNALLED_RUN.format(signal=sig, vehicle=WHEELSET, out=str(out), where=where)
    proc = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        start_new_session=True, env={**os.environ, "PYTHONPATH": str(ROOT / "src")},
    )  # fmt: skip
    _, stderr = proc.communicate(timeout=300)
    expected = -signal.SIGKILL if sig == "SIGKILL" else 1
    assert proc.returncode == expected, stderr.decode()[-3000:]
    assert _manifest(out)["complete"] is False
    if sig != "SIGKILL":
        assert b"marked incomplete" in stderr and b"Traceback" not in stderr
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline:
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        raise AssertionError("a child of railexu run outlived it")
