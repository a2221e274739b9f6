"""A vehicle through the turnout against the same run on plain track (issue 29).

The same vehicle, speed and distance on the shipped turnout track (``tracks/turnout_uk_r245_*``:
switch and crossing panels, the route's geometry) and on the same geometry with the plain rail
everywhere (the track's ``variable_rails`` removed). Printed per run: the model's build (the
turnout's station tables, one per station and panel side), the integration and their sum, and
the ratios turnout / plain. Both runs in this process, the plain one first (the compiled
kernels loaded before either is timed: a warm-up run of 1 m first).

Run: ``python benchmarks/turnout.py [vehicle] [route] [direction] [--speed 10] [--step-m 0.05]``
(defaults: hbbins_loaded, diverging, facing, 10 m/s, the design's 50 mm stations). The run
starts 12 m before the first panel (the longest wagon's wheelbase) and ends 3 m beyond the last
rail of the turnout; ``--panels switch`` or ``crossing`` times a shorter zone. Timings vary by
tens of percent on a shared machine; compare the ratio of one run of this script.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

from railexu.results.run import RunSettings, run
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("vehicle", nargs="?", default="hbbins_loaded")
    ap.add_argument("route", nargs="?", default="diverging", choices=("through", "diverging"))
    ap.add_argument("direction", nargs="?", default="facing", choices=("facing", "trailing"))
    ap.add_argument("--speed", type=float, default=10.0, help="m/s")
    ap.add_argument("--step-m", type=float, default=None, help="station step [m]")
    ap.add_argument("--panels", default="both", choices=("both", "switch", "crossing"))
    a = ap.parse_args()
    vehicle = load_vehicle(ROOT / "vehicles" / f"{a.vehicle}.yaml")
    file = ROOT / "tracks" / f"turnout_uk_r245_{a.route}_{a.direction}.yaml"
    sets = [f"turnout.panels={a.panels}"]
    if a.step_m is not None:
        sets.append(f"turnout.station_step={a.step_m} m")
    lo, hi = load_track(file, sets).variable_rails.zone_m()
    start = lo - 13.0
    turnout = load_track(file, [*sets, f"start={start} m"])
    plain = replace(turnout, variable_rails=None)
    settings = RunSettings(speed_m_per_s=a.speed, distance_m=hi - lo + 15.0, initial_lateral_m=0.0)
    run(vehicle, plain, replace(settings, distance_m=1.0))  # warm-up: kernels loaded
    rows = {}
    for name, track in (("plain", plain), ("turnout", turnout)):
        t0 = time.perf_counter()
        result = run(vehicle, track, settings)
        whole = time.perf_counter() - t0
        t = result.summary["timings_s"]
        rows[name] = (t["build_s"], t["integration_s"], whole, result.status["state"])
    print(f"{a.vehicle}, {a.route} {a.direction}, {a.speed:g} m/s, {settings.distance_m:.1f} m, "
          f"zone {lo:.2f} .. {hi:.2f} m ({a.panels}), stations every "
          f"{turnout.variable_rails.station_step_m * 1e3:g} mm")  # fmt: skip
    print(f"{'':8s} {'build':>8s} {'integration':>12s} {'whole run':>10s}  state")
    for name, (b, i, w, state) in rows.items():
        print(f"{name:8s} {b:7.2f}s {i:11.2f}s {w:9.2f}s  {state}")
    (pb, pi, pw, _), (tb, ti, tw, _) = rows["plain"], rows["turnout"]
    print(f"ratio turnout / plain: build {tb / pb:.1f}, integration {ti / pi:.2f}, "
          f"whole run {tw / pw:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
