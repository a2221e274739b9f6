"""Cost of each nonlinear suspension element per force evaluation and per Jacobian, in the form
the dynamics calls it (``docs/suspension.md``).

For each element type the EU07 gets 8 such elements (mirrored pairs at both bogies and both
ends); printed per element:

- the compiled force (:func:`railexu.model.suspension_forces.suspension_forces` over the model's
  kernel rows, called in a compiled loop, as inside ``generalized_forces``);
- its finite-difference Jacobian (:func:`railexu.model.suspension_forces.suspension_jacobian`);
- for scale, one evaluation of the whole compiled force function of the EU07 (4 wheelsets'
  contacts).

A step of the implicit solver evaluates the forces at every Newton iteration (about 2 to 3 with
the modified Newton method) and the Jacobian only when Newton stalls, so the cost per step is
about 2.5 force evaluations plus a share of a Jacobian. Run: ``python
benchmarks/suspension_elements.py`` (timings vary by tens of percent between runs).
"""

from __future__ import annotations

import copy
import time

import numba
import numpy as np

from railexu.model.assembly import VehicleModel
from railexu.model.forces import generalized_forces
from railexu.model.suspension_forces import suspension_forces, suspension_jacobian
from railexu.track.track import ideal_straight_track
from railexu.vehicle.vehicle import load_vehicle, vehicle_from_dict

BOGIES = (("bogie_1", 3.95), ("bogie_2", -3.95))


def _pairs(kind: str, values: dict) -> dict:
    """Mirrored pairs at both ends of both bogies (8 elements)."""
    out = {}
    for b, x in BOGIES:
        for dx in (-0.5, 0.5):
            out[f"{kind}_{b}_{dx}"] = {"type": kind, "bodies": ["car_body", b],
                                       "position": [x + dx, 1.0, 0.95], "mirror_y": True,
                                       **values}  # fmt: skip
    return out


ELEMENTS = {
    "nonlinear_spring (4-point table)": _pairs("nonlinear_spring", {
        "direction": "y", "deflection": [0, 0.03, 0.04, 0.05], "force": [0, 0, 2e4, 8e4],
        "symmetric": True}),
    "nonlinear_spring (smooth, 4 points)": _pairs("nonlinear_spring", {
        "direction": "y", "deflection": [0, 0.03, 0.04, 0.05], "force": [0, 0, 2e4, 8e4],
        "symmetric": True, "interpolation": "smooth"}),
    "damper (blow-off table)": _pairs("damper", {
        "direction": "y", "velocity": [0, 0.05, 0.2], "force": [0, 1.2e4, 1.6e4],
        "symmetric": True}),
    "damper + series stiffness (Maxwell)": _pairs("damper", {
        "direction": "x", "damping": 2.5e5, "series_stiffness": 6e6}),
    "friction (regularised)": _pairs("friction", {"direction": "z", "friction_force": 3e3}),
    "friction + stick stiffness": _pairs("friction", {
        "direction": "z", "friction_force": 3e3, "stick_stiffness": 5e6}),
    "air_spring (reservoir branch)": _pairs("air_spring", {
        "vertical_stiffness": 3e5, "reservoir_stiffness": 2.5e5, "orifice_damping": 3e4}),
    "uic_link (x and y)": _pairs("uic_link", {
        "pendulum_length": [0.16, 0.2], "friction_coefficient": [0.2, 0.1],
        "stick_stiffness": [8e6, 2e6], "vertical_load": 5e4}),
}  # fmt: skip


@numba.njit(cache=True)
def _forces(n, q, qt, qref, si, sr, tab, out):
    acc = 0.0
    for i in range(n):
        q[0] = 1e-9 * (i % 7)  # defeat hoisting
        for k in range(out.shape[0]):
            out[k] = 0.0
        suspension_forces(q, qt, qref, si, sr, tab, out)
        acc += out[0]
    return acc


def _time(fn, repeat=5):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    base = load_vehicle("eu07")
    track = ideal_straight_track()
    model = VehicleModel(base, track, 30.0, 0.0, 10.0)
    q = model.mbs.systemData.GetODE2Coordinates()[model.object_ltg]
    qt = model.mbs.systemData.GetODE2Coordinates_t()[model.object_ltg]
    out = np.zeros(q.size)
    generalized_forces(q, qt, model.kernel, out, model.points, model.ws_force)
    n = 2000
    whole = _time(lambda: [generalized_forces(q, qt, model.kernel, out, model.points,
                                              model.ws_force) for _ in range(n)]) / n  # fmt: skip
    print(f"whole force function of the EU07 (4 wheelsets): {whole * 1e6:8.2f} us per evaluation")
    print(f"{'element':40s} {'force [us]':>11s} {'Jacobian [us]':>14s}  (per element)")
    for label, elements in ELEMENTS.items():
        _measure(label, elements, base, track)


def _measure(label: str, elements: dict, base, track) -> None:
    raw = copy.deepcopy(base.raw)
    raw["suspension"].update(elements)
    vehicle = vehicle_from_dict(raw, "bench", base_dir=base.base_dir)
    m = VehicleModel(vehicle, track, 30.0, 0.0, 10.0)
    d = m.kernel
    q = np.ascontiguousarray(m.mbs.systemData.GetODE2Coordinates()[m.object_ltg])
    qt = np.ascontiguousarray(m.mbs.systemData.GetODE2Coordinates_t()[m.object_ltg])
    qt += 1e-3  # moving: the laws' non-trivial branches
    out = np.zeros(q.size)
    count = d.se_int.shape[0]
    n = 20000
    rows = (d.qref, d.se_int, d.se_real, d.se_table)
    _forces(10, q.copy(), qt, *rows, out)
    t_f = _time(lambda: _forces(n, q.copy(), qt, *rows, out)) / n / count
    jac = np.zeros((q.size, q.size))
    args = (q, qt, *rows, 1.0, 0.5, jac, q.copy(), qt.copy(), np.zeros(q.size), np.zeros(q.size))
    suspension_jacobian(*args)
    nj = 200
    t_j = _time(lambda: [suspension_jacobian(*args) for _ in range(nj)]) / nj / count
    print(f"{label:40s} {t_f * 1e6:11.3f} {t_j * 1e6:14.2f}  ({count} kernel elements)")


if __name__ == "__main__":
    main()
