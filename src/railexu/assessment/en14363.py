"""On-track assessment quantities of EN 14363:2016 (running safety, track loading, stability).

Each function returns a :class:`~railexu.assessment.criterion.Criterion` with its value, limit,
place, window and rule; ``docs/assessment.md`` gives the clause of each quantity and says which
values are the standard's and which are railexu's choices.

Processing (EN 14363:2016, on-track tests: processing and evaluation of the quantities):

- forces are low-pass filtered at :data:`LOWPASS_HZ` before any statistic;
- Y/Q and sum Y are sliding means over :data:`SAFETY_WINDOW_M` (2 m) placed every
  :data:`SAFETY_STEP_M` (0.5 m);
- the maximum of a section is its 99.85 % percentile (:data:`PERCENTILE_MAX`), the minimum the
  0.15 % one, the quasi-static value the 50 % one;
- running stability: rms of sum Y band-pass filtered at ``f0 +- 2 Hz`` over 100 m windows placed
  every 10 m, against half the track-shifting limit.

Sign convention of Y/Q: signed so that the **flanging** wheel has a **positive** value. The
flange pushes the wheel towards the track centre, so on the left wheel a flange force is
``Y < 0`` and on the right wheel ``Y > 0``: ``Y/Q = -Y/Q`` on the left wheel and ``+Y/Q`` on the
right wheel.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from railexu.assessment.criterion import Criterion
from railexu.assessment.filters import bandpass
from railexu.assessment.signals import percentile, window_means, window_rms
from railexu.errors import InputError, did_you_mean

FloatArray = NDArray[np.float64]

SIDES = ("left", "right")
#: Y/Q is signed so that the flanging wheel is positive: multiply the track-frame Y by this.
FLANGE_SIGN = {"left": -1.0, "right": 1.0}

#: EN 14363: low-pass cut-off of the wheel-rail forces before evaluation (Hz).
LOWPASS_HZ = 20.0
#: EN 14363: Y/Q and sum Y are sliding means over 2 m of track ...
SAFETY_WINDOW_M = 2.0
#: ... placed every 0.5 m.
SAFETY_STEP_M = 0.5
#: EN 14363 statistics: 99.85 % percentile for maxima, 0.15 % for minima, 50 % quasi-static.
PERCENTILE_MAX = 99.85
PERCENTILE_MIN = 0.15
PERCENTILE_QUASI_STATIC = 50.0
#: EN 14363 limit of the derailment quotient (Y/Q)_lim (curves of radius >= 250 m).
Y_OVER_Q_LIMIT = 0.8
#: EN 14363 running stability: rms of sum Y over 100 m windows placed every 10 m ...
STABILITY_WINDOW_M = 100.0
STABILITY_STEP_M = 10.0
#: ... band-pass filtered at f0 +- 2 Hz (f0: the frequency of the lateral oscillation).
STABILITY_HALF_BAND_HZ = 2.0
#: railexu: lowest lower edge of the stability band (f0 - 2 Hz is below it for f0 < 2.5 Hz; a
#: lower edge would pass the quasi-static drift and ring for seconds after the record's start).
STABILITY_MIN_EDGE_HZ = 0.5

#: EN 14363 track-shifting factor alpha per vehicle category: 1 for locomotives, power cars,
#: coaches and multiple units, 0.85 for freight wagons.
ALPHA = {"locomotive": 1.0, "coach": 1.0, "multiple_unit": 1.0, "wagon": 0.85}
CATEGORIES = tuple(ALPHA)
DEFAULT_CATEGORY = "locomotive"


def alpha_for(category: str) -> float:
    """EN 14363 factor alpha of the track-shifting limit for a vehicle ``category``.

    Raises:
        InputError: unknown category (with did-you-mean).
    """
    try:
        return ALPHA[category]
    except KeyError:
        raise InputError(
            f"unknown vehicle category {category!r}; expected one of {', '.join(CATEGORIES)}."
            + did_you_mean(category, CATEGORIES),
            key="category",
        ) from None


def nadal_limit(flange_angle_rad: float, friction: float) -> float:
    """Nadal's flange-climb limit ``(Y/Q)_lim = (tan g - mu) / (1 + mu tan g)`` (-).

    Nadal (1908), the single-point flange-climb criterion behind EN 14363's Y/Q limit. ``g``:
    largest flange contact angle (rad); ``mu``: wheel-rail friction coefficient (-). 70 deg and
    mu = 0.36 give 1.20.
    """
    t = math.tan(flange_angle_rad)
    return (t - friction) / (1.0 + friction * t)


def track_shifting_limit_N(static_axle_load_N: float, alpha: float = 1.0) -> float:
    """EN 14363 track-shifting limit (Prud'homme) ``(sum Y)_lim = alpha (10 kN + 2Q0/3)`` (N).

    Args:
        static_axle_load_N: static axle load ``2 Q0`` (N).
        alpha: see :data:`ALPHA` (1 for locomotives and passenger vehicles, 0.85 for wagons).

    Example: EU07, 80 t on 4 axles: 2Q0 = 196.2 kN gives 10 + 65.4 = 75.4 kN.
    """
    return alpha * (10.0e3 + static_axle_load_N / 3.0)


def y_over_q_values(y_N: FloatArray, q_N: FloatArray, side: str, min_load_N: float) -> FloatArray:
    """Signed Y/Q (-) of one wheel, positive for the flanging wheel; NaN where
    ``Q <= min_load_N`` (an unloaded or lifted wheel)."""
    if side not in FLANGE_SIGN:
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    y = np.asarray(y_N, dtype=float)
    q = np.asarray(q_N, dtype=float)
    loaded = q > min_load_N
    out = np.full(y.shape, np.nan)
    out[loaded] = FLANGE_SIGN[side] * y[loaded] / q[loaded]
    return out


def _largest(
    x: FloatArray, series: Mapping[str, FloatArray], start: float, end: float, statistic
) -> tuple[float | None, str | None, float | None, float | None]:
    """Over the series (by name): sliding means over 2 m in 0.5 m steps within [start, end];
    the largest ``statistic(means)``, at which series, the centre of that series' largest mean,
    and the largest mean itself."""
    best: tuple[float | None, str | None, float | None, float | None] = (None, None, None, None)
    for name, values in series.items():
        centres, means = window_means(x, values, SAFETY_WINDOW_M, SAFETY_STEP_M, start, end)
        value = statistic(means)
        if value is None or (best[0] is not None and value <= best[0]):
            continue
        k = int(np.nanargmax(np.abs(means)))
        best = (value, name, float(centres[k]), float(np.nanmax(np.abs(means))))
    return best


def _window_text() -> str:
    return f"{SAFETY_WINDOW_M:g} m sliding mean, {SAFETY_STEP_M:g} m steps"


def y_over_q_criterion(
    x: FloatArray, y_over_q: Mapping[str, FloatArray], start: float, end: float
) -> Criterion:
    """Derailment quotient (EN 14363): the 99.85 % percentile of the 2 m sliding means of Y/Q
    (low-passed forces, flanging wheel positive) of each wheel; the largest over the wheels,
    against (Y/Q)_lim = 0.8."""
    value, wheel, at, largest = _largest(
        x, y_over_q, start, end, lambda m: percentile(m, PERCENTILE_MAX)
    )
    return Criterion(
        value=value,
        limit=Y_OVER_Q_LIMIT,
        unit="-",
        where=wheel,
        distance_m=at,
        window=_window_text(),
        rule=(
            f"EN 14363: {PERCENTILE_MAX:g} % percentile of the 2 m means of Y/Q (forces low-passed "
            f"at {LOWPASS_HZ:g} Hz), largest over the wheels; limit (Y/Q)_lim = 0.8"
        ),
        details={"max_2m": largest},
    )


def sum_y_criterion(
    x: FloatArray,
    sum_y: Mapping[str, FloatArray],
    start: float,
    end: float,
    limit_N: float,
    alpha: float,
    category: str,
) -> Criterion:
    """Track-shifting force (EN 14363): 2 m sliding means of sum Y = Y_left + Y_right of each
    axle; the larger magnitude of the 0.15 % and 99.85 % percentiles, largest over the axles,
    against alpha (10 kN + 2Q0/3)."""

    def stat(means: FloatArray) -> float | None:
        hi, lo = percentile(means, PERCENTILE_MAX), percentile(means, PERCENTILE_MIN)
        return None if hi is None or lo is None else max(abs(hi), abs(lo))

    value, axle, at, largest = _largest(x, sum_y, start, end, stat)
    return Criterion(
        value=value,
        limit=limit_N,
        unit="N",
        where=axle,
        distance_m=at,
        window=_window_text(),
        rule=(
            f"EN 14363: larger magnitude of the {PERCENTILE_MIN:g} % and {PERCENTILE_MAX:g} % "
            "percentiles of the 2 m means of sum Y per axle; limit alpha (10 kN + 2Q0/3) "
            f"(Prud'homme) with alpha = {alpha:g} for a {category}"
        ),
        details={"max_2m": largest, "alpha": alpha, "category": category},
    )


def stability_band_Hz(f0_Hz: float | None) -> tuple[float, float] | None:
    """EN 14363's band ``f0 +- 2 Hz`` around the oscillation frequency, the lower edge at least
    :data:`STABILITY_MIN_EDGE_HZ` (railexu)."""
    if f0_Hz is None or not f0_Hz > 0.0:
        return None
    return (
        max(f0_Hz - STABILITY_HALF_BAND_HZ, STABILITY_MIN_EDGE_HZ),
        f0_Hz + STABILITY_HALF_BAND_HZ,
    )


def running_stability_criterion(
    x: FloatArray,
    fs_Hz: float,
    sum_y: Mapping[str, FloatArray],
    f0_Hz: float | None,
    start: float,
    end: float,
    track_shifting_limit: float,
) -> Criterion:
    """Running stability (EN 14363, normal measuring method): sum Y of each axle band-pass
    filtered at ``f0 +- 2 Hz``, rms over 100 m windows in 10 m steps; the largest, against half
    the track-shifting limit. Not evaluated (value None) when the evaluation window is shorter
    than 100 m or no oscillation frequency is known."""
    band = stability_band_Hz(f0_Hz)
    limit = 0.5 * track_shifting_limit
    rule = (
        "EN 14363 (normal measuring method): rms of sum Y band-pass filtered at f0 +- 2 Hz over "
        f"{STABILITY_WINDOW_M:g} m windows in {STABILITY_STEP_M:g} m steps, largest over the "
        "axles; limit half the track-shifting limit"
    )
    window = f"{STABILITY_WINDOW_M:g} m sliding rms, {STABILITY_STEP_M:g} m steps"
    details = {"f0_Hz": f0_Hz, "band_Hz": list(band) if band else None}
    if band is None or not fs_Hz > 2.0 * band[0]:
        details["note"] = "no oscillation frequency f0 in the lateral motion: not evaluated"
        return Criterion(None, limit, "N", window, rule, details=details)
    best: tuple[float, str, float] | None = None
    for axle, values in sum_y.items():
        filtered = bandpass(values, fs_Hz, *band)
        centres, rms = window_rms(x, filtered, STABILITY_WINDOW_M, STABILITY_STEP_M, start, end)
        if rms.size and np.any(np.isfinite(rms)):
            k = int(np.nanargmax(rms))
            if best is None or rms[k] > best[0]:
                best = (float(rms[k]), axle, float(centres[k]))
    if best is None:
        details["note"] = f"evaluation window shorter than {STABILITY_WINDOW_M:g} m: not evaluated"
        return Criterion(None, limit, "N", window, rule, details=details)
    return Criterion(best[0], limit, "N", window, rule, where=best[1], distance_m=best[2],
                     details=details)  # fmt: skip
