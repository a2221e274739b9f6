"""Run settings: speed, distance, initial offset, step and solver of one run (SI units).

:class:`RunSettings` is what :func:`railexu.run` takes; :func:`run_settings_from_dict`
reads it from a mapping with units, as study files give it. Every key is declared once in
:data:`RUN_SCHEMA` (unit, range, default, doc; ``docs/run-settings-format.md`` is generated from
it), and the dataclass takes its defaults and range checks from there.

Besides the ranges of single values, one rule ties the step to the speed
(:func:`check_step_for_speed`): per step the vehicle must not move more than
:data:`MAX_TRAVEL_PER_STEP_M` = 0.3 m, a tenth of the shortest irregularity wavelength railexu
synthesises by default (3 m, the lower end of the ERRI B176 band) and about a hundredth of the
kinematic (Klingel) wavelength of a wheelset. A coarser step cannot resolve the track the
wheels run over nor the contact forces' variation along it, and it changes the verdict (10 ms at
140 m/s is 1.4 m per step). The error names the step the physics needs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from railexu.errors import InputError
from railexu.inputs import OPTIONAL, Field, Schema, Section
from railexu.operation.speed_profile import SpeedProfile, SpeedProfileError
from railexu.operation.traction import BASES, Schedule, Traction, TractionError
from railexu.units import UnitError, to_si

#: Largest distance the vehicle may travel in one integration step [m] (see the module doc).
MAX_TRAVEL_PER_STEP_M = 0.3
#: Most integration steps of one run: more is a unit mistake (or weeks of computing).
MAX_STEPS = 20_000_000
SOLVERS = ("generalized_alpha", "trapezoidal")
#: The wear laws a run can be worn by: the names of
#: :data:`railexu.contact.wear.laws.WEAR_LAWS` (written here so that reading run settings loads
#: no numerical library; a test keeps the two equal).
WEAR_LAWS = ("archard_jendel", "energy_usfd")


class RunSettingsError(InputError):
    """Invalid run settings; ``field`` is the key of :data:`RUN_SCHEMA` at fault."""

    field: str = ""


RUN_SCHEMA = Schema(
    "run",
    (
        Field("speed", "constant forward speed (the start speed of a ramp)", unit="m/s",
              default=10.0, positive=True, maximum=150.0),
        Field("distance", "distance to run", unit="m", default=150.0, positive=True,
              maximum=200_000.0),
        Field("initial_lateral", "lateral offset of the whole vehicle at the start (the seed "
              "scenario uses 2 mm)", unit="m", default=0.002, minimum=-0.0199, maximum=0.0199),
        Field("time_step", "integration step; at most 0.3 m of travel per step", unit="s",
              default=0.002, minimum=1e-5, maximum=0.01),
        Field("output_interval", "interval of the recorded time series (default: 5 ms or the "
              "step)", unit="s", default=OPTIONAL, positive=True, maximum=10.0),
        Field("solver", "Exudyn's implicit integrator", "text", default="generalized_alpha",
              choices=SOLVERS),
        Field("spectral_radius", "numerical damping of generalized-alpha (1 = none)", unit="1",
              default=0.7, positive=True, maximum=1.0),
        Field("newton_tolerance", "Exudyn's relative Newton tolerance", unit="1",
              default=1.0e-3, minimum=1e-10, maximum=1e-2),
        Field("evaluate_from", "start of the evaluation window of every statistic (default: "
              "after the start-up, 20 m or a tenth of the run if less; docs/assessment.md)",
              unit="m", default=OPTIONAL, minimum=0.0, maximum=200_000.0),
        Field("evaluate_to", "end of the evaluation window (default: the end of the run)",
              unit="m", default=OPTIONAL, positive=True, maximum=200_000.0),
        Field("contact_outputs", "record every contact point (position, angle, creepages, "
              "forces, semi-axes, T-gamma) in the time series: larger files", "boolean",
              default=False),
        Field("traction_torque", "traction torque on each driven wheelset, constant or a table "
              "[[time or distance, torque], ...]; frees the forward motion "
              "(docs/traction-and-braking.md)", unit="N m", default=OPTIONAL),
        Field("brake_force", "tread-brake force on each wheel (a torque force x radius against "
              "the spin), constant or a table like traction_torque; frees the forward motion",
              unit="N", default=OPTIONAL, minimum=0.0),
        Field("driven_wheelsets", "the wheelsets traction_torque drives (default: all)",
              "text_list", default=()),
        Field("time_limit", "free motion: the run ends at its distance or at this time (default: "
              "3 x distance / speed)", unit="s", default=OPTIONAL, positive=True),
        Field("wear", "after the run, the wear and RCF of every wheel and rail by this wear law "
              "(`archard_jendel` or `{law: energy_usfd}`) into the run's folder: wear.csv, "
              "wear.json, summary.json's `wear`, the wear figure; turns contact_outputs on "
              "(docs/wear.md, \"Per run\")", "model", default=OPTIONAL,
              models={name: Schema(f"wear {name}", ()) for name in WEAR_LAWS}, selector="law"),
    ),
    "Settings of one run (`base.run` of a study; `railexu run` options). The speed is "
    "constant, or follows `speed_profile` (below), or is free with `traction_torque` or "
    "`brake_force`.",
    extra_keys=("speed_profile",),  # a table: read by read_speed_profile
)  # fmt: skip
#: Keys of the traction and braking demands (free forward motion, docs/traction-and-braking.md).
TRACTION_KEYS = ("traction_torque", "brake_force", "driven_wheelsets", "time_limit")
#: Keys that may hold a table (read by run_settings_from_dict itself).
_TABLE_KEYS = ("traction_torque", "brake_force")
#: Keys read by run_settings_from_dict itself (tables, the wear law's mapping).
_OWN_KEYS = (*_TABLE_KEYS, "wear")

#: The keys of a run-settings mapping (study ``run.*`` parameters).
RUN_KEYS = RUN_SCHEMA.keys()
_D = RUN_SCHEMA.default


@dataclass(frozen=True)
class RunSettings:
    """Settings of one run (SI units); defaults and ranges from :data:`RUN_SCHEMA`.

    Attributes:
        speed_m_per_s: constant forward speed V.
        distance_m: distance to run.
        initial_lateral_m: lateral offset of the whole vehicle at the start (the seed: 2 mm).
        time_step_s: integration step (default 2 ms; see :func:`check_step_for_speed`).
        output_interval_s: interval of the recorded time series (default: 5 ms or the step).
        solver: ``"generalized_alpha"`` (default) or ``"trapezoidal"``.
        spectral_radius: numerical damping of generalized-alpha (1 = none).
        newton_relative_tolerance: Exudyn's relative Newton tolerance.
        derailment_lift_fraction: a wheel that rises by this fraction of its flange height
            above its starting height has climbed its rail: the run stops as ``derailed``.
        derailment_lateral_m: a wheelset further than this from the track centre has left the
            rails: the run stops as ``derailed``.
        deceleration_m_per_s2: a constant deceleration from ``speed_m_per_s`` (the ramp method
            of the critical speed); the speed must stay positive over ``distance_m``. A special
            case of ``speed_profile``.
        speed_profile: the forward speed along the track (:class:`railexu.operation.speed_profile.
            SpeedProfile`, constant acceleration between its points); it sets
            ``speed_m_per_s`` to its start speed and must cover ``distance_m``.
        traction: traction torque and brake force with the forward motion free
            (:class:`railexu.operation.traction.Traction`, ``docs/traction-and-braking.md``);
            ``speed_m_per_s`` is then the start speed.
        wear_law: after the run, the wear and RCF of every wheel and rail by this law
            (:data:`WEAR_LAWS`) into the run's folder
            (docs/wear.md, "Per run"); None: none. It turns ``contact_outputs`` on (the wear
            is computed from the recorded contact points).
    """

    speed_m_per_s: float = _D("speed")
    distance_m: float = _D("distance")
    initial_lateral_m: float = _D("initial_lateral")
    time_step_s: float = _D("time_step")
    output_interval_s: float | None = _D("output_interval")
    solver: str = _D("solver")
    spectral_radius: float = _D("spectral_radius")
    newton_relative_tolerance: float = _D("newton_tolerance")
    evaluate_from_m: float | None = _D("evaluate_from")
    evaluate_to_m: float | None = _D("evaluate_to")
    contact_outputs: bool = _D("contact_outputs")
    derailment_lift_fraction: float = 0.75
    derailment_lateral_m: float = 0.040
    deceleration_m_per_s2: float = 0.0
    speed_profile: SpeedProfile | None = None
    traction: Traction | None = None
    wear_law: str | None = None

    def __post_init__(self) -> None:
        if self.wear_law is not None:
            if self.wear_law not in WEAR_LAWS:
                _fail("wear", f"must be one of {', '.join(WEAR_LAWS)}, got {self.wear_law!r}")
            # the wear is computed from the recorded contact points
            object.__setattr__(self, "contact_outputs", True)
        if self.speed_profile is not None:
            object.__setattr__(self, "speed_m_per_s", self.speed_profile.start_speed_m_per_s)
        for key, value in (
            ("speed", self.speed_m_per_s),
            ("distance", self.distance_m),
            ("initial_lateral", self.initial_lateral_m),
            ("time_step", self.time_step_s),
            ("spectral_radius", self.spectral_radius),
            ("newton_tolerance", self.newton_relative_tolerance),
        ):
            _check(key, value)
        if self.output_interval_s is not None:
            _check("output_interval", self.output_interval_s)
            if self.output_interval_s < self.time_step_s:
                _fail("output_interval", "must be >= the time step")
        for key, value in (("evaluate_from", self.evaluate_from_m),
                           ("evaluate_to", self.evaluate_to_m)):  # fmt: skip
            if value is not None:
                _check(key, value)
        lo, hi = self.evaluate_from_m, self.evaluate_to_m
        if lo is not None and hi is not None and hi <= lo:
            _fail("evaluate_to", f"must be beyond evaluate_from ({lo:g} m), got {hi:g} m")
        if lo is not None and lo >= self.distance_m:
            _fail("evaluate_from", f"must be within the run's distance ({self.distance_m:g} m)")
        if self.solver not in SOLVERS:
            _fail("solver", f"must be one of {', '.join(SOLVERS)}, got {self.solver!r}")
        if not 0.0 < self.derailment_lift_fraction <= 1.0:
            _fail("derailment_lift_fraction", "must be in (0, 1]")
        self._check_deceleration()
        self._check_profile()
        check_step_for_speed(self.max_speed_m_per_s, self.time_step_s)
        steps = self.duration_s / self.time_step_s
        if steps > MAX_STEPS:
            _fail("distance", f"{self.distance_m:g} m at {self.speed_m_per_s:g} m/s in steps of "
                  f"{self.time_step_s:g} s is {steps:.3g} steps, more than {MAX_STEPS:.3g}: is "
                  "a unit wrong?")  # fmt: skip

    def _check_deceleration(self) -> None:
        a = self.deceleration_m_per_s2
        if a == 0.0:
            return
        if not (math.isfinite(a) and a > 0.0):
            _fail("deceleration", f"must be >= 0 m/s^2, got {a!r}")
        if self.speed_m_per_s**2 - 2.0 * a * self.distance_m <= 0.0:
            _fail("deceleration", "the deceleration stops the vehicle before the end")

    def _check_profile(self) -> None:
        if self.speed_profile is not None:
            if self.deceleration_m_per_s2 != 0.0:
                _fail("speed_profile", "cannot be combined with a deceleration (give one)")
            try:
                self.speed_profile.check_covers(self.distance_m)
            except SpeedProfileError as exc:
                _fail("speed_profile", str(exc))
        if self.traction is not None and (
            self.speed_profile is not None or self.deceleration_m_per_s2 != 0.0
        ):
            _fail("speed_profile", "cannot be combined with traction_torque or brake_force, "
                  "which free the forward motion (nor with a deceleration)")  # fmt: skip

    @property
    def free_motion(self) -> bool:
        """The forward motion is free (traction and braking decide it), not prescribed."""
        return self.traction is not None

    @property
    def speed_varies(self) -> bool:
        """The forward speed changes during the run (a profile, a ramp, free motion)."""
        return self.free_motion or self.deceleration_m_per_s2 != 0.0 or (
            self.speed_profile is not None and len(self.speed_profile.points) > 1
        )  # fmt: skip

    @property
    def motion(self) -> SpeedProfile:
        """The prescribed forward motion (for free motion: the start speed, held; the achieved
        motion comes from the simulation)."""
        if self.speed_profile is not None:
            return self.speed_profile
        if self.deceleration_m_per_s2 != 0.0:
            return SpeedProfile.ramp(
                self.speed_m_per_s, -self.deceleration_m_per_s2, self.distance_m
            )
        return SpeedProfile.constant(self.speed_m_per_s)

    @property
    def max_speed_m_per_s(self) -> float:
        """Highest prescribed speed (the start speed for free motion) [m/s]."""
        if self.speed_profile is not None:
            return self.speed_profile.max_speed_m_per_s
        return self.speed_m_per_s

    @property
    def duration_s(self) -> float:
        """Duration of the run [s]; for free motion its time limit."""
        if self.traction is not None:
            limit = self.traction.time_limit_s
            return limit if limit is not None else 3.0 * self.distance_m / self.speed_m_per_s
        if self.speed_profile is not None:
            return self.speed_profile.time_at_distance(self.distance_m)
        a = self.deceleration_m_per_s2
        if a == 0.0:
            return self.distance_m / self.speed_m_per_s
        v_end = math.sqrt(self.speed_m_per_s**2 - 2.0 * a * self.distance_m)
        return (self.speed_m_per_s - v_end) / a

    def speed_at(self, t: float) -> float:
        """Prescribed forward speed at time ``t`` [m/s] (free motion: the start speed)."""
        if self.speed_profile is not None:
            return self.speed_profile.speed_at(t)
        if self.traction is not None:
            return self.speed_m_per_s
        return self.speed_m_per_s - self.deceleration_m_per_s2 * t

    def distance_at(self, t: float) -> float:
        """Prescribed distance run at time ``t`` [m] (free motion: at the start speed)."""
        if self.speed_profile is not None:
            return self.speed_profile.distance_at(t)
        if self.traction is not None:
            return self.speed_m_per_s * t
        return self.speed_m_per_s * t - 0.5 * self.deceleration_m_per_s2 * t * t

    def acceleration_at(self, t: float) -> float:
        """Prescribed forward acceleration at time ``t`` [m/s^2] (free motion: 0)."""
        if self.speed_profile is not None:
            return self.speed_profile.acceleration_at(t)
        if self.traction is not None:
            return 0.0
        return -self.deceleration_m_per_s2

    @property
    def output_every(self) -> int:
        interval = self.output_interval_s or max(self.time_step_s, 0.005)
        return max(1, int(round(interval / self.time_step_s)))


def _fail(key: str, message: str) -> None:
    error = RunSettingsError(f"run settings: {key} {message}")
    error.field = key
    raise error


def _check(key: str, value: float) -> None:
    RUN_SCHEMA[key].check(value, lambda m: _fail(key, m))


def max_time_step_s(speed_m_per_s: float) -> float:
    """The largest step at which the vehicle travels at most :data:`MAX_TRAVEL_PER_STEP_M`
    per step [s]."""
    return MAX_TRAVEL_PER_STEP_M / speed_m_per_s


def check_step_for_speed(speed_m_per_s: float, time_step_s: float) -> None:
    """Refuse a step in which the vehicle travels more than :data:`MAX_TRAVEL_PER_STEP_M`.

    Raises:
        RunSettingsError: naming the travel per step and the step the physics needs.
    """
    travel = speed_m_per_s * time_step_s
    if travel > MAX_TRAVEL_PER_STEP_M * (1.0 + 1e-9):
        needed = max_time_step_s(speed_m_per_s)
        _fail(
            "time_step",
            f"{time_step_s * 1e3:g} ms at {speed_m_per_s:g} m/s moves the vehicle {travel:.3g} m "
            f"per step, more than {MAX_TRAVEL_PER_STEP_M:g} m (a tenth of the shortest "
            f"irregularity wavelength, 3 m): use a step of at most {needed * 1e3:.3g} ms",
        )


def run_settings_from_dict(
    data: dict, source: str = "<run settings>", lines: dict | None = None, path: tuple = ()
) -> RunSettings:
    """Run settings from a mapping with units, as study files give them::

        {speed: 10 m/s, distance: 150 m, initial_lateral: 2 mm, time_step: 2 ms}

    Keys and defaults: :data:`RUN_SCHEMA` (``docs/run-settings-format.md``).

    Raises:
        InputError: unknown keys, wrong units, invalid values (naming source, line and key).
    """
    sec = Section(data, source, lines, path, RUN_KEYS)
    values = RUN_SCHEMA.read_all(sec, [k for k in RUN_SCHEMA.by_key if k not in _OWN_KEYS])
    kwargs = dict(
        speed_m_per_s=values["speed"],
        distance_m=values["distance"],
        initial_lateral_m=values["initial_lateral"],
        time_step_s=values["time_step"],
        output_interval_s=values["output_interval"],
        solver=values["solver"],
        spectral_radius=values["spectral_radius"],
        newton_relative_tolerance=values["newton_tolerance"],
        evaluate_from_m=values["evaluate_from"],
        evaluate_to_m=values["evaluate_to"],
        contact_outputs=values["contact_outputs"],
    )
    if data.get("wear") is not None:
        if not isinstance(data["wear"], str | dict):
            sec.fail(f"expected a wear law, one of {', '.join(WEAR_LAWS)} (or {{law: NAME}}), "
                     f"got {data['wear']!r}", key="wear")  # fmt: skip
        kwargs["wear_law"] = RUN_SCHEMA.read(sec, "wear")[0]
        if data.get("contact_outputs") is False:
            sec.fail("is false, but wear needs the contact points: leave it out or set it true "
                     "(wear turns it on)", key="contact_outputs")  # fmt: skip
    elif "wear" in data:
        sec.fail(f"expected a wear law, one of {', '.join(WEAR_LAWS)} (or {{law: NAME}}), "
                 "got nothing", key="wear")  # fmt: skip
    if "speed_profile" in data:
        if "speed" in data:
            sec.fail("give either speed or speed_profile (whose first point is the start "
                     "speed)", key="speed")  # fmt: skip
        kwargs["speed_profile"] = read_speed_profile(sec)
    if any(k in data for k in _TABLE_KEYS):
        kwargs["traction"] = read_traction(sec, values)
    else:
        for key in ("driven_wheelsets", "time_limit"):
            if key in data:
                sec.fail("only used with traction_torque or brake_force (free motion)", key=key)
    try:
        return RunSettings(**kwargs)
    except RunSettingsError as exc:
        key = exc.field if exc.field in RUN_KEYS else None
        sec.fail(str(exc).removeprefix(f"run settings: {exc.field} "), key=key)
        raise  # unreachable


def _pairs(sec: Section, key: str, units: tuple[str, str], names: tuple[str, str]) -> list:
    """A table ``[[x, y], ...]`` (or ``[{names[0]: x, names[1]: y}, ...]``) in SI; a unit of
    ``units[0]`` may be a tuple of choices (the first that fits is the table's basis).
    Returns ``[(x, y), ...]`` and the unit of the first column."""
    raw = sec.data[key]
    if not isinstance(raw, list) or not raw:
        sec.fail(f"expected a list of [{names[0]}, {names[1]}] pairs, e.g. "
                 f"[[0 {units[0][0]}, 10 {units[1]}], [100 {units[0][0]}, 20 {units[1]}]]",
                 key=key)  # fmt: skip
    where = Section({i: None for i in range(len(raw))}, sec.source, sec.lines, (*sec.path, key))
    out = []
    x_unit = None
    for i, item in enumerate(raw):
        if isinstance(item, dict):
            Section(item, sec.source, sec.lines, (*sec.path, key, i), names)
            item = [item.get(names[0]), item.get(names[1])]
        if not isinstance(item, list) or len(item) != 2:
            where.fail(f"expected a pair [{names[0]}, {names[1]}], got {item!r}", key=i)
        choices = (x_unit,) if x_unit else units[0]
        x = None
        for unit in choices:
            try:
                x = to_si(item[0], unit)
                x_unit = unit
                break
            except UnitError as exc:
                problem = str(exc)
        if x is None:
            where.fail(f"{names[0]}: {problem}", key=i)
        try:
            y = to_si(item[1], units[1])
        except UnitError as exc:
            where.fail(f"{names[1]}: {exc}", key=i)
        out.append((x, y))
    return out, x_unit


def read_speed_profile(sec: Section, key: str = "speed_profile") -> SpeedProfile:
    """The ``speed_profile`` of a run-settings mapping: ``[[0 m, 10 m/s], [200 m, 20 m/s]]``
    or ``[{distance: 0 m, speed: 10 m/s}, ...]``; constant acceleration between the points.

    Raises:
        InputError: naming the key (and the point) at fault.
    """
    pairs, _ = _pairs(sec, key, (("m",), "m/s"), ("distance", "speed"))
    try:
        return SpeedProfile(tuple(pairs))
    except SpeedProfileError as exc:
        sec.fail(str(exc), key=key)
        raise  # unreachable


def _schedule(sec: Section, key: str, unit: str) -> Schedule:
    """A constant (``20 kN m``) or a table over time or distance (``[[0 s, 0 N m], [5 s,
    20 kN m]]``: the first column's unit, s or m, says which)."""
    raw = sec.data[key]
    if not isinstance(raw, list):
        return Schedule.constant(sec.quantity(key, unit))
    pairs, x_unit = _pairs(sec, key, (("s", "m"), unit), ("time or distance", "value"))
    basis = next(b for b, u in BASES.items() if u == x_unit)
    try:
        return Schedule(tuple(pairs), basis)
    except TractionError as exc:
        sec.fail(str(exc), key=key)
        raise  # unreachable


def read_traction(sec: Section, values: dict) -> Traction:
    """The traction and braking demands of a run-settings mapping (free forward motion,
    docs/traction-and-braking.md)::

        {traction_torque: 20 kN m, driven_wheelsets: [ws1, ws2], brake_force: 0 N}

    ``values``: the other keys, read.

    Raises:
        InputError: naming the key at fault.
    """
    kwargs = {
        "wheelsets": values["driven_wheelsets"],
        "time_limit_s": values["time_limit"],
    }
    for key, name, unit in (("traction_torque", "torque_N_m", "N m"),
                            ("brake_force", "brake_force_N", "N")):  # fmt: skip
        if key in sec.data:
            kwargs[name] = _schedule(sec, key, unit)
    try:
        return Traction(**kwargs)
    except TractionError as exc:
        field, _, message = str(exc).partition(": ")
        sec.fail(message, key=field if field in TRACTION_KEYS else None)
        raise  # unreachable


def speed_profile_from_csv(path) -> SpeedProfile:
    """A speed profile from a CSV file of ``distance, speed`` rows (``railexu run
    --speed-profile``): bare numbers are SI (m, m/s), a cell may carry its unit (``0.5 km``,
    ``72 km/h``); a first row that is not a number (a header) and lines starting with ``#`` are
    skipped.

    Raises:
        InputError: naming the file and line of a bad row, or what is wrong with the profile.
    """
    from pathlib import Path

    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot read the speed profile: {exc.strerror}", source=source) from None
    points = []
    for number, line in enumerate(text.splitlines(), start=1):
        cells = [c.strip() for c in line.split(",")]
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        if len(cells) != 2:
            raise InputError(f"expected two columns, distance and speed, got {line!r}",
                             source=source, line=number)  # fmt: skip
        try:
            points.append((to_si(cells[0], "m"), to_si(cells[1], "m/s")))
        except UnitError as exc:
            if not points and number == _first_content_line(text):
                continue  # a header
            raise InputError(str(exc), source=source, line=number) from None
    try:
        return SpeedProfile(tuple(points))
    except SpeedProfileError as exc:
        raise InputError(str(exc), source=source, key="speed_profile") from None


def _first_content_line(text: str) -> int:
    for number, line in enumerate(text.splitlines(), start=1):
        if line.strip() and not line.lstrip().startswith("#"):
            return number
    return 0
