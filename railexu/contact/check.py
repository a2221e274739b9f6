"""Quasi-static wheel/rail check: the public function behind ``railexu contact``.

An engineer checks a wheel/rail pair before any dynamics: for a sweep of lateral displacements
(with yaw proportional to it, as in the Manchester contact benchmark), each wheel is pressed
onto its rail until it carries the given load, while the wheelset rolls forward at a speed with
the spin of its nominal radius. Every contact point is reported with its position on wheel and
rail, rolling radius, contact angle, ellipse, creepages and creep forces; the rolling radius
difference and the equivalent conicity follow from the rigid contact.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .conicity import equivalent_conicity
from .evaluation import ContactParameters, WheelsetContactModel
from .placement import symmetric_wheelset
from .quasistatic import PressedWheelset, press_wheelset

#: Columns of ``contact.csv`` (units in the names; angles in rad, creepages dimensionless).
CONTACT_COLUMNS = (
    "lateral_m",
    "yaw_rad",
    "roll_rad",
    "vertical_m",
    "side",
    "point",
    "wheel_lateral_m",
    "rail_lateral_m",
    "contact_x_m",
    "contact_y_m",
    "contact_z_m",
    "rolling_radius_m",
    "contact_angle_rad",
    "penetration_m",
    "normal_force_N",
    "a_m",
    "b_m",
    "creep_long",
    "creep_lat",
    "spin_per_m",
    "force_long_N",
    "force_lat_N",
    "force_x_track_N",
    "force_y_track_N",
    "force_z_track_N",
    "wheel_curvature_long_per_m",
    "wheel_curvature_lat_per_m",
    "rail_curvature_lat_per_m",
)


@dataclass(frozen=True)
class ContactCheckSettings:
    """Settings of a quasi-static contact check (defaults: the Manchester contact benchmark).

    Attributes:
        wheel, rail: built-in profile names or profile files.
        inclination: rail inclination (``"1:40"``, ``"1:20"``, ``"none"``).
        gauge_m: track gauge measured 14 mm below the top of rail [m].
        flange_back_m: flange-back distance of the wheelset [m].
        radius_m: nominal rolling radius [m].
        lateral_m: lateral displacements to evaluate [m].
        yaw_per_lateral_rad_per_m: yaw = factor * lateral [rad/m].
        load_N: vertical load of each wheel [N].
        speed_m_per_s: forward speed [m/s]; the wheelset spins at speed / radius.
        contact: contact parameters (material, friction, creep law).
        conicity_amplitudes_m: amplitudes for the equivalent conicity [m].
    """

    wheel: str = "S1002"
    rail: str = "UIC60"
    inclination: str | float = "1:40"
    gauge_m: float = 1.435
    flange_back_m: float = 1.360
    radius_m: float = 0.46
    lateral_m: tuple[float, ...] = tuple(np.round(np.arange(0.0, 0.01 + 1e-12, 0.0005), 10))
    yaw_per_lateral_rad_per_m: float = 0.0
    load_N: float = 10000.0
    speed_m_per_s: float = 2.0
    contact: ContactParameters = field(default_factory=ContactParameters)
    conicity_amplitudes_m: tuple[float, ...] = tuple(
        np.round(np.arange(0.0005, 0.01 + 1e-12, 0.0005), 10)
    )


@dataclass
class ContactCheckResult:
    """Outcome of :func:`contact_check`."""

    settings: ContactCheckSettings
    model: WheelsetContactModel
    pressed: list[PressedWheelset]
    rows: list[dict]
    conicity_amplitude_m: np.ndarray
    conicity: np.ndarray
    delta_r_lateral_m: np.ndarray
    delta_r_m: np.ndarray


def contact_check(settings: ContactCheckSettings) -> ContactCheckResult:
    """Run the quasi-static check: press the wheelset at each lateral displacement, report.

    Raises:
        railexu.contact.quasistatic.ContactSolveError: when a wheel leaves its rail.
    """
    geometry = symmetric_wheelset(
        settings.wheel,
        settings.rail,
        nominal_radius_m=settings.radius_m,
        inclination=settings.inclination,
        gauge_m=settings.gauge_m,
        flange_back_distance_m=settings.flange_back_m,
    )
    model = WheelsetContactModel(geometry, settings.contact, settings.speed_m_per_s)
    pressed: list[PressedWheelset] = []
    rows: list[dict] = []
    for y in settings.lateral_m:
        yaw = settings.yaw_per_lateral_rad_per_m * y
        state = press_wheelset(model, float(y), float(yaw), settings.load_N)
        pressed.append(state)
        for p in state.result.points:
            if not p.loaded:
                continue
            rows.append(
                {
                    "lateral_m": float(y),
                    "yaw_rad": float(yaw),
                    "roll_rad": state.roll_rad,
                    "vertical_m": state.vertical_m,
                    "side": p.side,
                    "point": p.point,
                    "wheel_lateral_m": p.wheel_lateral_m,
                    "rail_lateral_m": p.rail_lateral_m,
                    "contact_x_m": p.position_m[0],
                    "contact_y_m": p.position_m[1],
                    "contact_z_m": p.position_m[2],
                    "rolling_radius_m": p.rolling_radius_m,
                    "contact_angle_rad": p.contact_angle_rad,
                    "penetration_m": p.penetration_m,
                    "normal_force_N": p.normal_force_N,
                    "a_m": p.a_m,
                    "b_m": p.b_m,
                    "creep_long": p.creep_long,
                    "creep_lat": p.creep_lat,
                    "spin_per_m": p.spin_per_m,
                    "force_long_N": p.force_long_N,
                    "force_lat_N": p.force_lat_N,
                    "force_x_track_N": p.force_track_N[0],
                    "force_y_track_N": p.force_track_N[1],
                    "force_z_track_N": p.force_track_N[2],
                    "wheel_curvature_long_per_m": p.wheel_curvature_long_per_m,
                    "wheel_curvature_lat_per_m": p.wheel_curvature_lat_per_m,
                    "rail_curvature_lat_per_m": p.rail_curvature_lat_per_m,
                }
            )
    # renumber points per wheel among the loaded ones (1 = nearest the field side... by s)
    _renumber(rows)
    amps = np.asarray(settings.conicity_amplitudes_m, dtype=float)
    conicity, y_dr, dr = equivalent_conicity(model, amps)
    return ContactCheckResult(settings, model, pressed, rows, amps, conicity, y_dr, dr)


def _renumber(rows: list[dict]) -> None:
    """Number the loaded points of each wheel 1, 2, ... from the tread towards the flange."""
    groups: dict[tuple[float, str], list[dict]] = {}
    for r in rows:
        groups.setdefault((r["lateral_m"], r["side"]), []).append(r)
    for group in groups.values():
        group.sort(key=lambda r: -r["wheel_lateral_m"])
        for i, r in enumerate(group, start=1):
            r["point"] = i


def _fmt(v):
    if isinstance(v, float):
        return f"{v:.10g}"
    return v
