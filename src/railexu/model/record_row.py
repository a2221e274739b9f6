"""The recorder's work at every output time, compiled: copy the state it keeps and check for
derailment (:class:`railexu.simulation.recorder.Recorder`).

An output sample comes every second step or so, thousands of times a run; done with numpy on
arrays of four wheelsets, its two dozen small operations cost more than a tenth of the
integration. Here they are one call.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from railexu.model.forces import WL_LATERAL, WL_ROLL, WL_S, WL_VERTICAL

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}

#: :func:`keep_row`'s verdicts
ROW_KEPT = 0
ROW_NOT_FINITE = 1
ROW_WHEEL_ROSE = 2
ROW_OFF_TRACK = 3


@numba.njit(**_JIT)
def keep_row(
    k, q, qt, qtt, ws_local, points, order, kept, i_body, i_rail, i_acc,
    out_local, out_points, out_body, out_rail, out_acc,
):  # fmt: skip
    """Copy output ``k``: the wheelsets' track-relative poses and kept contact-point fields
    (wheelsets in ``order``), the coordinates ``q[i_body]``, ``q[i_rail]`` and ``qtt[i_acc]``
    (``qtt`` may be empty: then no accelerations). Returns False if the state is not finite
    (nothing is copied then)."""
    for i in range(q.size):
        if not (math.isfinite(q[i]) and math.isfinite(qt[i])):
            return False
    for w in range(order.size):
        o = order[w]
        for f in range(ws_local.shape[1]):
            out_local[k, w, f] = ws_local[o, f]
        for side in range(points.shape[1]):
            for p in range(points.shape[2]):
                for f in range(kept.size):
                    out_points[k, w, side, p, f] = points[o, side, p, kept[f]]
    for j in range(i_body.size):
        out_body[k, j] = q[i_body[j]]
    for j in range(i_rail.size):
        out_rail[k, j] = q[i_rail[j]]
    if qtt.size > 0:
        for j in range(i_acc.size):
            out_acc[k, j] = qtt[i_acc[j]]
    return True


@numba.njit(**_JIT)
def derailment(loc, z0, sin_roll0, e, lift_limit, centre_x, centre_y, lateral_limit_m):
    """Check one output's wheelset poses ``loc`` (n_ws, WL_SIZE) for derailment.

    A wheel has risen when its height above the static state, ``z - z0 +- e (sin(roll) -
    sin(roll0))`` (``e`` the lateral distance of the tape circle from the wheelset centre), is
    above ``lift_limit``; a wheelset is off the track when its lateral displacement from the
    track centre line (the design line plus ``centre_y`` interpolated at the wheelset's
    distance ``centre_x``, empty for none) exceeds ``lateral_limit_m``.

    Returns:
        ``(verdict, wheelset, side, rise_m, lateral_m)``: a ``ROW_*`` verdict, the wheelset's
        index in ``loc``, 0 left / 1 right, its rise and lateral displacement [m].
    """
    n = loc.shape[0]
    lateral = np.empty(n)
    for w in range(n):
        centre = 0.0
        if centre_x.size > 0:
            s = loc[w, WL_S]
            if centre_x[0] <= s <= centre_x[-1]:
                centre = np.interp(s, centre_x, centre_y)
        lateral[w] = loc[w, WL_LATERAL] - centre
    for w in range(n):
        droll = e[w] * (math.sin(loc[w, WL_ROLL]) - sin_roll0[w])
        left = loc[w, WL_VERTICAL] - z0[w] + droll
        right = loc[w, WL_VERTICAL] - z0[w] - droll
        rise = max(left, right)
        if rise > lift_limit[w]:
            return ROW_WHEEL_ROSE, w, 0 if left > right else 1, rise, lateral[w]
    for w in range(n):
        if abs(lateral[w]) > lateral_limit_m:
            return ROW_OFF_TRACK, w, 0, 0.0, lateral[w]
    return ROW_KEPT, 0, 0, 0.0, 0.0
