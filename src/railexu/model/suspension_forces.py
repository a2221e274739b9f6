"""Compiled forces of the suspension elements other than torsion springs: the linear
spring-dampers and the nonlinear elements (``docs/suspension.md``).

Every such element is reduced to one or more *kernel elements* acting between two body
points along one track axis (x, y or z); the forces on the two bodies act at the midpoint of
the two points (no couple when they separate), on a wheelset through its axlebox. With the
relative displacement ``d`` of the second point from the first along the axis, measured from
the nominal (static) geometry, and its rate ``v = d'``, a kernel element exerts ``-F`` on the
second body and ``+F`` on the first, with

    F = P(d + d_s) + c_p v + S

- ``P``: the parallel spring, from a table (piecewise linear, continued with the end slopes)
  or linear ``k_p (d + d_s)``; ``d_s`` is its static deflection (``P(d_s)`` = the static force
  of :mod:`railexu.model.statics`), so the vehicle starts in equilibrium;
- ``c_p``: parallel viscous damping;
- ``S``: the series branch, a force law ``g`` of a velocity, either directly ``S = g(v)``
  (a damper from its force-velocity table; regularised Coulomb friction
  ``g(v) = F_c tanh(v / v_s)``) or through a series spring ``k_s`` with one internal coordinate
  ``u`` (the displacement of the damper or slider): ``S = k_s (d - u)`` and

      m_i u'' = k_s (d - u) - g(u') - c_v u'.

  This is a Maxwell element (damper with its bush stiffness; air-spring reservoir). A slider
  behind a stick stiffness (stick-slip friction, the UIC link's friction) is elastic-perfectly-
  plastic instead: the internal coordinate is the slider's position and it flows only when the
  spring's force exceeds the friction force, at the rate of the overstress (viscoplastic,
  Perzyna's regularisation),

      m_i u'' = sign(f_s) max(0, |f_s| - F_c) - eta u',   f_s = k_s (d - u),

  with ``eta = F_c / (10^4 v_s)``: it sticks exactly (no creep) and slides at a force 1 % above
  ``F_c`` at 0.1 m/s for the default ``v_s`` = 1 mm/s. (A tanh law behind a spring saturates and
  stalls Newton's method; the overstress flow is piecewise linear and does not.) The
  small mass ``m_i = k_s / omega_i^2`` keeps the coordinate an Exudyn ODE2 coordinate (the
  linearised system of :mod:`railexu.stability.linear` needs a regular mass matrix), with
  ``omega_i = max(2 pi 1 kHz, 20 k_s / c_ref)`` far above the vehicle's frequencies; ``c_ref`` is
  the law's least slope (a damper's coefficient), ``eta`` for a slider, or for flat tables a
  tenth of the largest force per m/s. ``c_v = max(0, 2 k_s / omega_i - min g')`` makes the
  internal mode at least critically damped: nothing for a damper (its slope exceeds
  ``2 k_s / omega_i`` tenfold); for a slider ``c_v = eta``.

The kernel rows are built by :func:`kernel_arrays`; :func:`suspension_forces` adds all
elements' generalized forces and :func:`suspension_jacobian` their finite-difference Jacobian;
both are called by :func:`railexu.model.forces.generalized_forces` and
:func:`railexu.model.forces.jacobian`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from railexu.model.body_points import (
    apply_force,
    axlebox_point_state,
    midpoint_levers,
    point_state,
)
from railexu.model.characteristics import characteristic_table
from railexu.vehicle.vehicle import (
    AirSpring,
    Damper,
    Friction,
    NonlinearSpring,
    UICLink,
    linear_part,
)

if TYPE_CHECKING:  # pragma: no cover
    from railexu.model.statics import StaticSolution
    from railexu.vehicle.vehicle import Vehicle

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}

#: Frequency of an internal coordinate's mass on its series spring [Hz]: far above the
#: vehicle's (< 30 Hz) and contact-relevant suspension frequencies; the mode is overdamped.
INTERNAL_FREQUENCY_HZ = 1000.0
#: ``omega_i >= 20 k_s / c_ref``: the internal mass shifts the Maxwell pole ``k_s / c`` by less
#: than ``(k_s / (omega_i c))^2 = 0.25 %``.
INTERNAL_STIFFNESS_RATIO = 20.0

#: Columns of a kernel element's integer row.
SI_SLOT0 = 0  # node slot of the first body
SI_SLOT1 = 1  # node slot of the second body
SI_DIR = 2  # axis 0/1/2 (x/y/z)
SI_INTERNAL = 3  # index of the internal coordinate in the object's coordinates, -1: none
SI_SPRING_START = 4  # first row of the spring table in the table array, -1: linear k_p
SI_SPRING_N = 5  # its number of points
SI_LAW = 6  # series law: 0 none, 1 table, 2 tanh friction
SI_LAW_START = 7  # first row of the law's table
SI_LAW_N = 8  # its number of points
SI_BOX0 = 9  # 1: the first body is a wheelset and the point is on its axlebox (off the axle)
SI_BOX1 = 10  # 1: the same for the second body
SI_GROUP = 11  # elements in the group that starts here (same bodies and ends), 0: in a group
SI_NINT = 12

LAW_NONE = 0
LAW_TABLE = 1
LAW_FRICTION = 2
LAW_PLASTIC = 3  # a slider behind a series spring: elastic-perfectly-plastic (viscoplastic flow)

#: Viscoplastic regularisation of a slider behind a stick stiffness: it flows at
#: ``(|f| - F_c) / eta`` with ``eta = F_c / (PLASTIC_FLOW_FACTOR v_s)``; with the default slip
#: velocity ``v_s`` = 1 mm/s the force is 1 % above ``F_c`` at 0.1 m/s of sliding.
PLASTIC_FLOW_FACTOR = 1.0e4

#: Columns of a kernel element's real row.
SR_P0 = 0  # local attachment point on body 0 (3)
SR_P1 = 3  # local attachment point on body 1 (3)
SR_D0 = 6  # relative displacement along the axis in the nominal geometry [m]
SR_DS = 7  # static deflection of the parallel spring [m]
SR_KP = 8  # linear parallel stiffness [N/m] (no spring table)
SR_CP = 9  # parallel damping [N s/m]
SR_KS = 10  # series stiffness [N/m] (with an internal coordinate)
SR_CV = 11  # internal damping c_v [N s/m]
SR_FC = 12  # friction force F_c [N]
SR_VS = 13  # slip velocity v_s [m/s]
SR_NREAL = 14


# -- compiled -------------------------------------------------------------------------------------
@numba.njit(**_JIT)
def table_value(tab, start, n, x):
    """Piecewise-linear value of the table rows ``start .. start + n - 1`` (columns x, f) at
    ``x``, continued beyond its ends with the end segments' slopes."""
    if x <= tab[start, 0]:
        i = start
    elif x >= tab[start + n - 1, 0]:
        i = start + n - 2
    else:
        lo = start
        hi = start + n - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if tab[mid, 0] <= x:
                lo = mid
            else:
                hi = mid
        i = lo
    x0 = tab[i, 0]
    x1 = tab[i + 1, 0]
    f0 = tab[i, 1]
    return f0 + (tab[i + 1, 1] - f0) * (x - x0) / (x1 - x0)


