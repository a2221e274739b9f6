"""Hunting (self-excited lateral oscillation) told apart from track-forced response.

The leading wheelset's lateral displacement over the second half of the evaluation window is
examined (:func:`detect_hunting`). The verdict is one of:

- ``"below threshold"``: the amplitude over the last 10 % (:func:`~railexu.results.signals.
  amplitude`, half peak to peak) does not exceed the threshold (1 mm by default);
- ``"decaying"``: the amplitude of the last quarter is below 0.9 times that of the third quarter
  (a disturbance dying out: stable);
- ``"no sustained oscillation"``: fewer than one full period in the second half, or the last zero
  crossing is more than a wavelength before the end (a drift or an offset);
- ``"track-forced response"``: the motion is not narrow-band: less than
  :data:`NARROW_BAND_SHARE` of its power lies within +-10 % of its dominant frequency (a
  self-excited oscillation is nearly harmonic; the response to random irregularities spreads
  over the band the track excites);
- on irregular track (``track_irregular=True``), EN 14363's band-passed running-stability
  criterion decides among the rest: ``"hunting (running-stability limit exceeded)"`` or
  ``"oscillation within the running-stability limit"`` (EN 14363 calls a vehicle unstable when
  that criterion is exceeded, whatever the displacement);
- otherwise ``"hunting (growing)"`` (last quarter more than 10 % above the third) or
  ``"hunting (limit cycle)"``.

``detected`` is True exactly for the two or three verdicts starting with ``"hunting"``: the
verdict always agrees with the amplitude, growth and band share it reports.
The thresholds (0.9, 10 %, 0.5) are railexu's choices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from railexu.assessment.criterion import Criterion, finite_or_none
from railexu.assessment.filters import scipy_signal
from railexu.assessment.signals import amplitude, zero_crossing_wavelength, zero_crossings

FloatArray = NDArray[np.float64]

#: The amplitude over the last 10 % of the window is reported as the hunting amplitude.
FINAL_FRACTION = 0.10
#: Decaying when the last quarter's amplitude is below this fraction of the third quarter's.
HUNTING_DECAY_RATIO = 0.9
#: Growing when the last quarter's amplitude is above this multiple of the third quarter's.
HUNTING_GROWTH_RATIO = 1.1
#: Share of the power within +-10 % of the dominant frequency above which the motion is narrow
#: band (self-excited); below it, track-forced.
NARROW_BAND_SHARE = 0.5
NARROW_BAND_HALF_WIDTH = 0.10


@dataclass
class HuntingResult:
    """Hunting verdict with the numbers it rests on (SI units)."""

    detected: bool = False
    verdict: str = "not evaluated"
    wavelength_m: float | None = None
    frequency_Hz: float | None = None
    amplitude_m: float | None = None
    growth_ratio: float | None = None
    narrow_band_share: float | None = None
    threshold_m: float | None = None

    def to_dict(self) -> dict:
        return {
            "detected": bool(self.detected),
            "verdict": self.verdict,
            "wavelength_m": finite_or_none(self.wavelength_m),
            "frequency_Hz": finite_or_none(self.frequency_Hz),
            "amplitude_m": finite_or_none(self.amplitude_m),
            "growth_ratio": finite_or_none(self.growth_ratio),
            "narrow_band_share": finite_or_none(self.narrow_band_share),
            "threshold_m": finite_or_none(self.threshold_m),
        }


def narrow_band_share(x: FloatArray, y: FloatArray, wavelength_m: float) -> float | None:
    """Share of the power of ``y`` (mean removed, Hann window, resampled to a uniform distance
    grid) within +-10 % (at least +-2.5 frequency bins) of the spatial frequency
    ``1 / wavelength_m``."""
    if x.size < 16 or not x[-1] > x[0]:
        return None
    grid = np.linspace(x[0], x[-1], x.size)
    v = np.interp(grid, x, y)
    dx = grid[1] - grid[0]
    f, p = scipy_signal().periodogram(v, fs=1.0 / dx, window="hann", detrend="constant")
    total = float(np.sum(p[1:]))
    if not total > 0.0:
        return None
    f0 = 1.0 / wavelength_m
    half = max(NARROW_BAND_HALF_WIDTH * f0, 2.5 * (f[1] - f[0]))
    return float(np.sum(p[1:][np.abs(f[1:] - f0) <= half]) / total)


def detect_hunting(
    x: FloatArray,
    y: FloatArray | None,
    speed_m_per_s: float,
    threshold_m: float,
    track_irregular: bool | None = None,
    running_stability: Criterion | None = None,
) -> HuntingResult:
    """Hunting verdict for the lateral displacement ``y`` (m) of the leading wheelset against
    the distance ``x`` (m) of the evaluation window; see the module docstring for the rules."""
    out = HuntingResult(threshold_m=threshold_m)
    if y is None or x.size < 4 or not x[-1] > x[0]:
        return out
    x0, span = float(x[0]), float(x[-1] - x[0])
    last_half = x >= x0 + 0.5 * span
    xs, ys = x[last_half], y[last_half]
    amp_q3 = amplitude(y[last_half & (x < x0 + 0.75 * span)])
    amp_q4 = amplitude(y[x >= x0 + 0.75 * span])
    out.amplitude_m = amplitude(y[x >= x0 + (1.0 - FINAL_FRACTION) * span])
    out.growth_ratio = amp_q4 / amp_q3 if amp_q3 > 0.0 else None
    wl = zero_crossing_wavelength(xs, ys, min_periods=1.0)
    crossings = zero_crossings(xs, ys)
    sustained = wl is not None and crossings.size > 0 and float(x[-1] - crossings[-1]) <= wl
    if wl is not None:
        out.narrow_band_share = narrow_band_share(xs, ys, wl)
    if out.amplitude_m <= threshold_m:
        out.verdict = "below threshold"
    elif amp_q4 < HUNTING_DECAY_RATIO * amp_q3:
        out.verdict = "decaying"
    elif not sustained:
        out.verdict = "no sustained oscillation"
    elif out.narrow_band_share is None or out.narrow_band_share < NARROW_BAND_SHARE:
        out.verdict = "track-forced response"
    elif track_irregular and running_stability is not None and running_stability.value is not None:
        if running_stability.exceeded:
            out.verdict = "hunting (running-stability limit exceeded)"
        else:
            out.verdict = "oscillation within the running-stability limit"
    elif amp_q4 > HUNTING_GROWTH_RATIO * amp_q3:
        out.verdict = "hunting (growing)"
    else:
        out.verdict = "hunting (limit cycle)"
    out.detected = out.verdict.startswith("hunting")
    if not out.detected:
        wl = zero_crossing_wavelength(xs, ys, min_periods=2.0)
    out.wavelength_m = wl
    if wl is not None and speed_m_per_s > 0 and math.isfinite(wl):
        out.frequency_Hz = speed_m_per_s / wl
    return out
