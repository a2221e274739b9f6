"""Compiled generalized forces of the wheel-rail contacts and the nonlinear suspension elements.

One Exudyn ``ObjectGenericODE2`` spans the nodes of all wheelsets (and of the bodies joined by
bump stops); its force user function calls :func:`generalized_forces` once per residual
evaluation. Every node is an Exudyn ``NodeRigidBodyRxyz`` with total angles
``theta = (theta0, theta1, theta2)`` and rotation ``A = Rx(theta0) Ry(theta1) Rz(theta2)``:

- the global angular velocity is ``omega = G(theta) theta_dot`` with the columns of ``G``
  ``e_x``, ``Rx(theta0) e_y``, ``Rx(theta0) Ry(theta1) e_z``;
- a global torque ``M`` acts on the angle coordinates as ``G(theta)^T M``;
- a wheelset's reference rotation puts its axle on the body's third axis, so roll is
  ``phi = theta0 + pi/2``, yaw ``psi = -theta1`` and ``theta2`` is the spin
  (``docs/conventions.md``, verified in ``docs/dev/exudyn-api.md``).

Track irregularities enter as offsets of each rail from its nominal place, interpolated at the
wheelset's position along the track; the rail "velocity" passed to the contact is the forward
speed times their slope, which turns the rail's direction and the penetration rate correctly for
a rolling contact (to first order in the slope).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .contact import kernel as K

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}

#: Columns of the per-wheelset integer layout.
WS_SLOT = 0  # node slot of the wheelset in the object's node list
#: Columns of a bump stop's real data row.
BS_P0 = 0  # local attachment point on body 0 (3)
BS_P1 = 3  # local attachment point on body 1 (3)
BS_DIR = 6  # direction index 0/1/2 (x/y/z of the track)
BS_CLEAR = 7  # clearance [m]
BS_K = 8  # stiffness [N/m]
BS_C = 9  # damping [N s/m]
BS_D0 = 10  # relative displacement along the direction in the initial state [m]
BS_NREAL = 11
# integer row: slot0, slot1, wheelset0 (1 if body 0 is a wheelset), wheelset1


@numba.njit(inline="always", **_JIT)
def _rot(t0, t1, t2):
    """Rotation matrix entries of Rx(t0) Ry(t1) Rz(t2), row-major."""
    c0, s0 = math.cos(t0), math.sin(t0)
    c1, s1 = math.cos(t1), math.sin(t1)
    c2, s2 = math.cos(t2), math.sin(t2)
    return (
        c1 * c2, -c1 * s2, s1,
        c0 * s2 + s0 * s1 * c2, c0 * c2 - s0 * s1 * s2, -s0 * c1,
        s0 * s2 - c0 * s1 * c2, s0 * c2 + c0 * s1 * s2, c0 * c1,
    )  # fmt: skip


@numba.njit(**_JIT)
def _irregularity(x, start, step, values, slopes, out, speed):
    """Rail offsets at ``x`` (cubic Hermite) into ``out``: (dy_l, dz_l, vy_l, vz_l, dy_r, ...)."""
    n = values.shape[0]
    for k in range(8):
        out[k] = 0.0
    u = (x - start) / step
    if n < 2 or u < 0.0 or u > n - 1.0:
        return
    i = int(u)
    if i >= n - 1:
        i = n - 2
    t = u - i
    t2 = t * t
    t3 = t2 * t
    h00 = 2.0 * t3 - 3.0 * t2 + 1.0
    h10 = t3 - 2.0 * t2 + t
    h01 = -2.0 * t3 + 3.0 * t2
    h11 = t3 - t2
    for c in range(4):
        p0 = values[i, c]
        p1 = values[i + 1, c]
        m0 = slopes[i, c]
        m1 = slopes[i + 1, c]
        val = h00 * p0 + h10 * step * m0 + h01 * p1 + h11 * step * m1
        der = (6.0 * t2 - 6.0 * t) * (p0 - p1) / step + (3.0 * t2 - 4.0 * t + 1.0) * m0
        der += (3.0 * t2 - 2.0 * t) * m1
        # column c: 0 left dy, 1 left dz, 2 right dy, 3 right dz -> out layout
        side = c // 2
        comp = c % 2
        out[4 * side + comp] = val
        out[4 * side + 2 + comp] = der * speed


@numba.njit(**_JIT)
def _wheelset(w, q, qt, qref, ws_slots, wtab, winfo, rtab, rinfo, htab, ktab, params, irr_start,
              irr_step, irr_values, irr_slopes, gen, points, ws_force, work):  # fmt: skip
    """Generalized contact forces of wheelset ``w`` on its 6 node coordinates into ``gen``
    (``work``: scratch of 25 entries)."""
    o = 6 * ws_slots[w]
    t0 = qref[o + 3] + q[o + 3]
    t1 = qref[o + 4] + q[o + 4]
    c0, s0 = math.cos(t0), math.sin(t0)
    c1, s1 = math.cos(t1), math.sin(t1)
    d0 = qt[o + 3]
    d1 = qt[o + 4]
    d2 = qt[o + 5]
    x = qref[o] + q[o]
    state = work[0:11]
    rails = work[11:19]
    force = work[19:25]
    state[0] = x
    state[1] = qref[o + 1] + q[o + 1]
    state[2] = qref[o + 2] + q[o + 2]
    state[3] = t0 + 0.5 * math.pi
    state[4] = -t1
    state[5] = qt[o]
    state[6] = qt[o + 1]
    state[7] = qt[o + 2]
    state[8] = d0 + s1 * d2
    state[9] = c0 * d1 - s0 * c1 * d2
    state[10] = s0 * d1 + c0 * c1 * d2
    _irregularity(x, irr_start, irr_step, irr_values, irr_slopes, rails, qt[o])
    K.wheelset_contact(
        wtab[w, 0], winfo[w, 0], rtab[0], rinfo[0], wtab[w, 1], winfo[w, 1], rtab[1],
        rinfo[1], htab, ktab, params, state, rails, points[w], force,
    )  # fmt: skip
    for k in range(6):
        ws_force[w, k] = force[k]
    tx, ty, tz = force[3], force[4], force[5]
    gen[0] = force[0]
    gen[1] = force[1]
    gen[2] = force[2]
    gen[3] = tx
    gen[4] = c0 * ty + s0 * tz
    gen[5] = s1 * tx - s0 * c1 * ty + c0 * c1 * tz


@numba.njit(**_JIT)
def _bump_stop(b, q, qt, qref, bs_int, bs_real, out):
    """Add the generalized forces of bump stop ``b`` (piecewise-linear spring with clearance
    between two bodies, along one track axis) to ``out``."""
    oa = 6 * bs_int[b, 0]
    ob = 6 * bs_int[b, 1]
    dr = int(bs_real[b, BS_DIR])
    pa = np.empty(3)
    pb = np.empty(3)
    va = np.empty(3)
    vb = np.empty(3)
    ra = np.empty(3)
    rb = np.empty(3)
    for side in range(2):
        o = oa if side == 0 else ob
        lp = BS_P0 if side == 0 else BS_P1
        a = _rot(qref[o + 3] + q[o + 3], qref[o + 4] + q[o + 4], qref[o + 5] + q[o + 5])
        lx, ly, lz = bs_real[b, lp], bs_real[b, lp + 1], bs_real[b, lp + 2]
        rx = a[0] * lx + a[1] * ly + a[2] * lz
        ry = a[3] * lx + a[4] * ly + a[5] * lz
        rz = a[6] * lx + a[7] * ly + a[8] * lz
        t0 = qref[o + 3] + q[o + 3]
        t1 = qref[o + 4] + q[o + 4]
        c0, s0 = math.cos(t0), math.sin(t0)
        c1, s1 = math.cos(t1), math.sin(t1)
        wx = qt[o + 3] + s1 * qt[o + 5]
        wy = c0 * qt[o + 4] - s0 * c1 * qt[o + 5]
        wz = s0 * qt[o + 4] + c0 * c1 * qt[o + 5]
        p = pa if side == 0 else pb
        v = va if side == 0 else vb
        r = ra if side == 0 else rb
        p[0] = qref[o] + q[o] + rx
        p[1] = qref[o + 1] + q[o + 1] + ry
        p[2] = qref[o + 2] + q[o + 2] + rz
        v[0] = qt[o] + wy * rz - wz * ry
        v[1] = qt[o + 1] + wz * rx - wx * rz
        v[2] = qt[o + 2] + wx * ry - wy * rx
        r[0] = rx
        r[1] = ry
        r[2] = rz
    d = pb[dr] - pa[dr] - bs_real[b, BS_D0]
    clear = bs_real[b, BS_CLEAR]
    f = 0.0
    if d > clear:
        f = -bs_real[b, BS_K] * (d - clear) - bs_real[b, BS_C] * (vb[dr] - va[dr])
        if f > 0.0:
            f = 0.0
    elif d < -clear:
        f = -bs_real[b, BS_K] * (d + clear) - bs_real[b, BS_C] * (vb[dr] - va[dr])
        if f < 0.0:
            f = 0.0
    if f == 0.0:
        return
    for side in range(2):
        o = oa if side == 0 else ob
        sgn = -1.0 if side == 0 else 1.0
        r = ra if side == 0 else rb
        fv0 = sgn * f if dr == 0 else 0.0
        fv1 = sgn * f if dr == 1 else 0.0
        fv2 = sgn * f if dr == 2 else 0.0
        out[o] += fv0
        out[o + 1] += fv1
        out[o + 2] += fv2
        tx = r[1] * fv2 - r[2] * fv1
        ty = r[2] * fv0 - r[0] * fv2
        tz = r[0] * fv1 - r[1] * fv0
        t0 = qref[o + 3] + q[o + 3]
        t1 = qref[o + 4] + q[o + 4]
        c0, s0 = math.cos(t0), math.sin(t0)
        c1, s1 = math.cos(t1), math.sin(t1)
        out[o + 3] += tx
        out[o + 4] += c0 * ty + s0 * tz
        out[o + 5] += s1 * tx - s0 * c1 * ty + c0 * c1 * tz


@numba.njit(**_JIT)
def generalized_forces(q, qt, qref, ws_slots, wtab, winfo, rtab, rinfo, htab, ktab, params,
                       irr_start, irr_step, irr_values, irr_slopes, bs_int, bs_real, out,
                       points, ws_force):  # fmt: skip
    """Generalized forces of all contacts and bump stops on the object's coordinates.

    Args:
        q, qt: the object's coordinates and velocities (6 per node, without reference values).
        qref: reference coordinates of the same nodes.
        ws_slots: node slot of each wheelset.
        wtab, winfo: wheel tables ``(n_ws, 2, N, 4)`` and info ``(n_ws, 2, 5)`` (left, right).
        rtab, rinfo: rail tables ``(2, M, 4)`` and info ``(2, 3)`` (left, right rail).
        htab, ktab, params: Hertz table, Kalker table, contact parameters (kernel layout).
        irr_*: sampled irregularities (rail offsets and their slopes along the track).
        bs_int, bs_real: bump stops (see ``BS_*``).
        out: generalized forces, same length as ``q`` (overwritten).
        points: contact points ``(n_ws, 2, MAX_POINTS, N_POINT_FIELDS)`` (overwritten).
        ws_force: contact force and torque on each wheelset, track frame ``(n_ws, 6)``.
    """
    for i in range(out.shape[0]):
        out[i] = 0.0
    gen = np.empty(6)
    work = np.empty(25)
    for w in range(ws_slots.shape[0]):
        _wheelset(w, q, qt, qref, ws_slots, wtab, winfo, rtab, rinfo, htab, ktab, params,
                  irr_start, irr_step, irr_values, irr_slopes, gen, points, ws_force,
                  work)  # fmt: skip
        o = 6 * ws_slots[w]
        for k in range(6):
            out[o + k] += gen[k]
    for b in range(bs_int.shape[0]):
        _bump_stop(b, q, qt, qref, bs_int, bs_real, out)


#: Finite-difference steps of :func:`jacobian`: coordinates [m, rad] and velocities [m/s, rad/s].
EPS_Q = 1.0e-8
EPS_V = 1.0e-6


@numba.njit(**_JIT)
def jacobian(q, qt, qref, ws_slots, wtab, winfo, rtab, rinfo, htab, ktab, params, irr_start,
             irr_step, irr_values, irr_slopes, bs_int, bs_real, f_q, f_v, jac, points,
             ws_force):  # fmt: skip
    """Exudyn's Jacobian of the forces, ``-f_q df/dq - f_v df/dq_t``, by finite differences that
    use the structure: a wheelset's contact forces depend only on its own 12 coordinates and
    velocities, a bump stop's only on those of its two bodies. 13 wheelset evaluations per
    wheelset instead of ``2 n + 1`` evaluations of everything (``n`` = 6 per node), and no
    dependence on the spin angle (a body of revolution)."""
    n = q.shape[0]
    for i in range(n):
        for j in range(n):
            jac[i, j] = 0.0
    gen0 = np.empty(6)
    gen1 = np.empty(6)
    work = np.empty(25)
    qp = q.copy()
    qtp = qt.copy()
    for w in range(ws_slots.shape[0]):
        o = 6 * ws_slots[w]
        _wheelset(w, q, qt, qref, ws_slots, wtab, winfo, rtab, rinfo, htab, ktab, params,
                  irr_start, irr_step, irr_values, irr_slopes, gen0, points, ws_force,
                  work)  # fmt: skip
        for j in range(12):
            col = o + (j % 6)
            if j == 5:
                continue  # the spin angle does not change the contact
            if j < 6:
                h = EPS_Q
                qp[col] = q[col] + h
            else:
                h = EPS_V
                qtp[col] = qt[col] + h
            _wheelset(w, qp, qtp, qref, ws_slots, wtab, winfo, rtab, rinfo, htab, ktab, params,
                      irr_start, irr_step, irr_values, irr_slopes, gen1, points,
                      ws_force, work)  # fmt: skip
            factor = f_q if j < 6 else f_v
            for k in range(6):
                jac[o + k, col] -= factor * (gen1[k] - gen0[k]) / h
            qp[col] = q[col]
            qtp[col] = qt[col]
    # bump stops
    base = np.zeros(n)
    pert = np.zeros(n)
    for b in range(bs_int.shape[0]):
        for i in range(n):
            base[i] = 0.0
        _bump_stop(b, q, qt, qref, bs_int, bs_real, base)
        for side in range(2):
            o = 6 * bs_int[b, side]
            for j in range(12):
                col = o + (j % 6)
                if j < 6:
                    h = EPS_Q
                    qp[col] = q[col] + h
                else:
                    h = EPS_V
                    qtp[col] = qt[col] + h
                for i in range(n):
                    pert[i] = 0.0
                _bump_stop(b, qp, qtp, qref, bs_int, bs_real, pert)
                factor = f_q if j < 6 else f_v
                for side2 in range(2):
                    r = 6 * bs_int[b, side2]
                    for k in range(6):
                        jac[r + k, col] -= factor * (pert[r + k] - base[r + k]) / h
                qp[col] = q[col]
                qtp[col] = qt[col]