@numba.njit(**_JIT)
def _law(e, si, sr, tab, v):
    law = si[e, SI_LAW]
    if law == LAW_TABLE:
        return table_value(tab, si[e, SI_LAW_START], si[e, SI_LAW_N], v)
    if law == LAW_FRICTION:
        return sr[e, SR_FC] * math.tanh(v / sr[e, SR_VS])
    return 0.0


@numba.njit(**_JIT)
def _points(e, q, qt, qref, si, sr, pa, pb, va, vb, ra, rb):
    """Positions, velocities and levers of kernel element ``e``'s two ends (on a wheelset:
    its axlebox)."""
    oa = 6 * si[e, SI_SLOT0]
    ob = 6 * si[e, SI_SLOT1]
    if si[e, SI_BOX0] == 1:
        axlebox_point_state(oa, sr[e, SR_P0], sr[e, SR_P0 + 1], sr[e, SR_P0 + 2], q, qt, qref,
                            pa, va, ra)  # fmt: skip
    else:
        point_state(oa, sr[e, SR_P0], sr[e, SR_P0 + 1], sr[e, SR_P0 + 2], q, qt, qref, pa, va, ra)
    if si[e, SI_BOX1] == 1:
        axlebox_point_state(ob, sr[e, SR_P1], sr[e, SR_P1 + 1], sr[e, SR_P1 + 2], q, qt, qref,
                            pb, vb, rb)  # fmt: skip
    else:
        point_state(ob, sr[e, SR_P1], sr[e, SR_P1 + 1], sr[e, SR_P1 + 2], q, qt, qref, pb, vb, rb)


