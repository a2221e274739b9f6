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
b) *Contact points.* Along the locus the vertical gap to the rail ``g(s)`` is scanned on a coarse
   grid (``scan_step``); every local minimum is refined to machine precision by a bracketed
   Illinois iteration on ``g'(s) = 0`` (equal slopes = common normal). Each local minimum with
   ``g < 0`` is a contact point: one on the tread, or two when tread and flange both touch (the
   seed's Fig. 8). The normal penetration is ``delta = -g cos(gamma)``.
c) *Normal force.* Hertz's ellipse and stiffness from the principal curvatures of wheel and rail
   at the point (:mod:`railexu.contact.hertz`), and the damped force of the seed's eq. (2)
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

from .creep import creep_forces_nb
from .hertz import hertz_coefficients_nb
from .kalker import kalker_coefficients_nb
from .parameters import (  # noqa: F401 (P_*, N_PARAMS re-exported for kernel users)
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
def _scan_gap_slope(s, F, F1, F2, rtab, ctx):
    """The gap of :func:`_locus_gap` and its slope ``dg/ds`` for the coarse scan only: the
    rail's height and slope interpolated linearly (0.05 mm table, error ~h^2 z''/8 < 0.1 um,
    irrelevant for locating minima, which are then refined with the full interpolation); the
    slope's sign finds minima that the sampled values miss. Returns ``(1e9, 0)`` off the
    rail."""
    r = ctx[C_R0] + F
    u = -F1 * ctx[C_TPSI]
    w = math.sqrt(max(1.0 - u * u, 1.0e-12))
    px = r * u
    py = ctx[C_TAPE] + s
    pz = -r * w
    Py = ctx[C_CY] + ctx[C_R21] * px + ctx[C_R22] * py + ctx[C_R23] * pz
    Pz = ctx[C_CZ] + ctx[C_R31] * px + ctx[C_R32] * py + ctx[C_R33] * pz
    step = ctx[C_RSTEP]
    uu = (Py - ctx[C_RY0]) / step
    n = ctx[C_RN]
    if uu < 0.0 or uu > n - 1.0:
        return 1.0e9, 0.0
    i = int(uu)
    if i >= n - 1:
        i = int(n) - 2
    t = uu - i
    zr = (1.0 - t) * rtab[i, 0] + t * rtab[i + 1, 0]
    zr1 = (1.0 - t) * rtab[i, 1] + t * rtab[i + 1, 1]
    du = -F2 * ctx[C_TPSI]
    dw = -u * du / w
    dpx = F1 * u + r * du
    dpz = -F1 * w - r * dw
    dPy = ctx[C_R21] * dpx + ctx[C_R22] + ctx[C_R23] * dpz
    dPz = ctx[C_R31] * dpx + ctx[C_R32] + ctx[C_R33] * dpz
    return Pz - zr, dPz - zr1 * dPy


@numba.njit(**_JIT)
def _cell_minimum_bracket(sa, sb, ga, dga, gb, dgb, wtab, rtab, ctx):
    """A bracket ``(lo, hi)`` of a local minimum of the gap inside the scan cell ``[sa, sb]``
    (``lo >= hi``: none found), from the gap and its slope at the cell's ends.

    - the slope turns upwards (``dga < 0 <= dgb``): the whole cell;
    - the slope has the same sign at both ends but the cubic Hermite interpolant of the gap
      says it changes sign twice inside (a minimum and a hump within one cell): the exact slope
      at the interpolant's slope extremum decides, and the bracket is the part of the cell
      where the slope turns upwards.

    Only cells touching an overlap (a gap below 0.1 mm at an end) are examined this way."""
    if dga < 0.0 <= dgb:
        return sa, sb
    if min(ga, gb) > 1.0e-4 or (dga < 0.0) != (dgb < 0.0):
        return 0.0, 0.0
    h = sb - sa
    m0 = h * dga
    m1 = h * dgb
    # d/dt of the cubic Hermite interpolant on t in [0, 1]: A t^2 + B t + C
    qa = 6.0 * ga + 3.0 * m0 - 6.0 * gb + 3.0 * m1
    qb = -6.0 * ga - 4.0 * m0 + 6.0 * gb - 2.0 * m1
    if qa == 0.0:
        return 0.0, 0.0
    t = -qb / (2.0 * qa)
    if not (0.0 < t < 1.0):
        return 0.0, 0.0
    extremum = m0 + qb * t + qa * t * t
    if (dga < 0.0 and extremum <= 0.0) or (dga >= 0.0 and extremum >= 0.0):
        return 0.0, 0.0
    s_mid = sa + t * h
    g_mid, dg_mid, ok = _gap_at(s_mid, wtab, rtab, ctx)
    if not ok:
        return 0.0, 0.0
    if dga < 0.0 and dg_mid > 0.0:
        return sa, s_mid  # down, up (the minimum), down again
    if dga >= 0.0 and dg_mid < 0.0:
        return s_mid, sb  # up, down, up (the minimum)
    return 0.0, 0.0


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


@numba.njit(**_JIT)
def _gap_at(s, wtab, rtab, ctx):
    """``(g, dg/ds, ok)`` at wheel coordinate ``s`` (outside the tables: ``g = 1e9``)."""
    F, F1, F2, okw = _hermite(wtab, ctx[C_WS0], ctx[C_WSTEP], int(ctx[C_WN]), s)
    if not okw:
        return 1.0e9, 0.0, False
    g, dg, Py, Pz, zr, zr1, zr2, ok = _locus_gap(s, F, F1, F2, rtab, ctx)
    return g, dg, ok


_GOLDEN = 0.6180339887498949


@numba.njit(**_JIT)
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


@numba.njit(**_JIT)
def _refine_minimum(sa, sb, wtab, rtab, ctx):
    """Refine a local minimum of the gap bracketed by ``[sa, sb]``.

    Illinois iteration on ``g'(s) = 0`` (superlinear); where ``g'`` does not change sign over
    the bracket (two shallow minima in one scan cell, or a minimum at the bracket's end) a
    golden-section search on ``g`` instead, which always converges to a local minimum.
    """
    ga, fa, oka = _gap_at(sa, wtab, rtab, ctx)
    gb, fb, okb = _gap_at(sb, wtab, rtab, ctx)
    if not (oka and okb) or fa >= 0.0 or fb <= 0.0:
        return _golden(sa, sb, wtab, rtab, ctx, 1.0, 48)
    side = 0
    s = 0.5 * (sa + sb)
    for _ in range(60):
        s = (sa * fb - sb * fa) / (fb - fa)
        g, f, ok = _gap_at(s, wtab, rtab, ctx)
        if not ok:
            return _golden(sa, sb, wtab, rtab, ctx, 1.0, 48)
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
            overlap the rail (NaN otherwise).

    Returns:
        the number of candidates found.
    """
    ctx = _make_ctx(winfo, rinfo, cy, cz, phi, psi)
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
    g_prev2 = 1.0e9
    g_prev1 = 1.0e9
    dg_prev = 0.0
    k_prev1 = -1
    k_prev2 = -1
    # each ordinary minimum is seen by two rules below (the sampled values, and the slope
    # turning upwards in its cell); the second refinement of the same minimum is skipped: the
    # one refined first is kept either way (_add_candidate drops duplicates)
    value_s = np.nan  # minimum refined by the value rule in this iteration
    cell_s = np.nan  # minimum refined by the slope rule in the previous iteration
    # the scanned gaps are kept for the humps between minima below
    n_scan = (k_hi - k_lo) // stride + 2
    scan_g = np.empty(n_scan)
    j_scan = 0
    k = k_lo
    while k <= k_hi + stride:
        kk = k if k <= k_hi else k_hi
        s = ws0 + kk * wstep
        g, dg = _scan_gap_slope(s, wtab[kk, 0], wtab[kk, 1], wtab[kk, 2], rtab, ctx)
        if k > k_hi:
            g = 1.0e9  # the sentinel that closes a minimum at the edge
        elif j_scan < n_scan:
            scan_g[j_scan] = g
            j_scan += 1
        value_s = np.nan
        # the slope rule found this minimum in the previous cell, and the slope rises through
        # the rest of the bracket: the same minimum
        seen = k_prev2 >= 0 and dg > 0.0 and ws0 + k_prev2 * wstep <= cell_s
        seen = seen and cell_s <= ws0 + k_prev1 * wstep
        if k_prev1 >= 0 and g_prev1 < 1.0e8 and g_prev1 <= g_prev2 and g_prev1 < g and not seen:
            # local minimum at k_prev1, bracketed by its neighbours
            sa = ws0 + (k_prev2 if k_prev2 >= 0 else k_prev1) * wstep
            sb = ws0 + min(kk, k_hi) * wstep
            if sb <= sa:
                sb = sa + wstep
            s_ref = _refine_minimum(sa, sb, wtab, rtab, ctx)
            g_ref, dg_ref, ok_ref = _gap_at(s_ref, wtab, rtab, ctx)
            # a golden search may end on the bracket's end (no minimum inside): not a point
            if ok_ref and s_ref - sa > 1.0e-9 and sb - s_ref > 1.0e-9:
                n_found = _add_candidate(s_ref, g_ref, n_found, cand_s, cand_g)
                value_s = s_ref
        cell_s = np.nan
        # the cell where the locus comes onto (or leaves) the rail: a minimum between the
        # rail's edge and the first (last) node when the slope there rises (falls)
        onto = g < 1.0e8 and g_prev1 >= 1.0e8 and dg > 0.0
        off = g >= 1.0e8 and g_prev1 < 1.0e8 and dg_prev < 0.0
        if k <= k_hi and k_prev1 >= 0 and (onto or off):
            s_a = ws0 + k_prev1 * wstep
            s_ref = _refine_minimum(s_a, s, wtab, rtab, ctx)
            g_ref, dg_ref, ok_ref = _gap_at(s_ref, wtab, rtab, ctx)
            inside = s_ref - s_a > 1.0e-9 and s - s_ref > 1.0e-9
            if ok_ref and inside and g_ref < min(g_prev1, g):
                n_found = _add_candidate(s_ref, g_ref, n_found, cand_s, cand_g)
        if k <= k_hi and k_prev1 >= 0 and g < 1.0e8 and g_prev1 < 1.0e8:
            # minima that the sampled values may not show: the S1002 flange minimum beside the
            # flat hump towards the flange root on a 60E1 gauge corner lies within one or two
            # cells; missing it only at some positions of the scan grid makes the normal force
            # jump (docs/curving.md)
            s_a = ws0 + k_prev1 * wstep
            s_lo, s_hi = _cell_minimum_bracket(s_a, s, g_prev1, dg_prev, g, dg, wtab, rtab, ctx)
            if dg_prev < 0.0 <= dg and s_a <= value_s <= s:
                s_hi = s_lo  # the value rule has just refined the minimum of this cell
            if s_hi > s_lo:
                s_ref = _refine_minimum(s_lo, s_hi, wtab, rtab, ctx)
                g_ref, dg_ref, ok_ref = _gap_at(s_ref, wtab, rtab, ctx)
                # only a true interior minimum (the scan's linear rail slope may change sign
                # where the exact slope does not): below the cell's ends, away from them
                inside = s_ref - s_lo > 1.0e-9 and s_hi - s_ref > 1.0e-9
                if ok_ref and inside and g_ref < min(g_prev1, g):
                    n_found = _add_candidate(s_ref, g_ref, n_found, cand_s, cand_g)
                    if dg_prev < 0.0 <= dg:
                        cell_s = s_ref
        dg_prev = dg
        g_prev2 = g_prev1
        k_prev2 = k_prev1
        g_prev1 = g
        k_prev1 = kk
        k += stride
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
    # humps between neighbouring minima: the highest scan node between them, refined
    for i in range(n_found - 1):
        if cand_g[i] >= 0.0 or cand_g[i + 1] >= 0.0:
            continue  # only humps between two overlaps matter (candidate_weights)
        sa = cand_s[i]
        sb = cand_s[i + 1]
        # highest scanned node strictly between the two minima, then a golden refinement
        best_s = 0.5 * (sa + sb)
        best_g = _gap_at(best_s, wtab, rtab, ctx)[0]
        j = max(0, int((sa - ws0 - k_lo * wstep) / (stride * wstep)) + 1)
        while j < j_scan:
            sk = ws0 + (k_lo + j * stride) * wstep
            if sk >= sb:
                break
            if scan_g[j] > best_g:
                best_g = scan_g[j]
                best_s = sk
            j += 1
        h = stride * wstep
        lo = max(sa, best_s - h)
        hi = min(sb, best_s + h)
        s_max = _golden(lo, hi, wtab, rtab, ctx, -1.0, 16)
        cand_h[i] = max(best_g, _gap_at(s_max, wtab, rtab, ctx)[0])
    return n_found


@numba.njit(inline="always", **_JIT)
def _smoothstep(x):
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x * x * (3.0 - 2.0 * x)


@numba.njit(**_JIT)
def candidate_weights(n, cand_g, cand_h, weights):
    """Weights of neighbouring minima that share one overlap region (see ``wheel_contact``).

    Two penetrating minima ``a, b`` with the hump ``H`` between them: if the hump rises above
    zero (``H >= 0``) their overlap regions are separate and both count fully. If the hump is
    below zero they are one connected overlap, and the shallower minimum would count the same
    contact twice: its weight falls with the smoothstep of ``(H - g)/(-g)`` and vanishes when the
    hump sinks to its depth (the two minima merge). Which one is the shallower is itself blended
    over a depth band of 10 % of the deeper penetration, and a minimum whose prominence
    ``H - g`` vanishes (it is being born from, or dies into, a flat stretch of the gap, as on
    the nearly conformal S1002 tread on a 1:40 rail) fades out within 2 % of its depth: the
    normal force stays continuous when minima appear, merge, separate or change order inside
    one overlap region.
    """
    for k in range(n):
        weights[k] = 1.0
    for i in range(n - 1):
        ga = cand_g[i]
        gb = cand_g[i + 1]
        if ga >= 0.0 or gb >= 0.0:
            continue
        hump = cand_h[i]
        tau = 0.1 * (-min(ga, gb))
        theta_a = _smoothstep(0.5 + (ga - gb) / (2.0 * tau))  # 1: a is the shallower one
        sa = _smoothstep((hump - ga) / (-ga))
        sb = _smoothstep((hump - gb) / (-gb))
        # a minimum being born or dying in the overlap (its prominence H - g -> 0) fades out
        # over a depth of 2 % of its penetration (plus 0.2 um), whichever one it is
        ca = _smoothstep((hump - ga) / (0.02 * (-ga) + 2.0e-7))
        cb = _smoothstep((hump - gb) / (0.02 * (-gb) + 2.0e-7))
        # ... and only a minimum that exists (c = 1) can take load off its neighbour
        weights[i] *= (1.0 - theta_a * cb * (1.0 - sa)) * ca
        weights[i + 1] *= (1.0 - (1.0 - theta_a) * ca * (1.0 - sb)) * cb


@numba.njit(**_JIT)
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
        scratch: work array of at least ``4 * MAX_POINTS`` entries.

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
    n_cand = find_contact_candidates(
        wtab, winfo, rtab, rinfo, lcy, lcz, lphi, lpsi, params[P_SCAN], cand_s, cand_g, cand_h
    )
    candidate_weights(n_cand, cand_g, cand_h, weights)
    for k in range(MAX_POINTS):
        for f in range(N_POINT_FIELDS):
            points[side, k, f] = 0.0
    ctx = _make_ctx(winfo, rinfo, lcy, lcz, lphi, lpsi)
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
        s = cand_s[k]
        F, F1, F2, okw = _hermite(wtab, ws0, wstep, wn, s)
        g, dg, Py, Pz, zr, zr1, zr2, ok = _locus_gap(s, F, F1, F2, rtab, ctx)
        r = r0 + F
        u = -F1 * tpsi
        w = math.sqrt(max(1.0 - u * u, 1.0e-12))
        px = r * u
        py = tape + s
        pz = -r * w
        # contact point relative to the wheelset centre (left-type frame)
        relx = r11 * px + r12 * py
        rely = r21 * px + r22 * py + r23 * pz
        relz = r31 * px + r32 * py + r33 * pz
        inv = 1.0 / math.sqrt(1.0 + zr1 * zr1)
        ny = -zr1 * inv
        nz = inv
        delta = -g * inv
        # principal curvatures, convex positive; the lateral ones from the profiles' curvature
        # averaged over the contact width (tables' column 3), so that Hertz's stiffness does not
        # jump where a profile's curvature does (arc to arc, arc to line)
        q = 1.0 + F1 * F1
        kwx = 1.0 / (r * math.sqrt(q))
        kwy = -_linear(wtab, 3, ws0, wstep, wn, s) / (q * math.sqrt(q))
        kry = -_linear(rtab, 3, ry0, rstep, rn, Py) * inv * inv * inv
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
            kh, alpha_a, alpha_b = hertz_coefficients_nb(htab, 0.5 * kwx, 0.5 * (kwy + kry), e_star)
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
    for i in range(6):
        force[i] = 0.0
    scratch = np.empty(4 * MAX_POINTS)
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
