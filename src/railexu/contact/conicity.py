r"""Equivalent conicity from the rolling radius difference ``Delta r(y)`` (EN 15302).

Two methods are offered; the default is the one EN 15302 qualifies with its reference cases:

``"nonlinear"`` (default): the *integral method*, the nonlinear wavelength of EN 15302 (its
    annex on the calculation by integration of the nonlinear equation of the wheelset's kinematic
    motion; the same method as the published open implementation B_ECC). A wheelset rolling
    without creep obeys Klingel's equation ``y'' = -Delta r(y) / (2 e0 r0)`` along the track. With
    the potential ``V(y) = int_{y_eq}^{y} Delta r dy'`` (``y_eq``: the equilibrium position, where
    ``Delta r = 0``; for an asymmetric wheelset it is not the track centre), a kinematic
    oscillation between the turning points ``y_min < y_max`` of equal potential
    ``V(y_min) = V(y_max)`` has the amplitude ``A = (y_max - y_min)/2`` and the wavelength
    ``lambda = 2 int_{y_min}^{y_max} dy / sqrt((V(y_min) - V(y)) / (e0 r0))``. The equivalent
    conicity is that of the cone pair with the same wavelength, ``lambda = 2 pi sqrt(e0 r0 /
    gamma_e)``, so

        ``gamma_e(A) = 2 pi^2 / L^2``,  ``L = 2 int_{y_min}^{y_max} dy / sqrt(2 (V(y_min) - V(y)))``

    in which ``e0 r0`` cancels: only ``Delta r(y)`` is needed. A jump of ``Delta r`` (the contact
    point onto the flange root) is a kink of ``V`` and does no harm. The integral is taken with
    ``y = c - h cos(theta)``, which removes the inverse square-root singularities at the turning
    points, by the midpoint rule in ``theta``; ``V`` is integrated exactly from the piecewise
    linear ``Delta r`` table. ``Delta r`` is never extrapolated: an amplitude whose turning points
    leave the table is an error (or NaN on request). Where ``Delta r`` vanishes over the whole
    oscillation (a dead band) the wavelength is infinite and ``gamma_e = 0``.

``"harmonic"``: harmonic linearisation, ``gamma_e = b1 / (2 A)`` with the first Fourier
    coefficient ``b1`` of ``Delta r(A sin tau)`` about ``y = 0``; kept for comparison (it fails the
    EN 15302 band where ``Delta r`` jumps, and it cannot treat an asymmetric wheelset).

For a pure cone pair, ``Delta r = 2 gamma y``, both return ``gamma`` for every amplitude.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.quasistatic import ContactSolveError, rolling_radius_difference
from railexu.errors import InputError

__all__ = [
    "CONICITY_METHODS",
    "ConicityError",
    "equilibrium_lateral",
    "equivalent_conicity",
    "equivalent_conicity_from_delta_r",
]

#: Methods of :func:`equivalent_conicity_from_delta_r`.
CONICITY_METHODS = ("nonlinear", "harmonic")


class ConicityError(InputError):
    """A ``Delta r`` table or amplitude the conicity cannot be computed from."""


def _check_table(lateral_m, delta_r_m, amplitudes_m):
    y = np.asarray(lateral_m, dtype=float)
    dr = np.asarray(delta_r_m, dtype=float)
    amps = np.atleast_1d(np.asarray(amplitudes_m, dtype=float))
    if y.ndim != 1 or y.shape != dr.shape or y.size < 2:
        raise ConicityError("lateral positions and Delta r must be 1-D arrays of equal length >= 2")
    if np.any(np.diff(y) <= 0):
        raise ConicityError("lateral positions must be strictly increasing")
    if np.any(amps <= 0.0):
        raise ConicityError("amplitudes must be > 0")
    return y, dr, amps


def _harmonic(y, dr, amps, n_quadrature):
    if amps.max() > max(-y[0], y[-1]) + 1e-12:
        raise ConicityError(
            f"amplitude {amps.max() * 1e3:.2f} mm exceeds the tabulated range "
            f"[{y[0] * 1e3:.2f}, {y[-1] * 1e3:.2f}] mm"
        )
    # midpoint rule on a periodic integrand: spectrally accurate for smooth Delta r
    tau = (np.arange(n_quadrature) + 0.5) * (2.0 * np.pi / n_quadrature)
    sin_tau = np.sin(tau)
    out = np.empty(amps.size)
    for i, a in enumerate(amps):
        values = np.interp(a * sin_tau, y, dr)
        out[i] = np.mean(values * sin_tau)  # b1 / 2 = mean(dr sin) ; gamma = b1 / (2 A)
        out[i] = 2.0 * out[i] / (2.0 * a)
    return out


class _Potential:
    """``V(y) = int_{y_0}^{y} Delta r`` for a piecewise linear ``Delta r`` (exact)."""

    def __init__(self, y: np.ndarray, dr: np.ndarray) -> None:
        ye, de = y, dr
        self.y, self.dr = ye, de
        self.slope = np.diff(de) / np.diff(ye)
        self.v = np.concatenate([[0.0], np.cumsum(0.5 * (de[:-1] + de[1:]) * np.diff(ye))])

    def __call__(self, y):
        y = np.asarray(y, dtype=float)
        i = np.clip(np.searchsorted(self.y, y, side="right") - 1, 0, self.y.size - 2)
        h = y - self.y[i]
        return self.v[i] + self.dr[i] * h + 0.5 * self.slope[i] * h * h

    def delta_r(self, y):
        return np.interp(y, self.y, self.dr)


def _equilibrium(pot: _Potential) -> float:
    """The lateral position where ``Delta r = 0`` (minimum of V); the crossing nearest y = 0."""
    y, dr = pot.y, pot.dr
    change = np.nonzero((dr[:-1] <= 0.0) & (dr[1:] > 0.0))[0]
    if change.size == 0:
        raise ConicityError(
            "Delta r does not change sign from negative to positive: the wheelset has no "
            "equilibrium position within the table"
        )
    i = change[np.argmin(np.abs(y[change]))]
    if dr[i] == 0.0:
        return float(y[i])
    return float(y[i] - dr[i] * (y[i + 1] - y[i]) / (dr[i + 1] - dr[i]))


def _nonlinear(y, dr, amps, n_quadrature, out_of_range):
    pot = _Potential(y, dr)
    y_eq = _equilibrium(pot)
    lo_lim, hi_lim = pot.y[0], pot.y[-1]
    theta = (np.arange(n_quadrature) + 0.5) * (np.pi / n_quadrature)
    cos_t, sin_t = np.cos(theta), np.sin(theta)
    out = np.empty(amps.size)
    for k, amp in enumerate(amps):
        width = 2.0 * amp

        def mismatch(y_min: float, width: float = width) -> float:
            return float(pot(y_min + width) - pot(y_min))

        a_lo = max(lo_lim, y_eq - width)
        a_hi = min(y_eq, hi_lim - width)
        if not a_lo < a_hi or mismatch(a_lo) > 0.0 or mismatch(a_hi) < 0.0:
            if out_of_range == "nan":
                out[k] = np.nan
                continue
            raise ConicityError(
                f"no kinematic oscillation of amplitude {amp * 1e3:.2f} mm within the Delta r "
                f"table [{y[0] * 1e3:.2f}, {y[-1] * 1e3:.2f}] mm"
            )
        y_min = brentq(mismatch, a_lo, a_hi, xtol=1e-15, rtol=1e-13)
        level = float(pot(y_min) - pot(y_eq))
        if not level > 1e-15 * amp * amp:  # Delta r = 0 over the whole oscillation: dead band
            out[k] = 0.0
            continue
        level = float(pot(y_min))
        centre, half = y_min + amp, amp
        yy = centre - half * cos_t
        gap = np.maximum(level - pot(yy), 0.0)
        with np.errstate(divide="ignore"):
            integrand = np.where(gap > 0.0, half * sin_t / np.sqrt(2.0 * gap), 0.0)
        length = 2.0 * np.sum(integrand) * (np.pi / n_quadrature)
        out[k] = 2.0 * np.pi**2 / length**2
    return out


def equivalent_conicity_from_delta_r(
    lateral_m: np.ndarray,
    delta_r_m: np.ndarray,
    amplitudes_m: np.ndarray,
    n_quadrature: int = 2000,
    method: str = "nonlinear",
    out_of_range: str = "raise",
) -> np.ndarray:
    """Equivalent conicity [-] for each amplitude [m] from a tabulated ``Delta r(y)`` [m].

    Args:
        lateral_m: increasing lateral positions of the wheelset [m] (positive to the left).
        delta_r_m: ``r_left - r_right`` at those positions [m].
        amplitudes_m: amplitudes ``A = (y_max - y_min)/2`` of the oscillation [m].
        n_quadrature: points of the quadrature rule.
        method: ``"nonlinear"`` (EN 15302 integral method, about the equilibrium position) or
            ``"harmonic"`` (harmonic linearisation about ``y = 0``); module doc.
        out_of_range: ``"raise"`` or ``"nan"``: what an amplitude whose oscillation leaves the
            table gives (nonlinear method).

    Raises:
        ConicityError: bad table or amplitude, unknown method, no equilibrium position.
    """
    y, dr, amps = _check_table(lateral_m, delta_r_m, amplitudes_m)
    if method == "nonlinear":
        if out_of_range not in ("raise", "nan"):
            raise ConicityError(f"out_of_range must be 'raise' or 'nan', got {out_of_range!r}")
        return _nonlinear(y, dr, amps, n_quadrature, out_of_range)
    if method == "harmonic":
        return _harmonic(y, dr, amps, max(n_quadrature, 720))
    raise ConicityError(f"unknown conicity method {method!r}; valid: {', '.join(CONICITY_METHODS)}")


def equilibrium_lateral(model: WheelsetContactModel, search_m: float = 0.005) -> float:
    """Equilibrium lateral position [m] of a wheelset on its rails: ``Delta r(y) = 0``.

    Zero for a symmetric wheelset; for different radii or profiles left and right the position
    where both wheels roll on the same radius (searched within ``+-search_m``).
    """

    def f(y: float) -> float:
        return float(rolling_radius_difference(model, np.array([y]))[0])

    f0 = f(0.0)
    if abs(f0) < 1e-12:
        return 0.0
    lo, hi = -search_m, search_m
    if f(lo) * f(hi) > 0.0:
        raise ConicityError(
            f"no equilibrium position within +-{search_m * 1e3:.1f} mm: Delta r does not change "
            "sign (are the wheel radii or profiles very different?)"
        )
    return float(brentq(f, lo, hi, xtol=1e-8))


def equivalent_conicity(
    model: WheelsetContactModel,
    amplitudes_m: np.ndarray,
    step_m: float = 1.0e-4,
    method: str = "nonlinear",
    out_of_range: str = "raise",
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Equivalent conicity of a wheelset on its rails for each amplitude.

    ``Delta r(y)`` is tabulated from the rigid contact over ``y_eq +- (max(A) + 2 mm)`` around the
    equilibrium position ``y_eq`` (:func:`equilibrium_lateral`; 0 for a symmetric wheelset; the
    table stops where a wheel leaves its rail), and the conicity follows by
    :func:`equivalent_conicity_from_delta_r`.

    Returns ``(conicity, lateral_m, delta_r_m)``: the conicity per amplitude and the table.
    """
    amps = np.atleast_1d(np.asarray(amplitudes_m, dtype=float))
    y_eq = equilibrium_lateral(model) if method == "nonlinear" else 0.0
    reach = float(amps.max()) + (2.0e-3 if method == "nonlinear" else 0.0)
    n = int(np.ceil(reach / step_m))
    y = y_eq + np.linspace(-n * step_m, n * step_m, 2 * n + 1)
    keep = np.ones(y.size, dtype=bool)
    dr = np.zeros(y.size)
    for i, yi in enumerate(y):
        try:
            dr[i] = rolling_radius_difference(model, np.array([yi]))[0]
        except ContactSolveError:
            keep[i] = False
    y, dr = y[keep], dr[keep]
    gamma = equivalent_conicity_from_delta_r(y, dr, amps, method=method, out_of_range=out_of_range)
    return gamma, y, dr
