"""Are the turnout's single-step force spikes the step's or the physics'? (issue 29)

The same short run (one vehicle through one panel, every step recorded) at several steps; per
step the largest wheel load Q on the panel's side (where, which wheelset), its neighbours, how
many samples lie above ``2 Q0``, the impact's impulse above Q0, the 20 Hz value (EN 14363's
filter), the solver's step facts (``summary.json``'s ``solver`` block) and, for a landing (the
wheel in the air before the peak), the energy estimate of a Hertz impact:

    E = Q0 h  (or (1/2) m v^2)         the wheel pushed down by its load Q0 (gravity and the
                                       suspension's preload, constant over a drop h of under a
                                       millimetre) falls h: landing speed v = sqrt(2 Q0 h / m)
    E + Q0 delta = (2/5) k_H delta^(5/2),   F_max = k_H delta^(3/2)
    T = 2.94 delta / v                 (the Hertz impact's duration)

(Johnson, Contact Mechanics, 1985, sec. 11.4: the impact of two elastic bodies, Hertz's
``P = k_H delta^(3/2)`` integrated for the energy; the preload term ``Q0 delta`` added here).
``m`` is the wheel's effective mass on its rail: ``1 / (1/m_ws + y_c^2 / I_roll)`` with the
wheelset's mass, roll inertia and ``y_c`` = 0.75 m (the other wheel stays on its rail over the
~1 ms of the impact); ``k_H = (4/3) E* sqrt(R_e)`` with Hertz's equivalent radius from the
contact's semi-axes ``a, b`` and load ``N`` at the samples after the landing (``R_e = 4 E*
(ab)^(3/2) / (3 N)``; Johnson 1985 sec. 4.2, the equivalent circle, a few per cent for these
ellipticities); a rigid track (no track mass: the model's), the track's own mass would lower it.
``h`` is the wheel's fall from its highest point in the air to the last sample before it
lands, ``v`` its vertical velocity there (both in the track frame, the wheel's height ``z +/-
0.75 phi``); ``E`` from ``v`` is the one used, ``Q0 h`` printed beside it.

Run: ``python benchmarks/turnout_spikes.py [--vehicle hbbins_loaded] [--route
diverging_trailing] [--panel crossing] [--steps 0.4e-3,0.2e-3,0.1e-3] [--elastic] [--save
DIR]``; the run
goes from 3 m plus the wheelbase before the panel's first rail met to 2 m beyond its last
(the panel alone, ``turnout.panels``; ``--track-panels both``: the whole turnout), 10 m/s,
centred, on the turnout track's ``turnout.approach`` of 60 m as ``benchmarks/turnout_step.py``.
``--elastic``: on elastic track (``track_model: elastic``, its defaults; the saved arrays get
``_elastic`` in their names and keep the rail masses' deflections, velocities and
accelerations; the Hertz estimate above stays a rigid track's); ``benchmarks/turnout_elastic.py``
compares the two tracks against Jenkins et al.'s P1 and P2.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from turnout_vehicles import ROOT, panel_ranges  # noqa: E402

from railexu.assessment.filters import lowpass  # noqa: E402
from railexu.operation.run_settings import RunSettings  # noqa: E402
from railexu.simulation.recorder import POINT_FIELDS  # noqa: E402
from railexu.simulation.simulate import simulate, wheelset_order  # noqa: E402
from railexu.track.track import load_track  # noqa: E402
from railexu.vehicle.vehicle import load_vehicle  # noqa: E402

#: The crossing slices' first s [m] (tracks/uk_crossing/uk_crossing_full.yaml; as
#: docs/turnout_run_figures.py): the slices' s = 0 lies 0.995 m after the panel's first slice.
CROSSING_S0_M = -0.995
#: Half the distance between the wheels' contact points [m] (the wheel's height z +/- y_c phi).
Y_C_M = 0.75
#: A wheel "in the air": Q below this share of Q0.
AIR = 0.02
#: The impact's impulse is summed over this time either side of the peak [s].
IMPULSE_HALF_S = 5e-3


def hertz_impact(energy_J: float, preload_N: float, k_h: float) -> tuple[float, float]:
    """``(delta_max [m], F_max [N])`` of a Hertz impact: ``E + P delta = (2/5) k delta^(5/2)``
    (Johnson 1985 sec. 11.4 with the preload ``P``), by bisection."""
    lo, hi = 0.0, 1e-2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if 0.4 * k_h * mid**2.5 - preload_N * mid < energy_J:
            lo = mid
        else:
            hi = mid
    return lo, k_h * lo**1.5


def hertz_constant(points: np.ndarray, e_star_Pa: float) -> float | None:
    """``k_H`` [N/m^1.5] from the loaded points' semi-axes and loads (the median over the
    samples given, ``(n, MAX_POINTS, fields)``): ``(4/3) E* sqrt(R_e)``, ``R_e = 4 E*
    (ab)^(3/2) / (3 N)``."""
    f = list(POINT_FIELDS)
    n, a, b = (points[..., f.index(k)] for k in ("N_N", "a_m", "b_m"))
    ok = n > 1e3
    if not np.any(ok):
        return None
    r_e = 4.0 * e_star_Pa * (a[ok] * b[ok]) ** 1.5 / (3.0 * n[ok])
    return float(np.median(4.0 / 3.0 * e_star_Pa * np.sqrt(r_e)))


def analyse(ts, points: np.ndarray, vehicle, side: str, lo: float, hi: float, s0: float,
            facing: bool, rail: str = "") -> dict:  # fmt: skip
    """The peak of the panel side's Q inside ``lo .. hi`` (track distance) and its landing:
    ``ts`` the run's time series (or the saved arrays), ``points`` its contact points; ``rail``
    ``""`` for the wheel's Q (every rail), ``"rail1_"`` for one rail's."""
    order = wheelset_order(vehicle)
    n_ws = len(order)
    t = np.asarray(ts["time_s"])
    fs = 1.0 / float(np.median(np.diff(t)))
    q0 = float(np.mean([ts[f"ws{i}_{side}_Q_N"][0] for i in range(1, n_ws + 1)]))
    best = None
    above = 0
    for i in range(1, n_ws + 1):
        s = np.asarray(ts[f"ws{i}_s_m"])
        q = np.asarray(ts[f"ws{i}_{side}_{rail}Q_N"])
        win = (s >= lo) & (s <= hi)
        if not np.any(win):
            continue
        above += int(np.sum(q[win] > 2.0 * q0))
        k = int(np.flatnonzero(win)[np.argmax(q[win])])
        if best is None or q[k] > best["Q_N"]:
            q20 = lowpass(q, fs, 20.0)
            best = {"ws": i, "k": k, "Q_N": float(q[k]), "t_s": float(t[k]),
                    "s_slices_m": float(s[k] - s0 if facing else s0 - s[k]),
                    "Q20_N": float(q20[win].max()),
                    "before_N": float(q[k - 1]), "after_N": float(q[k + 1]) if k + 1 < len(q)
                    else math.nan}  # fmt: skip
            near = np.abs(t - t[k]) <= IMPULSE_HALF_S
            best["impulse_Ns"] = float(np.sum(np.maximum(q[near] - q0, 0.0)) / fs)
            best["wide_ms"] = float(np.sum(q[near] > 0.5 * (q[k] + q0)) / fs * 1e3)
    out = {"Q0_N": q0, "above_2Q0": above, **(best or {})}
    if best is None:
        return out
    if rail:  # one rail's load: no landing (the wheel may stand on the other rail)
        return out
    # the landing: the last samples in the air within IMPULSE_HALF_S before the peak
    i, k = best["ws"], best["k"]
    q = np.asarray(ts[f"ws{i}_{side}_{rail}Q_N"])
    back = np.flatnonzero((q[:k] < AIR * q0) & (t[:k] >= t[k] - IMPULSE_HALF_S))
    if back.size == 0:
        out["air_ms"] = 0.0
        return out
    land = int(back[-1]) + 1  # the first sample in contact again
    j = land - 1
    while j >= 0 and q[j] < AIR * q0:
        j -= 1
    flight = np.arange(j + 1, land)
    out["air_ms"] = len(flight) / fs * 1e3
    out["landing_to_peak_ms"] = (t[k] - t[land]) * 1e3
    out["landing_Q_N"] = float(q[land])
    if len(flight) < 2:
        return out
    sign = 1.0 if side == "left" else -1.0
    z_w = np.asarray(ts[f"ws{i}_vertical_m"]) + sign * Y_C_M * np.asarray(ts[f"ws{i}_roll_rad"])
    last = flight[-1]
    out["drop_h_m"] = float(np.max(z_w[j : last + 1]) - z_w[last])
    v = float((z_w[last - 1] - z_w[last]) * fs)  # downwards positive
    out["v_land_m_per_s"] = v
    ws = vehicle.wheelsets[order[i - 1]]
    roll = ws.inertia_kg_m2[0]
    m_eff = 1.0 / (1.0 / ws.mass_kg + Y_C_M**2 / roll)
    out["m_eff_kg"] = m_eff
    e_star = vehicle.contact.effective_modulus_Pa
    w_side = 0 if side == "left" else 1
    pts = points[land : land + int(2e-3 * fs) + 1, i - 1, w_side]
    k_h = hertz_constant(pts, e_star)
    out["k_H"] = k_h
    if k_h is None:
        return out
    energy = 0.5 * m_eff * v * v
    out["E_J"], out["E_Q0h_J"] = energy, q0 * out["drop_h_m"]
    delta, f_max = hertz_impact(energy, q0, k_h)
    out["delta_max_m"], out["F_max_N"] = delta, f_max
    out["T_hertz_ms"] = 2.94 * delta / v * 1e3 if v > 0 else math.nan
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicle", default="hbbins_loaded")
    ap.add_argument("--route", default="diverging_trailing")
    ap.add_argument("--panel", default="crossing", choices=("crossing", "switch"))
    ap.add_argument(
        "--track-panels",
        default=None,
        choices=("both", "switch", "crossing"),
        help="the track's panels (default: the panel analysed alone)",
    )
    ap.add_argument("--steps", default="0.4e-3,0.2e-3,0.1e-3")
    ap.add_argument("--s-window", default=None, help="slices' s from,to [m] (crossing only)")
    ap.add_argument("--rail", type=int, default=None, help="one rail's Q (1, 2): the wheel's")
    ap.add_argument("--save", type=Path, default=None, help="keep each run's arrays here")
    ap.add_argument("--reuse", type=Path, default=None, help="analyse the runs saved here")
    ap.add_argument(
        "--elastic", action="store_true", help="elastic track (track_model: elastic, defaults)"
    )
    a = ap.parse_args()
    file = ROOT / "tracks" / f"turnout_uk_r245_{a.route}.yaml"
    sets = [f"turnout.panels={a.track_panels or a.panel}", "turnout.approach=60 m"]
    if a.elastic:
        sets.append("track_model=elastic")
    vehicle = load_vehicle(ROOT / "vehicles" / f"{a.vehicle}.yaml")
    x = [w.position_x_m for w in vehicle.wheelsets]
    lo, hi = load_track(file, sets).variable_rails.zone_m()
    track = load_track(file, [*sets, f"start={lo - 3.0 - (max(x) - min(x))} m"])
    side, p_lo, p_hi, _ = panel_ranges(track)[a.panel]
    facing = a.route.endswith("facing")
    s0 = (p_lo - CROSSING_S0_M if facing else p_hi + CROSSING_S0_M) if a.panel == "crossing" else (
        p_lo if facing else p_hi)  # fmt: skip
    if a.s_window:  # a window of the slices' s: back to track distance
        w0, w1 = (float(v) for v in a.s_window.split(","))
        p_lo, p_hi = sorted((s0 + w0, s0 + w1) if facing else (s0 - w0, s0 - w1))
    distance = hi - lo + 5.0 + max(x) - min(x)
    print(f"{a.vehicle}, {a.route}, panel {a.panel} ({side} wheel), {distance:.1f} m at 10 m/s; "
          f"window {p_lo:.3f}-{p_hi:.3f} m (s = 0 at {s0:.3f} m)", flush=True)  # fmt: skip
    for step in (float(v) for v in a.steps.split(",")):
        tag = "_elastic" if a.elastic else ""
        name = f"{a.vehicle}_{a.route}_{a.track_panels or a.panel}_{step * 1e3:g}ms{tag}.npz"
        if a.reuse is not None:  # the saved run: analysed again
            d = np.load(a.reuse / name)
            ts, points = {k: d[k] for k in d.files}, d["points"]
            facts = json.loads(str(d["facts"]))
        else:
            settings = RunSettings(speed_m_per_s=10.0, distance_m=distance,
                                   initial_lateral_m=0.0, time_step_s=step,
                                   output_interval_s=step)  # fmt: skip
            t0 = time.perf_counter()
            result = simulate(vehicle, track, settings)
            facts = {"state": result.status["state"], "solver": result.summary["solver"],
                     "wall_s": time.perf_counter() - t0}  # fmt: skip
            ts, points = result.timeseries, result.contact_points
            if a.save is not None:
                a.save.mkdir(parents=True, exist_ok=True)
                keep = {k: np.asarray(ts[k]) for k in ts.names if k == "time_s"
                        or k.endswith(("_s_m", "_Q_N", "_vertical_m", "_roll_rad", "_m_per_s",
                                               "_m_per_s2"))}  # fmt: skip
                np.savez_compressed(a.save / name, points=points.astype(np.float32),
                                    facts=np.array(json.dumps(facts)), **keep)  # fmt: skip
        rail = f"rail{a.rail}_" if a.rail else ""
        r = analyse(ts, points, vehicle, side, p_lo, p_hi, s0, facing, rail)
        print_step(step, facts, r)


def print_step(step: float, facts: dict, r: dict) -> None:
    """The lines of one step: the peak, the landing and its Hertz estimate, the solver."""
    sv = facts["solver"]
    nan = math.nan
    kn = {k: r.get(k, nan) / 1e3 for k in ("Q_N", "Q20_N", "before_N", "after_N", "F_max_N",
                                           "Q0_N", "landing_Q_N")}  # fmt: skip
    print(f"step {step * 1e3:5.2f} ms {facts['state']:9s} Q0 {kn['Q0_N']:6.1f} kN  peak "
          f"{kn['Q_N']:7.1f} kN (ws{r.get('ws')}, s = {r.get('s_slices_m', nan):+.4f} m, t = "
          f"{r.get('t_s', nan):.5f} s; before {kn['before_N']:6.1f}, after {kn['after_N']:6.1f})"
          f"  20 Hz {kn['Q20_N']:6.1f}  samples > 2 Q0: {r['above_2Q0']}  impulse above Q0 "
          f"(+/-5 ms) {r.get('impulse_Ns', nan):7.2f} N s  above half-peak "
          f"{r.get('wide_ms', nan):.2f} ms", flush=True)  # fmt: skip
    print(f"    landing: in the air {r.get('air_ms', 0.0):.2f} ms, landed "
          f"{r.get('landing_to_peak_ms', nan):.2f} ms before the peak at {kn['landing_Q_N']:.1f}"
          f" kN; fall h {r.get('drop_h_m', nan) * 1e6:.1f} um, v "
          f"{r.get('v_land_m_per_s', nan):.4f} m/s, m_eff {r.get('m_eff_kg', nan):.0f} kg, k_H "
          f"{r.get('k_H') or nan:.3e} N/m^1.5, E {r.get('E_J', nan):.4f} J (Q0 h "
          f"{r.get('E_Q0h_J', nan):.4f} J) -> delta_max {r.get('delta_max_m', nan) * 1e6:.1f} "
          f"um, F_max {kn['F_max_N']:.1f} kN, Hertz duration {r.get('T_hertz_ms', nan):.3f} ms",
          flush=True)  # fmt: skip
    print(f"    solver: {sv.get('steps')} steps, {sv.get('step_cuts')} cuts, "
          f"{sv.get('steps_below_time_step')} below the step, first cut at "
          f"{sv.get('first_cut_time_s')}, smallest {sv.get('smallest_step_s')} s; "
          f"{sv.get('newton_iterations')} Newton iterations; integration "
          f"{facts.get('wall_s', nan):.0f} s", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
