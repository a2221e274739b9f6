"""Equivalent conicity by harmonic linearisation of the rolling radius difference (EN 15302).

For a wheelset moving sinusoidally, ``y = A sin(tau)``, the first harmonic of ``Delta r(y)`` is
``b1 sin(tau)`` with ``b1 = (1/pi) int_0^{2 pi} Delta r(A sin tau) sin tau d tau``. The equivalent
conicity is the conicity of the cone pair with the same first harmonic, ``Delta r = 2 gamma y``:

    gamma_e(A) = b1 / (2 A)

(EN 15302, harmonic linearisation; for a pure cone of slope gamma it returns gamma for every
amplitude). ``Delta r(y)`` comes from the rigid contact (:mod:`railexu.contact.quasistatic`) on a
fine grid of ``y`` and is interpolated linearly, so the jump of the contact point onto the flange
root is kept as the steep rise it is.
"""

from __future__ import annotations

import numpy as np

from .evaluation import WheelsetContactModel
from .quasistatic import rolling_radius_difference


def equivalent_conicity_from_delta_r(
    lateral_m: np.ndarray,
    delta_r_m: np.ndarray,
    amplitudes_m: np.ndarray,
    n_quadrature: int = 720,
) -> np.ndarray:
    """Equivalent conicity [-] for each amplitude [m] from a tabulated ``Delta r(y)`` [m].

    ``lateral_m`` must be increasing and cover ``[-max(A), max(A)]``.
    """
    y = np.asarray(lateral_m, dtype=float)
    dr = np.asarray(delta_r_m, dtype=float)
    amps = np.atleast_1d(np.asarray(amplitudes_m, dtype=float))
    if np.any(np.diff(y) <= 0):
        raise ValueError("lateral positions must be strictly increasing")
    if amps.max() > max(-y[0], y[-1]) + 1e-12:
        raise ValueError(
            f"amplitude {amps.max() * 1e3:.2f} mm exceeds the tabulated range "
            f"[{y[0] * 1e3:.2f}, {y[-1] * 1e3:.2f}] mm"
        )
    # midpoint rule on a periodic integrand: spectrally accurate for smooth Delta r
    tau = (np.arange(n_quadrature) + 0.5) * (2.0 * np.pi / n_quadrature)
    sin_tau = np.sin(tau)
    out = np.empty(amps.size)
    for i, a in enumerate(amps):
        if a <= 0.0:
            raise ValueError("amplitudes must be > 0")
        values = np.interp(a * sin_tau, y, dr)
        b1 = np.mean(values * sin_tau) * 2.0
        out[i] = b1 / (2.0 * a)
    return out


def equivalent_conicity(
    model: WheelsetContactModel,
    amplitudes_m: np.ndarray,
    step_m: float = 1.0e-4,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Equivalent conicity of a wheelset on its rails for each amplitude.

    Returns ``(conicity, lateral_m, delta_r_m)``: the conicity per amplitude and the ``Delta r(y)``
    table it came from (``y`` from ``-max(A)`` to ``+max(A)`` in steps of ``step_m``).
    """
    amps = np.atleast_1d(np.asarray(amplitudes_m, dtype=float))
    y_max = float(amps.max())
    n = int(np.ceil(y_max / step_m))
    y = np.linspace(-n * step_m, n * step_m, 2 * n + 1)
    dr = rolling_radius_difference(model, y)
    return equivalent_conicity_from_delta_r(y, dr, amps), y, dr
