"""Wear over a contact patch from FASTSIM's traction and slip (docs/wear.md).

Kalker's simplified theory (:mod:`railexu.contact.fastsim`, Kalker, VSD 11 (1982) 1-13) marches
the traction through the Hertz ellipse strip by strip; where the trial traction exceeds the
bound ``mu p`` the cell slides, and the slip per metre rolled is what the bound took away,
``s_x = L1 (q_trial,x - q_x) / h``, ``s_y = L2 (q_trial,y - q_y) / h`` (``h`` the step of the
march; in adhesion ``s = 0``). The local wear rate ``w(p, |q|, |s|, V |s|)`` of the chosen law
(:mod:`.laws`) is integrated along each strip: a point of the wheel at lateral position ``y``
of the patch loses ``d(y) = int w dx`` of depth each time it passes the patch (once a wheel
revolution), a point of the rail the same once a wheel passes. The same traction and pressure
as :func:`~railexu.contact.fastsim.fastsim3_nb` (same strips and cells), so the creep forces
returned here equal FASTSIM's.

Closed form (``tests/test_wear_models.py``): in steady full sliding with slip ``s`` and
Archard's law at a constant ``k``, ``d(y) = k s / H int p dx = 3 k s Q (1 - y^2/b^2) / (4 b H)``
and the volume per metre rolled is ``k Q s / H``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from railexu.contact.kalker import kalker_coefficients_nb, kalker_table_for_poisson
from railexu.contact.wear.coefficients import Coefficients
from railexu.contact.wear.laws import law_vector, wear_law_code

__all__ = ["PATCH_STRIPS", "PATCH_POINTS", "patch_wear", "patch_wear_nb", "wear_on_profile"]

#: default discretisation of the patch for wear (strips across, cells along a strip)
PATCH_STRIPS = 20
PATCH_POINTS = 20


@numba.njit(cache=True)
def _local_rate(code, lawv, p, q, s, speed):
    """Local wear rate [-] of law ``code`` (:mod:`.laws`) at pressure ``p``, traction ``q``
    [Pa] and slip ``s`` [-]; ``lawv`` from :func:`~.laws.law_vector`."""
    if s <= 0.0 or p <= 0.0:
        return 0.0
    if code == 0:
        v = speed * s
        if p > lawv[0]:
            k = lawv[3]
        elif v < lawv[1]:
            k = lawv[4]
        elif v <= lawv[2]:
            k = lawv[5]
        else:
            k = lawv[6]
        return k * p * s * lawv[7]
    x = q * s * 1e-6  # T gamma / A [N/mm^2]
    if x < lawv[0]:
        rate = lawv[2] * x
    elif x <= lawv[1]:
        rate = lawv[3]
    else:
        rate = lawv[4] * x - lawv[5]
    if rate < 0.0:
        rate = 0.0
    return rate * lawv[6]


@numba.njit(cache=True)
def patch_wear_nb(
    xi, eta, phi, Q, mu, a, b, G, c11, c22, c23, speed, code, lawv, n_strips, n_points, depth
):
    """Wear depth per passage across the patch, compiled; fills ``depth[j]`` (strip ``j`` of
    ``n_strips`` across ``-b .. b``) [m] and returns ``(Fx, Fy, volume_per_m)``: FASTSIM's
    forces on the wheel [N] and the volume removed per metre rolled ``sum_j depth_j 2b/n``
    [m^2] (module doc). Arguments as :func:`~railexu.contact.fastsim.fastsim3_nb` plus the
    rolling speed [m/s], the law's code and coefficient vector."""
    for j in range(n_strips):
        depth[j] = 0.0
    if not (Q > 0.0 and a > 0.0 and b > 0.0 and G > 0.0):
        return 0.0, 0.0, 0.0
    l1 = 8.0 * a / (3.0 * c11 * G)
    l2 = 8.0 * a / (3.0 * c22 * G)
    kx = xi / l1
    ky = eta / l2
    ks = phi * 4.0 * c23 * G / (math.pi * a * math.sqrt(a / b))
    p0_over_a = 1.5 * Q / (math.pi * a * b) / a
    inv3b2 = 1.0 / (3.0 * b * b)
    dy = 2.0 * b / n_strips
    fx = 0.0
    fy = 0.0
    vol = 0.0
    for j in range(n_strips):
        y_lo = -b + j * dy
        y_hi = y_lo + dy
        r = 1.0 - (y_lo * y_lo + y_lo * y_hi + y_hi * y_hi) * inv3b2
        if r <= 0.0:
            continue
        aj = a * math.sqrt(r)
        yc = 0.5 * (y_lo + y_hi)
        dx = 2.0 * aj / n_points
        wx = kx - ks * yc
        px = 0.0
        py = 0.0
        x_prev = aj
        d = 0.0
        for i in range(n_points):
            xc = aj - (i + 0.5) * dx
            h = x_prev - xc
            xm = 0.5 * (x_prev + xc)
            tx = px - h * wx
            ty = py - h * (ky + ks * xm)
            qq = aj * aj - xc * xc
            p = p0_over_a * math.sqrt(qq) if qq > 0.0 else 0.0
            bound = mu * p
            t2 = tx * tx + ty * ty
            if t2 > bound * bound:
                scale = bound / math.sqrt(t2)
                px = tx * scale
                py = ty * scale
                sx = l1 * (tx - px) / h
                sy = l2 * (ty - py) / h
                s = math.sqrt(sx * sx + sy * sy)
                d += _local_rate(code, lawv, p, bound, s, speed) * dx
            else:
                px = tx
                py = ty
            fx += px * dx * dy
            fy += py * dx * dy
            x_prev = xc
        depth[j] = d
        vol += d * dy
    return fx, fy, vol


