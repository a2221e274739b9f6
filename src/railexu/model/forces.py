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

Curved track (``docs/curving.md``): the nodes' coordinates are relative to a *vehicle frame*
that runs along the track centre line at the prescribed speed, stays horizontal and turns with
the track's heading at its own position ``s_F(t)`` (trajectory coordinates). The first
coordinate of a node is ``s_F(t)`` plus its longitudinal offset from the frame's origin, the
second and third its lateral and vertical position in the frame. The frame's motion adds
inertial forces (:func:`_frame_forces`: centripetal, Coriolis, Euler and gyroscopic terms,
exact for a frame turning about the vertical); on straight track they vanish and the
coordinates are the absolute ones of a straight track, so straight runs are unchanged. Each
wheelset's contact is evaluated in the *local* track frame at the point of the centre line
nearest to it (local heading, cant roll about the centre line at the top of rail), so the contact
kernel sees a straight, canted track as before; its forces are turned back into the vehicle
frame.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from railexu.contact import kernel as K
from railexu.model.body_points import (
    apply_force,
    axlebox_point_state,
    midpoint_levers,
    point_state,
    rotation,
)
from railexu.model.suspension_forces import suspension_forces, suspension_jacobian
from railexu.track.alignment import (
    TAB_CANT,
    TAB_DCANT,
    TAB_DDFROLL,
    TAB_DFROLL,
    TAB_DKAPPA,
    TAB_FROLL,
    TAB_KAPPA,
    TAB_PSI,
    TAB_X,
    TAB_Y,
)

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}
#: the functions that allocate nothing (railexu.contact.kernel.JIT_NO_REFCOUNT)
_JIT_NO_REFCOUNT = K.JIT_NO_REFCOUNT

#: :func:`_wheelset`'s work array: the contact kernel's wheelset state (11 entries), the rails'
#: offsets (8) and the wheelset's force (6), the vehicle frame's motion on curved track (12),
#: then from ``WORK_FIXED`` on the contact kernel's scratch (:func:`_work_size`)
W_STATE, W_RAILS, W_FORCE, W_FRAME, WORK_FIXED = 0, 11, 19, 25, 37

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

#: Entries of :attr:`KernelData.frame` (set before every call from the time).
FR_S = 0  # distance of the vehicle frame's origin along the track [m]
FR_V = 1  # its speed [m/s]
FR_VDOT = 2  # its acceleration [m/s^2]
FR_HALF_BASE = 3  # half the cant base [m] (rails' lateral position for the cant rate)
FR_G = 4  # gravity [m/s^2]
FR_SIZE = 5
#: Columns of :attr:`KernelData.ws_local` (written by every evaluation, track-relative pose).
WL_S = 0  # distance along the track of the wheelset centre's foot point [m]
WL_LATERAL = 1  # lateral displacement from the centre line, in the track plane [m]
WL_VERTICAL = 2  # vertical position in the canted track frame [m]
WL_ROLL = 3  # roll relative to the canted track [rad]
WL_YAW = 4  # yaw relative to the local track direction (angle of attack) [rad]
WL_CURVATURE = 5  # track curvature at the wheelset [1/m]
WL_CANT = 6  # cant angle of the track at the wheelset [rad]
WL_DPSI = 7  # track heading at the wheelset relative to the vehicle frame [rad]
WL_FRAME_ROLL = 8  # cant roll of the vehicle frame [rad]
WL_SIZE = 9


#: No switch-and-crossing zone: empty station tables (``KernelData.sc_tab``) and their sides.
NO_SC_TAB = np.zeros((0, 1, K.N_TABLE_COLUMNS))
NO_SC_INDEX = np.zeros((0, 2), dtype=np.int64)
NO_SC_SIDE = np.full(2, -1, dtype=np.int64)
NO_SC_INFO = np.zeros((2, 3))
NO_SC_CACHE = np.zeros((0, 1, 1, K.T_SLOPE_MAX))
NO_SC_KEY = np.zeros((0, 2), dtype=np.int64)
NO_SC_T = np.zeros((0, 2))
NO_SC_BASE = np.zeros((0, 1, K.T_SLOPE_MAX))
NO_SC_STATIONS = np.zeros(0)
NO_SC_WINDOW = np.zeros((0, 2), dtype=np.int64)


