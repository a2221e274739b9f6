"""One wear step of a 10-section route on 2 cores, and what the wear output costs a run.

Printed:

- one step of the wear loop (``railexu.study.wear.loop.wear_loop``, ``max_steps=1``) of the
  loaded wagon (``hbbins_loaded``) on ``studies/wear/curvy_10.yaml`` (a straight and nine
  curves in both directions: 19 cases, one study through ``run_study``) on 2 local worker
  processes, and the same with the free wheelset (the vehicle of the tests): wall time, cases,
  the time per case and the real-time factor (wall time over the simulated time of the cases,
  their distances over their speeds, summed: below 1 is faster than real time);
- a run of the wagon on the R 300 m case with and without ``contact_outputs`` (the recording the
  wear needs) and the wear post-processing of that run (``railexu.results.wear.run_wear``): the
  run's cost with the wear output off is unchanged by construction (nothing is computed), the
  recording and the post-processing are the price of it.

Run: ``python benchmarks/wear.py`` (a few minutes on 2 cores; other load makes it slower).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ROUTE = ROOT / "studies" / "wear" / "curvy_10.yaml"


def one_step(vehicle: str, workers: int) -> None:
    from railexu.study.wear.loop import wear_loop
    from railexu.study.wear.route import load_route

    route = load_route(ROUTE)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        result = wear_loop(vehicle, ROUTE, 1e6, Path(tmp) / "out", workers=workers, max_steps=1,
                           rate_tolerance=None)  # fmt: skip
        wall = time.perf_counter() - t0
    n = len(route.cases)
    row = result.steps[-1]
    simulated = sum(c.distance_m / c.speed_m_per_s for c in route.cases)
    print(f"{vehicle}: one wear step, {n} cases on {workers} processes: {wall:.1f} s "
          f"({wall / n:.2f} s a case), {simulated:.1f} s simulated: real-time factor "
          f"{wall / simulated:.2f}; step {row['step_km']:.4g} km")  # fmt: skip


def output_cost() -> None:
    from railexu.operation.run_settings import RunSettings
    from railexu.results.run import run
    from railexu.results.wear import run_wear
    from railexu.study.wear.route import load_route
    from railexu.track.track import load_track
    from railexu.vehicle.vehicle import load_vehicle

    route = load_route(ROUTE)
    case = next(c for c in route.cases if c.name == "R300" and c.direction == "forward")
    vehicle = load_vehicle("hbbins_loaded")
    with tempfile.TemporaryDirectory() as tmp:
        track = load_track(case.write_track(route, Path(tmp)))
        times = {}
        for outputs in (False, True, False, True):
            s = RunSettings(speed_m_per_s=case.speed_m_per_s, distance_m=case.distance_m,
                            contact_outputs=outputs)  # fmt: skip
            t0 = time.perf_counter()
            result = run(vehicle, track, s)
            times.setdefault(outputs, []).append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        run_wear(result.timeseries, vehicle, evaluate_from_m=case.evaluate_from_m)
        post = time.perf_counter() - t0
    off, on = min(times[False]), min(times[True])
    print(f"wagon R300 case ({case.distance_m:.0f} m): run {off:.2f} s without contact outputs, "
          f"{on:.2f} s with ({(on / off - 1) * 100:+.1f} %); wear and RCF post-processing "
          f"{post:.2f} s")  # fmt: skip


if __name__ == "__main__":
    output_cost()
    one_step("wheelset", 2)
    one_step("hbbins_loaded", 2)
