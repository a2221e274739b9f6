"""The compiled per-wheelset contact evaluation (numba).

This is the function the dynamics calls for every wheelset in every Newton iteration, so it is
written with scalars only, allocates nothing and reads precomputed tables.

Method (the seed's steps a-d, specialised to a rail that is a cylinder along the track):

a) *Contact locus.* A wheel is a surface of revolution. For each circle of the wheel (lateral
   profile coordinate ``s``) the only point where the wheel normal can be parallel to a rail
   normal lies where the wheel normal has no component along the track, because the normal of a
   straight rail lies in the track's y-z plane. With the wheelset orientation
   ``R = Rx(phi) Rz(psi)`` this point sits at the angle ``theta`` from the bottom of the circle with
   ``sin(theta) = -r'(s) tan(psi)``: it moves ahead of or behind the axle with yaw (flange
   lead). This is the exact 3-D solution of the parametric-surface conditions (wheel normal
   parallel to the rail normal, distance along the rail normal) for a straight rail, reduced to
   the single wheel parameter ``s``; :mod:`railexu.contact.search` solves the same conditions as a
   general nonlinear system in the four surface parameters and the tests compare the two.
b) *Contact points.* Along the locus the vertical gap to the rail ``g(s)`` and its exact slope
   are scanned on a coarse grid (``scan_step``); every local minimum is refined to machine
   precision by a bracketed Illinois iteration on ``g'(s) = 0`` (equal slopes = common normal).
   A minimum hidden between two scan nodes (beside a hump, where a profile's curvature jumps)
   is searched for by bisection wherever bounds of the gap's curvature
   (:func:`_curvature_bounds`) cannot rule out one that would carry force
   (:func:`_hidden_minima`), so that the forces do not depend on the scan grid. Each local
   minimum with ``g < 0`` is a contact point: one on the tread, or two when tread and flange
   both touch (the seed's Fig. 8); minima sharing one overlap region are weighted
   (:func:`candidate_weights`). The normal penetration is ``delta = -g cos(gamma)``.
c) *Normal force.* Each minimum is a patch (:func:`patch_centre`, issue 28): the force acts at
   the centroid of its load (virtual penetration, Kik and Piotrowski 2008), with the approach
   along the normal there and Hertz's lateral curvature the minimum's, bounded by the one the
   patch's load width implies (:func:`patch_curvature`; :mod:`railexu.contact.hertz`); so two
   minima in one nearly flat valley (S1002 flange root on a 60E1 gauge corner) have one patch,
   and the minima of one valley share it by their weights (:func:`candidate_weights`).
   The damped force of the seed's eq. (2)
   ``N = K delta^1.5 + D delta_dot`` (or Hunt-Crossley ``K delta^1.5 (1 + chi delta_dot)``), never
   negative.
d) *Tangential forces.* Creepages and spin from the wheel's velocity at the point; Kalker's
   coefficients for the ellipse's a/b; the creep law chosen by name (Polach by default).

Frames and signs follow ``docs/conventions.md``. The right wheel is evaluated as the mirror image
of a left wheel (``y -> -y``; roll, yaw, lateral velocity, roll and yaw rates change sign) so that
the same code serves both sides; the results are mirrored back.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from railexu.contact.creep import creep_forces_nb
from railexu.contact.hertz import hertz_coefficients_nb
from railexu.contact.kalker import kalker_coefficients_nb
from railexu.contact.parameters import (  # noqa: F401 (P_*, N_PARAMS re-exported for kernel users)
    N_PARAMS,
    P_CREEP,
    P_DAMP,
    P_DAMP_MODEL,
    P_ESTAR,
    P_FRIC_A,
    P_FRIC_B,
    P_KA,
    P_KS,
    P_MU,
    P_SCAN,
    P_SHEAR,
    P_SPEED,
    P_TANGENTIAL,
)

#: Most contact points searched per wheel.
MAX_POINTS = 3

# Fields of the per-point output array ``points[side, k, field]`` (real track frame unless noted).
PF_ACTIVE = 0  # 1.0 if the candidate exists (local minimum of the gap), else 0.0
PF_S = 1  # contact position on the wheel profile, from the tape circle, outwards positive [m]
PF_YRAIL = 2  # lateral position on the placed rail, left-type track axes [m]
PF_X = 3  # contact point, track frame [m]
PF_Y = 4
PF_Z = 5
PF_RADIUS = 6  # rolling radius of the wheel at the point [m]
PF_ANGLE = 7  # contact angle, positive towards the flange (left-type rail slope angle) [rad]
PF_GAP = 8  # vertical gap (negative = overlap) [m]
PF_DELTA = 9  # normal penetration [m]
PF_N = 10  # normal force [N]
PF_A = 11  # semi-axis in rolling direction [m]
PF_B = 12  # lateral semi-axis [m]
PF_XI = 13  # longitudinal creepage
PF_ETA = 14  # lateral creepage (real contact frame: t_y = n x t_x)
PF_SPIN = 15  # spin creepage [1/m] (real contact frame)
PF_FX = 16  # tangential force on the wheel along t_x [N]
PF_FY = 17  # tangential force on the wheel along t_y [N]
PF_FTX = 18  # total contact force on the wheel, track frame [N]
PF_FTY = 19
PF_FTZ = 20
PF_KWX = 21  # wheel principal curvature along the rolling direction [1/m]
PF_KWY = 22  # wheel lateral curvature (convex positive) [1/m]
PF_KRY = 23  # rail lateral curvature (convex positive) [1/m]
PF_DELTA_DOT = 24  # penetration rate [m/s]
PF_NX = 25  # contact normal, track frame
PF_NY = 26
PF_NZ = 27
PF_WEIGHT = 28  # weight of a minimum inside a shared overlap region (candidate_weights)
N_POINT_FIELDS = 29

# Entries of the parameter vector ``params``: P_* in railexu.contact.parameters (numba-free).

# Columns of ``wheel_info`` / ``rail_info``.
WI_S0, WI_STEP, WI_N, WI_R0, WI_TAPE = 0, 1, 2, 3, 4
RI_Y0, RI_STEP, RI_N = 0, 1, 2

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}


def _without_reference_counting() -> dict:
    """numba's option that compiles a function without its runtime's reference counting of
    arrays (``{}`` for a numba that no longer has it: the functions are then compiled with it,
    slower, with the same results).

    numba counts the references to an array around each use of it in a compiled function, with
    an atomic increment and decrement of a shared counter that its optimiser removes only
    within simple blocks; in the search loops of this kernel, which pass the wheel and rail
    tables down to inlined helpers, this counting took 40 % of the processor time of the seed
    run's integration (sampled with ``perf``) and half of ``benchmarks/contact.py``'s time per
    wheelset (docs/performance.md). The functions compiled with :data:`JIT_NO_REFCOUNT`
    allocate nothing: their callers own every array they read or write, and their work arrays
    (:func:`candidates_work_size`, :func:`wheelset_scratch_size`) are passed in."""
    try:
        from numba.core.cpu import CPUTargetOptions

        return {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}
    except ImportError:  # pragma: no cover - a numba that moved its options
        return {}


#: Options of the compiled functions that allocate nothing (:func:`_without_reference_counting`):
#: the contact search and the per-wheel and per-wheelset evaluations, and in
#: :mod:`railexu.model.forces` the per-wheelset force.
JIT_NO_REFCOUNT = {**_JIT, **_without_reference_counting()}

#: Columns of the wheel and rail tables: value, slope, curvature, smoothed curvature (built by
#: :mod:`railexu.contact.evaluation`), then the curvature-bound columns of
#: :func:`with_block_bounds`: over each block of ``TABLE_BLOCK`` rows the largest ``|slope|``,
#: the smallest and the largest curvature and the largest curvature change per metre; then the
#: same four bounds as a sparse table over short runs of rows (:func:`_range_bounds`).
T_SLOPE_MAX, T_CURV_MIN, T_CURV_MAX, T_CURV_RATE = 4, 5, 6, 7
N_BLOCK_COLUMNS = 8
TABLE_BLOCK = 16
#: Sparse-table levels: level ``L`` (1..``SPARSE_LEVELS``) holds in columns
#: ``T_SPARSE + 4 (L - 1) + c`` the bound ``c`` (largest ``|slope|``, smallest and largest
#: curvature, largest curvature jump between neighbouring rows) over the ``2^L`` rows (jumps) from
#: each row on, so that any run of up to ``2^(SPARSE_LEVELS + 1) - 1`` rows is two reads.
SPARSE_LEVELS = 5
T_SPARSE = N_BLOCK_COLUMNS
N_TABLE_COLUMNS = T_SPARSE + 4 * SPARSE_LEVELS


def with_block_bounds(tab: np.ndarray, step_m: float) -> np.ndarray:
    """The table ``[z, z', z'', z''_smooth]`` (rows on a uniform grid of ``step_m`` [m]) with the
    four curvature-bound columns ``T_*`` appended: every row holds the values of its block of
    ``TABLE_BLOCK`` rows (the curvature change of a block's last row is that to the next
    block's first), so that :func:`_curvature_bounds` reads a few blocks instead of every row
    of a scan cell."""
    tab = np.asarray(tab, dtype=np.float64)
    n = tab.shape[0]
    rate = np.zeros(n)
    rate[:-1] = np.abs(np.diff(tab[:, 2])) / step_m
    blocks = -(-n // TABLE_BLOCK)
    pad = blocks * TABLE_BLOCK - n

    def per_block(values: np.ndarray, reduce, fill: float) -> np.ndarray:
        padded = np.concatenate([values, np.full(pad, fill)]).reshape(blocks, TABLE_BLOCK)
        return np.repeat(reduce(padded, axis=1), TABLE_BLOCK)[:n]

    extra = np.column_stack([
        per_block(np.abs(tab[:, 1]), np.max, 0.0),
        per_block(tab[:, 2], np.min, np.inf),
        per_block(tab[:, 2], np.max, -np.inf),
        per_block(rate, np.max, 0.0),
    ])  # fmt: skip
    return np.ascontiguousarray(np.column_stack([tab[:, :4], extra, _sparse_bounds(tab)]))


def _sparse_bounds(tab: np.ndarray) -> np.ndarray:
    """The sparse-table columns of :data:`T_SPARSE`: for each level ``L`` the four bounds over
    rows ``i .. i + 2^L - 1`` (the jumps ``|z''[j + 1] - z''[j]|`` for ``j`` in that run), exact
    copies of the table's values so that a query equals a loop over the rows. Runs that pass
    the table's end hold the bounds of the rows that exist (a query never reads them)."""
    n = tab.shape[0]
    jump = np.zeros(n)
    jump[:-1] = np.abs(tab[1:, 2] - tab[:-1, 2])
    level = [np.abs(tab[:, 1]), tab[:, 2].copy(), tab[:, 2].copy(), jump]
    reduce = (np.maximum, np.minimum, np.maximum, np.maximum)
    columns = []
    for lv in range(1, SPARSE_LEVELS + 1):
        half = 1 << (lv - 1)
        nxt = []
        for values, op in zip(level, reduce, strict=True):
            shifted = values[np.minimum(np.arange(n) + half, n - 1)]
            nxt.append(op(values, shifted))
        level = nxt
        columns.extend(level)
    return np.column_stack(columns)


@numba.njit(inline="always", **_JIT)
def hermite_basis(t):
    """The cubic Hermite basis at ``t`` in [0, 1]: ``(h00, h10, h01, h11)`` with
    ``p(t) = h00 p0 + h10 h m0 + h01 p1 + h11 h m1`` on a cell of width ``h``. The one
    definition of the compiled code (profile tables, irregularities, the track alignment)."""
    t2 = t * t
    t3 = t2 * t
    return 2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + t, -2.0 * t3 + 3.0 * t2, t3 - t2


@numba.njit(inline="always", **_JIT)
def grid_cell(u, n):
    """Cell ``i`` and local coordinate ``t`` of the grid coordinate ``u`` (``0 <= u <= n - 1``)
    on a table of ``n`` samples; the last sample belongs to the last cell."""
    i = int(u)
    if i >= n - 1:
        i = n - 2
    return i, u - i


@numba.njit(inline="always", **_JIT)
def _hermite(tab, y0, step, n, y):
    """Cubic Hermite interpolation of ``tab[:, 0]`` with slopes ``tab[:, 1]`` on a uniform grid.

    Returns ``(value, slope, second_derivative, ok)``; the second derivative is interpolated
    linearly from ``tab[:, 2]``. ``ok`` is False outside the table.
    """
    u = (y - y0) / step
    if u < 0.0 or u > n - 1.0:
        return 0.0, 0.0, 0.0, False
    i, t = grid_cell(u, n)
    z0 = tab[i, 0]
    z1 = tab[i + 1, 0]
    d0 = tab[i, 1] * step
    d1 = tab[i + 1, 1] * step
    t2 = t * t
    h00, h10, h01, h11 = hermite_basis(t)
    val = h00 * z0 + h10 * d0
    val += h01 * z1 + h11 * d1
    der = (6.0 * t2 - 6.0 * t) * z0 + (3.0 * t2 - 4.0 * t + 1.0) * d0
    der += (6.0 * t - 6.0 * t2) * z1 + (3.0 * t2 - 2.0 * t) * d1
    sec = (1.0 - t) * tab[i, 2] + t * tab[i + 1, 2]
    return val, der / step, sec, True


@numba.njit(inline="always", **_JIT)
def _linear(tab, col, y0, step, n, y):
    """Linear interpolation of column ``col`` (the smoothed second derivative)."""
    u = (y - y0) / step
    if u < 0.0:
        u = 0.0
    if u > n - 1.0:
        u = n - 1.0
    i = int(u)
    if i >= n - 1:
        i = n - 2
    t = u - i
    return (1.0 - t) * tab[i, col] + t * tab[i + 1, col]


# ``ctx``: the pose of one wheel relative to its rail and the table geometry, a tuple of floats
C_R0, C_TAPE, C_CY, C_CZ = 0, 1, 2, 3
C_R21, C_R22, C_R23, C_R31, C_R32, C_R33, C_TPSI = 4, 5, 6, 7, 8, 9, 10
C_WS0, C_WSTEP, C_WN, C_RY0, C_RSTEP, C_RN = 11, 12, 13, 14, 15, 16


@numba.njit(inline="always", **_JIT)
def _make_ctx(winfo, rinfo, cy, cz, phi, psi):
    cphi = math.cos(phi)
    sphi = math.sin(phi)
    cpsi = math.cos(psi)
    spsi = math.sin(psi)
    return (
        winfo[WI_R0], winfo[WI_TAPE], cy, cz,
        cphi * spsi, cphi * cpsi, -sphi, sphi * spsi, sphi * cpsi, cphi, spsi / cpsi,
        winfo[WI_S0], winfo[WI_STEP], winfo[WI_N], rinfo[RI_Y0], rinfo[RI_STEP], rinfo[RI_N],
    )  # fmt: skip


@numba.njit(inline="always", **_JIT)
def _locus_gap(s, F, F1, F2, rtab, ctx):
    """Gap between the contact locus of the wheel circle at ``s`` and the rail, and ``dg/ds``.

    ``F, F1, F2`` are the wheel's radius increase and its first two derivatives at ``s``.
    Returns ``(g, dg, Py, Pz, zr, zr1, zr2, ok)``.
    """
    r = ctx[C_R0] + F
    u = -F1 * ctx[C_TPSI]
    w = math.sqrt(max(1.0 - u * u, 1.0e-12))
    px = r * u
    py = ctx[C_TAPE] + s
    pz = -r * w
    Py = ctx[C_CY] + ctx[C_R21] * px + ctx[C_R22] * py + ctx[C_R23] * pz
    Pz = ctx[C_CZ] + ctx[C_R31] * px + ctx[C_R32] * py + ctx[C_R33] * pz
    zr, zr1, zr2, ok = _hermite(rtab, ctx[C_RY0], ctx[C_RSTEP], int(ctx[C_RN]), Py)
    if not ok:
        return 1.0e9, 0.0, Py, Pz, 0.0, 0.0, 0.0, False
    du = -F2 * ctx[C_TPSI]
    dw = -u * du / w
    dpx = F1 * u + r * du
    dpz = -F1 * w - r * dw
    dPy = ctx[C_R21] * dpx + ctx[C_R22] + ctx[C_R23] * dpz
    dPz = ctx[C_R31] * dpx + ctx[C_R32] + ctx[C_R33] * dpz
    return Pz - zr, dPz - zr1 * dPy, Py, Pz, zr, zr1, zr2, True


@numba.njit(inline="always", **_JIT)
def _node_gap(kk, wtab, rtab, ctx):
    """The gap of :func:`_locus_gap` and its slope ``dg/ds`` at the wheel table's node ``kk``
    (the wheel's values read from the table, the rail interpolated as everywhere else), and
    the locus's lateral position on the rail ``Py``. ``(1e9, 0, Py)`` off the rail."""
    s = ctx[C_WS0] + kk * ctx[C_WSTEP]
    g, dg, Py, Pz, zr, zr1, zr2, ok = _locus_gap(s, wtab[kk, 0], wtab[kk, 1], wtab[kk, 2],
                                                 rtab, ctx)  # fmt: skip
    if not ok:
        return 1.0e9, 0.0, Py
    return g, dg, Py


@numba.njit(inline="always", **_JIT)
def _table_bounds(tab, a, b, use_blocks):
    """Over the profile table rows ``a..b``: the largest slope magnitude, the smallest and
    largest curvature, and the largest curvature change, from the per-block bound columns
    (``use_blocks``: the rate per metre) or from every row (the jump between neighbouring
    rows)."""
    if not use_blocks and tab.shape[1] >= N_TABLE_COLUMNS and b - a < (2 << SPARSE_LEVELS) - 1:
        return _range_bounds(tab, a, b)
    slope = 0.0
    lo = tab[a, 2]
    hi = lo
    rate = 0.0
    if use_blocks:
        for blk in range(a // TABLE_BLOCK, b // TABLE_BLOCK + 1):
            i = blk * TABLE_BLOCK
            slope = max(slope, tab[i, T_SLOPE_MAX])
            lo = min(lo, tab[i, T_CURV_MIN])
            hi = max(hi, tab[i, T_CURV_MAX])
            rate = max(rate, tab[i, T_CURV_RATE])
    else:
        for i in range(a, b + 1):
            slope = max(slope, abs(tab[i, 1]))
            c = tab[i, 2]
            lo = min(lo, c)
            hi = max(hi, c)
            if i < b:
                rate = max(rate, abs(tab[i + 1, 2] - c))
    return slope, lo, hi, rate


@numba.njit(inline="always", **_JIT)
def _sparse_level(m):
    """The largest ``L`` with ``2^L <= m`` (``m >= 1``)."""
    lv = 0
    while (2 << lv) <= m:
        lv += 1
    return lv


@numba.njit(inline="always", **_JIT)
def _range_bounds(tab, a, b):
    """:func:`_table_bounds` over every row ``a..b`` from the sparse-table columns: each bound
    is the better of two runs of ``2^L`` rows that cover ``a..b`` (``b - a < 2^(SPARSE_LEVELS +
    1) - 1``); the same values as the loop over the rows, in a few reads."""
    lv = _sparse_level(b - a + 1)
    c = b - (1 << lv) + 1
    if lv == 0:
        slope = abs(tab[a, 1])
        lo = tab[a, 2]
        hi = lo
    else:
        o = T_SPARSE + 4 * (lv - 1)
        slope = max(tab[a, o], tab[c, o])
        lo = min(tab[a, o + 1], tab[c, o + 1])
        hi = max(tab[a, o + 2], tab[c, o + 2])
    rate = 0.0
    if b > a:  # the jumps a .. b - 1
        lv = _sparse_level(b - a)
        c = b - (1 << lv)
        if lv == 0:
            rate = abs(tab[a + 1, 2] - tab[a, 2])
        else:
            o = T_SPARSE + 4 * (lv - 1) + 3
            rate = max(tab[a, o], tab[c, o])
    return slope, lo, hi, rate


@numba.njit(inline="always", **_JIT)
def _curvature_bounds(ka, kb, py_a, py_b, wtab, rtab, ctx):
    """Bounds ``(up, down)`` of the gap's curvature over the scan cell between the wheel nodes
    ``ka < kb`` whose locus falls on the rail at ``py_a``, ``py_b``: ``-down <= g'' <= up``
    [1/m], both ``>= 0``.

    From the second derivative of ``g = Pz - z_r(Py)`` along the locus of :func:`_locus_gap`,
    ``g'' = -cos(phi) w F'' - z_r'' Py'^2 + E``: the wheel's and the rail's curvature terms
    with their signs, over the range of ``F''`` at the cell's table nodes and of ``z_r''`` at the
    rail nodes under it (each range widened by half its width on both sides: the cubic
    interpolants overshoot where a profile's curvature jumps, e.g. from a line to an arc), and
    ``E`` (roll and yaw couplings, the rail slope times ``Py''``) bounded in magnitude by the
    largest slopes, curvatures and curvature changes. A convex stretch (``down = 0``) cannot
    hide a minimum beside a hump."""
    rstep = ctx[C_RSTEP]
    rn = int(ctx[C_RN])
    ia = max(0, int((min(py_a, py_b) - ctx[C_RY0]) / rstep) - 2)
    ib = min(rn - 1, int((max(py_a, py_b) - ctx[C_RY0]) / rstep) + 3)
    use_blocks = (
        wtab.shape[1] >= N_BLOCK_COLUMNS
        and rtab.shape[1] >= N_BLOCK_COLUMNS
        and kb - ka > 2 * TABLE_BLOCK
    )
    w1, f2_lo, f2_hi, w3 = _table_bounds(wtab, ka, kb, use_blocks)
    r1, z2_lo, z2_hi, z3 = _table_bounds(rtab, ia, ib, use_blocks)
    if use_blocks:
        z3 *= rstep
    else:
        w3 /= ctx[C_WSTEP]
    # the cubic interpolants' curvature overshoots that of the nodes by up to the largest jump
    # between neighbouring nodes
    spread = w3 * ctx[C_WSTEP]
    f2_lo -= spread
    f2_hi += spread
    w2 = max(abs(f2_lo), abs(f2_hi))
    z2_lo -= z3
    z2_hi += z3
    a = abs(ctx[C_TPSI])
    r = ctx[C_R0] + 0.1  # wheel radius bound (flange height well below 0.1 m)
    u = min(w1 * a, 0.5)
    w = math.sqrt(1.0 - u * u)
    du = w2 * a
    d2u = w3 * a
    dw = u * du / w
    d2w = (du * du + u * d2u) / w + u * u * du * du / (w * w * w)
    dpx = w1 * u + r * du
    dpz = w1 + r * dw
    d2px = w2 * u + 2.0 * w1 * du + r * d2u
    d2pz = w2 + 2.0 * w1 * dw + r * d2w
    spread_y = abs(ctx[C_R21]) * dpx + abs(ctx[C_R23]) * dpz
    dpy_hi = abs(ctx[C_R22]) + spread_y
    dpy_lo = max(0.0, abs(ctx[C_R22]) - spread_y)
    d2py = abs(ctx[C_R21]) * d2px + abs(ctx[C_R23]) * d2pz
    # E: Pz'' beyond -cos(phi) w F'', and -z_r' Py''
    e = abs(ctx[C_R31]) * d2px + abs(ctx[C_R33]) * (2.0 * w1 * dw + r * d2w) + r1 * d2py
    c33 = abs(ctx[C_R33])
    wheel_up = -f2_lo * (c33 if f2_lo < 0.0 else c33 * w)
    wheel_down = f2_hi * (c33 if f2_hi > 0.0 else c33 * w)
    rail_up = -z2_lo * (dpy_hi * dpy_hi if z2_lo < 0.0 else dpy_lo * dpy_lo)
    rail_down = z2_hi * (dpy_hi * dpy_hi if z2_hi > 0.0 else dpy_lo * dpy_lo)
    up = 1.25 * max(0.0, wheel_up + rail_up + e) + 1.0e-3
    down = 1.25 * max(0.0, wheel_down + rail_down + e) + 1.0e-3
    return up, down


#: Prominence ``H - g`` [m] over which a penetrating minimum fades in (:func:`candidate_weights`):
#: ``P0_REL`` of its penetration plus ``P0_ABS``.
P0_REL = 0.02
P0_ABS = 2.0e-7
#: A minimum-hump pair whose prominence is below this fraction of ``P0`` may be missed by the
#: scan (:func:`_hidden_minima`); :func:`_fade_in` gives it no weight. Above ``FADE_KNEE`` the
#: weight is the smoothstep of the seed's version (``3 x^2 - 2 x^3``), unchanged.
MISSABLE = 0.025
FADE_KNEE = 0.05
#: Most bisections of one scan cell in the search for hidden minima.
_MAX_BISECTIONS = 40
_STACK = 48


@numba.njit(inline="always", **_JIT)
def _hidden_minima(sa, ga, dga, sb, gb, dgb, py_a, py_b, up0, down0, stack, wtab, rtab, ctx,
                   n_found, cand_s, cand_g):  # fmt: skip
    """Minima hidden in the scan cell ``[sa, sb]`` whose gap slope has the same sign at both
    ends (a minimum and a hump between two nodes), with ``-down <= g'' <= up`` over the cell
    (:func:`_curvature_bounds`). Returns the new number of candidates.

    A slope that keeps its sign at both ends of a part of width ``h`` changes sign twice inside
    only if it can turn and come back: with the slope's envelope (rising at most at ``up``,
    falling at most at ``down``) its excursion beyond zero ``v`` must be positive, and the
    prominence of the pair is at most the area ``v^2 (1/up + 1/down) / 2``. The cell is
    bisected with the exact slope (where the excursion would peak; short parts get their own
    bounds) until in every part either ``v <= 0``, or that prominence is below
    ``MISSABLE * (P0_ABS + P0_REL * depth)``, which :func:`candidate_weights` gives no weight
    (the depth is at least that of the part's end above the minimum: the slope keeps its sign
    between them), or no point can penetrate (``min(g_a, g_b) > up h^2 / 8``), at most
    ``_MAX_BISECTIONS`` evaluations per cell. A minimum that is missed therefore carries no
    force, and the normal force does not jump when the scan grid moves over the profile
    (tests/test_contact_scan_robustness.py)."""
    stack[0] = sa
    stack[1] = ga
    stack[2] = dga
    stack[3] = sb
    stack[4] = gb
    stack[5] = dgb
    top = 1
    evaluations = 0
    while top > 0 and evaluations < _MAX_BISECTIONS:
        top -= 1
        o = 6 * top
        a = stack[o]
        g_a = stack[o + 1]
        d_a = stack[o + 2]
        b = stack[o + 3]
        g_b = stack[o + 4]
        d_b = stack[o + 5]
        h = b - a
        if h < 0.25 * (sb - sa):
            # a short part: its own (tighter) bounds from its nodes; the locus's place on the
            # rail interpolated linearly (within 0.1 h of it; the bounds take 2 rail nodes more)
            ka = int((a - ctx[C_WS0]) / ctx[C_WSTEP])
            kb = int((b - ctx[C_WS0]) / ctx[C_WSTEP]) + 1
            pa = py_a + (a - sa) / (sb - sa) * (py_b - py_a)
            pb = py_a + (b - sa) / (sb - sa) * (py_b - py_a)
            up, down = _curvature_bounds(ka, kb, pa, pb, wtab, rtab, ctx)
        else:
            up = up0
            down = down0
        if min(g_a, g_b) > 0.125 * up * h * h:
            continue
        if d_a < 0.0:  # falling: rises to a minimum (at most at up), falls after the hump
            first = up
            second = down
            g_up = g_a
        else:  # rising: falls to a hump first, rises after the minimum
            first = down
            second = up
            g_up = g_b
        # the slope's envelope: |d_a| - first (s - a) towards zero from a, |d_b| - second (b - s)
        # from b; where they meet (x from a) the excursion beyond zero is largest
        x = (second * h + abs(d_a) - abs(d_b)) / (first + second)
        x = min(max(x, 0.0), h)
        v = first * x - abs(d_a)
        if v <= 0.0:
            continue
        prominence = 0.5 * v * v * (1.0 / first + 1.0 / second)
        if prominence < MISSABLE * (P0_ABS + P0_REL * max(0.0, -g_up)):
            continue
        # split where the slope's excursion would peak: a hidden pair lies around it
        m = a + min(max(x, 0.05 * h), 0.95 * h)
        g_m, d_m, ok = _gap_at(m, wtab, rtab, ctx)
        evaluations += 1
        if not ok:
            continue
        if (d_m < 0.0) != (d_a < 0.0):
            # the slope changed sign twice: a minimum and a hump; the minimum is where the
            # slope turns upwards
            lo = a if d_a < 0.0 else m
            hi = m if d_a < 0.0 else b
            s_ref = _refine_minimum(lo, hi, wtab, rtab, ctx)
            g_ref = _gap_at(s_ref, wtab, rtab, ctx)[0]
            n_found = _add_candidate(s_ref, g_ref, n_found, cand_s, cand_g)
            continue
        if top + 2 > _STACK:
            continue
        o = 6 * top
        stack[o] = a
        stack[o + 1] = g_a
        stack[o + 2] = d_a
        stack[o + 3] = m
        stack[o + 4] = g_m
        stack[o + 5] = d_m
        stack[o + 6] = m
        stack[o + 7] = g_m
        stack[o + 8] = d_m
        stack[o + 9] = b
        stack[o + 10] = g_b
        stack[o + 11] = d_b
        top += 2
    return n_found


@numba.njit(inline="always", **_JIT)
def _add_candidate(s_ref, g_ref, n_found, cand_s, cand_g):
    """Add a refined minimum unless it is already there; keep the deepest ``MAX_POINTS``.
    Returns the new number of candidates."""
    for j in range(n_found):
        if abs(cand_s[j] - s_ref) < 1.0e-7:
            return n_found
    if n_found < MAX_POINTS:
        cand_s[n_found] = s_ref
        cand_g[n_found] = g_ref
        return n_found + 1
    worst = 0
    for j in range(1, MAX_POINTS):
        if cand_g[j] > cand_g[worst]:
            worst = j
    if g_ref < cand_g[worst]:
        cand_s[worst] = s_ref
        cand_g[worst] = g_ref
    return n_found


@numba.njit(inline="always", **_JIT)
def _gap_at(s, wtab, rtab, ctx):
    """``(g, dg/ds, ok)`` at wheel coordinate ``s`` (outside the tables: ``g = 1e9``)."""
    F, F1, F2, okw = _hermite(wtab, ctx[C_WS0], ctx[C_WSTEP], int(ctx[C_WN]), s)
    if not okw:
        return 1.0e9, 0.0, False
    g, dg, Py, Pz, zr, zr1, zr2, ok = _locus_gap(s, F, F1, F2, rtab, ctx)
    return g, dg, ok


_GOLDEN = 0.6180339887498949


@numba.njit(**JIT_NO_REFCOUNT)
def _golden(sa, sb, wtab, rtab, ctx, sign, iterations):
    """Golden-section search for a local minimum of ``sign * g`` in ``[sa, sb]``."""
    c = sb - _GOLDEN * (sb - sa)
    d = sa + _GOLDEN * (sb - sa)
    fc = sign * _gap_at(c, wtab, rtab, ctx)[0]
    fd = sign * _gap_at(d, wtab, rtab, ctx)[0]
    for _ in range(iterations):
        if fc < fd:
            sb = d
            d = c
            fd = fc
            c = sb - _GOLDEN * (sb - sa)
            fc = sign * _gap_at(c, wtab, rtab, ctx)[0]
        else:
            sa = c
            c = d
            fc = fd
            d = sa + _GOLDEN * (sb - sa)
            fd = sign * _gap_at(d, wtab, rtab, ctx)[0]
    return 0.5 * (sa + sb)


@numba.njit(**JIT_NO_REFCOUNT)
def _refine_minimum(sa, sb, wtab, rtab, ctx):
    """Refine a local minimum of the gap bracketed by ``[sa, sb]`` (see :func:`_refine`)."""
    return _refine(sa, sb, wtab, rtab, ctx, 1.0)


@numba.njit(**JIT_NO_REFCOUNT)
def _refine(sa, sb, wtab, rtab, ctx, sign):
    """Refine a local minimum of ``sign * g`` bracketed by ``[sa, sb]`` (``sign = -1``: a
    maximum, the hump between two minima).

    Illinois iteration on ``sign * g'(s) = 0`` (superlinear); where the slope does not change
    sign over the bracket (two shallow minima in one scan cell, or a minimum at the bracket's
    end) a golden-section search instead, which always converges to a local minimum.
    """
    ga, fa, oka = _gap_at(sa, wtab, rtab, ctx)
    gb, fb, okb = _gap_at(sb, wtab, rtab, ctx)
    fa *= sign
    fb *= sign
    if not (oka and okb) or fa >= 0.0 or fb <= 0.0:
        return _golden(sa, sb, wtab, rtab, ctx, sign, 48)
    side = 0
    s = 0.5 * (sa + sb)
    for _ in range(60):
        s = (sa * fb - sb * fa) / (fb - fa)
        g, f, ok = _gap_at(s, wtab, rtab, ctx)
        f *= sign
        if not ok:
            return _golden(sa, sb, wtab, rtab, ctx, sign, 48)
        if f > 0.0:
            sb = s
            fb = f
            if side == 1:
                fa *= 0.5
            side = 1
        else:
            sa = s
            fa = f
            if side == -1:
                fb *= 0.5
            side = -1
        if sb - sa < 1.0e-11 or abs(f) < 1.0e-13:
            break
    return s


def _scan_cell_py(ka, ga, dga, pya, kb, gb, dgb, pyb, stack, wtab, rtab, ctx, n_found, cand_s,
               cand_g):  # fmt: skip
    """The minima between the wheel nodes ``ka < kb`` (both on the rail) from the gap, its
    exact slope and the locus's place on the rail at both: the slope turns upwards (the
    minimum, refined), or it keeps its sign and the cell touches the overlap (a gap below
    0.1 mm at an end; :func:`_hidden_minima`). Returns the new number of candidates."""
    s_a = ctx[C_WS0] + ka * ctx[C_WSTEP]
    s_b = ctx[C_WS0] + kb * ctx[C_WSTEP]
    if dga < 0.0 <= dgb:
        s_ref = _refine_minimum(s_a, s_b, wtab, rtab, ctx)
        g_ref = _gap_at(s_ref, wtab, rtab, ctx)[0]
        return _add_candidate(s_ref, g_ref, n_found, cand_s, cand_g)
    if min(ga, gb) <= 1.0e-4 and (dga < 0.0) == (dgb < 0.0):
        up, down = _curvature_bounds(ka, kb, pya, pyb, wtab, rtab, ctx)
        return _hidden_minima(s_a, ga, dga, s_b, gb, dgb, pya, pyb, up, down, stack, wtab, rtab,
                              ctx, n_found, cand_s, cand_g)  # fmt: skip
    return n_found


#: inlined in the scan's loop; called (not inlined) for the parts of the cells at the rail's edges
_scan_cell = numba.njit(inline="always", **_JIT)(_scan_cell_py)
_scan_edge_cell = numba.njit(**JIT_NO_REFCOUNT)(_scan_cell_py)


@numba.njit(**_JIT)
def find_contact_candidates(wtab, winfo, rtab, rinfo, cy, cz, phi, psi, scan_step, cand_s,
                            cand_g, cand_h):  # fmt: skip
    """Local minima of the gap between a left-type wheel and its rail.

    Args:
        wtab, winfo: wheel table ``[F, F', F'', F''_smooth]`` over ``s`` and its info row
            ``(s0, step, n, r0, tape)``.
        rtab, rinfo: rail table ``[z, z', z'', z''_smooth]`` over track ``y``, ``(y0, step, n)``.
        cy, cz: wheelset centre relative to the rail's nominal position [m].
        phi, psi: roll and yaw [rad] (left-type frame).
        scan_step: coarse scan step [m].
        cand_s, cand_g: output arrays (length ``MAX_POINTS``), refined ``s`` and gap, sorted by
            increasing ``s``; unused entries hold NaN.
        cand_h: output (length ``MAX_POINTS``): ``cand_h[k]`` is the highest gap between
            candidates ``k`` and ``k + 1`` (the hump separating them), computed only where both
            overlap the rail (NaN otherwise); a lower bound of at least ``HUMP_SEPARATE_M``
            where a scan node between them lies that high.

    Returns:
        the number of candidates found.
    """
    work = np.empty(candidates_work_size(winfo))
    return _candidates(wtab, winfo, rtab, rinfo, cy, cz, phi, psi, scan_step, cand_s, cand_g,
                       cand_h, work)  # fmt: skip


@numba.njit(inline="always", **_JIT)
def candidates_work_size(winfo):
    """Entries of :func:`_candidates`' work array for a wheel table of ``winfo[WI_N]`` rows:
    the gap slopes at the scan's nodes (at most one per table row: the nodes are rows
    ``k_lo + j stride`` with ``0 <= k_lo``, ``k_hi <= n - 1``, ``stride >= 1``) and the stack
    of :func:`_hidden_minima`."""
    return int(winfo[WI_N]) + 2 + 6 * _STACK


@numba.njit(**JIT_NO_REFCOUNT)
def _candidates(wtab, winfo, rtab, rinfo, cy, cz, phi, psi, scan_step, cand_s, cand_g, cand_h,
                work):  # fmt: skip
    """:func:`find_contact_candidates` with its work array from the caller (at least
    :func:`candidates_work_size` entries), compiled without reference counting."""
    ctx = _make_ctx(winfo, rinfo, cy, cz, phi, psi)
    return _candidates_at(wtab, rtab, ctx, scan_step, cand_s, cand_g, cand_h, work)


#: A hump this far above the rail [m] separates two patches whatever its exact height: the
#: weights of minima sharing an overlap (:func:`candidate_weights`) and the patch sums
#: (:func:`patch_centre`) look at humps below the overlap (``< 0``) only. Where a scan node
#: between two minima is this high, ``cand_h`` is that node's gap (a lower bound of the hump)
#: instead of the hump refined to machine precision: the forces are the same to the last bit,
#: and a wheel on two rails across a flangeway (a hump of centimetres) skips a refinement of
#: some 14 gap evaluations (issue 29's cost per rail; docs/performance.md).
HUMP_SEPARATE_M = 1.0e-3


@numba.njit(**JIT_NO_REFCOUNT)
def _candidates_at(wtab, rtab, ctx, scan_step, cand_s, cand_g, cand_h, work):
    """:func:`_candidates` for the wheelset pose of ``ctx`` (:func:`_make_ctx`), which
    :func:`wheel_contact` builds once for the search and the contact points."""
    cy = ctx[C_CY]
    ws0 = ctx[C_WS0]
    wstep = ctx[C_WSTEP]
    wn = int(ctx[C_WN])
    r0 = ctx[C_R0]
    tape = ctx[C_TAPE]
    ry0 = ctx[C_RY0]
    rstep = ctx[C_RSTEP]
    rn = int(ctx[C_RN])
    sphi = -ctx[C_R23]
    r22 = ctx[C_R22]
    for k in range(MAX_POINTS):
        cand_s[k] = np.nan
        cand_g[k] = np.nan
        cand_h[k] = np.nan

    # Wheel nodes whose locus falls on the rail table: Py ~ cy + r22 (tape + s) + sphi r0.
    stride = max(1, int(round(scan_step / wstep)))
    y_lo = ry0
    y_hi = ry0 + (rn - 1) * rstep
    margin = 0.004 + abs(ctx[C_TPSI]) * r0 * 3.0
    s_lo = (y_lo - cy - sphi * r0) / r22 - tape - margin
    s_hi = (y_hi - cy - sphi * r0) / r22 - tape + margin
    k_lo = max(0, int((s_lo - ws0) / wstep))
    k_hi = min(wn - 1, int((s_hi - ws0) / wstep) + 1)

    n_found = 0
    if k_hi <= k_lo or not (r22 > 0.1):
        return 0  # the wheel is nowhere above its rail (or the wheelset is upside down)
    # The gap and its exact slope at the scan nodes (the slopes kept for the humps), then every
    # local minimum, cell by cell:
    # - the slope turns upwards between two nodes: the minimum, refined;
    # - the slope keeps its sign but the cell touches the overlap (a gap below 0.1 mm at an
    #   end): a minimum and a hump may hide inside (the S1002 flange beside the flat hump at
    #   the line-to-arc joint of its flank, on a 60E1 gauge corner): _hidden_minima;
    # - the cell where the locus comes onto (leaves) the rail: a minimum between the rail's
    #   edge and the first (last) node when the slope there rises (falls).
    n_nodes = (k_hi - k_lo) // stride + 1
    scan_dg = work[0:n_nodes]  # the slopes, kept for the humps below
    stack = work[n_nodes:]
    g_prev = 1.0e9
    dg_prev = 0.0
    py_prev = 0.0
    k_prev = -1
    for j in range(n_nodes + 1):
        if j < n_nodes:
            kk = k_lo + j * stride
            g, dg, py = _node_gap(kk, wtab, rtab, ctx)
            scan_dg[j] = dg
        else:  # the sentinel that closes a minimum at the edge
            kk = min(k_prev + stride, wn - 1)
            g = 1.0e9
            dg = 0.0
            py = 0.0
        if k_prev >= 0 and kk > k_prev:
            on_a = g_prev < 1.0e8
            on_b = g < 1.0e8
            if on_a and on_b:
                n_found = _scan_cell(k_prev, g_prev, dg_prev, py_prev, kk, g, dg, py, stack,
                                     wtab, rtab, ctx, n_found, cand_s, cand_g)  # fmt: skip
            elif on_a or on_b:
                # the cell where the locus comes onto (leaves) the rail: near the overlap, the
                # last table node off the rail is found and the part on it scanned like a
                # cell; a minimum between the rail's edge and the first (last) node on it when
                # the slope there rises (falls)
                k_on = kk if on_b else k_prev
                g_on = g if on_b else g_prev
                dg_on = dg if on_b else dg_prev
                py_on = py if on_b else py_prev
                k_off = k_prev if on_b else kk
                if g_on <= 1.0e-4:
                    while abs(k_on - k_off) > 1:
                        k_mid = (k_on + k_off) // 2
                        g_mid, dg_mid, py_mid = _node_gap(k_mid, wtab, rtab, ctx)
                        if g_mid < 1.0e8:
                            k_on_new = k_mid
                            if on_b:
                                n_found = _scan_edge_cell(k_mid, g_mid, dg_mid, py_mid, k_on, g_on,
                                                     dg_on, py_on, stack, wtab, rtab, ctx,
                                                     n_found, cand_s, cand_g)  # fmt: skip
                            else:
                                n_found = _scan_edge_cell(k_on, g_on, dg_on, py_on, k_mid, g_mid,
                                                     dg_mid, py_mid, stack, wtab, rtab, ctx,
                                                     n_found, cand_s, cand_g)  # fmt: skip
                            k_on = k_on_new
                            g_on = g_mid
                            dg_on = dg_mid
                            py_on = py_mid
                        else:
                            k_off = k_mid
                if (on_b and dg_on > 0.0) or (on_a and dg_on < 0.0):
                    s_a = ws0 + min(k_on, k_off) * wstep
                    s_b = ws0 + max(k_on, k_off) * wstep
                    s_ref = _refine_minimum(s_a, s_b, wtab, rtab, ctx)
                    g_ref, dg_ref, ok_ref = _gap_at(s_ref, wtab, rtab, ctx)
                    inside = s_ref - s_a > 1.0e-9 and s_b - s_ref > 1.0e-9
                    if ok_ref and inside and g_ref < g_on:
                        n_found = _add_candidate(s_ref, g_ref, n_found, cand_s, cand_g)
        g_prev = g
        dg_prev = dg
        py_prev = py
        k_prev = kk
    # sort by s (insertion sort, at most MAX_POINTS entries)
    for i in range(1, n_found):
        j = i
        while j > 0 and cand_s[j - 1] > cand_s[j]:
            ts = cand_s[j]
            tg = cand_g[j]
            cand_s[j] = cand_s[j - 1]
            cand_g[j] = cand_g[j - 1]
            cand_s[j - 1] = ts
            cand_g[j - 1] = tg
            j -= 1
    # humps between neighbouring overlapping minima (only those matter, candidate_weights),
    # refined to machine precision with the exact gap: approximate humps (the highest scan
    # node, a short search) made the weights, and the normal force, jump by tens of newtons
    # where the highest node changed. The hump lies where the slope turns downwards: between
    # the last scan node after the first minimum whose slope still rises and the next one.
    for i in range(n_found - 1):
        if cand_g[i] >= 0.0 or cand_g[i + 1] >= 0.0:
            continue
        sa = cand_s[i]
        sb = cand_s[i + 1]
        lo = sa + 1.0e-9
        hi = sb - 1.0e-9
        if hi > lo:
            j = max(0, int((sa - ws0 - k_lo * wstep) / (stride * wstep)))
            while j < n_nodes:
                sk = ws0 + (k_lo + j * stride) * wstep
                if sk >= hi:
                    break
                if sk > lo:
                    if scan_dg[j] < 0.0:
                        hi = sk
                        break
                    lo = sk
                j += 1
            g_lo = _gap_at(lo, wtab, rtab, ctx)[0]
            if g_lo >= HUMP_SEPARATE_M:
                # two separate patches (two rails across a flangeway, tread and flange apart):
                # a lower bound of the hump is all its users need (HUMP_SEPARATE_M)
                cand_h[i] = g_lo
            else:
                s_max = _refine(lo, hi, wtab, rtab, ctx, -1.0)
                cand_h[i] = max(_gap_at(s_max, wtab, rtab, ctx)[0], cand_g[i], cand_g[i + 1])
        else:
            cand_h[i] = max(cand_g[i], cand_g[i + 1])
    return n_found


@numba.njit(inline="always", **_JIT)
def _smoothstep(x):
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x * x * (3.0 - 2.0 * x)


@numba.njit(inline="always", **_JIT)
def _fade_in(x):
    """Weight of a minimum of relative prominence ``x = (H - g) / P0``: the smoothstep of ``x``
    above ``FADE_KNEE``; below it the smoothstep falls to zero at ``MISSABLE`` (continuous at
    the knee), so that a minimum the scan may miss (``_hidden_minima``) carries no force."""
    if x >= FADE_KNEE:
        return _smoothstep(x)
    return _smoothstep(FADE_KNEE) * _smoothstep((x - MISSABLE) / (FADE_KNEE - MISSABLE))


@numba.njit(inline="always", **_JIT)
def _existence(hump, g):
    """How far a penetrating minimum of gap ``g`` [m] exists beside the hump ``hump`` [m]: the
    fade-in (:func:`_fade_in`) of its prominence ``hump - g`` over ``P0`` = 2 % of its
    penetration plus 0.2 um; 0 where it is being born from, or dies into, the hump."""
    return _fade_in((hump - g) / (P0_REL * (-g) + P0_ABS))


@numba.njit(inline="always", **_JIT)
def _pair_factors(ga, gb, hump):
    """The weights ``(f_a, f_b)`` of two penetrating minima of gaps ``ga, gb`` [m] that share
    one overlap region with the hump ``hump < 0`` [m] between them (:func:`candidate_weights`).

    The deeper one (the senior) keeps the weight 1; the shallower one (the junior) has its
    *retention* ``r = sep * c``: ``sep`` the smoothstep of its relative prominence
    ``(H - g) / (-g)`` (1 while the hump is at or above zero: two overlap regions; 0 when the
    hump sinks to it and it merges; the seed's measure: a prominence measured against the
    patch's depth ``PATCH_EPSILON (-g)`` instead made the weight 1.8 times as sensitive to the
    hump, and the tests on S&C sections moved by 0.2 %) and ``c`` its existence
    (:func:`_existence`).
    Which one is the junior is blended over a depth band ``tau``: 10 % of the deeper
    penetration, but at most the larger prominence, so that a minimum that dies (its gap meets
    the hump) is the junior outright and its weight reaches 0. Where both prominences are tiny
    (two nearly equal minima in a flat valley bottom, the EU07's flange root on elastic track)
    both weights are about 1/2: one patch, counted once, not both faded out (the collapse of
    the seed version, which also faded the senior: 159 to 10 kN over 2 um, docs/validation.md).
    """
    sa = _smoothstep((hump - ga) / (-ga))
    sb = _smoothstep((hump - gb) / (-gb))
    pa = hump - ga
    pb = hump - gb
    tau = min(0.1 * (-min(ga, gb)), max(pa, pb))
    theta_a = 0.5  # 1: a is the junior
    if tau > 0.0:
        theta_a = _smoothstep(0.5 + (ga - gb) / (2.0 * tau))
    fa = 1.0 - theta_a * (1.0 - sa * _existence(hump, ga))
    fb = 1.0 - (1.0 - theta_a) * (1.0 - sb * _existence(hump, gb))
    return fa, fb


@numba.njit(**_JIT)
def candidate_weights(n, cand_g, cand_h, weights):
    """Weights of neighbouring minima that share one overlap region (see ``wheel_contact``).

    Two penetrating minima ``a, b`` with the hump ``H`` between them: if the hump rises above
    zero (``H >= 0``) their overlap regions are separate and both count fully. Below zero they
    are one connected overlap, in which the shallower minimum would count the overlap twice:
    :func:`_pair_factors` (the deeper keeps 1, the shallower its retention, which falls to 0
    as it merges or dies, and rises to 1 while the hump stands above its patch's threshold).
    Three penetrating minima (``MAX_POINTS``): each outer one has its factor against the middle
    one and, as far as the middle one does not exist (:func:`_existence`, against the lower of
    its humps), its factor against the other outer one across the higher hump; the middle one
    has the product of its two. So a minimum born between two others (the worn flange root of
    issue 30) neither takes load from them at birth nor separates them (before, each outer one
    jumped from sharing with the other to full weight: +163 kN over 1 um), and a hump that rises
    above zero gives the factor 1 (the pairs' formula is the limit). The weights are continuous
    functions of the gaps and the humps: the normal force does not jump when minima appear,
    merge, separate or change order inside one overlap region (tests/test_contact_valley.py).
    """
    for k in range(n):
        weights[k] = 1.0
    three = n == 3 and cand_g[0] < 0.0 and cand_g[1] < 0.0 and cand_g[2] < 0.0
    if three:
        c1 = _existence(min(cand_h[0], cand_h[1]), cand_g[1])
        across = max(cand_h[0], cand_h[1])
        f0, f2 = _pair_factors(cand_g[0], cand_g[2], across)
        a0, a1 = _pair_factors(cand_g[0], cand_g[1], cand_h[0])
        b1, b2 = _pair_factors(cand_g[1], cand_g[2], cand_h[1])
        weights[0] = a0 * (1.0 - (1.0 - c1) * (1.0 - f0))
        weights[1] = a1 * b1
        weights[2] = b2 * (1.0 - (1.0 - c1) * (1.0 - f2))
        return
    for i in range(n - 1):
        ga = cand_g[i]
        gb = cand_g[i + 1]
        hump = cand_h[i]
        if not (ga < 0.0 and gb < 0.0 and hump < 0.0):
            continue
        fa, fb = _pair_factors(ga, gb, hump)
        weights[i] *= fa
        weights[i + 1] *= fb


#: Virtual penetration ratio of the patch (Kik and Piotrowski 2008, VSD 46, 27-48; the value of
#: :mod:`railexu.contact.kik_piotrowski`): the patch of a minimum of depth ``-g_k`` is where the
#: gap is below ``(1 - PATCH_EPSILON) g_k``, and its line load is taken proportional to the
#: virtual penetration ``(1 - PATCH_EPSILON) g_k - g(s)`` there (for a Hertzian circle with
#: ``eps = 0.5`` exactly Hertz's line load ``1 - (y / b)^2`` over the true width).
PATCH_EPSILON = 0.55
#: Steps of the sum over the patch (:func:`patch_centre`): this share of the patch's half-width
#: estimated from the curvatures at the minimum, within these bounds [m]; most steps each way.
#: A fifth (integrated on the two lattices of powers of two times the smallest step that bracket
#: it, patch_centre): the integral's error is of order step^2; a tenth cost 25 % more on the
#: seed run.
PATCH_STEP_MIN = 5.0e-5
PATCH_STEP_MAX = 8.0e-4
PATCH_STEP_SHARE = 0.2
PATCH_MAX_STEPS = 400
#: Bisections for the table's edge inside a patch (:func:`_patch_moments`): 2^-30 of a lattice
#: step (below 1 nm).
EDGE_BISECTIONS = 30
#: Golden-section steps for the hump between two minima of a patch: 0.618^24 = 1e-5 of their
#: distance (0.1 um over 10 mm), far below the +-step over which the hump's side is switched.
HUMP_ITERATIONS = 24

#: How far the minimum's lateral curvature may stray from the one its patch's load width implies
#: before that width bounds it (:func:`patch_curvature`): a factor 1.5 in curvature, 22 % in
#: width (railexu's assumption: the Hertzian patches of the contact tests stay within it; the
#: conformal flange root of issue 28 is a factor 3 to 50 outside it).
PATCH_CURVATURE_RATIO = 1.5


@numba.njit(inline="always", **_JIT)
def patch_curvature(b_min, depth, cos_gamma, variance, step):
    """Half the relative lateral curvature ``B`` [1/m] used for Hertz's stiffness of a patch.

    ``b_min``: the one at the gap's minimum (the profiles' curvature averaged over the contact
    width); ``depth``: the minimum's vertical overlap ``-g`` [m]; ``cos_gamma``: the cosine of
    the contact angle at the patch's load centroid; ``variance``: the load's variance on the
    wheel's lateral coordinate [m^2] and ``step`` [m] the lattice it was integrated on
    (:func:`patch_centre`).

    For a parabolic gap (Hertz) with the Kik-Piotrowski line load the variance is
    ``eps depth cos^3(gamma) / (5 B)`` (the gap ``-depth + B s^2 / cos^3(gamma)`` in the
    vertical, over the horizontal ``s``), so the load's width implies
    ``B_w = eps depth cos^3(gamma) / (5 variance)``. Hertz's curvature at the minimum
    describes the patch only while the gap is near that parabola; where several minima share
    one valley, or a minimum sits at the end of a conformal one, it does not: a minimum born at
    an inflection has ``B = 0`` (Hertz's ellipse infinitely long, its stiffness unbounded), and
    at the EU07's flange root (issue 28) the minimum's ``B`` was 0.5 and 70 1/m on either side of
    a valley whose load width implies 1.5 1/m. So ``b_min`` is used as it is within a factor
    ``PATCH_CURVATURE_RATIO`` of ``B_w`` and clamped to that band outside it: exactly Hertz for
    a Hertzian patch, continuous in the pose (the clamp of two continuous functions), and a
    stiffness that follows the patch's real width where Hertz has no answer.
    """
    # the width is resolved by the lattice of ``step`` [m] (patch_centre) only where the load's
    # standard deviation spans two steps or more (a Hertzian patch: 2.2 steps); below one step
    # the minimum's curvature is kept, between the two the bound fades in
    trust = _smoothstep(math.sqrt(max(variance, 0.0)) / step - 1.0)
    if not (trust > 0.0):
        return b_min
    b_width = PATCH_EPSILON * depth * cos_gamma * cos_gamma * cos_gamma / (5.0 * variance)
    lo = b_width / PATCH_CURVATURE_RATIO
    hi = b_width * PATCH_CURVATURE_RATIO
    bounded = min(max(b_min, lo), hi)
    return b_min + trust * (bounded - b_min)


@numba.njit(inline="always", **_JIT)
def _neighbour_share(hump, g_nb, threshold):
    """How much of a neighbouring minimum's side a patch leaves to it: 1 while the hump between
    them is above the patch's threshold (two patches), falling with the smoothstep to 0 as the
    neighbour's prominence ``hump - g_nb`` vanishes (the neighbour dies into this patch)."""
    if hump >= threshold or not (threshold > g_nb):
        return 1.0
    return _smoothstep((hump - g_nb) / (threshold - g_nb))


@numba.njit(**JIT_NO_REFCOUNT)
def _patch_moments(k, n, cand_s, cand_g, cand_h, wtab, rtab, ctx, step):
    """The moments ``int w, int w s, int w s^2`` of the line load of the patch of minimum ``k``
    on the lattice ``s = i step`` (:func:`patch_centre`)."""
    s_k = cand_s[k]
    g_k = cand_g[k]
    if not (g_k < 0.0):
        return 0.0, 0.0, 0.0
    threshold = (1.0 - PATCH_EPSILON) * g_k
    m0 = 0.0
    m1 = 0.0
    m2 = 0.0
    i0 = math.floor(s_k / step + 0.5)  # the lattice point nearest the minimum
    s_start = i0 * step
    f_start = threshold - _gap_at(s_start, wtab, rtab, ctx)[0]
    for direction in (-1, 1):
        factor = 1.0  # weight of the part of the valley being summed
        j = k  # the last minimum passed
        hump_s = 0.0
        share = 1.0
        crossing = False
        nb = j + direction
        if 0 <= nb < n:
            hump = cand_h[min(j, nb)]
            if not math.isnan(hump):  # both overlap: the hump bounds this side of the patch
                share = _neighbour_share(hump, cand_g[nb], threshold)
                lo = min(cand_s[j], cand_s[nb])
                hi = max(cand_s[j], cand_s[nb])
                hump_s = _golden(lo, hi, wtab, rtab, ctx, -1.0, HUMP_ITERATIONS)
                crossing = True
        s_prev = s_start
        f_prev = f_start
        for i in range(1, PATCH_MAX_STEPS + 1):
            s = (i0 + direction * i) * step
            g, _dg, on_table = _gap_at(s, wtab, rtab, ctx)
            if not on_table:
                # the locus leaves the wheel's or the rail's table inside the patch: the load ends
                # at the table's edge (found by bisection), not at the lattice node beyond it,
                # which would make the patch jump by a cell as the edge passes a node
                s_in = s_prev
                s_out = s
                for _ in range(EDGE_BISECTIONS):
                    s_mid = 0.5 * (s_in + s_out)
                    if _gap_at(s_mid, wtab, rtab, ctx)[2]:
                        s_in = s_mid
                    else:
                        s_out = s_mid
                f_edge = factor * (threshold - _gap_at(s_in, wtab, rtab, ctx)[0])
                a0, a1, a2 = _cell_moments(s_prev, f_prev, s_in, f_edge)
                m0 += a0
                m1 += a1
                m2 += a2
                break
            w = threshold - g
            f = factor * w
            stop = False
            if not crossing or (share >= 1.0 and direction * (s - hump_s) < 0.0):
                stop = w <= 0.0
            if crossing and not stop and direction * (s - hump_s) >= 0.0:
                # the cell holds the hump: the part beyond it counts with 1 - share, split
                # exactly at the hump (share is 1 while the hump stands above the threshold: a
                # hump poking above it between two lattice nodes, where both nodes are inside
                # the load, must still end the patch; missing it counted the neighbour's whole
                # side: a 15 kN jump of the EU07's tread patch in R 600 m)
                f_hump = factor * (threshold - _gap_at(hump_s, wtab, rtab, ctx)[0])
                a0, a1, a2 = _cell_moments(s_prev, f_prev, hump_s, f_hump)
                m0 += a0
                m1 += a1
                m2 += a2
                factor *= 1.0 - share
                s_prev = hump_s
                f_prev = (1.0 - share) * f_hump
                f = factor * w
                crossing = False
                j = j + direction
                nb = j + direction
                stop = factor <= 0.0
                if not stop and 0 <= nb < n:
                    hump = cand_h[min(j, nb)]
                    if not math.isnan(hump):
                        share = _neighbour_share(hump, cand_g[nb], threshold)
                        lo = min(cand_s[j], cand_s[nb])
                        hi = max(cand_s[j], cand_s[nb])
                        hump_s = _golden(lo, hi, wtab, rtab, ctx, -1.0, HUMP_ITERATIONS)
                        crossing = True
            a0, a1, a2 = _cell_moments(s_prev, f_prev, s, f)
            m0 += a0
            m1 += a1
            m2 += a2
            if stop:
                break
            s_prev = s
            f_prev = f
    return m0, m1, m2


@numba.njit(**JIT_NO_REFCOUNT)
def patch_centre(k, n, cand_s, cand_g, cand_h, wtab, rtab, ctx, step):
    """Centroid ``s`` [m] of the line load of the patch of minimum ``k`` on the wheel's
    coordinate, and the load's variance about it [m^2] (``step``: the grid [m]).

    A Hertz point carries the whole force of its patch at the deepest point of the gap. Where
    the gap is nearly flat over millimetres (the S1002 flange root on a 60E1 gauge corner with
    yaw: one conformal patch from about 0.4 to 1.22 rad, issue 28) the deepest point jumps
    between the ends of that valley with micrometres of lateral motion, and with it the force's
    direction: the vertical force fell by 118 kN over 20 um and the coach's wheelsets chattered.
    The point where the force acts is therefore the centroid of the patch's line load, the
    virtual penetration ``w(s) = (1 - PATCH_EPSILON) g_k - g(s) > 0``, integrated exactly as the
    piecewise-linear function through its values on the lattice ``s = i step`` of the wheel's
    coordinate (:func:`_cell_moments`: the load grows continuously from the patch's edges, which
    move fast in a flat valley; summing the values alone made the centroid wiggle by 0.14 mm as
    lattice points entered). The lattice is not anchored at the minimum: in a flat valley bottom
    the minimum can jump between two places of nearly equal depth (0.7 mm for a 17 nm change of
    depth at the EU07's flange root, issue 28), and a grid anchored at it moved the centroid by
    0.12 mm and the wheel's vertical force by 1.7 kN within 0.04 um. The lattice's spacing is a
    power of two times ``PATCH_STEP_MIN``: the two lattices that bracket ``step`` are integrated
    and their moments blended by where ``step`` lies between them in ``log2``, so that the
    lattice does not move with the patch's estimated width (a lattice ``i step`` with a
    continuously varying ``step`` moves its points by ``i`` times the change: the centroid
    wiggled by 0.1 mm), nor jumps where it passes a power of two (17.6 um in 1/8 um at the
    coach's flange root). On a circular rail head the normal at the centroid is the mean normal
    of the line load. A neighbouring minimum's side beyond the hump between them counts with the
    weight ``1 - share`` (:func:`_neighbour_share`: 0 while the two patches are separate, 1 when
    the neighbour dies into this patch), from the hump on (the lattice cell that holds it split
    there). For a Hertzian patch (gap symmetric about the minimum) the centroid is the minimum
    within the quadrature's error (of order ``step^2`` relative, ``step`` a fifth of the patch's
    half-width); a patch with no load between lattice points is its minimum, with the variance
    0. For a parabolic gap ``g = -d + B s^2`` the variance is ``eps d / (5 B)`` (the line load
    ``eps d - B s^2``), from which the caller bounds the patch's curvature
    (:func:`patch_curvature`).
    """
    s_k = cand_s[k]
    level = math.log2(step / PATCH_STEP_MIN)
    low = math.floor(level)
    t = level - low
    h = PATCH_STEP_MIN * 2.0**low
    m0, m1, m2 = _patch_moments(k, n, cand_s, cand_g, cand_h, wtab, rtab, ctx, h)
    if t > 0.0:
        b0, b1, b2 = _patch_moments(k, n, cand_s, cand_g, cand_h, wtab, rtab, ctx, 2.0 * h)
        m0 = (1.0 - t) * m0 + t * b0
        m1 = (1.0 - t) * m1 + t * b1
        m2 = (1.0 - t) * m2 + t * b2
    if not (m0 > 0.0):
        return s_k, 0.0
    centre = m1 / m0
    return centre, max(m2 / m0 - centre * centre, 0.0)


@numba.njit(inline="always", **_JIT)
def _cell_moments(a, fa, b, fb):
    """The moments ``int f, int f s, int f s^2`` over one lattice cell of the positive part of
    the linear function from ``f(a) = fa`` to ``f(b) = fb`` (exact; the cell is cut where
    ``f`` crosses zero, so that the load grows continuously from the patch's edge)."""
    if b < a:
        a, fa, b, fb = b, fb, a, fa
    if fa <= 0.0 and fb <= 0.0:
        return 0.0, 0.0, 0.0
    if fa < 0.0:
        a = a + (b - a) * fa / (fa - fb)
        fa = 0.0
    elif fb < 0.0:
        b = a + (b - a) * fa / (fa - fb)
        fb = 0.0
    h = b - a
    m0 = 0.5 * h * (fa + fb)
    m1 = h / 6.0 * (fa * (2.0 * a + b) + fb * (a + 2.0 * b))
    m2 = fa * (3.0 * a * a + 2.0 * a * b + b * b) + fb * (a * a + 2.0 * a * b + 3.0 * b * b)
    m2 *= h / 12.0
    return m0, m1, m2


@numba.njit(**JIT_NO_REFCOUNT)
def wheel_contact(wtab, winfo, rtab, rinfo, htab, ktab, params, mirror, cx, cy, cz, phi, psi,
                  vx, vy, vz, wx, wy, wz, rail_dy, rail_dz, rail_vy, rail_vz, points, side,
                  force, scratch):  # fmt: skip
    """Contact forces of one wheel on its rail, all contact points.

    The wheelset state is given in the real track frame; for the right wheel (``mirror = -1``)
    it is mirrored into the left-type frame, evaluated, and the results mirrored back.

    Args:
        wtab, winfo, rtab, rinfo: wheel and rail tables (see :func:`find_contact_candidates`).
        htab: Hertz table (:func:`railexu.contact.hertz.hertz_table`).
        ktab: Kalker table for the Poisson ratio
            (:func:`railexu.contact.kalker.kalker_table_for_poisson`).
        params: parameter vector (``P_*`` indices).
        mirror: +1.0 for the left wheel, -1.0 for the right wheel.
        cx, cy, cz: wheelset centre, track frame [m].
        phi, psi: roll and yaw [rad]; vx, vy, vz: centre velocity [m/s];
        wx, wy, wz: angular velocity, track frame [rad/s].
        rail_dy, rail_dz, rail_vy, rail_vz: lateral/vertical offset of this rail from its nominal
            place (irregularity) and its velocity, track frame [m], [m/s].
        points: output ``(2, MAX_POINTS, N_POINT_FIELDS)``; row ``side`` is written.
        side: 0 left, 1 right.
        force: output, 6 entries; the wheel's force [N] and torque about the wheelset centre
            [N m] (track frame) are **added** to it.
        scratch: work array of at least ``4 * MAX_POINTS + candidates_work_size(winfo)``
            entries.

    Returns:
        the number of contact points carrying load.
    """
    m = mirror
    # Left-type frame: mirror y (and the pseudo-vector components x, z of omega).
    lcy = m * cy - m * rail_dy
    lcz = cz - rail_dz
    lphi = m * phi
    lpsi = m * psi
    lvy = m * vy
    lwx = m * wx
    lwz = m * wz
    lrvy = m * rail_vy
    cand_s = scratch[0:MAX_POINTS]
    cand_g = scratch[MAX_POINTS : 2 * MAX_POINTS]
    cand_h = scratch[2 * MAX_POINTS : 3 * MAX_POINTS]
    weights = scratch[3 * MAX_POINTS : 4 * MAX_POINTS]
    ctx = _make_ctx(winfo, rinfo, lcy, lcz, lphi, lpsi)
    n_cand = _candidates_at(wtab, rtab, ctx, params[P_SCAN], cand_s, cand_g, cand_h,
                            scratch[4 * MAX_POINTS :])  # fmt: skip
    candidate_weights(n_cand, cand_g, cand_h, weights)
    for k in range(MAX_POINTS):
        for f in range(N_POINT_FIELDS):
            points[side, k, f] = 0.0
    ws0 = winfo[WI_S0]
    wstep = winfo[WI_STEP]
    wn = int(winfo[WI_N])
    r0 = winfo[WI_R0]
    tape = winfo[WI_TAPE]
    ry0 = rinfo[RI_Y0]
    rstep = rinfo[RI_STEP]
    rn = int(rinfo[RI_N])
    tpsi = ctx[C_TPSI]
    cpsi = math.cos(lpsi)
    spsi = math.sin(lpsi)
    r11 = cpsi
    r12 = -spsi
    r21 = ctx[C_R21]
    r22 = ctx[C_R22]
    r23 = ctx[C_R23]
    r31 = ctx[C_R31]
    r32 = ctx[C_R32]
    r33 = ctx[C_R33]
    e_star = params[P_ESTAR]
    shear = params[P_SHEAR]
    speed = params[P_SPEED]
    n_loaded = 0
    for k in range(n_cand):
        # depth and Hertz curvatures at the minimum of the gap (the first point of contact)
        s_min = cand_s[k]
        F, F1, F2, okw = _hermite(wtab, ws0, wstep, wn, s_min)
        g, dg, Py, Pz, zr, zr1, zr2, ok = _locus_gap(s_min, F, F1, F2, rtab, ctx)
        r = r0 + F
        inv = 1.0 / math.sqrt(1.0 + zr1 * zr1)
        delta = -g * inv
        # principal curvatures, convex positive; the lateral ones from the profiles' curvature
        # averaged over the contact width (tables' column 3), so that Hertz's stiffness does not
        # jump where a profile's curvature does (arc to arc, arc to line)
        q = 1.0 + F1 * F1
        kwx = 1.0 / (r * math.sqrt(q))
        kwy = -_linear(wtab, 3, ws0, wstep, wn, s_min) / (q * math.sqrt(q))
        kry = -_linear(rtab, 3, ry0, rstep, rn, Py) * inv * inv * inv
        # the point where the force acts, whose normal, radius and velocity are used: the
        # centroid of the patch's line load (issue 28; the minimum for a symmetric patch)
        s = s_min
        b_lat = 0.5 * (kwy + kry)
        if delta > 0.0:
            half_width = math.sqrt(PATCH_EPSILON * delta / max(b_lat, 1.0)) * inv
            step = min(PATCH_STEP_MAX, max(PATCH_STEP_MIN, PATCH_STEP_SHARE * half_width))
            s, variance = patch_centre(k, n_cand, cand_s, cand_g, cand_h, wtab, rtab, ctx, step)
            if s != s_min:
                F, F1, F2, okw = _hermite(wtab, ws0, wstep, wn, s)
                g_c, dg, Py, Pz, zr, zr1, zr2, ok = _locus_gap(s, F, F1, F2, rtab, ctx)
                r = r0 + F
                inv = 1.0 / math.sqrt(1.0 + zr1 * zr1)
                # the approach along the patch's normal: two minima that share one patch have
                # one normal and (nearly) one depth, so the load moving from one to the other
                # does not change the force (along its own normal the steep flange minimum had
                # 0.4 times the root's approach at the same vertical depth)
                delta = -g * inv
            # Hertz's lateral curvature: the minimum's while the patch's load width agrees with
            # it, else bounded by the curvature that width implies (patch_curvature)
            b_lat = patch_curvature(b_lat, -g, inv, variance, step)
        u = -F1 * tpsi
        w = math.sqrt(max(1.0 - u * u, 1.0e-12))
        px = r * u
        py = tape + s
        pz = -r * w
        # contact point relative to the wheelset centre (left-type frame)
        relx = r11 * px + r12 * py
        rely = r21 * px + r22 * py + r23 * pz
        relz = r31 * px + r32 * py + r33 * pz
        ny = -zr1 * inv
        nz = inv
        # velocity of the wheel's material point at the contact, relative to the rail
        vrx = vx + wy * relz - lwz * rely
        vry = lvy + lwz * relx - lwx * relz - lrvy
        vrz = vz + lwx * rely - wy * relx - rail_vz
        # Penetration rate: the rate of change of the geometry, i.e. the motion of the wheel
        # surface without its spin about the axle (a body of revolution spinning in place does
        # not change the overlap; the material velocity would, wherever the contact point is
        # not straight below the axle, e.g. a flange point leading it).
        w_axle = lwx * r12 + wy * r22 + lwz * r32
        gwx = lwx - w_axle * r12
        gwy = wy - w_axle * r22
        gwz = lwz - w_axle * r32
        gvy = lvy + gwz * relx - gwx * relz - lrvy
        gvz = vz + gwx * rely - gwy * relx - rail_vz
        delta_dot = -(gvy * ny + gvz * nz)
        normal = 0.0
        a = 0.0
        b = 0.0
        xi = 0.0
        eta = 0.0
        spin = 0.0
        fx = 0.0
        fy = 0.0
        if delta > 0.0:
            kh, alpha_a, alpha_b = hertz_coefficients_nb(htab, 0.5 * kwx, b_lat, e_star)
            sd = math.sqrt(delta)
            elastic = kh * delta * sd
            if params[P_DAMP_MODEL] == 0.0:
                normal = elastic + params[P_DAMP] * delta_dot
            else:
                normal = elastic * (1.0 + params[P_DAMP] * delta_dot)
            normal *= weights[k]
            if normal < 0.0:
                normal = 0.0
            a = alpha_a * sd
            b = alpha_b * sd
            # creepages in the left-type contact frame: t_x = e_x, t_y = n x t_x = (0, nz, -ny)
            xi = vrx / speed
            eta = (vry * nz - vrz * ny) / speed
            spin = (wy * ny + lwz * nz) / speed
            if normal > 0.0 and params[P_TANGENTIAL] != 0.0:
                c11, c22, c23 = kalker_coefficients_nb(ktab, a / b)
                fx, fy = creep_forces_nb(
                    int(params[P_CREEP]), xi, eta, spin, normal, a, b, shear, c11, c22, c23,
                    params[P_MU], params[P_KA], params[P_KS], params[P_FRIC_A],
                    params[P_FRIC_B], speed,
                )  # fmt: skip
            if normal > 0.0:
                n_loaded += 1
        # total force on the wheel, left-type frame
        ftx = fx
        fty = normal * ny + fy * nz
        ftz = normal * nz - fy * ny
        # back to the real frame
        real_rely = m * rely
        real_fty = m * fty
        force[0] += ftx
        force[1] += real_fty
        force[2] += ftz
        force[3] += real_rely * ftz - relz * real_fty
        force[4] += relz * ftx - relx * ftz
        force[5] += relx * real_fty - real_rely * ftx
        pt = points[side, k]
        pt[PF_ACTIVE] = 1.0
        pt[PF_S] = s
        pt[PF_YRAIL] = Py
        pt[PF_X] = cx + relx
        pt[PF_Y] = cy + real_rely
        pt[PF_Z] = cz + relz
        pt[PF_RADIUS] = r
        pt[PF_ANGLE] = math.atan(zr1)
        pt[PF_GAP] = g
        pt[PF_DELTA] = delta
        pt[PF_N] = normal
        pt[PF_A] = a
        pt[PF_B] = b
        pt[PF_XI] = xi
        pt[PF_ETA] = m * eta
        pt[PF_SPIN] = m * spin
        pt[PF_FX] = fx
        pt[PF_FY] = m * fy
        pt[PF_FTX] = ftx
        pt[PF_FTY] = real_fty
        pt[PF_FTZ] = ftz
        pt[PF_KWX] = kwx
        pt[PF_KWY] = kwy
        pt[PF_KRY] = kry
        pt[PF_DELTA_DOT] = delta_dot
        pt[PF_NX] = 0.0
        pt[PF_NY] = m * ny
        pt[PF_NZ] = nz
        pt[PF_WEIGHT] = weights[k]
    return n_loaded


@numba.njit(**_JIT)
def wheelset_contact(wtab_l, winfo_l, rtab_l, rinfo_l, wtab_r, winfo_r, rtab_r, rinfo_r, htab,
                     ktab, params, state, rails, points, force):  # fmt: skip
    """Contact forces of a whole wheelset: both wheels, all contact points.

    Args:
        state: 11 entries ``(x, y, z, phi, psi, vx, vy, vz, wx, wy, wz)`` of the wheelset centre,
            track frame (m, rad, m/s, rad/s).
        rails: 8 entries ``(dy_l, dz_l, vy_l, vz_l, dy_r, dz_r, vy_r, vz_r)``: offsets of the left
            and right rail from their nominal places and their velocities [m], [m/s].
        points: output ``(2, MAX_POINTS, N_POINT_FIELDS)``.
        force: output, 6 entries: total force [N] and torque about the centre [N m], track frame.

    Returns:
        the number of loaded contact points of the wheelset.
    """
    scratch = np.empty(wheelset_scratch_size(winfo_l, winfo_r))
    return wheelset_contact_with_scratch(
        wtab_l, winfo_l, rtab_l, rinfo_l, wtab_r, winfo_r, rtab_r, rinfo_r, htab, ktab, params,
        state, rails, points, force, scratch,
    )  # fmt: skip


@numba.njit(inline="always", **_JIT)
def wheelset_scratch_size(winfo_l, winfo_r):
    """Entries of :func:`wheelset_contact_with_scratch`'s scratch array for the wheel tables of
    ``winfo_l``, ``winfo_r``."""
    return 4 * MAX_POINTS + max(candidates_work_size(winfo_l), candidates_work_size(winfo_r))


@numba.njit(**JIT_NO_REFCOUNT)
def wheelset_contact_with_scratch(wtab_l, winfo_l, rtab_l, rinfo_l, wtab_r, winfo_r, rtab_r,
                                  rinfo_r, htab, ktab, params, state, rails, points, force,
                                  scratch):  # fmt: skip
    """:func:`wheelset_contact` with its scratch array from the caller (at least
    :func:`wheelset_scratch_size` entries), compiled without reference counting."""
    for i in range(6):
        force[i] = 0.0
    n = wheel_contact(
        wtab_l, winfo_l, rtab_l, rinfo_l, htab, ktab, params, 1.0, state[0], state[1], state[2],
        state[3], state[4], state[5], state[6], state[7], state[8], state[9], state[10],
        rails[0], rails[1], rails[2], rails[3], points, 0, force, scratch,
    )  # fmt: skip
    n += wheel_contact(
        wtab_r, winfo_r, rtab_r, rinfo_r, htab, ktab, params, -1.0, state[0], state[1], state[2],
        state[3], state[4], state[5], state[6], state[7], state[8], state[9], state[10],
        rails[4], rails[5], rails[6], rails[7], points, 1, force, scratch,
    )  # fmt: skip
    return n
