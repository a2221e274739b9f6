"""Ride comfort: EN 12299 mean comfort N_MV and Sperling's ride index Wz.

- **EN 12299:2009 mean comfort, standard method** (section 6.2): the floor accelerations are
  weighted (lateral ``Wd``, vertical ``Wb``, see :mod:`.filters`), their rms is taken over
  consecutive 5 s blocks, and the 95 % percentile of the block values ``a_P95`` of each direction
  enters ``N_MV = 6 sqrt(a_XP95^2 + a_YP95^2 + a_ZP95^2)`` (accelerations in m/s^2). The
  standard asks for 5 min of running (60 blocks); a shorter run gives fewer blocks, and the
  summary says how many. railexu records no longitudinal acceleration: ``a_XP95`` is taken as 0
  (railexu's choice; on straight track at constant speed it is small).
  EN 12299's scale: N < 1.5 very comfortable, 1.5-2.5 comfortable, 2.5-3.5 medium, 3.5-4.5
  uncomfortable, > 4.5 very uncomfortable.
- **Sperling's ride index** (Sperling and Betzhold 1956; as given by Garg and Dukkipati 1984,
  "Dynamics of railway vehicle systems", chapter 11): for a harmonic acceleration of peak ``b``
  (cm/s^2) at frequency ``f`` (Hz), ``Wz = 0.896 (b^3 F(f) / f)^(1/10)``, with the weighting
  ``F`` vertical ``0.325 f^2`` (0.5-5.9 Hz), ``400 / f^2`` (5.9-20 Hz), 1 above; lateral
  ``0.8 f^2`` (0.5-5.4 Hz), ``650 / f^2`` (5.4-26 Hz), 1 above. A signal is split into its
  Fourier components ``b_i`` and ``Wz = (sum Wz_i^10)^(1/10)``. Components below 0.5 Hz are left
  out (the weighting is not defined there). Scale: 1 just noticeable, 2 clearly noticeable,
  2.5 more pronounced but not unpleasant, 3 strong, irregular but tolerable, 3.25 very irregular,
  3.5 extremely irregular, unpleasant, 4 extremely unpleasant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from railexu.assessment.filters import weight

#: EN 12299: rms of the weighted accelerations over 5 s blocks ...
COMFORT_BLOCK_S = 5.0
#: ... and the 95 % percentile of the blocks.
COMFORT_PERCENTILE = 95.0
#: EN 12299: length of a standard mean-comfort evaluation (5 min).
COMFORT_RECORD_S = 300.0
#: Sperling's weighting is defined from 0.5 Hz.
SPERLING_MIN_HZ = 0.5

N_MV_SCALE = ((1.5, "very comfortable"), (2.5, "comfortable"), (3.5, "medium"),
              (4.5, "uncomfortable"), (math.inf, "very uncomfortable"))  # fmt: skip


def comfort_class(n_mv: float | None) -> str | None:
    """EN 12299's words for a mean comfort value."""
    if n_mv is None:
        return None
    return next(text for bound, text in N_MV_SCALE if n_mv < bound)


def block_rms(values: ArrayLike, fs_Hz: float, block_s: float = COMFORT_BLOCK_S) -> np.ndarray:
    """Rms of consecutive blocks of ``block_s`` seconds (the last, incomplete block is dropped
    unless there is no complete one: then the whole record is one block)."""
    v = np.asarray(values, dtype=float)
    n = int(round(block_s * fs_Hz))
    blocks = v.size // n if n > 0 else 0
    if blocks == 0:
        return np.array([math.sqrt(float(np.mean(v * v)))]) if v.size else np.empty(0)
    return np.sqrt(np.mean(v[: blocks * n].reshape(blocks, n) ** 2, axis=1))


def p95(
    values: ArrayLike, fs_Hz: float, weighting: str, keep: ArrayLike | None = None
) -> tuple[float, int]:
    """``a_P95``: the 95 % percentile of the 5 s rms values of the weighted acceleration
    (m/s^2), and the number of blocks. The whole record is weighted; only the samples where
    ``keep`` holds (a contiguous evaluation window; default all) enter the blocks."""
    weighted = weight(values, fs_Hz, weighting)
    if keep is not None:
        weighted = weighted[np.asarray(keep, dtype=bool)]
    rms = block_rms(weighted, fs_Hz)
    return float(np.percentile(rms, COMFORT_PERCENTILE)), int(rms.size)


