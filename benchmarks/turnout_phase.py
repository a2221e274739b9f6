"""The loaded Hbbins' wing-rail peak before the nose against the time step's phase (issue 29).

The turnout's diverging route, facing, the loaded Hbbins at 10 m/s (as
``benchmarks/turnout_vehicles.py``): the same run with its start shifted along the track by a
fraction of the distance one time step covers (0.2 ms: 2 mm), so that the steps fall at other
places of the rails; per shift the largest wing-rail Q before the nose (the crossing panel's
slices' ``s < 0``, every wheelset) and the leading wheelset's samples around it. A peak that
moves with the shift is a property of the time stepping across the rails' geometry, not of the
rails (docs/switches-and-crossings.md, the turnout's "Cost", "The filter at the wheelset").

Run: ``python benchmarks/turnout_phase.py [--crossing-step-m 0.005] [--time-step 0.2e-3]
[--shifts-mm 0 0.5 1 1.5]`` (one run per shift, ~1-2 min each on 2 cores).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from turnout_vehicles import ROOT  # noqa: E402

from railexu.results.run import RunSettings, run  # noqa: E402
from railexu.track.track import load_track  # noqa: E402
from railexu.vehicle.vehicle import load_vehicle  # noqa: E402

SIDE = "right"  # the crossing's side on the diverging route


def wing_rail_peak(crossing_step_m: float, time_step_s: float, shift_m: float) -> dict:
    """One run with its start shifted by ``shift_m`` [m]: the wing rail's largest Q [N] before
    the nose, its wheelset and slices' ``s`` [m], and the leading wheelset's wing-rail Q [N]
    and ``s`` over the slices' ``s = -0.70 .. -0.67 m``."""
    vehicle = load_vehicle(ROOT / "vehicles" / "hbbins_loaded.yaml")
    file = ROOT / "tracks" / "turnout_uk_r245_diverging_facing.yaml"
    sets = ["turnout.panels=both", f"turnout.crossing_station_step={crossing_step_m} m",
            "turnout.approach=60 m"]  # fmt: skip
    x = [w.position_x_m for w in vehicle.wheelsets]
    wheelbase = max(x) - min(x)
    lo, hi = load_track(file, sets).variable_rails.zone_m()
    track = load_track(file, [*sets, f"start={lo - 3.0 - wheelbase + shift_m} m"])
    zone = track.variable_rails
    panel = zone.right.panels[1]  # the whole crossing's slices
    first = zone.start_m + panel.range_m[0]
    zero = first - panel.profile.positions_m[0]  # track distance of the slices' s = 0
    settings = RunSettings(speed_m_per_s=10.0, distance_m=hi - lo + 5.0 + wheelbase,
                           initial_lateral_m=0.0, time_step_s=time_step_s,
                           output_interval_s=time_step_s)  # fmt: skip
    ts = run(vehicle, track, settings).timeseries
    best = (0.0, 0, 0.0)
    for i in range(1, len(vehicle.wheelsets) + 1):
        s = np.asarray(ts[f"ws{i}_s_m"])
        q = np.asarray(ts[f"ws{i}_{SIDE}_rail2_Q_N"])  # rail 2: the wing rail
        inside = (s >= first) & (s < zero)
        k = int(np.argmax(np.where(inside, q, 0.0)))
        best = max(best, (float(q[k]), i, float(s[k] - zero)))
    s1 = np.asarray(ts["ws1_s_m"]) - zero
    near = (s1 > -0.700) & (s1 < -0.670)
    q1 = np.asarray(ts[f"ws1_{SIDE}_rail2_Q_N"])
    return {"peak_N": best[0], "wheelset": best[1], "s_m": best[2],
            "ws1_s_m": s1[near], "ws1_Q_N": q1[near]}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--crossing-step-m", type=float, default=0.005)
    ap.add_argument("--time-step", type=float, default=0.2e-3, help="[s]")
    ap.add_argument("--shifts-mm", type=float, nargs="+", default=[0.0, 0.5, 1.0, 1.5])
    a = ap.parse_args()
    print(f"loaded Hbbins, diverging facing, crossing stations {a.crossing_step_m * 1e3:g} mm, "
          f"{a.time_step * 1e3:g} ms; wing rail before the nose")  # fmt: skip
    for shift in a.shifts_mm:
        r = wing_rail_peak(a.crossing_step_m, a.time_step, shift * 1e-3)
        pairs = zip(r["ws1_s_m"], r["ws1_Q_N"], strict=True)
        trace = " ".join(f"{s * 1e3:.1f}:{q / 1e3:.0f}" for s, q in pairs)
        print(f"shift {shift:4.2f} mm: peak {r['peak_N'] / 1e3:6.1f} kN (ws{r['wheelset']}, "
              f"s {r['s_m'] * 1e3:+.1f} mm); ws1 [mm:kN] {trace}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
