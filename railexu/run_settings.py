"""Run settings: speed, distance, initial offset, step and solver of one run (SI units).

:class:`RunSettings` is what :func:`railexu.simulation.run` takes; :func:`run_settings_from_dict`
reads it from a mapping with units, as study files give it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import InputError
from .inputs import Section


class RunSettingsError(InputError):
    """Invalid run settings."""


@dataclass(frozen=True)
class RunSettings:
    """Settings of one run (SI units).

    Attributes:
        speed_m_per_s: constant forward speed V.
        distance_m: distance to run.
        initial_lateral_m: lateral offset of the whole vehicle at the start (the seed: 2 mm).
        time_step_s: integration step (default 2 ms, see the module docstring).
        output_interval_s: interval of the recorded time series (default: 5 ms or the step).
        solver: ``"generalized_alpha"`` (default) or ``"trapezoidal"``.
        spectral_radius: numerical damping of generalized-alpha (1 = none).
        newton_relative_tolerance: Exudyn's relative Newton tolerance.
        derailment_lift_fraction: a wheel that rises by this fraction of its flange height
            above its starting height has climbed its rail: the run stops as ``derailed``.
        derailment_lateral_m: a wheelset further than this from the track centre has left the
            rails: the run stops as ``derailed``.
        deceleration_m_per_s2: a constant deceleration from ``speed_m_per_s`` (the ramp method
            of the critical speed); the speed must stay positive over ``distance_m``.
    """

    speed_m_per_s: float = 10.0
    distance_m: float = 150.0
    initial_lateral_m: float = 0.002
    time_step_s: float = 0.002
    output_interval_s: float | None = None
    solver: str = "generalized_alpha"
    spectral_radius: float = 0.7
    newton_relative_tolerance: float = 1.0e-3
    derailment_lift_fraction: float = 0.75
    derailment_lateral_m: float = 0.040
    deceleration_m_per_s2: float = 0.0

    def __post_init__(self) -> None:
        checks = [
            (self.speed_m_per_s > 0.0, "speed must be > 0 m/s"),
            (self.speed_m_per_s <= 150.0, "speed must be <= 150 m/s (is it in km/h?)"),
            (self.distance_m > 0.0, "distance must be > 0 m"),
            (abs(self.initial_lateral_m) < 0.02, "initial lateral offset must be below 20 mm"),
            (1e-5 <= self.time_step_s <= 0.01, "time step must be within 0.01 .. 10 ms"),
            (0.0 < self.spectral_radius <= 1.0, "spectral radius must be in (0, 1]"),
            (1e-10 <= self.newton_relative_tolerance <= 1e-2, "Newton tolerance out of range"),
            (0.0 < self.derailment_lift_fraction <= 1.0, "lift fraction must be in (0, 1]"),
            (self.solver in ("generalized_alpha", "trapezoidal"), "solver must be "
             "'generalized_alpha' or 'trapezoidal'"),
        ]  # fmt: skip
        if self.deceleration_m_per_s2 != 0.0:
            v_end_sq = self.speed_m_per_s**2 - 2.0 * self.deceleration_m_per_s2 * self.distance_m
            checks.append((self.deceleration_m_per_s2 > 0.0, "deceleration must be >= 0"))
            checks.append((v_end_sq > 0.0, "the deceleration stops the vehicle before the end"))
        if self.output_interval_s is not None:
            checks.append((self.output_interval_s >= self.time_step_s, "output interval < step"))
        for ok, message in checks:
            if not ok:
                raise RunSettingsError(f"run settings: {message}")

    @property
    def duration_s(self) -> float:
        a = self.deceleration_m_per_s2
        if a == 0.0:
            return self.distance_m / self.speed_m_per_s
        v_end = math.sqrt(self.speed_m_per_s**2 - 2.0 * a * self.distance_m)
        return (self.speed_m_per_s - v_end) / a

    def speed_at(self, t: float) -> float:
        """Forward speed at time ``t`` [m/s]."""
        return self.speed_m_per_s - self.deceleration_m_per_s2 * t

    def distance_at(self, t: float) -> float:
        """Distance run at time ``t`` [m]."""
        return self.speed_m_per_s * t - 0.5 * self.deceleration_m_per_s2 * t * t

    @property
    def output_every(self) -> int:
        interval = self.output_interval_s or max(self.time_step_s, 0.005)
        return max(1, int(round(interval / self.time_step_s)))


RUN_KEYS = (
    "speed",
    "distance",
    "initial_lateral",
    "time_step",
    "output_interval",
    "solver",
    "spectral_radius",
    "newton_tolerance",
)


def run_settings_from_dict(
    data: dict, source: str = "<run settings>", lines: dict | None = None, path: tuple = ()
) -> RunSettings:
    """Run settings from a mapping with units, as study files give them::

        {speed: 10 m/s, distance: 150 m, initial_lateral: 2 mm, time_step: 2 ms}

    Keys: ``speed`` [m/s], ``distance`` [m], ``initial_lateral`` [m], ``time_step`` [s],
    ``output_interval`` [s], ``solver``, ``spectral_radius``, ``newton_tolerance``; missing ones
    take the defaults of :class:`RunSettings`.

    Raises:
        InputError: unknown keys, wrong units, invalid values (naming source, line and key).
    """
    sec = Section(data, source, lines, path, RUN_KEYS)
    d = RunSettings()
    kwargs = dict(
        speed_m_per_s=sec.quantity("speed", "m/s", default=d.speed_m_per_s),
        distance_m=sec.quantity("distance", "m", default=d.distance_m),
        initial_lateral_m=sec.quantity("initial_lateral", "m", default=d.initial_lateral_m),
        time_step_s=sec.quantity("time_step", "s", default=d.time_step_s),
        solver=sec.string("solver", default=d.solver, choices=("generalized_alpha", "trapezoidal")),
        spectral_radius=sec.quantity("spectral_radius", "1", default=d.spectral_radius),
        newton_relative_tolerance=sec.quantity(
            "newton_tolerance", "1", default=d.newton_relative_tolerance
        ),
    )
    if sec.has("output_interval"):
        kwargs["output_interval_s"] = sec.quantity("output_interval", "s")
    try:
        return RunSettings(**kwargs)
    except RunSettingsError as exc:
        sec.fail(str(exc))
        raise  # unreachable
