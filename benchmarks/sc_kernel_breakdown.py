"""Where the compiled contact kernel's time goes on a crossing against plain track (issue 29).

For one wheel (the left, the crossing's side) on five rail tables, pressed with about 49 kN
where not stated:

- ``plain``: the plain rail (S1002 on Manchester UIC60, 1:40), one point on the tread;
- ``short crossing``: the two-rail effective section of CONTACT's ``uk_interrupt_v2`` at
  s = 160 mm (``benchmarks/sc_contact.py``'s case: nose and wing rail, 3 loaded points);
- ``UK plain 56E1``: the shipped crossing's own plain rail (upright), the reference of the
  next two;
- ``UK crossing``: the shipped whole crossing's effective section (the left side of
  ``uk_crossing_facing``) at s = 0.28 m, the transfer from wing rail to nose (two rails);
- ``turnout blade``: the shipped turnout's switch panel (through route, left side) 3.5 m
  after the toe, blade and stock rail;

it times, per call (best of several loops of ``n`` calls, one process, interleaved):

1. ``scan``: the gap and its slope at every scan node over the part of the wheel above the
   rail table (``kernel._node_gap``, as ``_candidates_at`` does before any refinement);
2. ``search``: the whole candidate search (``kernel._candidates_at``: scan, refinement of each
   minimum, hidden-minimum bisections, edge cells, humps);
3. ``patch``: the patch sums (``kernel.patch_centre``) of the penetrating candidates;
4. ``wheel``: the whole wheel evaluation (``kernel.wheel_contact``: search, patches, Hertz,
   creep forces), and the same without tangential forces (``P_TANGENTIAL = 0``): ``creep`` is
   the difference (creepages' Kalker coefficients and the creep law), ``hertz`` the rest of
   the per-point work (``wheel`` without creep ``- search - patch``).

and prints the rail table's rows, the scan's nodes and the candidates. The kernel's own
numbers are its own (no change to it): this is a measurement of the code as it is.

Run: ``python benchmarks/sc_kernel_breakdown.py [n]`` (timings vary by tens of percent on a
shared machine; compare the ratios of one run).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numba
import numpy as np

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.placement import symmetric_wheelset
from railexu.contact.variable_tables import section_rail_arrays, station_tables
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.track.track import load_track

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "switches_crossings" / "profiles"


@numba.njit(cache=True)
def _scan_loop(n, wtab, winfo, rtab, rinfo, cy, cz, scan_step):
    """The scan's node evaluations of ``_candidates_at`` alone (same nodes)."""
    acc = 0.0
    nodes = 0
    for _ in range(n):
        ctx = K._make_ctx(winfo, rinfo, cy, cz, 0.0, 0.0)
        wstep = ctx[K.C_WSTEP]
        stride = max(1, int(round(scan_step / wstep)))
        r22 = ctx[K.C_R22]
        sphi = -ctx[K.C_R23]
        y_lo = ctx[K.C_RY0]
        y_hi = y_lo + (ctx[K.C_RN] - 1) * ctx[K.C_RSTEP]
        margin = 0.004 + abs(ctx[K.C_TPSI]) * ctx[K.C_R0] * 3.0
        s_lo = (y_lo - cy - sphi * ctx[K.C_R0]) / r22 - ctx[K.C_TAPE] - margin
        s_hi = (y_hi - cy - sphi * ctx[K.C_R0]) / r22 - ctx[K.C_TAPE] + margin
        k_lo = max(0, int((s_lo - ctx[K.C_WS0]) / wstep))
        k_hi = min(int(ctx[K.C_WN]) - 1, int((s_hi - ctx[K.C_WS0]) / wstep) + 1)
        nodes = (k_hi - k_lo) // stride + 1
        for j in range(nodes):
            g, dg, py = K._node_gap(k_lo + j * stride, wtab, rtab, ctx)
            acc += g
    return acc, nodes


@numba.njit(cache=True)
def _search_loop(n, wtab, winfo, rtab, rinfo, cy, cz, scan_step, cs, cg, ch, work):
    found = 0
    for _ in range(n):
        ctx = K._make_ctx(winfo, rinfo, cy, cz, 0.0, 0.0)
        found = K._candidates_at(wtab, rtab, rtab, ctx, scan_step, cs, cg, ch, work)
    return found


