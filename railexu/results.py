"""Results of a running simulation: the time series, the summary metrics and their limits.

A run (``railexu run``) records one row per output step in a :class:`TimeSeries`. The column
names are fixed (wheelsets numbered from 1 = leading, sides ``left``/``right`` seen in the
direction of travel; SI units, suffix = unit):

- ``time_s``, ``distance_m`` (always the first two columns);
- per wheelset ``i``: ``ws{i}_lateral_m`` (lateral displacement, positive to the left) and
  ``ws{i}_yaw_rad`` (yaw, positive counter-clockwise seen from above);
- per wheel (``side`` = ``left`` or ``right``): ``ws{i}_{side}_Y_N`` (lateral wheel-rail force on
  the wheel in the track frame, positive to the left), ``ws{i}_{side}_Q_N`` (vertical force on the
  wheel, positive up = load), ``ws{i}_{side}_n_contacts`` (number of loaded contact points) and
  ``ws{i}_{side}_max_angle_rad`` (largest contact angle among the loaded points, positive towards
  the flange, 0 if there is none);
- other bodies: ``{name}_lateral_m`` (``bogie_1_lateral_m``, ``car_body_lateral_m``, ...).

:func:`summarize` turns a series into a JSON-serialisable dict with the safety and stability
criteria of EN 14363 (Y/Q against Nadal's flange-climb limit, track-shifting force sum Y, running
stability as the rms of sum Y) and a hunting detection with its wavelength and frequency; see
``docs``-level formulas in ``physics.md`` section 7.

Sign convention of Y/Q (used by :func:`summarize`, :func:`y_over_q` and the plots): Y/Q is
signed so that the **flanging** wheel has a **positive** value. The flange pushes the wheel
towards the track centre, so on the left wheel (at ``y > 0``) a flange force is ``Y < 0`` and on
the right wheel ``Y > 0``: ``Y/Q = -Y/Q`` on the left wheel and ``+Y/Q`` on the right wheel.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import InputError

FloatArray = NDArray[np.float64]

SIDES = ("left", "right")
#: Y/Q is signed so that the flanging wheel is positive: multiply the track-frame Y by this.
FLANGE_SIGN = {"left": -1.0, "right": 1.0}

#: EN 14363: Y/Q and sum Y are assessed as sliding means over 2 m of track.
SAFETY_WINDOW_M = 2.0
#: EN 14363 running stability: rms of sum Y over a 100 m sliding window.
STABILITY_WINDOW_M = 100.0
#: Y/Q is evaluated only where Q exceeds this fraction of the mean static wheel load.
MIN_LOAD_FRACTION = 0.05
#: Final amplitude and hunting persistence use the last 10 % of the distance covered.
FINAL_FRACTION = 0.10
#: Hunting: the last quarter's amplitude must be at least this fraction of the previous
#: quarter's (growing or steady limit cycle; a decay by more than 10 % per quarter is stable).
HUNTING_DECAY_RATIO = 0.9
#: Zero crossings are counted with a hysteresis of this fraction of the signal's peak.
CROSSING_HYSTERESIS = 0.01
#: EN 14363 track-shifting factor alpha: 1 for locomotives (and passenger vehicles), 0.85 for
#: freight wagons.
ALPHA_LOCOMOTIVE = 1.0
ALPHA_FREIGHT_WAGON = 0.85

_WHEELSET_LATERAL = re.compile(r"^ws(\d+)_lateral_m$")


class ResultsError(InputError):
    """Invalid results data: bad time-series columns, unreadable CSV or summary file."""


# ----------------------------------------------------------------------------------------------
# Time series
# ----------------------------------------------------------------------------------------------


class TimeSeries:
    """Equal-length columns of a run, in insertion order (SI units, name suffix = unit).

    Built from a dict of arrays in one go (no appending): ``TimeSeries({"time_s": t,
    "distance_m": x, "ws1_lateral_m": y1, ...})``. ``time_s`` and ``distance_m`` are required
    and are moved to the front if they are not already there; the order of the other columns is
    kept. Every column is stored as a 1-D ``float64`` array (counts such as ``_n_contacts`` too).

    Attributes:
        columns: ``name -> array``, all of the same length.
    """

    REQUIRED = ("time_s", "distance_m")

    def __init__(self, columns: Mapping[str, ArrayLike]) -> None:
        missing = [name for name in self.REQUIRED if name not in columns]
        if missing:
            raise ResultsError(f"time series lacks the required column(s) {', '.join(missing)}")
        order = list(self.REQUIRED) + [n for n in columns if n not in self.REQUIRED]
        data: dict[str, FloatArray] = {}
        length: int | None = None
        for name in order:
            if not isinstance(name, str) or not name or "," in name or name != name.strip():
                raise ResultsError(f"invalid column name {name!r} (non-empty, no comma/space)")
            try:
                arr = np.array(columns[name], dtype=float)
            except (TypeError, ValueError) as exc:
                raise ResultsError(f"column {name!r} is not numeric: {exc}") from None
            if arr.ndim != 1:
                raise ResultsError(f"column {name!r} must be 1-D, got shape {arr.shape}")
            if length is None:
                length = arr.size
            elif arr.size != length:
                raise ResultsError(
                    f"column {name!r} has {arr.size} rows, expected {length} (as 'time_s')"
                )
            data[name] = arr
        self.columns: dict[str, FloatArray] = data

    # -- container protocol ------------------------------------------------------------------

    def __len__(self) -> int:
        return int(self.columns["time_s"].size)

    def __getitem__(self, name: str) -> FloatArray:
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"no column {name!r} in the time series") from None

    def __contains__(self, name: object) -> bool:
        return name in self.columns

    def __repr__(self) -> str:
        return f"TimeSeries({len(self)} rows, columns={self.names})"

    @property
    def names(self) -> list[str]:
        """Column names in order."""
        return list(self.columns)

    @property
    def time_s(self) -> FloatArray:
        """Simulated time (s)."""
        return self.columns["time_s"]

    @property
    def distance_m(self) -> FloatArray:
        """Distance travelled along the track (m)."""
        return self.columns["distance_m"]

    # -- naming helpers ----------------------------------------------------------------------

    def wheelset_indices(self) -> list[int]:
        """1-based indices ``i`` of the wheelsets with a ``ws{i}_lateral_m`` column, ascending."""
        found = (_WHEELSET_LATERAL.match(n) for n in self.columns)
        return sorted(int(m.group(1)) for m in found if m)

    def wheelset_count(self) -> int:
        """Number of wheelsets (columns ``ws{i}_lateral_m``)."""
        return len(self.wheelset_indices())

    def body_names(self) -> list[str]:
        """Names of the other bodies with a lateral displacement (``bogie_1``, ``car_body``...):
        the ``{name}_lateral_m`` columns that are not wheelsets, in column order."""
        return [
            n[: -len("_lateral_m")]
            for n in self.columns
            if n.endswith("_lateral_m") and not _WHEELSET_LATERAL.match(n)
        ]

    def truncated(self, n: int) -> TimeSeries:
        """A new series with the first ``n`` rows (copies)."""
        if n < 0:
            raise ValueError(f"n must be >= 0, got {n}")
        return TimeSeries({k: v[:n].copy() for k, v in self.columns.items()})

    # -- CSV -----------------------------------------------------------------------------------

    def to_csv(self, path: str | Path) -> Path:
        """Write a CSV file: one header row of column names, values as ``%.9g``."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        table = np.column_stack(list(self.columns.values())) if self.columns else np.empty((0, 0))
        with path.open("w", encoding="utf-8", newline="\n") as fh:
            fh.write(",".join(self.columns) + "\n")
            if len(self):
                np.savetxt(fh, table.reshape(len(self), -1), fmt="%.9g", delimiter=",")
        return path

    @classmethod
    def from_csv(cls, path: str | Path) -> TimeSeries:
        """Read a CSV file written by :meth:`to_csv` (header row of names, numbers below).

        Raises:
            ResultsError: naming the file and the problem (missing file, empty file, duplicate
                or missing columns, non-numeric value, wrong number of fields in a row).
        """
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as exc:
            raise ResultsError(f"{path}: cannot read time series: {exc.strerror or exc}") from None
        lines = [ln for ln in text.splitlines() if ln.strip()]
        if not lines:
            raise ResultsError(f"{path}: empty file, expected a header row of column names")
        names = [s.strip() for s in lines[0].split(",")]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ResultsError(f"{path}: duplicate column name(s) {', '.join(dup)}")
        table = np.empty((len(lines) - 1, len(names)))
        for row, line in enumerate(lines[1:]):
            fields = line.split(",")
            if len(fields) != len(names):
                raise ResultsError(
                    f"{path}, line {row + 2}: {len(fields)} fields, expected {len(names)} "
                    "(one per header column)"
                )
            try:
                table[row] = [float(f) for f in fields]
            except ValueError:
                bad = next(f for f in fields if not _is_float(f))
                raise ResultsError(
                    f"{path}, line {row + 2}: value {bad.strip()!r} is not a number"
                ) from None
        try:
            return cls({n: table[:, j] for j, n in enumerate(names)})
        except ResultsError as exc:
            raise ResultsError(f"{path}: {exc}") from None


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


