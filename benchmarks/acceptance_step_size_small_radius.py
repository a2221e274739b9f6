"""Step-size study of the coach programme's 250-400 m zone, section by section.

The quick programme's step study (``benchmarks/acceptance_step_size.py``) found the zone's
Y/Q, sum Y and Q_max depending on the step in the sections where the leading outer wheel runs
on its flange (docs/acceptance.md, "Step-size study"). This script re-runs sections of that
zone (``programmes/coach.yaml``, ``curve_very_small_radius``, the quick programme's sections:
R 250, 300, 350 and 400 m) at several steps, each section exactly as the programme runs it
(the straight lead, the 75 m transition, the rest of the 150 m run-in, the 70 m window), and
prints every quantity of every section at every step with its difference relative to the
finest step. The tolerances (1 % quasi-static, 5 % peaks) are those of docs/acceptance.md.

Run: ``python benchmarks/acceptance_step_size_small_radius.py [--sections 0,1,2]
[--steps 2,1,0.5] [--workers N] [--full] [--zone NAME]`` (steps in ms; ``--full``: indices of
the full programme's 50 sections instead of the quick programme's 4; ``--zone``: another zone).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

ZONE = "curve_very_small_radius"
OUTPUT_INTERVAL_S = 0.005
QUASI_STATIC = ("Y_qst", "Q_qst", "car_body_acc_y_qst")


def run_section(
    index: int, step_s: float, full: bool = False, zone_name: str = ZONE
) -> tuple[int, float, str, dict, float]:
    """Run section ``index`` of the quick (or with ``full`` the full) programme's zone
    ``zone_name`` at ``step_s``: (index, step, status, section values, wall time s)."""
    from railexu.assessment.acceptance.programme import load_programme
    from railexu.assessment.acceptance.quantities import section_values
    from railexu.operation.run_settings import RunSettings
    from railexu.results.run import run
    from railexu.study.acceptance.zone_study import section_distance_m, start_lead_m, zone_track
    from railexu.track.track import track_from_dict
    from railexu.vehicle.vehicle import load_vehicle

    zone = load_programme("coach", quick=not full).zone(zone_name)
    section = zone.sections()[index]
    vehicle = load_vehicle("manchester_coach_extended")
    track = track_from_dict(zone_track(zone, [section], start_lead_m(vehicle)))
    settings = RunSettings(speed_m_per_s=section.speed_m_per_s,
                           distance_m=section_distance_m(section), initial_lateral_m=0.0,
                           time_step_s=step_s, output_interval_s=OUTPUT_INTERVAL_S)  # fmt: skip
    t0 = time.perf_counter()
    result = run(vehicle, track, settings)
    wall = time.perf_counter() - t0
    state = result.status["state"]
    if state not in ("completed", "completed_with_exceedances"):
        return index, step_s, f"{state} at {result.status.get('distance_m', 0.0):.1f} m", {}, wall
    values = section_values(result.timeseries, vehicle, section).values
    return index, step_s, state, dict(values), wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sections", default="0,1,2", help="indices of the quick sections")
    parser.add_argument("--steps", default="2,1,0.5", help="time steps in ms, coarsest first")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--full", action="store_true", help="sections of the full programme")
    parser.add_argument("--zone", default=ZONE, help="another zone of the coach programme")
    args = parser.parse_args()
    sections = [int(s) for s in args.sections.split(",")]
    steps = [float(s) / 1000.0 for s in args.steps.split(",")]

    from railexu.assessment.acceptance.programme import load_programme

    specs = load_programme("coach", quick=not args.full).zone(args.zone).sections()
    jobs = [(i, s, args.full, args.zone) for i in sections for s in steps]
    results: dict[tuple[int, float], tuple[str, dict, float]] = {}
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        for index, step, state, values, wall in pool.map(run_section, *zip(*jobs, strict=True)):
            results[(index, step)] = (state, values, wall)
            print(f"section {index} step {step * 1000:g} ms: {state}, {wall:.0f} s wall",
                  file=sys.stderr, flush=True)  # fmt: skip
    for i in sections:
        s = specs[i]
        print(f"\n{s.name}: R {s.radius_m:g} m, cant deficiency {s.cant_deficiency_m * 1000:.0f}"
              f" mm, {s.speed_m_per_s:.2f} m/s")  # fmt: skip
        _print_section(i, steps, results)


def _print_section(i: int, steps: list[float], results: dict) -> None:
    print("  status: " + ", ".join(f"{s * 1000:g} ms {results[(i, s)][0]} "
                                    f"({results[(i, s)][2]:.0f} s)" for s in steps))  # fmt: skip
    header = "".join(f"{f'{s * 1000:g} ms':>12s}" for s in steps)
    diffs = "".join(f"{f'd{s * 1000:g} %':>9s}" for s in steps[:-1])
    print(f"  {'quantity':26s}{header}{diffs}  tol %")
    names = next((v[1].keys() for s in reversed(steps) if (v := results[(i, s)])[1]), ())
    for name in names:
        vals = [results[(i, s)][1].get(name, math.nan) for s in steps]
        ref = vals[-1] if len(vals) > 0 else math.nan
        rel = [100.0 * (v - ref) / abs(ref) if ref and math.isfinite(ref) else math.nan
               for v in vals[:-1]]  # fmt: skip
        tol = 1.0 if name in QUASI_STATIC else 5.0
        print(f"  {name:26s}" + "".join(f"{v:12.5g}" for v in vals)
              + "".join(f"{r:9.2f}" for r in rel) + f"  {tol:g}")  # fmt: skip


if __name__ == "__main__":
    main()
