"""Signal helpers on a distance axis: sliding means and rms, zero crossings, amplitude.

Every function takes the distance travelled (m, non-decreasing, possibly non-uniform) and the
samples; the signal is piecewise linear between samples where an integral is needed.

**Amplitude** has one definition in railexu (:func:`amplitude`): half the peak-to-peak range of
the samples in a window, ``(max - min) / 2``. The summary, the hunting detection and the
critical-speed methods all use it.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Zero crossings are counted with a hysteresis of this fraction of the signal's peak.
CROSSING_HYSTERESIS = 0.01


def amplitude(values: ArrayLike) -> float:
    """Amplitude of an oscillation: half its peak-to-peak range ``(max - min) / 2`` over the
    samples given (same unit as ``values``); non-finite samples are ignored, 0 if none is left.

    A sine ``A sin(.)`` over at least half a period has amplitude ``A``; a constant offset has
    amplitude 0 (an offset is not an oscillation)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return 0.5 * float(np.max(v) - np.min(v)) if v.size else 0.0


def _check_axis(x_m: ArrayLike, values: ArrayLike) -> tuple[FloatArray, FloatArray]:
    x = np.asarray(x_m, dtype=float)
    v = np.asarray(values, dtype=float)
    if x.ndim != 1 or v.shape != x.shape:
        raise ValueError(f"x and values must be 1-D of equal length, got {x.shape}, {v.shape}")
    if x.size > 1 and np.any(np.diff(x) < 0):
        raise ValueError("the distance axis must be non-decreasing")
    return x, v


def _locate(x: FloatArray, t: FloatArray) -> tuple[NDArray[np.intp], FloatArray, FloatArray]:
    """Interval index k, offset u = t - x[k] and length dx of the interval holding each t."""
    k = np.clip(np.searchsorted(x, t, side="right") - 1, 0, x.size - 2)
    dx = x[k + 1] - x[k]
    return k, np.clip(t - x[k], 0.0, dx), dx


def _integral_at(
    v: FloatArray, cum: FloatArray, loc: tuple[NDArray[np.intp], FloatArray, FloatArray]
) -> FloatArray:
    """Exact integral from x[0] to t of the piecewise-linear interpolant of v (t located by
    :func:`_locate`; ``cum`` is the cumulative trapezoid integral at the samples)."""
    k, u, dx = loc
    safe = np.where(dx > 0, dx, 1.0)
    slope = np.where(dx > 0, (v[k + 1] - v[k]) / safe, 0.0)
    return cum[k] + v[k] * u + 0.5 * slope * u * u