def patch_wear(
    law: str,
    coef: Coefficients,
    xi: float,
    eta: float,
    phi: float,
    Q: float,
    mu: float,
    a: float,
    b: float,
    G: float,
    poisson: float,
    speed_m_per_s: float,
    n_strips: int = PATCH_STRIPS,
    n_points: int = PATCH_POINTS,
) -> dict:
    """Wear of one contact patch (module doc).

    Args:
        law: wear law name (:data:`~.laws.WEAR_LAWS`).
        coef: coefficients (:func:`~.coefficients.load_coefficients`).
        xi, eta: longitudinal, lateral creepage [-]; phi: spin [1/m].
        Q: normal force [N]; mu: friction coefficient [-].
        a, b: semi-axes along the rolling direction and across [m].
        G: shear modulus [Pa]; poisson: Poisson's ratio [-] (Kalker's coefficients).
        speed_m_per_s: rolling speed [m/s].

    Returns:
        ``{"y_m": strip centres across the patch, "depth_m": depth per passage per strip,
        "volume_per_m_m2": volume removed per metre rolled, "Fx_N", "Fy_N"}``.
    """
    if n_strips < 1 or n_points < 1:
        raise ValueError("n_strips and n_points must be >= 1")
    code = wear_law_code(law)
    c11, c22, c23 = kalker_coefficients_nb(kalker_table_for_poisson(poisson), a / b)
    depth = np.zeros(n_strips)
    fx, fy, vol = patch_wear_nb(
        float(xi), float(eta), float(phi), float(Q), float(mu), float(a), float(b), float(G),
        c11, c22, c23, float(speed_m_per_s), code, law_vector(law, coef), int(n_strips),
        int(n_points), depth,
    )  # fmt: skip
    dy = 2.0 * b / n_strips
    return {
        "y_m": -b + dy * (np.arange(n_strips) + 0.5),
        "depth_m": depth,
        "volume_per_m_m2": float(vol),
        "Fx_N": float(fx),
        "Fy_N": float(fy),
    }


