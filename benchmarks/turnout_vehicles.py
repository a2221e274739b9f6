"""Every shipped vehicle through the turnout's routes and directions (issue 29): the status of
each run and, per panel, the largest vertical force per rail, the crossing's impact and the
transfer from wing rail to nose, the largest Tgamma per rail; the integration time.

Run: ``python benchmarks/turnout_vehicles.py [--panels both] [--step-m 0.05] [--time-step 0.2e-3]
[--crossing-step-m 0.005] [--vehicles a,b] [--routes through_facing,diverging_trailing]
[--save DIR]`` (defaults: every vehicle in ``vehicles/``, the four tracks, the whole turnout
(switch panel, whole crossing, check rail) at the track files' stations: the design's 50 mm,
5 mm over the crossing panel with the 12 mm contact filter at the wheelset
(``turnout.crossing_station_step``, ``turnout.contact_filter``; printed per route; others with
``--crossing-step-m``, ``--contact-filter-m``; the filter's first form, filtered stations
blended linearly, with ``--filter-at-stations``), a 0.2 ms step with every step recorded: the
default 2 ms moves a wheel 20 mm per step at 10 m/s, longer than a crossing's impact, and the
blade's impact needs 0.2 ms (184 kN at 0.4 ms, 197.3 kN at 0.2 ms, the loaded Hbbins;
docs/switches-and-crossings.md). Each run starts on straight track 3 m plus the wheelbase
before the first rail of the turnout met and ends 3 m beyond its last, at 10 m/s, centred.
``--save DIR`` keeps each run's per-rail columns (``DIR/<vehicle>_<route>.npz``) and its line
(``DIR/table.jsonl``) for ``docs/turnout_run_figures.py``.

Quantities (the window of each: the wheelset's per-rail columns inside the panel named, every
wheelset of the vehicle), per rail under the panel's rail names (``rails``, the slices'
``rail_names`` as in the run summary's ``switches_crossings`` ``rails`` block; a contact is the
rail's whose surface is on top at its lateral position, ``railexu.profiles.variable.rails``):
``switch``: the route side's switch panel, the blade and the stock rail; ``crossing``: the route
side's crossing panel, the nose and the wing rail, the largest Q there (the impact), the
wheelsets' transfer points (the nose's share of the side's Q first crossing 50 %) and the
largest Tgamma per rail; ``check``: the other side's check-rail panel, the check rail and its
stock rail. Lists (``Q_max_N`` ...) are in the order of ``rails`` (gauge side first); ``by_rail``
holds the same per name. ``Q_sum_residual_N``: per panel the largest ``|Q_rail1 + Q_rail2 - Q|``
over its window (every wheelset), ``Q`` the side's total: the labels split the wheel's load, so
it is round-off. The line also keeps the run summary's ``rails`` block per wheelset and side
(``summary_rails``).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from railexu.profiles.variable.rails import DEFAULT_NAMES
from railexu.results.run import RunSettings, run
from railexu.simulation.sc_outputs import crossing_summary
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
ROUTES = ("through_facing", "through_trailing", "diverging_facing", "diverging_trailing")


def panel_ranges(track) -> dict[str, tuple[str, float, float, list[str]]]:
    """``{name: (side, first, last track distance [m], its two rails' names)}`` of the switch
    panel, the crossing and the check rail (the panels present); names gauge side first."""
    zone = track.variable_rails
    out = {}
    for side, prof in (("left", zone.left), ("right", zone.right)):
        if prof is None:
            continue
        for p in prof.panels:
            lo, hi = (zone.start_m + v for v in p.range_m)
            source = p.profile.slices.source
            name = "switch" if "switch panel" in source else (
                "crossing" if len(prof.panels) > 1 or "full" in source else "check")  # fmt: skip
            if "check_rail" in source:
                name = "check"
            names = list(p.profile.slices.rail_names or DEFAULT_NAMES)
            out[name] = (side, lo, hi, names)
    return out


def panel_quantities(ts, n_ws: int, side: str, lo: float, hi: float, names: list[str]) -> dict:
    """Per rail (``names``, gauge side first): the largest Q [N] (where, which wheelset), the
    largest |Y| [N] and Tgamma [N] over the vehicle's wheelsets inside ``lo .. hi``; the
    transfer points (the field side's rail -> the gauge side's: wing rail -> nose); the largest
    ``|Q_1 + Q_2 - Q|`` [N] against the side's total ``Q``."""
    cols = {f"ws{i}_{side}_{q}": np.asarray(ts[f"ws{i}_{side}_{q}"])
            for i in range(1, n_ws + 1) for q in ("in_zone",)}  # fmt: skip
    out = {"Q_max_N": [0.0, 0.0], "Q_max_at_m": [None, None], "Q_max_ws": [None, None],
           "Y_absmax_N": [0.0, 0.0], "Tgamma_max_N": [0.0, 0.0]}  # fmt: skip
    out["Q_sum_residual_N"] = 0.0
    sub = {}
    for i in range(1, n_ws + 1):
        s = np.asarray(ts[f"ws{i}_s_m"])
        win = (s >= lo) & (s <= hi) & (cols[f"ws{i}_{side}_in_zone"] > 0.5)
        if not np.any(win):
            continue
        q_sum = sum(np.asarray(ts[f"ws{i}_{side}_rail{r}_Q_N"])[win] for r in (1, 2))
        residual = float(np.max(np.abs(q_sum - np.asarray(ts[f"ws{i}_{side}_Q_N"])[win])))
        out["Q_sum_residual_N"] = max(out["Q_sum_residual_N"], residual)
        for r in (1, 2):
            key = f"ws{i}_{side}_rail{r}"
            q = np.asarray(ts[f"{key}_Q_N"])[win]
            k = int(np.argmax(q))
            if q[k] > out["Q_max_N"][r - 1]:
                out["Q_max_N"][r - 1] = float(q[k])
                out["Q_max_at_m"][r - 1] = float(s[win][k])
                out["Q_max_ws"][r - 1] = i
            y = float(np.max(np.abs(np.asarray(ts[f"{key}_Y_N"])[win])))
            out["Y_absmax_N"][r - 1] = max(out["Y_absmax_N"][r - 1], y)
            tg = float(np.max(np.asarray(ts[f"{key}_Tgamma_N"])[win]))
            out["Tgamma_max_N"][r - 1] = max(out["Tgamma_max_N"][r - 1], tg)
        for r in (1, 2):
            for q in ("Q_N", "Tgamma_N", "Y_N", "contact_y_m"):
                sub[f"ws{i}_{side}_rail{r}_{q}"] = np.asarray(ts[f"ws{i}_{side}_rail{r}_{q}"])
        sub[f"ws{i}_{side}_in_zone"] = win.astype(float)  # the panel's window only
        sub[f"ws{i}_s_m"] = np.asarray(ts[f"ws{i}_s_m"])
    summary = crossing_summary(sub, (lo, hi), n_ws) if sub else {}
    out["transfer_at_m"] = [summary.get(f"ws{i}_{side}", {}).get("transfer_at_m")
                            for i in range(1, n_ws + 1)]  # fmt: skip
    keys = ("Q_max_N", "Q_max_at_m", "Q_max_ws", "Y_absmax_N", "Tgamma_max_N")
    out["rails"] = list(names)
    out["by_rail"] = {n: {k: out[k][r] for k in keys} for r, n in enumerate(names)}
    return out


class TableCache:
    """The kernel's station tables of the last (track, wheel) built, for the next run on the
    same track with the same wheel (the tables depend on the rails and the first wheelset's
    wheel only): ``railexu.model.sc_tables.sc_kernel_fields`` wrapped where the model calls
    it; each run gets its own blend caches (``sc_cache``, ``sc_key``, ``sc_t``)."""

    def __init__(self, filter_at_stations: bool = False) -> None:
        import railexu.model.assembly as assembly

        self.filter_at_stations = filter_at_stations
        self.key: tuple | None = None
        self.fields: dict | None = None
        self.hits = 0
        self._build = assembly.sc_kernel_fields
        assembly.sc_kernel_fields = self

    def __call__(self, rails, geometry, width, n_wheelsets: int = 1, **kw) -> dict:
        if self.fields is None or self.key is None or self.built_for != self.key:
            self.fields = self._build(rails, geometry, width, n_wheelsets=1, **kw,
                                      filter_at_stations=self.filter_at_stations)  # fmt: skip
            self.built_for = self.key
        else:
            self.hits += 1
        f = dict(self.fields)
        if f:
            cache = f["sc_cache"]
            f["sc_cache"] = np.zeros((n_wheelsets, *cache.shape[1:]))
            f["sc_key"] = np.full((n_wheelsets, 2), -1, dtype=np.int64)
            f["sc_t"] = np.full((n_wheelsets, 2), np.nan)
        return f


def one(vehicle_name: str, route: str, sets: list[str], settings_kw: dict, save: Path | None,
        cache: TableCache | None = None):  # fmt: skip
    """One run: its table line (a dict)."""
    vehicle = load_vehicle(ROOT / "vehicles" / f"{vehicle_name}.yaml")
    if cache is not None:
        w = vehicle.wheelsets[0]
        cache.key = (route, tuple(sets), w.wheel_profile, w.nominal_radius_m,
                     w.flange_back_distance_m, vehicle.contact.curvature_smoothing_m)  # fmt: skip
    file = ROOT / "tracks" / f"turnout_uk_r245_{route}.yaml"
    x = [w.position_x_m for w in vehicle.wheelsets]
    wheelbase = max(x) - min(x)
    probe = load_track(file, [*sets, "turnout.approach=60 m"])
    lo, hi = probe.variable_rails.zone_m()
    track = load_track(file, [*sets, "turnout.approach=60 m", f"start={lo - 3.0 - wheelbase} m"])
    settings = RunSettings(speed_m_per_s=10.0, distance_m=hi - lo + 5.0 + wheelbase,
                           initial_lateral_m=0.0, **settings_kw)  # fmt: skip
    t0 = time.perf_counter()
    result = run(vehicle, track, settings)
    whole = time.perf_counter() - t0
    ts = result.timeseries
    n_ws = len(vehicle.wheelsets)
    line = {"vehicle": vehicle_name, "route": route, "state": result.status["state"],
            "reason": result.status.get("reason", ""),
            "distance_m": result.status.get("distance_m"),
            "timings_s": {**result.summary["timings_s"], "whole_s": whole},
            "time_step_s": settings.time_step_s, "panels": {}}  # fmt: skip
    ranges = panel_ranges(track)
    for name, (side, a, b, names) in ranges.items():
        line["panels"][name] = {"side": side, "range_m": [a, b],
                                **panel_quantities(ts, n_ws, side, a, b, names)}  # fmt: skip
    sc = result.summary.to_dict().get("switches_crossings", {})
    line["summary_rails"] = {k: v["rails"] for k, v in sc.items()
                             if isinstance(v, dict) and "rails" in v}  # fmt: skip
    if save is not None:
        keep = {"time_s": np.asarray(ts["time_s"])}
        for i in range(1, n_ws + 1):
            keep[f"ws{i}_s_m"] = np.asarray(ts[f"ws{i}_s_m"])
            for side in ("left", "right"):
                for q in ("Q_N", "Y_N"):
                    keep[f"ws{i}_{side}_{q}"] = np.asarray(ts[f"ws{i}_{side}_{q}"])
                if f"ws{i}_{side}_in_zone" not in ts.names:
                    continue
                keep[f"ws{i}_{side}_in_zone"] = np.asarray(ts[f"ws{i}_{side}_in_zone"])
                for r in (1, 2):
                    for q in ("Q_N", "Y_N", "Tgamma_N", "contact_y_m"):
                        k = f"ws{i}_{side}_rail{r}_{q}"
                        keep[k] = np.asarray(ts[k], dtype=np.float32)
        np.savez_compressed(save / f"{vehicle_name}_{route}.npz", **keep)
        with open(save / "table.jsonl", "a") as f:
            f.write(json.dumps({**line, "panel_ranges": ranges}) + "\n")
    return line


def text_line(line: dict) -> str:
    """The printed row: state, then per panel (switch, crossing, check rail) each rail's name
    and largest Q [kN], the largest Tgamma per crossing rail [N], the integration time [s]."""
    p = line["panels"]

    def cells(name):
        if name not in p:
            return f"{name}: -"
        rails = p[name].get("rails", list(DEFAULT_NAMES))  # a line saved before the names
        return " ".join(f"{n} {q / 1e3:.1f}" for n, q in zip(rails, p[name]["Q_max_N"],
                                                                strict=True))  # fmt: skip

    cr = p.get("crossing")
    tg = ("Tgamma " + " / ".join(f"{v:.0f}" for v in cr["Tgamma_max_N"])) if cr else ""
    return (f"{line['vehicle']:26s} {line['route']:19s} {line['state']:10s} | "
            f"{cells('switch')} | {cells('crossing')} {tg} | {cells('check')} | "
            f"{line['timings_s']['integration_s']:.1f} s")  # fmt: skip


def stations_text(route: str, sets: list[str]) -> str:
    """The route's stations in words: the zone's step, each part's own step and range (track
    distance [m], ``turnout.crossing_station_step``) and the count, as the runs build them."""
    file = ROOT / "tracks" / f"turnout_uk_r245_{route}.yaml"
    zone = load_track(file, [*sets, "turnout.approach=60 m"]).variable_rails
    parts = "".join(f", {h * 1e3:g} mm over {lo:.2f} .. {hi:.2f} m"
                    for lo, hi, h in zone.station_steps_m)  # fmt: skip
    return f"stations every {zone.station_step_m * 1e3:g} mm{parts}: {zone.stations_m().size}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--panels", default="both", choices=("both", "switch", "crossing"))
    ap.add_argument("--step-m", type=float, default=None, help="station step [m]")
    ap.add_argument("--crossing-step-m", type=float, default=None,
                    help="the crossing panel's station step [m]")  # fmt: skip
    ap.add_argument("--contact-filter-m", type=float, default=None,
                    help="the contact filter's length [m] (turnout.contact_filter)")  # fmt: skip
    ap.add_argument("--filter-at-stations", action="store_true",
                    help="the contact filter's first form: each station's table filtered at the "
                    "build, two stations blended linearly (the default: the filter at the "
                    "wheelset's position)")  # fmt: skip
    ap.add_argument("--time-step", type=float, default=0.2e-3, help="[s]")
    ap.add_argument("--vehicles", default="")
    ap.add_argument("--routes", default=",".join(ROUTES))
    ap.add_argument("--save", type=Path, default=None)
    a = ap.parse_args()
    names = a.vehicles.split(",") if a.vehicles else sorted(
        p.stem for p in (ROOT / "vehicles").glob("*.yaml"))  # fmt: skip
    sets = [f"turnout.panels={a.panels}"]
    if a.step_m is not None:
        sets.append(f"turnout.station_step={a.step_m} m")
    if a.crossing_step_m is not None:
        sets.append(f"turnout.crossing_station_step={a.crossing_step_m} m")
    if a.contact_filter_m is not None:
        sets.append(f"turnout.contact_filter={a.contact_filter_m} m")
    if a.save is not None:
        a.save.mkdir(parents=True, exist_ok=True)
    kw = {"time_step_s": a.time_step, "output_interval_s": a.time_step}
    print(f"panels {a.panels}, stations {a.step_m or 'design'} (crossing: "
          f"{a.crossing_step_m or 'the track file'}), step {a.time_step * 1e3:g} ms, "
          "10 m/s")  # fmt: skip
    print(f"{'vehicle':26s} {'track':19s} {'state':10s} | per panel: rail, largest Q [kN] "
          "(Tgamma per crossing rail [N]) | integration [s]")  # fmt: skip
    done = set()
    if a.save is not None and (a.save / "table.jsonl").exists():
        for text in (a.save / "table.jsonl").read_text().splitlines():
            line = json.loads(text)
            done.add((line["vehicle"], line["route"]))
            print(text_line(line), " (saved)", flush=True)
    cache = TableCache(filter_at_stations=a.filter_at_stations)
    for route in a.routes.split(","):  # the tables shared by the vehicles with one wheel
        print(f"{route}: {stations_text(route, sets)}", flush=True)
        for name in sorted(names, key=lambda n: load_vehicle(
                ROOT / "vehicles" / f"{n}.yaml").wheelsets[0].nominal_radius_m):  # fmt: skip
            if (name, route) not in done:
                print(text_line(one(name, route, sets, kw, a.save, cache)), flush=True)


if __name__ == "__main__":
    main()
