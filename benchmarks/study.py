"""How a study scales: 16 runs one by one in this process against 2 local worker processes.

The study: the seed scenario (the EU07 from a 2 mm offset on 150 m of ideal straight track) at
16 speeds from 10 to 25 m/s (no plots). Printed:

- the 16 runs one after the other in this process (``workers=0``; this process has run one case
  before, so its imports and compiled kernels are loaded, as a long session's would be), with
  the wheelsets' contacts on one thread (``RAILEXU_THREADS=1``), as in a study's workers;
- the same study on 2 local worker processes (started for the study: their start-up, imports and
  kernel loading are in the time), and the speed-up (issue 11's budget: at least 1.8x on 2
  cores);
- the 16 runs one by one with the contacts on threads (``railexu.runtime.threads``, the
  default outside a study), against which 2 workers gain less: one run then already uses
  part of the second core;
- the median time of a case inside the workers against the same case as function calls in this
  process (``run`` and ``write_run`` without plots, as a case does, on one thread; workers stay
  warm: a case must not cost more there), and the call on threads.

- the machine's own limit: a fixed compiled loop (no railexu, no Exudyn) timed alone and as two
  copies in two processes at once. If two copies each run slower than one alone, no study can
  reach 2x on this machine (shared caches, memory bandwidth, a virtual machine's cores); the
  printed ceiling is 2 divided by that slowdown.

Run: ``python benchmarks/study.py`` (about two minutes on 2 cores; a machine with other load gives
smaller speed-ups).
"""

from __future__ import annotations

import os
import statistics
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

STUDY = f"""
format_version: 1
name: scaling benchmark
analysis: run
base:
  vehicle: {ROOT / "vehicles" / "eu07.yaml"}
  run: {{distance: 150 m, initial_lateral: 2 mm}}
vary:
  parameters:
    run.speed: {{from: 10 m/s, to: 25 m/s, step: 1 m/s}}
collect:
  - max_abs_lateral_force_N
"""


def _busy_loop(_job: int = 0) -> float:
    """A fixed compiled workload (a few MB of arrays, like a run's tables); its wall time."""
    import numba
    import numpy as np

    @numba.njit(cache=False)
    def work(a, n):
        acc = 0.0
        for _ in range(n):
            for i in range(a.size):
                acc += a[i] * a[(i * 7) % a.size]
        return acc

    a = np.random.default_rng(0).random(400_000)
    work(a, 1)  # compile
    t0 = time.perf_counter()
    work(a, 60)
    return time.perf_counter() - t0


def machine_slowdown() -> float:
    """Wall time of the busy loop as one of two simultaneous processes over its time alone."""
    from concurrent.futures import ProcessPoolExecutor

    alone = _busy_loop()
    with ProcessPoolExecutor(2) as pool:
        list(pool.map(_busy_loop, [0, 1]))  # start and compile in both
        both = list(pool.map(_busy_loop, [0, 1]))
    return max(both) / alone


def main() -> None:
    from railexu import RunSettings, load_vehicle, run, threads, write_run
    from railexu.study import load_study, run_study

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "study.yaml"
        path.write_text(STUDY, encoding="utf-8")
        study = load_study(path)
        n = len(study.cases())
        vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
        settings = RunSettings(speed_m_per_s=17.0, distance_m=150.0, initial_lateral_m=0.002)
        write_run(run(vehicle, None, settings), Path(tmp) / "warm", plots=False)  # imports, kernels
        t0 = time.perf_counter()
        write_run(run(vehicle, None, settings), Path(tmp) / "threads", plots=False)
        call_threads = time.perf_counter() - t0
        t0 = time.perf_counter()
        run_study(study, Path(tmp) / "one_by_one_threads", workers=0)
        serial_threads = time.perf_counter() - t0
        # a study's workers run the contacts on one thread (railexu.runtime.threads): the scaling is
        # measured against the same runs on one thread
        os.environ[threads.ENV] = "1"
        t0 = time.perf_counter()
        write_run(run(vehicle, None, settings), Path(tmp) / "call", plots=False)
        call = time.perf_counter() - t0
        t0 = time.perf_counter()
        run_study(study, Path(tmp) / "one_by_one", workers=0)
        serial = time.perf_counter() - t0
        del os.environ[threads.ENV]
        t0 = time.perf_counter()
        result = run_study(study, Path(tmp) / "two_workers", workers=2)
        parallel = time.perf_counter() - t0
        in_worker = statistics.median(float(r["run_time_s"]) for r in result.rows)

    print(f"study of {n} runs (the seed scenario, EU07, 150 m, at 10-25 m/s)")
    print(f"  one by one in this process, one thread:    {serial:6.1f} s")
    print(f"  2 worker processes (one thread each):      {parallel:6.1f} s   "
          f"speed-up {serial / parallel:4.2f}x")  # fmt: skip
    print(f"  one by one in this process, contacts on threads: {serial_threads:6.1f} s "
          f"(2 workers: {serial_threads / parallel:4.2f}x faster)")  # fmt: skip
    print(f"  a case at 17 m/s as a function call (one thread): {call:5.2f} s; median case in a "
          f"worker: {in_worker:5.2f} s (ratio {in_worker / call:4.2f}); the call on threads: "
          f"{call_threads:5.2f} s")  # fmt: skip
    slowdown = machine_slowdown()
    print(
        f"  this machine: a compiled loop runs {slowdown:4.2f}x slower as one of two processes "
        f"than alone; ceiling of any 2-process speed-up {2.0 / slowdown:4.2f}x (the study "
        f"reached {100 * (serial / parallel) / (2.0 / slowdown):3.0f} % of it)"
    )


if __name__ == "__main__":
    main()
