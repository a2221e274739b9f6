"""The exact steady rolling tangential problem on the elastic half-space (one patch, a grid).

Given the pressure ``p`` of a patch on a uniform grid of rectangular elements (rows along the
rolling direction ``x``, increasing towards the leading edge; columns along ``s`` in the contact
plane), the creepages ``(xi, eta, phi)`` and the friction ``mu``, find the tangential traction
``q = (q_x, q_s)`` on the rail such that, element by element (Kalker, *Three-dimensional elastic
bodies in rolling contact*, 1990, ch. 5; the steady state CONTACT solves):

- the slip (over the rolling speed) ``S = w + (u_i - u_{i+1}) / dx``, with the rigid slip
  ``w = (xi - phi s, eta + phi x)`` and the tangential displacement difference ``u`` of the
  two bodies at the element and at its upstream neighbour ``i + 1`` (one element towards the
  leading edge: the first-order backward difference along the material's path of CONTACT's
  steady state; ``S = w - du/dx`` in the limit);
- Coulomb's law: ``|q| <= mu p``; ``S = 0`` where ``|q| < mu p`` (adhesion), ``q = -mu p S / |S|``
  where it slides.

**Influence coefficients.** For two bodies of the same material the tangential and the normal
problems decouple (Kalker's quasi-identity: the coupling term ``(1 - 2 nu)`` of Cerruti's
solution cancels between the bodies), so ``p`` is the normal solution's
(:mod:`railexu.contact.halfspace`). Cerruti's point load (Johnson, *Contact Mechanics*, 1985,
eq. 3.86a-b) gives, for the two bodies together, the displacement difference per unit force
``u_x = (1 / (pi G)) ((1 - nu) / r + nu x^2 / r^3)``, ``u_s = (1 / (pi G)) nu x s / r^3`` (and
``x <-> s``). Their integrals over a uniform traction on a rectangle are in closed form by the
primitives ``F`` with ``d2F / dx ds`` the integrand: ``1 / r``: ``x asinh(s / |x|) + s asinh(x /
|s|)`` (Love's, as the normal problem's); ``x^2 / r^3``: ``s asinh(x / |s|)``; ``s^2 / r^3``:
``x asinh(s / |x|)``; ``x s / r^3``: ``-r``.

**Solver.** Gauss-Seidel sweeps as Kalker's / CONTACT's: elements are visited row by row
from the leading edge; each element's traction is solved with all others fixed, and the slip
of all elements is updated by its change (``O(N)`` per element, ``O(N^2)`` per sweep, compiled
by numba). The slip's own coefficient of an element is diagonal, ``K(0) = (A(0) - A(1)) / dx
> 0`` per component, but plain Gauss-Seidel with it diverges on the steady rolling problem
(the upstream neighbour's coefficient is ``-K(0)``, the downstream one's 0.25 ``K(0)``, the
lateral neighbours' together 0.2-2 ``K(0)`` for ``dx / ds`` = 1-4: not diagonally dominant).
The local problem is therefore solved with the coefficient ``L`` = 3 times the sum of ``|K|``
along the element's own row (under-relaxation; 2 diverged in adhesion on a Hertz circle for
``dx / ds`` = 0.5-2, 2.5 and 3 converged everywhere tried; 6 and 12 are tried in turn if 3
does not converge): adhesion ``q = q_old - S / L``; sliding
``q_k = -S_0k / (L_k + m)`` with ``S_0 = S - L q_old`` and ``m >= 0`` such that ``|q| = mu p``
(Newton's method on a convex decreasing function from the left of its root), i.e. ``q`` of
magnitude ``mu p`` against the slip the element would have with the coefficient ``L``; at
convergence ``q`` no longer changes, so ``S`` is the true slip and Coulomb's law holds. Sweeps
stop when no traction changed by more than ``tol`` times the largest traction (default
1e-4: on the S&C patches the forces are then within 0.003 % of mu N of the 1e-6 solution);
a :class:`railexu.errors.ComputationError` names the patch's size and the last change if
``max_sweeps`` is reached with every coefficient. Convergence is shown by the tests
(Carter's 2-D solution, Kalker's linear coefficients, full sliding, CONTACT's S&C cases), not
proven.
"""