@numba.njit(cache=True)
def _deposit(grid_y0, grid_step, area, y, amount):
    """Add ``amount`` [m^2] at lateral ``y`` to the nodal areas ``area`` (linear split between
    the two neighbouring nodes: the sum is kept exactly)."""
    u = (y - grid_y0) / grid_step
    n = area.shape[0]
    if u <= 0.0:
        area[0] += amount
        return
    if u >= n - 1:
        area[n - 1] += amount
        return
    i = int(math.floor(u))
    t = u - i
    area[i] += (1.0 - t) * amount
    area[i + 1] += t * amount


@numba.njit(cache=True)
def wear_on_profile_nb(
    rows, mu, G, table, code, lawv, n_strips, n_points, grid_y0, grid_step, area, rail_area
):
    """Accumulate the worn area of many contacts on a wheel's and a rail's lateral grids.

    ``rows[k]`` = ``[xi, eta, phi, Q, a, b, wheel_s, rail_y, angle, speed, weight_wheel,
    weight_rail, lateral_sign]``: creepages, normal force, semi-axes, the contact's position on
    the wheel and the rail profile [m], contact angle [rad], rolling speed [m/s], and the
    weights that turn a passage's depth into the sample's share (wheel: passages = distance /
    (2 pi r); rail: wheel passages over that rail point), ``lateral_sign`` the direction of the
    patch's lateral axis along the profile coordinate (+1 or -1). A strip at ``eta`` across the
    patch lands at ``s + sign eta cos(angle)`` on the profile; its area ``depth eta_step`` is
    kept (the graph's height change there is the area over the grid step). Returns the volume
    per metre rolled summed with the wheel weights (for the conservation check).
    """
    depth = np.zeros(n_strips)
    total = 0.0
    for k in range(rows.shape[0]):
        r = rows[k]
        Q = r[3]
        a = r[4]
        b = r[5]
        if not (Q > 0.0 and a > 0.0 and b > 0.0):
            continue
        c11, c22, c23 = kalker_coefficients_nb(table, a / b)
        _, _, vol = patch_wear_nb(
            r[0], r[1], r[2], Q, mu, a, b, G, c11, c22, c23, r[9], code, lawv, n_strips,
            n_points, depth,
        )  # fmt: skip
        if vol <= 0.0:
            continue
        total += vol * r[10]
        dy = 2.0 * b / n_strips
        c = math.cos(r[8]) * r[12]
        for j in range(n_strips):
            eta = -b + (j + 0.5) * dy
            if depth[j] > 0.0:
                _deposit(grid_y0, grid_step, area, r[6] + eta * c, depth[j] * dy * r[10])
                _deposit(grid_y0, grid_step, rail_area, r[7] + eta * c, depth[j] * dy * r[11])
    return total


def wear_on_profile(
    rows: np.ndarray,
    law: str,
    coef: Coefficients,
    mu: float,
    G: float,
    poisson: float,
    grid_y0_m: float,
    grid_step_m: float,
    n_grid: int,
    n_strips: int = PATCH_STRIPS,
    n_points: int = PATCH_POINTS,
) -> tuple[np.ndarray, np.ndarray, float]:
    """The worn area per grid node of a wheel and of a rail [m^2] from many contacts
    (:func:`wear_on_profile_nb`; ``rows`` as there), and the summed volume term (the same
    area before it is placed on the grid) for the conservation check.

    The height removed at node ``i`` of the lateral grid is ``area[i] / grid_step_m``.
    """
    rows = np.ascontiguousarray(rows, dtype=np.float64).reshape(-1, 13)
    if not np.all(np.isfinite(rows)):
        raise ValueError("contact rows with NaN or infinite values")
    area = np.zeros(int(n_grid))
    rail = np.zeros(int(n_grid))
    total = wear_on_profile_nb(
        rows, float(mu), float(G), kalker_table_for_poisson(poisson), wear_law_code(law),
        law_vector(law, coef), int(n_strips), int(n_points), float(grid_y0_m),
        float(grid_step_m), area, rail,
    )  # fmt: skip
    return area, rail, float(total)