@numba.njit(**_JIT)
def _axis_force(e, pa, pb, va, vb, q, qt, si, sr, tab, out):
    """Force ``F`` [N] of kernel element ``e`` from its ends' states (module doc); adds its
    internal coordinate's generalized force to ``out``."""
    dr = si[e, SI_DIR]
    d = pb[dr] - pa[dr] - sr[e, SR_D0]
    v = vb[dr] - va[dr]
    start = si[e, SI_SPRING_START]
    if start >= 0:
        f = table_value(tab, start, si[e, SI_SPRING_N], d + sr[e, SR_DS])
    else:
        f = sr[e, SR_KP] * (d + sr[e, SR_DS])
    f += sr[e, SR_CP] * v
    iu = si[e, SI_INTERNAL]
    if iu >= 0:
        fs = sr[e, SR_KS] * (d - q[iu])
        ut = qt[iu]
        if si[e, SI_LAW] == LAW_PLASTIC:
            over = abs(fs) - sr[e, SR_FC]
            flow = math.copysign(over, fs) if over > 0.0 else 0.0
            out[iu] += flow - sr[e, SR_CV] * ut
        else:
            out[iu] += fs - _law(e, si, sr, tab, ut) - sr[e, SR_CV] * ut
        f += fs
    else:
        f += _law(e, si, sr, tab, v)
    return f


@numba.njit(**_JIT)
def _apply_pair(e, f0, f1, f2, pa, pb, ra, rb, q, qref, si, out):
    """Add the force ``(f0, f1, f2)`` on the first body of element ``e`` and its opposite on
    the second, both at the midpoint of the element's ends (``docs/suspension.md``, "The
    couple of an element whose ends separate"); on a wheelset through its axlebox."""
    oa = 6 * si[e, SI_SLOT0]
    ob = 6 * si[e, SI_SLOT1]
    midpoint_levers(pa, pb, ra, rb)
    apply_force(oa, ob if si[e, SI_BOX0] == 1 else -1, f0, f1, f2, ra, q, qref, out)
    apply_force(ob, oa if si[e, SI_BOX1] == 1 else -1, -f0, -f1, -f2, rb, q, qref, out)


def element_deflection(e: int, q: np.ndarray, qref: np.ndarray, si: np.ndarray,
                       sr: np.ndarray) -> float:  # fmt: skip
    """The deflection ``d`` [m] of kernel element ``e`` along its axis from the nominal
    geometry at the coordinates ``q`` (the ``d`` of the module doc)."""
    p = [np.empty(3) for _ in range(6)]
    _points(e, q, np.zeros_like(q), qref, si, sr, *p)
    dr = si[e, SI_DIR]
    return float(p[1][dr] - p[0][dr] - sr[e, SR_D0])


@numba.njit(**_JIT)
def element_force(e, q, qt, qref, si, sr, tab, out):
    """Add the generalized forces of kernel element ``e`` to ``out`` and return its force
    ``F`` [N] (``-F`` acts on the second body along the element's axis). Both forces act at
    the midpoint of the element's two ends, so that the pair carries no couple whatever the
    separation of its ends (``docs/suspension.md``, "The couple of an element whose ends
    separate")."""
    pa = np.empty(3)
    pb = np.empty(3)
    va = np.empty(3)
    vb = np.empty(3)
    ra = np.empty(3)
    rb = np.empty(3)
    _points(e, q, qt, qref, si, sr, pa, pb, va, vb, ra, rb)
    f = _axis_force(e, pa, pb, va, vb, q, qt, si, sr, tab, out)
    if f != 0.0:
        dr = si[e, SI_DIR]
        _apply_pair(e, f if dr == 0 else 0.0, f if dr == 1 else 0.0, f if dr == 2 else 0.0,
                    pa, pb, ra, rb, q, qref, si, out)  # fmt: skip
    return f


