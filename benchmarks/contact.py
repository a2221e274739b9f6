"""Time per wheelset contact evaluation, in the form the dynamics calls it.

One evaluation = both wheels of a wheelset, every contact point (tread and flange), the Hertz
normal force with damping and the creep forces with spin (the default law unless named), from
the wheelset's position and velocity. Printed:

- the compiled kernel called from compiled code (as inside the dynamics' force function, which
  evaluates all wheelsets in one compiled call);
- the same through the Python wrapper ``WheelsetContactModel.evaluate_raw`` (one call from
  Python per wheelset);
- the slow general four-parameter search, for comparison (it checks the kernel in the tests).

Run: ``python benchmarks/contact.py [CREEP_LAW ...]`` (default ``polach_fastsim``; timings vary
by tens of percent between runs).
"""

from __future__ import annotations

import time

import numba
import numpy as np

from railexu.contact import kernel as K
from railexu.contact.creep import creep_forces_nb, spin_blend_weight
from railexu.contact.evaluation import ContactParameters, WheelsetContactModel
from railexu.contact.kalker import kalker_coefficients
from railexu.contact.kik_piotrowski import patch_creep_forces, wheel_point_patch
from railexu.contact.placement import symmetric_wheelset
from railexu.contact.quasistatic import press_wheelset
from railexu.contact.search import general_contact_search


@numba.njit(cache=True)
def _loop(n, model_arrays, params, states, rails, points, force):
    wl, il, rl, ril, wr, ir, rr, rir, ht, kt = model_arrays
    acc = 0.0
    m = states.shape[0]
    for i in range(n):
        K.wheelset_contact(wl, il, rl, ril, wr, ir, rr, rir, ht, kt, params, states[i % m],
                           rails, points, force)  # fmt: skip
        acc += force[1]
    return acc


@numba.njit(cache=True)
def _creep_loop(n, code, phi):
    acc = 0.0
    for i in range(n):
        _, fy = creep_forces_nb(
            code, 1e-3 + 1e-9 * i, 2e-3, phi, 50000.0, 0.006, 0.005, 82e9, 4.3, 3.8, 1.6, 0.3,
            1.0, 1.0, 1.0, 0.0, 10.0,
        )  # fmt: skip
        acc += fy
    return acc


def per_point_costs() -> None:
    """Cost of one creep-law call: Polach, and FASTSIM as the default runs it at large spin."""
    cases = (
        (1, 0.1, "polach"),
        (4, 0.1, "polach_fastsim at small spin (Polach)"),
        (4, 3.0, "polach_fastsim at large spin (FASTSIM 10 x 10)"),
        (3, 3.0, "fastsim (20 x 20)"),
    )
    print("per contact point (a = 6 mm, b = 5 mm, 50 kN):")
    for code, phi, label in cases:
        _creep_loop(10, code, phi)
        best = np.inf
        for _ in range(5):
            t0 = time.perf_counter()
            _creep_loop(200_000, code, phi)
            best = min(best, (time.perf_counter() - t0) / 200_000)
        print(f"  {label:<48s} {best * 1e6:7.3f} us")


def _states(model: WheelsetContactModel, speed: float, r0: float) -> np.ndarray:
    """Realistic poses: tread contact near the centre and flange contact at 7 mm, with yaw and
    small lateral/vertical velocities."""
    rng = np.random.default_rng(1)
    out = []
    for y in (0.0, 0.002, 0.004, -0.003, 0.0068, -0.0068):
        yaw = 0.002 * np.sign(y)
        st = press_wheelset(model, y, yaw, 50000.0)
        for _ in range(20):
            out.append(
                [
                    0.0,
                    y + rng.normal(0, 1e-5),
                    st.vertical_m + rng.normal(0, 2e-6),
                    st.roll_rad,
                    yaw,
                    speed,
                    rng.normal(0, 0.01),
                    rng.normal(0, 0.001),
                    0.0,
                    speed / r0,
                    rng.normal(0, 0.01),
                ]
            )
    return np.array(out)


def _model(creep_model: str) -> tuple[WheelsetContactModel, np.ndarray, tuple]:
    r0, speed = 0.625, 10.0
    geometry = symmetric_wheelset("S1002", "UIC60", nominal_radius_m=r0, inclination="1:40")
    model = WheelsetContactModel(geometry, ContactParameters(creep_model=creep_model), speed)
    states = _states(model, speed, r0)
    arrays = (
        model.wtab_l, model.winfo_l, model.rtab_l, model.rinfo_l,
        model.wtab_r, model.winfo_r, model.rtab_r, model.rinfo_r, model.htab, model.ktab,
    )  # fmt: skip
    return model, states, arrays


