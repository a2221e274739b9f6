"""Filters of the assessment: Butterworth low- and band-pass, and the frequency weightings of
ride comfort, all with :mod:`scipy.signal`.

- :func:`lowpass` and :func:`bandpass`: Butterworth filters run forwards and backwards
  (``sosfiltfilt``, no phase shift: a peak stays where it occurred along the track, which is what
  a "where it occurred" needs). The magnitude is the square of the single filter's.
- :func:`weighting_zpk`, :func:`weighting_gain`, :func:`weight`: the frequency weightings
  ``Wb`` (vertical), ``Wc`` (longitudinal), ``Wd`` (horizontal) of EN 12299:2009 (section 5 and
  annex A) and ISO 2631-1:1997 / ISO 2631-4:2001 (annex A), built from their analogue definition
  (band limiting, acceleration-velocity transition, upward step, gain K) and made digital with
  the bilinear transform. Weighting runs forwards only (``sosfilt``): the standards define a
  causal filter whose magnitude is the weighting, and a zero-phase filter would square it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Order of the Butterworth low- and band-pass filters (railexu's choice; each runs forwards and
#: backwards, so the roll-off is that of twice this order).
BUTTERWORTH_ORDER = 4


@dataclass(frozen=True)
class Weighting:
    """Parameters of a frequency weighting (EN 12299:2009 annex A, ISO 2631-1:1997 annex A,
    ISO 8041): band limiting high pass ``f1`` / low pass ``f2`` (Q = 1/sqrt(2)), acceleration-
    velocity transition ``f3, f4, Q4``, upward step ``f5, Q5, f6, Q6`` (``inf`` = none), gain
    ``K``. Frequencies in Hz."""

    name: str
    f1: float
    f2: float
    f3: float
    f4: float
    q4: float
    f5: float
    q5: float
    f6: float
    q6: float
    k: float


#: The weightings of EN 12299 (and ISO 2631): Wb vertical, Wd lateral (and longitudinal on the
#: floor), Wc longitudinal at the seat back. Values of the standards.
WEIGHTINGS = {
    "Wb": Weighting("Wb", 0.4, 100.0, 16.0, 16.0, 0.55, 2.5, 0.9, 4.0, 0.95, 1.024),
    "Wc": Weighting("Wc", 0.4, 100.0, 8.0, 8.0, 0.63, math.inf, 1.0, math.inf, 1.0, 1.0),
    "Wd": Weighting("Wd", 0.4, 100.0, 2.0, 2.0, 0.63, math.inf, 1.0, math.inf, 1.0, 1.0),
}


def _weighting(name: str) -> Weighting:
    try:
        return WEIGHTINGS[name]
    except KeyError:
        raise ValueError(
            f"unknown weighting {name!r}; expected one of {sorted(WEIGHTINGS)}"
        ) from None


def weighting_zpk(name: str, band_limit_low_pass: bool = True) -> tuple[list, list, float]:
    """Zeros, poles (rad/s) and gain of the analogue weighting ``name`` (``Wb``, ``Wc``, ``Wd``).

    ``H(s) = Hh Hl Ht Hs``: high pass ``s^2 / (s^2 + w1 s / Q1 + w1^2)``, low pass
    ``w2^2 / (s^2 + w2 s / Q2 + w2^2)``, transition ``K (1 + s / w3) / (1 + s / (Q4 w4) +
    s^2 / w4^2)``, upward step ``(s^2 + w5 s / Q5 + w5^2) / (s^2 + w6 s / Q6 + w6^2)``
    (EN 12299:2009 annex A; ISO 2631-1:1997 annex A)."""
    w = _weighting(name)
    q12 = 1.0 / math.sqrt(2.0)
    num = np.poly1d([w.k, 0.0, 0.0])  # K s^2 (high pass numerator with the gain)
    den = np.poly1d([1.0, 2 * math.pi * w.f1 / q12, (2 * math.pi * w.f1) ** 2])
    if band_limit_low_pass:
        w2 = 2 * math.pi * w.f2
        num = num * w2**2
        den = den * np.poly1d([1.0, w2 / q12, w2**2])
    w3, w4 = 2 * math.pi * w.f3, 2 * math.pi * w.f4
    num = num * np.poly1d([w4**2 / w3, w4**2])  # (1 + s/w3) w4^2
    den = den * np.poly1d([1.0, w4 / w.q4, w4**2])
    if math.isfinite(w.f5):
        w5, w6 = 2 * math.pi * w.f5, 2 * math.pi * w.f6
        num = num * np.poly1d([1.0, w5 / w.q5, w5**2])
        den = den * np.poly1d([1.0, w6 / w.q6, w6**2])
    z, p, k = scipy_signal().tf2zpk(num.coeffs, den.coeffs)
    return list(z), list(p), float(k)


def weighting_gain(name: str, frequency_Hz: ArrayLike) -> FloatArray:
    """Magnitude of the analogue weighting ``name`` at ``frequency_Hz`` (-)."""
    z, p, k = weighting_zpk(name)
    f = np.atleast_1d(np.asarray(frequency_Hz, dtype=float))
    _, h = scipy_signal().freqs_zpk(z, p, k, worN=2 * math.pi * f)
    return np.abs(h)


def weighting_sos(name: str, fs_Hz: float) -> FloatArray:
    """Second-order sections of the digital weighting ``name`` at the sample rate ``fs_Hz``
    (bilinear transform of :func:`weighting_zpk`). The band-limiting low pass (100 Hz) is left
    out when it is not below 0.4 ``fs_Hz``: no content above the Nyquist frequency is left in a
    sampled signal to limit, and the bilinear transform cannot place a pole beyond it."""
    w = _weighting(name)
    z, p, k = weighting_zpk(name, band_limit_low_pass=w.f2 < 0.4 * fs_Hz)
    zd, pd, kd = scipy_signal().bilinear_zpk(z, p, k, fs_Hz)
    return scipy_signal().zpk2sos(zd, pd, kd)


def weight(acceleration: ArrayLike, fs_Hz: float, name: str) -> FloatArray:
    """The acceleration (m/s^2) sampled at ``fs_Hz``, weighted by ``name`` (forward filter)."""
    a = np.asarray(acceleration, dtype=float)
    return scipy_signal().sosfilt(weighting_sos(name, fs_Hz), a)


def lowpass(values: ArrayLike, fs_Hz: float, cutoff_Hz: float) -> FloatArray:
    """Zero-phase Butterworth low pass (order :data:`BUTTERWORTH_ORDER`, forwards and
    backwards) at ``cutoff_Hz``. A cut-off at or above 0.45 ``fs_Hz`` leaves the signal as it is
    (nothing to remove below the Nyquist frequency)."""
    v = np.asarray(values, dtype=float)
    if not cutoff_Hz < 0.45 * fs_Hz or v.size < 16:
        return v.copy()
    sos = scipy_signal().butter(
        BUTTERWORTH_ORDER, cutoff_Hz, btype="lowpass", fs=fs_Hz, output="sos"
    )
    return scipy_signal().sosfiltfilt(sos, v)


def bandpass(values: ArrayLike, fs_Hz: float, low_Hz: float, high_Hz: float) -> FloatArray:
    """Zero-phase Butterworth band pass (order :data:`BUTTERWORTH_ORDER`, forwards and
    backwards) between ``low_Hz`` and ``high_Hz``; the upper edge is capped below the Nyquist
    frequency. The record is padded by three periods of the lower edge (odd extension)."""
    v = np.asarray(values, dtype=float)
    high = min(high_Hz, 0.45 * fs_Hz)
    if not 0.0 < low_Hz < high:
        raise ValueError(f"band {low_Hz:g} to {high_Hz:g} Hz does not fit below {fs_Hz / 2:g} Hz")
    sos = scipy_signal().butter(
        BUTTERWORTH_ORDER, [low_Hz, high], btype="bandpass", fs=fs_Hz, output="sos"
    )
    # pad (odd extension) by three periods of the lower edge, so that the filter's start-up
    # transient, slow for a low edge, dies out before the record begins
    padlen = int(min(v.size - 1, math.ceil(3.0 * fs_Hz / low_Hz)))
    return scipy_signal().sosfiltfilt(sos, v, padlen=padlen)


def dominant_frequency(
    values: ArrayLike, fs_Hz: float, band_Hz: tuple[float, float]
) -> float | None:
    """Frequency (Hz) of the largest peak of the periodogram (Hann window, mean removed) of
    ``values`` within ``band_Hz``; None if the band holds no bin or the signal is constant."""
    v = np.asarray(values, dtype=float)
    if v.size < 8 or not np.all(np.isfinite(v)):
        return None
    f, p = scipy_signal().periodogram(v, fs=fs_Hz, window="hann", detrend="constant")
    band = (f >= band_Hz[0]) & (f <= band_Hz[1])
    if not np.any(band) or not np.max(p[band]) > 0.0:
        return None
    return float(f[band][int(np.argmax(p[band]))])


def scipy_signal():
    """``scipy.signal``, imported at the first use (by the filters here and the hunting
    detection): its import costs some 0.8 s, which a process that only reads or unpickles a
    summary (:mod:`railexu.runtime.warm_process`) does not pay."""
    from scipy import signal

    return signal
