"""The four critical-speed methods compared on one vehicle, with the wall time of each (issue 28).

Run: ``python benchmarks/critical_speed_methods.py eu07_bogie OUT`` (or ``eu07``; a third
argument chooses methods, ``branch,ramp``; ``figure`` draws ``OUT/bifurcation_<vehicle>.png``
from the written results); writes
``OUT/<vehicle>_<method>.json`` (the method's section of ``critical_speed.json`` with its wall
time and the processor time of this process) as each method finishes, so that a long
comparison keeps what it has done. Settings (coarse, for a shared 2-core machine): runs and
plateaus of 300 m (150 m left the EU07 bogie at 45 m/s still settling onto its cycle from
above with the patch-centroid kernel: "decaying" 6.89 mm), 5 mm disturbance, branch steps of
5 m/s refined to 1.25 m/s, the ramp at the default 0.2 m/s^2 (and 0.4 m/s^2 as its rate check)
after 300 m of settling; the speed ranges
of docs/validation.md (EU07 bogie 20-45 m/s, EU07 25-55 m/s). The numbers are in
docs/validation.md ("EU07 bogie and EU07: the four methods"). Wall times depend on the machine's
load: compare them within one run of this script.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RANGES = {"eu07_bogie": (20.0, 45.0), "eu07": (25.0, 55.0)}


def settings_for(vehicle_name: str, method: str):
    from railexu.stability import CriticalSpeedSettings

    lo, hi = RANGES[vehicle_name]
    return CriticalSpeedSettings(
        methods=(method,),
        speed_min_m_per_s=lo,
        speed_max_m_per_s=hi,
        tolerance_m_per_s=1.25,
        initial_lateral_m=0.005,
        distance_m=300.0,
        linear_points=11,
        branch_step_m_per_s=5.0,
        max_runs=20,
        ramp_settle_m=300.0,
    )


def main(vehicle_name: str, out: Path, methods: list[str]) -> None:
    from railexu.jsonable import jsonable
    from railexu.stability import critical_speed
    from railexu.vehicle.vehicle import load_vehicle

    vehicle = load_vehicle(ROOT / "vehicles" / f"{vehicle_name}.yaml")
    out.mkdir(parents=True, exist_ok=True)
    for method in methods:
        wall, cpu = time.perf_counter(), time.process_time()
        result = critical_speed(vehicle, None, settings_for(vehicle_name, method),
                                progress=lambda m: print(f"  {m}", flush=True))  # fmt: skip
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        result["wall_time_s"], result["process_time_s"] = wall, cpu
        path = out / f"{vehicle_name}_{method}.json"
        path.write_text(json.dumps(jsonable(result), indent=1))
        print(f"{vehicle_name} {method}: {wall:.0f} s wall, {cpu:.0f} s processor", flush=True)


def figure(vehicle_name: str, out: Path) -> Path | None:
    """The bifurcation diagram of ``OUT/<vehicle>_{branch,linear,ramp}.json`` (the branch with
    the ramp's windows and the linear critical speed), written to
    ``OUT/bifurcation_<vehicle>.png``; None without a branch result."""
    from railexu.report.stability_figures import critical_speed_figures

    result: dict = {"vehicle": vehicle_name}
    for method in ("branch", "linear", "ramp"):
        path = out / f"{vehicle_name}_{method}.json"
        if path.exists():
            result[method] = json.loads(path.read_text()).get(method)
    if not result.get("branch"):
        return None
    fig = critical_speed_figures(result)["bifurcation_diagram"]
    target = out / f"bifurcation_{vehicle_name}.png"
    fig.savefig(target, dpi=90)
    return target


if __name__ == "__main__":
    name, folder = sys.argv[1], Path(sys.argv[2])
    if sys.argv[3:] == ["figure"]:
        print(figure(name, folder))
        sys.exit(0)
    chosen = sys.argv[3].split(",") if len(sys.argv) > 3 else ["linear", "branch", "ramp",
                                                               "bisection"]  # fmt: skip
    main(name, folder, chosen)
