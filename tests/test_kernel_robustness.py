"""The compiled contact forces never fail, whatever state a Newton iteration tries."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railexu.forces import generalized_forces
from railexu.model import VehicleModel
from railexu.track import ideal_straight_track
from railexu.vehicle import load_vehicle

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
    # far off the track: no contact at all
    q = np.zeros(n)
    q[1::6] = 1.0
    generalized_forces(q, np.zeros(n), data, out, points, ws_force)
    assert np.all(out[: 6 * len(data.ws_slots)] == 0.0)
