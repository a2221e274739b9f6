"""The nonlinear suspension elements against analytic solutions (``docs/suspension.md``).

Element-level tests drive the compiled kernel (:mod:`railexu.model.suspension_forces`) on a rig of
one moving mass (or an imposed motion) against a fixed ground and integrate its equations with
scipy's Radau (tight tolerances, so that what remains is the element's own error); vehicle-level
tests check the statics, the start in equilibrium, and the linearised model (Exudyn's
``ComputeLinearizedSystem``) with the elements in it.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from railexu.errors import InputError
from railexu.model.characteristics import characteristic_table, table_force
from railexu.model.statics import static_equilibrium
from railexu.model.suspension_forces import (
    LAW_FRICTION,
    LAW_PLASTIC,
    LAW_TABLE,
    KernelElement,
    kernel_arrays,
    kernel_elements,
    suspension_forces,
    table_value,
)
from railexu.vehicle.vehicle import load_vehicle, vehicle_from_dict

AXIS = 2  # the rig moves along z


# -- the rig -------------------------------------------------------------------------------------
class Rig:
    """One kernel element between a fixed ground (node slot 0) and a mass (slot 1) moving along
    ``AXIS``; the element's internal coordinate (if any) is coordinate 12."""

    def __init__(self, element: KernelElement):
        element.bodies = ("ground", "mass")
        element.axis = AXIS
        self.element = element
        zero = np.zeros(3)
        self.si, self.sr, self.tab = kernel_arrays(
            [element], {"ground": 0, "mass": 1}, {element.name: ((zero, zero), 0.0)}, 12
        )
        self.n = 13 if element.internal else 12
        self.qref = np.zeros(self.n)
        self.m_i = element.internal_mass_kg() if element.internal else 0.0

    def forces(self, x, xt, u=0.0, ut=0.0):
        """(force on the mass along the axis, generalized force on the internal coordinate)."""
        q = np.zeros(self.n)
        qt = np.zeros(self.n)
        q[6 + AXIS], qt[6 + AXIS] = x, xt
        if self.n == 13:
            q[12], qt[12] = u, ut
        out = np.zeros(self.n)
        suspension_forces(q, qt, self.qref, self.si, self.sr, self.tab, out)
        return out[6 + AXIS], (out[12] if self.n == 13 else 0.0)

    def imposed(self, x_of_t, v_of_t, t_end, n_out=4000, u0=(0.0, 0.0)):
        """Force on the mass under an imposed motion ``x(t)`` (internal coordinate integrated
        from ``u0`` = (u, u'))."""
        t_eval = np.linspace(0.0, t_end, n_out)
        if self.n == 12:
            return t_eval, np.array([-self.forces(x_of_t(t), v_of_t(t))[0] for t in t_eval])

        def rhs(t, y):
            _, g = self.forces(x_of_t(t), v_of_t(t), y[0], y[1])
            return [y[1], g / self.m_i]

        sol = solve_ivp(rhs, (0.0, t_end), list(u0), method="Radau", t_eval=t_eval,
                        rtol=1e-8, atol=1e-12, jac=_jacobian(rhs))  # fmt: skip
        force = [-self.forces(x_of_t(t), v_of_t(t), u, ut)[0]
                 for t, u, ut in zip(t_eval, sol.y[0], sol.y[1], strict=True)]  # fmt: skip
        return t_eval, np.array(force)

    def free(self, mass_kg, y0, t_end, external=None, n_out=4000, max_step=np.inf):
        """Motion of the mass under the element and ``external(t)`` [N]; ``y0 = (x, v)``."""
        t_eval = np.linspace(0.0, t_end, n_out)

        internal = self.n == 13

        def rhs(t, y):
            u, ut = (y[2], y[3]) if internal else (0.0, 0.0)
            f, g = self.forces(y[0], y[1], u, ut)
            f_ext = external(t) if external else 0.0
            acc = (f + f_ext) / mass_kg
            return [y[1], acc, ut, g / self.m_i] if internal else [y[1], acc]

        y_start = [y0[0], y0[1], 0.0, 0.0] if internal else [y0[0], y0[1]]
        sol = solve_ivp(rhs, (0.0, t_end), y_start, method="Radau", t_eval=t_eval, rtol=1e-9,
                        atol=1e-12, max_step=max_step, jac=_jacobian(rhs))  # fmt: skip
        return sol.t, sol.y[0], sol.y[1]


def _jacobian(rhs, h=1e-9):
    """Central-difference Jacobian of ``rhs`` (scipy's own estimate fails on a right-hand
    side that is exactly zero at the start)."""

    def jac(t, y):
        y = np.asarray(y, float)
        cols = []
        for i in range(y.size):
            step = np.zeros_like(y)
            step[i] = h
            cols.append((np.asarray(rhs(t, y + step)) - np.asarray(rhs(t, y - step))) / (2 * h))
        return np.column_stack(cols)

    return jac


