"""Vehicle files: the validated :class:`Vehicle` and its loader (``docs/vehicle-format.md``).

A vehicle is a set of rigid bodies (car body, bogie frames, ...), wheelsets, suspension elements
between them and constant external loads (:mod:`railexu.vehicle.parts`). Positions are in **vehicle
axes**: ``x`` forward from the vehicle centre, ``y`` to the left, ``z`` up from the top of the
rails, in metres. Every number may carry a unit (``"51.6 t"``, ``"1.2 MN/m"``); plain numbers are
SI.

:func:`load_vehicle` reads a file or a shipped vehicle by name (with ``--set``-style overrides),
checks it against :data:`railexu.vehicle.schema.VEHICLE` (unknown or missing keys, wrong types,
units or ranges are errors that name the file, the line and the key), checks its topology
(:mod:`railexu.vehicle.checks`) and returns a :class:`Vehicle`. :meth:`Vehicle.replace` gives a
changed, re-validated copy with the same paths as ``--set``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from railexu.contact.parameters import ContactParameterError, ContactParameters
from railexu.inputs import LineMap, Section, load_yaml_with_overrides, resolve_file
from railexu.inputs.catalog import find_input
from railexu.inputs.overrides import set_values
from railexu.profiles import ProfileError, wheel_profile
from railexu.vehicle.checks import check_topology
from railexu.vehicle.format_history import (
    check_format_1_category,
    check_format_1_elements,
    format_1_contact_defaults,
)
from railexu.vehicle.parts import (
    AirSpring,
    AntiRollBar,
    Body,
    BumpStop,
    Damper,
    Friction,
    Load,
    MeasurementPoint,
    NonlinearSpring,
    SpringDamper,
    SuspensionElement,
    TorsionSpring,
    UICLink,
    Wheelset,
    linear_part,
)
from railexu.vehicle.schema import (
    AXES,
    BODY,
    CONTACT,
    DEFAULT_FLOOR_HEIGHT_M,
    ELEMENT_TYPE,
    ELEMENTS,
    FORMAT_VERSION,
    LOAD,
    MAX_DAMPING,
    MAX_STIFFNESS,
    MEASUREMENT_POINT,
    VEHICLE,
    WHEELSET,
)

__all__ = [
    "AXES",
    "FORMAT_VERSION",
    "AirSpring",
    "AntiRollBar",
    "Body",
    "BumpStop",
    "Damper",
    "Friction",
    "Load",
    "MeasurementPoint",
    "NonlinearSpring",
    "SpringDamper",
    "TorsionSpring",
    "UICLink",
    "Vehicle",
    "Wheelset",
    "linear_part",
    "load_vehicle",
    "vehicle_from_dict",
]


def heaviest_body(bodies: Iterable[Body]) -> str | None:
    """The car body by railexu's rule: the name of the heaviest body (None: no body)."""
    bodies = list(bodies)
    return max(bodies, key=lambda b: b.mass_kg).name if bodies else None


