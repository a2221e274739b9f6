"""The crossing's impacts on rigid and on elastic track against Jenkins' P1 and P2 (issue 29).

Reads the runs ``benchmarks/turnout_spikes.py --save DIR`` keeps (rigid, and ``--elastic``:
``track_model: elastic`` with its defaults, one co-running rail mass per rail and wheelset) and
prints per case and window the peak Q, its time above half the peak, the impulse above Q0
(``turnout_spikes.analyse``), the 20 Hz value (EN 14363's filter), the largest Q low-passed at
100 Hz (the P2 band: P2 passes, P1 is removed), the dominant frequency of the Q above 100 Hz
near the peak (P1's band) and of the Q band-passed at 10-150 Hz near the 100 Hz peak (P2's),
and on elastic track the rail mass's deflection in the window; beside them Jenkins et al.'s
estimates (Jenkins, Stephenson, Clayton, Morland & Lyon 1974, *The effect of track and vehicle
parameters on wheel/rail vertical dynamic forces*, Railway Engineering Journal 3, 2-16) for a
slope change ``2 alpha`` of the wheel's path at speed ``V``:

    P1 = P0 + 2 alpha V sqrt(k_H m_t / (1 + m_t / m_u))
    P2 = P0 + 2 alpha V sqrt(m_u / (m_u + m_t)) (1 - c_t pi / (4 sqrt(k_t (m_u + m_t))))
              sqrt(k_t m_u)
    f_P1 = sqrt(k_H (1/m_t + 1/m_u)) / (2 pi),   f_P2 = sqrt(k_t / (m_u + m_t)) / (2 pi)

with ``k_H`` the linearised Hertz stiffness at the static load (``1.5 P0 / delta_0``, ``k_H`` of
the contact from the first samples' semi-axes, ``turnout_spikes.hertz_constant``), ``m_u`` the
wheel's effective unsprung mass (``1 / (1/m_ws + y_c^2 / I_roll)``: the other wheel stays on
its rail), ``m_t``, ``k_t``, ``c_t`` the rail mass, the vertical stiffness and damping per rail
and wheelset (``railexu.track.elastic``). On rigid track (``m_t`` infinite) P1 becomes
``P0 + 2 alpha V sqrt(k_H m_u)`` and P2 does not exist.

The dip angles are the crossing's geometry (docs/switches-and-crossings.md, "What a run over it
shows"): where the wing rail's field side rises (s = -0.71 to -0.63 m) the rigid wheel rises
0.62 mm over 68 mm (9.1 mrad on average, up to 15 mrad between slices): facing the ramp's foot
is a concave kink, trailing the wheel comes down the ramp and meets its foot; the transfer
between wing rail and nose (s = 276 mm): the wheel descends 7.2 mrad on the wing rail and rises
10.7 mrad on the nose, 2 alpha = 17.9 mrad (trailing the same, mirrored); the nose's end, where
its raised field side falls back to the plain rail: the wheel drops 0.65 mm between s = 1.88
and 1.94 m, 10.8 mrad (trailing: a rise of the same slope).

Run: ``python benchmarks/turnout_spikes.py --vehicle wheelset --route through_facing
[--elastic] --steps 0.4e-3,0.2e-3 --save DIR`` and the same for ``--vehicle hbbins_loaded
--route diverging_trailing``, then ``python benchmarks/turnout_elastic.py DIR``.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from turnout_spikes import CROSSING_S0_M, Y_C_M, analyse, hertz_constant  # noqa: E402
from turnout_vehicles import ROOT, panel_ranges  # noqa: E402

from railexu.assessment.filters import bandpass, lowpass  # noqa: E402
from railexu.simulation.simulate import wheelset_order  # noqa: E402
from railexu.track.elastic import ElasticTrack  # noqa: E402
from railexu.track.track import load_track  # noqa: E402
from railexu.vehicle.vehicle import load_vehicle  # noqa: E402

SPEED_M_PER_S = 10.0
#: (vehicle, route, window name, slices' s window [m], dip angle 2 alpha [rad]: low, high)
CASES = (
    ("wheelset", "through_facing", "s < 0: the wing rail's ramp", (-1.0, 0.0), (9.1e-3, 15e-3)),
    ("wheelset", "through_facing", "0-1 m: the nose", (0.0, 1.0), (17.9e-3, 17.9e-3)),
    ("wheelset", "through_facing", "> 1 m: the nose's end", (1.0, 2.3), (10.8e-3, 10.8e-3)),
    ("hbbins_loaded", "diverging_trailing", "s < 0: the ramp's foot", (-1.0, 0.0),
     (9.1e-3, 15e-3)),
    ("hbbins_loaded", "diverging_trailing", "0-1 m: nose to wing rail", (0.0, 1.0),
     (17.9e-3, 17.9e-3)),
    ("hbbins_loaded", "diverging_trailing", "> 1 m: the nose's end", (1.0, 2.3),
     (10.8e-3, 10.8e-3)),
)  # fmt: skip


def dominant_Hz(t: np.ndarray, x: np.ndarray, k: int, half_s: float) -> float:
    """The largest peak of ``x``'s spectrum (Hann window) within ``half_s`` of sample ``k``."""
    near = np.abs(t - t[k]) <= half_s
    fs = 1.0 / float(np.median(np.diff(t)))
    n = 1 << 16
    spectrum = np.abs(np.fft.rfft(x[near] * np.hanning(int(near.sum())), n=n))
    return float(np.fft.rfftfreq(n, 1.0 / fs)[np.argmax(spectrum)])


