"""The outer wheel's flange contact in the turnout's R 245 m circle, on the plain rail (issue 29).

The diverging route's geometry (``tracks/turnout_uk_r245_diverging_facing.yaml``) with the plain
rail everywhere (the track's ``variable_rails`` removed, as ``benchmarks/turnout.py``'s plain
run): the curvature starts abruptly at the switch's toe. The vehicle runs from 13 m before the
zone to 3 m beyond it at 10 m/s with every step recorded; printed, for each wheel of the leading
wheelset in three windows of the circle (its first 0.5 s, 0.5-1.5 s, 1.5 s to the circle's end):
the range of Q, its rms above 20 Hz (Q minus its 20 Hz low pass), the frequency of that part's
largest spectral peak and the raw over 20 Hz maximum; and the solver's step facts. A sustained
oscillation shows as rms above 20 Hz of kilonewtons in the steady window.

Run: ``python benchmarks/turnout_circle.py [vehicle] [--time-step 0.4e-3]`` (default: the loaded
Hbbins at 0.4 ms; docs/switches-and-crossings.md, "The R 245 m circle on the current kernel").
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from railexu.assessment.filters import lowpass
from railexu.results.run import RunSettings, run
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
TRACK = ROOT / "tracks" / "turnout_uk_r245_diverging_facing.yaml"
WINDOWS_S = ((0.0, 0.5), (0.5, 1.5), (1.5, np.inf))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("vehicle", nargs="?", default="hbbins_loaded")
    ap.add_argument("--time-step", type=float, default=0.4e-3, help="s")
    a = ap.parse_args()
    vehicle = load_vehicle(ROOT / "vehicles" / f"{a.vehicle}.yaml")
    lo, hi = load_track(TRACK, []).variable_rails.zone_m()
    track = replace(load_track(TRACK, [f"start={lo - 13.0} m"]), variable_rails=None)
    settings = RunSettings(speed_m_per_s=10.0, distance_m=hi - lo + 15.0, initial_lateral_m=0.0,
                           time_step_s=a.time_step, output_interval_s=a.time_step)  # fmt: skip
    result = run(vehicle, track, settings)
    ts = result.timeseries
    print(f"{a.vehicle}, {a.time_step * 1e3:g} ms: {result.status['state']}, solver "
          f"{ {k: v for k, v in result.summary['solver'].items() if 'step' in k} }")  # fmt: skip
    t, s = np.asarray(ts["time_s"]), np.asarray(ts["ws1_s_m"])
    circle = np.array([abs(track.alignment.curvature(float(v))) > 0.0 for v in s])
    if not circle.any():
        print("the leading wheelset never reached the circle")
        return
    t0, fs = t[circle][0], 1.0 / a.time_step
    for side in ("left", "right"):
        q = np.asarray(ts[f"ws1_{side}_Q_N"])
        q20 = lowpass(q, fs, 20.0)
        for lo_s, hi_s in WINDOWS_S:
            m = circle & (t >= t0 + lo_s) & (t < t0 + hi_s)
            if m.sum() < 16:
                continue
            high = q[m] - q20[m]
            peak = np.fft.rfftfreq(m.sum(), 1.0 / fs)[np.argmax(np.abs(np.fft.rfft(high)))]
            print(f"  ws1 {side:5s} {lo_s:.1f}-{min(hi_s, t[circle][-1] - t0):.1f} s: Q "
                  f"{q[m].min() / 1e3:6.1f}-{q[m].max() / 1e3:6.1f} kN, rms above 20 Hz "
                  f"{high.std() / 1e3:6.2f} kN, peak {peak:5.0f} Hz, raw / 20 Hz max "
                  f"{q[m].max() / q20[m].max():.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
