"""Several variable profiles along one side of a zone, the plain rail between them.

A turnout's side holds the switch panel (stock rail and blade) and, some 20 m further, the
crossing panel (wing rail and nose), with plain rail between. :class:`ZonedProfile` puts each
panel's :class:`~railexu.profiles.variable.VariableProfile` at its own position and offset
(each panel in its own axes: the crossing's slices keep CONTACT's origin) and gives the plain
rail's curve between and beyond them. It offers what the dynamics and the outputs read of a
variable profile (``s_range_m``, ``curves_at``, ``heights_on_grid``, ``slices.source``), so a
:class:`~railexu.track.variable_rails.VariableRails` side may be either.

Inside a panel the curves are the panel's, shifted by its offset; between panels (and outside
all of them) the plain rail. A panel's own profile is constant beyond its first and last slice,
so a panel whose end slices are not the plain rail has a step there (the shipped crossing's
slices 41-60: docs/switches-and-crossings.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railexu.profiles.core import ProfileError
from railexu.profiles.variable.interpolate import VariableProfile, top_surface_heights
from railexu.profiles.variable.slices import ProfileSlices


@dataclass(frozen=True)
class Panel:
    """One variable profile placed along the side.

    Attributes:
        profile: the panel's variable profile (its own ``s`` and axes).
        s0_m: where the panel's ``s = 0`` lies in the zoned profile's ``s`` [m].
        offset_m: ``(dy, dz)`` added to the panel's points to give the zoned profile's axes [m].
    """

    profile: VariableProfile
    s0_m: float = 0.0
    offset_m: tuple[float, float] = (0.0, 0.0)

    @property
    def range_m(self) -> tuple[float, float]:
        lo, hi = self.profile.s_range_m
        return self.s0_m + lo, self.s0_m + hi


@dataclass(frozen=True)
class _Source:
    """What readers of ``profile.slices`` ask of a zoned profile: its name; no feature points
    spanning the zone (each panel has its own)."""

    source: str
    features_m: None = None


class ZonedProfile:
    """Panels of variable profile along one side, the plain rail between (module docstring)."""

    def __init__(self, panels: list[Panel], plain_points_m: np.ndarray, source: str):
        if not panels:
            raise ProfileError(f"{source}: a zoned profile needs at least one panel")
        order = sorted(panels, key=lambda p: p.range_m[0])
        for a, b in zip(order, order[1:], strict=False):
            if b.range_m[0] <= a.range_m[1]:
                raise ProfileError(
                    f"{source}: the panels {a.profile.slices.source} ({a.range_m[0]:.3f} .. "
                    f"{a.range_m[1]:.3f} m) and {b.profile.slices.source} ({b.range_m[0]:.3f} "
                    f".. {b.range_m[1]:.3f} m) overlap: expected panels one after the other"
                )
        plain = np.asarray(plain_points_m, dtype=float)
        if plain.ndim != 2 or plain.shape[0] < 4 or not np.all(np.diff(plain[:, 0]) > 0):
            raise ProfileError(f"{source}: the plain rail's points must be a graph z(y)")
        self.panels = tuple(order)
        # the plain rail resampled as every slice is: where a panel's end slice is the plain
        # rail, the surface is the same on both sides of the panel's end, to the last bit
        uniform = ProfileSlices(f"{source} (plain rail)", np.array([0.0, 1.0]), (plain, plain),
                                None, (None, None), ("plain", "plain"))  # fmt: skip
        self.plain_m = VariableProfile(uniform).curves_at(0.0)[0]
        self.slices = _Source(source)

    @property
    def s_range_m(self) -> tuple[float, float]:
        """First slice of the first panel and last slice of the last [m]."""
        return self.panels[0].range_m[0], self.panels[-1].range_m[1]

    def panel_at(self, s_m: float) -> Panel | None:
        """The panel whose slices span ``s`` (None: plain rail there)."""
        for p in self.panels:
            lo, hi = p.range_m
            if lo <= s_m <= hi:
                return p
        return None

    def is_plain_over(self, lo_m: float, hi_m: float) -> bool:
        """Whether ``[lo, hi]`` lies outside every panel: the surface is the plain rail all
        along it (a station's effective section there is the plain rail's, the same at every
        such station: a table store may keep it once)."""
        return all(hi_m < p.range_m[0] or lo_m > p.range_m[1] for p in self.panels)

    def curves_at(self, s_m: float) -> list[np.ndarray]:
        """The curves ``(m, 2)`` [m] at ``s``: the panel's (shifted) or the plain rail."""
        p = self.panel_at(float(s_m))
        if p is None:
            return [self.plain_m]
        shift = np.asarray(p.offset_m, dtype=float)
        return [c + shift for c in p.profile.curves_at(float(s_m) - p.s0_m)]

    def heights_on_grid(
        self, s_m: np.ndarray, y_m: np.ndarray, *, smooth: bool = False
    ) -> np.ndarray:
        """``z(y)`` [m] (down) of the top surface at each ``s`` (as
        :meth:`VariableProfile.heights_on_grid`: ``+inf`` where no rail lies; ``smooth``
        a monotone cubic between the curves' points)."""
        return top_surface_heights(self.curves_at, s_m, y_m, smooth=smooth)


__all__ = ["Panel", "ZonedProfile"]