@dataclass(frozen=True)
class Vehicle:
    """A validated vehicle.

    Derived quantities: :attr:`total_mass_kg`, :attr:`primary_yaw_stiffness_N_m_per_rad`,
    :attr:`wheelbases_m`; a changed copy: :meth:`replace`. Static axle loads need the statics:
    :func:`railexu.model.statics.static_axle_loads_N`. ``admissible_speed_m_per_s`` [m/s] and
    ``admissible_cant_deficiency_m`` [m] are the file's (None when it does not give them): the
    conditions ``railexu acceptance`` takes when its command line does not give them.
    """

    name: str
    description: str
    bodies: tuple[Body, ...]
    wheelsets: tuple[Wheelset, ...]
    suspension: tuple[SuspensionElement, ...]
    loads: tuple[Load, ...]
    contact: ContactParameters
    speed_body: str
    gravity_m_per_s2: float = VEHICLE.default("gravity")
    sources: tuple[str, ...] = ()
    category: str = "locomotive"  # a file must name it (VEHICLE schema); Python callers may not
    measurement_points: tuple[MeasurementPoint, ...] = ()
    source: str = ""
    admissible_speed_m_per_s: float | None = None
    admissible_cant_deficiency_m: float | None = None
    raw: dict = field(default_factory=dict, repr=False, compare=False)
    lines: dict = field(default_factory=dict, repr=False, compare=False)
    base_dir: Path | None = field(default=None, repr=False, compare=False)

    def body_names(self) -> list[str]:
        return [b.name for b in self.bodies] + [w.name for w in self.wheelsets]

    @property
    def total_mass_kg(self) -> float:
        """Mass of every body and wheelset [kg] (external loads not included)."""
        return sum(b.mass_kg for b in self.bodies) + sum(w.mass_kg for w in self.wheelsets)

    @property
    def car_body(self) -> str | None:
        """The car body: the heaviest body (railexu's rule), None for wheelsets alone."""
        return heaviest_body(self.bodies)

    @property
    def car_body_points(self) -> tuple[str, ...]:
        """The measurement points on the car body: where ride comfort (EN 12299) and the car
        body's accelerations (EN 14363) are evaluated; points on bogie frames are not."""
        car = self.car_body
        return tuple(p.name for p in self.measurement_points if p.body == car)

    def wheelset(self, name: str) -> Wheelset:
        return next(w for w in self.wheelsets if w.name == name)

    @property
    def primary_yaw_stiffness_N_m_per_rad(self) -> dict[str, float]:
        """Per wheelset, the yaw stiffness of the springs on it about its centre [N m/rad]:
        sum of ``k_x y^2`` over its spring-dampers, i.e. ``2 k_x b^2`` for one pair of axlebox
        springs ``2 b`` apart (the springs act on the axle, so their ``x`` offset is 0)."""
        out = {}
        for ws in self.wheelsets:
            out[ws.name] = (
                sum(
                    el.stiffness_N_per_m[0] * el.position_m[1] ** 2
                    for el in self.suspension
                    if isinstance(el, SpringDamper) and ws.name in el.bodies
                )
                + 0.0
            )
        return out

    @property
    def wheelbases_m(self) -> dict[str, float]:
        """Per body carrying two or more wheelsets directly (a bogie frame, a two-axle car),
        the distance between its outermost axles [m]."""
        carried: dict[str, set[str]] = {}
        wheelsets = {w.name: w for w in self.wheelsets}
        for el in self.suspension:
            a, b = el.bodies
            for body, other in ((a, b), (b, a)):
                if body not in wheelsets and other in wheelsets:
                    carried.setdefault(body, set()).add(other)
        return {
            body: max(wheelsets[w].position_x_m for w in ws)
            - min(wheelsets[w].position_x_m for w in ws)
            for body, ws in carried.items()
            if len(ws) >= 2
        }

    def replace(self, *changes: Any, **named: Any) -> Vehicle:
        """A new validated vehicle with some values changed, by the paths of ``--set``.

        ``vehicle.replace("suspension.primary_ws*.stiffness.x", "4 MN/m")``; several pairs:
        ``replace("a.b", 1, "c.d", "2 t")``, ``replace({"a.b": 1, "c.d": "2 t"})`` or
        ``replace(("a.b", 1), ("c.d", "2 t"))``. Values are Python values or text with units;
        patterns (``*``, ``?``) match several keys as in ``--set``.

        Raises:
            InputError: an unknown path or an invalid value (validated like a file).
        """
        pairs = _change_pairs(changes, named)
        data = set_values(self.raw, pairs, source="Vehicle.replace")
        return vehicle_from_dict(data, self.source, self.lines, self.base_dir)


def _change_pairs(changes: tuple, named: Mapping[str, Any]) -> list[tuple[str, Any]]:
    from railexu.errors import InputError

    pairs: list[tuple[str, Any]] = []
    if len(changes) == 1 and isinstance(changes[0], Mapping):
        pairs.extend(changes[0].items())
    elif changes and all(isinstance(c, tuple) and len(c) == 2 for c in changes):
        pairs.extend(changes)
    elif len(changes) % 2 == 0:
        pairs.extend(zip(changes[::2], changes[1::2], strict=True))
    else:
        raise InputError("Vehicle.replace takes path, value pairs, (path, value) tuples or a dict")
    pairs.extend(named.items())
    if not pairs or not all(isinstance(p, str) for p, _ in pairs):
        raise InputError("Vehicle.replace: give at least one 'dotted.path', value pair")
    return pairs


