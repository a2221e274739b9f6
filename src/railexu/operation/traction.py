"""Traction and braking demands of a run with the forward motion free (SI units).

A run with a :class:`Traction` has no speed constraint: a traction torque on each driven
wheelset and a brake force on each wheel act, and the longitudinal creep forces (adhesion)
decide how the vehicle moves (``docs/traction-and-braking.md``). Each demand is constant or a
:class:`Schedule`, a table over time or over distance, linear between its points and constant
beyond them.

Which wheelsets are driven is given with the torque (a run property here, like the torque
demand itself; the vehicle files have no key for it yet).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field

from railexu.errors import InputError, did_you_mean

#: Largest traction torque per wheelset accepted [N m]: 10 times the torque that slips a
#: 25 t axle load wheelset of 0.625 m radius at mu = 0.5 (about 77 kN m); more is a unit mistake.
MAX_TORQUE_N_M = 1.0e6
#: Largest brake force per wheel [N]: ten times the normal force of a 25 t axle's wheel.
MAX_BRAKE_FORCE_N = 1.25e6
#: The bases a schedule may be given over, with the unit of its first column.
BASES = {"time": "s", "distance": "m"}


class TractionError(InputError):
    """An invalid traction setting (the caller adds file, line and key)."""


@dataclass(frozen=True)
class Schedule:
    """A value given constant or as a table over time [s] or distance [m]: points
    ``(t or s, value)`` with increasing abscissae, linear between them, constant beyond."""

    points: tuple[tuple[float, float], ...]
    basis: str = "time"

    def __post_init__(self) -> None:
        pts = tuple((float(x), float(y)) for x, y in self.points)
        object.__setattr__(self, "points", pts)
        if self.basis not in BASES:
            raise TractionError(f"basis must be one of {', '.join(BASES)}, got {self.basis!r}")
        if not pts:
            raise TractionError("needs at least one point")
        for i, (x, y) in enumerate(pts):
            if not (math.isfinite(x) and math.isfinite(y)):
                raise TractionError(f"point {i + 1}: expected finite values, got {x!r}, {y!r}")
            if i and not x > pts[i - 1][0]:
                raise TractionError(
                    f"the {self.basis}s must increase: point {i + 1} ({x:g} {BASES[self.basis]}) "
                    f"is not beyond point {i}"
                )

    @classmethod
    def constant(cls, value: float) -> Schedule:
        return cls(((0.0, value),))

    def value(self, time_s: float, distance_m: float) -> float:
        """The value at a time and distance (the one of the schedule's basis is used)."""
        x = time_s if self.basis == "time" else distance_m
        pts = self.points
        xs = [p[0] for p in pts]
        i = bisect.bisect_right(xs, x)
        if i == 0:
            return pts[0][1]
        if i == len(pts):
            return pts[-1][1]
        (x0, y0), (x1, y1) = pts[i - 1], pts[i]
        return y0 + (y1 - y0) * (x - x0) / (x1 - x0)

    def extremes(self) -> tuple[float, float]:
        values = [y for _, y in self.points]
        return min(values), max(values)


@dataclass(frozen=True)
class Traction:
    """Traction and brake demands; with them the forward motion of the vehicle is free.

    Attributes:
        torque_N_m: traction torque on each driven wheelset [N m] (positive drives forward).
        wheelsets: names of the driven wheelsets (empty: all).
        brake_force_N: tread-brake force on each wheel [N] (>= 0), acting as the torque
            ``force x nominal radius`` against the wheelset's spin.
        time_limit_s: the run ends at its distance or at this time, whichever comes first
            (None: three times the time the distance takes at the start speed).
    """

    torque_N_m: Schedule = field(default_factory=lambda: Schedule.constant(0.0))
    wheelsets: tuple[str, ...] = ()
    brake_force_N: Schedule = field(default_factory=lambda: Schedule.constant(0.0))
    time_limit_s: float | None = None

    def __post_init__(self) -> None:
        lo, hi = self.torque_N_m.extremes()
        if max(abs(lo), abs(hi)) > MAX_TORQUE_N_M:
            raise TractionError(
                f"traction_torque: {max(abs(lo), abs(hi)):.3g} N m is more than "
                f"{MAX_TORQUE_N_M:.3g} N m per wheelset: is a unit wrong?"
            )
        lo, hi = self.brake_force_N.extremes()
        if lo < 0.0:
            raise TractionError(f"brake_force: must be >= 0 N, got {lo:g} N")
        if hi > MAX_BRAKE_FORCE_N:
            raise TractionError(
                f"brake_force: {hi:.3g} N per wheel is more than {MAX_BRAKE_FORCE_N:.3g} N: is "
                "a unit wrong?"
            )
        if self.time_limit_s is not None and not self.time_limit_s > 0.0:
            raise TractionError(f"time_limit: must be > 0 s, got {self.time_limit_s:g} s")
        object.__setattr__(self, "wheelsets", tuple(self.wheelsets))

    def driven(self, names: list[str]) -> list[str]:
        """The driven wheelsets among ``names`` (all if none are named).

        Raises:
            TractionError: a named wheelset the vehicle does not have.
        """
        for name in self.wheelsets:
            if name not in names:
                raise TractionError(
                    f"driven_wheelsets: unknown wheelset {name!r}.{did_you_mean(name, names)} The "
                    f"vehicle's wheelsets: {', '.join(names)}"
                )
        return list(self.wheelsets) or list(names)