# ----------------------------------------------------------------------------------------------
# Signal helpers
# ----------------------------------------------------------------------------------------------


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
    valid = np.isfinite(v)
    v0 = np.where(valid, v, 0.0)
    w = valid.astype(float)
    dx = np.diff(x)
    cum_v = np.concatenate(([0.0], np.cumsum(0.5 * (v0[1:] + v0[:-1]) * dx)))
    cum_w = np.concatenate(([0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * dx)))
    loc_a, loc_b = _locate(x, a), _locate(x, b)
    num = _integral_at(v0, cum_v, loc_b) - _integral_at(v0, cum_v, loc_a)
    den = _integral_at(w, cum_w, loc_b) - _integral_at(w, cum_w, loc_a)
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


def nadal_limit(flange_angle_rad: float, friction: float) -> float:
    """Nadal's flange-climb limit ``(Y/Q)_lim = (tan g - mu) / (1 + mu tan g)`` (-).

    Nadal (1908), the single-point flange-climb criterion used by EN 14363 as background to its
    Y/Q limit. ``g``: largest flange contact angle (rad); ``mu``: wheel-rail friction coefficient
    (-). 70 deg and mu = 0.36 give 1.20 (physics.md section 7).
    """
    t = math.tan(flange_angle_rad)
    return (t - friction) / (1.0 + friction * t)


