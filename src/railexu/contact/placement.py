"""Place a wheel and a rail profile in the track: inclination, gauge, flange back, rolling radius.

The result, :class:`WheelRailPair`, holds everything the contact search needs for one side in the
"left-type" frame of ``docs/conventions.md`` (outwards = ``+y``): the canted rail as a graph
``z(y)`` in track axes with the top of rail at ``z = 0`` and the gauge point at ``y = gauge/2``,
and the wheel profile with the lateral position of its tape circle on the axle. The right side is
the mirror image, so one pair serves a symmetric wheelset; :class:`WheelsetGeometry` holds one pair
per side so that left and right profiles may differ (worn wheels, asymmetric rails).

Track gauge is measured as EN 13848-1 defines it: the smallest distance between the two rail
heads within the band from the running surface down to 14 mm below it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from railexu.contact.standard_gauge import STANDARD_FLANGE_BACK_M, STANDARD_GAUGE_M
from railexu.errors import InputError
from railexu.profiles import Profile, SampledProfile, rail_profile, wheel_profile

#: Lateral step of the tables the compiled kernel interpolates [m].
TABLE_STEP_M = 5.0e-5

#: Default gauge measurement depth below the top of rail [m] (EN 13848-1).
GAUGE_MEASUREMENT_DEPTH_M = 0.014


class PlacementError(InputError):
    """A wheel/rail placement that cannot be built (bad inclination, wheel without flange back)."""


def parse_inclination(value: str | float | int | None) -> float:
    """Rail inclination as an angle [rad] from ``"1:40"``, ``"1/40"``, ``"none"``, ``0`` or a float.

    A bare number is taken as the angle in radians; ``"1:n"`` as the slope 1/n, whose angle is
    ``atan(1/n)`` (1:40 -> 0.024995 rad, 1:20 -> 0.049958 rad).
    """
    if value is None:
        return 0.0
    if isinstance(value, int | float):
        return float(value)
    text = str(value).strip().lower()
    if text in ("none", "0", "0.0", "vertical", "upright"):
        return 0.0
    for sep in (":", "/"):
        if sep in text:
            num, den = text.split(sep, 1)
            try:
                ratio = Fraction(num.strip()) / Fraction(den.strip())
            except (ValueError, ZeroDivisionError) as exc:
                raise PlacementError(
                    f"rail inclination {value!r}: expected '1:40', '1:20', 'none' or rad"
                ) from exc
            return float(np.arctan(float(ratio)))
    try:
        return float(text)
    except ValueError as exc:
        raise PlacementError(
            f"rail inclination {value!r}: expected '1:40', '1:20', 'none' or an angle in rad"
        ) from exc


def _rotate(y: np.ndarray, z: np.ndarray, angle: float) -> tuple[np.ndarray, np.ndarray]:
    """Rotate points counter-clockwise in the (y outwards, z up) plane by ``angle`` [rad].

    A positive angle tilts the top of a rail towards ``-y``, the gauge side of a left-type rail.
    """
    c, s = np.cos(angle), np.sin(angle)
    return c * y - s * z, s * y + c * z


@dataclass(frozen=True)
class WheelRailPair:
    """One wheel and its rail, placed in the left-type track frame.

    Attributes:
        wheel: the wheel profile (lateral from the tape circle, value = radius increase).
        rail: the rail profile as given (its own axes, maybe pre-canted).
        nominal_radius_m: rolling radius at the tape circle ``r0``.
        tape_circle_lateral_m: distance ``e`` of the tape circle from the wheelset centre along
            the axle (0.750 m for a 1.360 m flange-back distance and S1002).
        rail_table: the canted rail as a graph in track axes: ``z`` [m] over track ``y`` [m], top
            of rail at ``z = 0``; uniform grid for the kernel.
        wheel_table: the wheel's radius increase over its lateral coordinate ``s``; uniform grid.
        rail_cant_rad: rotation applied to the rail's own axes to reach track axes.
        rail_origin_track_m: ``(y, z)`` of the rail profile's own origin in track axes, so that
            a track point maps back to the profile's own coordinates (for reporting).
        rail_canted: the rail profile turned by ``rail_cant_rad`` about its own origin; track
            axes are its axes shifted by ``rail_origin_track_m``.
        gauge_point_track_m: ``(y, z)`` of the gauge point (track axes).
    """

    wheel: Profile
    rail: Profile
    nominal_radius_m: float
    tape_circle_lateral_m: float
    inclination_rad: float
    gauge_m: float
    flange_back_distance_m: float
    rail_table: SampledProfile
    wheel_table: SampledProfile
    rail_cant_rad: float
    rail_origin_track_m: tuple[float, float]
    gauge_point_track_m: tuple[float, float]
    rail_canted: Profile = field(repr=False)
    rail_outline_track_m: np.ndarray = field(repr=False)

    def rail_track_to_own(self, y_track: np.ndarray | float, z_track: np.ndarray | float):
        """Map track-axis points (left-type frame) back to the rail profile's own axes [m]."""
        y0, z0 = self.rail_origin_track_m
        return _rotate(np.asarray(y_track) - y0, np.asarray(z_track) - z0, -self.rail_cant_rad)

    def rail_height(self, y_track: np.ndarray | float) -> np.ndarray:
        """Height of the placed rail [m] at track lateral position ``y_track`` (left-type)."""
        t = self.rail_table
        return np.interp(y_track, t.y0_m + t.step_m * np.arange(t.z.size), t.z)