def load_vehicle(path: str | Path, overrides: str | Iterable[str] = ()) -> Vehicle:
    """Read and validate a vehicle file (or a shipped vehicle by name, e.g. ``"eu07"``),
    applying ``dotted.key=value`` overrides first (one string is one override).

    Raises:
        InputError: any problem, with file, line, key and what was expected.
    """
    path = find_input("vehicle", path)
    data, lines = load_yaml_with_overrides(path, overrides)
    return vehicle_from_dict(data, source=str(path), lines=lines, base_dir=path.parent)


def vehicle_from_dict(
    data: dict,
    source: str = "<vehicle>",
    lines: dict | None = None,
    base_dir: Path | None = None,
) -> Vehicle:
    """Validate raw vehicle data (as read from YAML) into a :class:`Vehicle`."""
    lines = lines if lines is not None else LineMap()
    top = VEHICLE.wrap(data, source, lines)
    version = VEHICLE.read(top, "format_version")
    if version == 1:
        check_format_1_category(top)
        data, lines = _upgrade_version_1(data, lines)
        data = format_1_contact_defaults(data)
        top = VEHICLE.wrap(data, source, lines)
    bodies = [_body(top.child("bodies", n, BODY.keys()), n) for n, _ in top.items("bodies", False)]
    wheelsets = [
        _wheelset(top.child("wheelsets", n, WHEELSET.keys()), n, base_dir)
        for n, _ in top.items("wheelsets")
    ]
    if not wheelsets:
        top.fail("a vehicle needs at least one wheelset", key="wheelsets")
    names = [b.name for b in bodies] + [w.name for w in wheelsets]
    duplicates = {n for n in names if names.count(n) > 1}
    if duplicates:
        top.fail(f"names used twice among bodies and wheelsets: {', '.join(sorted(duplicates))}")
    suspension = [el for n, _ in top.items("suspension", False) for el in _element(top, n, names)]
    if version == 1:
        check_format_1_elements(top, wheelsets)
    loads = [ld for n, _ in top.items("loads", False) for ld in _loads(top, n, names)]
    speed_body = VEHICLE.read(top, "speed_body") or names[0]
    if speed_body not in names:
        top.fail(f"unknown body {speed_body!r}.{_did_you_mean(speed_body, names)}",
                 key="speed_body")  # fmt: skip
    vehicle = Vehicle(
        name=VEHICLE.read(top, "name"),
        description=VEHICLE.read(top, "description"),
        bodies=tuple(bodies),
        wheelsets=tuple(wheelsets),
        suspension=tuple(suspension),
        loads=tuple(loads),
        contact=_contact_parameters(CONTACT.section(top, "contact")),
        speed_body=speed_body,
        gravity_m_per_s2=VEHICLE.read(top, "gravity"),
        sources=VEHICLE.read(top, "sources"),
        category=VEHICLE.read(top, "category"),
        admissible_speed_m_per_s=VEHICLE.read(top, "admissible_speed"),
        admissible_cant_deficiency_m=VEHICLE.read(top, "admissible_cant_deficiency"),
        measurement_points=_measurement_points(top, names, bodies, wheelsets, suspension),
        source=source,
        raw=data,
        lines=lines,
        base_dir=base_dir,
    )
    check_topology(vehicle, top)
    return vehicle


def _measurement_points(
    top: Section,
    names: list[str],
    bodies: list[Body],
    wheelsets: list[Wheelset],
    suspension: list[SuspensionElement],
) -> tuple[MeasurementPoint, ...]:
    """The named points of the file, or the defaults: on the floor of the first body (the car
    body) above each bogie (the other bodies' x) and at its centre, and on each bogie frame
    above its outermost wheelsets (:func:`_bogie_frame_points`); none for a vehicle without
    bodies (a wheelset alone)."""
    points = []
    for name, _ in top.items("measurement_points", False):
        sec = top.child("measurement_points", name, MEASUREMENT_POINT.keys())
        body = MEASUREMENT_POINT.read(sec, "body")
        if body not in names:
            sec.fail(f"unknown body {body!r}.{_did_you_mean(body, names)}", key="body")
        points.append(MeasurementPoint(str(name), body, MEASUREMENT_POINT.read(sec, "position")))
    if points or not bodies:
        return tuple(points)
    car = bodies[0]
    x0, z = car.position_m[0], DEFAULT_FLOOR_HEIGHT_M
    pivots = sorted((b.position_m[0] for b in bodies[1:]), reverse=True) or [
        w.position_x_m for w in (wheelsets[0], wheelsets[-1])
    ]
    defaults = [("body_front", pivots[0]), ("body_centre", x0), ("body_rear", pivots[-1])]
    on_car = [MeasurementPoint(n, car.name, (x, 0.0, z)) for n, x in defaults]
    return tuple(on_car) + _bogie_frame_points(bodies[1:], wheelsets, suspension)