def track_shifting_limit_N(static_axle_load_N: float, alpha: float = ALPHA_LOCOMOTIVE) -> float:
    """EN 14363 track-shifting limit (Prud'homme) ``(sum Y)_lim = alpha (10 kN + 2Q0/3)`` (N).

    Args:
        static_axle_load_N: static axle load ``2 Q0`` (N), i.e. the vehicle's static weight
            divided by the number of axles.
        alpha: 1 for locomotives, power cars and passenger vehicles, 0.85 for freight wagons
            (EN 14363).

    Example: EU07, 80 t on 4 axles: 2Q0 = 196.2 kN gives 10 + 65.4 = 75.4 kN.
    """
    return alpha * (10.0e3 + static_axle_load_N / 3.0)


def y_over_q(ts: TimeSeries, wheelset: int, side: str, min_load_N: float) -> FloatArray:
    """Signed Y/Q (-) of one wheel, positive for the flanging wheel; NaN where ``Q <= min_load_N``.

    ``Y`` (``ws{i}_{side}_Y_N``) is the lateral force on the wheel in the track frame, positive to
    the left; the flange pushes the wheel towards the track centre, so a flange-type force is
    ``Y < 0`` on the left wheel and ``Y > 0`` on the right wheel. The value returned is
    ``-Y/Q`` for the left wheel and ``+Y/Q`` for the right wheel, so that flange climbing is
    positive for both. Samples with ``Q <= min_load_N`` (an unloaded or lifted wheel) are NaN.
    """
    if side not in FLANGE_SIGN:
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    y = ts[f"ws{wheelset}_{side}_Y_N"]
    q = ts[f"ws{wheelset}_{side}_Q_N"]
    loaded = q > min_load_N
    out = np.full(y.shape, np.nan)
    out[loaded] = FLANGE_SIGN[side] * y[loaded] / q[loaded]
    return out


