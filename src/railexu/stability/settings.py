"""Settings of a critical-speed analysis, from code, files (study ``critical_speed:``
sections) and the command line."""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from railexu.errors import InputError, did_you_mean

METHODS = ("linear", "bisection", "ramp", "branch")
LINEARIZATIONS = ("equivalent_conicity", "profiles")


#: Finest bisection bracket [m/s]: 0.01 m/s of a 75 m/s range is 13 runs; a critical speed is
#: not defined finer than that (it moves with the disturbance and the run length).
MIN_TOLERANCE_M_PER_S = 0.01
#: Largest hunting threshold and initial lateral offset [m]: the flanges stop a wheelset about
#: 10 mm from the track centre (flangeway clearance), so a larger amplitude is never reached.
MAX_LATERAL_M = 0.02
#: Lowest speed searched [m/s].
MIN_SPEED_M_PER_S = 1.0
#: Shortest run of the nonlinear methods [m]: hunting wavelengths are 10-30 m.
MIN_DISTANCE_M = 20.0
#: Most speeds of the linear analysis.
MAX_LINEAR_POINTS = 1000
#: Steepest deceleration of the ramp method [m/s^2].
MAX_DECELERATION_M_PER_S2 = 5.0


class StabilityError(InputError):
    """Invalid critical-speed settings."""