def mean_comfort(
    acc_y: ArrayLike | None,
    acc_z: ArrayLike | None,
    fs_Hz: float,
    acc_x: ArrayLike | None = None,
    keep: ArrayLike | None = None,
) -> dict:
    """EN 12299 mean comfort N_MV (standard method) from floor accelerations (m/s^2) sampled
    at ``fs_Hz``; a missing direction counts as 0. Returns ``N_MV``, ``a_x_P95``, ``a_y_P95``,
    ``a_z_P95`` (m/s^2), ``blocks`` and ``class``."""
    out: dict = {"a_x_P95_m_per_s2": None, "a_y_P95_m_per_s2": None, "a_z_P95_m_per_s2": None}
    total, blocks = 0.0, 0
    for key, acc, weighting in (
        ("a_x_P95_m_per_s2", acc_x, "Wd"),
        ("a_y_P95_m_per_s2", acc_y, "Wd"),
        ("a_z_P95_m_per_s2", acc_z, "Wb"),
    ):
        if acc is None:
            continue
        value, blocks = p95(acc, fs_Hz, weighting, keep)
        out[key] = value
        total += value * value
    out["N_MV"] = 6.0 * math.sqrt(total)
    out["blocks"] = blocks
    out["class"] = comfort_class(out["N_MV"])
    return out


def sperling_weighting(frequency_Hz: ArrayLike, direction: str) -> np.ndarray:
    """Sperling's frequency weighting ``F(f)`` (-) for ``direction`` ``"vertical"`` or
    ``"lateral"`` (see the module docstring)."""
    f = np.asarray(frequency_Hz, dtype=float)
    if direction == "vertical":
        f1, a, f2, b = 5.9, 0.325, 20.0, 400.0
    elif direction == "lateral":
        f1, a, f2, b = 5.4, 0.8, 26.0, 650.0
    else:
        raise ValueError(f"direction must be 'vertical' or 'lateral', got {direction!r}")
    return np.where(f < f1, a * f * f, np.where(f < f2, b / np.maximum(f, 1e-12) ** 2, 1.0))


def sperling_index(acceleration: ArrayLike, fs_Hz: float, direction: str) -> float | None:
    """Sperling's ride index Wz of an acceleration record (m/s^2) sampled at ``fs_Hz``.

    The record's Fourier components (peak amplitudes ``b_i``, converted to cm/s^2) at
    frequencies ``f_i >= 0.5 Hz`` each give ``Wz_i = 0.896 (b_i^3 F(f_i) / f_i)^(1/10)``;
    ``Wz = (sum Wz_i^10)^(1/10)``. None for a record shorter than 2 s (no component at 0.5 Hz)."""
    a = np.asarray(acceleration, dtype=float)
    n = a.size
    if n < 4 or n / fs_Hz < 2.0:
        return None
    spectrum = np.fft.rfft(a - np.mean(a))
    f = np.fft.rfftfreq(n, d=1.0 / fs_Hz)
    b = 2.0 * np.abs(spectrum) / n * 100.0  # peak amplitude per component, cm/s^2
    if n % 2 == 0:
        b[-1] *= 0.5  # the Nyquist bin is not doubled
    keep = f >= SPERLING_MIN_HZ
    terms = 0.896**10 * b[keep] ** 3 * sperling_weighting(f[keep], direction) / f[keep]
    total = float(np.sum(terms))
    return total**0.1 if total > 0.0 else 0.0


@dataclass
class PointComfort:
    """Ride comfort at one measurement point."""

    point: str
    n_mv: dict | None
    sperling_lateral: float | None
    sperling_vertical: float | None

    def to_dict(self) -> dict:
        return {
            "N_MV": None if self.n_mv is None else self.n_mv["N_MV"],
            "N_MV_details": self.n_mv,
            "sperling_lateral_Wz": self.sperling_lateral,
            "sperling_vertical_Wz": self.sperling_vertical,
        }


def point_comfort(
    point: str,
    acc_y: ArrayLike | None,
    acc_z: ArrayLike | None,
    fs_Hz: float,
    keep: ArrayLike | None = None,
) -> PointComfort:
    """EN 12299 N_MV and Sperling's Wz (lateral, vertical) at one point, over the samples where
    ``keep`` holds (the evaluation window; default all)."""

    def cut(a: ArrayLike) -> np.ndarray:
        a = np.asarray(a, dtype=float)
        return a if keep is None else a[np.asarray(keep, dtype=bool)]

    return PointComfort(
        point=point,
        n_mv=None
        if acc_y is None and acc_z is None
        else mean_comfort(acc_y, acc_z, fs_Hz, keep=keep),
        sperling_lateral=None if acc_y is None else sperling_index(cut(acc_y), fs_Hz, "lateral"),
        sperling_vertical=None if acc_z is None else sperling_index(cut(acc_z), fs_Hz, "vertical"),
    )