@numba.njit(**_JIT)
def group_force(g, q, qt, qref, si, sr, tab, out):
    """Add the generalized forces of the group of kernel elements that starts at ``g`` (the
    ``si[g, SI_GROUP]`` elements from ``g`` on share their bodies and ends: a spring-damper's
    axes) to ``out``: the ends' states once, the axes' forces summed into one force at the
    midpoint. The same forces as :func:`element_force` of each element, in a third of the
    time for a three-axis spring-damper."""
    _group_force(g, q, qt, qref, si, sr, tab, out, np.empty((6, 3)))


@numba.njit(**_JIT)
def _group_force(g, q, qt, qref, si, sr, tab, out, work):
    """:func:`group_force` with the ends' states in ``work`` (6 x 3, overwritten): one work
    array for all groups of a call instead of six small arrays per group."""
    pa, pb, va, vb, ra, rb = work[0], work[1], work[2], work[3], work[4], work[5]
    _points(g, q, qt, qref, si, sr, pa, pb, va, vb, ra, rb)
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    for e in range(g, g + si[g, SI_GROUP]):
        f = _axis_force(e, pa, pb, va, vb, q, qt, si, sr, tab, out)
        dr = si[e, SI_DIR]
        if dr == 0:
            f0 += f
        elif dr == 1:
            f1 += f
        else:
            f2 += f
    if f0 != 0.0 or f1 != 0.0 or f2 != 0.0:
        _apply_pair(g, f0, f1, f2, pa, pb, ra, rb, q, qref, si, out)


@numba.njit(**_JIT)
def suspension_forces(q, qt, qref, si, sr, tab, out):
    """Add the generalized forces of all kernel elements to ``out`` (see the module doc)."""
    work = np.empty((6, 3))
    for g in range(si.shape[0]):
        if si[g, SI_GROUP] > 0:
            _group_force(g, q, qt, qref, si, sr, tab, out, work)


#: Finite-difference steps of :func:`suspension_jacobian` [m, rad; m/s, rad/s].
EPS_Q = 1.0e-8
EPS_V = 1.0e-6


@numba.njit(**_JIT)
def _group_columns(g, si, sr, cols):
    """The coordinates a group's forces depend on, into ``cols``: ``(n_q, n_v)``, the first
    ``n_q`` entries by position, the next ``n_v`` by velocity. Not a wheelset's spin (an
    axlebox does not turn with it), not the bodies' velocities when no element of the group
    has damping, a velocity law or an internal coordinate."""
    n = 0
    for side in range(2):
        o = 6 * si[g, SI_SLOT0 + side]
        for k in range(6):
            if k == 5 and si[g, SI_BOX0 + side] == 1:
                continue
            cols[n] = o + k
            n += 1
    rate = False
    for e in range(g, g + si[g, SI_GROUP]):
        if si[e, SI_INTERNAL] >= 0:
            cols[n] = si[e, SI_INTERNAL]
            n += 1
            rate = True
        if sr[e, SR_CP] != 0.0 or si[e, SI_LAW] != LAW_NONE:
            rate = True
    if not rate:
        return n, 0
    for k in range(n):
        cols[n + k] = cols[k]
    return n, n


