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

The breakdown per run (issue 29: why the turnout's integration costs what it does): the
solver's steps, step cuts, Newton iterations and Jacobian updates (the run's ``summary.json``
``solver`` block), the force function's calls, and the integration's **processor time**
(``time.thread_time``, so that other jobs on the machine do not count) split into the force
function (per call), the Jacobian function, the recording of the outputs after each step and
the rest (Exudyn's own work: the residual, the linear solves, the Python callbacks). The
contacts run on one thread here (``RAILEXU_THREADS=1`` unless set: the processor time of the
integration's thread is then all of its work; the results are the same either way); the
timing wrappers add about 1 us per call to both runs.

``--store``: only the station store's build, before and after issue 29's sharing (every
station's table computed and stored, against the plain rail's computed once and stored in one
row): build seconds, the store's MB and rows, and whether the two give the same table at every
station (to the last bit). With ``--shared-only`` or ``--crossing-step-m``: the shared store
only (one row per station of 10 mm would not fit in memory), its build also in processor time.
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

os.environ.setdefault("RAILEXU_THREADS", "1")  # before railexu: the processor times' thread

from railexu.model import assembly  # noqa: E402
from railexu.model.assembly import wheelset_geometry  # noqa: E402
from railexu.model.sc_tables import sc_kernel_fields  # noqa: E402
from railexu.results.run import RunSettings, run  # noqa: E402
from railexu.simulation import recorder as _recorder  # noqa: E402
from railexu.simulation import simulate as _simulate  # noqa: E402
from railexu.track.track import load_track  # noqa: E402
from railexu.vehicle.vehicle import load_vehicle  # noqa: E402

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
    clocks = _ProcessorClocks()
    run(vehicle, plain, replace(settings, distance_m=1.0))  # warm-up: kernels loaded
    rows, parts = {}, {}
    for name, track in (("plain", plain), ("turnout", turnout)):
        clocks.reset()
        t0 = time.perf_counter()
        result = run(vehicle, track, settings)
        whole = time.perf_counter() - t0
        t = result.summary["timings_s"]
        rows[name] = (t["build_s"], t["integration_s"], whole, result.status["state"])
        parts[name] = (result.summary["solver"], dict(clocks.s))
    where = f"zone {lo:.2f} .. {hi:.2f} m ({a.panels}), {_stations(turnout.variable_rails)}"
    print(f"{a.vehicle}, {a.route} {a.direction}, {a.speed:g} m/s, {settings.distance_m:.1f} m, "
          f"{where}")  # fmt: skip
    print(f"{'':8s} {'build':>8s} {'integration':>12s} {'whole run':>10s}  state")
    for name, (b, i, w, state) in rows.items():
        print(f"{name:8s} {b:7.2f}s {i:11.2f}s {w:9.2f}s  {state}")
    (pb, pi, pw, _), (tb, ti, tw, _) = rows["plain"], rows["turnout"]
    print(f"ratio turnout / plain: build {tb / pb:.1f}, integration {ti / pi:.2f}, "
          f"whole run {tw / pw:.2f}")  # fmt: skip
    _print_breakdown(parts)


class _ProcessorClocks:
    """Processor time of the integration and of its parts, by wrapping the model's compiled
    force and Jacobian functions (after ``VehicleModel.warm_up``), the recorder and
    ``simulate._integrate`` for this process (``s``: seconds and calls per part)."""

    def __init__(self) -> None:
        self.s: dict[str, float] = {}
        clock = time.thread_time
        s = self.s

        def timed(key, f):
            def call(*args, **kwargs):
                t0 = clock()
                out = f(*args, **kwargs)
                s[key] += clock() - t0
                s[key + "_n"] += 1
                return out

            return call

        warm_up = assembly.VehicleModel.warm_up

        def warm_up_timed(model, *args, **kwargs):
            warm_up(model, *args, **kwargs)
            for key in ("forces", "jacobian"):
                model._compiled[key] = timed(key, model._compiled[key])

        assembly.VehicleModel.warm_up = warm_up_timed
        _recorder.Recorder.record = timed("record", _recorder.Recorder.record)
        _simulate._integrate = timed("integration", _simulate._integrate)
        self.reset()

    def reset(self) -> None:
        for key in ("forces", "jacobian", "record", "integration"):
            self.s[key] = 0.0
            self.s[key + "_n"] = 0


def _print_breakdown(parts: dict) -> None:
    """The solver's counts and the integration's processor time by part, per run, and the
    ratios turnout / plain."""
    print("breakdown (processor time of the integration's thread; steps and counts from the "
          "run's solver block):")  # fmt: skip
    for name, (solver, c) in parts.items():
        steps = max(solver.get("steps", 0), 1)
        calls = max(c["forces_n"], 1)
        rest = c["integration"] - c["forces"] - c["jacobian"] - c["record"]
        print(f"  {name:8s} {solver.get('steps')} steps ({solver.get('step_cuts')} cut), "
              f"{solver.get('newton_iterations')} Newton iterations "
              f"({solver.get('newton_iterations', 0) / steps:.2f} per step), "
              f"{solver.get('jacobian_updates')} Jacobian updates, {c['forces_n']} force calls "
              f"({c['forces_n'] / steps:.2f} per step)")  # fmt: skip
        print(f"  {'':8s} integration {c['integration']:.3f} s = force function "
              f"{c['forces']:.3f} s ({c['forces'] / calls * 1e6:.1f} us per call) + Jacobian "
              f"{c['jacobian']:.3f} s ({c['jacobian_n']} calls) + recording {c['record']:.3f} s "
              f"+ the rest (Exudyn, callbacks) {rest:.3f} s; the force function's wall time "
              f"{solver.get('force_function_s', float('nan')):.3f} s")  # fmt: skip
    (_, p), (_, t) = parts["plain"], parts["turnout"]
    per_call = (t["forces"] / max(t["forces_n"], 1)) / (p["forces"] / max(p["forces_n"], 1))
    print(f"ratio turnout / plain (processor time): integration "
          f"{t['integration'] / p['integration']:.2f}, force function "
          f"{t['forces'] / p['forces']:.2f} ({per_call:.2f} per call)")  # fmt: skip


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