def _maxwell_start(k, c, omega, x_amp):
    """The steady state of a Maxwell element's internal coordinate at t = 0 under
    ``x = X sin(omega t)``: ``u = Im(U e^(i omega t))``, ``U = X k / (k + i omega c)``, so that
    the record starts without the transient (its time constant c / k may be long)."""
    big_u = x_amp * k / (k + 1j * omega * c)
    return big_u.imag, omega * big_u.real


def _harmonic_fit(t, force, omega, x_amp):
    """Complex dynamic stiffness ``F / x`` of the steady response to ``x = X sin(omega t)``
    (least squares on sin and cos over the last half of the record)."""
    keep = t >= t[-1] / 2
    a = np.column_stack([np.sin(omega * t[keep]), np.cos(omega * t[keep]), np.ones(keep.sum())])
    s, c, _ = np.linalg.lstsq(a, force[keep], rcond=None)[0]
    return complex(s, c) / x_amp


def _loop_energy(x, force):
    """Energy dissipated over the record (the area of the force-displacement loops) [J]."""
    return float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(x)))


# -- tables -------------------------------------------------------------------------------------
def test_tables_interpolate_and_continue_with_the_end_slopes():
    """Linear interpolation between points and the end segments' slopes beyond (exact for a
    piecewise-linear function); the smooth (PCHIP) table passes through the points and stays
    monotone (Fritsch and Carlson 1980)."""
    x, f = [-0.02, 0.0, 0.01, 0.03], [-4e3, 0.0, 1e3, 9e3]
    tab = characteristic_table(x, f, "linear")
    for at, expected in [(-0.03, -6e3), (-0.01, -2e3), (0.005, 500.0), (0.02, 5e3), (0.05, 17e3)]:
        assert table_value(tab, 0, len(tab), at) == pytest.approx(expected, rel=1e-12)
        assert table_force(tab, at) == pytest.approx(expected, rel=1e-12)
    smooth = characteristic_table(x, f, "smooth")
    for xi, fi in zip(x, f, strict=True):
        assert table_force(smooth, xi) == pytest.approx(fi, abs=1e-9)
    assert np.all(np.diff(smooth[:, 1]) >= 0.0)


# -- nonlinear spring -----------------------------------------------------------------------------
def _progressive():
    """A progressive spring: F = k0 d (1 + (d / d1)^2), sampled every 2 mm to 60 mm."""
    d = np.linspace(0.0, 0.06, 31)
    return d, 1.0e6 * d * (1.0 + (d / 0.03) ** 2)


def test_nonlinear_spring_free_decay_about_its_static_deflection():
    """A 2 t mass on a progressive spring table with a parallel damper: it rests where the
    table's force equals its weight (the static deflection), and a small disturbance decays
    with the frequency and damping of the tangent stiffness k_t (the slope of the table's
    segment there): omega_d = omega_n sqrt(1 - zeta^2), zeta = c / (2 sqrt(k_t m)). Tolerance
    0.3 %: the record's sampling of the zero crossings (4000 samples over 20 periods)."""
    d, f = _progressive()
    mass, c = 2000.0, 4000.0
    weight = mass * 9.81
    tab = characteristic_table(d, f, "linear")
    d_s = brentq(lambda x: table_force(tab, x) - weight, 0.0, 0.06)
    el = KernelElement("spring", ("a", "b"), (0, 0, 0), AXIS, spring_table=tab,
                       static_deflection_m=d_s, parallel_damping_N_s_per_m=c)  # fmt: skip
    rig = Rig(el)
    assert -rig.forces(0.0, 0.0)[0] == pytest.approx(weight, rel=1e-9)  # brentq's tolerance
    i = np.searchsorted(d, d_s) - 1
    k_t = (f[i + 1] - f[i]) / (d[i + 1] - d[i])
    omega_n = math.sqrt(k_t / mass)
    zeta = c / (2.0 * math.sqrt(k_t * mass))
    amplitude = 0.05 * min(d_s - d[i], d[i + 1] - d_s)  # stays within the segment
    # the rig's ground is the first body: +z of the mass compresses the spring (d > 0), so the
    # weight that compresses it acts along +z here
    period = 2 * math.pi / (omega_n * math.sqrt(1 - zeta**2))
    t, x, _ = rig.free(mass, (amplitude, 0.0), 20 * period, external=lambda t: weight)
    up = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    crossings = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    measured = np.mean(np.diff(crossings))
    assert measured == pytest.approx(period, rel=3e-3)
    peaks = [np.max(x[(t >= a) & (t < b)]) for a, b in zip(crossings[:-1], crossings[1:],
                                                          strict=True)]  # fmt: skip
    decrement = math.log(peaks[0] / peaks[-1]) / (len(peaks) - 1)
    assert decrement == pytest.approx(2 * math.pi * zeta / math.sqrt(1 - zeta**2), rel=3e-3)