class KernelData(NamedTuple):
    """Everything the compiled force functions read besides the state (named, not positional).

    Arrays are shared with the model: ``params``, ``frame`` may be changed between calls
    (speed, frame position); ``ws_local`` is an output.
    """

    qref: np.ndarray  # reference coordinates of the object's nodes (6 per node)
    ws_slots: np.ndarray  # node slot of each wheelset (int64)
    wtab: np.ndarray  # the distinct wheel tables (n_tables, N, kernel.N_TABLE_COLUMNS)
    wtab_index: np.ndarray  # the table of each wheel (n_ws, 2) (int64)
    winfo: np.ndarray  # wheel info (n_ws, 2, 5)
    rtab: np.ndarray  # rail tables (2, M, kernel.N_TABLE_COLUMNS), left and right
    rinfo: np.ndarray  # rail info (2, 3)
    htab: np.ndarray  # Hertz table
    ktab: np.ndarray  # Kalker table
    params: np.ndarray  # contact parameters (kernel layout, K.P_*)
    irr_start: float  # irregularities: distance of the first sample [m]
    irr_step: float  # sample step [m]
    irr_values: np.ndarray  # rail offsets (n, 4): left dy, dz, right dy, dz [m]
    irr_slopes: np.ndarray  # their slopes along the track (n, 4)
    bs_int: np.ndarray  # bump stops: integer rows (n_bs, 4): slots, axlebox flags of body 0, 1
    bs_real: np.ndarray  # bump stops: real rows (n_bs, BS_NREAL)
    curved: bool  # the track has curvature or cant somewhere (else the straight-track path)
    align_start: float  # design geometry samples: distance of the first [m]
    align_step: float  # sample step [m]
    align: np.ndarray  # samples (n, alignment.TAB_COLUMNS)
    frame: np.ndarray  # vehicle frame state (FR_*)
    body_slots: np.ndarray  # node slots that get the vehicle frame's inertial forces (int64)
    body_mass: np.ndarray  # their masses [kg]
    body_inertia: np.ndarray  # their principal inertias in body axes (n, 3) [kg m^2]
    ws_local: np.ndarray  # output: track-relative pose of each wheelset (n_ws, WL_SIZE)
    rail_index: np.ndarray  # elastic track: first of the 4 rail coordinates of each wheelset
    #                         (left y, z, right y, z) in the object's coordinates; empty: rigid
    rail_preload: np.ndarray  # elastic track: static vertical wheel loads (n_ws, 2) [N]
    se_int: np.ndarray  # nonlinear suspension elements: integer rows (suspension_forces.SI_*)
    se_real: np.ndarray  # their real rows (suspension_forces.SR_*)
    se_table: np.ndarray  # their characteristic tables (n, 2)
    # switches and crossings (railexu.track.variable_rails): rail tables at stations
    # sc_stations (sc_start + i sc_step if uniform), blended linearly by the wheelset's track
    # position inside the zone (_station_interval)
    sc_start: float = 0.0  # track distance of the first station [m]
    sc_step: float = 1.0  # distance between stations if uniform [m]; 0: sc_stations not uniform
    sc_tab: np.ndarray = NO_SC_TAB  # (n_rows, M, columns): the distinct station tables
    sc_index: np.ndarray = NO_SC_INDEX  # (n_stations, 2) int64: each station's row per side
    sc_side: np.ndarray = NO_SC_SIDE  # per side the index into sc_cache's axis 1, -1: plain
    sc_info: np.ndarray = NO_SC_INFO  # per side the station tables' grid (y0, step, n)
    # per wheelset and side its blended base columns (sc_cache; the kernel reads the bound
    # columns from station i's own row of sc_tab), the station i of the blend (sc_key, -1:
    # none; -2 - row: that row's own, two stations sharing it) and its fraction (sc_t):
    # written by the force function, which re-blends only what changed (_blend_station)
    sc_cache: np.ndarray = NO_SC_CACHE  # (n_ws, n_sides, M, 4)
    sc_key: np.ndarray = NO_SC_KEY  # (n_ws, 2) int64
    sc_t: np.ndarray = NO_SC_T  # (n_ws, 2)
    # the four base columns of sc_tab on their own (n_rows, M, 4): the blend at a new position
    # reads 32 bytes a row instead of a 224-byte row's first 32 (2.5x faster, model/sc_tables.py)
    sc_base: np.ndarray = NO_SC_BASE
    sc_stations: np.ndarray = NO_SC_STATIONS  # (n_stations,) their track distances [m], increasing
    # the contact filter at the wheelset (model/sc_filter.py): its length [m]; 0: the linear
    # blend of two stations (_blend_station). > 0: the box average of the stations'
    # piecewise-linear interpolant over [s - L/2, s + L/2] (_filter_station), reading per
    # interval i the stations sc_window[i, 0] .. sc_window[i, 1], whose bounds row i envelopes
    sc_filter: float = 0.0
    sc_window: np.ndarray = NO_SC_WINDOW  # (n_stations, 2) int64


@numba.njit(**_JIT_NO_REFCOUNT)
def _irregularity(x, start, step, values, slopes, out, speed):
    """Rail offsets at ``x`` (cubic Hermite) into ``out``: (dy_l, dz_l, vy_l, vz_l, dy_r, ...)."""
    n = values.shape[0]
    for k in range(8):
        out[k] = 0.0
    u = (x - start) / step
    if n < 2 or u < 0.0 or u > n - 1.0:
        return
    i, t = K.grid_cell(u, n)
    t2 = t * t
    h00, h10, h01, h11 = K.hermite_basis(t)
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


@numba.njit(inline="always", **_JIT)
def _align_at(d, s):
    """Design geometry at distance ``s``: (x, y, heading, curvature, cant angle, d curvature/ds,
    d cant angle/ds, d^2 cant angle/ds^2); plan position and heading cubic Hermite (their
    derivatives are the heading's direction and the curvature), the rest linear between
    samples (the second derivative of the cant: the slope of the linear first derivative)."""
    tab = d.align
    n = tab.shape[0]
    h = d.align_step
    u = (s - d.align_start) / h
    if u < 0.0:
        u = 0.0
    if u > n - 1.0:
        u = n - 1.0
    i, t = K.grid_cell(u, n)
    h00, h10, h01, h11 = K.hermite_basis(t)
    p0 = tab[i, TAB_PSI]
    p1 = tab[i + 1, TAB_PSI]
    x = h00 * tab[i, TAB_X] + h10 * h * math.cos(p0) + h01 * tab[i + 1, TAB_X]
    x += h11 * h * math.cos(p1)
    y = h00 * tab[i, TAB_Y] + h10 * h * math.sin(p0) + h01 * tab[i + 1, TAB_Y]
    y += h11 * h * math.sin(p1)
    psi = h00 * p0 + h10 * h * tab[i, TAB_KAPPA] + h01 * p1 + h11 * h * tab[i + 1, TAB_KAPPA]
    a = 1.0 - t
    kappa = a * tab[i, TAB_KAPPA] + t * tab[i + 1, TAB_KAPPA]
    cant = a * tab[i, TAB_CANT] + t * tab[i + 1, TAB_CANT]
    dkappa = a * tab[i, TAB_DKAPPA] + t * tab[i + 1, TAB_DKAPPA]
    dcant = a * tab[i, TAB_DCANT] + t * tab[i + 1, TAB_DCANT]
    ddcant = (tab[i + 1, TAB_DCANT] - tab[i, TAB_DCANT]) / h
    return x, y, psi, kappa, cant, dkappa, dcant, ddcant


@numba.njit(inline="always", **_JIT)
def _frame_roll_at(d, s):
    """The vehicle frame's roll at distance ``s`` and its first and second derivatives along
    the track (linear between samples)."""
    tab = d.align
    n = tab.shape[0]
    u = (s - d.align_start) / d.align_step
    if u < 0.0:
        u = 0.0
    if u > n - 1.0:
        u = n - 1.0
    i = int(u)
    if i >= n - 1:
        i = n - 2
    t = u - i
    a = 1.0 - t
    return (
        a * tab[i, TAB_FROLL] + t * tab[i + 1, TAB_FROLL],
        a * tab[i, TAB_DFROLL] + t * tab[i + 1, TAB_DFROLL],
        a * tab[i, TAB_DDFROLL] + t * tab[i + 1, TAB_DDFROLL],
    )


