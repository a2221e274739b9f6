"""Derailment criteria beyond EN 14363's Y/Q: wheel unloading and flange climb.

The run itself stops when a wheel has risen by a fraction of its flange height (the geometric
check of :mod:`railexu.simulation.simulate`). These criteria catch the situations that
come before it:

- **wheel unloading** ``Delta Q / Q0 = (Q0 - Q) / Q0`` of each wheel (``Q0``: static wheel load):
  the 99.85 % percentile of its 2 m sliding means against :data:`WHEEL_UNLOADING_LIMIT` (0.6).
  0.6 is the wheel-unloading limit of the twist test (EN 14363:2016, safety against derailment
  on twisted track, and UIC 530-2 for wagons); applying it to the dynamic on-track signal, with
  EN 14363's 2 m window, is railexu's choice. The smallest instantaneous wheel load is reported
  with it (a wheel at 0 N has lifted).
- **flange climb**: Nadal's limit (Nadal 1908) for the flange angle and friction, applied to the
  largest 2 m sliding mean of Y/Q of each wheel (a distance window, as Y/Q is assessed in
  EN 14363, so that a single impact sample does not count but a sustained climb does). The
  longest continuous stretch over which the instantaneous Y/Q exceeds Nadal's limit is reported
  too. Nadal's value as a limit here is railexu's choice (EN 14363 uses 0.8). A wheel without
  a flange (a cone, a tread without a rim: its profile rises less than
  :data:`MIN_FLANGE_HEIGHT_M` above the tape circle) has nothing to climb: the criterion is
  reported as not applicable (value and limit None, ``applicable: false``), never as exceeded
  against the meaningless Nadal value of its tread slope (negative when the slope is below the
  friction angle).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from railexu.assessment.criterion import Criterion
from railexu.assessment.en14363 import LOWPASS_HZ, PERCENTILE_MAX, SAFETY_STEP_M, SAFETY_WINDOW_M
from railexu.assessment.signals import percentile, window_means

FloatArray = NDArray[np.float64]

#: Limit of the wheel unloading Delta Q / Q0 (twist-test value of EN 14363 / UIC 530-2).
WHEEL_UNLOADING_LIMIT = 0.6
#: A wheel profile has a flange when its highest point (the flange tip) is at least this far
#: above the tape circle [m]. railexu's assumption: a flange is a rim of the order of 25-30 mm
#: (S1002: 28 mm at the design point); a conical tread rises 1.75 mm over 70 mm at 1:40.
MIN_FLANGE_HEIGHT_M = 0.010


def has_flange(flange_height_m: float | None) -> bool:
    """Whether a wheel with its flange tip ``flange_height_m`` above the tape circle [m] has
    a flange (:data:`MIN_FLANGE_HEIGHT_M`); unknown (None) counts as a flange."""
    return flange_height_m is None or flange_height_m >= MIN_FLANGE_HEIGHT_M


def wheel_unloading_criterion(
    x: FloatArray,
    q_by_wheel: Mapping[str, FloatArray],
    q0_by_wheel: Mapping[str, float],
    start: float,
    end: float,
) -> Criterion:
    """Wheel unloading ``(Q0 - Q) / Q0`` (see the module docstring); ``q_by_wheel`` holds the
    low-passed vertical wheel forces (N) by wheel name, ``q0_by_wheel`` the static wheel loads
    (N) by the same names."""
    best: tuple[float, str, float] | None = None
    min_q: tuple[float, str, float] | None = None
    inside = (x >= start) & (x <= end)
    for wheel, q in q_by_wheel.items():
        q0_N = q0_by_wheel[wheel]
        unloading = (q0_N - q) / q0_N
        centres, means = window_means(x, unloading, SAFETY_WINDOW_M, SAFETY_STEP_M, start, end)
        p = percentile(means, PERCENTILE_MAX)
        if p is not None and (best is None or p > best[0]):
            best = (p, wheel, float(centres[int(np.nanargmax(means))]))
        qw = np.where(inside, q, np.inf)
        if np.any(np.isfinite(qw)):
            k = int(np.argmin(qw))
            if min_q is None or qw[k] < min_q[0]:
                min_q = (float(qw[k]), wheel, float(x[k]))
    return Criterion(
        value=None if best is None else best[0],
        limit=WHEEL_UNLOADING_LIMIT,
        unit="-",
        where=None if best is None else best[1],
        distance_m=None if best is None else best[2],
        window=f"{SAFETY_WINDOW_M:g} m sliding mean, {SAFETY_STEP_M:g} m steps",
        rule=(
            f"railexu: {PERCENTILE_MAX:g} % percentile of the 2 m means of (Q0 - Q)/Q0 (Q "
            f"low-passed at {LOWPASS_HZ:g} Hz), largest over the wheels; limit 0.6, the "
            "twist-test wheel-unloading limit of EN 14363 / UIC 530-2"
        ),
        details={
            "static_wheel_load_N": {k: float(v) for k, v in q0_by_wheel.items()},
            "min_Q_N": None if min_q is None else min_q[0],
            "min_Q_wheel": None if min_q is None else min_q[1],
            "min_Q_distance_m": None if min_q is None else min_q[2],
        },
    )


def _longest_run(x: FloatArray, flag: FloatArray) -> tuple[float, float | None]:
    """Length (m) of the longest stretch where ``flag`` holds, and where it starts."""
    best, at = 0.0, None
    if not np.any(flag):
        return best, at
    edges = np.diff(np.concatenate(([0], flag.astype(int), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    for i0, i1 in zip(starts, ends, strict=True):
        length = float(x[i1] - x[i0])
        if at is None or length > best:
            best, at = length, float(x[i0])
    return best, at


def flange_climb_not_applicable(flange_height_m: float) -> Criterion:
    """The flange-climb criterion of a wheel without a flange: not applicable."""
    return Criterion(
        value=None,
        limit=None,
        unit="-",
        window=f"{SAFETY_WINDOW_M:g} m sliding mean, {SAFETY_STEP_M:g} m steps",
        rule=(
            "railexu: flange climb applies to wheels with a flange (tip at least "
            f"{MIN_FLANGE_HEIGHT_M * 1e3:g} mm above the tape circle)"
        ),
        details={
            "applicable": False,
            "flange_height_m": float(flange_height_m),
            "note": (
                f"not applicable: the wheel profile has no flange (its highest point is "
                f"{flange_height_m * 1e3:.1f} mm above the tape circle, less than "
                f"{MIN_FLANGE_HEIGHT_M * 1e3:g} mm)"
            ),
        },
    )


def flange_climb_criterion(
    x: FloatArray, y_over_q: Mapping[str, FloatArray], nadal: float, start: float, end: float
) -> Criterion:
    """Flange climb: the largest 2 m sliding mean of Y/Q (flanging wheel positive) over the
    wheels against Nadal's limit ``nadal``; see the module docstring (a wheel without a flange:
    :func:`flange_climb_not_applicable`)."""
    best: tuple[float, str, float] | None = None
    longest: tuple[float, str | None, float | None] = (0.0, None, None)
    inside = (x >= start) & (x <= end)
    for wheel, yq in y_over_q.items():
        centres, means = window_means(x, yq, SAFETY_WINDOW_M, SAFETY_STEP_M, start, end)
        if means.size and np.any(np.isfinite(means)):
            k = int(np.nanargmax(means))
            if best is None or means[k] > best[0]:
                best = (float(means[k]), wheel, float(centres[k]))
        length, at = _longest_run(x, inside & np.isfinite(yq) & (np.nan_to_num(yq) > nadal))
        if length > longest[0] or (longest[1] is None and at is not None):
            longest = (length, wheel, at)
    return Criterion(
        value=None if best is None else best[0],
        limit=nadal,
        unit="-",
        where=None if best is None else best[1],
        distance_m=None if best is None else best[2],
        window=f"{SAFETY_WINDOW_M:g} m sliding mean, {SAFETY_STEP_M:g} m steps",
        rule=(
            "railexu: largest 2 m mean of Y/Q (flanging wheel positive) over the wheels against "
            "Nadal's limit (tan g - mu)/(1 + mu tan g) for the flange angle g and friction mu"
        ),
        details={
            "applicable": True,
            "longest_above_limit_m": longest[0],
            "longest_above_limit_wheel": longest[1],
            "longest_above_limit_from_m": longest[2],
        },
    )