def _eu07_with(elements: dict, changes: dict | None = None):
    v = load_vehicle("eu07")
    raw = copy.deepcopy(v.raw)
    for key, value in (changes or {}).items():
        node = raw
        *path, last = key.split(".")
        for p in path:
            node = node[p]
        node[last] = value
    raw["suspension"].update(copy.deepcopy(elements))
    return vehicle_from_dict(raw, "test", base_dir=v.base_dir)


def _nonlinear_secondary():
    """EU07 with its car body on progressive nonlinear springs instead of the linear secondary
    z stiffness (the same points, mirrored)."""
    d, f = _progressive()
    elements = {}
    for i, x in ((1, 3.95), (2, -3.95)):
        elements[f"secondary_z_{i}"] = {
            "type": "nonlinear_spring", "bodies": ["car_body", f"bogie_{i}"],
            "position": [x, 1.0, 0.95], "mirror_y": True, "direction": "z",
            "deflection": [float(v) for v in -d[::-1]][:-1] + [float(v) for v in d],
            "force": [float(v) for v in -f[::-1]][:-1] + [float(v) for v in f],
        }  # fmt: skip
    base = load_vehicle("eu07")
    kx, ky, _ = next(
        e for e in base.suspension if e.name.startswith("secondary_1")
    ).stiffness_N_per_m
    changes = {f"suspension.secondary_{i}.stiffness": {"x": kx, "y": ky, "z": 0.0} for i in (1, 2)}
    return _eu07_with(elements, changes)


def test_statics_give_the_nonlinear_springs_their_share_of_the_car_body():
    """EU07 with its car body on four progressive springs: by symmetry each carries a quarter of
    the car body's weight (plus its static loads), and the statics' deflection is where the
    table gives that force (the secant iteration's fixed point, 1e-6)."""
    vehicle = _nonlinear_secondary()
    statics = static_equilibrium(vehicle, [0.75] * len(vehicle.wheelsets))
    body = next(b for b in vehicle.bodies if b.name == "car_body")
    carried = body.mass_kg * vehicle.gravity_m_per_s2 - sum(
        ld.force_N[2] for ld in vehicle.loads if ld.body == "car_body" and ld.static
    )
    d, f = _progressive()
    tab = characteristic_table(d, f, "linear")
    for el in vehicle.suspension:
        if el.name.startswith("secondary_z"):
            d_s = statics.static_deflections[el.name]
            assert table_force(tab, d_s) == pytest.approx(carried / 4, rel=1e-6)
            assert -statics.element_forces[el.name][2] == pytest.approx(carried / 4, rel=1e-6)


@pytest.mark.slow
def test_vehicle_on_nonlinear_and_air_springs_starts_in_equilibrium():
    """EU07 on progressive springs, air springs, yaw dampers with bushes, friction and an
    anti-roll bar, on ideal straight track: the preloads hold it at rest (wheel loads within
    0.5 N of the statics over 0.4 s)."""
    vehicle = _nonlinear_secondary()
    extra = {
        "air": {"type": "air_spring", "bodies": ["car_body", "bogie_1"],
                "position": [3.95, 0.9, 0.95], "mirror_y": True,
                "vertical_stiffness": "0.3 MN/m", "reservoir_stiffness": "0.25 MN/m",
                "orifice_damping": "30 kN s/m"},
        "yaw": {"type": "damper", "bodies": ["car_body", "bogie_2"],
                "position": [-3.95, 1.2, 0.8], "mirror_y": True, "direction": "x",
                "damping": "200 kN s/m", "series_stiffness": "6 MN/m"},
        "wedge": {"type": "friction", "bodies": ["bogie_1", "ws1"],
                  "position": [5.45, 1.05, 0.625], "mirror_y": True, "direction": "z",
                  "friction_force": "3 kN", "stick_stiffness": "5 MN/m"},
        "arb": {"type": "anti_roll_bar", "bodies": ["car_body", "bogie_1"],
                "position": [3.95, 0.0, 0.95], "stiffness": "2 MN m/rad"},
    }  # fmt: skip
    raw = copy.deepcopy(vehicle.raw)
    raw["suspension"].update(extra)
    vehicle = vehicle_from_dict(raw, "test", base_dir=vehicle.base_dir)
    from railexu.results.run import RunSettings, run
    from railexu.track.track import ideal_straight_track

    settings = RunSettings(speed_m_per_s=20.0, distance_m=8.0, initial_lateral_m=0.0)
    result = run(vehicle, ideal_straight_track(), settings)
    assert result.status["state"] == "completed"
    statics = static_equilibrium(vehicle, [0.75] * 4)
    ts = result.timeseries
    for w, ws in enumerate(vehicle.wheelsets):
        for s, side in enumerate(("left", "right")):
            q = np.asarray(ts[f"{ws.name}_{side}_Q_N"])
            # 0.5 N of ~100 kN (measured 0.07 N): the statics here assume the contact points
            # at 0.75 m, the model finds them within a fraction of a millimetre of that
            assert np.max(np.abs(q - statics.wheel_loads_N[w, s])) < 0.5