def jenkins(p0_N: float, two_alpha: float, speed: float, k_h: float, m_u: float,
            track: ElasticTrack | None) -> dict:  # fmt: skip
    """Jenkins et al.'s (1974) P1 and P2 [N] and their frequencies [Hz] (``track`` None: rigid
    track, P1 with an infinite track mass, no P2)."""
    v = two_alpha * speed
    if track is None:
        return {
            "P1_N": p0_N + v * math.sqrt(k_h * m_u),
            "f_P1_Hz": math.sqrt(k_h / m_u) / 2 / math.pi,
        }
    m_t, k_t = track.rail_mass_kg, track.vertical_stiffness_N_per_m
    c_t = track.vertical_damping_N_s_per_m
    p1 = p0_N + v * math.sqrt(k_h * m_t / (1.0 + m_t / m_u))
    damp = 1.0 - c_t * math.pi / (4.0 * math.sqrt(k_t * (m_u + m_t)))
    p2 = p0_N + v * math.sqrt(m_u / (m_u + m_t)) * damp * math.sqrt(k_t * m_u)
    return {"P1_N": p1, "P2_N": p2, "f_P1_Hz": math.sqrt(k_h * (1 / m_t + 1 / m_u)) / 2 / math.pi,
            "f_P2_Hz": math.sqrt(k_t / (m_u + m_t)) / 2 / math.pi}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("saved", type=Path, help="the runs turnout_spikes.py --save kept")
    ap.add_argument("--steps", default="0.4,0.2", help="steps [ms]")
    a = ap.parse_args()
    track_e = ElasticTrack()
    for vname, route, label, (w0, w1), dips in CASES:
        vehicle = load_vehicle(ROOT / "vehicles" / f"{vname}.yaml")
        file = ROOT / "tracks" / f"turnout_uk_r245_{route}.yaml"
        track = load_track(file, ["turnout.panels=crossing", "turnout.approach=60 m"])
        side, p_lo, p_hi, _ = panel_ranges(track)["crossing"]
        facing = route.endswith("facing")
        s0 = p_lo - CROSSING_S0_M if facing else p_hi + CROSSING_S0_M
        lo, hi = sorted((s0 + w0, s0 + w1) if facing else (s0 - w0, s0 - w1))
        ws = vehicle.wheelsets[wheelset_order(vehicle)[0]]
        m_u = 1.0 / (1.0 / ws.mass_kg + Y_C_M**2 / ws.inertia_kg_m2[0])
        print(f"== {vname}, {route}, {label}; m_u {m_u:.0f} kg")
        for step in (float(s) for s in a.steps.split(",")):
            for tag in ("", "_elastic"):
                path = a.saved / f"{vname}_{route}_crossing_{step:g}ms{tag}.npz"
                if not path.exists():
                    continue
                d = np.load(path)
                ts = {k: d[k] for k in d.files}
                r = analyse(ts, d["points"], vehicle, side, lo, hi, s0, facing)
                w = 0 if side == "left" else 1
                k_h = hertz_constant(d["points"][:20, r["ws"] - 1, w],
                                     vehicle.contact.effective_modulus_Pa)  # fmt: skip
                p0 = r["Q0_N"]
                k_lin = 1.5 * p0 / (p0 / k_h) ** (2.0 / 3.0)
                t = np.asarray(ts["time_s"])
                fs = 1.0 / float(np.median(np.diff(t)))
                q = np.asarray(ts[f"ws{r['ws']}_{side}_Q_N"])
                s = np.asarray(ts[f"ws{r['ws']}_s_m"])
                win = (s >= lo) & (s <= hi)
                q100 = lowpass(q, fs, 100.0)
                k1 = int(np.flatnonzero(win)[np.argmax(q100[win])])
                f_p1 = dominant_Hz(t, q - q100, r["k"], 0.01)
                f_p2 = dominant_Hz(t, bandpass(q, fs, 10.0, 150.0), k1, 0.05)
                extra = (f"  100 Hz {q100[k1] / 1e3:6.1f} kN, above 100 Hz {f_p1:.0f} Hz, "
                         f"10-150 Hz {f_p2:.0f} Hz")  # fmt: skip
                if tag:
                    z = np.asarray(ts[f"ws{r['ws']}_{side}_rail_vertical_m"])[win]
                    extra += f"  rail z {z.min() * 1e3:+.3f} .. {z.max() * 1e3:+.3f} mm"
                air = r.get("air_ms", 0.0)
                print(f"  {step:g} ms {'elastic' if tag else 'rigid  '}: peak {r['Q_N'] / 1e3:6.1f}"
                      f" kN at s {r['s_slices_m']:+.4f} m, above half-peak {r['wide_ms']:.2f} ms,"
                      f" impulse {r['impulse_Ns']:6.1f} N s, 20 Hz {r['Q20_N'] / 1e3:6.1f} kN, "
                      f"in the air {air:.2f} ms{extra}")  # fmt: skip
        for dip in sorted(set(dips)):
            jr = jenkins(p0, dip, SPEED_M_PER_S, k_lin, m_u, None)
            je = jenkins(p0, dip, SPEED_M_PER_S, k_lin, m_u, track_e)
            print(f"  Jenkins, 2 alpha {dip * 1e3:.1f} mrad (V 2alpha {dip * SPEED_M_PER_S:.3f} "
                  f"m/s), P0 {p0 / 1e3:.1f} kN, k_H {k_lin:.3g} N/m (Hertz constant {k_h:.3g}"
                  f" N/m^1.5): rigid P1 "
                  f"{jr['P1_N'] / 1e3:.0f} kN ({jr['f_P1_Hz']:.0f} Hz); elastic P1 "
                  f"{je['P1_N'] / 1e3:.0f} kN ({je['f_P1_Hz']:.0f} Hz), P2 {je['P2_N'] / 1e3:.0f}"
                  f" kN ({je['f_P2_Hz']:.1f} Hz)")  # fmt: skip


if __name__ == "__main__":
    main()