@numba.njit(**_JIT)
def frame_motion(d, out):
    """Motion of the vehicle frame into ``out`` (12 entries): heading, cant roll, angular
    velocity (3) and acceleration (3) in frame axes, the origin's acceleration in frame axes
    (y, z) and gravity in frame axes (y, z).

    The frame's origin runs along the centre line at the top of rail at speed ``V``; its
    orientation is ``Rz(psi(s_F)) Rx(phi(s_F))``: the track's heading and its cant roll there
    (smoothed along the track, :meth:`railexu.track.alignment.Alignment.table`), so that the
    suspension elements, which act along the frame's axes, act along the canted track axes as
    on straight track.
    """
    s_f = d.frame[FR_S]
    v = d.frame[FR_V]
    vd = d.frame[FR_VDOT]
    _, _, psi, kappa, _, dkappa, _, _ = _align_at(d, s_f)
    phi, dphi, ddphi = _frame_roll_at(d, s_f)
    cp, sp = math.cos(phi), math.sin(phi)
    psi_d = v * kappa
    psi_dd = vd * kappa + v * v * dkappa
    phi_d = v * dphi
    phi_dd = vd * dphi + v * v * ddphi
    out[0] = psi
    out[1] = phi
    # Omega = phi_d e_x + psi_d Rx(phi)^T e_z
    out[2] = phi_d
    out[3] = psi_d * sp
    out[4] = psi_d * cp
    out[5] = phi_dd
    out[6] = psi_dd * sp + psi_d * phi_d * cp
    out[7] = psi_dd * cp - psi_d * phi_d * sp
    # origin acceleration (V', V^2 kappa, 0) horizontal -> frame axes (x component cancels)
    out[8] = cp * v * psi_d
    out[9] = -sp * v * psi_d
    # gravity (0, 0, -g) -> frame axes, minus the (0, 0, -g) Exudyn already applies
    g = d.frame[FR_G]
    out[10] = -g * sp
    out[11] = g * (1.0 - cp)


@numba.njit(**_JIT)
def track_position(d, rx, ry, rz):
    """Foot point on the centre line of a point at ``(rx, ry, rz)`` in the vehicle frame
    (offset from the frame's origin): ``(s, lateral offset, height, heading relative to the
    frame)``, lateral offset and height in the horizontal plane of the foot point. Newton's
    method on the along-track distance (2-3 iterations)."""
    s_f = d.frame[FR_S]
    xf, yf, psif, _, _, _, _, _ = _align_at(d, s_f)
    phif = _frame_roll_at(d, s_f)[0]
    cx, sx = math.cos(phif), math.sin(phif)
    yh = cx * ry - sx * rz
    zh = sx * ry + cx * rz
    cf, sf = math.cos(psif), math.sin(psif)
    px = xf + cf * rx - sf * yh
    py = yf + sf * rx + cf * yh
    s = s_f + rx
    lateral = yh
    psi = psif
    for _ in range(4):
        xs, ys, psi, kappa, _, _, _, _ = _align_at(d, s)
        dx = px - xs
        dy = py - ys
        ct, st = math.cos(psi), math.sin(psi)
        along = dx * ct + dy * st
        lateral = -dx * st + dy * ct
        s += along / (1.0 - kappa * lateral)
        if abs(along) < 1e-12:
            break
    return s, lateral, zh, psi - psif


@numba.njit(inline="always", **_JIT)
def _work_size(d):
    """Entries of :func:`_wheelset`'s work array: its state, rails and force (``WORK_FIXED``)
    and the contact kernel's scratch for the largest wheel table."""
    size = 0
    for w in range(d.winfo.shape[0]):
        size = max(size, K.wheelset_scratch_size(d.winfo[w, 0], d.winfo[w, 1]))
    return WORK_FIXED + size


@numba.njit(**_JIT_NO_REFCOUNT)
def _station_interval(d, s):
    """The stations ``i, i + 1`` around track distance ``s`` [m] and the blend fraction
    ``t = (s - x_i) / (x_{i+1} - x_i)`` (``-1, 0``: outside the stations). Uniform stations
    (``d.sc_step > 0``): ``u = (s - sc_start) / sc_step``, ``i = int(u)``, ``t = u - i``, the
    numbers of the uniform grid to the last bit; else a binary search in ``d.sc_stations``."""
    n = d.sc_index.shape[0]
    if d.sc_step > 0.0:
        u = (s - d.sc_start) / d.sc_step
        if u >= 0.0 and u <= n - 1.0:
            i = min(int(u), n - 2)
            return i, u - i
        return -1, 0.0
    x = d.sc_stations
    if not (s >= x[0] and s <= x[n - 1]):
        return -1, 0.0
    lo, hi = 0, n - 1  # x[lo] <= s, and s < x[hi] or hi the last
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if x[mid] <= s:
            lo = mid
        else:
            hi = mid
    return lo, (s - x[lo]) / (x[lo + 1] - x[lo])


@numba.njit(**_JIT_NO_REFCOUNT)
def _blend_station(d, w, i, t, side):
    """Make wheelset ``w``'s table of one side at ``(1 - t) station i + t station i+1`` in its
    cache (``d.sc_cache[w, sc_side]``): the four base columns, blended only when ``i`` or ``t``
    changes (the solver's evaluations at one track position, its Jacobian's columns but the
    longitudinal one, reuse it), read from their own contiguous copy (``d.sc_base``). The
    curvature-bound columns are not copied: the kernel reads them from station ``i``'s own row
    (``d.sc_tab[d.sc_index[i, side]]``, the pair envelopes of stations ``i`` and ``i + 1``,
    :func:`railexu.model.sc_tables.pair_envelope_bounds`, which hold for any ``t``). Copying
    them (24 columns of 4077 rows, 0.8 MB from a store of ~1 GB) at every new station cost
    ~100 us per side, most of a turnout run's force function (issue 29, docs/performance.md).

    Two stations that share one row (the plain rail between a turnout's panels) blend to that
    row at any ``t`` (``a + t (b - a)`` with ``b = a``): its base columns are copied once and
    kept while the wheelset stays on such stations (``sc_key`` then ``-2 - row``)."""
    ra = d.sc_index[i, side]
    rb = d.sc_index[i + 1, side]
    if ra == rb:
        if d.sc_key[w, side] != -2 - ra:
            out = d.sc_cache[w, d.sc_side[side]]
            a = d.sc_base[ra]
            for r in range(out.shape[0]):
                for c in range(K.T_SLOPE_MAX):
                    out[r, c] = a[r, c]
            d.sc_key[w, side] = -2 - ra
            d.sc_t[w, side] = np.nan
    elif d.sc_key[w, side] != i or d.sc_t[w, side] != t:
        out = d.sc_cache[w, d.sc_side[side]]
        a = d.sc_base[ra]
        b = d.sc_base[rb]
        for r in range(out.shape[0]):
            for c in range(K.T_SLOPE_MAX):
                out[r, c] = a[r, c] + t * (b[r, c] - a[r, c])
        d.sc_key[w, side] = i
        d.sc_t[w, side] = t


