"""A zone of the track whose rails vary along it: switches and crossings (issue 29).

:class:`VariableRails` names, per side, a variable rail profile
(:class:`~railexu.profiles.variable.VariableProfile`: slices interpolated along the track, one
curve or several rails per side) and where its ``s = 0`` lies on the track. Inside the zone the
dynamics reads kernel rail tables of the profile at stations every ``station_step_m``, blended
linearly between stations (:mod:`railexu.model.forces`); outside it the track's rail profile as
on plain track. Parts of the zone may have their own station step (``station_steps_m``: finer
stations in a crossing, coarser along a switch blade): the stations are then the union of each
part's uniform grid (:meth:`VariableRails.stations_m`). Given from Python (``Track(...,
variable_rails=VariableRails(...))``) or by a track file's ``variable_rails:`` section
(:mod:`railexu.track.variable_rails_file`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from railexu.errors import InputError
from railexu.profiles.variable import VariableProfile

#: Stations closer than this are one (the later dropped, a part's end kept) [m]: float rounding
#: of ``a + k step`` against a part's end; 1 % of the smallest step accepted (0.1 mm).
SAME_STATION_M = 1.0e-6
#: Most stations of one zone (railexu's bound): a station's effective-section table takes about
#: 0.7 MB per side (the shipped crossing: 833 MB for 569 stations of 10 mm and two sides), so 5000
#: stations stay within about 7 GB; the shipped turnout with 5 mm crossing stations has 1615-1616.
MAX_STATIONS = 5000

#: The contact filter's length along the track [m] of a zone built from Python
#: (:mod:`railexu.model.sc_filter`): 0, not filtered; a zone built in code states its filter.
DEFAULT_CONTACT_FILTER_M = 0.0
#: The contact filter's length [m] of a track file's zone (``variable_rails:``) and of a
#: turnout (``turnout:``) unless the file sets ``contact_filter``: railexu's assumption, a box
#: with the second moment of a Hertz patch's load along the track, ``L^2 / 12 = a^2 / 5``,
#: ``a = 7.7 mm`` (the loaded wagon's wheel, 130 kN on a 0.46 m wheel and a 0.3 m crown):
#: applied at the wheelset's position and with stations of 5 mm (``L / 2``) or less the
#: crossing's peaks converge with the station step (docs/switches-and-crossings.md, the
#: turnout's "Cost").
FILE_CONTACT_FILTER_M = 0.012
#: A turnout's stations over its crossing panel [m] unless the file sets
#: ``crossing_station_step`` (or a finer ``station_step``): fine enough for
#: :data:`FILE_CONTACT_FILTER_M`, ``L / 2`` (with the filter at the wheelset: the named windows
#: of the crossing within 1 % of their 2.5 mm values at 5 mm, 3.4 % below them at 10 mm; 20 mm
#: stations do not converge; docs/switches-and-crossings.md, the turnout's "Cost").
FILE_CROSSING_STATION_STEP_M = 0.005


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
        station_steps_m: parts of the zone with their own station step, ``(from, to, step)``
            in track distances [m] (e.g. a turnout's crossing panel at 5 mm, the rest at
            ``station_step_m``); parts must not overlap. Empty: one uniform grid.
        grids_from_end: with parts of their own step, each grid (a part's, the zone's
            default) runs from its last track distance backwards instead of from its first: the
            stations of a zone met in reverse (a track file's ``direction: trailing``) are then
            the mirror image of the facing zone's, at the same slices' ``s``. Refused without
            parts (a uniform zone's stations run from its first slice: the kernel's division).
        contact_filter_m: length of the contact filter along the track [m]: the station tables
            are the effective section averaged over a box of this length centred on each
            station (:mod:`railexu.model.sc_filter`, railexu's assumption for a contact patch
            10-15 mm long); 0: not filtered.
    """

    left: VariableProfile | None = None
    right: VariableProfile | None = None
    start_m: float = 0.0
    station_step_m: float = 0.01
    rail_origin_m: tuple[float, float] | None = None
    x_max_m: float = 0.06
    station_steps_m: tuple[tuple[float, float, float], ...] = ()
    grids_from_end: bool = False
    contact_filter_m: float = DEFAULT_CONTACT_FILTER_M

    def __post_init__(self) -> None:
        if self.left is None and self.right is None:
            raise InputError("variable rails: give a variable profile for the left or right rail")
        for name in ("start_m", "station_step_m", "x_max_m", "contact_filter_m"):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise InputError(f"variable rails: {name} = {value}: expected a finite number")
        if not 1e-4 <= self.station_step_m <= 1.0:
            raise InputError(
                f"variable rails: station_step_m = {self.station_step_m}: expected 0.1 mm .. 1 m"
            )
        if not 0.0 <= self.x_max_m <= 0.2:
            raise InputError(f"variable rails: x_max_m = {self.x_max_m}: expected 0 .. 0.2 m")
        if not 0.0 <= self.contact_filter_m <= 0.1:
            raise InputError(
                f"variable rails: contact_filter_m = {self.contact_filter_m}: expected 0 .. 0.1 m"
            )
        parts = sorted(tuple(float(v) for v in p) for p in self.station_steps_m)
        for a, b, step in parts:
            if not (math.isfinite(a) and math.isfinite(b) and a < b):
                raise InputError(f"variable rails: station step part {a} .. {b} m: expected "
                                 "finite track distances, from < to")  # fmt: skip
            if not 1e-4 <= step <= 1.0:
                raise InputError(f"variable rails: station step {step} m of the part {a} .. "
                                 f"{b} m: expected 0.1 mm .. 1 m")  # fmt: skip
        for (a0, b0, _), (a1, b1, _) in zip(parts, parts[1:], strict=False):
            if a1 < b0:
                raise InputError(f"variable rails: station step parts {a0} .. {b0} m and {a1} "
                                 f".. {b1} m overlap")  # fmt: skip
        object.__setattr__(self, "station_steps_m", tuple(parts))
        if self.grids_from_end and not parts:
            raise InputError(
                "variable rails: grids_from_end needs parts of their own step "
                "(station_steps_m); a uniform zone's grid runs from its first slice"
            )

    def sides(self) -> tuple[VariableProfile | None, VariableProfile | None]:
        """``(left, right)``."""
        return self.left, self.right

    def zone_m(self) -> tuple[float, float]:
        """Track distances of the zone's first and last slice [m] (both sides together)."""
        ranges = [p.s_range_m for p in self.sides() if p is not None]
        return (self.start_m + min(r[0] for r in ranges), self.start_m + max(r[1] for r in ranges))

    @property
    def uniform(self) -> bool:
        """Whether the stations are ``first + i station_step_m`` (no part with its own step)."""
        return not self.station_steps_m

    def stations_m(self) -> np.ndarray:
        """Track distances of the stations whose tables the dynamics blends [m], increasing.

        Uniform: every ``station_step_m`` from the zone's first slice, the last at or before
        its last slice (at least two). With parts of their own step: the union of each part's
        uniform grid (from the part's start, its end included) and of the zone's default grid
        outside the parts, both zone ends included; stations closer than
        :data:`SAME_STATION_M` are one. ``grids_from_end``: each grid from its last track
        distance backwards (the mirror image of the same parts met facing)."""
        lo, hi = self.zone_m()
        step = self.station_step_m
        if self.uniform:
            n = int(np.floor((hi - lo) / step)) + 1
            return lo + step * np.arange(max(n, 2))
        if self.grids_from_end:  # the same union in the mirrored distance -x
            parts = [(-b, -a, h) for a, b, h in self.station_steps_m]
            return -_union_of_grids(-hi, -lo, step, parts)[::-1]
        return _union_of_grids(lo, hi, step, self.station_steps_m)

    def too_many_stations(self) -> str | None:
        """Why the zone's stations are too many to build (:data:`MAX_STATIONS`), or None."""
        n = self.stations_m().size
        if n <= MAX_STATIONS:
            return None
        return (f"the zone has {n} stations (about {n * 0.7e-3 * 2:.0f} GB of tables): expected "
                f"at most {MAX_STATIONS}; give a larger station step or shorter parts")  # fmt: skip


