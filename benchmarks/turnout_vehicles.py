"""Every shipped vehicle through the turnout's routes and directions (issue 29): the status of
each run, its largest vertical force per rail on the panel side and the integration time.

Run: ``python benchmarks/turnout_vehicles.py [--panels switch] [--step-m 0.2] [--vehicles a,b]
[--routes through_facing,diverging_trailing]`` (defaults: every vehicle in ``vehicles/``, the
four tracks, the switch panel only at 0.2 m stations: a quick pass; ``--panels both --step-m
0.05`` is the whole turnout). Each run starts on straight track 13 m before the first panel
met (a 10 m wheelbase started inside the R 245 m circle from the straight track's equilibrium
derails at once) and ends 3 m beyond the last, at 10 m/s, centred.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from railexu.results.run import RunSettings, run
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
ROUTES = ("through_facing", "through_trailing", "diverging_facing", "diverging_trailing")


def one(vehicle_name: str, route: str, sets: list[str]) -> str:
    """One run's line of the table."""
    vehicle = load_vehicle(ROOT / "vehicles" / f"{vehicle_name}.yaml")
    file = ROOT / "tracks" / f"turnout_uk_r245_{route}.yaml"
    x = [w.position_x_m for w in vehicle.wheelsets]
    wheelbase = max(x) - min(x)
    probe = load_track(file, [*sets, "turnout.approach=60 m"])
    lo, hi = probe.variable_rails.zone_m()
    track = load_track(file, [*sets, "turnout.approach=60 m", f"start={lo - 3.0 - wheelbase} m"])
    settings = RunSettings(speed_m_per_s=10.0, distance_m=hi - lo + 5.0 + wheelbase,
                           initial_lateral_m=0.0)  # fmt: skip
    result = run(vehicle, track, settings)
    ts = result.timeseries
    side = "left" if track.variable_rails.left is not None else "right"
    q = [max(float(np.max(ts[f"ws{i}_{side}_rail{r}_Q_N"])) for i in
             range(1, len(vehicle.wheelsets) + 1)) / 1e3 for r in (1, 2)]  # fmt: skip
    t = result.summary["timings_s"]["integration_s"]
    return (f"{vehicle_name:26s} {route:19s} {result.status['state']:10s} "
            f"{q[0]:7.1f} {q[1]:7.1f} {t:8.1f}")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--panels", default="switch", choices=("both", "switch", "crossing"))
    ap.add_argument("--step-m", type=float, default=0.2)
    ap.add_argument("--vehicles", default="")
    ap.add_argument("--routes", default=",".join(ROUTES))
    a = ap.parse_args()
    names = a.vehicles.split(",") if a.vehicles else sorted(
        p.stem for p in (ROOT / "vehicles").glob("*.yaml"))  # fmt: skip
    sets = [f"turnout.panels={a.panels}", f"turnout.station_step={a.step_m} m"]
    print(f"panels {a.panels}, stations every {a.step_m * 1e3:g} mm, 10 m/s")
    print(f"{'vehicle':26s} {'track':19s} {'state':10s} {'rail1 Q':>7s} {'rail2 Q':>7s} "
          f"{'integr.':>8s}  (max kN over the wheelsets on the panel side; s)")  # fmt: skip
    for name in names:
        for route in a.routes.split(","):
            print(one(name, route, sets), flush=True)


if __name__ == "__main__":
    main()
