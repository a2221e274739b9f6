"""A vehicle through the turnout against the same run on plain track (issue 29).

The same vehicle, speed and distance on the shipped turnout track (``tracks/turnout_uk_r245_*``:
switch and crossing panels, the route's geometry) and on the same geometry with the plain rail
everywhere (the track's ``variable_rails`` removed). Printed per run: the model's build (the
turnout's station tables, one per station and panel side), the integration and their sum, and
the ratios turnout / plain. Both runs in this process, the plain one first (the compiled
kernels loaded before either is timed: a warm-up run of 1 m first).

Run: ``python benchmarks/turnout.py [vehicle] [route] [direction] [--speed 10] [--step-m 0.05]
[--crossing-step-m 0.01]`` (defaults: hbbins_loaded, diverging, facing, 10 m/s, the track
file's stations: the design's 50 mm, 10 mm over the crossing panel, the 12 mm contact filter;
``--crossing-step-m``:
another for the crossing panel, ``turnout.crossing_station_step``). The run starts 12 m before
the first panel (the longest wagon's wheelbase) and ends 3 m beyond the last rail of the
turnout; ``--panels switch`` or ``crossing`` times a shorter zone. Timings vary by tens of
percent on a shared machine; compare the ratio of one run of this script.

``--store``: only the station store's build, before and after issue 29's sharing (every
station's table computed and stored, against the plain rail's computed once and stored in one
row): build seconds, the store's MB and rows, and whether the two give the same table at every
station (to the last bit). With ``--shared-only`` or ``--crossing-step-m``: the shared store
only (one row per station of 10 mm would not fit in memory), its build also in processor time.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from railexu.model.assembly import wheelset_geometry
from railexu.model.sc_tables import sc_kernel_fields
from railexu.results.run import RunSettings, run
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("vehicle", nargs="?", default="hbbins_loaded")
    ap.add_argument("route", nargs="?", default="diverging", choices=("through", "diverging"))
    ap.add_argument("direction", nargs="?", default="facing", choices=("facing", "trailing"))
    ap.add_argument("--speed", type=float, default=10.0, help="m/s")
    ap.add_argument("--step-m", type=float, default=None, help="station step [m]")
    ap.add_argument("--crossing-step-m", type=float, default=None,
                    help="the crossing panel's station step [m]")  # fmt: skip
    ap.add_argument("--panels", default="both", choices=("both", "switch", "crossing"))
    ap.add_argument("--store", action="store_true", help="only the station store, before/after")
    ap.add_argument("--shared-only", action="store_true", help="--store: the shared store only")
    a = ap.parse_args()
    vehicle = load_vehicle(ROOT / "vehicles" / f"{a.vehicle}.yaml")
    file = ROOT / "tracks" / f"turnout_uk_r245_{a.route}_{a.direction}.yaml"
    sets = [f"turnout.panels={a.panels}"]
    if a.step_m is not None:
        sets.append(f"turnout.station_step={a.step_m} m")
    if a.crossing_step_m is not None:
        sets.append(f"turnout.crossing_station_step={a.crossing_step_m} m")
    lo, hi = load_track(file, sets).variable_rails.zone_m()
    start = lo - 13.0
    turnout = load_track(file, [*sets, f"start={start} m"])
    if a.store:
        store(vehicle, turnout, before=a.crossing_step_m is None and not a.shared_only)
        return
    plain = replace(turnout, variable_rails=None)
    settings = RunSettings(speed_m_per_s=a.speed, distance_m=hi - lo + 15.0, initial_lateral_m=0.0)
    run(vehicle, plain, replace(settings, distance_m=1.0))  # warm-up: kernels loaded
    rows = {}
    for name, track in (("plain", plain), ("turnout", turnout)):
        t0 = time.perf_counter()
        result = run(vehicle, track, settings)
        whole = time.perf_counter() - t0
        t = result.summary["timings_s"]
        rows[name] = (t["build_s"], t["integration_s"], whole, result.status["state"])
    where = f"zone {lo:.2f} .. {hi:.2f} m ({a.panels}), {_stations(turnout.variable_rails)}"
    print(f"{a.vehicle}, {a.route} {a.direction}, {a.speed:g} m/s, {settings.distance_m:.1f} m, "
          f"{where}")  # fmt: skip
    print(f"{'':8s} {'build':>8s} {'integration':>12s} {'whole run':>10s}  state")
    for name, (b, i, w, state) in rows.items():
        print(f"{name:8s} {b:7.2f}s {i:11.2f}s {w:9.2f}s  {state}")
    (pb, pi, pw, _), (tb, ti, tw, _) = rows["plain"], rows["turnout"]
    print(f"ratio turnout / plain: build {tb / pb:.1f}, integration {ti / pi:.2f}, "
          f"whole run {tw / pw:.2f}")  # fmt: skip


def _stations(rails) -> str:
    """The stations in words: their step(s) and count."""
    x = rails.stations_m()
    parts = "".join(
        f", {h * 1e3:g} mm over {a:.2f} .. {b:.2f} m" for a, b, h in rails.station_steps_m
    )
    return f"stations every {rails.station_step_m * 1e3:g} mm{parts}: {x.size} stations"


def store(vehicle, track, before: bool = True) -> None:
    """The station store built before (every station its own table) and after the sharing."""
    geometry = wheelset_geometry(vehicle.wheelsets[0], track)
    rails = track.variable_rails
    out = {}
    cases = (("before", False), ("after", True)) if before else (("after", True),)
    for name, share in cases:
        t0, c0 = time.perf_counter(), time.process_time()
        f = sc_kernel_fields(rails, geometry, 5.0e-4, share_tables=share, share_rows=share)
        out[name] = (time.perf_counter() - t0, f, time.process_time() - c0)
    lo, hi = rails.zone_m()
    print(f"station store, zone {lo:.2f} .. {hi:.2f} m, {_stations(rails)}")
    for name, (t, f, c) in out.items():
        mb = f["sc_tab"].nbytes / 1e6
        print(f"{name:7s} build {t:7.1f} s (processor {c:.1f} s)  store {mb:8.1f} MB  "
              f"rows {f['sc_tab'].shape[0]}")  # fmt: skip
    if not before:
        return
    a, b = out["before"][1], out["after"][1]
    same = all(
        np.array_equal(a["sc_tab"][a["sc_index"][:, k]], b["sc_tab"][b["sc_index"][:, k]])
        for k in range(2) if a["sc_side"][k] >= 0
    )  # fmt: skip
    print(f"the same table at every station and side: {same}")


if __name__ == "__main__":
    main()
