"""The compiled contact forces never fail, whatever state a Newton iteration tries."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railexu.model.assembly import VehicleModel
from railexu.model.forces import generalized_forces
from railexu.track.track import ideal_straight_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


def test_wild_states_give_finite_forces():
    """Newton iterates far from any physical state (a wheelset a metre off the track, upside
    down, spinning backwards) must give finite forces, zero where no wheel touches, so that the
    solver can cut its step and recover instead of stopping on an exception."""
    model = VehicleModel(load_vehicle(ROOT / "vehicles" / "eu07_bogie.yaml"),
                         ideal_straight_track(), 40.0, 0.0, 10.0)  # fmt: skip
    rng = np.random.default_rng(7)
    n = model._out.size
    data = model.kernel
    out = np.zeros(n)
    points = np.zeros_like(model.points)
    ws_force = np.zeros_like(model.ws_force)
    for scale in (1e-4, 1e-2, 1.0, 10.0):
        for _ in range(200):
            q = rng.normal(0.0, scale, n)
            qt = rng.normal(0.0, 10.0 * scale, n)
            generalized_forces(q, qt, data, out, points, ws_force)
            assert np.all(np.isfinite(out))
    # far off the track: no contact at all (the contact's force and torque on every wheelset;
    # ``out`` also holds the compiled suspension elements' forces since issue 26's couple fix,
    # and the springs to the displaced wheelsets pull on them)
    q = np.zeros(n)
    q[1::6] = 1.0
    ws_force[:] = np.nan
    generalized_forces(q, np.zeros(n), data, out, points, ws_force)
    assert np.all(ws_force == 0.0)
    assert np.all(np.isfinite(out))


def test_the_search_stays_within_the_work_array_its_caller_gives():
    """The contact search is compiled without numba's reference counting and allocates nothing:
    its callers pass its work array, sized by ``candidates_work_size`` (one slope per scan
    node, at most one node per wheel-table row, and the hidden-minima stack). Compiled code
    does not check bounds, so the test does: with the finest scan (a node at every table row)
    and wheelsets anywhere across the rail, rolled and yawed, no entry past that size is
    written, and the candidates are those of ``find_contact_candidates``, which sizes its own."""
    from railexu.contact import kernel as K
    from railexu.contact.evaluation import WheelsetContactModel
    from railexu.model.assembly import wheelset_geometry

    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
    model = WheelsetContactModel(wheelset_geometry(vehicle.wheelsets[0], ideal_straight_track()))
    wtab, winfo, rtab, rinfo = model.wtab_l, model.winfo_l, model.rtab_l, model.rinfo_l
    size = K.candidates_work_size(winfo)
    assert size >= int(winfo[K.WI_N])  # room for a slope at every row
    guard = 64
    rng = np.random.default_rng(11)
    finest = 0.5 * winfo[K.WI_STEP]  # the scan's stride is then one row
    r0 = winfo[K.WI_R0]
    for _ in range(400):
        cy = rng.uniform(-0.08, 0.08)
        phi = rng.uniform(-0.02, 0.02)
        psi = rng.uniform(-0.05, 0.05)
        cz = r0 + rng.uniform(-2e-3, 5e-4)
        work = np.full(size + guard, 1234.5)
        found = [np.full(K.MAX_POINTS, np.nan) for _ in range(3)]
        n = K._candidates(wtab, winfo, rtab, rinfo, cy, cz, phi, psi, finest, *found, work)
        assert np.all(work[size:] == 1234.5)
        expected = [np.full(K.MAX_POINTS, np.nan) for _ in range(3)]
        assert K.find_contact_candidates(wtab, winfo, rtab, rinfo, cy, cz, phi, psi, finest,
                                         *expected) == n  # fmt: skip
        for a, b in zip(found, expected, strict=True):
            np.testing.assert_array_equal(a, b)


def test_the_hot_compiled_functions_run_without_reference_counting():
    """The contact search and the per-wheel and per-wheelset evaluations are compiled without
    numba's reference counting of arrays (an atomic increment and decrement around each use
    of an array, 40 % of the seed run's integration before: docs/performance.md). If a numba
    release drops the option this test fails, to tell that the kernel became slower (its
    results stay the same)."""
    from railexu.contact import kernel as K
    from railexu.model import forces

    assert K.JIT_NO_REFCOUNT.get("_nrt") is False, "this numba cannot compile without NRT"
    hot = [K._candidates, K._refine, K._golden, K._refine_minimum, K._scan_edge_cell,
           K.wheel_contact, K.wheelset_contact_with_scratch, forces._wheelset,
           forces._curved_state, forces._irregularity, forces._to_vehicle_frame,
           forces._add_wheelset]  # fmt: skip
    for function in hot:
        assert function.targetoptions.get("_nrt") is False, function.py_func.__name__