@numba.njit(inline="always", **_JIT)
def _hat_integral(x, j, u):
    """``int_{x_0}^{u} phi_j`` [m] of station ``j``'s hat function on the stations ``x`` [m]
    (``x_0 <= u <= x_{n-1}``; the first station's hat has no left half, the last's no right)."""
    n = x.shape[0]
    xj = x[j]
    if j > 0:
        left = xj - x[j - 1]
        if u <= x[j - 1]:
            return 0.0
        if u <= xj:
            return (u - x[j - 1]) ** 2 / (2.0 * left)
        half = 0.5 * left
    else:
        half = 0.0
    if j == n - 1:
        return half
    right = x[j + 1] - xj
    v = min(u, x[j + 1]) - xj
    return half + v - v * v / (2.0 * right)


@numba.njit(**_JIT_NO_REFCOUNT)
def filter_weight(x, j, s, length):
    """Weight of station ``j`` in the contact filter at track distance ``s`` [m]: ``(1/L)
    int_{s-L/2}^{s+L/2} phi_j``, ``phi_j`` the hat function of the stations ``x`` [m] (the
    interpolant constant beyond the first and the last station), ``L = length`` [m] > 0.
    Non-negative; the weights of all stations sum to 1 (model/sc_filter.py)."""
    n = x.shape[0]
    a = s - 0.5 * length
    b = s + 0.5 * length
    total = 0.0
    if j == 0 and a < x[0]:  # the interpolant constant before the first station
        total += min(b, x[0]) - a
    if j == n - 1 and b > x[n - 1]:  # and after the last
        total += b - max(a, x[n - 1])
    lo = min(max(a, x[0]), x[n - 1])
    hi = min(max(b, x[0]), x[n - 1])
    if hi > lo:
        total += _hat_integral(x, j, hi) - _hat_integral(x, j, lo)
    return total / length


@numba.njit(**_JIT_NO_REFCOUNT)
def _filter_station(d, w, i, s, side):
    """Make wheelset ``w``'s table of one side the contact filter at track distance ``s`` [m]
    (interval ``i``): the box average over ``[s - L/2, s + L/2]`` of the stations'
    piecewise-linear interpolant, ``sum_j w_j(s) station_j`` (:func:`filter_weight`: a convex
    combination, C1 in ``s``). The base columns are combined when ``s`` changes, from the
    stations whose hat meets the box and whose row is not the first one's (the plain rail
    between a turnout's panels: to the last bit); the bound columns are not copied: the kernel
    reads them from row ``i`` of the store (the envelope of the stations ``d.sc_window[i]``
    that any ``s`` of the interval reads, :func:`railexu.model.sc_tables.filter_windows`)."""
    out = d.sc_cache[w, d.sc_side[side]]
    if d.sc_key[w, side] != i:
        d.sc_key[w, side] = i
        d.sc_t[w, side] = np.nan
    if d.sc_t[w, side] == s:
        return
    x = d.sc_stations
    length = d.sc_filter
    lo = d.sc_window[i, 0]
    hi = d.sc_window[i, 1]
    # the stations whose hat meets the box: x_{j+1} > s - L/2 and x_{j-1} < s + L/2
    while lo < hi and x[lo + 1] <= s - 0.5 * length:
        lo += 1
    while hi > lo and x[hi - 1] >= s + 0.5 * length:
        hi -= 1
    # station lo's table plus the weighted differences of the others' (the weights sum to 1):
    # stations with station lo's table add nothing, so the plain rail is kept to the last bit
    # and a store with shared rows gives the same numbers as one row per station
    row_lo = d.sc_index[lo, side]
    a = d.sc_base[row_lo]
    base = d.sc_base
    # up to four other stations in one pass over the rows (10 mm stations and a 12 mm box: at
    # most three), the same sums in the same order as one pass per station (beyond four)
    n_other = 0
    r1 = r2 = r3 = r4 = row_lo
    w1 = w2 = w3 = w4 = 0.0
    for j in range(lo + 1, hi + 1):
        row = d.sc_index[j, side]
        if row == row_lo:
            continue
        wj = filter_weight(x, j, s, length)
        if wj > 0.0:
            if n_other == 0:
                r1, w1 = row, wj
            elif n_other == 1:
                r2, w2 = row, wj
            elif n_other == 2:
                r3, w3 = row, wj
            elif n_other == 3:
                r4, w4 = row, wj
            n_other += 1
    if n_other <= 4:
        rows = (r1, r2, r3, r4)
        weights = (w1, w2, w3, w4)
        for r in range(out.shape[0]):
            for c in range(K.T_SLOPE_MAX):
                v = a[r, c]
                acc = v
                for k in range(n_other):
                    acc += weights[k] * (base[rows[k], r, c] - v)
                out[r, c] = acc
    else:
        for r in range(out.shape[0]):
            for c in range(K.T_SLOPE_MAX):
                out[r, c] = a[r, c]
        for j in range(lo + 1, hi + 1):
            if d.sc_index[j, side] == row_lo:
                continue
            wj = filter_weight(x, j, s, length)
            if wj > 0.0:
                b = base[d.sc_index[j, side]]
                for r in range(out.shape[0]):
                    for c in range(K.T_SLOPE_MAX):
                        out[r, c] += wj * (b[r, c] - a[r, c])
    d.sc_t[w, side] = s


