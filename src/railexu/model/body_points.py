"""Kinematics of points fixed to Exudyn ``NodeRigidBodyRxyz`` nodes, and forces on them.

Shared by the compiled force functions of the bump stops (:mod:`railexu.model.forces`) and of the
nonlinear suspension elements (:mod:`railexu.model.suspension_forces`). A node at coordinate offset
``o`` has ``(x, y, z, theta0, theta1, theta2)`` with the rotation ``A = Rx(theta0) Ry(theta1)
Rz(theta2)``; the global angular velocity is ``G(theta) theta_dot`` and a global torque ``M``
acts on the angles as ``G(theta)^T M`` (``docs/dev/exudyn-api.md``).
"""

from __future__ import annotations

import math

import numba

from railexu.runtime.compiled_cache import refresh

refresh()  # numba's cache follows the current sources (src/railexu/runtime/compiled_cache.py)

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}


@numba.njit(inline="always", **_JIT)
def rotation(t0, t1, t2):
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
def point_state(o, lx, ly, lz, q, qt, qref, p, v, r):
    """Position ``p``, velocity ``v`` and lever ``r`` (global) of the body point with local
    coordinates ``l`` on the node at coordinate offset ``o`` (Tait-Bryan Rxyz angles)."""
    t0 = qref[o + 3] + q[o + 3]
    t1 = qref[o + 4] + q[o + 4]
    a00, a01, a02, a10, a11, a12, a20, a21, a22 = rotation(t0, t1, qref[o + 5] + q[o + 5])
    c0, s0 = math.cos(t0), math.sin(t0)
    c1, s1 = math.cos(t1), math.sin(t1)
    rx = a00 * lx + a01 * ly + a02 * lz
    ry = a10 * lx + a11 * ly + a12 * lz
    rz = a20 * lx + a21 * ly + a22 * lz
    wx = qt[o + 3] + s1 * qt[o + 5]
    wy = c0 * qt[o + 4] - s0 * c1 * qt[o + 5]
    wz = s0 * qt[o + 4] + c0 * c1 * qt[o + 5]
    p[0] = qref[o] + q[o] + rx
    p[1] = qref[o + 1] + q[o + 1] + ry
    p[2] = qref[o + 2] + q[o + 2] + rz
    v[0] = qt[o] + wy * rz - wz * ry
    v[1] = qt[o + 1] + wz * rx - wx * rz
    v[2] = qt[o + 2] + wx * ry - wy * rx
    r[0] = rx
    r[1] = ry
    r[2] = rz


@numba.njit(**_JIT)
def axlebox_point_state(o, lx, ly, lz, q, qt, qref, p, v, r):
    """Like :func:`point_state` for a point on a wheelset's axlebox: it follows the wheelset's
    translation and its first two angles (roll and yaw of the axle) but not its spin, the last
    angle (``A_box = Rx(theta0) Ry(theta1)``; ``l`` in the wheelset's axes, its third axis the
    axle)."""
    t0 = qref[o + 3] + q[o + 3]
    t1 = qref[o + 4] + q[o + 4]
    a00, a01, a02, a10, a11, a12, a20, a21, a22 = rotation(t0, t1, 0.0)
    c0, s0 = math.cos(t0), math.sin(t0)
    rx = a00 * lx + a01 * ly + a02 * lz
    ry = a10 * lx + a11 * ly + a12 * lz
    rz = a20 * lx + a21 * ly + a22 * lz
    wx = qt[o + 3]
    wy = c0 * qt[o + 4]
    wz = s0 * qt[o + 4]
    p[0] = qref[o] + q[o] + rx
    p[1] = qref[o + 1] + q[o + 1] + ry
    p[2] = qref[o + 2] + q[o + 2] + rz
    v[0] = qt[o] + wy * rz - wz * ry
    v[1] = qt[o + 1] + wz * rx - wx * rz
    v[2] = qt[o + 2] + wx * ry - wy * rx
    r[0] = rx
    r[1] = ry
    r[2] = rz


@numba.njit(**_JIT)
def apply_force(o, o_guide, fv0, fv1, fv2, r, q, qref, out):
    """Add the force ``(fv0, fv1, fv2)`` (global) at lever ``r`` to the node at offset ``o``:
    the force and its moment ``r x F`` (a global moment ``M`` acts on the angles as
    ``G(theta)^T M``).

    With ``o_guide >= 0`` the node is a wheelset and ``r`` leads from its centre to a point on
    its axlebox (:func:`axlebox_point_state`): the force and the moment about the axes across
    the axle pass into the axle (as its bearings do); the moment about the axle, which a
    bearing cannot carry, goes to the axlebox's guide on the body at offset ``o_guide`` (the
    element's other body), so that the element's forces and moments balance exactly
    (``docs/suspension.md``, "Elements at a wheelset"); the spin row gets nothing."""
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
    if o_guide < 0:
        out[o + 3] += tx
        out[o + 4] += c0 * ty + s0 * tz
        out[o + 5] += s1 * tx - s0 * c1 * ty + c0 * c1 * tz
        return
    # the axle's direction (the wheelset's third axis, without its spin)
    ex, ey, ez = s1, -s0 * c1, c0 * c1
    m_axle = tx * ex + ty * ey + tz * ez
    tx -= m_axle * ex
    ty -= m_axle * ey
    tz -= m_axle * ez
    out[o + 3] += tx
    out[o + 4] += c0 * ty + s0 * tz
    # (the spin row, e . M, is zero by construction)
    g0 = qref[o_guide + 3] + q[o_guide + 3]
    g1 = qref[o_guide + 4] + q[o_guide + 4]
    cg0, sg0 = math.cos(g0), math.sin(g0)
    cg1, sg1 = math.cos(g1), math.sin(g1)
    mx, my, mz = m_axle * ex, m_axle * ey, m_axle * ez
    out[o_guide + 3] += mx
    out[o_guide + 4] += cg0 * my + sg0 * mz
    out[o_guide + 5] += sg1 * mx - sg0 * cg1 * my + cg0 * cg1 * mz


@numba.njit(inline="always", **_JIT)
def midpoint_levers(pa, pb, ra, rb):
    """Turn the levers ``ra``, ``rb`` of an element's two ends ``pa``, ``pb`` (from their
    bodies' centres) into the levers of the ends' midpoint ``(pa + pb) / 2``: an element's
    equal and opposite forces then act at one point and carry no couple ``(pb - pa) x F``,
    which a coil spring's seats carry half each (``docs/suspension.md``, "The couple of an
    element whose ends separate")."""
    for k in range(3):
        half = 0.5 * (pb[k] - pa[k])
        ra[k] += half
        rb[k] -= half