@dataclass(frozen=True)
class CriticalSpeedSettings:
    """Settings of a critical-speed analysis (SI units).

    Attributes:
        methods: any of ``linear``, ``bisection``, ``ramp``.
        speed_min_m_per_s, speed_max_m_per_s: the speed range searched.
        tolerance_m_per_s: width of the final bisection bracket.
        initial_lateral_m: lateral disturbance (initial offset of the whole vehicle).
        threshold_m: amplitude above which a nonlinear run counts as hunting.
        distance_m: distance of each bisection run.
        linear_points: number of speeds of the linear analysis.
        conicity_amplitude_m: amplitude at which the equivalent conicity is taken.
        linearization: ``equivalent_conicity`` (default) or ``profiles``.
        ramp_deceleration_m_per_s2: deceleration of the ramp (0.2 m/s^2: the 1 % per period
            drift rule of :mod:`railexu.stability.ramp`); a second ramp at twice it checks
            that the result does not depend on the rate.
        ramp_settle_m: distance run at the top speed before the ramp starts.
        ramp_budget_m: the most distance one ramp may run (settling included): a ramp that
            would need more is cut there and says ``budget exhausted``.
        time_step_s: integration step of the nonlinear runs.
        branch_step_m_per_s: speed step of the limit-cycle branch (``branch`` method).
        max_runs: most runs of the branch method (its budget).
        fit_fraction: share of each nonlinear run's time (its end) over which the
            oscillation's envelope is fitted for the growth-rate classification.
        floor_m: amplitude below which a nonlinear run's oscillation counts as none (stable).
        limit_cycle_floor_m: a sustained oscillation (limit cycle) smaller than this is
            labelled a small limit cycle (the run summary's 1 mm hunting threshold); a label
            only: every sustained or growing oscillation above ``floor_m`` is unstable, so no
            critical speed moves with this value.
    """

    methods: tuple[str, ...] = METHODS
    speed_min_m_per_s: float = 5.0
    speed_max_m_per_s: float = 80.0
    tolerance_m_per_s: float = 1.0
    initial_lateral_m: float = 0.004
    threshold_m: float = 0.003
    distance_m: float = 300.0
    linear_points: int = 31
    conicity_amplitude_m: float = 0.003
    linearization: str = "equivalent_conicity"
    ramp_deceleration_m_per_s2: float = 0.2
    ramp_settle_m: float = 200.0
    ramp_budget_m: float = 20000.0
    time_step_s: float = 0.002
    branch_step_m_per_s: float = 5.0
    max_runs: int = 30
    fit_fraction: float = 0.5
    floor_m: float = 1.0e-4
    limit_cycle_floor_m: float = 1.0e-3

    def __post_init__(self) -> None:
        for m in self.methods:
            if m not in METHODS:
                raise StabilityError(f"unknown method {m!r}; expected some of {', '.join(METHODS)}")
        if self.linearization not in LINEARIZATIONS:
            raise StabilityError(
                f"linearization {self.linearization!r}: expected one of {', '.join(LINEARIZATIONS)}"
            )
        if not self.speed_min_m_per_s >= MIN_SPEED_M_PER_S:
            raise StabilityError(
                f"speed_min {self.speed_min_m_per_s:g} m/s: expected at least "
                f"{MIN_SPEED_M_PER_S:g} m/s (critical speeds of rail vehicles are above 10 m/s; "
                "below 1 m/s the creepages, normalised by the speed, lose their meaning)"
            )
        if not 0.0 < self.speed_min_m_per_s < self.speed_max_m_per_s <= 150.0:
            raise StabilityError(
                "need 0 < speed_min < speed_max <= 150 m/s (the limit of a run's speed), got "
                f"{self.speed_min_m_per_s:g} and {self.speed_max_m_per_s:g} m/s"
            )
        if not self.tolerance_m_per_s > 0.0:
            raise StabilityError("tolerance must be > 0 m/s")
        span = self.speed_max_m_per_s - self.speed_min_m_per_s
        if not MIN_TOLERANCE_M_PER_S <= self.tolerance_m_per_s <= span:
            raise StabilityError(
                f"tolerance {self.tolerance_m_per_s:g} m/s: expected {MIN_TOLERANCE_M_PER_S:g} "
                f"m/s .. the searched range ({span:g} m/s); a finer bracket only adds runs"
            )
        if not self.threshold_m > 0.0:
            raise StabilityError("threshold must be > 0 m")
        if not self.threshold_m >= self.floor_m:
            raise StabilityError(
                f"threshold {self.threshold_m:g} m: expected at least the floor "
                f"{self.floor_m:g} m (an oscillation below it counts as none)"
            )
        if not self.distance_m >= MIN_DISTANCE_M:
            raise StabilityError(
                f"distance {self.distance_m:g} m: expected at least {MIN_DISTANCE_M:g} m (a "
                "hunting wavelength is 10-30 m; a run must hold several to judge it)"
            )
        for name, value in (("threshold", self.threshold_m),
                            ("initial_lateral", self.initial_lateral_m)):  # fmt: skip
            if not abs(value) <= MAX_LATERAL_M:
                raise StabilityError(
                    f"{name} {value:g} m: expected at most {MAX_LATERAL_M:g} m (the flanges stop "
                    "a wheelset about 10 mm from the track centre)"
                )
        if not 2 <= self.linear_points <= MAX_LINEAR_POINTS:
            raise StabilityError(
                f"linear_points must be 2 .. {MAX_LINEAR_POINTS} (0.075 m/s steps over 75 m/s), "
                f"got {self.linear_points}"
            )
        if not 0.0 < self.ramp_deceleration_m_per_s2 <= MAX_DECELERATION_M_PER_S2:
            raise StabilityError(
                f"ramp_deceleration {self.ramp_deceleration_m_per_s2:g} m/s^2: expected > 0 and "
                f"<= {MAX_DECELERATION_M_PER_S2:g} m/s^2 (trains brake at 1-1.5 m/s^2; a "
                "faster ramp outruns the growth of the hunting it is to find)"
            )
        if not self.ramp_settle_m >= 0.0:
            raise StabilityError(f"ramp_settle {self.ramp_settle_m:g} m: expected >= 0 m")
        if not self.branch_step_m_per_s > 0.0:
            raise StabilityError("branch_step must be > 0 m/s")
        if not self.ramp_budget_m > self.ramp_settle_m:
            raise StabilityError("ramp_budget must be longer than ramp_settle")
        if self.max_runs < 2:
            raise StabilityError("max_runs must be >= 2")
        if not 0.1 <= self.fit_fraction <= 0.9:
            raise StabilityError("fit_fraction must be between 0.1 and 0.9")
        if not 0.0 < self.floor_m <= self.limit_cycle_floor_m:
            raise StabilityError("need 0 < floor <= limit_cycle_floor")