@numba.njit(**_JIT_NO_REFCOUNT)
def _wheelset(w, q, qt, d, gen, points, ws_force, work):
    """Generalized contact forces of wheelset ``w`` on its 6 node coordinates into ``gen[:6]``
    and, on elastic track, on its 4 rail coordinates into ``gen[6:10]`` (``work``: scratch of
    :func:`_work_size` entries). Compiled without reference counting: it allocates nothing."""
    o = 6 * d.ws_slots[w]
    t0 = d.qref[o + 3] + q[o + 3]
    t1 = d.qref[o + 4] + q[o + 4]
    c0, s0 = math.cos(t0), math.sin(t0)
    c1, s1 = math.cos(t1), math.sin(t1)
    d0 = qt[o + 3]
    d1 = qt[o + 4]
    d2 = qt[o + 5]
    x = d.qref[o] + q[o]
    state = work[W_STATE:W_RAILS]
    rails = work[W_RAILS:W_FORCE]
    force = work[W_FORCE:W_FRAME]
    if d.curved:
        _curved_state(w, o, q, qt, d, c0, s0, c1, s1, state, rails, work[W_FRAME:WORK_FIXED])
    else:
        state[0] = x
        state[1] = d.qref[o + 1] + q[o + 1]
        state[2] = d.qref[o + 2] + q[o + 2]
        state[3] = t0 + 0.5 * math.pi
        state[4] = -t1
        state[5] = qt[o]
        state[6] = qt[o + 1]
        state[7] = qt[o + 2]
        state[8] = d0 + s1 * d2
        state[9] = c0 * d1 - s0 * c1 * d2
        state[10] = s0 * d1 + c0 * c1 * d2
        _irregularity(x, d.irr_start, d.irr_step, d.irr_values, d.irr_slopes, rails, qt[o])
        loc = d.ws_local[w]
        loc[WL_S] = x
        loc[WL_LATERAL] = state[1]
        loc[WL_VERTICAL] = state[2]
        loc[WL_ROLL] = state[3]
        loc[WL_YAW] = state[4]
        loc[WL_CURVATURE] = 0.0
        loc[WL_CANT] = 0.0
        loc[WL_DPSI] = 0.0
        loc[WL_FRAME_ROLL] = 0.0
    elastic = d.rail_index.shape[0] > 0
    if elastic:
        # the co-running rail masses under this wheelset move the rails (track frame)
        r = d.rail_index[w]
        for side in range(2):
            rails[4 * side] += q[r + 2 * side]
            rails[4 * side + 1] += q[r + 2 * side + 1]
            rails[4 * side + 2] += qt[r + 2 * side]
            rails[4 * side + 3] += qt[r + 2 * side + 1]
    rtab_l, rinfo_l, rtab_r, rinfo_r = d.rtab[0], d.rinfo[0], d.rtab[1], d.rinfo[1]
    rbnd_l, rbnd_r = rtab_l, rtab_r  # the tables whose curvature bounds the search reads
    end = work.shape[0]
    n_st = d.sc_index.shape[0]
    if n_st > 1:
        # switches and crossings: inside the zone, the stations' tables blended at the wheelset
        s_ws = d.ws_local[w, WL_S]
        i, t = _station_interval(d, s_ws)
        if i >= 0:
            if d.sc_side[0] >= 0:
                if d.sc_filter > 0.0:
                    _filter_station(d, w, i, s_ws, 0)
                else:
                    _blend_station(d, w, i, t, 0)
                rtab_l = d.sc_cache[w, d.sc_side[0]]
                rbnd_l = d.sc_tab[d.sc_index[i, 0]]
                rinfo_l = d.sc_info[0]
            if d.sc_side[1] >= 0:
                if d.sc_filter > 0.0:
                    _filter_station(d, w, i, s_ws, 1)
                else:
                    _blend_station(d, w, i, t, 1)
                rtab_r = d.sc_cache[w, d.sc_side[1]]
                rbnd_r = d.sc_tab[d.sc_index[i, 1]]
                rinfo_r = d.sc_info[1]
    K.wheelset_contact_with_scratch(
        d.wtab[d.wtab_index[w, 0]], d.winfo[w, 0], rtab_l, rinfo_l,
        d.wtab[d.wtab_index[w, 1]], d.winfo[w, 1],
        rtab_r, rinfo_r, d.htab, d.ktab, d.params, state, rails, points[w], force,
        work[WORK_FIXED:end], rbnd_l, rbnd_r,
    )  # fmt: skip
    if elastic:
        # reaction on the rail masses, and the static wheel load they carry at rest (their
        # coordinates are measured from the statically loaded position)
        for side in range(2):
            fy = 0.0
            fz = 0.0
            for k in range(points.shape[2]):
                fy += points[w, side, k, K.PF_FTY]
                fz += points[w, side, k, K.PF_FTZ]
            gen[6 + 2 * side] = -fy
            gen[7 + 2 * side] = d.rail_preload[w, side] - fz
    if d.curved:
        loc = d.ws_local[w]
        _to_vehicle_frame(loc[WL_CANT], loc[WL_DPSI], loc[WL_FRAME_ROLL], force)
    for k in range(6):
        ws_force[w, k] = force[k]
    tx, ty, tz = force[3], force[4], force[5]
    gen[0] = force[0]
    gen[1] = force[1]
    gen[2] = force[2]
    gen[3] = tx
    gen[4] = c0 * ty + s0 * tz
    gen[5] = s1 * tx - s0 * c1 * ty + c0 * c1 * tz


@numba.njit(inline="always", **_JIT)
def _to_local(cf, sf, cz, sz, cx, sx, vx, vy, vz):
    """``Rx(cant)^T Rz(dpsi)^T Rx(phi_F) v``: vehicle frame -> canted local track frame."""
    b = cf * vy - sf * vz
    c = sf * vy + cf * vz
    a = cz * vx + sz * b
    b = -sz * vx + cz * b
    return a, cx * b + sx * c, -sx * b + cx * c