# -- dampers --------------------------------------------------------------------------------------
def test_damper_table_with_blow_off_gives_its_force_at_each_velocity():
    """A damper without bushes: the force is the table's at the relative velocity (an
    antisymmetric blow-off characteristic, 12 kN at 0.05 m/s then 16 kN at 0.2 m/s)."""
    v = (-0.2, -0.05, 0.0, 0.05, 0.2)
    f = (-16e3, -12e3, 0.0, 12e3, 16e3)
    el = KernelElement("d", ("a", "b"), (0, 0, 0), AXIS, law=LAW_TABLE,
                       law_table=characteristic_table(v, f, "linear"))  # fmt: skip
    rig = Rig(el)
    for vel, expected in [(0.025, 6e3), (0.05, 12e3), (0.125, 14e3), (-0.3, -16e3 - 8e3 / 3)]:
        assert -rig.forces(0.0, vel)[0] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("ratio", [0.1, 1.0, 10.0])
def test_maxwell_damper_dynamic_stiffness(ratio):
    """A damper c in series with its bushes k (a yaw damper: 250 kN s/m, 6 MN/m) under an
    imposed harmonic displacement: the complex dynamic stiffness is the Maxwell element's
    K = k c i omega / (k + c i omega) at omega = 0.1, 1 and 10 times k / c. Tolerance 0.5 %:
    the internal coordinate's small mass shifts it by (k / (omega_i c))^2 < 0.25 %."""
    k, c = 6.0e6, 2.5e5
    el = KernelElement("yd", ("a", "b"), (0, 0, 0), AXIS, law=LAW_TABLE,
                       law_table=characteristic_table((-1.0, 1.0), (-c, c), "linear"),
                       series_stiffness_N_per_m=k)  # fmt: skip
    rig = Rig(el)
    omega = ratio * k / c
    x_amp = 1e-3
    t, force = rig.imposed(
        lambda t: x_amp * math.sin(omega * t),
        lambda t: x_amp * omega * math.cos(omega * t),
        4 * 2 * math.pi / omega,
        u0=_maxwell_start(k, c, omega, x_amp),
    )
    measured = _harmonic_fit(t, force, omega, x_amp)
    expected = k * c * 1j * omega / (k + c * 1j * omega)
    assert abs(measured - expected) < 5e-3 * abs(expected)


def test_air_spring_dynamic_stiffness_from_static_to_high_frequency():
    """An air spring (k1 = 0.3 MN/m, reservoir k2 = 0.25 MN/m through c = 30 kN s/m):
    K(omega) = k1 + k2 c i omega / (k2 + c i omega), so K(0) = k1 and K(inf) = k1 + k2 (Berg
    1999, linear form). Measured at omega = 0.01 and 100 times k2 / c: |K| within 0.2 % of k1
    and of k1 + k2 (the formula's own difference from its limits there is < 0.01 %), and at
    k2 / c the full complex value within 0.5 %."""
    vehicle = _eu07_with({"air": {
        "type": "air_spring", "bodies": ["car_body", "bogie_1"], "position": [3.95, 0.9, 0.95],
        "vertical_stiffness": "0.3 MN/m", "reservoir_stiffness": "0.25 MN/m",
        "orifice_damping": "30 kN s/m"}})  # fmt: skip
    statics = static_equilibrium(vehicle, [0.75] * 4)
    (el,) = kernel_elements(vehicle, statics)
    air = next(e for e in vehicle.suspension if e.name == "air")
    k1, k2, c = 0.3e6, 0.25e6, 30e3
    assert (air.vertical_stiffness_N_per_m, air.reservoir_stiffness_N_per_m) == (k1, k2)
    rig = Rig(el)
    for ratio, expected_abs in [(0.01, k1), (1.0, None), (100.0, k1 + k2)]:
        omega = ratio * k2 / c
        x_amp = 1e-3
        t, force = rig.imposed(
            lambda t, w=omega, a=x_amp: a * math.sin(w * t),
            lambda t, w=omega, a=x_amp: a * w * math.cos(w * t),
            4 * 2 * math.pi / omega,
            u0=_maxwell_start(k2, c, omega, x_amp),
        )
        measured = k1 + _harmonic_fit(t, force, omega, x_amp)  # k1 is the linear connector
        exact = k1 + k2 * c * 1j * omega / (k2 + c * 1j * omega)
        if expected_abs is None:
            assert abs(measured - exact) < 5e-3 * abs(exact)
        else:
            assert abs(measured) == pytest.approx(expected_abs, rel=2e-3)


