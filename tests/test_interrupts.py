"""From Python, an interrupt interrupts (issue 26): a script's loop of runs stops at Ctrl-C or
SIGTERM, with the interrupted run's results attached to the exception; a study stopped by
either exits 130 with its finished cases kept, no worker left running and no leaked semaphore;
the switch that turns the helper processes off gives the same files.

Each case runs in a subprocess (a signal to this test process would stop the test run), with
the single wheelset over a few metres; the signal is sent once the subprocess reports progress,
so no timing is assumed."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
WHEELSET = ROOT / "vehicles" / "wheelset.yaml"
LIMIT_S = 300.0  # a loaded test machine: only to never hang

# the subprocess gets the default handlers of an interactive process: a shell's background job
# (the test run's, maybe) ignores SIGINT, and Python keeps an ignored signal ignored
PREAMBLE = (
    "import signal\n"
    "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
    "signal.signal(signal.SIGTERM, signal.SIG_DFL)\n"
)

LOOP = PREAMBLE + textwrap.dedent(
    f"""\
    import railexu
    from railexu.errors import RunInterrupted

    vehicle = railexu.load_vehicle({str(WHEELSET)!r})
    told = []

    def progress(distance, total, speed, eta):
        if distance > 1.0 and not told:
            told.append(distance)
            print("integrating", flush=True)

    try:
        for i in (1, 2):
            print(f"run {{i}}", flush=True)
            try:
                railexu.run(vehicle, None, railexu.RunSettings(distance_m=400.0), progress)
            except Exception as exc:  # a loop that carries on after a failed run
                print(f"carried on after {{exc!r}}", flush=True)
    except RunInterrupted as exc:
        status = exc.result.status
        print(f"stopped: {{type(exc).__name__}} {{status['state']}} "
              f"{{status['distance_m']:.1f}} {{len(exc.result.timeseries.distance_m)}}", flush=True)
        raise
    """
)


def _read_until(stream, pattern: bytes, limit_s: float = LIMIT_S) -> bytes:
    """What ``stream`` gives until ``pattern`` appears (or it ends, or the limit is reached)."""
    seen = b""
    deadline = time.monotonic() + limit_s
    while time.monotonic() < deadline and not re.search(pattern, seen):
        chunk = stream.read1(4096)
        if not chunk:
            break
        seen += chunk
    return seen


@pytest.mark.parametrize("signame", ["SIGINT", "SIGTERM"])
def test_a_loop_of_runs_stops_at_a_signal(tmp_path, signame):
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.Popen(
        [sys.executable, "-c", LOOP], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
        start_new_session=True,
    )  # fmt: skip
    try:
        seen = _read_until(proc.stdout, rb"integrating")
        assert b"integrating" in seen, seen.decode()
        proc.send_signal(getattr(signal, signame))
        stdout, stderr = proc.communicate(timeout=LIMIT_S)
    finally:
        if proc.poll() is None:
            proc.kill()
    out = (seen + stdout).decode()
    assert "run 2" not in out and "carried on" not in out, out + stderr.decode()
    kind = "RunTerminated" if signame == "SIGTERM" else "RunInterrupted"
    match = re.search(rf"stopped: {kind} interrupted ([\d.]+) (\d+)", out)
    assert match, out + stderr.decode()
    assert 0.9 < float(match.group(1)) < 400.0  # the interrupted run's result, attached
    assert int(match.group(2)) > 1  # its time series up to the stop
    assert proc.returncode != 0  # the script ended with the exception uncaught


def _session_processes(sid: int) -> list[int]:
    """The processes still alive in session ``sid`` (zombies are gone: only their entry is)."""
    found = []
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat") as fh:
                fields = fh.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if fields[0] != "Z" and int(fields[3]) == sid:
            found.append(int(name))
    return found


@pytest.mark.parametrize("signame", ["SIGINT", "SIGTERM"])
def test_a_study_stopped_by_a_signal_exits_130_and_keeps_its_finished_cases(tmp_path, signame):
    """Ctrl-C reaches the study's whole process group (as at a terminal); SIGTERM only its
    main process (as ``kill PID`` or ``timeout``). Either way: exit code 130 as the docs say,
    the finished case in results.csv, no worker or fork server left, no leaked semaphore."""
    study = tmp_path / "study.yaml"
    study.write_text(
        textwrap.dedent(
            f"""\
            format_version: 1
            name: interrupted
            base:
              vehicle: {WHEELSET}
              run: {{initial_lateral: 2 mm}}
            vary:
              parameters:
                run.distance: [2 m, 400 m, 401 m]
            """
        )
    )
    out = tmp_path / "out"
    code = PREAMBLE + (
        "import sys\n"
        "from railexu.cli import entry_point\n"
        f"sys.argv = ['railexu', 'study', {str(study)!r}, '--out', {str(out)!r}, "
        "'--workers', '1', '--no-plots']\n"
        "entry_point()\n"
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
        start_new_session=True,
    )  # fmt: skip
    try:
        seen = _read_until(proc.stderr, rb"1/3 cases")
        assert b"1/3 cases" in seen, seen.decode()
        if signame == "SIGINT":
            os.killpg(proc.pid, signal.SIGINT)
        else:
            proc.send_signal(signal.SIGTERM)
        stdout, stderr = proc.communicate(timeout=LIMIT_S)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    text = (seen + stderr).decode()
    assert proc.returncode == 130, text
    assert "interrupted; 1 finished case(s) are kept" in text, text
    assert "leaked" not in text, text
    rows = (out / "results.csv").read_text().splitlines()
    assert len(rows) == 2 and ",completed," in rows[1], rows  # the header and the first case
    deadline = time.monotonic() + 30.0  # the fork server ends when it sees the study gone
    while _session_processes(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _session_processes(proc.pid) == []


def _stop_first_child(proc: subprocess.Popen) -> None:
    """SIGSTOP the first child of ``proc`` (its warm process) as soon as it exists."""
    pid = proc.pid
    deadline = time.monotonic() + LIMIT_S
    while time.monotonic() < deadline and proc.poll() is None:
        try:
            with open(f"/proc/{pid}/task/{pid}/children") as fh:
                found = fh.read().split()
        except OSError:
            found = []
        if found:
            os.kill(int(found[0]), signal.SIGSTOP)
            return
        time.sleep(0.002)


def test_the_helper_switch_gives_the_same_files(tmp_path):
    """``railexu run`` with its helper processes (the warm process, the figure writers), with
    ``--no-helper-processes``, with ``RAILEXU_HELPER_PROCESSES=0`` and with its warm process
    stopped (a helper starved of processor time): the same time series, figures and summary,
    byte for byte (but the timings), and no run waits for ever."""
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    env.pop("RAILEXU_HELPER_PROCESSES", None)
    # the helpers start however busy the test machine is (railexu.runtime.helpers.free_core)
    code = (
        "import railexu.runtime.helpers as helpers\n"
        "helpers.free_core = lambda *args, **kwargs: True\n"
        "from railexu.cli import entry_point\n"
        "entry_point()\n"
    )
    base = [sys.executable, "-c", code, "run", "wheelset", "--distance", "3", "--quiet"]
    outs = [tmp_path / name for name in ("on", "option", "environment", "starved")]
    for out, extra, more_env in (
        (outs[0], [], {}),
        (outs[1], ["--no-helper-processes"], {}),
        (outs[2], [], {"RAILEXU_HELPER_PROCESSES": "0"}),
        (outs[3], [], {}),
    ):
        proc = subprocess.Popen(
            [*base, *extra, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            env={**env, **more_env},
        )  # fmt: skip
        if out.name == "starved":
            # its warm process gets no processor time at all (stopped as soon as it exists):
            # the run must not wait for it (before issue 26 it waited for ever)
            _stop_first_child(proc)
        try:
            _, stderr = proc.communicate(timeout=LIMIT_S)
        finally:
            if proc.poll() is None:
                proc.kill()
        assert proc.returncode == 0, stderr.decode()
    names = sorted(p.name for p in outs[0].iterdir() if not p.name.startswith("."))
    assert "timeseries.csv" in names and any(n.endswith(".png") for n in names)

    def summary(out: Path) -> dict:
        data = json.loads((out / "summary.json").read_text())
        for key in ("timings_s", "realtime_factor"):
            data.pop(key, None)
        # wall-clock time in the force function, and when the contacts' threads started (they
        # wait for the warm process's imports): facts of the run's process, not results
        for key in ("force_function_s", "contact_threads_from_s"):
            data["solver"].pop(key, None)
        return data

    for other in outs[1:]:
        assert sorted(p.name for p in other.iterdir() if not p.name.startswith(".")) == names
        for name in names:
            if name != "summary.json":
                assert (other / name).read_bytes() == (outs[0] / name).read_bytes(), name
        assert summary(other) == summary(outs[0])
    bad = subprocess.run(
        [*base, "--out", str(tmp_path / "bad")], capture_output=True, timeout=LIMIT_S,
        env={**env, "RAILEXU_HELPER_PROCESSES": "maybe"},
    )  # fmt: skip
    assert bad.returncode == 2 and b"RAILEXU_HELPER_PROCESSES" in bad.stderr