@numba.njit(**_JIT_NO_REFCOUNT)
def _curved_state(w, o, q, qt, d, c0, s0, c1, s1, state, rails, fm):
    """The kernel's state and rail offsets of wheelset ``w`` in its local track frame (curved
    track); also fills ``d.ws_local[w]`` (``fm``: scratch of 12 entries)."""
    frame_motion(d, fm)
    rx = d.qref[o] + q[o] - d.frame[FR_S]
    ry = d.qref[o + 1] + q[o + 1]
    rz = d.qref[o + 2] + q[o + 2]
    s, lateral, zh, dpsi = track_position(d, rx, ry, rz)
    _, _, _, kappa, cant, _, dcant, _ = _align_at(d, s)
    cf, sf = math.cos(fm[1]), math.sin(fm[1])
    cz, sz = math.cos(dpsi), math.sin(dpsi)
    cx, sx = math.cos(cant), math.sin(cant)
    # position: the foot point is the local origin (along-track offset zero)
    state[0] = s
    state[1] = cx * lateral + sx * zh
    state[2] = -sx * lateral + cx * zh
    # axle direction (body z) -> roll and yaw relative to the canted local track
    ax, ay, az = _to_local(cf, sf, cz, sz, cx, sx, s1, -s0 * c1, c0 * c1)
    state[3] = math.atan2(az, ay)
    state[4] = math.asin(-ax)
    # absolute velocity of the centre (frame velocity + Omega x r) and absolute angular
    # velocity, local axes
    ox, oy, oz = fm[2], fm[3], fm[4]
    vx = qt[o] + oy * rz - oz * ry
    vy = qt[o + 1] + oz * rx - ox * rz
    vz = qt[o + 2] + ox * ry - oy * rx
    state[5], state[6], state[7] = _to_local(cf, sf, cz, sz, cx, sx, vx, vy, vz)
    d0, d1, d2 = qt[o + 3], qt[o + 4], qt[o + 5]
    wx = d0 + s1 * d2 + ox
    wy = c0 * d1 - s0 * c1 * d2 + oy
    wz = s0 * d1 + c0 * c1 * d2 + oz
    state[8], state[9], state[10] = _to_local(cf, sf, cz, sz, cx, sx, wx, wy, wz)
    _irregularity(s, d.irr_start, d.irr_step, d.irr_values, d.irr_slopes, rails, state[5])
    # the cant changing along the track raises one rail and lowers the other under the wheel
    rate = d.frame[FR_HALF_BASE] * dcant * state[5]
    rails[3] += rate
    rails[7] -= rate
    loc = d.ws_local[w]
    loc[WL_S] = s
    loc[WL_LATERAL] = state[1]
    loc[WL_VERTICAL] = state[2]
    loc[WL_ROLL] = state[3]
    loc[WL_YAW] = state[4]
    loc[WL_CURVATURE] = kappa
    loc[WL_CANT] = cant
    loc[WL_DPSI] = dpsi
    loc[WL_FRAME_ROLL] = fm[1]


@numba.njit(**_JIT_NO_REFCOUNT)
def _to_vehicle_frame(cant, dpsi, phi_f, force):
    """Turn the kernel's force and torque from the local track frame (cant angle, heading
    ``dpsi`` relative to the frame) into the vehicle frame: ``Rx(phi_F)^T Rz(dpsi) Rx(cant)``."""
    cz, sz = math.cos(dpsi), math.sin(dpsi)
    cx, sx = math.cos(cant), math.sin(cant)
    cf, sf = math.cos(phi_f), math.sin(phi_f)
    for k in (0, 3):
        fx, fy, fz = force[k], force[k + 1], force[k + 2]
        b = cx * fy - sx * fz
        c = sx * fy + cx * fz
        a = cz * fx - sz * b
        b = sz * fx + cz * b
        force[k] = a
        force[k + 1] = cf * b + sf * c
        force[k + 2] = -sf * b + cf * c


@numba.njit(**_JIT)
def _cross(ax, ay, az, bx, by, bz):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@numba.njit(**_JIT)
def _frame_forces(j, q, qt, d, out):
    """Add the inertial forces of the moving vehicle frame and the frame's share of gravity on
    body ``j`` of ``d.body_slots``.

    A body at ``r`` in a frame with origin acceleration ``a_O``, angular velocity ``Omega`` and
    angular acceleration ``Omega'`` has the absolute acceleration
    ``a_O + r'' + 2 Omega x r' + Omega' x r + Omega x (Omega x r)`` and the absolute angular
    velocity ``w + Omega`` (Goldstein, Poole & Safko 2002, Classical Mechanics, 3rd ed.,
    ch. 4.10); the terms Exudyn does not know are added as forces. The tangential ``V'`` of the
    origin cancels because the first coordinate already contains ``s_F``.
    """
    fm = np.empty(12)
    frame_motion(d, fm)
    o = 6 * d.body_slots[j]
    m = d.body_mass[j]
    v = d.frame[FR_V]
    rx = d.qref[o] + q[o] - d.frame[FR_S]
    ry = d.qref[o + 1] + q[o + 1]
    rz = d.qref[o + 2] + q[o + 2]
    vx, vy, vz = qt[o] - v, qt[o + 1], qt[o + 2]
    ox, oy, oz = fm[2], fm[3], fm[4]
    c1x, c1y, c1z = _cross(ox, oy, oz, vx, vy, vz)
    c2x, c2y, c2z = _cross(fm[5], fm[6], fm[7], rx, ry, rz)
    wx_, wy_, wz_ = _cross(ox, oy, oz, rx, ry, rz)
    c3x, c3y, c3z = _cross(ox, oy, oz, wx_, wy_, wz_)
    out[o] -= m * (2.0 * c1x + c2x + c3x)
    out[o + 1] -= m * (fm[8] + 2.0 * c1y + c2y + c3y - fm[10])
    out[o + 2] -= m * (fm[9] + 2.0 * c1z + c2z + c3z - fm[11])
    # rotation: J (A^T Omega' - w_b x Omega_b) + w_b x J Omega_b + Omega_b x J (w_b + Omega_b)
    t0 = d.qref[o + 3] + q[o + 3]
    t1 = d.qref[o + 4] + q[o + 4]
    t2 = d.qref[o + 5] + q[o + 5]
    a = rotation(t0, t1, t2)
    c0, s0 = math.cos(t0), math.sin(t0)
    c1, s1 = math.cos(t1), math.sin(t1)
    wx = qt[o + 3] + s1 * qt[o + 5]
    wy = c0 * qt[o + 4] - s0 * c1 * qt[o + 5]
    wz = s0 * qt[o + 4] + c0 * c1 * qt[o + 5]
    # body axes: u_b = A^T u
    bx = a[0] * wx + a[3] * wy + a[6] * wz
    by = a[1] * wx + a[4] * wy + a[7] * wz
    bz = a[2] * wx + a[5] * wy + a[8] * wz
    obx = a[0] * ox + a[3] * oy + a[6] * oz
    oby = a[1] * ox + a[4] * oy + a[7] * oz
    obz = a[2] * ox + a[5] * oy + a[8] * oz
    dbx = a[0] * fm[5] + a[3] * fm[6] + a[6] * fm[7]
    dby = a[1] * fm[5] + a[4] * fm[6] + a[7] * fm[7]
    dbz = a[2] * fm[5] + a[5] * fm[6] + a[8] * fm[7]
    jx, jy, jz = d.body_inertia[j, 0], d.body_inertia[j, 1], d.body_inertia[j, 2]
    kx, ky, kz = _cross(bx, by, bz, obx, oby, obz)
    ex, ey, ez = jx * (dbx - kx), jy * (dby - ky), jz * (dbz - kz)
    kx, ky, kz = _cross(bx, by, bz, jx * obx, jy * oby, jz * obz)
    ex, ey, ez = ex + kx, ey + ky, ez + kz
    kx, ky, kz = _cross(obx, oby, obz, jx * (bx + obx), jy * (by + oby), jz * (bz + obz))
    ex, ey, ez = ex + kx, ey + ky, ez + kz
    # torque -A e in the frame, then on the angles through G^T
    tx = -(a[0] * ex + a[1] * ey + a[2] * ez)
    ty = -(a[3] * ex + a[4] * ey + a[5] * ez)
    tz = -(a[6] * ex + a[7] * ey + a[8] * ez)
    out[o + 3] += tx
    out[o + 4] += c0 * ty + s0 * tz
    out[o + 5] += s1 * tx - s0 * c1 * ty + c0 * c1 * tz


