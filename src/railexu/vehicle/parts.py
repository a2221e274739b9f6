"""The parts a vehicle is made of: bodies, wheelsets, suspension elements, external loads and
measurement points (SI units, vehicle axes: ``x`` forward from the vehicle centre, ``y`` to the
left, ``z`` up from the top of the rails; ``docs/vehicle-format.md``).

These are plain validated values; :mod:`railexu.vehicle.vehicle` reads them from a file and
assembles the :class:`~railexu.vehicle.vehicle.Vehicle`. :class:`VehicleLayout` is what the
topology checks (:mod:`railexu.vehicle.checks`) need of a vehicle.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

from railexu.vehicle.schema import AXES


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
    """A wheelset: axle along y, centre at the nominal rolling radius above the rails.

    ``wheel_profile`` and ``nominal_radius_m`` are the left wheel's (the common value when both
    wheels are alike); ``wheel_profile_right`` and ``nominal_radius_right_m`` the right wheel's
    when the file gives ``{left: ..., right: ...}``, else empty (``""``, ``0.0``: as the left
    one), so that ``dataclasses.replace(wheelset, wheel_profile=...)`` changes both wheels.
    :attr:`profile_right` and :attr:`radius_right_m` give the right wheel's values."""

    name: str
    position_x_m: float
    mass_kg: float
    inertia_kg_m2: tuple[float, float, float]  # roll, yaw, spin
    wheel_profile: str
    nominal_radius_m: float
    flange_back_distance_m: float
    axle_load_N: float | None = None  # declared static axle load, checked against the statics
    estimate: str = ""
    wheel_profile_right: str = ""
    nominal_radius_right_m: float = 0.0

    @property
    def profile_right(self) -> str:
        """The right wheel's profile."""
        return self.wheel_profile_right or self.wheel_profile

    @property
    def radius_right_m(self) -> float:
        """The right wheel's nominal rolling radius [m]."""
        return self.nominal_radius_right_m or self.nominal_radius_m

    @property
    def position_m(self) -> tuple[float, float, float]:
        return (self.position_x_m, 0.0, self.nominal_radius_m)

    @property
    def symmetric(self) -> bool:
        """Both wheels have the same profile and radius."""
        return (
            self.wheel_profile == self.profile_right
            and self.nominal_radius_m == self.radius_right_m
        )


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


@dataclass(frozen=True)
class NonlinearSpring:
    """Force against deflection from a table along one track axis (``docs/suspension.md``).

    The deflection ``d`` is the second body's attachment point minus the first's along
    ``direction`` (measured from the unloaded element); the element pushes the second body with
    ``-F(d) - c d'``. The table is the full one (a ``symmetric`` file table is mirrored)."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    direction: str
    deflection_m: tuple[float, ...]
    force_N: tuple[float, ...]
    interpolation: str = "linear"
    damping_N_s_per_m: float = 0.0
    estimate: str = ""


@dataclass(frozen=True)
class Damper:
    """A damper along one track axis: force ``F(v)`` of the relative velocity from a table (a
    linear damper is the table ``[-1, 1] m/s -> [-c, c]``, continued linearly), in series with
    the bushes' stiffness when ``series_stiffness_N_per_m`` is set (a Maxwell element)."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    direction: str
    velocity_m_per_s: tuple[float, ...]
    force_N: tuple[float, ...]
    interpolation: str = "linear"
    series_stiffness_N_per_m: float | None = None
    damping_N_s_per_m: float | None = None  # the linear coefficient when the file gave one
    estimate: str = ""