@numba.njit(cache=True)
def _patch_steps(wtab, winfo, rtab, rinfo, cy, cz, found, cs, steps):
    """The patch sums' steps as ``kernel.wheel_contact`` takes them (same lines)."""
    ctx = K._make_ctx(winfo, rinfo, cy, cz, 0.0, 0.0)
    for k in range(found):
        F, F1, F2, okw = K._hermite(wtab, winfo[0], winfo[1], int(winfo[2]), cs[k])
        g, dg, Py, Pz, zr, zr1, zr2, ok = K._locus_gap(cs[k], F, F1, F2, rtab, ctx)
        inv = 1.0 / np.sqrt(1.0 + zr1 * zr1)
        delta = -g * inv
        q = 1.0 + F1 * F1
        kwy = -K._linear(wtab, 3, winfo[0], winfo[1], int(winfo[2]), cs[k]) / (q * np.sqrt(q))
        kry = -K._linear(rtab, 3, rinfo[0], rinfo[1], int(rinfo[2]), Py) * inv * inv * inv
        b_lat = 0.5 * (kwy + kry)
        half = np.sqrt(K.PATCH_EPSILON * max(delta, 0.0) / max(b_lat, 1.0)) * inv
        steps[k] = min(K.PATCH_STEP_MAX, max(K.PATCH_STEP_MIN, K.PATCH_STEP_SHARE * half))


@numba.njit(cache=True)
def _patch_loop(n, wtab, winfo, rtab, rinfo, cy, cz, found, cs, cg, ch, steps):
    acc = 0.0
    for _ in range(n):
        ctx = K._make_ctx(winfo, rinfo, cy, cz, 0.0, 0.0)
        for k in range(found):
            if cg[k] < 0.0:
                acc += K.patch_centre(k, found, cs, cg, ch, wtab, rtab, ctx, steps[k])[0]
    return acc


@numba.njit(cache=True)
def _wheel_loop(n, wtab, winfo, rtab, rinfo, htab, ktab, params, cy, cz, points, force, scratch):
    loaded = 0
    for _ in range(n):
        loaded = K.wheel_contact(wtab, winfo, rtab, rinfo, htab, ktab, params, 1.0, 0.0, cy, cz,
                                 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 2.0 / 0.46, 0.0, 0.0, 0.0, 0.0,
                                 0.0, points, 0, force, scratch, rtab)  # fmt: skip
    return loaded


def _best(f, repeat: int = 5) -> float:
    best = np.inf
    for _ in range(repeat):
        t = time.thread_time()
        f()
        best = min(best, time.thread_time() - t)
    return best


def cases() -> list[tuple[str, WheelsetContactModel, np.ndarray, np.ndarray, float, float]]:
    """``(label, model, rail table, rail info, lateral [m], wheelset height [m])``."""
    geo = symmetric_wheelset(
        "MBench_S1002", "MBench_UIC60", nominal_radius_m=0.46, inclination="1:40",
        gauge_m=1.435, flange_back_distance_m=1.36,
    )  # fmt: skip
    m = WheelsetContactModel(geo, speed_m_per_s=2.0)
    rail = VariableProfile(read_slcs(DATA / "uk_interrupt_v2.slcs", scale_to_mm=1000.0))
    short, short_info = section_rail_arrays(
        rail, 0.16, geo.left, rail_origin_m=(0.75, 0.0), x_max_m=0.06
    )
    track = load_track("uk_crossing_facing")
    uk = WheelsetContactModel(
        symmetric_wheelset(
            "MBench_S1002",
            track.rail_profile,
            nominal_radius_m=0.46,
            inclination="none",
            gauge_m=1.435,
            flange_back_distance_m=1.36,
        ),  # fmt: skip
        speed_m_per_s=2.0,
    )
    vr = track.variable_rails
    tabs, uk_info = station_tables(
        vr.left, uk.geometry.left, np.array([0.28]), rail_origin_m=vr.rail_origin_m,
        x_max_m=vr.x_max_m,
    )  # fmt: skip
    uk_height = _pressed_height(uk, tabs[0], uk_info, 0.0, 49_000.0)
    # the turnout's switch panel (through route, left: the straight blade against the curved
    # stock rail) 3.5 m after the toe, where the blade carries the wheel; the same 56E1 rail
    turnout = load_track("turnout_uk_r245_through_facing").variable_rails
    toe = turnout.left.panels[0].range_m[0] + 0.2  # the slices begin 0.2 m ahead of the toe
    blade, blade_info = station_tables(
        turnout.left, uk.geometry.left, np.array([toe + 3.5]),
        rail_origin_m=turnout.rail_origin_m, x_max_m=turnout.x_max_m,
    )  # fmt: skip
    return [
        ("plain", m, m.rtab_l, m.rinfo_l, 0.0035, 0.45997),
        ("short crossing (2 rails)", m, short, short_info, 0.0035, 0.4609236),
        ("UK plain 56E1", uk, uk.rtab_l, uk.rinfo_l, 0.0,
         _pressed_height(uk, uk.rtab_l, uk.rinfo_l, 0.0, 49_000.0)),
        ("UK crossing s = 0.28 m", uk, tabs[0], uk_info, 0.0, uk_height),
        ("turnout blade, toe + 3.5 m", uk, blade[0], blade_info, 0.0,
         _pressed_height(uk, blade[0], blade_info, 0.0, 49_000.0)),
    ]  # fmt: skip