def kernel_seconds_per_wheelset(creep_model: str = "polach_fastsim", n: int = 200_000) -> float:
    """The compiled kernel's time per wheelset evaluation [s], best of five loops over the
    benchmark's 120 states (what ``benchmarks/realtime.py`` takes as the contact floor)."""
    model, states, arrays = _model(creep_model)
    points = np.zeros((2, K.MAX_POINTS, K.N_POINT_FIELDS))
    force = np.zeros(6)
    rails = np.zeros(8)
    _loop(10, arrays, model.params, states, rails, points, force)  # compile / load cache
    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        _loop(n, arrays, model.params, states, rails, points, force)
        best = min(best, (time.perf_counter() - t0) / n)
    return best


def main(creep_model: str = "polach_fastsim") -> None:
    model, states, arrays = _model(creep_model)
    geometry = model.geometry
    points = np.zeros((2, K.MAX_POINTS, K.N_POINT_FIELDS))
    force = np.zeros(6)
    rails = np.zeros(8)
    best = kernel_seconds_per_wheelset(creep_model)
    _loop(10, arrays, model.params, states, rails, points, force)
    n_pts = np.mean([np.count_nonzero(points[:, :, K.PF_N] > 0)])
    print(f"S1002 / UIC60 1:40, r0 = 0.625 m, V = 10 m/s, creep law {creep_model}, 50 kN/wheel")
    print(f"  compiled kernel, from compiled code: {best * 1e6:6.2f} us per wheelset evaluation")
    print(f"    (both wheels, ~{n_pts:.0f} loaded points in the last state; limit 10 us)")

    weights = []
    for st in states:
        model.evaluate_raw(st, rails)
        for side in (0, 1):
            for k in range(K.MAX_POINTS):
                row = model._points[side, k]
                if row[K.PF_ACTIVE] and row[K.PF_N] > 0.0:
                    a, b = row[K.PF_A], row[K.PF_B]
                    c23 = kalker_coefficients(a / b, model.parameters.poisson)[2]
                    weights.append(
                        spin_blend_weight(
                            row[K.PF_SPIN], row[K.PF_N], model.parameters.friction, a, b,
                            model.parameters.shear_modulus_Pa, c23,
                        )
                    )  # fmt: skip
    weights = np.asarray(weights)
    print(
        f"    loaded points in the {len(states)} states: {weights.size}; FASTSIM weight > 0 "
        f"(polach_fastsim runs FASTSIM) at {np.mean(weights > 0) * 100:.0f} %"
    )

    n = 20_000
    t0 = time.perf_counter()
    for i in range(n):
        model.evaluate_raw(states[i % len(states)], rails)
    dt = (time.perf_counter() - t0) / n
    print(f"  through the Python wrapper:          {dt * 1e6:6.2f} us per call")

    st = states[0]
    model.evaluate_raw(st, rails)
    loaded = [p for p in model._result(model._force).points if p.loaded]

    def kik_piotrowski_once() -> None:
        for p in loaded:
            kp = wheel_point_patch(
                model, p.side, st[1], st[2], st[3], st[4], p.wheel_lateral_m, p.contact_angle_rad
            )
            patch_creep_forces(
                kp, p.creep_long, p.creep_lat, p.spin_per_m, model.parameters.friction,
                model.parameters.shear_modulus_Pa, model.parameters.poisson,
            )  # fmt: skip

    kik_piotrowski_once()
    reps = 50
    t0 = time.perf_counter()
    for _ in range(reps):
        kik_piotrowski_once()
    dt = (time.perf_counter() - t0) / reps
    print(
        f"  Kik-Piotrowski patch + strip FASTSIM (Python level, {len(loaded)} points): "
        f"{dt * 1e3:6.2f} ms per wheelset evaluation"
    )

    pair = geometry.left
    t0 = time.perf_counter()
    reps = 5
    for _ in range(reps):
        general_contact_search(pair, st[1], st[2], st[3], st[4])
    dt = (time.perf_counter() - t0) / reps
    print(f"  general 4-parameter search (1 wheel): {dt * 1e3:6.1f} ms (reference only)")


if __name__ == "__main__":
    import sys

    per_point_costs()
    for name in sys.argv[1:] or ["polach_fastsim"]:
        main(name)
