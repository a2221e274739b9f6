"""The wheelset rows of Wickens' textbook linear model (Wickens, "Fundamentals of Rail Vehicle
Dynamics", the two-axle vehicle and the bogie with linear creep), shared by the tests that
check railexu's linear critical speed against it (test_stability, test_stability_two_axle)."""

from __future__ import annotations

import numpy as np


def add_wheelset(c, k, i, x, v, lam, creep, geometry, i_spin, springs):
    """Add wheelset ``i`` (coordinates ``2 i`` lateral, ``2 i + 1`` yaw) at ``x`` [m] ahead of
    the centre of the body it is sprung to (coordinates 4 lateral, 5 yaw) to the damping ``c``
    and stiffness ``k`` at speed ``v`` [m/s] and conicity ``lam``:

        m_w y'' + 2 f22 (1 + lam r0 / e0) y' / V - 2 f22 psi + 2 k_y (y - y_b - x psi_b) = 0
        I_w psi'' + 2 f11 e0^2 psi' / V + 2 f11 e0 lam y / r0 + I_spin (V / r0)(lam / e0) y'
            + 2 k_x b^2 (psi - psi_b) = 0

    with the roll-rate part of the lateral creepage (``1 + lam r0 / e0``) and the gyroscopic
    yaw moment of the spinning wheelset, which a 3-D rolling wheelset has. ``creep`` is
    ``(f11, f22)`` [N], ``geometry`` ``(r0, e0)`` [m], ``springs`` ``(k_x, k_y, b)`` per side
    [N/m, N/m, m]."""
    f11, f22 = creep
    r0, e0 = geometry
    kx, ky, b = springs
    n = c.shape[0]
    iy, ip = 2 * i, 2 * i + 1
    c[iy, iy] += 2 * f22 * (1 + lam * r0 / e0) / v
    k[iy, ip] -= 2 * f22
    c[ip, ip] += 2 * f11 * e0**2 / v
    k[ip, iy] += 2 * f11 * e0 * lam / r0
    c[ip, iy] += i_spin * v / r0 * lam / e0
    t = np.zeros(n)
    t[[iy, 4, 5]] = (1.0, -1.0, -x)
    k += 2 * ky * np.outer(t, t)
    t = np.zeros(n)
    t[[ip, 5]] = (1.0, -1.0)
    k += 2 * kx * b * b * np.outer(t, t)
