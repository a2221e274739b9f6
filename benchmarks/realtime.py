"""Real-time factors of the shipped vehicles on the seed scenario (10 m/s, 2 mm, 150 m).

For each vehicle the whole ``railexu run`` command is timed as a new process (Python start-up,
imports, loading the compiled kernels, building the model, the integration, writing the time
series, the summary and the plots), and the integration alone is read from its summary.

    real-time factor = simulated time / wall-clock time  (15 s simulated here)

Run: ``python benchmarks/realtime.py`` (timings vary by tens of percent between runs; the first
run of a fresh installation also compiles the kernels and is not representative).
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


def run_once(vehicle: str, out: Path) -> tuple[float, dict]:
    cmd = [
        sys.executable, "-m", "railexu.cli", "run", str(ROOT / "vehicles" / f"{vehicle}.yaml"),
        "--speed", str(SPEED), "--distance", str(DISTANCE), "--initial-lateral", "0.002",
        "--out", str(out), "--quiet",
    ]  # fmt: skip
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    wall = time.perf_counter() - t0
    return wall, json.loads((out / "summary.json").read_text())


def main() -> None:
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