def _bogie_frame_points(
    frames: list[Body], wheelsets: list[Wheelset], suspension: list[SuspensionElement]
) -> tuple[MeasurementPoint, ...]:
    """Default points of EN 14363's simplified measuring method: on each body other than the
    first that carries wheelsets directly (a bogie frame), above its outermost wheelsets, at
    the frame's centre height on its centre line (the height and lateral place on the frame
    are railexu's choice); named ``<frame>_above_<wheelset>``."""
    positions = {w.name: w.position_x_m for w in wheelsets}
    out = []
    for frame in frames:
        carried = {b for el in suspension if frame.name in el.bodies for b in el.bodies}
        ends = sorted(carried & positions.keys(), key=lambda w: -positions[w])
        for ws in dict.fromkeys(ends[:1] + ends[-1:]):
            xyz = (positions[ws], frame.position_m[1], frame.position_m[2])
            out.append(MeasurementPoint(f"{frame.name}_above_{ws}", frame.name, xyz))
    return tuple(out)


def _body(sec: Section, name: Any) -> Body:
    inertia = BODY.read(sec, "inertia")
    _check_inertia(sec, inertia)
    return Body(
        name=str(name),
        mass_kg=BODY.read(sec, "mass"),
        inertia_kg_m2=inertia,
        position_m=BODY.read(sec, "position"),
        estimate=BODY.read(sec, "estimate"),
    )


def _wheelset(sec: Section, name: Any, base_dir: Path | None) -> Wheelset:
    inertia = WHEELSET.read(sec, "inertia")
    _check_inertia(sec, inertia)
    profiles = []
    raw = sec.data.get("wheel_profile")
    for side, profile in zip(("left", "right"), WHEELSET.read(sec, "wheel_profile"), strict=True):
        resolved = resolve_file(profile, base_dir)
        try:
            wheel_profile(resolved)
        except ProfileError as exc:
            if isinstance(raw, dict):
                Section(raw, sec.source, sec.lines, (*sec.path, "wheel_profile")).fail(
                    str(exc), key=side
                )
            sec.fail(str(exc), key="wheel_profile")
        profiles.append(resolved)
    left_radius, right_radius = WHEELSET.read(sec, "nominal_radius")
    return Wheelset(
        name=str(name),
        position_x_m=WHEELSET.read(sec, "position")[0],
        mass_kg=WHEELSET.read(sec, "mass"),
        inertia_kg_m2=inertia,
        wheel_profile=profiles[0],
        nominal_radius_m=left_radius,
        flange_back_distance_m=WHEELSET.read(sec, "flange_back_distance"),
        axle_load_N=WHEELSET.read(sec, "axle_load"),
        estimate=WHEELSET.read(sec, "estimate"),
        wheel_profile_right=profiles[1] if profiles[1] != profiles[0] else "",
        nominal_radius_right_m=right_radius if right_radius != left_radius else 0.0,
    )


def _element(top: Section, name: Any, names: list[str]) -> list[SuspensionElement]:
    kind = top.child("suspension", name).string("type", choices=ELEMENT_TYPE.allowed_choices())
    schema = ELEMENTS[kind]
    sec = top.child("suspension", name, ("type", *schema.keys()))
    pair = schema.read(sec, "bodies")
    if len(pair) != 2:
        sec.fail(f"expected two body names [upper, lower], got {list(pair)}", key="bodies")
    for b in pair:
        if b not in names:
            sec.fail(f"unknown body {b!r}.{_did_you_mean(b, names)}", key="bodies")
    if pair[0] == pair[1]:
        sec.fail("an element must connect two different bodies", key="bodies")
    position = schema.read(sec, "position")
    estimate = schema.read(sec, "estimate")
    make = _ELEMENT_MAKERS[kind](sec, schema, pair, estimate)
    mirror = _mirror(sec, schema, position) if "mirror_y" in schema.by_key else False
    return [make(n, p) for n, p in _mirrored(str(name), position, mirror)]