def place_wheel_rail(
    wheel: Profile | str,
    rail: Profile | str,
    *,
    nominal_radius_m: float,
    inclination: str | float | None = "1:40",
    gauge_m: float = STANDARD_GAUGE_M,
    flange_back_distance_m: float = STANDARD_FLANGE_BACK_M,
    gauge_depth_m: float = GAUGE_MEASUREMENT_DEPTH_M,
    table_step_m: float = TABLE_STEP_M,
) -> WheelRailPair:
    """Place a wheel and a rail profile in the track (left-type frame, see conventions).

    Args:
        wheel: wheel profile or a built-in name / file path (``"S1002"``).
        rail: rail profile or a built-in name / file path (``"UIC60"``).
        nominal_radius_m: rolling radius at the tape circle [m] (EU07: 0.625).
        inclination: final rail inclination (``"1:40"``, ``"1:20"``, ``"none"`` or rad). A rail
            profile that is already canted (``Profile.inclination_rad``) is only turned by the
            difference.
        gauge_m: track gauge [m], measured ``gauge_depth_m`` below the top of rail.
        flange_back_distance_m: distance between the two wheels' flange backs [m].
        gauge_depth_m: depth of the gauge measurement below the top of rail [m].
        table_step_m: lateral step of the kernel tables [m].
    """
    wheel_p = wheel if isinstance(wheel, Profile) else wheel_profile(wheel)
    rail_p = rail if isinstance(rail, Profile) else rail_profile(rail)
    if wheel_p.kind != "wheel":
        raise PlacementError(f"profile {wheel_p.name!r} is a {wheel_p.kind} profile, not a wheel")
    if rail_p.kind != "rail":
        raise PlacementError(f"profile {rail_p.name!r} is a {rail_p.kind} profile, not a rail")
    if not nominal_radius_m > 0.0:
        raise PlacementError(f"nominal radius must be > 0 m, got {nominal_radius_m}")
    if not 1.0 < gauge_m < 2.0:
        raise PlacementError(f"track gauge {gauge_m} m is outside 1 .. 2 m (is it in metres?)")
    inclination_rad = parse_inclination(inclination)
    cant = inclination_rad - float(rail_p.inclination_rad)

    # Rail: rotate the outline and the graph, find the top and the gauge point.
    outline = np.asarray(rail_p.outline_m, dtype=float)
    oy, oz = _rotate(outline[:, 0], outline[:, 1], cant)
    canted = rail_p.canted(cant) if cant != 0.0 else rail_p
    grid_y = np.arange(canted.y_min, canted.y_max, 2.0e-5)
    z_top = float(np.max(canted.height(grid_y)))
    in_band = oz >= z_top - gauge_depth_m
    if not np.any(in_band):
        raise PlacementError(f"rail {rail_p.name!r}: no outline point within the gauge band")
    # Innermost point of the head within the band (gauge side = -y); interpolate the crossing of
    # the band's lower edge so that the result does not depend on the outline's point spacing.
    y_gauge = _innermost_within_band(oy, oz, z_top - gauge_depth_m)
    y_offset = 0.5 * gauge_m - y_gauge
    sampled = canted.sampled(table_step_m)
    rail_table = SampledProfile(
        y0_m=sampled.y0_m + y_offset,
        step_m=sampled.step_m,
        z=sampled.z - z_top,
        dz=sampled.dz,
        d2z=sampled.d2z,
    )
    origin = (y_offset, -z_top)

    # Wheel: tape circle position on the axle from the flange back.
    if wheel_p.flange_back_m is None:
        raise PlacementError(
            f"wheel profile {wheel_p.name!r} has no flange back: give its position to place it"
        )
    tape = 0.5 * flange_back_distance_m - float(wheel_p.flange_back_m)
    wheel_table = wheel_p.sampled(table_step_m)
    return WheelRailPair(
        wheel=wheel_p,
        rail=rail_p,
        nominal_radius_m=float(nominal_radius_m),
        tape_circle_lateral_m=float(tape),
        inclination_rad=inclination_rad,
        gauge_m=float(gauge_m),
        flange_back_distance_m=float(flange_back_distance_m),
        rail_table=rail_table,
        wheel_table=wheel_table,
        rail_cant_rad=cant,
        rail_origin_track_m=origin,
        gauge_point_track_m=(0.5 * gauge_m, -gauge_depth_m),
        rail_canted=canted,
        rail_outline_track_m=np.column_stack([oy + y_offset, oz - z_top]),
    )


