"""The irregularity record: interpolation, fade-in/out, rail offsets and sampling."""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import CubicSpline

from railexu.track.irregularities.common import (
    _CSV_BASES,
    _FADE_DEFAULT_M,
    _UNIFORM_RTOL,
    COMPONENTS,
    FloatArray,
    IrregularityError,
)

# ----------------------------------------------------------------------------------------------
# Profile
# ----------------------------------------------------------------------------------------------


def _smootherstep(t: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Quintic smoothstep on [0, 1] (clamped outside) and its derivative d/dt."""
    t = np.clip(t, 0.0, 1.0)
    s = t * t * t * (t * (6.0 * t - 15.0) + 10.0)
    ds = 30.0 * t * t * (1.0 - t) ** 2
    return s, ds


def _readonly(a: ArrayLike, name: str) -> FloatArray:
    arr = np.array(a, dtype=float, copy=True)
    if arr.ndim != 1:
        raise IrregularityError(f"{name} must be a 1-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise IrregularityError(f"{name} contains non-finite values")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class IrregularityProfile:
    """The four irregularity signals of a track on a uniform grid (SI units).

    Attributes:
        distance_m: uniform, strictly increasing grid of distances along the track (m).
        lateral_m: alignment ``y_a`` (m, positive left).
        vertical_m: vertical profile ``z_v`` (m, positive up).
        cross_level_m: height of the left rail minus the right rail ``c`` (m).
        gauge_m: gauge minus nominal gauge ``g`` (m).
        fade_length_m: length (m) of the smooth fade-in at the start and fade-out at the end
            applied to the rail offsets (0 disables it; then the offsets jump at the ends).
        description: free text on where the data comes from.

    The stored arrays are the raw (unfaded) signals; see the module docstring for the
    interpolation, the fade and the rail offsets. The arrays are read-only copies; use
    ``dataclasses.replace(profile, fade_length_m=...)`` for another fade length.
    """

    distance_m: FloatArray
    lateral_m: FloatArray
    vertical_m: FloatArray
    cross_level_m: FloatArray
    gauge_m: FloatArray
    fade_length_m: float = _FADE_DEFAULT_M
    description: str = ""
    _spline: CubicSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        names = ("distance_m", "lateral_m", "vertical_m", "cross_level_m", "gauge_m")
        arrays = {n: _readonly(getattr(self, n), n) for n in names}
        for n, a in arrays.items():
            object.__setattr__(self, n, a)
        x = arrays["distance_m"]
        if x.size < 2:
            raise IrregularityError("an irregularity profile needs at least 2 grid points")
        for n in names[1:]:
            if arrays[n].shape != x.shape:
                raise IrregularityError(
                    f"{n} has {arrays[n].size} values but distance_m has {x.size}"
                )
        dx = np.diff(x)
        if np.any(dx <= 0.0):
            i = int(np.argmax(dx <= 0.0))
            raise IrregularityError(
                f"distance_m must increase strictly; index {i + 1} ({x[i + 1]} m) follows {x[i]} m"
            )
        h = (x[-1] - x[0]) / (x.size - 1)
        if np.max(np.abs(dx - h)) > _UNIFORM_RTOL * h:
            raise IrregularityError(
                f"distance_m must be a uniform grid; steps range from {dx.min()} to {dx.max()} m"
            )
        fade = float(self.fade_length_m)
        if not (math.isfinite(fade) and fade >= 0.0):
            raise IrregularityError(f"fade_length_m must be >= 0, got {self.fade_length_m!r}")
        if 2.0 * fade > x[-1] - x[0] + 1e-12:
            raise IrregularityError(
                f"fade_length_m = {fade} m is longer than half the record "
                f"({x[-1] - x[0]} m); use a shorter fade or a longer record"
            )
        object.__setattr__(self, "fade_length_m", fade)
        stacked = np.stack([arrays[f"{c}_m"] for c in COMPONENTS], axis=-1)
        object.__setattr__(self, "_spline", CubicSpline(x, stacked, axis=0))

    # -- grid ----------------------------------------------------------------------------------

    @property
    def start_m(self) -> float:
        """First grid distance (m)."""
        return float(self.distance_m[0])

    @property
    def end_m(self) -> float:
        """Last grid distance (m)."""
        return float(self.distance_m[-1])

    @property
    def length_m(self) -> float:
        """Length of the record (m)."""
        return self.end_m - self.start_m

    @property
    def step_m(self) -> float:
        """Grid step (m)."""
        return self.length_m / (self.distance_m.size - 1)

    # -- evaluation ----------------------------------------------------------------------------

    def window(self, x: ArrayLike, derivative: int = 0) -> FloatArray:
        """The fade window ``w(x)`` (``derivative=0``, dimensionless) or ``dw/dx`` (1/m)."""
        w, dw = self._window(np.asarray(x, dtype=float))
        return w if _check_derivative(derivative) == 0 else dw

    def _window(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        inside = (x >= self.start_m) & (x <= self.end_m)
        fade = self.fade_length_m
        if fade == 0.0:
            return inside.astype(float), np.zeros_like(x)
        s_in, ds_in = _smootherstep((x - self.start_m) / fade)
        s_out, ds_out = _smootherstep((self.end_m - x) / fade)
        w = np.where(inside, s_in * s_out, 0.0)
        dw = np.where(inside, (ds_in * s_out - s_in * ds_out) / fade, 0.0)
        return w, dw

    def _faded(self, x: ArrayLike, derivative: int) -> FloatArray:
        """Faded signals, shape ``x.shape + (4,)`` in ``COMPONENTS`` order."""
        derivative = _check_derivative(derivative)
        xa = np.asarray(x, dtype=float)
        xc = np.clip(xa, self.start_m, self.end_m)
        w, dw = self._window(xa)
        q = self._spline(xc)
        if derivative == 0:
            return w[..., None] * q
        return dw[..., None] * q + w[..., None] * self._spline(xc, 1)

    def signals(self, x: ArrayLike, derivative: int = 0) -> dict[str, FloatArray]:
        """The four faded signals at ``x`` (m): values in m (``derivative=0``) or slopes d/dx
        (``derivative=1``, m/m), keyed by ``COMPONENTS``; arrays shaped like ``x``."""
        q = self._faded(x, derivative)
        return {c: q[..., i] for i, c in enumerate(COMPONENTS)}

    def left_rail_offsets(self, x: ArrayLike, derivative: int = 0) -> tuple[FloatArray, FloatArray]:
        """Displacement ``(dy, dz)`` (m) of the left rail at ``x`` (m): ``(y_a + g/2,
        z_v + c/2)`` times the fade window; with ``derivative=1`` its slope d/dx (multiply by the
        speed for the rail velocity). Vectorised; arrays shaped like ``x``."""
        q = self._faded(x, derivative)
        return q[..., 0] + 0.5 * q[..., 3], q[..., 1] + 0.5 * q[..., 2]

    def right_rail_offsets(
        self, x: ArrayLike, derivative: int = 0
    ) -> tuple[FloatArray, FloatArray]:
        """Displacement ``(dy, dz)`` (m) of the right rail at ``x`` (m): ``(y_a - g/2,
        z_v - c/2)`` times the fade window; with ``derivative=1`` its slope d/dx."""
        q = self._faded(x, derivative)
        return q[..., 0] - 0.5 * q[..., 3], q[..., 1] - 0.5 * q[..., 2]

    def rail_offsets(self, x: ArrayLike, derivative: int = 0) -> FloatArray:
        """Left dy, left dz, right dy, right dz stacked on a last axis of length 4 (m or m/m),
        the column order of :class:`SampledIrregularities`."""
        ly, lz = self.left_rail_offsets(x, derivative)
        ry, rz = self.right_rail_offsets(x, derivative)
        return np.stack([ly, lz, ry, rz], axis=-1)

    def mirrored(self) -> IrregularityProfile:
        """The mirror image of the track about its centre line (``y -> -y``): the left rail
        takes the right rail's offsets mirrored, so the lateral alignment and the cross level
        change sign and the vertical profile and the gauge stay (from the rail offsets of the
        module doc: ``dy_left' = -dy_right = -y_a + g/2``, ``dz_left' = dz_right = z_v - c/2``).
        """
        return IrregularityProfile(
            distance_m=self.distance_m,
            lateral_m=-self.lateral_m,
            vertical_m=self.vertical_m,
            cross_level_m=-self.cross_level_m,
            gauge_m=self.gauge_m,
            fade_length_m=self.fade_length_m,
            description=f"{self.description} (mirrored)".strip(),
        )

    def sampled(self, step_m: float) -> SampledIrregularities:
        """Faded rail offsets and their slopes on a uniform grid for a compiled kernel.

        The grid covers the record with the largest step not above ``step_m`` that divides the
        length. Values and slopes at the nodes are exact (spline times window); between nodes
        the kernel interpolates with the cubic Hermite polynomial, whose error relative to this
        profile is ``O(step^4)``.
        """
        step_target = float(step_m)
        if not (math.isfinite(step_target) and step_target > 0.0):
            raise IrregularityError(f"step_m must be positive, got {step_m!r}")
        n_intervals = max(1, math.ceil(self.length_m / step_target - 1e-9))
        x = self.start_m + (self.length_m / n_intervals) * np.arange(n_intervals + 1)
        x[-1] = self.end_m
        return SampledIrregularities(
            start_m=self.start_m,
            step_m=self.length_m / n_intervals,
            values=self.rail_offsets(x, 0),
            slopes=self.rail_offsets(x, 1),
        )

    # -- construction and output ---------------------------------------------------------------

    @classmethod
    def zeros(
        cls, length_m: float, step_m: float = 1.0, start_m: float = 0.0
    ) -> IrregularityProfile:
        """Ideal track: all signals zero over ``[start_m, start_m + length_m]`` (m)."""
        length = float(length_m)
        if not (math.isfinite(length) and length > 0.0):
            raise IrregularityError(f"length_m must be positive, got {length_m!r}")
        if not (math.isfinite(float(step_m)) and step_m > 0.0):
            raise IrregularityError(f"step_m must be positive, got {step_m!r}")
        n = max(1, math.ceil(length / float(step_m) - 1e-9)) + 1
        x = float(start_m) + np.linspace(0.0, length, n)
        z = np.zeros(n)
        return cls(x, z, z, z, z, fade_length_m=0.0, description="ideal track (zeros)")

    def to_csv(self, path: str | Path, units: str = "m") -> None:
        """Write the raw signals as CSV with a header row ``distance_m, lateral_m, vertical_m,
        cross_level_m, gauge_m`` (``units="mm"``: the same names with ``_mm``, values in mm).
        The fade length is not stored."""
        if units not in ("m", "mm"):
            raise IrregularityError(f"units must be 'm' or 'mm', got {units!r}")
        scale = 1.0 if units == "m" else 1000.0
        cols = [self.distance_m, self.lateral_m, self.vertical_m, self.cross_level_m, self.gauge_m]
        with open(path, "w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow([f"{base}_{units}" for base in _CSV_BASES])
            for row in zip(*cols, strict=True):
                writer.writerow([f"{v * scale:.17g}" for v in row])


def _check_derivative(derivative: int) -> int:
    if derivative not in (0, 1):
        raise IrregularityError(f"derivative must be 0 or 1, got {derivative!r}")
    return int(derivative)


@dataclass(frozen=True, eq=False)
class SampledIrregularities:
    """Faded rail offsets on a uniform grid, for a compiled kernel.

    Attributes:
        start_m: distance of the first node (m).
        step_m: node spacing (m).
        values: ``(n, 4)`` C-contiguous float64: left dy, left dz, right dy, right dz (m).
        slopes: ``(n, 4)`` their derivatives with respect to ``x`` (m/m).

    Between nodes ``i`` and ``i+1``, with ``t = (x - x_i)/h``, the offsets are the cubic Hermite
    polynomial ``p = h00 p_i + h h10 m_i + h01 p_{i+1} + h h11 m_{i+1}`` (``h00 = 2t^3 - 3t^2 +
    1``, ``h10 = t^3 - 2t^2 + t``, ``h01 = -2t^3 + 3t^2``, ``h11 = t^3 - t^2``); outside
    ``[start_m, end_m]`` they are zero.
    """

    start_m: float
    step_m: float
    values: FloatArray
    slopes: FloatArray

    columns: ClassVar[tuple[str, ...]] = ("left_dy", "left_dz", "right_dy", "right_dz")

    def __post_init__(self) -> None:
        for name in ("values", "slopes"):
            arr = np.ascontiguousarray(getattr(self, name), dtype=np.float64)
            if arr.ndim != 2 or arr.shape[1] != 4:
                raise IrregularityError(f"{name} must have shape (n, 4), got {arr.shape}")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if self.values.shape != self.slopes.shape or self.values.shape[0] < 2:
            raise IrregularityError("values and slopes must have the same shape, n >= 2")

    @property
    def end_m(self) -> float:
        """Distance of the last node (m)."""
        return self.start_m + self.step_m * (self.values.shape[0] - 1)

    def evaluate(self, x: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Reference cubic Hermite interpolation: offsets (m) and slopes d/dx at ``x`` (m),
        each shaped ``x.shape + (4,)``; zero outside the grid."""
        xa = np.asarray(x, dtype=float)
        h = self.step_m
        n = self.values.shape[0]
        u = (xa - self.start_m) / h
        inside = (u >= 0.0) & (u <= n - 1)
        i = np.clip(np.floor(u).astype(np.int64), 0, n - 2)
        t = np.clip(u - i, 0.0, 1.0)[..., None]
        p0, p1 = self.values[i], self.values[i + 1]
        m0, m1 = self.slopes[i], self.slopes[i + 1]
        t2, t3 = t * t, t * t * t
        val = (
            (2 * t3 - 3 * t2 + 1) * p0
            + (t3 - 2 * t2 + t) * h * m0
            + (-2 * t3 + 3 * t2) * p1
            + (t3 - t2) * h * m1
        )
        slope = (6 * t2 - 6 * t) * (p0 - p1) / h + (3 * t2 - 4 * t + 1) * m0 + (3 * t2 - 2 * t) * m1
        mask = inside[..., None]
        return np.where(mask, val, 0.0), np.where(mask, slope, 0.0)
