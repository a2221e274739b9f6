"""Cost of the vertical alignment (issue 29): the EU07 on the seed scenario's plane track against
the same run over a sag and a crest (``tracks/gradient_sag_crest.yaml`` from 150 m, where the
sag begins, through the +15 per mille gradient).

Run: ``python benchmarks/vertical.py`` (both cases, interleaved, best of ``--repeat`` each) or
``python benchmarks/vertical.py --plane`` (the plane track only: run it in two trees to compare a
change's cost on the plane track). The processor time of the whole ``simulate`` call is
measured in this process on one contact thread (``RAILEXU_THREADS=1``), so that other work on a
shared machine changes it little; the integration's wall time from the run is printed beside
it. Compare the ratios of one run of this script, not absolute times across machines or days.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

os.environ.setdefault("RAILEXU_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]
SPEED_M_PER_S, DISTANCE_M = 10.0, 100.0


def run_case(track_name: str | None, start_m: float = 0.0) -> tuple[float, float, int]:
    """(processor seconds of simulate, integration wall seconds, Newton iterations)."""
    import dataclasses

    from railexu.operation.run_settings import RunSettings
    from railexu.simulation.simulate import simulate
    from railexu.track.track import ideal_straight_track, load_track
    from railexu.vehicle.vehicle import load_vehicle

    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
    track = ideal_straight_track() if track_name is None else load_track(track_name)
    if start_m:
        track = dataclasses.replace(track, start_m=start_m)
    settings = RunSettings(
        speed_m_per_s=SPEED_M_PER_S, distance_m=DISTANCE_M, initial_lateral_m=0.002
    )
    t0 = time.process_time()
    result = simulate(vehicle, track, settings)
    cpu = time.process_time() - t0
    assert result.status["state"] == "completed", result.status
    return cpu, result.timings_s["integration_s"], result.summary["solver"]["newton_iterations"]


def main() -> None:
    repeat = 2
    if "--repeat" in sys.argv:
        repeat = int(sys.argv[sys.argv.index("--repeat") + 1])
    cases = {"plane": (None, 0.0)}
    if "--plane" not in sys.argv:
        cases["sag and gradient"] = (str(ROOT / "tracks" / "gradient_sag_crest.yaml"), 150.0)
    run_case(None)  # load the compiled kernels once
    best: dict[str, tuple[float, float, int]] = {}
    for _ in range(repeat):
        for label, (track, start) in cases.items():
            got = run_case(track, start)
            best[label] = min(best.get(label, got), got)
    print(f"EU07, {SPEED_M_PER_S:g} m/s, {DISTANCE_M:g} m, one contact thread, best of {repeat}")
    for label, (cpu, wall, newton) in best.items():
        print(f"{label:18s} simulate {cpu:7.2f} s CPU, integration {wall:7.2f} s wall, "
              f"{newton} Newton iterations")  # fmt: skip
    if len(best) == 2:
        ratio = best["sag and gradient"][0] / best["plane"][0]
        print(f"vertical alignment / plane track (CPU): {ratio:.3f}")


if __name__ == "__main__":
    main()