# ----------------------------------------------------------------------------------------------
# Summary
# ----------------------------------------------------------------------------------------------


def _f(value: Any) -> float | None:
    """A finite Python float, or None."""
    if value is None:
        return None
    v = float(value) + 0.0  # no -0.0 in the output
    return v if math.isfinite(v) else None


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, Mapping):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return _f(obj)
    if isinstance(obj, Path):
        return str(obj)
    return obj


def _finite_rows(ts: TimeSeries) -> int:
    """Number of leading rows in which every column is finite (rows after a divergence are
    meaningless and are dropped from the summary)."""
    n = len(ts)
    finite = np.ones(n, dtype=bool)
    for values in ts.columns.values():
        finite &= np.isfinite(values)
    bad = np.flatnonzero(~finite)
    return int(bad[0]) if bad.size else n


def _half_range(v: FloatArray) -> float:
    return 0.5 * float(np.max(v) - np.min(v)) if v.size else 0.0


def _argmax_finite(v: FloatArray) -> int | None:
    if v.size == 0 or not np.any(np.isfinite(v)):
        return None
    return int(np.nanargmax(v))


def _hunting(
    x: FloatArray, y: FloatArray | None, speed_m_per_s: float, threshold_m: float
) -> dict[str, Any]:
    out: dict[str, Any] = {
        "detected": False,
        "wavelength_m": None,
        "frequency_Hz": None,
        "amplitude_m": None,
    }
    if y is None or x.size < 4 or not x[-1] > x[0]:
        return out
    x0, span = float(x[0]), float(x[-1] - x[0])
    last_half = x >= x0 + 0.5 * span
    xs, ys = x[last_half], y[last_half]
    q3 = last_half & (x < x0 + 0.75 * span)
    q4 = x >= x0 + 0.75 * span
    amp_final = _half_range(y[x >= x0 + (1.0 - FINAL_FRACTION) * span])
    amp_q3, amp_q4 = _half_range(y[q3]), _half_range(y[q4])
    crossings = zero_crossings(xs, ys)
    wl = zero_crossing_wavelength(xs, ys, min_periods=1.0)
    persists = (
        wl is not None
        and amp_final > threshold_m
        and crossings.size > 0
        and float(x[-1] - crossings[-1]) <= wl
    )
    detected = bool(persists and amp_q4 >= HUNTING_DECAY_RATIO * amp_q3)
    if not detected:
        wl = zero_crossing_wavelength(xs, ys, min_periods=2.0)
    out["detected"] = detected
    out["wavelength_m"] = _f(wl)
    if wl is not None and speed_m_per_s > 0:
        out["frequency_Hz"] = _f(speed_m_per_s / wl)
    out["amplitude_m"] = _f(amp_final)
    return out


