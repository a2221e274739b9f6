"""Step-size study of an acceptance programme: does a verdict depend on the integration step?

Runs the programme of a vehicle (default: the extended Manchester coach, ``--quick``: the
reduced programme) twice, at the default step (2 ms) and at half of it, into two folders,
without the quasi-static tests (they do not integrate the track), and prints for every zone and
criterion the estimate at both steps, the difference relative to the default step's value and
relative to the limit, then the largest difference of every section value. The tolerances that
``docs/acceptance.md`` states on physical grounds are checked on a short case in
``tests/test_acceptance_step_size.py``.

Run: ``python benchmarks/acceptance_step_size.py [VEHICLE] [--quick] [--workers N]
[--out DIR]`` (the coach's quick programme: minutes on 2 cores).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

HALF_STEP = {"time_step": "1 ms", "output_interval": "5 ms"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("vehicle", nargs="?", default="manchester_coach_extended")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()

    from railexu.study.acceptance import run_acceptance

    out = args.out or Path(tempfile.mkdtemp(prefix="railexu-step-study-"))
    results = {}
    for label, settings in (("2 ms", None), ("1 ms", HALF_STEP)):
        t0 = time.perf_counter()
        results[label] = run_acceptance(
            args.vehicle, out / label.replace(" ", ""), quick=args.quick,
            workers=args.workers, quasi_static=False, run_settings=settings,
            progress=lambda line: print(line, file=sys.stderr),
        )  # fmt: skip
        print(f"step {label}: {time.perf_counter() - t0:.0f} s wall", file=sys.stderr)
    _print_criteria(results["2 ms"], results["1 ms"])
    _print_sections(results["2 ms"], results["1 ms"])
    print(f"folders: {out}")


def _print_criteria(coarse, fine) -> None:
    print(f"{'zone':26s} {'criterion':24s} {'2 ms':>11s} {'1 ms':>11s} {'diff %':>8s} "
          f"{'% limit':>8s}")  # fmt: skip
    for zone, result in coarse.zone_results.items():
        other = fine.zone_results.get(zone)
        if other is None:
            continue
        for name, c in result.criteria.items():
            v1, v2 = c.value, other.criteria[name].value
            if v1 is None or v2 is None or not (math.isfinite(v1) and math.isfinite(v2)):
                continue
            rel = 100.0 * (v2 - v1) / abs(v1) if v1 else math.nan
            lim = 100.0 * (v2 - v1) / abs(c.limit) if c.limit else math.nan
            print(f"{zone:26s} {name:24s} {v1:11.4g} {v2:11.4g} {rel:8.2f} {lim:8.2f}")


def _print_sections(coarse, fine) -> None:
    print("largest difference of a section value (relative to the 2 ms value):")
    worst: dict[str, float] = {}
    for zone, svs in coarse.section_values.items():
        for sv1, sv2 in zip(svs, fine.section_values.get(zone, []), strict=False):
            for name, v1 in sv1.values.items():
                v2 = sv2.values.get(name)
                if v2 is None or not (math.isfinite(v1) and math.isfinite(v2)) or v1 == 0.0:
                    continue
                worst[name] = max(worst.get(name, 0.0), abs(v2 - v1) / abs(v1))
    for name, rel in sorted(worst.items()):
        print(f"  {name:26s} {100.0 * rel:6.2f} %")


if __name__ == "__main__":
    main()