def _union_of_grids(
    lo: float, hi: float, step: float, parts: Iterable[tuple[float, float, float]]
) -> np.ndarray:
    """The zone's default grid (``step`` from ``lo``) outside the parts, each part's own grid,
    both zone ends and the parts' ends [m], increasing; stations closer than
    :data:`SAME_STATION_M` are one (an end kept)."""
    grid = _grid(lo, hi, step)
    outside = np.ones(grid.size, dtype=bool)
    ends = [np.array([lo, hi])]
    grids = []
    for a, b, h in parts:
        a, b = max(a, lo), min(b, hi)
        if b <= a:
            continue
        outside &= (grid <= a) | (grid >= b)
        grids.append(_grid(a, b, h))
        ends.append(np.array([a, b]))
    x = np.sort(np.concatenate([grid[outside], *grids, *ends]))
    keep = [0]
    ends_set = np.concatenate(ends)
    for k in range(1, x.size):
        if x[k] - x[keep[-1]] > SAME_STATION_M:
            keep.append(k)
        elif np.any(ends_set == x[k]):  # a part's end or the zone's: it wins
            keep[-1] = k
    return x[keep]


def _grid(a: float, b: float, step: float) -> np.ndarray:
    """``a + k step`` from ``a`` up to ``b`` [m], and ``b`` itself (closer than
    :data:`SAME_STATION_M` to the last: replaces it)."""
    x = a + step * np.arange(int(np.floor((b - a) / step)) + 1)
    if b - x[-1] > SAME_STATION_M:
        return np.append(x, b)
    x[-1] = b if x.size > 1 else x[-1]
    return x