# -- friction -----------------------------------------------------------------------------------
def _coulomb_exact(mass, f_c, p, omega, t_end):
    """Exact motion of a mass on Coulomb friction ``F_c`` under ``p sin(omega t)`` from rest
    at t = 0: it sticks while ``|p sin| <= F_c``; sliding in direction s,
    ``m v' = p sin(omega t) - s F_c`` integrates in closed form until v = 0 (the stop, found by
    brentq), and it sticks again unless the force still exceeds friction. Returns a function of
    t giving (x, v)."""
    period = 2 * math.pi / omega
    pieces = []  # (t0, t1, x0, s): s = 0 stuck, else sliding from rest at t0 in direction s

    def velocity(t0, s, tt):
        return (p / (mass * omega)) * (math.cos(omega * t0) - math.cos(omega * tt)) - (
            s * f_c / mass * (tt - t0)
        )

    def position(t0, x0, s, tt):
        drive = (
            math.cos(omega * t0) * (tt - t0) - (math.sin(omega * tt) - math.sin(omega * t0)) / omega
        )
        return x0 + (p / (mass * omega)) * drive - s * f_c / (2 * mass) * (tt - t0) ** 2

    def excess(tt):
        return abs(p * math.sin(omega * tt)) - f_c

    t, x = 0.0, 0.0
    while t < t_end:
        start = t
        if excess(t) <= 0.0:  # stuck until the force overcomes friction
            grid = np.linspace(t, t + period, 4001)
            j = next(i for i, g in enumerate(grid) if excess(g) > 0.0)
            start = brentq(excess, grid[j - 1], grid[j], xtol=1e-14)
            pieces.append((t, start, x, 0))
        s = 1 if math.sin(omega * start) > 0 else -1
        grid = np.linspace(start + period / 4000, start + period, 4000)
        j = next(i for i, g in enumerate(grid) if s * velocity(start, s, g) <= 0.0)
        stop = brentq(lambda tt, a=start, d=s: velocity(a, d, tt), grid[j - 1], grid[j],
                      xtol=1e-14)  # fmt: skip
        pieces.append((start, stop, x, s))
        x = position(start, x, s, stop)
        t = stop

    def at(time):
        for t0, t1, x0, s in pieces:
            if t0 <= time <= t1:
                return (x0, 0.0) if s == 0 else (position(t0, x0, s, time), velocity(t0, s, time))
        raise ValueError(time)

    return at


def test_mass_on_coulomb_friction_under_a_sine_force_sticks_and_slips_as_exact():
    """A 500 kg mass on regularised Coulomb friction (F_c = 2 kN, slip velocity 0.1 mm/s) under
    4 kN sin(2 pi t): stick while the force is below F_c, slide, stop, stick (den Hartog 1931's
    case without viscous damping, solved piecewise in closed form). Over two periods the
    velocity agrees within 1 % of its peak and the displacement within 1 % of its range: the
    regularisation creeps at v_s atanh(F / F_c) while stuck and lags the stops by ~ m v_s / F_c."""
    mass, f_c, p, omega = 500.0, 2.0e3, 3.0e3, 2 * math.pi
    el = KernelElement("fr", ("a", "b"), (0, 0, 0), AXIS, law=LAW_FRICTION,
                       friction_force_N=f_c, slip_velocity_m_per_s=1e-4)  # fmt: skip
    rig = Rig(el)
    t, x, v = rig.free(mass, (0.0, 0.0), 2.0, external=lambda t: p * math.sin(omega * t),
                       max_step=1e-3)  # fmt: skip
    exact = _coulomb_exact(mass, f_c, p, omega, 2.0)
    xe, ve = np.array([exact(a) for a in t]).T
    assert np.max(np.abs(v - ve)) < 0.01 * np.max(np.abs(ve))
    assert np.max(np.abs(x - xe)) < 0.01 * (np.max(xe) - np.min(xe))
    stuck = np.abs(ve) == 0.0
    assert stuck.mean() > 0.15  # the exact motion sticks for about a fifth of the time
    # and the regularised one only creeps then (v_s atanh(F / F_c) stays below 2 % of the peak)
    assert np.max(np.abs(v[stuck])) < 0.02 * np.max(np.abs(ve))