def _window_integrals(
    x: FloatArray, v: FloatArray, a: FloatArray, b: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Integrals over ``[a, b]`` of the piecewise-linear signal with its non-finite samples set
    to zero, and of the indicator of finite samples: a window's mean over its finite part is
    their quotient."""
    valid = np.isfinite(v)
    v0 = np.where(valid, v, 0.0)
    w = valid.astype(float)
    dx = np.diff(x)
    cum_v = np.concatenate(([0.0], np.cumsum(0.5 * (v0[1:] + v0[:-1]) * dx)))
    cum_w = np.concatenate(([0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * dx)))
    loc_a, loc_b = _locate(x, a), _locate(x, b)
    num = _integral_at(v0, cum_v, loc_b) - _integral_at(v0, cum_v, loc_a)
    den = _integral_at(w, cum_w, loc_b) - _integral_at(w, cum_w, loc_a)
    return num, den


def _sliding(x_m: ArrayLike, values: ArrayLike, window_m: float) -> tuple[FloatArray, FloatArray]:
    """Sliding mean and the window centres; see :func:`sliding_mean`."""
    if not window_m > 0:
        raise ValueError(f"window_m must be > 0, got {window_m}")
    x, v = _check_axis(x_m, values)
    out = np.full(x.shape, np.nan)
    if x.size < 2 or (x[-1] - x[0]) < window_m * (1.0 - 1e-9):
        return out, out.copy()
    half = 0.5 * window_m
    lo_c, hi_c = x[0] + half, max(x[-1] - half, x[0] + half)
    centres = np.clip(x, lo_c, hi_c)
    a = np.clip(centres - half, x[0], x[-1])
    b = np.clip(centres + half, x[0], x[-1])
    num, den = _window_integrals(x, v, a, b)
    ok = den > 1e-9 * window_m
    out[ok] = num[ok] / den[ok]
    return out, centres


def sliding_mean(x_m: ArrayLike, values: ArrayLike, window_m: float) -> FloatArray:
    """Sliding mean of ``values`` over ``window_m`` metres of the distance axis ``x_m``.

    The signal is taken as piecewise linear between samples and integrated exactly, so the axis
    may be non-uniform (it must be non-decreasing). Each sample gets the mean over the window
    ``[x - w/2, x + w/2]`` centred on it; near the start and the end of the run the window is
    shifted inwards so that it stays **complete** (every value is a mean over a full
    ``window_m``; the first and last windows ``[x0, x0 + w]`` and ``[x_end - w, x_end]`` are
    both evaluated). If the run is shorter than the window, the result is all NaN.

    Non-finite samples are left out: the mean is taken over the finite part of the window only
    (NaN where the window has no finite sample).

    Args:
        x_m: distance along the track (m), non-decreasing.
        values: samples at ``x_m`` (any unit; the result has the same unit).
        window_m: window length (m), > 0.

    Returns:
        Array of the same length as ``x_m``.
    """
    return _sliding(x_m, values, window_m)[0]


def sliding_rms(x_m: ArrayLike, values: ArrayLike, window_m: float) -> FloatArray:
    """Sliding root mean square of ``values`` over ``window_m`` metres: the square root of
    :func:`sliding_mean` of ``values**2`` (same window handling, same unit as ``values``)."""
    v = np.asarray(values, dtype=float)
    return np.sqrt(sliding_mean(x_m, v * v, window_m))


def _axis_mean(x: FloatArray, v: FloatArray) -> float:
    """Distance-weighted (trapezoid) mean of v; plain mean if the span is zero."""
    span = x[-1] - x[0] if x.size else 0.0
    if x.size < 2 or span <= 0:
        return float(np.mean(v)) if v.size else 0.0
    return float(np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(x)) / span)


def zero_crossings(
    distance_m: ArrayLike,
    signal: ArrayLike,
    *,
    remove_mean: bool = True,
    hysteresis: float = CROSSING_HYSTERESIS,
) -> FloatArray:
    """Distances (m) at which ``signal`` (minus its mean) crosses zero, linearly interpolated.

    A crossing is counted only when the signal goes from below ``-h`` to above ``+h`` (or back)
    with ``h = hysteresis * max|signal|``, so that numerical noise around a settled signal does
    not count; the crossing itself is interpolated at the zero between those samples.
    """
    x, s = _check_axis(distance_m, signal)
    keep = np.isfinite(s)
    x, s = x[keep], s[keep]
    if x.size < 2:
        return np.empty(0)
    if remove_mean:
        s = s - _axis_mean(x, s)
    peak = float(np.max(np.abs(s)))
    if peak <= 0:
        return np.empty(0)
    h = hysteresis * peak
    state = np.where(s > h, 1, np.where(s < -h, -1, 0))
    idx = np.flatnonzero(state)
    flips = np.flatnonzero(state[idx[1:]] != state[idx[:-1]])
    out = np.empty(flips.size)
    for n, f in enumerate(flips):
        i, j = idx[f], idx[f + 1]
        seg = s[i : j + 1]
        # last sign change between sample i and j (exactly one for a clean signal)
        ch = np.flatnonzero(np.sign(seg[1:]) != np.sign(seg[:-1]))
        k = i + int(ch[-1])
        s0, s1 = s[k], s[k + 1]
        out[n] = x[k] if s1 == s0 else x[k] + (x[k + 1] - x[k]) * s0 / (s0 - s1)
    return out


def zero_crossing_wavelength(
    distance_m: ArrayLike,
    signal: ArrayLike,
    *,
    min_periods: float = 1.0,
    remove_mean: bool = True,
    hysteresis: float = CROSSING_HYSTERESIS,
) -> float | None:
    """Wavelength (m) of an oscillation from the mean spacing of its zero crossings.

    Crossings of the signal minus its (distance-weighted) mean are interpolated linearly (see
    :func:`zero_crossings`); successive crossings are half a period apart, so the wavelength is
    ``2 (x_last - x_first) / (n - 1)`` for ``n`` crossings.

    Args:
        distance_m: distance along the track (m), non-decreasing.
        signal: the oscillating quantity (any unit).
        min_periods: at least this many full periods must be visible (``2 min_periods + 1``
            crossings), else None.
        remove_mean: subtract the mean before looking for crossings.
        hysteresis: noise band as a fraction of the peak, see :func:`zero_crossings`.

    Returns:
        The wavelength in m, or None if fewer crossings are found.
    """
    xc = zero_crossings(distance_m, signal, remove_mean=remove_mean, hysteresis=hysteresis)
    needed = max(2, int(math.ceil(2.0 * min_periods - 1e-9)) + 1)
    if xc.size < needed or xc[-1] <= xc[0]:
        return None
    return float(2.0 * (xc[-1] - xc[0]) / (xc.size - 1))


def window_means(
    x_m: ArrayLike,
    values: ArrayLike,
    window_m: float,
    step_m: float,
    start_m: float | None = None,
    end_m: float | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Means over windows of ``window_m`` placed every ``step_m`` metres (EN 14363's sliding mean
    over 2 m in 0.5 m steps).

    Windows ``[s, s + window_m]`` start at ``start_m`` (default: the first sample) and every
    ``step_m`` after it, as long as they end by ``end_m`` (default: the last sample). The signal is
    piecewise linear between samples and integrated exactly; non-finite samples are left out of a
    window's mean (NaN if a window has none).

    Returns:
        ``(centres_m, means)``: the centre of each window (m) and its mean (unit of ``values``);
        empty arrays if no complete window fits.
    """
    if not window_m > 0 or not step_m > 0:
        raise ValueError(f"window_m and step_m must be > 0, got {window_m}, {step_m}")
    x, v = _check_axis(x_m, values)
    if x.size < 2:
        return np.empty(0), np.empty(0)
    lo = x[0] if start_m is None else max(float(start_m), x[0])
    hi = x[-1] if end_m is None else min(float(end_m), x[-1])
    count = int(math.floor((hi - lo - window_m) / step_m + 1e-9)) + 1
    if count < 1:
        return np.empty(0), np.empty(0)
    a = lo + step_m * np.arange(count)
    b = a + window_m
    num, den = _window_integrals(x, v, a, b)
    out = np.full(count, np.nan)
    ok = den > 1e-9 * window_m
    out[ok] = num[ok] / den[ok]
    return a + 0.5 * window_m, out


def window_rms(
    x_m: ArrayLike,
    values: ArrayLike,
    window_m: float,
    step_m: float,
    start_m: float | None = None,
    end_m: float | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Root mean square over windows placed like :func:`window_means` (EN 14363 running
    stability: rms over 100 m in 10 m steps). Returns ``(centres_m, rms)``."""
    v = np.asarray(values, dtype=float)
    centres, ms = window_means(x_m, v * v, window_m, step_m, start_m, end_m)
    return centres, np.sqrt(ms)


def percentile(values: ArrayLike, q: float) -> float | None:
    """The ``q`` % percentile of the finite values (linear interpolation between order
    statistics, numpy's default), or None if there are none."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(np.percentile(v, q)) if v.size else None


def uniform_time_axis(
    time_s: ArrayLike, *signals: ArrayLike
) -> tuple[FloatArray, float, list[FloatArray]]:
    """Signals on a uniform time grid (for the filters): the recorded grid itself when it is
    uniform to 1e-6 of a step (a run's output grid, maybe but for its last row), else a linear
    interpolation onto a grid with the median step.

    Returns:
        ``(t, fs_Hz, resampled)``.
    """
    t = np.asarray(time_s, dtype=float)
    if t.size < 2:
        return t, math.nan, [np.asarray(s, dtype=float) for s in signals]
    dt = float(np.median(np.diff(t)))
    grid = t[0] + dt * np.arange(int(math.floor((t[-1] - t[0]) / dt + 1e-9)) + 1)
    if grid.size <= t.size and np.allclose(t[: grid.size], grid, rtol=0.0, atol=1e-6 * dt):
        return grid, 1.0 / dt, [np.asarray(s, dtype=float)[: grid.size] for s in signals]
    return grid, 1.0 / dt, [np.interp(grid, t, np.asarray(s, dtype=float)) for s in signals]
