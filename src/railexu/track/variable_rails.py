"""A zone of the track whose rails vary along it: switches and crossings (issue 29).

:class:`VariableRails` names, per side, a variable rail profile
(:class:`~railexu.profiles.variable.VariableProfile`: slices interpolated along the track, one
curve or several rails per side) and where its ``s = 0`` lies on the track. Inside the zone the
dynamics reads kernel rail tables of the profile at stations every ``station_step_m``, blended
linearly between stations (:mod:`railexu.model.forces`); outside it the track's rail profile as
on plain track. Given from Python (``Track(..., variable_rails=VariableRails(...))``) or by a
track file's ``variable_rails:`` section (:mod:`railexu.track.variable_rails_file`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from railexu.errors import InputError
from railexu.profiles.variable import VariableProfile


@dataclass(frozen=True, eq=False)
class VariableRails:
    """Variable rail profiles of an S&C zone.

    Attributes:
        left, right: the variable profile of each side (``None``: the track's rail there). A
            side's profile is in that rail's own axes, field side positive, z down (a left-type
            rail, as every rail profile in railexu).
        start_m: track distance of the profiles' ``s = 0`` [m].
        station_step_m: distance between the stations whose tables are blended [m].
        rail_origin_m: ``(y, z)`` of the profiles' origin in the track's left-type axes [m];
            ``None``: the placed rail profile's own origin (slices in the track's rail axes).
        x_max_m: half-length of the effective section (contact ahead of or behind the axle) [m].
    """

    left: VariableProfile | None = None
    right: VariableProfile | None = None
    start_m: float = 0.0
    station_step_m: float = 0.01
    rail_origin_m: tuple[float, float] | None = None
    x_max_m: float = 0.06

    def __post_init__(self) -> None:
        if self.left is None and self.right is None:
            raise InputError("variable rails: give a variable profile for the left or right rail")
        for name in ("start_m", "station_step_m", "x_max_m"):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise InputError(f"variable rails: {name} = {value}: expected a finite number")
        if not 1e-4 <= self.station_step_m <= 1.0:
            raise InputError(
                f"variable rails: station_step_m = {self.station_step_m}: expected 0.1 mm .. 1 m"
            )
        if not 0.0 <= self.x_max_m <= 0.2:
            raise InputError(f"variable rails: x_max_m = {self.x_max_m}: expected 0 .. 0.2 m")

    def sides(self) -> tuple[VariableProfile | None, VariableProfile | None]:
        """``(left, right)``."""
        return self.left, self.right

    def zone_m(self) -> tuple[float, float]:
        """Track distances of the zone's first and last slice [m] (both sides together)."""
        ranges = [p.s_range_m for p in self.sides() if p is not None]
        return (self.start_m + min(r[0] for r in ranges), self.start_m + max(r[1] for r in ranges))