@numba.njit(inline="always", **_JIT)
def bump_stop_law(d, v, clear, k, c):
    """Force of a bump stop on its second body along its axis [N] at separation change ``d``
    [m] and relative velocity ``v`` [m/s]: nothing within ``+-clear``, beyond it
    ``-k (d -+ clear) - c v``, never pulling (also called from Python, e.g. by the
    yaw-resistance test)."""
    f = 0.0
    if d > clear:
        f = -k * (d - clear) - c * v
        if f > 0.0:
            f = 0.0
    elif d < -clear:
        f = -k * (d + clear) - c * v
        if f < 0.0:
            f = 0.0
    return f


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
    p0, p1 = BS_P0, BS_P1
    box_a = bs_int[b, 2] == 1
    box_b = bs_int[b, 3] == 1
    if box_a:
        axlebox_point_state(oa, bs_real[b, p0], bs_real[b, p0 + 1], bs_real[b, p0 + 2], q, qt,
                            qref, pa, va, ra)  # fmt: skip
    else:
        point_state(oa, bs_real[b, p0], bs_real[b, p0 + 1], bs_real[b, p0 + 2], q, qt, qref,
                    pa, va, ra)  # fmt: skip
    if box_b:
        axlebox_point_state(ob, bs_real[b, p1], bs_real[b, p1 + 1], bs_real[b, p1 + 2], q, qt,
                            qref, pb, vb, rb)  # fmt: skip
    else:
        point_state(ob, bs_real[b, p1], bs_real[b, p1 + 1], bs_real[b, p1 + 2], q, qt, qref,
                    pb, vb, rb)  # fmt: skip
    d = pb[dr] - pa[dr] - bs_real[b, BS_D0]
    f = bump_stop_law(d, vb[dr] - va[dr], bs_real[b, BS_CLEAR], bs_real[b, BS_K], bs_real[b, BS_C])
    if f != 0.0:
        midpoint_levers(pa, pb, ra, rb)  # no couple of the separated ends (docs/suspension.md)
        f0 = f if dr == 0 else 0.0
        f1 = f if dr == 1 else 0.0
        f2 = f if dr == 2 else 0.0
        apply_force(oa, ob if box_a else -1, -f0, -f1, -f2, ra, q, qref, out)
        apply_force(ob, oa if box_b else -1, f0, f1, f2, rb, q, qref, out)


@numba.njit(**_JIT)
def generalized_forces(q, qt, d, out, points, ws_force):
    """Generalized forces of all contacts, bump stops and (curved track) the vehicle frame's
    inertial forces on the object's coordinates.

    Args:
        q, qt: the object's coordinates and velocities (6 per node, without reference values).
        d: the :class:`KernelData`.
        out: generalized forces, same length as ``q`` (overwritten).
        points: contact points ``(n_ws, 2, MAX_POINTS, N_POINT_FIELDS)`` (overwritten).
        ws_force: contact force and torque on each wheelset, vehicle frame ``(n_ws, 6)``.
    """
    for i in range(out.shape[0]):
        out[i] = 0.0
    gen = np.empty(10)
    work = np.empty(_work_size(d))
    for w in range(d.ws_slots.shape[0]):
        _wheelset(w, q, qt, d, gen, points, ws_force, work)
        _add_wheelset(w, d, gen, out)
    _other_forces(q, qt, d, out)


@numba.njit(**_JIT_NO_REFCOUNT)
def _add_wheelset(w, d, gen, out):
    """Add wheelset ``w``'s generalized contact forces ``gen`` (:func:`_wheelset`) into
    ``out``: its node's 6 coordinates and, on elastic track, its 4 rail coordinates."""
    o = 6 * d.ws_slots[w]
    for k in range(6):
        out[o + k] += gen[k]
    if d.rail_index.shape[0] > 0:
        r = d.rail_index[w]
        for k in range(4):
            out[r + k] += gen[6 + k]


