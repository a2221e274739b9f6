"""Issue 28: the Manchester coach (extended) in R 300 m at 20 m/s, raw and filtered wheel forces
at two integration steps, and the run's cost.

Runs ``railexu run`` (a new process each, as a user runs it) for the coach in
``tracks/curve_r300.yaml`` started 30 m into the constant-radius curve (``track.start=200m``),
80 m, the time series every step (``--output-interval`` = step, so that the raw maxima are the
integration's own samples), at the steps given (default 1 ms and 0.25 ms), and prints per wheel
of the leading bogie, in the window 20-80 m of the run (steady curving, after the start's
transient):

- the raw maxima of Y, Q and Y/Q (the recorded samples), and the maxima of the same signals
  low-passed at 20 Hz (EN 14363's filter for the guiding forces, zero-phase Butterworth,
  ``railexu.assessment.filters.lowpass``), and the ratio raw / filtered;
- the EN 14363-processed values of ``summary.json`` (Y/Q, sum Y, wheel unloading: 2 m sliding
  means of the 20 Hz forces, their 99.85 % percentiles; the run's default window, from 8 m) and
  the quasi-static values (50 %);
- the run's real-time factor (simulated seconds per wall-clock second of the integration).

Run: ``python benchmarks/flange_root_chatter.py [--steps 1ms,0.25ms] [--out DIR]``. The
timings depend on the machine's load; compare the ratios of one run.
"""

from __future__ import annotations

import argparse
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SPEED_M_PER_S = 20.0
DISTANCE_M = 80.0
WINDOW_M = (20.0, 80.0)
CUTOFF_HZ = 20.0
WHEELS = ("ws1_left", "ws1_right", "ws2_left", "ws2_right")


def _seconds(text: str) -> float:
    return float(text[:-2]) * 1e-3 if text.endswith("ms") else float(text.rstrip("s"))


def run_case(step: str, folder: Path) -> dict:
    """One ``railexu run``; returns its summary."""
    command = [
        sys.executable, "-m", "railexu.cli", "run",
        str(ROOT / "vehicles" / "manchester_coach_extended.yaml"),
        "--track", str(ROOT / "tracks" / "curve_r300.yaml"),
        "--speed", str(SPEED_M_PER_S), "--distance", str(DISTANCE_M),
        "--set", "track.start=200m", "--step", step, "--output-interval", step,
        "--no-plots", "--quiet", "--out", str(folder),
    ]  # fmt: skip
    subprocess.run(command, check=True)
    return json.loads((folder / "summary.json").read_text())


def _read(folder: Path) -> dict[str, np.ndarray]:
    with open(folder / "timeseries.csv", newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        data = np.array([[float(v) for v in row] for row in reader])
    return {name: data[:, i] for i, name in enumerate(header)}


def wheel_maxima(folder: Path) -> dict[str, dict[str, float]]:
    """Raw and 20 Hz maxima of Y, Q, Y/Q per wheel in the window."""
    from railexu.assessment.filters import lowpass

    ts = _read(folder)
    t = ts["time_s"]
    fs = 1.0 / float(np.median(np.diff(t)))
    inside = (ts["distance_m"] >= WINDOW_M[0]) & (ts["distance_m"] <= WINDOW_M[1])
    out = {}
    for wheel in WHEELS:
        y_raw, q_raw = ts[f"{wheel}_Y_N"], ts[f"{wheel}_Q_N"]
        y_lp, q_lp = lowpass(y_raw, fs, CUTOFF_HZ), lowpass(q_raw, fs, CUTOFF_HZ)
        ratio_raw = np.abs(y_raw) / np.maximum(q_raw, 1.0)
        ratio_lp = np.abs(y_lp) / np.maximum(q_lp, 1.0)
        out[wheel] = {
            "Y_raw": float(np.max(np.abs(y_raw[inside]))),
            "Y_20Hz": float(np.max(np.abs(y_lp[inside]))),
            "Q_raw": float(np.max(q_raw[inside])),
            "Q_20Hz": float(np.max(q_lp[inside])),
            "Q_min_raw": float(np.min(q_raw[inside])),
            "YQ_raw": float(np.max(ratio_raw[inside])),
            "YQ_20Hz": float(np.max(ratio_lp[inside])),
        }
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", default="1ms,0.25ms")
    parser.add_argument("--out", default=None, help="keep the run folders here")
    args = parser.parse_args()
    base = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="railexu-issue28-"))
    for step in args.steps.split(","):
        folder = base / f"step_{step}"
        summary = run_case(step, folder)
        crit = summary["assessment"]["criteria"]
        rtf = DISTANCE_M / SPEED_M_PER_S / summary["timings_s"]["integration_s"]
        print(f"step {step} ({_seconds(step) * 1e3:g} ms): status {summary['status']['state']}, "
              f"integration {summary['timings_s']['integration_s']:.1f} s, "
              f"real-time factor {rtf:.3f}")  # fmt: skip
        print(f"  EN 14363: Y/Q {crit['y_over_q']['value']:.3f} ({crit['y_over_q']['where']}), "
              f"sum Y {crit['sum_y']['value'] / 1e3:.1f} kN, "
              f"wheel unloading {crit['wheel_unloading']['value']:.3f}")  # fmt: skip
        ws1 = summary["curving"]["curves"][0]["wheelsets"][0]
        print(f"  ws1 quasi-static: Y outer {ws1['Y_outer_N']['quasi_static'] / 1e3:.1f} kN, "
              f"Y/Q outer {ws1['Y_over_Q_outer']['quasi_static']:.3f}, "
              f"lateral {ws1['lateral_m']['quasi_static'] * 1e3:.2f} mm")  # fmt: skip
        print("  wheel      Y raw/20Hz [kN]   Q raw/20Hz [kN]  Q min raw  Y/Q raw/20Hz   ratios")
        for wheel, m in wheel_maxima(folder).items():
            print(f"  {wheel:9s} {m['Y_raw'] / 1e3:6.1f} /{m['Y_20Hz'] / 1e3:6.1f}   "
                  f"{m['Q_raw'] / 1e3:6.1f} /{m['Q_20Hz'] / 1e3:6.1f}   {m['Q_min_raw'] / 1e3:6.1f}"
                  f"    {m['YQ_raw']:.3f} / {m['YQ_20Hz']:.3f}   "
                  f"{m['Y_raw'] / m['Y_20Hz']:.2f} {m['Q_raw'] / m['Q_20Hz']:.2f} "
                  f"{m['YQ_raw'] / m['YQ_20Hz']:.2f}")  # fmt: skip
    print(f"run folders: {base}")


if __name__ == "__main__":
    main()