def _linear_maker(sec: Section, schema, pair, estimate):
    kind = schema.name
    if kind == "spring_damper":
        stiffness, damping = schema.read(sec, "stiffness"), schema.read(sec, "damping")
        if not (any(stiffness) or any(damping)):
            sec.fail("give a stiffness or a damping", key="stiffness")
        return lambda n, p: SpringDamper(n, pair, p, stiffness, damping, estimate)
    if kind == "torsion_spring":
        axis, k, c = (schema.read(sec, key) for key in ("axis", "stiffness", "damping"))
        if not (k or c):
            sec.fail("give a stiffness or a damping (both 0: no element)", key="stiffness")
        return lambda n, p: TorsionSpring(n, pair, p, axis, k, c, estimate)
    values = [schema.read(sec, k) for k in ("direction", "clearance", "stiffness", "damping")]
    return lambda n, p: BumpStop(n, pair, p, *values, estimate)


def _nonlinear_spring_maker(sec: Section, schema, pair, estimate):
    direction = schema.read(sec, "direction")
    x, f = _table(sec, schema, "deflection", "force", "deflection")
    interpolation, damping = schema.read(sec, "interpolation"), schema.read(sec, "damping")
    return lambda n, p: NonlinearSpring(
        n, pair, p, direction, x, f, interpolation, damping, estimate
    )


def _damper_maker(sec: Section, schema, pair, estimate):
    direction = schema.read(sec, "direction")
    c = schema.read(sec, "damping")
    given = [k for k in ("velocity", "force") if k in sec.data]
    if c is not None and given:
        sec.fail("give either damping or a velocity/force table, not both", key="damping")
    if c is None and not given:
        sec.fail("give a damping coefficient or a velocity/force table", key="damping")
    if c is not None:
        v, f = (-1.0, 1.0), (-c, c)
    else:
        v, f = _table(sec, schema, "velocity", "force", "velocity")
        if abs(_interpolate_linear(v, f, 0.0)) > 1e-6 * max(abs(x) for x in f):
            sec.fail("a damper's force must be 0 at zero velocity", key="force")
    k_s = schema.read(sec, "series_stiffness")
    interpolation = schema.read(sec, "interpolation")
    return lambda n, p: Damper(n, pair, p, direction, v, f, interpolation, k_s, c, estimate)


def _friction_maker(sec: Section, schema, pair, estimate):
    values = [schema.read(sec, k) for k in ("direction", "friction_force", "slip_velocity",
                                            "stick_stiffness")]  # fmt: skip
    return lambda n, p: Friction(n, pair, p, *values, estimate)


def _uic_link_maker(sec: Section, schema, pair, estimate):
    keys = ("pendulum_length", "friction_coefficient", "stick_stiffness", "vertical_load",
            "slip_velocity")  # fmt: skip
    values = [schema.read(sec, k) for k in keys]
    return lambda n, p: UICLink(n, pair, p, *values, estimate)


def _air_spring_maker(sec: Section, schema, pair, estimate):
    keys = ("vertical_stiffness", "reservoir_stiffness", "orifice_damping", "lateral_stiffness",
            "lateral_damping")  # fmt: skip
    values = [schema.read(sec, k) for k in keys]
    return lambda n, p: AirSpring(n, pair, p, *values, estimate)


def _anti_roll_bar_maker(sec: Section, schema, pair, estimate):
    k, c = schema.read(sec, "stiffness"), schema.read(sec, "damping")
    return lambda n, p: AntiRollBar(n, pair, p, k, c, estimate)


_ELEMENT_MAKERS = {
    "spring_damper": _linear_maker,
    "torsion_spring": _linear_maker,
    "bump_stop": _linear_maker,
    "nonlinear_spring": _nonlinear_spring_maker,
    "damper": _damper_maker,
    "friction": _friction_maker,
    "uic_link": _uic_link_maker,
    "air_spring": _air_spring_maker,
    "anti_roll_bar": _anti_roll_bar_maker,
}