@numba.njit(**_JIT)
def suspension_jacobian(q, qt, qref, si, sr, tab, f_q, f_v, jac, qp, qtp, base, pert):
    """Add ``-f_q dF/dq - f_v dF/dq_t`` of every kernel element to ``jac`` by finite
    differences over the coordinates of each group of elements (:func:`group_force`: its two
    bodies' and its internal ones, :func:`_group_columns`). ``qp``, ``qtp`` are copies of
    ``q``, ``qt`` (restored on return); ``base``, ``pert`` work arrays of the coordinates'
    length."""
    cols = np.empty(2 * (12 + si.shape[0]), dtype=np.int64)
    rows = np.empty(12 + si.shape[0], dtype=np.int64)
    work = np.empty((6, 3))
    for g in range(si.shape[0]):
        if si[g, SI_GROUP] <= 0:
            continue
        n_q, n_v = _group_columns(g, si, sr, cols)
        # rows: the two bodies' 12 coordinates and the internal ones
        nr = 0
        for side in range(2):
            o = 6 * si[g, SI_SLOT0 + side]
            for k in range(6):
                rows[nr] = o + k
                nr += 1
        for e in range(g, g + si[g, SI_GROUP]):
            if si[e, SI_INTERNAL] >= 0:
                rows[nr] = si[e, SI_INTERNAL]
                nr += 1
        for k in range(nr):
            base[rows[k]] = 0.0
        _group_force(g, q, qt, qref, si, sr, tab, base, work)
        for j in range(n_q + n_v):
            col = cols[j]
            if j < n_q:
                h = EPS_Q
                qp[col] = q[col] + h
            else:
                h = EPS_V
                qtp[col] = qt[col] + h
            for k in range(nr):
                pert[rows[k]] = 0.0
            _group_force(g, qp, qtp, qref, si, sr, tab, pert, work)
            factor = f_q if j < n_q else f_v
            for k in range(nr):
                row = rows[k]
                jac[row, col] -= factor * (pert[row] - base[row]) / h
            qp[col] = q[col]
            qtp[col] = qt[col]


# -- Python side: the kernel rows of a vehicle's elements ----------------------------------------
@dataclass
class KernelElement:
    """One kernel element before packing (see the module doc for the symbols)."""

    name: str  # the vehicle element's name (with _x, _y for the two axes of a UIC link)
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    axis: int
    spring_table: np.ndarray | None = None  # (n, 2): deflection [m], force [N]
    static_deflection_m: float = 0.0
    parallel_stiffness_N_per_m: float = 0.0
    parallel_damping_N_s_per_m: float = 0.0
    law: int = LAW_NONE
    law_table: np.ndarray | None = None  # (n, 2): velocity [m/s], force [N]
    series_stiffness_N_per_m: float = 0.0  # > 0: an internal coordinate
    friction_force_N: float = 0.0
    slip_velocity_m_per_s: float = 1.0e-3

    @property
    def internal(self) -> bool:
        return self.series_stiffness_N_per_m > 0.0 and self.law != LAW_NONE

    def minimum_law_slope(self) -> float:
        """Least slope of the series law [N s/m] (0 for friction: it saturates)."""
        if self.law == LAW_TABLE and self.law_table is not None:
            t = self.law_table
            return max(float(np.min(np.diff(t[:, 1]) / np.diff(t[:, 0]))), 0.0)
        return 0.0

    def reference_damping_N_s_per_m(self) -> float:
        """``c_ref`` of the internal coordinate: the law's least slope; for a slider behind a
        spring its flow viscosity ``eta``; for flat tables a tenth of the largest force per
        m/s."""
        c_min = self.minimum_law_slope()
        if c_min > 0.0:
            return c_min
        if self.law == LAW_PLASTIC:
            return self.friction_force_N / (PLASTIC_FLOW_FACTOR * self.slip_velocity_m_per_s)
        if self.law == LAW_TABLE and self.law_table is not None:
            return 0.1 * float(np.max(np.abs(self.law_table[:, 1])))
        return 0.1 * self.friction_force_N

    def internal_omega_rad_per_s(self) -> float:
        """``omega_i = max(2 pi f_i, 20 k_s / c_ref)``."""
        return max(
            2.0 * math.pi * INTERNAL_FREQUENCY_HZ,
            INTERNAL_STIFFNESS_RATIO * self.series_stiffness_N_per_m
            / self.reference_damping_N_s_per_m(),
        )  # fmt: skip

    def internal_mass_kg(self) -> float:
        """``m_i = k_s / omega_i^2`` of its internal coordinate."""
        return self.series_stiffness_N_per_m / self.internal_omega_rad_per_s() ** 2

    def internal_damping_N_s_per_m(self) -> float:
        """``c_v = max(0, 2 k_s / omega_i - min g')``: the internal mode at least critically
        damped; for a slider behind a spring its flow viscosity ``eta``."""
        if self.law == LAW_PLASTIC:
            return self.reference_damping_N_s_per_m()
        critical = 2.0 * self.series_stiffness_N_per_m / self.internal_omega_rad_per_s()
        return max(0.0, critical - self.minimum_law_slope())


