"""Real-time factors of the shipped vehicles on the seed scenario (10 m/s, 2 mm, 150 m).

For each vehicle the whole ``railexu run`` command is timed as a new process (Python start-up,
imports, loading the compiled kernels, building the model, the integration, writing the time
series, the summary and the plots), and the integration alone is read from its summary.

    real-time factor = simulated time / wall-clock time  (15 s simulated here)

Run: ``python benchmarks/realtime.py`` (timings vary by tens of percent between runs; the first
run of a fresh installation also compiles the kernels and is not representative). The command
is started as the console script starts it (``railexu.cli.entry_point``), and railexu's Python
bytecode is compiled first, as any installation has it: where ``PYTHONDONTWRITEBYTECODE`` is
set (some sandboxes and CI images) every new process would otherwise compile railexu's
sources again, some 0.3 s that a user's installation does not pay.

``python benchmarks/realtime.py --curve`` compares the integration time of the EU07 in the R 600 m
curve (``tracks/curve_r600.yaml``, 20 m/s, 500 m: transition, curve, transition) with the same
distance on ideal straight track, both from the seed's 2 mm initial offset (the budget: a curved
run costs at most 25 % more). From a centred start the straight run is cheaper only because
nothing moves on ideal straight track (one Newton iteration per step).

For every vehicle it also prints where the time goes (issue 11's budget):

- *overhead*: the whole command minus the integration (Python start-up, imports, building the
  model, files, figures); the budget is 1 s;
- *force function*: the time inside the wheel-rail force function during the integration, and
  the number of its calls (from ``summary.json``);
- *contact floor*: Newton iterations x wheelsets x the compiled kernel's time per wheelset
  measured now by ``benchmarks/contact.py`` on its 120 states (the seed's law of each vehicle);
  the budget for the integration is 2.5 floors;
- *run-state floor*: Newton iterations x the force function's own time per call in this run
  (the same contact work on the states the run visits, where two-point and flange contacts
  cost more than the benchmark's mix; it includes the suspension elements' and bump stops'
  compiled forces and the call itself), and the integration divided by it: what the solver
  adds around the force evaluations (the extra residual per step, Jacobians, the recorder);
- *threads from*: the simulated time from which the wheelsets' contacts ran on threads
  (``railexu.runtime.threads``; ``railexu run`` starts them once its warm process has done its
  imports, ``-``: none, as for one wheelset);
- below the table, the EU07's command without figures (``--no-plots``): its overhead is the
  start-up, the assessment and the data files; the difference to the table's is what the six
  figures add at the end;
- the integration of the same run as a function call in this process (``railexu.run``
  from a script: no warm process, threads from the start) against the same floor;
- and the floor under the overhead on this machine (``benchmarks/overhead_floor.py``: the
  libraries' imports, numba's first call, the six figures' axes without data), to read the
  table's overhead against.
Compare the ratios of one run of this script, not absolute times across machines or days.
"""

from __future__ import annotations

import compileall
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VEHICLES = ("wheelset", "eu07_bogie", "eu07")
SPEED, DISTANCE = 10.0, 150.0


def run_once(vehicle: str, out: Path, *extra: str, speed: float = SPEED,
             distance: float = DISTANCE, lateral: str = "0.002") -> tuple[float, dict]:  # fmt: skip
    cmd = [
        # what the console script runs (railexu.console: BLAS's threads, the paused collector)
        sys.executable, "-c", "from railexu.console import entry_point; entry_point()", "run",
        str(ROOT / "vehicles" / f"{vehicle}.yaml"),
        "--speed", str(speed), "--distance", str(distance), "--initial-lateral", lateral,
        "--out", str(out), "--quiet", *extra,
    ]  # fmt: skip
    t0 = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode not in (0, 1):  # 1: completed with a safety limit exceeded
        raise RuntimeError(f"{' '.join(cmd)} ended with {done.returncode}:\n{done.stderr}")
    wall = time.perf_counter() - t0
    return wall, json.loads((out / "summary.json").read_text())


def curve_case() -> None:
    """EU07, 20 m/s, 500 m: R 600 m curve against straight track (best of two each)."""
    speed, distance = 20.0, 500.0
    tracks = {
        "straight": [],
        "curve R600": ["--track", str(ROOT / "tracks" / "curve_r600.yaml")],
    }
    with tempfile.TemporaryDirectory() as tmp:
        run_once("wheelset", Path(tmp) / "warm-up")
        print(f"EU07, {speed:g} m/s, {distance:g} m ({distance / speed:g} s simulated)")
        times = {}
        for label, extra in tracks.items():
            best = min(
                (summary["timings_s"]["integration_s"], summary["solver"]["newton_iterations"])
                for summary in (
                    run_once("eu07", Path(tmp) / f"{k}{label[:5]}", *extra, "--no-plots",
                             speed=speed, distance=distance)[1]
                    for k in range(2)
                )
            )  # fmt: skip
            times[label] = best[0]
            print(f"{label:12s} integration {best[0]:7.2f} s = {distance / speed / best[0]:5.1f}x"
                  f"  ({best[1]} Newton iterations)")  # fmt: skip
        extra_cost = times["curve R600"] / times["straight"] - 1.0
        print(f"curved track costs {100 * extra_cost:+.0f} % against straight track")