def _table(sec: Section, schema, x_key: str, f_key: str, what: str):
    """A characteristic table ``(x, F)``: same lengths, ``x`` strictly increasing, ``F``
    non-decreasing (a falling characteristic is a negative stiffness or damping: unstable);
    a ``symmetric`` table starts at (0, 0) and is mirrored, ``F(-x) = -F(x)``."""
    for key in (x_key, f_key):
        if key not in sec.data:
            sec.fail(f"missing key {key!r}: the table needs both {x_key} and {f_key}", key=key)
    x, f = schema.read(sec, x_key), schema.read(sec, f_key)
    if len(x) != len(f):
        sec.fail(f"{f_key} has {len(f)} values but {x_key} has {len(x)}", key=f_key)
    for i in range(1, len(x)):
        if not x[i] > x[i - 1]:
            sec.fail(f"the {what} values must increase, but entry {i} ({x[i]:g}) is not above "
                     f"entry {i - 1} ({x[i - 1]:g})", key=x_key)  # fmt: skip
        if f[i] < f[i - 1]:
            sec.fail(f"the {f_key} must not decrease with the {what} (a falling "
                     f"characteristic is a negative stiffness or damping), but entry {i} "
                     f"({f[i]:g}) is below entry {i - 1} ({f[i - 1]:g})", key=f_key)  # fmt: skip
        _check_slope(sec, x, f, i, f_key, what)
    if f[-1] == f[0]:
        sec.fail(f"the {f_key} is constant: the element would carry no load", key=f_key)
    if schema.read(sec, "symmetric"):
        if x[0] != 0.0 or f[0] != 0.0:
            sec.fail(f"a symmetric table starts at {what} 0 with {f_key} 0, got "
                     f"({x[0]:g}, {f[0]:g})", key=x_key)  # fmt: skip
        x = tuple(-v for v in reversed(x[1:])) + tuple(x)
        f = tuple(-v for v in reversed(f[1:])) + tuple(f)
    return tuple(x), tuple(f)


#: The steepest slope of a table [SI], by its abscissa: the largest stiffness or damping of the
#: linear elements (``vehicle/schema.py``; reasons in docs/vehicle-format.md, "Ranges").
_MAX_SLOPE = {"deflection": (MAX_STIFFNESS, "N/m"), "velocity": (MAX_DAMPING, "N s/m")}


def _check_slope(sec: Section, x, f, i: int, f_key: str, what: str) -> None:
    """Refuse a segment steeper than a rigid stop (a force jump over a tiny step)."""
    limit, unit = _MAX_SLOPE[what]
    slope = (f[i] - f[i - 1]) / (x[i] - x[i - 1])
    if slope > limit:
        sec.fail(f"the slope between entries {i - 1} and {i} is {slope:.3g} {unit}, above "
                 f"{limit:g} {unit} (a rigid stop: a force jump the integration cannot follow; "
                 f"spread the rise over a longer {what})", key=f_key)  # fmt: skip


def _interpolate_linear(x, f, at: float) -> float:
    import numpy as np

    if at <= x[0]:
        return f[0] + (f[1] - f[0]) / (x[1] - x[0]) * (at - x[0])
    if at >= x[-1]:
        return f[-1] + (f[-1] - f[-2]) / (x[-1] - x[-2]) * (at - x[-1])
    return float(np.interp(at, x, f))


def _loads(top: Section, name: Any, names: list[str]) -> list[Load]:
    sec = top.child("loads", name, LOAD.keys())
    body = LOAD.read(sec, "body")
    if body not in names:
        sec.fail(f"unknown body {body!r}.{_did_you_mean(body, names)}", key="body")
    force, position = LOAD.read(sec, "force"), LOAD.read(sec, "position")
    estimate, static = LOAD.read(sec, "estimate"), LOAD.read(sec, "static")
    mirror = _mirror(sec, LOAD, position)
    return [
        Load(n, body, p, force, estimate, static) for n, p in _mirrored(str(name), position, mirror)
    ]


def _mirror(sec: Section, schema, position) -> bool:
    mirror = schema.read(sec, "mirror_y")
    if mirror and position[1] == 0.0:
        sec.fail("mirror_y needs a lateral position y != 0", key="position")
    return mirror


