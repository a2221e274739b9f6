"""A prescribed forward speed along the track: (distance, speed) points, constant acceleration
between them (SI units).

Between two points ``(s0, v0)`` and ``(s1, v1)`` the acceleration is constant,

    a = (v1^2 - v0^2) / (2 (s1 - s0)),

so that the speed squared is linear in the distance, ``v(s)^2 = v0^2 + 2 a (s - s0)``, and the
speed linear in time within the segment; the segment takes exactly

    t1 - t0 = 2 (s1 - s0) / (v0 + v1)

(the mean of the two speeds; for ``a = 0`` the familiar ``(s1 - s0) / v0``). The time at every
point is precomputed from this exact integral of ``dt = ds / v``, and
:meth:`SpeedProfile.speed_at`, :meth:`SpeedProfile.distance_at` and
:meth:`SpeedProfile.acceleration_at` are exact functions of time: a constant acceleration, a
constant speed and the critical-speed ramp (a constant deceleration) are special cases.
Constant acceleration between points was chosen over a speed linear in distance because it is
what a driver or a test programme prescribes (a traction or braking rate), it makes the
vehicle frame's acceleration piecewise constant, and the ramp stays exact.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

from railexu.errors import InputError

#: Largest acceleration or deceleration a profile may ask for [m/s^2]: above the adhesion of dry
#: rail (mu g = 0.4 x 9.81 = 3.9 m/s^2 with every axle braked), so no wheel-rail vehicle can
#: follow it; a larger value is a unit mistake (km/h for m/s, km for m).
MAX_ACCELERATION_M_PER_S2 = 5.0
#: Highest speed a profile may ask for [m/s]: the same limit as a run's constant ``speed``
#: (540 km/h, above every service speed; a larger value is usually km/h given as m/s).
MAX_SPEED_M_PER_S = 150.0


class SpeedProfileError(InputError):
    """An invalid profile; the message says what is wrong (the caller adds the key)."""


@dataclass(frozen=True)
class SpeedProfile:
    """Forward speed as a function of the distance run: points ``(distance [m], speed [m/s])``
    with increasing distances from 0 and positive speeds, constant acceleration between them
    (module doc).

    Raises:
        SpeedProfileError: fewer than one point, a first distance other than 0, distances not
            increasing, a speed that is not positive, an acceleration above
            :data:`MAX_ACCELERATION_M_PER_S2`.
    """

    points: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        pts = tuple((float(s), float(v)) for s, v in self.points)
        object.__setattr__(self, "points", pts)
        if not pts:
            raise SpeedProfileError("needs at least one (distance, speed) point")
        for i, (s, v) in enumerate(pts):
            if not (math.isfinite(s) and math.isfinite(v)):
                raise SpeedProfileError(f"point {i + 1}: expected finite values, got {s!r}, {v!r}")
            if not v > 0.0:
                raise SpeedProfileError(
                    f"point {i + 1} ({s:g} m): speed must be > 0 m/s, got {v:g} m/s (the "
                    "creepages are normalised by the speed: a profile cannot stop the vehicle)"
                )
            if v > MAX_SPEED_M_PER_S:
                raise SpeedProfileError(
                    f"point {i + 1} ({s:g} m): speed must be <= {MAX_SPEED_M_PER_S:g} m/s "
                    f"(540 km/h, the limit of a run's speed), got {v:g} m/s: is a unit wrong?"
                )
        if pts[0][0] != 0.0:
            raise SpeedProfileError(f"the first point must be at 0 m, got {pts[0][0]:g} m")
        times = [0.0]
        for i in range(1, len(pts)):
            (s0, v0), (s1, v1) = pts[i - 1], pts[i]
            if not s1 > s0:
                raise SpeedProfileError(
                    f"distances must increase: point {i + 1} ({s1:g} m) is not beyond point {i} "
                    f"({s0:g} m)"
                )
            a = (v1 * v1 - v0 * v0) / (2.0 * (s1 - s0))
            if abs(a) > MAX_ACCELERATION_M_PER_S2:
                raise SpeedProfileError(
                    f"{v0:g} -> {v1:g} m/s between {s0:g} m and {s1:g} m needs "
                    f"{a:.3g} m/s^2, more than {MAX_ACCELERATION_M_PER_S2:g} m/s^2 (beyond the "
                    "adhesion of dry rail): is a unit wrong?"
                )
            times.append(times[-1] + 2.0 * (s1 - s0) / (v0 + v1))
        object.__setattr__(self, "_times", tuple(times))

    # -- constructors ---------------------------------------------------------------------------
    @classmethod
    def constant(cls, speed_m_per_s: float) -> SpeedProfile:
        """A constant speed."""
        return cls(((0.0, speed_m_per_s),))

    @classmethod
    def ramp(cls, speed_m_per_s: float, acceleration_m_per_s2: float, distance_m: float):
        """A constant acceleration (negative: deceleration) from ``speed_m_per_s`` over
        ``distance_m``."""
        v2 = speed_m_per_s**2 + 2.0 * acceleration_m_per_s2 * distance_m
        if not v2 > 0.0:
            raise SpeedProfileError("the deceleration stops the vehicle before the end")
        return cls(((0.0, speed_m_per_s), (distance_m, math.sqrt(v2))))

    # -- queries --------------------------------------------------------------------------------
    @property
    def times_s(self) -> tuple[float, ...]:
        """Time at each point [s]."""
        return self._times  # type: ignore[attr-defined]

    @property
    def start_speed_m_per_s(self) -> float:
        return self.points[0][1]

    @property
    def max_speed_m_per_s(self) -> float:
        return max(v for _, v in self.points)

    @property
    def end_distance_m(self) -> float:
        """Distance of the last point [m] (the speed is constant beyond it)."""
        return self.points[-1][0]

    def _segment(self, t: float) -> tuple[float, float, float, float]:
        """``(t0, s0, v0, a)`` of the segment holding time ``t`` (constant speed after the last
        point, the first segment's state before 0)."""
        times = self.times_s
        i = max(0, min(bisect.bisect_right(times, t) - 1, len(times) - 1))
        s0, v0 = self.points[i]
        if i == len(times) - 1:
            return times[i], s0, v0, 0.0
        s1, v1 = self.points[i + 1]
        return times[i], s0, v0, (v1 - v0) / (times[i + 1] - times[i])

    def speed_at(self, t: float) -> float:
        """Forward speed at time ``t`` [m/s]."""
        t0, _, v0, a = self._segment(t)
        return v0 + a * (t - t0)

    def distance_at(self, t: float) -> float:
        """Distance run at time ``t`` [m]."""
        t0, s0, v0, a = self._segment(t)
        dt = t - t0
        return s0 + v0 * dt + 0.5 * a * dt * dt

    def acceleration_at(self, t: float) -> float:
        """Forward acceleration at time ``t`` [m/s^2] (piecewise constant)."""
        return self._segment(t)[3]

    def time_at_distance(self, s: float) -> float:
        """Time at which the distance ``s`` is reached [s] (exact, per segment)."""
        pts = self.points
        dists = [p[0] for p in pts]
        i = max(0, min(bisect.bisect_right(dists, s) - 1, len(pts) - 1))
        s0, v0 = pts[i]
        t0 = self.times_s[i]
        if i == len(pts) - 1:
            return t0 + (s - s0) / v0
        s1, v1 = pts[i + 1]
        v = math.sqrt(max(v0 * v0 + (v1 * v1 - v0 * v0) * (s - s0) / (s1 - s0), 0.0))
        return t0 + 2.0 * (s - s0) / (v0 + v)

    def check_covers(self, distance_m: float) -> None:
        """Refuse a profile whose last point is before ``distance_m``."""
        if self.end_distance_m < distance_m * (1.0 - 1e-12):
            raise SpeedProfileError(
                f"ends at {self.end_distance_m:g} m, before the run's distance {distance_m:g} m: "
                "the profile must cover the whole run"
            )
