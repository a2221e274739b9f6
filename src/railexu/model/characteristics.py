"""Force characteristics of the nonlinear suspension elements as tables (SI units).

A characteristic given as points ``(x, f)`` (deflection [m] or velocity [m/s] against force
[N]) becomes an ``(n, 2)`` table that the compiled force functions
(:mod:`railexu.model.suspension_forces`) and the statics (:mod:`railexu.model.statics`) evaluate
piecewise-linearly, end slopes continued; ``"smooth"`` tables sample the monotone cubic through
the points (PCHIP, Fritsch and Carlson 1980, Monotone piecewise cubic interpolation, SIAM J.
Numer. Anal. 17, 238-246).
"""

from __future__ import annotations

import numpy as np


def smooth_table(x, f, per_interval: int = 16) -> np.ndarray:
    """A table of the monotone cubic (PCHIP, Fritsch and Carlson 1980) through ``(x, f)``,
    sampled at ``per_interval`` points per interval: piecewise-linear in the kernel, with the
    same end slopes continued (``scipy.interpolate.PchipInterpolator``)."""
    from scipy.interpolate import PchipInterpolator

    x = np.asarray(x, float)
    f = np.asarray(f, float)
    pchip = PchipInterpolator(x, f)
    pieces = [np.linspace(x[i], x[i + 1], per_interval, endpoint=False) for i in range(len(x) - 1)]
    xs = np.concatenate([*pieces, x[-1:]])
    return np.column_stack([xs, pchip(xs)])


def characteristic_table(x, f, interpolation: str) -> np.ndarray:
    """The ``(n, 2)`` kernel table of a characteristic (``"linear"`` or ``"smooth"``)."""
    if interpolation == "smooth" and len(x) > 2:
        return smooth_table(x, f)
    return np.column_stack([np.asarray(x, float), np.asarray(f, float)])


def table_force(table: np.ndarray, x: float) -> float:
    """The kernel's piecewise-linear value of an ``(n, 2)`` table at ``x`` (end slopes
    continued), in Python."""
    t = np.asarray(table, float)
    if x <= t[0, 0]:
        i = 0
    elif x >= t[-1, 0]:
        i = len(t) - 2
    else:
        i = int(np.searchsorted(t[:, 0], x, side="right")) - 1
    (x0, f0), (x1, f1) = t[i], t[i + 1]
    return float(f0 + (f1 - f0) * (x - x0) / (x1 - x0))
