"""The compiled force function reads one contact table per distinct wheel (a vehicle's wheels
mostly share one profile), and each wheel the table of its own profile: the forces are those of
each wheel's own table (docs/performance.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railexu.contact.evaluation import wheel_arrays
from railexu.model.assembly import VehicleModel
from railexu.track.track import ideal_straight_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


def _model(overrides=()) -> VehicleModel:
    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml", overrides)
    return VehicleModel(vehicle, ideal_straight_track(), 10.0, 0.002, 5.0)


def _own_table(model: VehicleModel, i: int, side: int) -> np.ndarray:
    geometry = model.geometries[i]
    wheel = geometry.left if side == 0 else geometry.right
    tab, _ = wheel_arrays(wheel, model.contact_params.curvature_smoothing_m)
    return tab


def test_wheels_with_one_profile_share_one_table():
    model = _model()
    assert model.wtab.shape[0] == 1 and np.all(model.wtab_index == 0)
    tab = _own_table(model, 3, 1)
    assert np.array_equal(model.wtab[0, : tab.shape[0]], tab)


def test_each_wheel_reads_its_own_table(monkeypatch):
    """A wheel whose table differs (here the third wheelset's right wheel, its radius
    increased by 1 um everywhere): two tables, and every wheel reads exactly its own."""
    import railexu.model.assembly as model_module

    built = []
    original = model_module.wheel_arrays

    def wheel_arrays_one_differs(wheel, width):
        tab, info = original(wheel, width)
        if len(built) == 5:  # left, right of each wheelset in turn: ws3's right wheel
            tab = tab.copy()
            tab[:, 0] += 1.0e-6
        built.append(tab)
        return tab, info

    monkeypatch.setattr(model_module, "wheel_arrays", wheel_arrays_one_differs)
    model = _model()
    assert model.wtab.shape[0] == 2
    assert model.wtab_index.tolist() == [[0, 0], [0, 0], [0, 1], [0, 0]]
    for i in range(4):
        for side in range(2):
            tab = built[2 * i + side]
            assert np.array_equal(model.wtab[model.wtab_index[i, side], : tab.shape[0]], tab)
