"""The contact forces must not depend on the numerical scan grid of the contact-point search:
the EU07's S1002 wheel on the 60E1 gauge corner (tracks/curve_r300.yaml) touches at the flange
root and on the flange, with a shallow minimum-hump pair of the gap at the line-to-arc joint of
the S1002 flank. A search that finds that minimum at some poses and misses it at others makes
the normal force jump (by up to 200 N before issue 11's rework), and a Newton iteration whose
solution lies on a jump cannot converge: the R 300 m run then stops with a rounding-level change
of its input (docs/curving.md). Physical reference: the normal force is a continuous function of
the wheelset's pose (Hertz, dN/d(delta) = 1.5 N / delta), so it must be the same for any scan
grid, and it must not jump along a path through pose space."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.model.assembly import wheelset_geometry
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
SPEED = 17.2
#: the leading wheelset in the R 300 m curve at the flange-root two-point contact (lateral,
#: vertical [m], roll, yaw [rad], local track frame; tests/test_contact_two_point_continuity.py)
POSE = np.array([-6.1110945164045624e-03, 6.2517433869944150e-01, -6.9025248506109874e-04,
                 -9.0529960044296344e-03])  # fmt: skip
#: spread of the random poses around it: +-0.3 mm lateral, 20 um vertical (0 to 500 kN on the
#: right wheel), 0.3 mrad roll, 2 mrad yaw
SPREAD = np.array([3e-4, 2e-5, 3e-4, 2e-3])
#: Newton's residual tolerance is of the order of 0.1 N: a jump well below it cannot stop a step
JUMP_N = 0.05


@pytest.fixture(scope="module")
def model() -> WheelsetContactModel:
    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
    geometry = wheelset_geometry(vehicle.wheelsets[0], load_track(ROOT / "tracks/curve_r300.yaml"))
    return WheelsetContactModel(geometry, replace(vehicle.contact, scan_step_m=1.0e-3), SPEED)


def _state(model, pose):
    y, z, phi, psi = pose
    spin = SPEED / model.geometry.left.nominal_radius_m
    return np.array([0.0, y, z, phi, psi, SPEED, 0.0, 0.0, -spin * np.sin(psi),
                     spin * np.cos(phi) * np.cos(psi), 0.0])  # fmt: skip


def _normal(model, pose, scan_step_m=None) -> float:
    """Total normal force on the right (outer, flanging) wheel [N]."""
    if scan_step_m is not None:
        model.params[K.P_SCAN] = scan_step_m
    try:
        model.evaluate_raw(_state(model, pose))
    finally:
        model.params[K.P_SCAN] = model.parameters.scan_step_m
    return float(model._points[1, :, K.PF_N].sum())


def test_normal_force_does_not_depend_on_the_scan_grid(model):
    """400 random poses at the two-point contact and on the tread: the 1 mm scan gives the
    normal force of a scan at every table node (0.05 mm) within JUMP_N (measured: 0.005 N at
    most; the old search differed by more than 1 N at 0.3 % of such poses, by up to 195 N)."""
    rng = np.random.default_rng(5)
    worst = 0.0
    for i in range(400):
        if i % 2:
            pose = POSE + rng.normal(0.0, 1.0, 4) * SPREAD
        else:
            pose = POSE + np.array([rng.uniform(0.0, 6e-3), rng.normal(0.0, 4e-5),
                                    rng.normal(0.0, 3e-4), rng.normal(0.0, 3e-3)])  # fmt: skip
        coarse = _normal(model, pose)
        fine = _normal(model, pose, 5.0e-5)
        worst = max(worst, abs(coarse - fine))
    assert worst < JUMP_N


def _jumps(model, p0, d, n=1001):
    """Discontinuities of the normal force along ``p0 + t d``, ``t`` in [-1, 1]: intervals whose
    force change stands out from their neighbours', bisected down to 1e-13 of the path; what
    is left there is a jump (a continuous function's change vanishes)."""
    ts = np.linspace(-1.0, 1.0, n)
    forces = np.array([_normal(model, p0 + t * d) for t in ts])
    diff = np.diff(forces)
    pad = np.abs(np.concatenate([[diff[0]], diff, [diff[-1]]]))
    found = []
    for i in np.where(np.abs(diff) > 3.0 * np.minimum(pad[:-2], pad[2:]) + 0.2)[0]:
        a, b, fa, fb = ts[i], ts[i + 1], forces[i], forces[i + 1]
        for _ in range(40):
            m = 0.5 * (a + b)
            fm = _normal(model, p0 + m * d)
            if abs(fm - fa) > abs(fb - fm):
                b, fb = m, fm
            else:
                a, fa = m, fm
        if abs(fb - fa) > JUMP_N:
            found.append((a, fb - fa))
    return found


def test_normal_force_is_continuous_along_paths_through_the_two_point_contact(model):
    """Random straight paths of +-10 um lateral, +-1 um vertical, +-10 urad roll and +-0.1 mrad
    yaw around the two-point pose (the old search: jumps of 5 to 116 N on some of them)."""
    rng = np.random.default_rng(0)
    for _ in range(12):
        p0 = POSE + rng.normal(0.0, 1.0, 4) * SPREAD
        d = rng.normal(0.0, 1.0, 4) * np.array([1e-5, 1e-6, 1e-5, 1e-4])
        assert _jumps(model, p0, d) == []


def test_curvature_bounds_hold(model):
    """The bounds of the gap's curvature over a scan cell (kernel._curvature_bounds), on which
    the search for hidden minima relies, against the curvature of the kernel's own slope by
    finite differences at 200 points per cell, near the overlap at random poses."""
    rng = np.random.default_rng(11)
    wtab, winfo, rtab, rinfo = model.wtab_r, model.winfo_r, model.rtab_r, model.rinfo_r
    s0, step = winfo[K.WI_S0], winfo[K.WI_STEP]
    checked = 0
    for _ in range(16):
        y, z, phi, psi = POSE + rng.normal(0.0, 1.0, 4) * SPREAD
        ctx = K._make_ctx(winfo, rinfo, -y, z, -phi, -psi)
        for ka in range(300, 2200, 20):
            kb = ka + 20
            ga, _, pya = K._node_gap(ka, wtab, rtab, ctx)
            gb, _, pyb = K._node_gap(kb, wtab, rtab, ctx)
            if max(ga, gb) > 1e8 or min(ga, gb) > 1e-3:
                continue
            up, down = K._curvature_bounds(ka, kb, pya, pyb, wtab, rtab, ctx)
            s = np.linspace(s0 + ka * step, s0 + kb * step, 201)
            slope = np.array([K._gap_at(x, wtab, rtab, ctx)[1] for x in s])
            curvature = np.diff(slope) / np.diff(s)
            assert curvature.max() <= up and -curvature.min() <= down
            checked += 1
    assert checked > 50


def test_range_bounds_equal_the_loop_over_the_rows(model):
    """The scan cells' table bounds read from the sparse-table columns (kernel._range_bounds,
    two reads per bound) are exactly those of the loop over every row they replace, for every
    run length they serve (1 to 63 rows), anywhere in the wheel and rail tables; runs too long
    for them keep the loop."""
    rng = np.random.default_rng(5)
    for tab in (model.wtab_r, model.rtab_r):
        assert tab.shape[1] == K.N_TABLE_COLUMNS
        n = tab.shape[0]
        for length in range(1, 64):
            for a in [0, n - length, *rng.integers(0, n - length + 1, 20)]:
                b = a + length - 1
                fast = K._table_bounds(tab, a, b, False)
                rows = tab[a : b + 1]
                loop = (
                    np.abs(rows[:, 1]).max(),
                    rows[:, 2].min(),
                    rows[:, 2].max(),
                    np.abs(np.diff(rows[:, 2])).max() if length > 1 else 0.0,
                )
                assert fast == loop, (length, a)
        long = K._table_bounds(tab, 0, 100, False)  # 101 rows: the loop itself
        assert long[1] == tab[:101, 2].min() and long[3] == np.abs(np.diff(tab[:101, 2])).max()