def test_friction_with_stick_stiffness_dissipates_the_elastic_plastic_loop():
    """A slider (F_c = 4 kN) behind a stick stiffness k = 5 MN/m under an imposed displacement
    X sin(omega t), X = 4 mm, 5 Hz: the elastic-perfectly-plastic loop (Masing) dissipates
    4 F_c (X - F_c / k) per cycle and peaks at F_c. Tolerance 2 %: the viscoplastic flow adds
    (|v| / 10 m/s) F_c while sliding, up to 1.3 % at the 126 mm/s here."""
    f_c, k, x_amp, omega = 4.0e3, 5.0e6, 4e-3, 10 * math.pi
    el = KernelElement("fr", ("a", "b"), (0, 0, 0), AXIS, law=LAW_PLASTIC, friction_force_N=f_c,
                       series_stiffness_N_per_m=k)  # fmt: skip
    rig = Rig(el)
    period = 2 * math.pi / omega
    t, force = rig.imposed(lambda t: x_amp * math.sin(omega * t),
                           lambda t: x_amp * omega * math.cos(omega * t), 3 * period,
                           n_out=12000)  # fmt: skip
    last = t >= 2 * period
    x = x_amp * np.sin(omega * t[last])
    energy = _loop_energy(x, force[last])
    assert energy == pytest.approx(4 * f_c * (x_amp - f_c / k), rel=2e-2)
    assert np.max(np.abs(force[last])) == pytest.approx(f_c, rel=2e-2)


# -- UIC link -----------------------------------------------------------------------------------
def _wagon_like():
    """EU07 with a UIC link at every primary spring point (x, y): the primary springs' static
    loads are the links' vertical loads."""
    link = {"type": "uic_link", "mirror_y": True,
            "pendulum_length": {"x": "0.16 m", "y": "0.2 m"},
            "friction_coefficient": {"x": 0.2, "y": 0.1},
            "stick_stiffness": {"x": "8 MN/m", "y": "2 MN/m"}}  # fmt: skip
    base = load_vehicle("eu07")
    elements = {}
    for el in base.suspension:
        if el.name.startswith("primary_") and el.name.endswith("_left"):
            name = el.name.removesuffix("_left").replace("primary", "link")
            elements[name] = {**link, "bodies": list(el.bodies), "position": list(el.position_m)}
    return _eu07_with(elements)


def test_uic_link_takes_the_static_load_of_its_spring():
    """Each link's vertical load W is the static load of the primary spring at its point (the
    vehicle is symmetric: an eighth of what the springs carry, the sprung weight), its pendulum
    stiffness W / L and friction limit mu W (Piotrowski 2003)."""
    vehicle = _wagon_like()
    statics = static_equilibrium(vehicle, [0.75] * 4)
    sprung = (vehicle.total_mass_kg - sum(w.mass_kg for w in vehicle.wheelsets)) * 9.81
    sprung -= sum(ld.force_N[2] for ld in vehicle.loads if ld.static)
    elements = kernel_elements(vehicle, statics)
    assert len(elements) == 16  # 8 links, x and y
    for e in elements:
        w = e.friction_force_N / (0.2 if e.axis == 0 else 0.1)
        assert w == pytest.approx(sprung / 8, rel=1e-3)  # symmetric: 8 equal springs
        length = 0.16 if e.axis == 0 else 0.2
        assert e.parallel_stiffness_N_per_m == pytest.approx(w / length, rel=1e-12)


def test_uic_link_lateral_hysteresis_loop():
    """A link (W = 50 kN, L = 0.2 m, mu = 0.1, stick stiffness 2 MN/m) driven laterally by
    X sin(omega t), X = 10 mm: the pendulum W / L is conservative, the friction element
    dissipates 4 mu W (X - mu W / k) per cycle; at the turning points the force is
    W X / L + mu W. Tolerance 1 % (the viscoplastic flow adds up to 0.6 % of mu W at the
    63 mm/s of sliding here)."""
    w, length, mu, k, x_amp, omega = 50e3, 0.2, 0.1, 2e6, 10e-3, 2 * math.pi
    el = KernelElement("link_y", ("a", "b"), (0, 0, 0), AXIS, parallel_stiffness_N_per_m=w / length,
                       law=LAW_PLASTIC, friction_force_N=mu * w,
                       series_stiffness_N_per_m=k)  # fmt: skip
    rig = Rig(el)
    period = 2 * math.pi / omega
    t, force = rig.imposed(lambda t: x_amp * math.sin(omega * t),
                           lambda t: x_amp * omega * math.cos(omega * t), 3 * period,
                           n_out=12000)  # fmt: skip
    last = t >= 2 * period
    x = x_amp * np.sin(omega * t[last])
    assert _loop_energy(x, force[last]) == pytest.approx(4 * mu * w * (x_amp - mu * w / k),
                                                         rel=1e-2)  # fmt: skip
    assert np.max(force[last]) == pytest.approx(w * x_amp / length + mu * w, rel=1e-2)


# -- in the linearised vehicle ------------------------------------------------------------------
def _linearised(vehicle, speed=40.0):
    from railexu.model.assembly import VehicleModel
    from railexu.stability.linear import linear_model_vehicle
    from railexu.stability.settings import CriticalSpeedSettings
    from railexu.track.track import ideal_straight_track

    lin, track, _ = linear_model_vehicle(vehicle, ideal_straight_track(), CriticalSpeedSettings())
    model = VehicleModel(lin, track, speed, 0.0, 10.0)
    return model, [np.asarray(m) for m in model.mbs.ComputeLinearizedSystem()]


