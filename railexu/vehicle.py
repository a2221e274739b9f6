"""Vehicle files: schema, units, validation (``docs/vehicle-format.md`` documents the format).

A vehicle is a set of rigid bodies (car body, bogie frames, ...), wheelsets, suspension elements
between them and constant external loads. Positions are in **vehicle axes**: ``x`` forward from
the vehicle centre, ``y`` to the left, ``z`` up from the top of the rails, in metres. Every
number may carry a unit (``"51.6 t"``, ``"1.2 MN/m"``); plain numbers are SI.

:func:`load_vehicle` reads a file (with ``--set``-style overrides), checks it strictly (unknown or
missing keys, wrong types, units or ranges are errors that name the file, the line and the key)
and returns a :class:`Vehicle`.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .contact.evaluation import ContactParameterError, ContactParameters
from .inputs import Section, load_yaml_with_overrides, resolve_file
from .profiles import ProfileError, wheel_profile

FORMAT_VERSION = 1
AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Body:
    """A rigid body (car body, bogie frame). Inertia about the centre of gravity, principal axes
    along the vehicle axes (roll about x, pitch about y, yaw about z)."""

    name: str
    mass_kg: float
    inertia_kg_m2: tuple[float, float, float]  # roll, pitch, yaw
    position_m: tuple[float, float, float]  # centre of gravity, vehicle axes
    estimate: str = ""


@dataclass(frozen=True)
class Wheelset:
    """A wheelset: axle along y, centre at the nominal rolling radius above the rails."""

    name: str
    position_x_m: float
    mass_kg: float
    inertia_kg_m2: tuple[float, float, float]  # roll, yaw, spin
    wheel_profile: str
    nominal_radius_m: float
    flange_back_distance_m: float
    axle_load_N: float | None = None  # declared static axle load, checked against the statics
    estimate: str = ""

    @property
    def position_m(self) -> tuple[float, float, float]:
        return (self.position_x_m, 0.0, self.nominal_radius_m)


@dataclass(frozen=True)
class SpringDamper:
    """Linear spring and damper between two bodies at one point, acting along the track axes
    (a bushing, coil spring, or a damper when the stiffness is zero)."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    stiffness_N_per_m: tuple[float, float, float]
    damping_N_s_per_m: tuple[float, float, float]
    estimate: str = ""


@dataclass(frozen=True)
class TorsionSpring:
    """Rotational spring and damper between two bodies about one axis (e.g. secondary yaw)."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    axis: str
    stiffness_N_m_per_rad: float
    damping_N_m_s_per_rad: float
    estimate: str = ""


@dataclass(frozen=True)
class BumpStop:
    """A stop with a clearance: no force while the relative displacement along ``direction``
    stays within +-clearance, then a linear spring (and damper) beyond it."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    direction: str
    clearance_m: float
    stiffness_N_per_m: float
    damping_N_s_per_m: float = 0.0
    estimate: str = ""


@dataclass(frozen=True)
class Load:
    """A constant force on a body at a point (vehicle axes).

    A ``static`` load (the default: weights carried, a share of a car body) is part of the
    static equilibrium the vehicle starts in; a non-static load is applied suddenly at the start
    of the run (a step: a wind gust, a lateral impact)."""

    name: str
    body: str
    position_m: tuple[float, float, float]
    force_N: tuple[float, float, float]
    estimate: str = ""
    static: bool = True


SuspensionElement = SpringDamper | TorsionSpring | BumpStop


@dataclass(frozen=True)
class Vehicle:
    """A validated vehicle."""

    name: str
    description: str
    bodies: tuple[Body, ...]
    wheelsets: tuple[Wheelset, ...]
    suspension: tuple[SuspensionElement, ...]
    loads: tuple[Load, ...]
    contact: ContactParameters
    speed_body: str
    gravity_m_per_s2: float = 9.81
    sources: tuple[str, ...] = ()
    source: str = ""
    raw: dict = field(default_factory=dict, repr=False, compare=False)

    def body_names(self) -> list[str]:
        return [b.name for b in self.bodies] + [w.name for w in self.wheelsets]

    def total_mass_kg(self) -> float:
        return sum(b.mass_kg for b in self.bodies) + sum(w.mass_kg for w in self.wheelsets)

    def wheelset(self, name: str) -> Wheelset:
        return next(w for w in self.wheelsets if w.name == name)


TOP_KEYS = (
    "format_version",
    "name",
    "description",
    "sources",
    "speed_body",
    "gravity",
    "contact",
    "bodies",
    "wheelsets",
    "suspension",
    "loads",
)
BODY_KEYS = ("mass", "inertia", "position", "estimate", "notes")
WHEELSET_KEYS = (
    "position",
    "mass",
    "inertia",
    "wheel_profile",
    "nominal_radius",
    "flange_back_distance",
    "axle_load",
    "estimate",
    "notes",
)
COMMON_ELEMENT_KEYS = ("type", "bodies", "position", "mirror_y", "estimate", "notes")
ELEMENT_KEYS = {
    "spring_damper": (*COMMON_ELEMENT_KEYS, "stiffness", "damping"),
    "torsion_spring": (*COMMON_ELEMENT_KEYS, "axis", "stiffness", "damping"),
    "bump_stop": (*COMMON_ELEMENT_KEYS, "direction", "clearance", "stiffness", "damping"),
}
LOAD_KEYS = ("body", "position", "force", "mirror_y", "static", "estimate", "notes")
CONTACT_KEYS = (
    "friction",
    "creep_model",
    "shear_modulus",
    "poisson",
    "damping_model",
    "normal_damping",
    "polach_2005",
    "scan_step",
)