def _innermost_within_band(y: np.ndarray, z: np.ndarray, z_low: float) -> float:
    """Smallest ``y`` of a polyline restricted to ``z >= z_low`` (crossings interpolated)."""
    best = np.inf
    inside = z >= z_low
    best = min(best, float(np.min(y[inside])))
    # Segments crossing the lower edge of the band.
    for i in np.nonzero(inside[:-1] != inside[1:])[0]:
        t = (z_low - z[i]) / (z[i + 1] - z[i])
        best = min(best, float(y[i] + t * (y[i + 1] - y[i])))
    return best


@dataclass(frozen=True)
class WheelsetGeometry:
    """Both wheel/rail pairs of a wheelset, ``left`` and ``right``, each in its left-type frame."""

    left: WheelRailPair
    right: WheelRailPair

    @property
    def pairs(self) -> tuple[WheelRailPair, WheelRailPair]:
        return (self.left, self.right)


def symmetric_wheelset(
    wheel: Profile | str,
    rail: Profile | str,
    **kwargs,
) -> WheelsetGeometry:
    """A wheelset with the same wheel and rail on both sides (mirror images), see
    :func:`place_wheel_rail` for the arguments."""
    pair = place_wheel_rail(wheel, rail, **kwargs)
    return WheelsetGeometry(left=pair, right=pair)


def wheelset_geometry(
    wheel: Profile | str | dict,
    rail: Profile | str | dict,
    *,
    nominal_radius_m: float | dict,
    **kwargs,
) -> WheelsetGeometry:
    """A wheelset whose wheels (profile, radius) and rails may differ left and right.

    ``wheel``, ``rail`` and ``nominal_radius_m`` are each one value for both sides or a mapping
    ``{"left": ..., "right": ...}`` (a vehicle file's ``wheel_profile: {left:, right:}``,
    ``nominal_radius: {left:, right:}``); the other arguments are those of
    :func:`place_wheel_rail` and apply to both sides. Each side is placed in its own left-type
    frame, so the right wheel's profile is given as a normal (left-type) wheel profile too.

    Raises:
        PlacementError: a mapping without exactly the keys ``left`` and ``right``.
    """

    def side(value, name: str):
        if isinstance(value, dict):
            if set(value) != {"left", "right"}:
                raise PlacementError(
                    f"{name}: a per-wheel value needs exactly the keys 'left' and 'right', "
                    f"got {sorted(value)}"
                )
            return value["left"], value["right"]
        return value, value

    wl, wr = side(wheel, "wheel profile")
    rl, rr = side(rail, "rail profile")
    r0l, r0r = side(nominal_radius_m, "nominal radius")
    left = place_wheel_rail(wl, rl, nominal_radius_m=float(r0l), **kwargs)
    if wl is wr and rl is rr and r0l == r0r:
        return WheelsetGeometry(left=left, right=left)
    right = place_wheel_rail(wr, rr, nominal_radius_m=float(r0r), **kwargs)
    return WheelsetGeometry(left=left, right=right)
