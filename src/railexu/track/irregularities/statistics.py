"""Statistics of irregularity signals: rms and a Welch PSD estimate."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from railexu.track.irregularities.common import FloatArray, IrregularityError

# ----------------------------------------------------------------------------------------------
# Statistics
# ----------------------------------------------------------------------------------------------


def rms(signal: ArrayLike) -> float:
    """Root mean square ``sqrt(mean(signal**2))`` (same unit as ``signal``; mean not removed)."""
    a = np.asarray(signal, dtype=float)
    if a.size == 0:
        raise IrregularityError("rms of an empty signal")
    return float(np.sqrt(np.mean(a * a)))


def psd_estimate(
    signal: ArrayLike, step: float, segment_length_m: float | None = None
) -> tuple[FloatArray, FloatArray]:
    """Welch estimate of the one-sided PSD of a uniformly sampled signal.

    Args:
        signal: samples (m) at spacing ``step`` (m).
        step: sample spacing (m).
        segment_length_m: Welch segment length (m); default an eighth of the record (at least
            256 samples). Hann window, 50 % overlap, mean removed per segment.

    Returns:
        ``(omega, psd)``: spatial angular frequency (rad/m) and PSD in m^2/(rad/m), the units of
        :meth:`TrackSpectrum.psd` (``scipy.signal.welch`` gives m^2/(1/m) over cycles/m; the
        PSD over rad/m is that divided by ``2 pi``).
    """
    x = np.asarray(signal, dtype=float)
    h = float(step)
    if x.ndim != 1 or x.size < 2:
        raise IrregularityError("psd_estimate needs a 1-D signal with at least 2 samples")
    if not (math.isfinite(h) and h > 0.0):
        raise IrregularityError(f"step must be positive, got {step!r}")
    if segment_length_m is None:
        nperseg = max(256, x.size // 8)
    else:
        nperseg = max(2, round(float(segment_length_m) / h))
    nperseg = min(nperseg, x.size)
    from scipy import signal as sp_signal

    f, p = sp_signal.welch(
        x, fs=1.0 / h, window="hann", nperseg=nperseg, detrend="constant", scaling="density"
    )
    return 2.0 * math.pi * f, p / (2.0 * math.pi)
