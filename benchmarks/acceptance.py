"""The wall time of a whole acceptance programme (``railexu acceptance``) and the share of the
machine it used.

Runs the full programme of its category for a vehicle (default: the EU07 and the locomotive
programme; ``--quick`` for the reduced one) on local workers into a new folder, and prints:

- the wall time, the number of sections and the simulated distance;
- the sum of the sections' own run times (``run_time_s`` of every zone's ``results.csv``)
  divided by (wall time x workers): the share of the workers' ceiling spent running sections
  (the rest: workers' start-up, the evaluation, the figures, the quasi-static tests).

Run: ``python benchmarks/acceptance.py [VEHICLE] [--quick] [--workers N]`` (the EU07's full
programme: minutes on 2 cores). Timings belong here, never in tests.
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import tempfile
import time
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("vehicle", nargs="?", default="eu07")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()

    from railexu.study.acceptance import run_acceptance

    out = Path(tempfile.mkdtemp(prefix="railexu-acceptance-bench-"))
    t0 = time.perf_counter()
    result = run_acceptance(args.vehicle, out, quick=args.quick, workers=args.workers,
                            progress=lambda line: print(line, file=sys.stderr))  # fmt: skip
    wall = time.perf_counter() - t0
    busy, sections, distance = 0.0, 0, 0.0
    for zone in result.data["zones"].values():
        folder = Path(zone["study"]["folder"])
        with open(folder / "results.csv", newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
        busy += sum(float(r["run_time_s"] or 0.0) for r in rows)
        sections += len(rows)
        for s in zone.get("sections", []):
            distance += float(s["window_m"][1])
    print(f"vehicle {args.vehicle}, {'quick' if args.quick else 'full'} programme, "
          f"{args.workers} workers")  # fmt: skip
    print(f"  sections              {sections}")
    print(f"  simulated distance    {distance / 1000.0:.1f} km")
    print(f"  wall time             {wall:.1f} s")
    print(f"  sections' own time    {busy:.1f} s")
    print(f"  share of the ceiling  {busy / (wall * args.workers):.2f} "
          "(sections' time / (wall x workers))")  # fmt: skip
    print(f"  verdict               {result.verdict}")
    print(f"  output                {out}")


if __name__ == "__main__":
    main()
