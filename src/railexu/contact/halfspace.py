"""The non-Hertzian normal contact problem on the elastic half-space (frictionless, one patch).

Given the interpenetration ``h(x, y)`` of the undeformed surfaces on a uniform grid of
rectangular elements, find the pressure ``p >= 0`` such that the deformed gap
``g = u(p) - h >= 0`` with ``p g = 0`` (Kalker, *Three-dimensional elastic bodies in rolling
contact*, 1990, ch. 5; the normal problem CONTACT solves). The surface displacement of a
uniform pressure on a rectangle is Love's (1929) closed form (Johnson, *Contact Mechanics*,
1985, eq. 3.25); for two bodies of the same material the combined displacement is
``u = (1 / (pi E*)) * integral p / r dA`` with ``1 / E* = (1 - nu) / G``. The convolution is
evaluated by FFT on the doubled grid; the constrained problem is solved by the conjugate
gradient method of Polonsky & Keer (Wear 231, 1999, 206-219), prescribed approach version.
"""

from __future__ import annotations

import numpy as np


def _love_primitive(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``F`` with ``d2F/dxdy = 1/sqrt(x^2 + y^2)`` (terms in one variable only dropped)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(x != 0.0, x * np.arcsinh(y / np.abs(x)), 0.0)
        b = np.where(y != 0.0, y * np.arcsinh(x / np.abs(y)), 0.0)
    return a + b


def influence_kernel(nx: int, ny: int, dx_m: float, dy_m: float, e_star_pa: float) -> np.ndarray:
    """Displacement [m] at element offsets ``(i, j)`` per unit pressure [Pa] on one element,
    on the wrapped ``(2 nx, 2 ny)`` grid for the FFT convolution."""
    i = np.arange(-nx, nx) * dx_m
    j = np.arange(-ny, ny) * dy_m
    X, Y = np.meshgrid(i, j, indexing="ij")
    a, b = 0.5 * dx_m, 0.5 * dy_m
    f = _love_primitive
    integral = f(X + a, Y + b) - f(X - a, Y + b) - f(X + a, Y - b) + f(X - a, Y - b)
    k = integral / (np.pi * e_star_pa)
    return np.fft.ifftshift(k)


class HalfSpace:
    """The influence operator of one grid: ``u = A p`` by FFT."""

    def __init__(self, nx: int, ny: int, dx_m: float, dy_m: float, e_star_pa: float):
        self.shape = (nx, ny)
        self.area_m2 = dx_m * dy_m
        self._kf = np.fft.rfft2(influence_kernel(nx, ny, dx_m, dy_m, e_star_pa))

    def displacement(self, p_pa: np.ndarray) -> np.ndarray:
        """Normal surface displacement [m] of the pressure ``p`` [Pa] on the grid."""
        nx, ny = self.shape
        big = np.zeros((2 * nx, 2 * ny))
        big[:nx, :ny] = p_pa
        u = np.fft.irfft2(np.fft.rfft2(big) * self._kf, s=big.shape)
        return u[:nx, :ny]


def solve_normal(
    h_m: np.ndarray, dx_m: float, dy_m: float, e_star_pa: float, *, tol: float = 1.0e-8,
    max_iter: int = 2000,
) -> np.ndarray:  # fmt: skip
    """Pressure [Pa] on the grid for the interpenetration ``h`` [m] (positive = overlap).

    Polonsky-Keer conjugate gradients with the approach contained in ``h``. Converged when the
    gap's rms on the loaded elements is below ``tol`` times the largest overlap.
    """
    h = np.asarray(h_m, dtype=float)
    if not np.any(h > 0.0):
        return np.zeros_like(h)
    hs = HalfSpace(h.shape[0], h.shape[1], dx_m, dy_m, e_star_pa)
    p = np.where(h > 0.0, 1.0e6, 0.0)
    t = np.zeros_like(h)
    g_old, delta = 1.0, 0.0
    scale = float(h.max())
    for _ in range(max_iter):
        g = hs.displacement(p) - h
        loaded = p > 0.0
        g_norm = float(np.sum(g[loaded] ** 2))
        t = np.where(loaded, g + delta * (g_norm / g_old) * t, 0.0)
        g_old = g_norm
        r = hs.displacement(t)
        denom = float(np.sum(r[loaded] * t[loaded]))
        tau = float(np.sum(g[loaded] * t[loaded])) / denom if denom > 0.0 else 0.0
        p = p - tau * t
        p[p < 0.0] = 0.0
        overlap = (p == 0.0) & (g < 0.0)
        if np.any(overlap):
            p[overlap] -= tau * g[overlap]
            delta = 0.0
        else:
            delta = 1.0
        if np.sqrt(g_norm / max(1, int(loaded.sum()))) < tol * scale and not np.any(overlap):
            break
    return p
