"""Cost of the EU07's compiled force function and of its Jacobian at the seed model's initial
state, in one process (``docs/suspension.md``, "Cost per element").

Issue 26's couple fix made the EU07's 12 linear spring-dampers compiled elements (36 axes in
12 groups) instead of Exudyn Cartesian spring-dampers; this prints the minimum over repeated
calls (robust on a shared machine) of:

- the whole compiled force function (:func:`railexu.model.forces.generalized_forces`: the 4
  wheelsets' contacts, the bump stops and the suspension elements);
- its Jacobian (:func:`railexu.model.forces.jacobian`);
- the suspension elements alone (:func:`railexu.model.suspension_forces.suspension_forces`).

Run it with two source trees to compare them, e.g. ``PYTHONPATH=<tree>/src python
benchmarks/force_function_eu07.py <label>``; the seed command's own timing is
``benchmarks/realtime.py``.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from railexu.model.assembly import VehicleModel
from railexu.model.forces import generalized_forces, jacobian
from railexu.model.suspension_forces import suspension_forces
from railexu.track.track import ideal_straight_track
from railexu.vehicle.vehicle import load_vehicle

ROUNDS = 5
FORCE_CALLS = 300
JACOBIAN_CALLS = 20


def _best(call, repeats: int) -> float:
    """The shortest of ``repeats`` calls [s]."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - start)
    return best


def main(label: str) -> None:
    model = VehicleModel(load_vehicle("eu07"), ideal_straight_track(), 10.0, 0.002, 10.0)
    d = model.kernel
    q = np.asarray(model.mbs.systemData.GetODE2Coordinates(), float)[model.object_ltg]
    qt = np.asarray(model.mbs.systemData.GetODE2Coordinates_t(), float)[model.object_ltg]
    out = np.zeros(q.size)
    jac = np.zeros((q.size, q.size))
    points, ws_force = model.points.copy(), model.ws_force.copy()

    def forces():
        generalized_forces(q, qt, d, out, points, ws_force)

    def jacobian_call():
        jacobian(q, qt, d, 1.0, 0.01, jac, points, ws_force)

    def suspension():
        suspension_forces(q, qt, d.qref, d.se_int, d.se_real, d.se_table, out)

    forces()
    jacobian_call()
    rows = [
        (_best(forces, FORCE_CALLS), _best(jacobian_call, JACOBIAN_CALLS),
         _best(suspension, FORCE_CALLS))
        for _ in range(ROUNDS)
    ]  # fmt: skip
    f, j, s = np.min(np.array(rows), axis=0)
    print(f"{label}: {d.se_int.shape[0]} kernel elements; force function {f * 1e6:.1f} us, "
          f"Jacobian {j * 1e3:.3f} ms, suspension elements {s * 1e6:.2f} us")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "this tree")