def load_vehicle(path: str | Path, overrides: Iterable[str] = ()) -> Vehicle:
    """Read and validate a vehicle file, applying ``dotted.key=value`` overrides first.

    Raises:
        InputError: any problem, with file, line, key and what was expected.
    """
    path = Path(path)
    data, lines = load_yaml_with_overrides(path, overrides)
    return vehicle_from_dict(data, source=str(path), lines=lines, base_dir=path.parent)


def vehicle_from_dict(
    data: dict,
    source: str = "<vehicle>",
    lines: dict | None = None,
    base_dir: Path | None = None,
) -> Vehicle:
    """Validate raw vehicle data (as read from YAML) into a :class:`Vehicle`."""
    top = Section(data, source, lines, (), TOP_KEYS)
    version = top.integer("format_version")
    if version != FORMAT_VERSION:
        top.fail(f"format_version {version} is not supported (this railexu reads {FORMAT_VERSION})")
    name = top.string("name")
    description = top.string("description", default="")
    sources = top.string_list("sources")
    gravity = top.quantity("gravity", "m/s^2", default=9.81, positive=True)

    bodies = []
    for body_name, _ in top.items("bodies", required=False):
        sec = top.child("bodies", body_name, BODY_KEYS)
        inertia = sec.vector("inertia", "kg m^2", components=("roll", "pitch", "yaw"))
        _check_inertia(sec, inertia)
        bodies.append(
            Body(
                name=str(body_name),
                mass_kg=sec.quantity("mass", "kg", positive=True),
                inertia_kg_m2=inertia,  # type: ignore[arg-type]
                position_m=sec.vector("position", "m"),  # type: ignore[arg-type]
                estimate=sec.string("estimate", default=""),
            )
        )

    wheelsets = []
    for ws_name, _ in top.items("wheelsets"):
        sec = top.child("wheelsets", ws_name, WHEELSET_KEYS)
        inertia = sec.vector("inertia", "kg m^2", components=("roll", "yaw", "spin"))
        _check_inertia(sec, inertia)
        profile = sec.string("wheel_profile")
        resolved = resolve_file(profile, base_dir)
        try:
            wheel_profile(resolved)
        except ProfileError as exc:
            sec.fail(str(exc), key="wheel_profile")
        x = sec.vector("position", "m", n=1, components=("x",))[0]
        axle_load = sec.quantity("axle_load", "N", required=False, positive=True)
        wheelsets.append(
            Wheelset(
                name=str(ws_name),
                position_x_m=x,
                mass_kg=sec.quantity("mass", "kg", positive=True),
                inertia_kg_m2=inertia,  # type: ignore[arg-type]
                wheel_profile=resolved,
                nominal_radius_m=sec.quantity(
                    "nominal_radius", "m", positive=True, minimum=0.2, maximum=1.0
                ),
                flange_back_distance_m=sec.quantity(
                    "flange_back_distance", "m", default=1.360, minimum=0.9, maximum=1.7
                ),
                axle_load_N=None if np.isnan(axle_load) else axle_load,
                estimate=sec.string("estimate", default=""),
            )
        )
    if not wheelsets:
        top.fail("a vehicle needs at least one wheelset", key="wheelsets")

    names = [b.name for b in bodies] + [w.name for w in wheelsets]
    duplicates = {n for n in names if names.count(n) > 1}
    if duplicates:
        top.fail(f"names used twice among bodies and wheelsets: {', '.join(sorted(duplicates))}")

    suspension: list[SuspensionElement] = []
    for el_name, raw in top.items("suspension", required=False):
        if not isinstance(raw, dict):
            Section(raw, source, lines, ("suspension", el_name))
        kind_sec = Section(raw, source, lines, ("suspension", el_name))
        kind = kind_sec.string("type", choices=tuple(ELEMENT_KEYS))
        sec = top.child("suspension", el_name, ELEMENT_KEYS[kind])
        pair = sec.string_list("bodies")
        if len(pair) != 2:
            sec.fail(f"expected two body names [upper, lower], got {list(pair)}", key="bodies")
        for b in pair:
            if b not in names:
                sec.fail(f"unknown body {b!r}.{_did_you_mean(b, names)}", key="bodies")
        if pair[0] == pair[1]:
            sec.fail("an element must connect two different bodies", key="bodies")
        position = sec.vector("position", "m")
        mirror = sec.boolean("mirror_y", default=False)
        estimate = sec.string("estimate", default="")
        if kind == "spring_damper":
            stiffness = sec.vector("stiffness", "N/m", default=(0, 0, 0), nonnegative=True)
            damping = sec.vector("damping", "N s/m", default=(0, 0, 0), nonnegative=True)
            if not (any(stiffness) or any(damping)):
                sec.fail("give a stiffness or a damping", key="stiffness")

            def make(n, p, st=stiffness, dm=damping, pr=pair, est=estimate):
                return SpringDamper(n, pr, p, st, dm, est)  # type: ignore[arg-type]

        elif kind == "torsion_spring":
            axis = sec.string("axis", choices=AXES)
            k = sec.quantity("stiffness", "N m/rad", default=0.0, minimum=0.0)
            c = sec.quantity("damping", "N m s/rad", default=0.0, minimum=0.0)

            def make(n, p, ax=axis, k=k, c=c, pr=pair, est=estimate):
                return TorsionSpring(n, pr, p, ax, k, c, est)  # type: ignore[arg-type]

        else:
            direction = sec.string("direction", choices=AXES)
            clearance = sec.quantity("clearance", "m", minimum=0.0)
            k = sec.quantity("stiffness", "N/m", positive=True)
            c = sec.quantity("damping", "N s/m", default=0.0, minimum=0.0)

            def make(n, p, d=direction, cl=clearance, k=k, c=c, pr=pair, est=estimate):
                return BumpStop(n, pr, p, d, cl, k, c, est)  # type: ignore[arg-type]

        if mirror and position[1] == 0.0:
            sec.fail("mirror_y needs a lateral position y != 0", key="position")
        for n, p in _mirrored(str(el_name), position, mirror):
            suspension.append(make(n, p))

    loads: list[Load] = []
    for load_name, _ in top.items("loads", required=False):
        sec = top.child("loads", load_name, LOAD_KEYS)
        body = sec.string("body")
        if body not in names:
            sec.fail(f"unknown body {body!r}.{_did_you_mean(body, names)}", key="body")
        force = sec.vector("force", "N")
        position = sec.vector("position", "m")
        est = sec.string("estimate", default="")
        mirror = sec.boolean("mirror_y", default=False)
        if mirror and position[1] == 0.0:
            sec.fail("mirror_y needs a lateral position y != 0", key="position")
        static = sec.boolean("static", default=True)
        for n, p in _mirrored(str(load_name), position, mirror):
            loads.append(Load(n, body, p, force, est, static))  # type: ignore[arg-type]

    default_speed_body = bodies[0].name if bodies else wheelsets[0].name
    speed_body = top.string("speed_body", default=default_speed_body)
    if speed_body not in names:
        top.fail(
            f"unknown body {speed_body!r}.{_did_you_mean(speed_body, names)}", key="speed_body"
        )

    contact = _contact_parameters(top.section("contact", CONTACT_KEYS, required=False))
    return Vehicle(
        name=name,
        description=description,
        bodies=tuple(bodies),
        wheelsets=tuple(wheelsets),
        suspension=tuple(suspension),
        loads=tuple(loads),
        contact=contact,
        speed_body=speed_body,
        gravity_m_per_s2=gravity,
        sources=sources,
        source=source,
        raw=data,
    )