@dataclass(frozen=True)
class Friction:
    """Dry friction along one track axis: ``F_c tanh(v / v_s)`` of the sliding velocity; with
    a stick stiffness, a spring in series with the slider (stick-slip, one internal
    coordinate)."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    direction: str
    friction_force_N: float
    slip_velocity_m_per_s: float = 1.0e-3
    stick_stiffness_N_per_m: float | None = None
    estimate: str = ""


@dataclass(frozen=True)
class UICLink:
    """The UIC double-link suspension, longitudinal (x) and lateral (y): pendulum stiffness
    ``W / L`` in parallel with a stick-slip friction element of limit ``mu W`` (Piotrowski
    2003). ``vertical_load_N`` None: the static load of the vertical elements at its point."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    pendulum_length_m: tuple[float, float]
    friction_coefficient: tuple[float, float]
    stick_stiffness_N_per_m: tuple[float, float]
    vertical_load_N: float | None = None
    slip_velocity_m_per_s: float = 1.0e-3
    estimate: str = ""


@dataclass(frozen=True)
class AirSpring:
    """An air spring with reservoir (vertical): ``k1`` in parallel with ``k2`` in series with
    the orifice damping ``c``; shear stiffness and damping in x and y."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    vertical_stiffness_N_per_m: float
    reservoir_stiffness_N_per_m: float
    orifice_damping_N_s_per_m: float
    lateral_stiffness_N_per_m: tuple[float, float] = (0.0, 0.0)
    lateral_damping_N_s_per_m: tuple[float, float] = (0.0, 0.0)
    estimate: str = ""


@dataclass(frozen=True)
class AntiRollBar:
    """A torsion bar resisting the relative roll of two bodies (moment ``k (phi_2 - phi_1)``)."""

    name: str
    bodies: tuple[str, str]
    position_m: tuple[float, float, float]
    stiffness_N_m_per_rad: float
    damping_N_m_s_per_rad: float = 0.0
    estimate: str = ""


SuspensionElement = (
    SpringDamper
    | TorsionSpring
    | BumpStop
    | NonlinearSpring
    | Damper
    | Friction
    | UICLink
    | AirSpring
    | AntiRollBar
)


def linear_part(el: SuspensionElement) -> SpringDamper | TorsionSpring | None:
    """The linear connector part of an element (same name, bodies and point), or None.

    Spring-dampers and torsion springs are their own; an air spring's static stiffness ``k1``
    and shear stiffness and damping form a spring-damper (its reservoir branch is nonlinear
    kernel work, :mod:`railexu.model.suspension_forces`); an anti-roll bar is a torsion spring about
    x; a linear damper without series stiffness is a spring-damper with damping on its axis.
    """
    if isinstance(el, SpringDamper | TorsionSpring):
        return el
    if isinstance(el, AirSpring):
        k = (*el.lateral_stiffness_N_per_m, el.vertical_stiffness_N_per_m)
        c = (*el.lateral_damping_N_s_per_m, 0.0)
        return SpringDamper(el.name, el.bodies, el.position_m, k, c, el.estimate)
    if isinstance(el, AntiRollBar):
        return TorsionSpring(el.name, el.bodies, el.position_m, "x", el.stiffness_N_m_per_rad,
                             el.damping_N_m_s_per_rad, el.estimate)  # fmt: skip
    linear_damper = isinstance(el, Damper) and el.damping_N_s_per_m is not None
    if linear_damper and el.series_stiffness_N_per_m is None:
        c = [0.0, 0.0, 0.0]
        c[AXES.index(el.direction)] = el.damping_N_s_per_m
        return SpringDamper(el.name, el.bodies, el.position_m, (0.0, 0.0, 0.0), tuple(c),
                            el.estimate)  # fmt: skip
    return None


@dataclass(frozen=True)
class MeasurementPoint:
    """A point fixed to a body whose accelerations are recorded (vehicle axes, m)."""

    name: str
    body: str
    position_m: tuple[float, float, float]


class VehicleLayout(Protocol):
    """What the checks of a vehicle's topology read: its parts and the mapping they came from
    (:class:`~railexu.vehicle.vehicle.Vehicle` is one)."""

    bodies: tuple[Body, ...]
    wheelsets: tuple[Wheelset, ...]
    suspension: tuple[SuspensionElement, ...]
    loads: tuple[Load, ...]
    raw: dict[str, Any]

    def wheelset(self, name: str) -> Wheelset: ...
