"""Real-time factors of the shipped vehicles on the seed scenario (10 m/s, 2 mm, 150 m).

For each vehicle the whole ``railexu run`` command is timed as a new process (Python start-up,
imports, loading the compiled kernels, building the model, the integration, writing the time
series, the summary and the plots), and the integration alone is read from its summary.

    real-time factor = simulated time / wall-clock time  (15 s simulated here)

Run: ``python benchmarks/realtime.py`` (timings vary by tens of percent between runs; the first
run of a fresh installation also compiles the kernels and is not representative).

``python benchmarks/realtime.py --curve`` compares the integration time of the EU07 in the R 600 m
curve (``tracks/curve_r600.yaml``, 20 m/s, 500 m: transition, curve, transition) with the same
distance on ideal straight track, both from the seed's 2 mm initial offset (the budget: a curved
run costs at most 25 % more). From a centred start the straight run is cheaper only because
nothing moves on ideal straight track (one Newton iteration per step).
"""

from __future__ import annotations

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
        sys.executable, "-c", "import sys; from railexu.cli import main; sys.exit(main())", "run",
        str(ROOT / "vehicles" / f"{vehicle}.yaml"),
        "--speed", str(speed), "--distance", str(distance), "--initial-lateral", lateral,
        "--out", str(out), "--quiet", *extra,
    ]  # fmt: skip
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
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


def main() -> None:
    if "--curve" in sys.argv[1:]:
        curve_case()
        return
    simulated = DISTANCE / SPEED
    with tempfile.TemporaryDirectory() as tmp:
        run_once("wheelset", Path(tmp) / "warm-up")  # load/compile the kernels once
        print(f"seed scenario: {SPEED:g} m/s, {DISTANCE:g} m ({simulated:g} s simulated)")
        print(f"{'vehicle':12s} {'whole command':>22s} {'integration only':>22s}")
        for name in VEHICLES:
            best = None
            for k in range(2):
                wall, summary = run_once(name, Path(tmp) / f"{name}{k}")
                if best is None or wall < best[0]:
                    best = (wall, summary)
            wall, summary = best
            integration = summary["timings_s"]["integration_s"]
            print(
                f"{name:12s} {wall:7.2f} s = {simulated / wall:5.1f}x real time "
                f"{integration:7.2f} s = {simulated / integration:5.1f}x"
            )


if __name__ == "__main__":
    main()