def summarize(
    ts: TimeSeries,
    *,
    wheelset_names: list[str],
    status: dict,
    realtime_factor: float,
    speed_m_per_s: float,
    friction: float,
    flange_angle_rad: float,
    static_axle_loads_N: list[float],
    locomotive: bool = True,
    hunting_threshold_m: float = 1.0e-3,
    flange_contact_angle_rad: float = math.radians(45),
) -> dict:
    """Summary metrics of a run as a JSON-serialisable dict (SI units, None where undefined).

    Rows from the first non-finite value on (a diverged run) are ignored; a truncated run
    (derailed, diverged) is summarised over the rows it has. "The last 10 %" always means the
    last 10 % of the distance covered by the (finite) rows.

    Keys:

    - ``status``: the dict passed in (e.g. ``{"state": "completed", "distance_m": ..., ...}``).
    - ``realtime_factor``: as passed in.
    - ``wheelsets``: per wheelset (in index order, named by ``wheelset_names``)
      ``{"name", "max_abs_lateral_m", "final_amplitude_m"}``; the final amplitude is
      ``max |lateral|`` over the last 10 % of the distance.
    - ``flange_contact``: ``{"occurred", "first_distance_m"}``: flange contact is any wheel whose
      largest loaded contact angle (``_max_angle_rad``) exceeds ``flange_contact_angle_rad``.
    - ``max_abs_lateral_force_N``: ``max |Y|`` over all wheels.
    - ``max_Y_over_Q``: ``{"value", "wheel", "distance_m", "value_2m", "nadal_limit",
      "exceeded"}``. Y/Q is **signed so that the flanging wheel is positive** (flange force
      towards the track centre: ``-Y/Q`` on the left wheel, ``+Y/Q`` on the right one, see
      :func:`y_over_q`) and evaluated only where ``Q > 5 %`` of the mean static wheel load.
      ``value`` is the raw maximum over all wheels, at ``wheel`` (``"ws1_left"``) and
      ``distance_m``; ``value_2m`` the maximum of the 2 m sliding mean (EN 14363);
      ``nadal_limit`` is Nadal's limit for ``flange_angle_rad`` and ``friction``;
      ``exceeded`` is judged on ``value_2m`` (False if the run is shorter than 2 m).
    - ``max_sum_Y_N``: track-shifting force (EN 14363): ``value`` is the maximum over axles of
      ``|sliding mean over 2 m of (Y_left + Y_right)|`` at ``wheelset`` (name) and
      ``distance_m`` (window centre), ``raw_value`` the unfiltered maximum of ``|sum Y|``;
      ``limit_N = alpha (10 kN + 2Q0/3)`` (Prud'homme, EN 14363) with ``2Q0`` the **mean**
      static axle load of ``static_axle_loads_N`` and ``alpha = 1`` if ``locomotive`` (also
      right for passenger vehicles) else ``0.85`` (freight wagons); ``exceeded = value > limit``.
    - ``running_stability``: ``{"rms_sum_Y_N", "limit_N", "exceeded"}``: the maximum over axles
      of the rms of ``sum Y`` over a 100 m sliding window (None if the run covered less than
      100 m), limit = half the track-shifting limit. This is EN 14363's normal-measuring-method
      criterion **simplified: no band-pass filter** (EN 14363 filters sum Y around the hunting
      frequency), so quasi-static lateral forces count too and the value is conservative.
    - ``hunting``: ``{"detected", "wavelength_m", "frequency_Hz", "amplitude_m"}`` from the
      leading wheelset's lateral displacement over the last half of the run. Detected when all
      of: (1) the amplitude (half peak-to-peak) in the last 10 % exceeds
      ``hunting_threshold_m``; (2) the oscillation persists: at least one full period in the
      last half and a zero crossing (of the signal minus its mean) within one wavelength of the
      end; (3) it does not decay: the amplitude of the last quarter is at least
      ``HUNTING_DECAY_RATIO`` (0.9) times that of the third quarter (growing or steady limit
      cycle). The wavelength is the mean zero-crossing spacing (:func:`zero_crossing_wavelength`)
      over the last half, the frequency ``speed / wavelength``; when not detected the dominant
      wavelength is still reported if at least 2 full periods are visible, else None.
      ``amplitude_m`` is the half peak-to-peak amplitude over the last 10 %.

    Args:
        ts: the recorded time series.
        wheelset_names: one name per wheelset, in index order (1 = leading).
        status: run status, copied into the summary.
        realtime_factor: simulated time / wall-clock time (-).
        speed_m_per_s: vehicle speed (m/s).
        friction: wheel-rail friction coefficient (-), for Nadal's limit.
        flange_angle_rad: maximum flange angle (rad), for Nadal's limit.
        static_axle_loads_N: static load of each axle (N), one per wheelset.
        locomotive: EN 14363 factor alpha = 1 (True) or 0.85 (False, freight wagon).
        hunting_threshold_m: amplitude above which an oscillation counts as hunting (m).
        flange_contact_angle_rad: contact angle above which a contact is a flange contact (rad).

    Raises:
        ResultsError: wheelset_names or static_axle_loads_N do not match the wheelsets, or the
            distance axis decreases.
    """
    indices = ts.wheelset_indices()
    if len(wheelset_names) != len(indices):
        raise ResultsError(
            f"{len(wheelset_names)} wheelset names for {len(indices)} wheelsets in the series"
        )
    if len(static_axle_loads_N) != len(indices) or not static_axle_loads_N:
        raise ResultsError(
            f"{len(static_axle_loads_N)} static axle loads for {len(indices)} wheelsets; "
            "give one per wheelset"
        )
    n = _finite_rows(ts)
    x = ts.distance_m[:n]
    if n > 1 and np.any(np.diff(x) < 0):
        raise ResultsError("distance_m decreases; expected a non-decreasing distance axis")
    span = float(x[-1] - x[0]) if n else 0.0
    final = x >= (x[-1] - FINAL_FRACTION * span) if n else np.zeros(0, bool)

    def col(name: str) -> FloatArray | None:
        return ts.columns[name][:n] if name in ts.columns else None

    axle_load_N = float(np.mean(static_axle_loads_N))
    min_load_N = MIN_LOAD_FRACTION * 0.5 * axle_load_N
    alpha = ALPHA_LOCOMOTIVE if locomotive else ALPHA_FREIGHT_WAGON
    shift_limit_N = track_shifting_limit_N(axle_load_N, alpha)
    nadal = nadal_limit(flange_angle_rad, friction)

    # wheelsets
    wheelsets = []
    for name, i in zip(wheelset_names, indices, strict=True):
        lat = np.abs(ts[f"ws{i}_lateral_m"][:n])
        wheelsets.append(
            {
                "name": str(name),
                "max_abs_lateral_m": _f(np.max(lat)) if n else None,
                "final_amplitude_m": _f(np.max(lat[final])) if n else None,
            }
        )

    # flange contact, lateral force, Y/Q
    flange = np.zeros(n, dtype=bool)
    max_abs_y: float | None = None
    best_raw: tuple[float, str, float] | None = None
    best_2m: float | None = None
    for i in indices:
        for side in SIDES:
            wheel = f"ws{i}_{side}"
            angle = col(f"{wheel}_max_angle_rad")
            if angle is not None:
                flange |= angle > flange_contact_angle_rad
            y = col(f"{wheel}_Y_N")
            if y is None or n == 0:
                continue
            m = float(np.max(np.abs(y)))
            max_abs_y = m if max_abs_y is None else max(max_abs_y, m)
            if col(f"{wheel}_Q_N") is None:
                continue
            yq = y_over_q(ts, i, side, min_load_N)[:n]
            k = _argmax_finite(yq)
            if k is not None and (best_raw is None or yq[k] > best_raw[0]):
                best_raw = (float(yq[k]), wheel, float(x[k]))
            yq2 = sliding_mean(x, yq, SAFETY_WINDOW_M)
            k2 = _argmax_finite(yq2)
            if k2 is not None and (best_2m is None or yq2[k2] > best_2m):
                best_2m = float(yq2[k2])
    first_flange = int(np.argmax(flange)) if flange.any() else None

    # track-shifting force and running stability
    best_sum: tuple[float, str, float] | None = None
    raw_sum: float | None = None
    rms_sum: float | None = None
    for name, i in zip(wheelset_names, indices, strict=True):
        yl, yr = col(f"ws{i}_left_Y_N"), col(f"ws{i}_right_Y_N")
        if yl is None or yr is None or n == 0:
            continue
        sum_y = yl + yr
        raw = float(np.max(np.abs(sum_y)))
        raw_sum = raw if raw_sum is None else max(raw_sum, raw)
        mean2, centres = _sliding(x, sum_y, SAFETY_WINDOW_M)
        k = _argmax_finite(np.abs(mean2))
        if k is not None and (best_sum is None or abs(mean2[k]) > best_sum[0]):
            best_sum = (float(abs(mean2[k])), str(name), float(centres[k]))
        if span >= STABILITY_WINDOW_M * (1.0 - 1e-9):
            rms = sliding_rms(x, sum_y, STABILITY_WINDOW_M)
            if np.any(np.isfinite(rms)):
                r = float(np.nanmax(rms))
                rms_sum = r if rms_sum is None else max(rms_sum, r)

    lead = col(f"ws{indices[0]}_lateral_m") if indices else None
    summary = {
        "status": _jsonable(dict(status)),
        "realtime_factor": _f(realtime_factor),
        "wheelsets": wheelsets,
        "flange_contact": {
            "occurred": first_flange is not None,
            "first_distance_m": None if first_flange is None else _f(x[first_flange]),
        },
        "max_abs_lateral_force_N": _f(max_abs_y),
        "max_Y_over_Q": {
            "value": None if best_raw is None else _f(best_raw[0]),
            "wheel": None if best_raw is None else best_raw[1],
            "distance_m": None if best_raw is None else _f(best_raw[2]),
            "value_2m": _f(best_2m),
            "nadal_limit": _f(nadal),
            "exceeded": bool(best_2m is not None and best_2m > nadal),
        },
        "max_sum_Y_N": {
            "value": None if best_sum is None else _f(best_sum[0]),
            "raw_value": _f(raw_sum),
            "wheelset": None if best_sum is None else best_sum[1],
            "distance_m": None if best_sum is None else _f(best_sum[2]),
            "limit_N": _f(shift_limit_N),
            "exceeded": bool(best_sum is not None and best_sum[0] > shift_limit_N),
        },
        "running_stability": {
            "rms_sum_Y_N": _f(rms_sum),
            "limit_N": _f(0.5 * shift_limit_N),
            "exceeded": bool(rms_sum is not None and rms_sum > 0.5 * shift_limit_N),
        },
        "hunting": _hunting(x, lead, speed_m_per_s, hunting_threshold_m),
    }
    return summary


def write_summary(summary: Mapping[str, Any], path: str | Path) -> Path:
    """Write ``summary`` as JSON (indent 2); non-finite numbers become ``null``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(_jsonable(summary), indent=2, allow_nan=False)
    path.write_text(text + "\n", encoding="utf-8")
    return path


def read_summary(path: str | Path) -> dict:
    """Read a summary written by :func:`write_summary`.

    Raises:
        ResultsError: naming the file, if it cannot be read or is not a JSON object.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ResultsError(f"{path}: cannot read summary: {exc.strerror or exc}") from None
    except json.JSONDecodeError as exc:
        raise ResultsError(f"{path}: invalid JSON at line {exc.lineno}: {exc.msg}") from None
    if not isinstance(data, dict):
        raise ResultsError(f"{path}: expected a JSON object, got {type(data).__name__}")
    return data