def _check_inertia(sec: Section, inertia: tuple[float, ...]) -> None:
    """Principal moments of inertia of a rigid body are positive and satisfy the triangle
    inequality (each at most the sum of the other two)."""
    a, b, c = inertia
    if a > b + c or b > a + c or c > a + b:
        sec.fail(
            f"principal inertias {a:g}, {b:g}, {c:g} kg m^2 violate the triangle inequality "
            "(each must be at most the sum of the other two for a real body)",
            key="inertia",
        )


def _mirrored(name: str, position, mirror: bool):
    if not mirror:
        return [(name, tuple(position))]
    x, y, z = position
    return [(f"{name}_left", (x, abs(y), z)), (f"{name}_right", (x, -abs(y), z))]


def _did_you_mean(name: str, names: list[str]) -> str:
    from railexu.errors import did_you_mean

    return did_you_mean(name, names)


def _contact_parameters(sec: Section) -> ContactParameters:
    creep, creep_params = CONTACT.read(sec, "creep")
    damping_model, damping_params = CONTACT.read(sec, "normal_damping")
    kwargs: dict[str, Any] = dict(
        friction=CONTACT.read(sec, "friction"),
        creep_model=creep,
        shear_modulus_Pa=CONTACT.read(sec, "shear_modulus"),
        poisson=CONTACT.read(sec, "poisson"),
        damping_model=damping_model,
        damping=damping_params["coefficient"],
        scan_step_m=CONTACT.read(sec, "scan_step"),
    )
    if creep == "polach_2005":
        kwargs["polach_2005"] = tuple(creep_params[k] for k in ("k_a", "k_s", "A", "B"))
    try:
        return ContactParameters(**kwargs)
    except (ContactParameterError, ValueError) as exc:
        sec.fail(str(exc))
        raise  # unreachable


# -- format version 1 -----------------------------------------------------------------------------
_V1_CONTACT = ("creep_model", "damping_model", "normal_damping", "polach_2005")


def _upgrade_version_1(data: dict, lines: dict) -> tuple[dict, dict]:
    """Version 1 files are read as version 2: their contact keys
    ``creep_model`` + ``polach_2005`` become ``creep: {model: ..., k_a: ...}`` and
    ``damping_model`` + ``normal_damping`` (whose unit followed the model) become
    ``normal_damping: {model: ..., coefficient: ...}``; every other key is unchanged."""
    contact = data.get("contact")
    if not isinstance(contact, dict) or not any(k in contact for k in _V1_CONTACT):
        return data, lines
    if isinstance(contact.get("normal_damping"), dict) or "creep" in contact:
        return data, lines  # already written the version 2 way
    new = dict(contact)
    lines = lines.copy() if isinstance(lines, LineMap) else LineMap(lines)
    creep: dict[str, Any] = {}
    if "creep_model" in new:
        creep["model"] = new.pop("creep_model")
        _move_line(lines, ("contact", "creep_model"), ("contact", "creep", "model"))
    polach = new.pop("polach_2005", None)
    if isinstance(polach, dict) and creep.get("model") == "polach_2005":
        creep.update(polach)
        for k in polach:
            _move_line(lines, ("contact", "polach_2005", k), ("contact", "creep", k))
    if creep:
        new["creep"] = creep
    damping: dict[str, Any] = {}
    if "damping_model" in new:
        damping["model"] = new.pop("damping_model")
        _move_line(lines, ("contact", "damping_model"), ("contact", "normal_damping", "model"))
    if "normal_damping" in new:
        damping.setdefault("model", ContactParameters().damping_model)
        damping["coefficient"] = new.pop("normal_damping")
    elif damping:  # version 1 took the one default coefficient whatever the model
        damping["coefficient"] = ContactParameters().damping
        _move_line(lines, ("contact", "normal_damping"), ("contact", "normal_damping",
                                                          "coefficient"))  # fmt: skip
    if damping:
        new["normal_damping"] = damping
    return {**data, "contact": new}, lines


def _move_line(lines: dict, old: tuple, new: tuple) -> None:
    if old in lines:
        lines[new] = lines[old]
        lines.setdefault(new[:-1], lines[old])
