"""Kalker's linear theory of rolling contact: creepage coefficients and linear creep forces.

Source: J. J. Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer 1990,
Table E.3 (docs/theory.md section 4.2): the coefficients ``c11``, ``c22``, ``c23`` for an elliptic
contact with semi-axes ``a`` (rolling direction) and ``b`` (lateral), tabulated over ``a/b`` for
Poisson's ratios ``nu = 0, 0.25, 0.5``.

Linear theory, force **on the wheel** in the contact frame (docs/conventions.md)::

    Fx = -G a b c11 xi
    Fy = -G a b c22 eta - G (ab)^(3/2) c23 phi

Interpolation (docs/theory.md section 4.2): the table is used as a function of ``g = min(a/b, b/a)``
separately in its two halves (``a <= b``: rows ``a/b = 0.1 .. 1``; ``a >= b``: rows
``a/b = 1 .. 10``, i.e. ``b/a = 1 .. 0.1``); in each half the nodes are ``g = 0.1, 0.2, .., 1``.
In ``nu`` the reciprocal ``1/c`` is interpolated by the quadratic Lagrange polynomial through
``nu = 0, 0.25, 0.5``. We first reduce the table to the requested ``nu`` (Lagrange on ``1/c`` at
each node, :func:`kalker_table_for_poisson`) and then interpolate linearly in ``g``; at the
table nodes this is identical to the other order, and it makes the compiled lookup
(:func:`kalker_coefficients_nb`, which receives the reduced table) agree with
:func:`kalker_coefficients` everywhere. Example: ``nu = 0.28, a/b = 1`` gives
``c11 = 4.226, c22 = 3.705, c23 = 1.488``.

Clamping outside the table: ``a/b < 0.1`` uses the ``a/b = 0.1`` row and ``a/b > 10`` the
``a/b = 10`` row (``g`` is clamped to ``[0.1, 1]``). Kalker's coefficients keep growing for
slender ellipses (asymptotically like ``1/(g ln(16/g^2))``-type expressions), so the clamp
*underestimates* them there; such ellipses are outside Hertz's reliable range anyway.
``nu`` is clamped to ``[0, 0.5]`` (the Lagrange polynomial is not extrapolated).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = [
    "KALKER_POISSON_NODES",
    "KALKER_TABLE_E3",
    "kalker_coefficients",
    "kalker_table_for_poisson",
    "kalker_coefficients_nb",
    "kalker_linear_forces",
    "kalker_linear_nb",
]

#: Poisson's ratios of the columns of :data:`KALKER_TABLE_E3`.
KALKER_POISSON_NODES = (0.0, 0.25, 0.5)

# Kalker 1990, Table E.3. Rows: a/b as printed (1.111 = 1/0.9, ..., 3.333 = 1/0.3), then
# c11, c22, c23 for nu = 0, 0.25, 0.5.
_TABLE_E3_PRINTED = (
    (0.1, 2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731),
    (0.2, 2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809),
    (0.3, 2.68, 3.44, 4.80, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889),
    (0.4, 2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.720, 0.823, 0.977),
    (0.5, 2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07),
    (0.6, 2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.930, 1.03, 1.18),
    (0.7, 3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29),
    (0.8, 3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40),
    (0.9, 3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51),
    (1.0, 3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63),
    (1.111, 3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77),
    (1.25, 3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94),
    (1.429, 3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18),
    (1.667, 4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50),
    (2.0, 4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96),
    (2.5, 4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70),
    (3.333, 5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01),
    (5.0, 6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89),
    (10.0, 10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0),
)


def _build_table() -> np.ndarray:
    table = np.array(_TABLE_E3_PRINTED, dtype=float)
    # The a > b rows are the nodes g = b/a = 0.9, 0.8, ..., 0.1; store a/b = 1/g exactly so
    # that linear interpolation in g hits the nodes exactly.
    upper = table[:, 0] > 1.0
    table[upper, 0] = 1.0 / np.round(1.0 / table[upper, 0], 1)
    table.setflags(write=False)
    return table


#: Kalker 1990 Table E.3, shape (19, 10): ``a/b``, ``c11(nu=0, 0.25, 0.5)``,
#: ``c22(...)``, ``c23(...)``. The ``a/b > 1`` rows hold ``a/b = 1/g`` exactly (1/0.9 for the
#: printed 1.111, and so on). Read-only.
KALKER_TABLE_E3 = _build_table()


def _lagrange_weights(poisson: float) -> tuple[float, float, float]:
    """Quadratic Lagrange weights through nu = 0, 0.25, 0.5 (nu clamped to [0, 0.5])."""
    nu = min(max(float(poisson), 0.0), 0.5)
    n0, n1, n2 = KALKER_POISSON_NODES
    w0 = (nu - n1) * (nu - n2) / ((n0 - n1) * (n0 - n2))
    w1 = (nu - n0) * (nu - n2) / ((n1 - n0) * (n1 - n2))
    w2 = (nu - n0) * (nu - n1) / ((n2 - n0) * (n2 - n1))
    return w0, w1, w2


def kalker_table_for_poisson(poisson: float) -> np.ndarray:
    """Kalker's table reduced to one Poisson's ratio.

    Each coefficient at each ``a/b`` node is ``1 / sum_k L_k(nu) / c(nu_k)`` with the quadratic
    Lagrange basis ``L_k`` through ``nu_k = 0, 0.25, 0.5`` (docs/theory.md section 4.2).

    Args:
        poisson: Poisson's ratio ``nu`` [-], clamped to ``[0, 0.5]``.

    Returns:
        ``(19, 4)`` array, rows ``[a_over_b, c11, c22, c23]`` with ``a_over_b`` increasing from
        0.1 to 10 (row 9 is ``a/b = 1``). Input of :func:`kalker_coefficients_nb`.
    """
    w = _lagrange_weights(poisson)
    src = KALKER_TABLE_E3
    out = np.empty((src.shape[0], 4))
    out[:, 0] = src[:, 0]
    for j in range(3):
        cols = src[:, 1 + 3 * j : 4 + 3 * j]
        out[:, 1 + j] = 1.0 / (w[0] / cols[:, 0] + w[1] / cols[:, 1] + w[2] / cols[:, 2])
    return out


def _interpolate_reduced(table: np.ndarray, a_over_b: float) -> tuple[float, float, float]:
    """Linear interpolation in g = min(a/b, b/a) within the proper half of a reduced table."""
    r = float(a_over_b)
    if not r > 0.0:
        raise ValueError(f"a/b must be positive, got {a_over_b}")
    ratios = table[:, 0]
    if r <= 1.0:
        half = table[ratios <= 1.0]
        g_nodes = half[:, 0]
        g = r
    else:
        half = table[ratios >= 1.0][::-1]  # g = b/a increasing: a/b = 10 .. 1
        g_nodes = 1.0 / half[:, 0]
        g = 1.0 / r
    # np.interp clamps outside [g_nodes[0], g_nodes[-1]] = [0.1, 1].
    c11 = float(np.interp(g, g_nodes, half[:, 1]))
    c22 = float(np.interp(g, g_nodes, half[:, 2]))
    c23 = float(np.interp(g, g_nodes, half[:, 3]))
    return c11, c22, c23


def kalker_coefficients(a_over_b: float, poisson: float) -> tuple[float, float, float]:
    """Kalker's creepage coefficients ``(c11, c22, c23)`` [-] (Kalker 1990, Table E.3).

    Interpolation and clamping as in the module doc: quadratic Lagrange of ``1/c`` in ``nu``
    through 0, 0.25, 0.5, then linear in ``g = min(a/b, b/a)`` within the ``a <= b`` or
    ``a > b`` half of the table; ``a/b`` outside ``[0.1, 10]`` and ``nu`` outside ``[0, 0.5]``
    are clamped.

    Args:
        a_over_b: ratio of the semi-axes, ``a`` along the rolling direction, ``b`` lateral [-].
        poisson: Poisson's ratio [-] (steel 0.28-0.30).

    Returns:
        ``(c11, c22, c23)``. ``kalker_coefficients(1.0, 0.28)`` = (4.226, 3.705, 1.488).
    """
    return _interpolate_reduced(kalker_table_for_poisson(poisson), a_over_b)


@numba.njit(cache=True)
def kalker_coefficients_nb(table: np.ndarray, a_over_b: float) -> tuple[float, float, float]:
    """Compiled :func:`kalker_coefficients` on a table from :func:`kalker_table_for_poisson`.

    Same interpolation and clamping (``g`` to ``[0.1, 1]``); non-positive or NaN ``a/b`` are
    treated as ``a/b -> 0`` (first row). Allocation-free.

    Args:
        table: ``(n, 4)`` rows ``[a_over_b, c11, c22, c23]``, ``a_over_b`` increasing and
            containing the node ``a/b = 1``.
        a_over_b: semi-axis ratio ``a/b`` [-].

    Returns:
        ``(c11, c22, c23)``.
    """
    n = table.shape[0]
    r = a_over_b
    if not r > 0.0:
        r = 0.0
    if r <= 1.0:
        # rows with a/b <= 1, g = a/b increasing with the row index
        if r <= table[0, 0]:
            return table[0, 1], table[0, 2], table[0, 3]
        i = 0
        while i < n - 2 and table[i + 1, 0] < r:
            i += 1
        g0 = table[i, 0]
        g1 = table[i + 1, 0]
        g = r
    else:
        if r >= table[n - 1, 0]:
            return table[n - 1, 1], table[n - 1, 2], table[n - 1, 3]
        i = n - 2
        while i > 0 and table[i, 0] > r:
            i -= 1
        # rows i (a/b <= r) and i + 1 (a/b > r); g = b/a decreases with the row index
        g0 = 1.0 / table[i, 0]
        g1 = 1.0 / table[i + 1, 0]
        g = 1.0 / r
    w = (g - g0) / (g1 - g0)
    c11 = table[i, 1] + w * (table[i + 1, 1] - table[i, 1])
    c22 = table[i, 2] + w * (table[i + 1, 2] - table[i, 2])
    c23 = table[i, 3] + w * (table[i + 1, 3] - table[i, 3])
    return c11, c22, c23


def kalker_linear_forces(
    xi: float,
    eta: float,
    spin_per_m: float,
    a_m: float,
    b_m: float,
    shear_modulus_Pa: float,
    c11: float,
    c22: float,
    c23: float,
) -> tuple[float, float]:
    """Kalker's linear creep forces on the wheel [N] (Kalker 1990; docs/conventions.md).

    ``Fx = -G a b c11 xi``, ``Fy = -G a b c22 eta - G (ab)^(3/2) c23 phi``. Works element-wise on
    numpy arrays as well.

    Args:
        xi: longitudinal creepage [-].
        eta: lateral creepage [-].
        spin_per_m: spin creepage ``phi`` [1/m].
        a_m: semi-axis along the rolling direction [m].
        b_m: lateral semi-axis [m].
        shear_modulus_Pa: combined shear modulus ``G`` [Pa] (steel about 8.1e10).
        c11: Kalker coefficient, longitudinal [-].
        c22: Kalker coefficient, lateral [-].
        c23: Kalker coefficient, lateral-spin [-].

    Returns:
        ``(Fx, Fy)`` on the wheel in the contact frame [N].
    """
    gab = shear_modulus_Pa * a_m * b_m
    fx = -gab * c11 * xi
    fy = -gab * c22 * eta - gab * np.sqrt(a_m * b_m) * c23 * spin_per_m
    return fx, fy


@numba.njit(cache=True)
def kalker_linear_nb(
    xi: float,
    eta: float,
    phi: float,
    a: float,
    b: float,
    G: float,
    c11: float,
    c22: float,
    c23: float,
) -> tuple[float, float]:
    """Compiled :func:`kalker_linear_forces` (scalars; force on the wheel [N])."""
    gab = G * a * b
    return -gab * c11 * xi, -gab * c22 * eta - gab * math.sqrt(a * b) * c23 * phi