def test_anti_roll_bar_adds_its_roll_stiffness_between_the_bodies():
    """An anti-roll bar of 2 MN m/rad between the EU07 car body and bogie_1: the linearised
    stiffness matrix gains exactly +k on both roll coordinates and -k between them, nothing
    else (1e-6 of k: the finite differences of Exudyn's linearisation)."""
    k = 2.0e6
    base_model, (_, k0, _) = _linearised(load_vehicle("eu07"))
    arb = {"arb": {"type": "anti_roll_bar", "bodies": ["car_body", "bogie_1"],
                   "position": [3.95, 0.0, 0.95], "stiffness": k}}  # fmt: skip
    model, (_, k1, _) = _linearised(_eu07_with(arb))
    diff = k1 - k0
    cb, bg = model.ltg["car_body"][3], model.ltg["bogie_1"][3]
    expected = np.zeros_like(diff)
    expected[cb, cb] = expected[bg, bg] = k
    expected[cb, bg] = expected[bg, cb] = -k
    assert np.max(np.abs(diff - expected)) < 1e-6 * k


def _coach_with_yaw_dampers(series_stiffness=None, c=250e3, spring=None):
    """The Manchester coach with a pair of yaw dampers per bogie (1.3 m from the centre)."""
    elements = {}
    for b, x in (("bogie_1", 9.5), ("bogie_2", -9.5)):
        e = {
            "type": "damper",
            "bodies": ["car_body", b],
            "position": [x, 1.3, 0.8275],
            "mirror_y": True,
            "direction": "x",
            "damping": c,
        }
        if series_stiffness:
            e["series_stiffness"] = series_stiffness
        if spring is not None:  # its linear equivalent (k, c) as a spring-damper
            e = {
                "type": "spring_damper",
                "bodies": e["bodies"],
                "position": e["position"],
                "mirror_y": True,
                "stiffness": {"x": spring[0]},
                "damping": {"x": spring[1]},
            }
        elements[f"yaw_damper_{b}"] = e
    v = load_vehicle("manchester_coach")
    raw = copy.deepcopy(v.raw)
    raw["suspension"].update(elements)
    return vehicle_from_dict(raw, "test", base_dir=v.base_dir)


def _lateral_eigenvalues(model, mats):
    from railexu.stability.linear import lateral_modes

    return sorted((m.eigenvalue for m in lateral_modes(model)), key=lambda s: s.imag)


def test_yaw_damper_with_stiff_bushes_is_the_pure_damper():
    """Manchester coach with yaw dampers (250 kN s/m): bushes of 10 GN/m in series (a Maxwell
    element with an internal coordinate) give the lateral eigenvalues of the pure damper (a
    linear connector) within 0.1 %; the bush's flexibility c omega / k is 1e-4 at 5 Hz."""
    pure = _lateral_eigenvalues(*_linearised(_coach_with_yaw_dampers()))
    stiff = _lateral_eigenvalues(*_linearised(_coach_with_yaw_dampers(1.0e10)))
    assert len(pure) == len(stiff)
    for a, b in zip(pure, stiff, strict=True):
        assert abs(a - b) < 1e-3 * abs(a)


def test_yaw_damper_with_soft_bushes_equals_its_dynamic_stiffness_at_the_eigenvalue():
    """Manchester coach with yaw dampers of 250 kN s/m behind 5 MN/m bushes: at an eigenvalue s
    of the model, each damper acts as K(s) = k c s / (k + c s). Replacing the dampers by linear
    spring-dampers with k_e + c_e s = K(s) (c_e = Im K / Im s, k_e = Re K - c_e Re s) must leave
    s an eigenvalue of the linear model: checked for the least damped hunting mode within
    1e-4 of |s| (the internal mass shifts it by (k / (omega_i c))^2 = 1e-5; measured 1e-6; the
    pure damper's eigenvalue differs by 12 %)."""
    k, c = 5.0e6, 250e3
    model, mats = _linearised(_coach_with_yaw_dampers(k, c))
    from railexu.stability.linear import lateral_modes

    hunting = min((m for m in lateral_modes(model) if "hunting" in m.name),
                  key=lambda m: m.damping_ratio)  # fmt: skip
    s = hunting.eigenvalue
    big_k = k * c * s / (k + c * s)
    c_e = big_k.imag / s.imag
    k_e = big_k.real - c_e * s.real
    model2, (m2, k2, d2) = _linearised(_coach_with_yaw_dampers(spring=(k_e, c_e)))
    n = m2.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(m2, k2), -np.linalg.solve(m2, d2)]])  # fmt: skip
    values = np.linalg.eigvals(a)
    assert np.min(np.abs(values - s)) < 1e-4 * abs(s)