from __future__ import annotations

import numba
import numpy as np

from railexu.errors import ComputationError

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}

#: The local coefficients tried in turn, in multiples of the sum of ``|K|`` along the
#: element's own row (its own slip coefficient and its lateral neighbours'; module doc).
RELAXATION: tuple[float, ...] = (3.0, 6.0, 12.0)


def _primitives(x: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(Fxx, Fss, Fxs)``: primitives of ``x^2 / r^3``, ``s^2 / r^3`` and ``x s / r^3``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        fss = np.where(x != 0.0, x * np.arcsinh(s / np.abs(x)), 0.0)
        fxx = np.where(s != 0.0, s * np.arcsinh(x / np.abs(s)), 0.0)
    return fxx, fss, -np.hypot(x, s)


def influence_coefficients(
    nx: int, ns: int, dx_m: float, ds_m: float, shear_modulus_pa: float, poisson: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(Axx, Ass, Axs)`` [m/Pa]: the tangential displacement difference of the two bodies at
    element offsets ``(i, j)``, ``i`` in ``-nx .. nx``, ``j`` in ``-ns .. ns`` (array index
    ``i + nx``, ``j + ns``), per unit traction [Pa] on one element (module doc)."""
    x = np.arange(-nx, nx + 1) * dx_m
    s = np.arange(-ns, ns + 1) * ds_m
    X, S = np.meshgrid(x, s, indexing="ij")
    a, b = 0.5 * dx_m, 0.5 * ds_m
    corners = [(X + a, S + b, 1.0), (X - a, S + b, -1.0), (X + a, S - b, -1.0), (X - a, S - b, 1.0)]
    ixx = np.zeros_like(X)
    iss = np.zeros_like(X)
    ixs = np.zeros_like(X)
    for cx, cs, sign in corners:
        fxx, fss, fxs = _primitives(cx, cs)
        ixx += sign * fxx
        iss += sign * fss
        ixs += sign * fxs
    i_r = ixx + iss  # 1 / r = (x^2 + s^2) / r^3
    c = 1.0 / (np.pi * shear_modulus_pa)
    return (
        c * ((1.0 - poisson) * i_r + poisson * ixx),
        c * ((1.0 - poisson) * i_r + poisson * iss),
        c * poisson * ixs,
    )


@numba.njit(**_JIT)
def _local(s0x, s0y, cx, cy, bound):
    """One element's traction for the slip ``S0`` of all other elements (module doc)."""
    qx, qy = -s0x / cx, -s0y / cy
    mag = np.hypot(qx, qy)
    if mag <= bound:
        return qx, qy
    if bound <= 0.0:
        return 0.0, 0.0
    cmin = min(cx, cy)
    m = cmin * (mag / bound - 1.0)  # left of the root (both C's = cmin reach the bound there)
    for _ in range(50):
        ax, ay = s0x / (cx + m), s0y / (cy + m)
        norm = np.hypot(ax, ay)
        if abs(norm - bound) <= 1e-12 * bound:
            break
        slope = -(ax * ax / (cx + m) + ay * ay / (cy + m)) / norm
        if slope >= 0.0:
            break
        m += max((norm - bound) / -slope, 0.0)
    ax, ay = s0x / (cx + m), s0y / (cy + m)
    scale = bound / np.hypot(ax, ay)
    return -ax * scale, -ay * scale


@numba.njit(**_JIT)
def _gauss_seidel(ii, jj, wx, wy, bound, kxx, kyy, kxy, nx, ny, lx, ly, tol, max_sweeps):
    """Gauss-Seidel sweeps over the elements in the given order with the local coefficients
    ``(lx, ly)``: ``(qx, qy, sweeps, change)``, the last sweep's largest change over the
    largest traction."""
    n = ii.size
    qx = np.zeros(n)
    qy = np.zeros(n)
    sx = wx.copy()
    sy = wy.copy()
    change = 0.0
    for sweep in range(max_sweeps):
        change = 0.0
        for e in range(n):
            s0x = sx[e] - lx * qx[e]
            s0y = sy[e] - ly * qy[e]
            nqx, nqy = _local(s0x, s0y, lx, ly, bound[e])
            dqx, dqy = nqx - qx[e], nqy - qy[e]
            d = max(abs(dqx), abs(dqy))
            if d == 0.0:
                continue
            change = max(change, d)
            qx[e], qy[e] = nqx, nqy
            ie, je = ii[e], jj[e]
            for f in range(n):
                di = ii[f] - ie + nx
                dj = jj[f] - je + ny
                sx[f] += kxx[di, dj] * dqx + kxy[di, dj] * dqy
                sy[f] += kxy[di, dj] * dqx + kyy[di, dj] * dqy
        qmax = 0.0
        for e in range(n):
            qmax = max(qmax, abs(qx[e]), abs(qy[e]))
        if change <= tol * qmax:
            return qx, qy, sweep + 1, change / qmax if qmax > 0.0 else 0.0
    return qx, qy, max_sweeps, change / max(qmax, 1e-300)


def solve_tangential(
    pressure_pa: np.ndarray,
    x_m: np.ndarray,
    s_m: np.ndarray,
    xi: float,
    eta: float,
    phi_per_m: float,
    friction: float,
    shear_modulus_pa: float,
    poisson: float,
    *,
    tol: float = 1.0e-4,
    max_sweeps: int = 1000,
) -> tuple[np.ndarray, np.ndarray]:
    """The steady rolling tractions ``(q_x, q_s)`` [Pa] on the rail (module doc).

    Args:
        pressure_pa: the pressure on the grid [Pa], rows along ``x_m``, columns along ``s_m``.
        x_m, s_m: the elements' centres [m], uniform and increasing (``x`` towards the leading
            edge), from the spin's pole.
        xi, eta: creepages [-]; phi_per_m: spin creepage [1/m] (Kalker's signs:
            :mod:`railexu.contact.variable_creep`); friction: ``mu`` [-].
        shear_modulus_pa, poisson: ``G`` [Pa] and ``nu`` of both bodies.
        tol: convergence: the largest change of a traction in the last sweep over the
            largest traction; max_sweeps: sweeps before giving up.
    """
    p = np.asarray(pressure_pa, dtype=float)
    nx, ns = p.shape
    qx = np.zeros_like(p)
    qs = np.zeros_like(p)
    ii, jj = np.nonzero(p > 0.0)
    if ii.size == 0 or friction <= 0.0:
        return qx, qs
    dx = float(x_m[1] - x_m[0]) if nx > 1 else 1.0
    ds = float(s_m[1] - s_m[0]) if ns > 1 else 1.0
    axx, ass, axs = influence_coefficients(nx, ns, dx, ds, shear_modulus_pa, poisson)
    # slip coefficients K(di) = (A(di) - A(di + 1)) / dx for di = -nx .. nx - 1 (index di + nx)
    kxx, kss, kxs = ((a[:-1] - a[1:]) / dx for a in (axx, ass, axs))
    order = np.lexsort((jj, -ii))  # rows from the leading edge, then across
    ii, jj = ii[order].astype(np.int64), jj[order].astype(np.int64)
    wx = xi - phi_per_m * s_m[jj]
    ws = eta + phi_per_m * x_m[ii]
    bound = friction * p[ii, jj]
    kernels = [np.ascontiguousarray(k) for k in (kxx, kss, kxs)]
    row = (float(np.abs(kxx[nx]).sum()), float(np.abs(kss[nx]).sum()))
    for relax in RELAXATION:
        q1, q2, sweeps, change = _gauss_seidel(
            ii, jj, wx, ws, bound, *kernels, nx, ns, relax * row[0], relax * row[1],
            tol, max_sweeps,
        )  # fmt: skip
        if change <= tol:
            break
    else:
        raise ComputationError(
            f"exact tangential solution: no convergence in {sweeps} sweeps on a patch of "
            f"{ii.size} elements ({nx} x {ns}) with the local coefficient {relax:g} times its "
            f"row's; last change {change:.2e} of the largest traction, tolerance {tol:.0e}"
        )
    qx[ii, jj] = q1
    qs[ii, jj] = q2
    return qx, qs
