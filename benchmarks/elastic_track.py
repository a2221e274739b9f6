"""Flange-impact forces on rigid and elastic track against the time step (``docs/curving.md``,
section "Elastic track").

Case (issue 9): the EU07 bogie without its car body (``vehicles/eu07_bogie.yaml``) at 45 m/s on
ideal straight track, 2 mm initial offset; it hunts in a limit cycle with flange contact on
both rails. For each track model and time step (the time series recorded at every step) it
prints, over the evaluation window (from ``--from`` m to the end; every wheel):

- ``raw``: the largest unfiltered |Y| of any recorded sample;
- ``p99.9``: the 99.9 % percentile of the unfiltered |Y| samples;
- ``lp20``: the largest |Y| after EN 14363's 20 Hz low-pass (``railexu.assessment.filters``),
  the processing EN 14363:2016 applies to wheel-rail forces before any statistic;
- ``sumY``: EN 14363's track-shifting force as the run's summary gives it (2 m sliding means
  of the low-passed sum Y, larger magnitude of the 0.15 / 99.85 % percentiles);
- ``Y/Q``: EN 14363's derailment quotient (99.85 % of the 2 m means of low-passed Y/Q);
- ``rail``: the largest lateral spring force of a rail, ``k_y |dy|`` (elastic track);
- ``amp``: the leading wheelset's largest lateral displacement (the limit cycle's amplitude);
- ``hf``: the largest rms over the wheels of what the 20 Hz low-pass removes from Y (raw minus
  low-passed), and ``f_hf`` the dominant frequency of that remainder [Hz]: the rail masses'
  vibration on the contact (a self-excited one in steady flange contact, docs/curving.md);
- the run's wall time (the machine is shared: compare within one call only).

``--vehicle eu07 --track curve_r300`` runs the whole locomotive at 150 mm cant deficiency in
the 300 m curve instead (the leading outer wheel on its flange, a vehicle in service).

Run: ``python benchmarks/elastic_track.py [--steps 0.5 0.25 0.125] [--distance 120]
[--tracks rigid elastic] [--rail-mass 150] [--lateral-damping 1e5] [--vertical-damping 1e5]
[--friction 0.3]`` (a run of the bogie over 120 m takes 5-20 s, of the EU07 in the curve 10-70 s).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from railexu.assessment.en14363 import LOWPASS_HZ
from railexu.assessment.filters import lowpass
from railexu.results.run import RunSettings, run
from railexu.track.track import load_track, track_from_dict
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
G = 9.80665


def _track(kind: str, name: str, changes: dict):
    """The straight ideal track or a shipped track file, rigid or with the elastic defaults
    (``changes``: ElasticTrack fields to set instead)."""
    if name == "straight":
        data = {"format_version": 1, "name": "straight"}
        track = track_from_dict(data)
    else:
        track = load_track(ROOT / "tracks" / f"{name}.yaml")
    if kind == "rigid":
        return track
    from dataclasses import replace

    from railexu.track.elastic import ElasticTrack

    return replace(track, elastic=replace(ElasticTrack(), **changes))


def _statistics(result, start_m: float, k_y: float | None) -> dict[str, float]:
    """The statistics listed in the module docstring, forces in kN."""
    ts = result.timeseries
    x = np.asarray(ts["ws1_s_m"])
    t = np.asarray(ts["time_s"])
    fs = 1.0 / float(np.median(np.diff(t)))
    inside = x >= start_m
    n_ws = len(result.vehicle.wheelsets)
    raw, lp, samples, rail, hf, f_hf = 0.0, 0.0, [], 0.0, 0.0, float("nan")
    for i in range(1, n_ws + 1):
        for side in ("left", "right"):
            y = np.asarray(ts[f"ws{i}_{side}_Y_N"])
            raw = max(raw, float(np.max(np.abs(y[inside]))))
            samples.append(np.abs(y[inside]))
            low = lowpass(y, fs, LOWPASS_HZ)
            lp = max(lp, float(np.max(np.abs(low[inside]))))
            rest = (y - low)[inside]
            if float(np.std(rest)) > hf:
                hf = float(np.std(rest))
                spectrum = np.abs(np.fft.rfft(rest - np.mean(rest)))
                f_hf = float(np.fft.rfftfreq(rest.size, 1.0 / fs)[int(np.argmax(spectrum))])
            if k_y is not None:
                dy = np.asarray(ts[f"ws{i}_{side}_rail_lateral_m"])
                rail = max(rail, k_y * float(np.max(np.abs(dy[inside]))))
    s = result.summary
    return {
        "raw": raw / 1e3,
        "p99.9": float(np.percentile(np.concatenate(samples), 99.9)) / 1e3,
        "lp20": lp / 1e3,
        "sumY": (s["max_sum_Y_N"]["value"] or float("nan")) / 1e3,
        "Y/Q": s["max_Y_over_Q"]["value_en14363"] or float("nan"),
        "rail": rail / 1e3 if k_y is not None else float("nan"),
        "amp": 1e3 * float(np.max(np.abs(np.asarray(ts["ws1_lateral_m"])[inside]))),
        "hf": hf / 1e3,
        "f_hf": f_hf,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=float, nargs="+", default=[0.5, 0.25, 0.125],
                        help="time steps [ms]")  # fmt: skip
    parser.add_argument("--tracks", nargs="+", default=["rigid", "elastic"])
    parser.add_argument("--vehicle", default="eu07_bogie")
    parser.add_argument("--track", default="straight", help="straight or a file in tracks/")
    parser.add_argument("--distance", type=float, default=120.0, help="[m]")
    parser.add_argument("--from", dest="start", type=float, default=20.0, help="[m]")
    parser.add_argument("--speed", type=float, default=None, help="[m/s] (default: the case's)")
    parser.add_argument("--rail-mass", type=float, default=None, help="[kg] (default: schema)")
    parser.add_argument("--lateral-damping", type=float, default=None, help="[N s/m]")
    parser.add_argument("--vertical-damping", type=float, default=None, help="[N s/m]")
    parser.add_argument("--friction", type=float, default=None, help="wheel-rail friction [-]")
    args = parser.parse_args()
    changes = {
        name: value
        for name, value in (
            ("rail_mass_kg", args.rail_mass),
            ("lateral_damping_N_s_per_m", args.lateral_damping),
            ("vertical_damping_N_s_per_m", args.vertical_damping),
        )
        if value is not None
    }

    vehicle = load_vehicle(ROOT / "vehicles" / f"{args.vehicle}.yaml")
    if args.friction is not None:
        from dataclasses import replace

        vehicle = replace(vehicle, contact=replace(vehicle.contact, friction=args.friction))
    if args.speed is not None:
        speed = args.speed
    elif args.track == "curve_r300":
        speed = math.sqrt((0.15 + 0.15) * G * 300.0 / 1.5)  # 150 mm cant deficiency, 24.3 m/s
    else:
        speed = 45.0
    initial = 0.002 if args.track == "straight" else 0.0
    print(f"{vehicle.name} on {args.track} at {speed:.1f} m/s, {args.distance:g} m, "
          f"statistics from {args.start:g} m (forces in kN)")  # fmt: skip
    columns = ("raw", "p99.9", "lp20", "sumY", "Y/Q", "rail", "amp", "hf", "f_hf")
    print(f"{'track':8s} {'h [ms]':>7s} " + " ".join(f"{c:>7s}" for c in columns) + "  wall [s]")
    for kind in args.tracks:
        track = _track(kind, args.track, changes)
        k_y = track.elastic.lateral_stiffness_N_per_m if track.elastic is not None else None
        for h_ms in args.steps:
            h = h_ms * 1e-3
            settings = RunSettings(speed_m_per_s=speed, distance_m=args.distance,
                                   initial_lateral_m=initial, time_step_s=h,
                                   output_interval_s=h)  # fmt: skip
            t0 = time.perf_counter()
            result = run(vehicle, track, settings)
            wall = time.perf_counter() - t0
            state = result.status["state"]
            stats = _statistics(result, args.start, k_y)
            line = " ".join(f"{stats[c]:7.3g}" for c in columns)
            print(f"{kind:8s} {h_ms:7.4g} {line}  {wall:7.1f}  {state}", flush=True)


if __name__ == "__main__":
    main()
