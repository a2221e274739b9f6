"""Checks of a vehicle's topology and geometry at load time (before any simulation).

A file can be valid key by key and still describe a vehicle that cannot stand on its rails:

- a body that no chain of springs with vertical stiffness joins to a wheelset would fall freely;
- a wheelset joined to nothing in a vehicle that has bodies would roll away on its own;
- two wheelsets closer than the sum of their wheel radii would overlap;
- a suspension element or load whose point lies far outside one of its bodies (a typo in a
  position, mm taken for m) makes absurd lever arms.

A body's extent is estimated from its mass and principal inertias as the equivalent homogeneous
box (``I_roll = m (w^2 + h^2) / 12`` and so on, solved for the length ``l``, width ``w`` and height
``h``); a point is refused when it lies beyond 1.5 times the half-size plus 0.5 m in any axis,
generous enough for frames that are not boxes.
"""

from __future__ import annotations

import math
from typing import Any

from railexu.inputs import Section
from railexu.vehicle.parts import Body, VehicleLayout

#: Margin of the extent check: factor on the box half-size, plus metres.
EXTENT_FACTOR = 1.5
EXTENT_MARGIN_M = 0.5
#: A wheelset is about its gauge wide; elements act on its axle (the axlebox).
WHEELSET_HALF_WIDTH_M = 1.5


def check_topology(vehicle: VehicleLayout, top: Section) -> None:
    """Raise an :class:`~railexu.errors.InputError` at the offending key for a vehicle that
    cannot stand on its rails (see the module docstring)."""
    _check_wheelset_spacing(vehicle, top)
    _check_points(vehicle, top)
    _check_element_bodies(vehicle, top)
    if vehicle.bodies:
        _check_connections(vehicle, top)


def carries_weight(el) -> bool:
    """The element has a vertical stiffness that can carry a body's weight at rest: a
    spring-damper with z stiffness, a nonlinear spring along z, an air spring (torsion springs,
    bump stops, dampers, friction, links and anti-roll bars carry no weight)."""
    kind = type(el).__name__
    if kind == "SpringDamper":
        return el.stiffness_N_per_m[2] > 0.0
    if kind == "NonlinearSpring":
        return el.direction == "z"
    return kind == "AirSpring"


def _check_element_bodies(vehicle: VehicleLayout, top: Section) -> None:
    """Anti-roll bars act on the relative roll of two bodies; a wheelset's roll coordinate is
    not separable from its spin, so they are refused on wheelsets (like torsion springs)."""
    wheelsets = {w.name for w in vehicle.wheelsets}
    raw = vehicle.raw.get("suspension") or {}
    for el in vehicle.suspension:
        if type(el).__name__ == "AntiRollBar" and set(el.bodies) & wheelsets:
            _fail_at(
                top,
                ("suspension", _entry(el.name, raw), "bodies"),
                "an anti-roll bar joins two bodies (car body and bogie frame), not a wheelset",
            )


def _fail_at(top: Section, path: tuple, message: str) -> None:
    Section({}, top.source, top.lines, path[:-1]).fail(message, key=path[-1])


def _entry(name: str, raw: Any) -> str:
    """The file's entry name of an element or load (mirrored ones end in _left / _right)."""
    if isinstance(raw, dict) and name not in raw:
        for suffix in ("_left", "_right"):
            if name.endswith(suffix) and name[: -len(suffix)] in raw:
                return name[: -len(suffix)]
    return name


def _check_wheelset_spacing(vehicle: VehicleLayout, top: Section) -> None:
    ws = sorted(vehicle.wheelsets, key=lambda w: w.position_x_m)
    for a, b in zip(ws, ws[1:], strict=False):
        gap = b.position_x_m - a.position_x_m
        reach = max(a.nominal_radius_m, a.radius_right_m) + max(
            b.nominal_radius_m, b.radius_right_m
        )
        if gap < reach:
            _fail_at(
                top,
                ("wheelsets", b.name, "position"),
                f"wheelsets {a.name} and {b.name} are {gap:g} m apart, less than the sum of "
                f"their wheel radii ({reach:g} m): their wheels would overlap",
            )