@numba.njit(**_JIT)
def _other_forces(q, qt, d, out):
    """Add the bump stops', the nonlinear suspension elements' and (curved track) the vehicle
    frame's inertial forces into ``out``."""
    for b in range(d.bs_int.shape[0]):
        _bump_stop(b, q, qt, d.qref, d.bs_int, d.bs_real, out)
    suspension_forces(q, qt, d.qref, d.se_int, d.se_real, d.se_table, out)
    if d.curved:
        for j in range(d.body_slots.shape[0]):
            _frame_forces(j, q, qt, d, out)


@numba.njit(parallel=True, **_JIT)
def generalized_forces_threaded(q, qt, d, out, points, ws_force):
    """:func:`generalized_forces` with the wheelsets' contacts on numba's threads
    (:mod:`railexu.runtime.threads`): each wheelset's contact writes only its own rows, and the sums
    into ``out`` are made afterwards in the wheelsets' order, so the results are those of
    :func:`generalized_forces` to the last bit."""
    n_ws = d.ws_slots.shape[0]
    gens = np.empty((n_ws, 10))
    works = np.empty((n_ws, _work_size(d)))
    for w in numba.prange(n_ws):
        _wheelset(w, q, qt, d, gens[w], points, ws_force, works[w])
    for i in range(out.shape[0]):
        out[i] = 0.0
    for w in range(n_ws):
        _add_wheelset(w, d, gens[w], out)
    _other_forces(q, qt, d, out)


def compiled_entry(function, *args):
    """The compiled machine-code entry of a numba function for arguments like ``args``,
    bypassing numba's type dispatch on every call.

    The force function is called some 30 000 times per simulated 15 s, and resolving the types of
    :class:`KernelData` (a named tuple of 27 arrays and numbers) costs several microseconds per
    call (``benchmarks/realtime.py`` prints the effect). The function is first called with
    ``args`` (compiling it or loading it from numba's cache); if numba's compiled-overload table
    is not available (a numba version that changed it), the dispatcher itself is returned."""
    function(*args)
    try:
        signature = tuple(numba.typeof(a) for a in args)
        return function.overloads[signature].entry_point
    except (AttributeError, KeyError, TypeError):
        return function


#: Finite-difference steps of :func:`jacobian`: coordinates [m, rad] and velocities [m/s, rad/s].
EPS_Q = 1.0e-8
EPS_V = 1.0e-6


@numba.njit(**_JIT)
def jacobian(q, qt, d, f_q, f_v, jac, points, ws_force):
    """Exudyn's Jacobian of the forces, ``-f_q df/dq - f_v df/dq_t``, by finite differences that
    use the structure: a wheelset's contact forces depend only on its own 12 coordinates and
    velocities, a bump stop's only on those of its two bodies, a body's inertial frame forces
    only on its own. 13 wheelset evaluations per wheelset instead of ``2 n + 1`` evaluations of
    everything (``n`` = 6 per node), and no dependence on the spin angle (a body of
    revolution)."""
    n = q.shape[0]
    for i in range(n):
        for j in range(n):
            jac[i, j] = 0.0
    gen0 = np.empty(10)
    gen1 = np.empty(10)
    work = np.empty(_work_size(d))
    qp = q.copy()
    qtp = qt.copy()
    elastic = d.rail_index.shape[0] > 0
    n_own = 10 if elastic else 6  # the wheelset's coordinates and its rail masses'
    index = np.empty(10, dtype=np.int64)
    for w in range(d.ws_slots.shape[0]):
        o = 6 * d.ws_slots[w]
        for k in range(6):
            index[k] = o + k
        if elastic:
            for k in range(4):
                index[6 + k] = d.rail_index[w] + k
        _wheelset(w, q, qt, d, gen0, points, ws_force, work)
        for j in range(2 * n_own):
            col = index[j % n_own]
            if j == 5:
                continue  # the spin angle does not change the contact
            if j < n_own:
                h = EPS_Q
                qp[col] = q[col] + h
            else:
                h = EPS_V
                qtp[col] = qt[col] + h
            _wheelset(w, qp, qtp, d, gen1, points, ws_force, work)
            factor = f_q if j < n_own else f_v
            for k in range(n_own):
                jac[index[k], col] -= factor * (gen1[k] - gen0[k]) / h
            qp[col] = q[col]
            qtp[col] = qt[col]
    # bump stops
    base = np.zeros(n)
    pert = np.zeros(n)
    for b in range(d.bs_int.shape[0]):
        for i in range(n):
            base[i] = 0.0
        _bump_stop(b, q, qt, d.qref, d.bs_int, d.bs_real, base)
        for side in range(2):
            o = 6 * d.bs_int[b, side]
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
                _bump_stop(b, qp, qtp, d.qref, d.bs_int, d.bs_real, pert)
                factor = f_q if j < 6 else f_v
                for side2 in range(2):
                    r = 6 * d.bs_int[b, side2]
                    for k in range(6):
                        jac[r + k, col] -= factor * (pert[r + k] - base[r + k]) / h
                qp[col] = q[col]
                qtp[col] = qt[col]
    suspension_jacobian(q, qt, d.qref, d.se_int, d.se_real, d.se_table, f_q, f_v, jac, qp, qtp,
                        base, pert)  # fmt: skip
    if d.curved:
        _frame_jacobian(q, qt, d, f_q, f_v, jac, qp, qtp, base, pert)


@numba.njit(**_JIT)
def _frame_jacobian(q, qt, d, f_q, f_v, jac, qp, qtp, base, pert):
    """Add the finite-difference Jacobian of the vehicle frame's inertial forces (each body's
    depend on its own 12 coordinates and velocities only)."""
    n = q.shape[0]
    for jb in range(d.body_slots.shape[0]):
        o = 6 * d.body_slots[jb]
        for i in range(n):
            base[i] = 0.0
        _frame_forces(jb, q, qt, d, base)
        for j in range(12):
            col = o + (j % 6)
            if j < 6:
                h = EPS_Q
                qp[col] = q[col] + h
            else:
                h = EPS_V
                qtp[col] = qt[col] + h
            for k in range(6):
                pert[o + k] = 0.0
            _frame_forces(jb, qp, qtp, d, pert)
            factor = f_q if j < 6 else f_v
            for k in range(6):
                jac[o + k, col] -= factor * (pert[o + k] - base[o + k]) / h
            qp[col] = q[col]
            qtp[col] = qt[col]