# -- bad inputs ---------------------------------------------------------------------------------
_DAMPER = {"type": "damper", "bodies": ["car_body", "bogie_1"], "position": [3.95, 1.2, 0.8],
           "direction": "x"}  # fmt: skip
_SPRING = {"type": "nonlinear_spring", "bodies": ["car_body", "bogie_1"],
           "position": [3.95, 0.0, 0.95], "direction": "y"}  # fmt: skip


@pytest.mark.parametrize(
    ("element", "key", "words"),
    [
        ({**_DAMPER, "damping": "100 kN s/m", "dampnig": 1}, "dampnig", "Did you mean"),
        ({**_DAMPER}, "damping", "give a damping coefficient or a velocity/force table"),
        ({**_DAMPER, "damping": 1e5, "velocity": [0, 1], "force": [0, 1e5]}, "damping", "not both"),
        ({**_DAMPER, "damping": -1e5}, "damping", "must be > 0"),
        ({**_DAMPER, "velocity": [0, 0.1, 0.2], "force": [0, 1e4]}, "force", "has 2 values"),
        (
            {**_DAMPER, "velocity": [0, 0.2, 0.1], "force": [0, 1e4, 2e4]},
            "velocity",
            "must increase",
        ),
        ({**_DAMPER, "velocity": [-0.1, 0.1], "force": [-1e4, 3e4]}, "force", "0 at zero velocity"),
        (
            {**_DAMPER, "velocity": [0.1, 0.2], "force": [1e4, 2e4], "symmetric": True},
            "velocity",
            "starts at velocity 0",
        ),
        ({**_DAMPER, "damping": 1e5, "series_stiffness": 0}, "series_stiffness", "must be > 0"),
        (
            {**_SPRING, "deflection": [0, 0.01, 0.02], "force": [0, 2e4, 1e4]},
            "force",
            "must not decrease",
        ),
        ({**_SPRING, "deflection": [0, 0.01], "force": [0, 0]}, "force", "constant"),
        (
            {**_SPRING, "deflection": [0, 0.01], "force": [0, "1 kN"], "interpolation": "cubic"},
            "interpolation",
            "not one of",
        ),
        ({**_SPRING, "deflection": "1 mm", "force": [0, 1]}, "deflection", "at least 2 values"),
        ({**_SPRING, "deflection": [0, "1 kg"], "force": [0, 1]}, "deflection.1", "kg"),
        (
            {
                "type": "friction",
                "bodies": ["bogie_1", "ws1"],
                "position": [5.45, 1.05, 0.625],
                "direction": "z",
                "friction_force": 0,
            },
            "friction_force",
            "must be > 0",
        ),
        (
            {
                "type": "air_spring",
                "bodies": ["car_body", "bogie_1"],
                "position": [3.95, 1.0, 0.95],
                "vertical_stiffness": "0.3 MN/m",
                "reservoir_stiffness": -1,
                "orifice_damping": 3e4,
            },
            "reservoir_stiffness",
            "must be >= 0",
        ),
        (
            {
                "type": "anti_roll_bar",
                "bodies": ["bogie_1", "ws1"],
                "position": [5.45, 0, 0.625],
                "stiffness": 1e6,
            },
            "bodies",
            "not a wheelset",
        ),
        (
            {
                "type": "anti_roll_bar",
                "bodies": ["car_body", "bogie_1"],
                "position": [3.95, 0, 1],
                "stiffness": 1e6,
                "mirror_y": True,
            },
            "mirror_y",
            "unknown key",
        ),
        (
            {
                "type": "uic_link",
                "bodies": ["bogie_1", "ws1"],
                "position": [5.45, 1.05, 0.625],
                "pendulum_length": [0.16, 0.2],
                "friction_coefficient": [0.2, 1.5],
                "stick_stiffness": [1e6, 1e6],
            },
            "friction_coefficient.1",
            "must be <= 1",
        ),
    ],
)
def test_bad_element_values_are_refused_at_their_key(element, key, words):
    with pytest.raises(InputError) as info:
        _eu07_with({"bad": element})
    message = str(info.value)
    assert f"suspension.bad.{key}" in message, message
    assert words in message, message


def test_uic_link_without_a_vertical_spring_asks_for_its_load():
    """A link where no spring carries a vertical load: the model refuses it and asks for
    ``vertical_load``."""
    from railexu.model.assembly import ModelError, VehicleModel
    from railexu.track.track import ideal_straight_track

    link = {"type": "uic_link", "bodies": ["car_body", "bogie_1"], "position": [3.0, 0.5, 1.0],
            "pendulum_length": [0.16, 0.2], "friction_coefficient": [0.2, 0.1],
            "stick_stiffness": [1e6, 1e6]}  # fmt: skip
    with pytest.raises(ModelError, match="give vertical_load"):
        VehicleModel(_eu07_with({"link": link}), ideal_straight_track(), 10.0)