def _check_inertia(sec: Section, inertia: tuple[float, ...]) -> None:
    """Principal moments of inertia of a rigid body are positive and satisfy the triangle
    inequality (each at most the sum of the other two)."""
    if min(inertia) <= 0.0:
        sec.fail("inertias must be > 0 kg m^2", key="inertia")
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
    import difflib

    close = difflib.get_close_matches(name, names, n=1, cutoff=0.6)
    return f" Did you mean {close[0]!r}?" if close else f" Known: {', '.join(names)}"


def _contact_parameters(sec: Section) -> ContactParameters:
    defaults = ContactParameters()
    kwargs = dict(
        friction=sec.quantity("friction", "1", default=defaults.friction, minimum=0.0),
        creep_model=sec.string("creep_model", default=defaults.creep_model),
        shear_modulus_Pa=sec.quantity(
            "shear_modulus", "Pa", default=defaults.shear_modulus_Pa, positive=True
        ),
        poisson=sec.quantity("poisson", "1", default=defaults.poisson, minimum=0.0, maximum=0.499),
        damping_model=sec.string(
            "damping_model", default=defaults.damping_model, choices=("linear", "hunt_crossley")
        ),
        scan_step_m=sec.quantity("scan_step", "m", default=defaults.scan_step_m, positive=True),
    )
    unit = "N s/m" if kwargs["damping_model"] == "linear" else "s/m"
    kwargs["damping"] = sec.quantity("normal_damping", unit, default=defaults.damping, minimum=0.0)
    if sec.has("polach_2005"):
        p = sec.section("polach_2005", ("k_a", "k_s", "A", "B"))
        kwargs["polach_2005"] = (
            p.quantity("k_a", "1", positive=True, maximum=1.0),
            p.quantity("k_s", "1", positive=True, maximum=1.0),
            p.quantity("A", "1", positive=True, maximum=1.0),
            p.quantity("B", "s/m", minimum=0.0),
        )
    try:
        return ContactParameters(**kwargs)
    except (ContactParameterError, ValueError) as exc:
        sec.fail(str(exc))
        raise  # unreachable
