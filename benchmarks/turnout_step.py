"""Step-independence of the turnout's peak wheel-rail forces (issue 29): the same run at
several integration steps, each output recorded, and per rail of the panel side the raw
largest Q and Y and those of the signal low-passed at 20 Hz (EN 14363's filter of the
quasi-static and the ``Y_max``/``Q_max`` estimates: ``railexu.assessment.filters.lowpass``).

Run: ``python benchmarks/turnout_step.py [--vehicles eu07,hbbins_loaded] [--route
diverging_facing] [--panels switch] [--steps 0.4e-3,0.2e-3] [--save DIR]``. Window: every
wheelset's samples inside the panel (``benchmarks/turnout_vehicles.panel_ranges``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from turnout_vehicles import ROOT, panel_ranges  # noqa: E402

from railexu.assessment.filters import lowpass  # noqa: E402
from railexu.results.run import RunSettings, run  # noqa: E402
from railexu.track.track import load_track  # noqa: E402
from railexu.vehicle.vehicle import load_vehicle  # noqa: E402

LOWPASS_HZ = 20.0


def peaks(ts, n_ws: int, side: str, lo: float, hi: float) -> dict[str, list[float]]:
    """Per rail (1, 2): raw and 20 Hz low-passed maxima of Q and |Y| [N] inside ``lo .. hi``."""
    fs = 1.0 / float(np.median(np.diff(np.asarray(ts["time_s"]))))
    out = {k: [0.0, 0.0] for k in ("Q_raw", "Q_lp20", "Y_raw", "Y_lp20")}
    for i in range(1, n_ws + 1):
        s = np.asarray(ts[f"ws{i}_s_m"])
        win = (s >= lo) & (s <= hi)
        if not np.any(win):
            continue
        for r in (1, 2):
            q = np.asarray(ts[f"ws{i}_{side}_rail{r}_Q_N"])
            y = np.abs(np.asarray(ts[f"ws{i}_{side}_rail{r}_Y_N"]))
            for name, sig in (("Q", q), ("Y", y)):
                out[f"{name}_raw"][r - 1] = max(out[f"{name}_raw"][r - 1], float(sig[win].max()))
                lp = lowpass(sig, fs, LOWPASS_HZ)[win]
                out[f"{name}_lp20"][r - 1] = max(out[f"{name}_lp20"][r - 1], float(lp.max()))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", default="eu07,hbbins_loaded")
    ap.add_argument("--route", default="diverging_facing")
    ap.add_argument("--panels", default="switch", choices=("both", "switch", "crossing"))
    ap.add_argument("--steps", default="0.4e-3,0.2e-3")
    ap.add_argument("--save", type=Path, default=None)
    a = ap.parse_args()
    file = ROOT / "tracks" / f"turnout_uk_r245_{a.route}.yaml"
    sets = [f"turnout.panels={a.panels}", "turnout.approach=60 m"]
    print(f"{a.route}, panels {a.panels}, 10 m/s; max over the wheelsets, kN: rail 1, rail 2")
    for name in a.vehicles.split(","):
        vehicle = load_vehicle(ROOT / "vehicles" / f"{name}.yaml")
        x = [w.position_x_m for w in vehicle.wheelsets]
        lo, hi = load_track(file, sets).variable_rails.zone_m()
        track = load_track(file, [*sets, f"start={lo - 3.0 - (max(x) - min(x))} m"])
        for step in (float(v) for v in a.steps.split(",")):
            settings = RunSettings(speed_m_per_s=10.0, distance_m=hi - lo + 5.0 + max(x) - min(x),
                                   initial_lateral_m=0.0, time_step_s=step,
                                   output_interval_s=step)  # fmt: skip
            result = run(vehicle, track, settings)
            ts = result.timeseries
            for panel, (side, p_lo, p_hi, _) in panel_ranges(track).items():
                p = peaks(ts, len(vehicle.wheelsets), side, p_lo, p_hi)
                cells = "  ".join(f"{k} {v[0] / 1e3:6.1f} {v[1] / 1e3:6.1f}" for k, v in p.items())
                print(f"{name:14s} {step * 1e3:5.2f} ms {result.status['state']:9s} {panel:8s} "
                      f"{side:5s} {cells}", flush=True)  # fmt: skip
            if a.save is not None:
                a.save.mkdir(parents=True, exist_ok=True)
                keep = {k: np.asarray(ts[k]) for k in ts.names
                        if k == "time_s" or k.endswith("_s_m") or "_rail" in k}  # fmt: skip
                np.savez_compressed(a.save / f"{name}_{a.route}_{step * 1e3:g}ms.npz", **keep)


if __name__ == "__main__":
    main()