def box_half_sizes_m(body: Body) -> tuple[float, float, float]:
    """Half length, width, height [m] of the homogeneous box with the body's mass and
    principal inertias (``I_x = m (w^2 + h^2) / 12``, ...)."""
    ix, iy, iz = body.inertia_kg_m2
    m = body.mass_kg
    sq = (6.0 * (iy + iz - ix) / m, 6.0 * (ix + iz - iy) / m, 6.0 * (ix + iy - iz) / m)
    return tuple(0.5 * math.sqrt(max(s, 0.0)) for s in sq)  # type: ignore[return-value]


def _outside(vehicle: VehicleLayout, body_name: str, point) -> str:
    """Why ``point`` is far outside ``body_name`` ('' if it is not)."""
    bodies = {b.name: b for b in vehicle.bodies}
    if body_name in bodies:
        body = bodies[body_name]
        centre = body.position_m
        limits = [EXTENT_FACTOR * h + EXTENT_MARGIN_M for h in box_half_sizes_m(body)]
    else:
        ws = vehicle.wheelset(body_name)
        centre = ws.position_m
        r = max(ws.nominal_radius_m, ws.radius_right_m)
        limits = [r + EXTENT_MARGIN_M, WHEELSET_HALF_WIDTH_M, r + EXTENT_MARGIN_M]
    for axis, p, c, lim in zip("xyz", point, centre, limits, strict=True):
        if abs(p - c) > lim:
            return (
                f"the point {tuple(round(v, 4) for v in point)} m is {abs(p - c):g} m from the "
                f"centre of {body_name} along {axis}, more than its extent allows ({lim:.3g} m, "
                "estimated from its mass and inertia): is a position wrong or in mm?"
            )
    return ""


def _check_points(vehicle: VehicleLayout, top: Section) -> None:
    raw_elements = vehicle.raw.get("suspension") or {}
    for el in vehicle.suspension:
        for body in el.bodies:
            why = _outside(vehicle, body, el.position_m)
            if why:
                name = _entry(el.name, raw_elements)
                _fail_at(top, ("suspension", name, "position"), why)
    raw_loads = vehicle.raw.get("loads") or {}
    for load in vehicle.loads:
        why = _outside(vehicle, load.body, load.position_m)
        if why:
            _fail_at(top, ("loads", _entry(load.name, raw_loads), "position"), why)


def _check_connections(vehicle: VehicleLayout, top: Section) -> None:
    """Every wheelset is joined to some body; every body reaches a wheelset through springs
    with vertical stiffness (else nothing carries its weight)."""
    wheelsets = {w.name for w in vehicle.wheelsets}
    joined = {b for el in vehicle.suspension for b in el.bodies}
    for ws in vehicle.wheelsets:
        if ws.name not in joined:
            _fail_at(
                top,
                ("wheelsets", ws.name),
                "this wheelset is connected to no body by any suspension element: it would "
                "run on its own (give a primary suspension element between it and a body)",
            )
    vertical: dict[str, set[str]] = {}
    for el in vehicle.suspension:
        if carries_weight(el):
            a, b = el.bodies
            vertical.setdefault(a, set()).add(b)
            vertical.setdefault(b, set()).add(a)
    supported = set(wheelsets)
    frontier = list(wheelsets)
    while frontier:
        for other in vertical.get(frontier.pop(), ()):
            if other not in supported:
                supported.add(other)
                frontier.append(other)
    for body in vehicle.bodies:
        if body.name not in supported:
            what = "connected to nothing" if body.name not in joined else "not carried"
            _fail_at(
                top,
                ("bodies", body.name),
                f"this body is {what}: no chain of spring-dampers with vertical (z) stiffness "
                "joins it to a wheelset, so nothing carries its weight",
            )