def _pressed_height(m, rtab, rinfo, cy, load_n) -> float:
    """The wheelset height at which the left wheel carries ``load_n`` (bisection)."""
    pts = np.zeros((2, K.MAX_POINTS, K.N_POINT_FIELDS))
    scratch = np.zeros(4 * K.MAX_POINTS + K.candidates_work_size(m.winfo_l))
    lo, hi = m.geometry.left.nominal_radius_m - 0.01, m.geometry.left.nominal_radius_m + 0.01
    for _ in range(60):
        z = 0.5 * (lo + hi)
        f = np.zeros(6)
        _wheel_loop(1, m.wtab_l, m.winfo_l, rtab, rinfo, m.htab, m.ktab, m.params, cy, z, pts, f,
                    scratch)  # fmt: skip
        lo, hi = (z, hi) if f[2] > load_n else (lo, z)
    return 0.5 * (lo + hi)


def main(n: int = 20_000) -> None:
    print(f"per call of one wheel (the left), best of 5 x {n}, us:")
    print(f"{'case':<28s} {'rows':>5s} {'nodes':>5s} {'cand':>4s} {'load':>4s} {'scan':>7s} "
          f"{'search':>7s} {'patch':>7s} {'wheel':>7s} {'hertz':>7s} {'creep':>7s}")  # fmt: skip
    rows = []
    for label, m, rtab, rinfo, cy, cz in cases():
        scan_step = float(m.params[K.P_SCAN])
        cs, cg, ch = np.zeros(K.MAX_POINTS), np.zeros(K.MAX_POINTS), np.zeros(K.MAX_POINTS)
        work = np.zeros(K.candidates_work_size(m.winfo_l))
        scratch = np.zeros(4 * K.MAX_POINTS + work.size)
        pts = np.zeros((2, K.MAX_POINTS, K.N_POINT_FIELDS))
        f = np.zeros(6)
        args_w = (m.wtab_l, m.winfo_l, rtab, rinfo, m.htab, m.ktab, m.params, cy, cz, pts, f,
                  scratch)  # fmt: skip
        loaded = _wheel_loop(2, *args_w)
        found = _search_loop(2, m.wtab_l, m.winfo_l, rtab, rinfo, cy, cz, scan_step, cs, cg, ch,
                             work)  # fmt: skip
        _, nodes = _scan_loop(2, m.wtab_l, m.winfo_l, rtab, rinfo, cy, cz, scan_step)
        step = np.zeros(K.MAX_POINTS)
        _patch_steps(m.wtab_l, m.winfo_l, rtab, rinfo, cy, cz, found, cs, step)
        _patch_loop(2, m.wtab_l, m.winfo_l, rtab, rinfo, cy, cz, found, cs, cg, ch, step)
        t_scan = _best(lambda: _scan_loop(n, m.wtab_l, m.winfo_l, rtab, rinfo, cy, cz, scan_step))  # noqa: B023,E501
        t_search = _best(lambda: _search_loop(n, m.wtab_l, m.winfo_l, rtab, rinfo, cy, cz,  # noqa: B023
                                              scan_step, cs, cg, ch, work))  # noqa: B023  # fmt: skip
        t_patch = _best(lambda: _patch_loop(n, m.wtab_l, m.winfo_l, rtab, rinfo, cy, cz, found,  # noqa: B023
                                            cs, cg, ch, step))  # noqa: B023  # fmt: skip
        t_wheel = _best(lambda: _wheel_loop(n, *args_w))  # noqa: B023
        normal_only = m.params.copy()
        normal_only[K.P_TANGENTIAL] = 0.0
        args_n = (*args_w[:6], normal_only, *args_w[7:])
        t_normal = _best(lambda: _wheel_loop(n, *args_n))  # noqa: B023
        us = [t * 1e6 / n for t in (t_scan, t_search, t_patch, t_wheel, t_normal)]
        rows.append((label, us))
        print(f"{label:<28s} {int(rinfo[2]):5d} {nodes:5d} {found:4d} {loaded:4d} {us[0]:7.2f} "
              f"{us[1]:7.2f} {us[2]:7.2f} {us[3]:7.2f} {us[4] - us[1] - us[2]:7.2f} "
              f"{us[3] - us[4]:7.2f}")  # fmt: skip
    plain = {"short crossing (2 rails)": 0, "UK crossing s = 0.28 m": 2}
    plain["turnout blade, toe + 3.5 m"] = 2
    for label, us in rows:
        if label in plain:
            ref_label, ref = rows[plain[label]]
            print(f"ratio {label} / {ref_label}, whole wheel: {us[3] / ref[3]:.2f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20_000)
