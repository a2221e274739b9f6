"""``railexu run eu07`` with and without its helper processes, on an idle and a loaded machine
(issue 26: a run must never wait on a helper that gets no processor time).

The whole command (the console script, as a user types it) runs ``--reps`` times in each of
four settings, interleaved (on, off, on, off, ...), so that a change of the machine's load
during the benchmark affects both alike:

- *idle*: nothing of this benchmark runs beside the command;
- *loaded*: ``--loops`` (default 2) CPU-bound Python processes (``while True: pass``) run beside
  it, one per core of a 2-core machine: the helpers then compete for the processor;
- *starved*: nothing beside it, but the warm process is stopped (SIGSTOP) as soon as it is
  forked: the worst a machine can do to a helper (it gets no processor time at all; before
  issue 26 such a run never ended);
- *helpers on*: the default (the warm process, the forked figure writer);
- *helpers off*: ``RAILEXU_HELPER_PROCESSES=0`` (as ``--no-helper-processes``).

It prints each command's wall-clock time and processor time (its own and its children's,
``os.wait4``), the medians and the ratio *on / off* of the medians in each condition: below 1
the helpers save time, above 1 they cost time. Other work on the machine (other users, other
jobs) changes the absolute times: compare the ratios within one run of this script, not
times across runs. The contacts' threads (``RAILEXU_THREADS``) are left as the environment
sets them and printed.

Run: ``python benchmarks/loaded_machine.py [--reps 3] [--loops 2] [--vehicle eu07]
[--conditions idle,loaded,starved]``.
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the console script's code (railexu.console), run by this interpreter with this tree's package
CONSOLE = "from railexu.console import entry_point; entry_point()"
LOOP = "while True: pass"


def children(pid: int) -> list[int]:
    """The ids of the child processes of ``pid`` (Linux)."""
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as fh:
            return [int(p) for p in fh.read().split()]
    except OSError:
        return []


def stop_first_child(proc: subprocess.Popen, limit_s: float = 60.0) -> None:
    """Stop (SIGSTOP) the first child of ``proc`` as soon as it exists: the warm process, which
    then gets no processor time at all, as on a machine that starves it (none when the command
    started no helper: without a free core it starts none)."""
    end = time.monotonic() + limit_s
    while time.monotonic() < end:
        if _ended(proc.pid):
            return
        found = children(proc.pid)
        if found:
            os.kill(found[0], signal.SIGSTOP)
            return
        time.sleep(0.002)


def _ended(pid: int) -> bool:
    """Whether ``pid`` has exited (a zombie not yet reaped counts)."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] in ("Z", "X")
    except OSError:
        return True


def run_command(
    vehicle: str, out: Path, helpers: bool, starve: bool = False
) -> tuple[float, float, int]:
    """One ``railexu run VEHICLE``: (wall-clock s, processor s of it and its children, exit);
    ``starve``: its warm process is stopped as soon as it is forked."""
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    env["RAILEXU_HELPER_PROCESSES"] = "1" if helpers else "0"
    argv = [sys.executable, "-c", CONSOLE, "run", vehicle, "--quiet", "--out", str(out)]
    start = time.perf_counter()
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    if starve:
        stop_first_child(proc)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if proc.returncode != 0:
        print(f"  exit {proc.returncode}: {err.strip()[-300:]}", file=sys.stderr)
    # os.wait4's usage covers the command and its reaped children (the warm process, forks)
    return wall, usage.ru_utime + usage.ru_stime, proc.returncode


def start_loops(n: int) -> list[subprocess.Popen]:
    return [subprocess.Popen([sys.executable, "-c", LOOP]) for _ in range(n)]


def stop_loops(loops: list[subprocess.Popen]) -> None:
    for loop in loops:
        loop.kill()
        loop.wait()


CONDITIONS = ("idle", "loaded", "starved")


def measure(
    vehicle: str, reps: int, loops: int, folder: Path, conditions: tuple[str, ...] = CONDITIONS
) -> dict:
    """Wall and processor times per (condition, helpers), interleaved."""
    times: dict[tuple[str, bool], list[tuple[float, float]]] = {}
    # a first run loads numba's cache and the file system's: not counted
    run_command(vehicle, folder / "first", True)
    for condition in conditions:
        n_loops = loops if condition == "loaded" else 0
        running = start_loops(n_loops)
        try:
            time.sleep(0.5 if n_loops else 0.0)
            for rep in range(reps):
                for helpers in (True, False) if rep % 2 == 0 else (False, True):
                    out = folder / f"{condition}_{'on' if helpers else 'off'}_{rep}"
                    starve = helpers and condition == "starved"
                    wall, cpu, code = run_command(vehicle, out, helpers, starve)
                    times.setdefault((condition, helpers), []).append((wall, cpu))
                    state = "on " if helpers else "off"
                    print(f"  {condition:6s} helpers {state} rep {rep + 1}: {wall:7.2f} s wall, "
                          f"{cpu:7.2f} s CPU (exit {code})", flush=True)  # fmt: skip
        finally:
            stop_loops(running)
    return times


def report(times: dict, loops: int) -> None:
    print(f"\nmedians (interleaved; loaded = {loops} CPU-bound processes beside the command)")
    print(f"{'condition':10s} {'helpers on':>22s} {'helpers off':>22s} {'on/off wall':>12s}")
    for condition in CONDITIONS:
        on = times.get((condition, True), [])
        off = times.get((condition, False), [])
        if not on or not off:
            continue
        on_wall = statistics.median(w for w, _ in on)
        off_wall = statistics.median(w for w, _ in off)
        on_cpu = statistics.median(c for _, c in on)
        off_cpu = statistics.median(c for _, c in off)
        print(f"{condition:10s} {on_wall:8.2f} s ({on_cpu:6.2f} CPU) "
              f"{off_wall:8.2f} s ({off_cpu:6.2f} CPU) {on_wall / off_wall:12.2f}")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=3, help="runs per setting")
    parser.add_argument("--loops", type=int, default=2, help="CPU-bound processes when loaded")
    parser.add_argument("--vehicle", default="eu07", help="the vehicle of railexu run")
    parser.add_argument(
        "--conditions", default=",".join(CONDITIONS), help="which of idle,loaded,starved"
    )
    args = parser.parse_args(argv)
    print(f"railexu run {args.vehicle}: {os.cpu_count()} cores, load average "
          f"{os.getloadavg()[0]:.2f} at the start, RAILEXU_THREADS="
          f"{os.environ.get('RAILEXU_THREADS', '(not set)')}")  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="railexu-loaded-") as tmp:
        conditions = tuple(c.strip() for c in args.conditions.split(",") if c.strip())
        times = measure(args.vehicle, args.reps, args.loops, Path(tmp), conditions)
    report(times, args.loops)
    print(f"load average at the end: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
