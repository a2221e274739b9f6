"""An oscillation about a quasi-static position: its frequency, amplitude and growth rate from
a fitted envelope (docs/theory.md, "Oscillations: fitted envelope and growth rate").

:func:`fit_oscillation` takes a signal sampled in time (a wheelset's lateral displacement or
yaw angle, straight track or curve) and

1. finds the dominant frequency ``f0`` (periodogram peak of the linearly detrended signal,
   Hann window, at least two periods in the window);
2. removes the quasi-static position: a centred moving mean over one period ``1 / f0`` (which
   removes a sine of that period exactly and follows a curve's slowly changing offset);
3. band-passes the rest around ``f0`` (Butterworth, 4th order, ``0.6 f0`` to ``1.6 f0``,
   forward and backward) and takes the envelope as the magnitude of its analytic signal
   (Hilbert transform);
4. fits ``ln envelope = a + sigma t`` by least squares, one period at each end left out (the
   filter's and the Hilbert transform's end effects): ``sigma`` (1/s) is the growth rate, the
   amplitude is the fitted envelope extrapolated to the end of the window,
   ``exp(a + sigma t_end)``.

The classification (:func:`classify`) uses the growth per period ``sigma / f0`` (the
logarithmic decrement with the sign turned; ``-sigma / (2 pi f0)`` is the damping ratio of a
linear oscillation): ``growing`` above :data:`GROWTH_PER_PERIOD`, ``decaying`` below minus it,
else ``sustained``; ``below floor`` when the fitted amplitude is below the signal's floor;
``broad-band`` when less than :data:`NARROW_BAND_SHARE` of the power (quasi-static part
removed) lies within +-10 % of ``f0`` (a response to random irregularities, not one
oscillation). The tolerances are railexu's choices, stated here and in docs/assessment.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from railexu.assessment.filters import scipy_signal

#: An amplitude change of less than 1 % per period counts as sustained (railexu's choice;
#: the damping ratio of such an oscillation is below 0.0016 in magnitude).
GROWTH_PER_PERIOD = 0.01
#: Share of the power (quasi-static part removed) within +-10 % of f0 above which the motion is
#: one oscillation (railexu's choice, as in :mod:`railexu.assessment.hunting`).
NARROW_BAND_SHARE = 0.5
#: Lowest frequency looked for (Hz): below it a "period" is a curve transition, not an
#: oscillation.
MIN_FREQUENCY_HZ = 0.3


@dataclass
class OscillationFit:
    """A fitted oscillation (SI units): ``frequency_Hz``, ``amplitude`` (fitted envelope at the
    window's end, unit of the signal), ``mean_amplitude`` (mean envelope), ``growth_rate_per_s``
    (sigma), ``growth_per_period`` (sigma / f0), ``narrow_band_share``, ``offset`` (mean
    quasi-static position), ``window_s`` ([start, end] of the fit) and ``status``."""

    frequency_Hz: float | None = None
    amplitude: float = 0.0
    mean_amplitude: float = 0.0
    growth_rate_per_s: float | None = None
    growth_per_period: float | None = None
    narrow_band_share: float | None = None
    offset: float | None = None
    window_s: tuple[float, float] | None = None
    status: str = "no oscillation"

    def to_dict(self) -> dict:
        def num(v):
            return float(v) if v is not None and math.isfinite(v) else None

        return {
            "status": self.status,
            "frequency_Hz": num(self.frequency_Hz),
            "amplitude": num(self.amplitude),
            "mean_amplitude": num(self.mean_amplitude),
            "growth_rate_per_s": num(self.growth_rate_per_s),
            "growth_per_period": num(self.growth_per_period),
            "narrow_band_share": num(self.narrow_band_share),
            "offset": num(self.offset),
            "window_s": None if self.window_s is None else [float(v) for v in self.window_s],
        }


def _uniform(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The signal on a uniform time grid of the median step."""
    dt = float(np.median(np.diff(t)))
    n = int(round((t[-1] - t[0]) / dt)) + 1
    grid = t[0] + dt * np.arange(n)
    return grid, np.interp(grid, t, y), dt


def dominant_frequency(y: np.ndarray, dt: float) -> float | None:
    """Frequency (Hz) of the periodogram's peak of ``y`` (linear trend removed, Hann window),
    searched above :data:`MIN_FREQUENCY_HZ` and above two periods in the window."""
    f, p = scipy_signal().periodogram(y, fs=1.0 / dt, window="hann", detrend="linear")
    lowest = max(MIN_FREQUENCY_HZ, 2.0 / (y.size * dt))
    ok = f >= lowest
    if not np.any(ok) or not np.max(p[ok]) > 0.0:
        return None
    k = int(np.argmax(np.where(ok, p, -1.0)))
    if 0 < k < f.size - 1:  # parabolic interpolation of the peak on the log power
        a, b, c = np.log(np.maximum(p[k - 1 : k + 2], 1e-300))
        denom = a - 2.0 * b + c
        if denom < 0.0:
            return float(f[k] + 0.5 * (a - c) / denom * (f[1] - f[0]))
    return float(f[k])


def _moving_mean(y: np.ndarray, width: int) -> np.ndarray:
    """Centred moving mean over ``width`` samples (ends: the shorter window available)."""
    width = max(1, min(width, y.size))
    c = np.concatenate([[0.0], np.cumsum(y)])
    half = width // 2
    lo = np.clip(np.arange(y.size) - half, 0, y.size)
    hi = np.clip(lo + width, 0, y.size)
    lo = np.clip(hi - width, 0, y.size)
    return (c[hi] - c[lo]) / (hi - lo)


def fit_oscillation(t_s: ArrayLike, y: ArrayLike, floor: float) -> OscillationFit:
    """Fit the dominant oscillation of ``y`` against time ``t_s`` (s); see the module docstring.

    ``floor`` (unit of ``y``) is the amplitude below which the motion is not reported. Needs
    at least four periods and 32 samples, else the status is ``"too short"``."""
    t, v = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
    keep = np.isfinite(t) & np.isfinite(v)
    t, v = t[keep], v[keep]
    out = OscillationFit()
    if t.size < 32 or not t[-1] > t[0]:
        out.status = "too short"
        return out
    grid, u, dt = _uniform(t, v)
    f0 = dominant_frequency(u, dt)
    if f0 is None or (grid[-1] - grid[0]) * f0 < 4.0 or f0 > 0.4 / dt:
        out.status = "too short" if f0 is not None else "no oscillation"
        return out
    period = max(1, int(round(1.0 / (f0 * dt))))
    quasi_static = _moving_mean(u, period)
    rest = u - quasi_static
    out.frequency_Hz, out.offset = f0, float(np.mean(quasi_static))
    sig = scipy_signal()
    nyq = 0.5 / dt
    sos = sig.butter(4, [0.6 * f0 / nyq, min(1.6 * f0 / nyq, 0.99)], btype="band", output="sos")
    band = sig.sosfiltfilt(sos, rest)
    total = float(np.sum(rest[period:-period] ** 2)) if rest.size > 2 * period else 0.0
    f, p = sig.periodogram(rest, fs=1.0 / dt, window="hann", detrend="constant")
    if np.sum(p[1:]) > 0.0:
        near = np.abs(f[1:] - f0) <= max(0.1 * f0, 2.5 * (f[1] - f[0]))
        out.narrow_band_share = float(np.sum(p[1:][near]) / np.sum(p[1:]))
    envelope = np.abs(sig.hilbert(band))
    inner = slice(period, envelope.size - period)
    te, env = grid[inner], envelope[inner]
    if te.size < 8 or total == 0.0 or not np.all(env > 0.0):
        out.status = "no oscillation"
        return out
    slope, intercept = np.polyfit(te - te[0], np.log(env), 1)
    out.growth_rate_per_s = float(slope)
    out.growth_per_period = float(slope / f0)
    out.amplitude = float(np.exp(intercept + slope * (grid[-1] - te[0])))
    out.mean_amplitude = float(np.mean(env))
    out.window_s = (float(te[0]), float(te[-1]))
    out.status = classify(out, floor)
    return out


def classify(fit: OscillationFit, floor: float) -> str:
    """``below floor``, ``broad-band``, ``growing``, ``decaying`` or ``sustained`` (module
    docstring)."""
    if fit.growth_per_period is None:
        return fit.status
    if fit.amplitude < floor and fit.mean_amplitude < floor:
        return "below floor"
    if fit.narrow_band_share is not None and fit.narrow_band_share < NARROW_BAND_SHARE:
        return "broad-band"
    if fit.growth_per_period > GROWTH_PER_PERIOD:
        return "growing"
    if fit.growth_per_period < -GROWTH_PER_PERIOD:
        return "decaying"
    return "sustained"