def _creep_law(vehicle: str) -> str:
    from railexu.vehicle.vehicle import load_vehicle

    return load_vehicle(ROOT / "vehicles" / f"{vehicle}.yaml").contact.creep_model


def compile_bytecode() -> None:
    """Compile railexu's modules to bytecode (``__pycache__``), as an installation has them."""
    import railexu

    compileall.compile_dir(Path(railexu.__file__).parent, quiet=1)


def main() -> None:
    compile_bytecode()
    if "--curve" in sys.argv[1:]:
        curve_case()
        return
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from contact import kernel_seconds_per_wheelset
    from overhead_floor import report as overhead_floor

    simulated = DISTANCE / SPEED
    kernel = {}
    with tempfile.TemporaryDirectory() as tmp:
        run_once("wheelset", Path(tmp) / "warm-up")  # load/compile the kernels once
        print(f"seed scenario: {SPEED:g} m/s, {DISTANCE:g} m ({simulated:g} s simulated), "
              "median of three whole commands")  # fmt: skip
        print(
            f"{'vehicle':11s} {'whole command':>20s} {'integration':>18s} {'overhead':>9s} "
            f"{'force function':>22s} {'floor':>8s} {'int/floor':>9s} "
            f"{'run-state floor':>15s} {'int/run floor':>13s} {'threads from':>12s}"
        )
        floors = {}
        overheads = {}
        for name in VEHICLES:
            runs = sorted(
                (run_once(name, Path(tmp) / f"{name}{k}") for k in range(3)), key=lambda r: r[0]
            )
            wall, summary = runs[1]
            law = _creep_law(name)
            if law not in kernel:
                kernel[law] = kernel_seconds_per_wheelset(law)
            integration = summary["timings_s"]["integration_s"]
            solver = summary["solver"]
            n_ws = _wheelsets(name)
            floor = solver["newton_iterations"] * n_ws * kernel[law]
            calls = solver.get("force_evaluations", 0)
            in_force = solver.get("force_function_s", float("nan"))
            run_floor = solver["newton_iterations"] * in_force / max(calls, 1)
            since = solver.get("contact_threads_from_s")
            since_text = "-" if since is None else f"{since:.2f} s"
            print(
                f"{name:11s} {wall:6.2f} s = {simulated / wall:5.1f}x  "
                f"{integration:6.2f} s = {simulated / integration:5.1f}x "
                f"{wall - integration:7.2f} s "
                f"{in_force:6.2f} s ({calls:6d} calls) "
                f"{floor:6.2f} s {integration / floor:8.1f}x "
                f"{run_floor:13.2f} s {integration / run_floor:12.1f}x {since_text:>12s}"
            )
            floors[name] = floor
            overheads[name] = wall - integration
        runs = sorted(
            (run_once("eu07", Path(tmp) / f"no-plots{k}", "--no-plots") for k in range(3)),
            key=lambda r: r[0],
        )
        wall, summary = runs[1]
        integration = summary["timings_s"]["integration_s"]
        print(
            f"eu07 without figures (--no-plots, median of three): {wall:.2f} s whole, "
            f"{integration:.2f} s integration, {wall - integration:.2f} s overhead; the figures "
            f"add {overheads['eu07'] - (wall - integration):.2f} s"
        )
        print("the same runs as function calls in this process (median of three):")
        for name in VEHICLES:
            integration, threads = in_process(name)
            print(
                f"{name:11s} integration {integration:6.2f} s = {integration / floors[name]:4.1f}"
                f" floors ({threads} thread{'s' if threads > 1 else ''})"
            )
        for law, seconds in kernel.items():
            print(f"contact kernel ({law}): {seconds * 1e6:.2f} us per wheelset evaluation")
    overhead_floor()


def in_process(vehicle: str) -> tuple[float, int]:
    """The integration time of the seed run as ``railexu.run`` in this process (median of three,
    after one run that loads everything) and its contact threads."""
    from railexu import RunSettings, load_vehicle, run

    v = load_vehicle(ROOT / "vehicles" / f"{vehicle}.yaml")
    settings = RunSettings(speed_m_per_s=SPEED, distance_m=DISTANCE, initial_lateral_m=0.002)
    run(v, None, RunSettings(speed_m_per_s=SPEED, distance_m=1.0))
    results = sorted(
        (r.summary["timings_s"]["integration_s"], r.summary["solver"]["contact_threads"])
        for r in (run(v, None, settings) for _ in range(3))
    )
    return results[1]


def _wheelsets(vehicle: str) -> int:
    from railexu.vehicle.vehicle import load_vehicle

    return len(load_vehicle(ROOT / "vehicles" / f"{vehicle}.yaml").wheelsets)


if __name__ == "__main__":
    main()