def kernel_arrays(
    elements: list[KernelElement],
    slot: dict[str, int],
    local: dict[str, tuple[np.ndarray, np.ndarray]],
    internal_start: int,
    axlebox: dict[str, tuple[bool, bool]] | None = None,
):
    """Pack kernel elements into ``(si, sr, tab)``.

    Args:
        elements: the kernel elements.
        slot: node slot of each body name in the force object.
        local: per element name, ``(local point on body 0, on body 1, nominal separation)`` as
            ``((la, lb), d0)``.
        internal_start: index of the first internal coordinate in the object's coordinates.
        axlebox: per element name, whether its point on body 0 and on body 1 is on a
            wheelset's axlebox away from the axle (its local point then in the wheelset's axes
            without spin); none by default.
    """
    n = len(elements)
    si = np.full((n, SI_NINT), -1, dtype=np.int64)
    sr = np.zeros((n, SR_NREAL))
    rows: list[np.ndarray] = []
    n_rows = 0
    i_int = internal_start
    for e, el in enumerate(elements):
        (la, lb), d0 = local[el.name]
        si[e, SI_SLOT0] = slot[el.bodies[0]]
        si[e, SI_SLOT1] = slot[el.bodies[1]]
        si[e, SI_DIR] = el.axis
        box = (axlebox or {}).get(el.name, (False, False))
        si[e, SI_BOX0] = int(box[0])
        si[e, SI_BOX1] = int(box[1])
        sr[e, SR_P0 : SR_P0 + 3] = la
        sr[e, SR_P1 : SR_P1 + 3] = lb
        sr[e, SR_D0] = d0
        sr[e, SR_DS] = el.static_deflection_m
        sr[e, SR_KP] = el.parallel_stiffness_N_per_m
        sr[e, SR_CP] = el.parallel_damping_N_s_per_m
        if el.spring_table is not None:
            si[e, SI_SPRING_START], si[e, SI_SPRING_N] = n_rows, len(el.spring_table)
            rows.append(el.spring_table)
            n_rows += len(el.spring_table)
        si[e, SI_LAW] = el.law
        if el.law == LAW_TABLE:
            si[e, SI_LAW_START], si[e, SI_LAW_N] = n_rows, len(el.law_table)
            rows.append(el.law_table)
            n_rows += len(el.law_table)
        sr[e, SR_FC] = el.friction_force_N
        sr[e, SR_VS] = el.slip_velocity_m_per_s
        if el.internal:
            si[e, SI_INTERNAL] = i_int
            i_int += 1
            sr[e, SR_KS] = el.series_stiffness_N_per_m
            sr[e, SR_CV] = el.internal_damping_N_s_per_m()
    _mark_groups(si, sr)
    tab = np.concatenate(rows) if rows else np.zeros((0, 2))
    return si, sr, np.ascontiguousarray(tab)


def _mark_groups(si: np.ndarray, sr: np.ndarray) -> None:
    """``si[:, SI_GROUP]``: consecutive elements with the same bodies, axlebox flags and local
    ends (a spring-damper's axes, a UIC link's two directions) form one group, evaluated
    together (:func:`group_force`); its first element holds the group's size, the others 0."""
    lead = -1
    for e in range(si.shape[0]):
        same = lead >= 0 and (
            np.array_equal(si[e, [SI_SLOT0, SI_SLOT1, SI_BOX0, SI_BOX1]],
                           si[lead, [SI_SLOT0, SI_SLOT1, SI_BOX0, SI_BOX1]])
            and np.array_equal(sr[e, SR_P0 : SR_P1 + 3], sr[lead, SR_P0 : SR_P1 + 3])
        )  # fmt: skip
        if same:
            si[lead, SI_GROUP] += 1
            si[e, SI_GROUP] = 0
        else:
            lead = e
            si[e, SI_GROUP] = 1


#: A UIC link finds its vertical load among the weight-carrying elements between the same
#: bodies within this distance (x and y) of its point [m].
LINK_SPRING_DISTANCE_M = 0.05