CRITICAL_SPEED_KEYS = (
    "methods",
    "speed_min",
    "speed_max",
    "tolerance",
    "initial_lateral",
    "threshold",
    "distance",
    "linear_points",
    "conicity_amplitude",
    "linearization",
    "ramp_deceleration",
    "ramp_settle",
    "ramp_budget",
    "time_step",
    "branch_step",
    "max_runs",
    "fit_fraction",
    "floor",
    "limit_cycle_floor",
)


def critical_speed_settings_from_dict(
    data: dict, source: str = "<critical speed>", lines: dict | None = None, path: tuple = ()
) -> CriticalSpeedSettings:
    """Settings from a mapping with units (study files, ``critical_speed:`` section)::

        {methods: [linear, bisection], speed_min: 20 m/s, speed_max: 80 m/s, tolerance: 2 m/s}

    Raises:
        InputError: unknown keys, wrong units or values, naming source, line and key.
    """
    from railexu.inputs import Section

    sec = Section(data, source, lines, path, CRITICAL_SPEED_KEYS)
    d = CriticalSpeedSettings()
    methods = sec.string_list("methods", default=d.methods)
    for m in methods:
        if m not in METHODS:
            sec.fail(f"unknown method {m!r}; expected some of {', '.join(METHODS)}", key="methods")
    kwargs = dict(
        methods=tuple(methods),
        speed_min_m_per_s=sec.quantity("speed_min", "m/s", default=d.speed_min_m_per_s),
        speed_max_m_per_s=sec.quantity("speed_max", "m/s", default=d.speed_max_m_per_s),
        tolerance_m_per_s=sec.quantity("tolerance", "m/s", default=d.tolerance_m_per_s),
        initial_lateral_m=sec.quantity("initial_lateral", "m", default=d.initial_lateral_m),
        threshold_m=sec.quantity("threshold", "m", default=d.threshold_m),
        distance_m=sec.quantity("distance", "m", default=d.distance_m, positive=True),
        linear_points=sec.integer("linear_points", default=d.linear_points, minimum=2),
        conicity_amplitude_m=sec.quantity(
            "conicity_amplitude", "m", default=d.conicity_amplitude_m, positive=True
        ),
        linearization=sec.string("linearization", default=d.linearization, choices=LINEARIZATIONS),
        ramp_deceleration_m_per_s2=sec.quantity(
            "ramp_deceleration", "m/s^2", default=d.ramp_deceleration_m_per_s2, positive=True
        ),
        ramp_settle_m=sec.quantity("ramp_settle", "m", default=d.ramp_settle_m, minimum=0.0),
        ramp_budget_m=sec.quantity("ramp_budget", "m", default=d.ramp_budget_m, positive=True),
        time_step_s=sec.quantity("time_step", "s", default=d.time_step_s, positive=True),
        branch_step_m_per_s=sec.quantity(
            "branch_step", "m/s", default=d.branch_step_m_per_s, positive=True
        ),
        max_runs=sec.integer("max_runs", default=d.max_runs, minimum=2),
        fit_fraction=sec.quantity(
            "fit_fraction", "", default=d.fit_fraction, minimum=0.1, maximum=0.9
        ),
        floor_m=sec.quantity("floor", "m", default=d.floor_m, positive=True),
        limit_cycle_floor_m=sec.quantity(
            "limit_cycle_floor", "m", default=d.limit_cycle_floor_m, positive=True
        ),
    )
    try:
        return CriticalSpeedSettings(**kwargs)
    except StabilityError as exc:
        sec.fail(str(exc))
        raise  # unreachable


def print_messages(stream=sys.stderr) -> Callable[[str], None]:
    """A progress callback that prints each message on its own line."""

    def report(message: str) -> None:
        stream.write(f"  {message}\n")
        stream.flush()

    return report


def parse_methods(text: str | Sequence[str]) -> tuple[str, ...]:
    """``"linear,bisection"`` -> ``("linear", "bisection")`` (checked)."""
    items = text.split(",") if isinstance(text, str) else list(text)
    methods = tuple(m.strip() for m in items if m.strip())
    for m in methods:
        if m not in METHODS:
            hint = did_you_mean(m, METHODS, known=False)
            raise StabilityError(f"unknown method {m!r}.{hint} Valid: {', '.join(METHODS)}")
    return methods
