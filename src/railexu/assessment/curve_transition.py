"""EN 12299 comfort on curve transitions P_CT: the share of passengers (%) who feel discomfort
when the car body passes a curve transition.

EN 12299:2009 (comfort on curve transitions; the 2024 edition keeps the method) gives, for a
transition that the car body passes from ``t_start`` to ``t_end`` (s)::

    P_CT = max(A * y_max + B * dy_max - C, 0) + D * phi_max ** E      [%]

with

- ``y_max`` (m/s^2): the largest magnitude of the car body's lateral acceleration on the floor
  (the accelerometer's reading: the uncompensated lateral acceleration plus g times the body's
  roll relative to the track), low-pass filtered, over ``[t_start, t_end + 1.6 s]``;
- ``dy_max`` (m/s^3): the largest peak-to-peak change of the same filtered signal within 1 s
  (a jerk over 1 s), over 1 s windows that start in ``[t_start - 1 s, t_end]``;
- ``phi_max`` (deg/s): the largest magnitude of the car body's roll velocity (absolute: the
  track's cant rate plus the body's roll relative to the track), low-pass filtered, over
  ``[t_start, t_end]``;
- ``A..E``: constants for standing and for seated passengers (:data:`PCT_CONSTANTS`).

Sources named for the method and its constants: the public research texts on tilting trains
that reproduce them (FACT project deliverable D8 "Tracks for tilting trains", section 3.1.2
"CEN comfort index PCT"; Lauriks et al., "UIC comfort tests", VTI notat 56A-2003; R. Persson,
"Tilting trains - technology, benefits and motion sickness", KTH licentiate thesis 2008); a
later search (docs/acceptance.md) reached only their opening pages, not these sections. The
text of EN 12299 is not public: the constants, the windows (1 s, 1.6 s) and the filters'
cut-off frequencies are parameters of :class:`PctParameters`, and every result says
``assumption: true`` until they are checked against the purchased standard. The filter cut-offs
(0.3 Hz for the acceleration and the roll velocity, Butterworth of order 4 run forwards and
backwards, :func:`railexu.assessment.filters.lowpass`) are railexu's assumption.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from railexu.assessment.filters import lowpass
from railexu.errors import InputError

FloatArray = NDArray[np.float64]

#: EN 12299 P_CT constants ``(A, B, C, D, E)``: A in % s^2/m, B in % s^3/m, C in %, D in
#: % (s/deg)^E, E (-), as reproduced in the public texts of the module docstring.
PCT_CONSTANTS = {
    "standing": (28.54, 20.69, 11.1, 0.185, 2.283),
    "seated": (8.97, 9.68, 5.9, 0.120, 1.626),
}

#: Where the rules come from (cited in every result).
PCT_CLAUSE = "EN 12299:2009, comfort on curve transitions (P_CT)"


@dataclass(frozen=True)
class PctParameters:
    """The windows and filters of P_CT (see the module docstring). ``assumption`` marks that
    railexu could not confirm them in a public text of the standard itself."""

    acceleration_lowpass_Hz: float = 0.3
    roll_velocity_lowpass_Hz: float = 0.3
    after_end_s: float = 1.6  # y_max: until this long after the transition's end
    jerk_window_s: float = 1.0  # dy_max: peak-to-peak within windows of this length ...
    jerk_before_start_s: float = 1.0  # ... starting this long before the transition's start
    assumption: bool = True

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            if name == "assumption":
                continue
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0):
                raise InputError(f"P_CT parameter {name}: expected a finite value >= 0, got "
                                 f"{value!r}")  # fmt: skip
        if self.acceleration_lowpass_Hz <= 0.0 or self.roll_velocity_lowpass_Hz <= 0.0:
            raise InputError("P_CT parameters: the low-pass cut-off frequencies must be > 0 Hz")
        if self.jerk_window_s <= 0.0:
            raise InputError("P_CT parameter jerk_window_s: expected a length > 0 s")


def pct_formula(
    y_max_m_per_s2: float, dy_max_m_per_s3: float, phi_max_deg_per_s: float, posture: str
) -> float:
    """``P_CT`` (%) from the three motion values for ``posture`` ``"standing"`` or
    ``"seated"`` (the formula of the module docstring; the first term is not negative)."""
    try:
        a, b, c, d, e = PCT_CONSTANTS[posture]
    except KeyError:
        raise InputError(f"posture must be 'standing' or 'seated', got {posture!r}") from None
    values = (y_max_m_per_s2, dy_max_m_per_s3, phi_max_deg_per_s)
    if not all(math.isfinite(v) and v >= 0.0 for v in values):
        raise InputError(f"P_CT needs finite magnitudes >= 0, got {values}")
    return max(a * y_max_m_per_s2 + b * dy_max_m_per_s3 - c, 0.0) + d * phi_max_deg_per_s**e


@dataclass
class TransitionComfort:
    """P_CT of one transition at one point: the motion values, both postures, the windows."""

    point: str
    start_s: float
    end_s: float
    y_max_m_per_s2: float
    dy_max_m_per_s3: float
    phi_max_deg_per_s: float
    pct_standing: float
    pct_seated: float
    parameters: PctParameters = field(default_factory=PctParameters)

    def to_dict(self) -> dict:
        p = self.parameters
        return {
            "point": self.point,
            "P_CT_standing_percent": self.pct_standing,
            "P_CT_seated_percent": self.pct_seated,
            "y_max_m_per_s2": self.y_max_m_per_s2,
            "dy_max_m_per_s3": self.dy_max_m_per_s3,
            "phi_max_deg_per_s": self.phi_max_deg_per_s,
            "transition_time_s": [self.start_s, self.end_s],
            "rule": (
                f"y_max over [t_start, t_end + {p.after_end_s:g} s], dy_max the largest "
                f"peak-to-peak within {p.jerk_window_s:g} s windows starting in "
                f"[t_start - {p.jerk_before_start_s:g} s, t_end], phi_max over "
                f"[t_start, t_end]; low pass {p.acceleration_lowpass_Hz:g} Hz (acceleration), "
                f"{p.roll_velocity_lowpass_Hz:g} Hz (roll velocity), Butterworth order 4 "
                "forwards and backwards"
            ),
            "clause": PCT_CLAUSE,
            "assumption": p.assumption,
        }


def _between(t: FloatArray, lo: float, hi: float) -> NDArray[np.bool_]:
    return (t >= lo - 1e-9) & (t <= hi + 1e-9)


def max_peak_to_peak(t: FloatArray, values: FloatArray, window_s: float, lo: float, hi: float):
    """The largest ``max - min`` of ``values`` within windows ``[t0, t0 + window_s]`` whose
    start ``t0`` is a sample time in ``[lo, hi]`` (same units as ``values``)."""
    best = 0.0
    starts = np.flatnonzero(_between(t, lo, hi))
    ends = np.searchsorted(t, t[starts] + window_s + 1e-9, side="right")
    for i, j in zip(starts, ends, strict=True):
        if j - i >= 2:
            seg = values[i:j]
            best = max(best, float(np.max(seg) - np.min(seg)))
    return best


def transition_comfort(
    point: str,
    time_s: ArrayLike,
    acc_y_m_per_s2: ArrayLike,
    roll_velocity_rad_per_s: ArrayLike,
    start_s: float,
    end_s: float,
    parameters: PctParameters | None = None,
) -> TransitionComfort:
    """P_CT of the transition that ``point`` passes from ``start_s`` to ``end_s`` (s), from
    its lateral acceleration (m/s^2) and its body's absolute roll velocity (rad/s), sampled at
    the uniform times ``time_s``. The signals are filtered over the whole record, then cut to
    the windows (a window reaching past the record is cut at its end)."""
    p = parameters or PctParameters()
    t = np.asarray(time_s, dtype=float)
    if t.size < 8 or not np.all(np.diff(t) > 0):
        raise InputError("P_CT needs at least 8 samples at increasing times")
    if not (math.isfinite(start_s) and math.isfinite(end_s) and end_s >= start_s):
        raise InputError(f"P_CT: bad transition times {start_s!r}..{end_s!r} s")
    fs = (t.size - 1) / (t[-1] - t[0])
    ay = lowpass(np.asarray(acc_y_m_per_s2, dtype=float), fs, p.acceleration_lowpass_Hz)
    roll_deg = np.degrees(
        lowpass(np.asarray(roll_velocity_rad_per_s, dtype=float), fs, p.roll_velocity_lowpass_Hz)
    )
    in_y = _between(t, start_s, end_s + p.after_end_s)
    in_roll = _between(t, start_s, end_s)
    if not np.any(in_y) or not np.any(in_roll):
        raise InputError(f"P_CT: the transition {start_s:g}..{end_s:g} s is outside the record")
    y_max = float(np.max(np.abs(ay[in_y])))
    dy_max = max_peak_to_peak(t, ay, p.jerk_window_s, start_s - p.jerk_before_start_s, end_s)
    dy_max /= p.jerk_window_s
    phi_max = float(np.max(np.abs(roll_deg[in_roll])))
    return TransitionComfort(
        point=point,
        start_s=float(start_s),
        end_s=float(end_s),
        y_max_m_per_s2=y_max,
        dy_max_m_per_s3=dy_max,
        phi_max_deg_per_s=phi_max,
        pct_standing=pct_formula(y_max, dy_max, phi_max, "standing"),
        pct_seated=pct_formula(y_max, dy_max, phi_max, "seated"),
        parameters=p,
    )