def link_vertical_load_N(el: UICLink, vehicle: Vehicle, statics: StaticSolution) -> float:
    """The vertical load ``W`` on a UIC link suspension [N]: its ``vertical_load``, else the
    static vertical force of the weight-carrying elements between the same two bodies at its
    point (its leaf spring).

    Raises:
        InputError: none found and no ``vertical_load`` given.
    """
    from railexu.errors import InputError
    from railexu.vehicle.checks import carries_weight

    if el.vertical_load_N is not None:
        return el.vertical_load_N
    total = 0.0
    found = False
    for other in vehicle.suspension:
        near = all(
            abs(a - b) <= LINK_SPRING_DISTANCE_M
            for a, b in zip(other.position_m[:2], el.position_m[:2], strict=True)
        )
        if near and set(other.bodies) == set(el.bodies) and carries_weight(other):
            found = True
            total += abs(float(np.asarray(statics.element_forces[other.name])[2]))
    if not found or total <= 0.0:
        raise InputError(
            f"suspension element {el.name}: no vertical spring between {el.bodies[0]} and "
            f"{el.bodies[1]} within {LINK_SPRING_DISTANCE_M} m of its point carries a load; "
            "give vertical_load"
        )
    return total


def _friction_law(force_N: float, stick_stiffness: float | None) -> int:
    """Regularised Coulomb friction alone; a slider behind a stick stiffness; none without a
    friction force."""
    if force_N <= 0.0:
        return LAW_NONE
    return LAW_PLASTIC if stick_stiffness else LAW_FRICTION


def kernel_elements(vehicle: Vehicle, statics: StaticSolution) -> list[KernelElement]:
    """The kernel elements of a vehicle's nonlinear suspension (elements whose whole force is
    a linear connector, :func:`railexu.vehicle.vehicle.linear_part`, give none)."""
    out: list[KernelElement] = []
    for el in vehicle.suspension:
        base = dict(bodies=el.bodies, position_m=el.position_m)
        if isinstance(el, NonlinearSpring):
            table = characteristic_table(el.deflection_m, el.force_N, el.interpolation)
            out.append(KernelElement(
                el.name, axis="xyz".index(el.direction), spring_table=table,
                static_deflection_m=statics.static_deflections[el.name],
                parallel_damping_N_s_per_m=el.damping_N_s_per_m, **base,
            ))  # fmt: skip
        elif isinstance(el, Damper) and linear_part(el) is None:
            out.append(KernelElement(
                el.name, axis="xyz".index(el.direction), law=LAW_TABLE,
                law_table=characteristic_table(el.velocity_m_per_s, el.force_N,
                                               el.interpolation),
                series_stiffness_N_per_m=el.series_stiffness_N_per_m or 0.0, **base,
            ))  # fmt: skip
        elif isinstance(el, Friction):
            out.append(KernelElement(
                el.name, axis="xyz".index(el.direction),
                law=_friction_law(el.friction_force_N, el.stick_stiffness_N_per_m),
                friction_force_N=el.friction_force_N,
                slip_velocity_m_per_s=el.slip_velocity_m_per_s,
                series_stiffness_N_per_m=el.stick_stiffness_N_per_m or 0.0, **base,
            ))  # fmt: skip
        elif isinstance(el, UICLink):
            w = link_vertical_load_N(el, vehicle, statics)
            for axis in (0, 1):
                f_c = el.friction_coefficient[axis] * w
                out.append(KernelElement(
                    f"{el.name}_{'xy'[axis]}", axis=axis,
                    parallel_stiffness_N_per_m=w / el.pendulum_length_m[axis],
                    law=_friction_law(f_c, el.stick_stiffness_N_per_m[axis]),
                    friction_force_N=f_c,
                    slip_velocity_m_per_s=el.slip_velocity_m_per_s,
                    series_stiffness_N_per_m=el.stick_stiffness_N_per_m[axis], **base,
                ))  # fmt: skip
        elif isinstance(el, AirSpring) and el.reservoir_stiffness_N_per_m > 0.0:
            c = el.orifice_damping_N_s_per_m
            out.append(KernelElement(
                f"{el.name}_reservoir", axis=2, law=LAW_TABLE,
                law_table=np.array([[-1.0, -c], [1.0, c]]),
                series_stiffness_N_per_m=el.reservoir_stiffness_N_per_m, **base,
            ))  # fmt: skip
    return out
