"""Critical speed: linear eigenvalues, nonlinear bisection, and the ramp method.

Above its critical speed a railway vehicle hunts: a self-excited lateral oscillation of its
wheelsets and bogies. Three ways to find it (physics.md section 7):

- **linear** (:func:`linear_stability`): linearise the vehicle about centred running at a speed
  with Exudyn (``ComputeLinearizedSystem``: stiffness, damping and mass matrices, the creep
  damping included through the contact force's numerical Jacobian) and follow the least damped
  lateral eigenvalue over speed; the critical speed is where its damping ratio crosses zero. As
  the classical linear analysis does, the wheel profiles are replaced by cones with the
  *equivalent conicity* of the profile pair (EN 15302, harmonic linearisation at a given
  amplitude, 3 mm by default), and creep follows Kalker's linear theory. (``linearization =
  "profiles"`` linearises the real profile contact instead, whose slope at the centre can be far
  from the equivalent conicity.)
- **nonlinear bisection** (:func:`bisection_critical_speed`): runs of the full model after a
  lateral disturbance (an initial lateral offset of the whole vehicle); a run is *unstable*
  when the lateral motion of a wheelset over the last 10 % of the distance still exceeds a
  threshold amplitude (3 mm by default) or grows; bisection between a stable and an unstable
  speed. Deterministic: the same inputs give the same speed.
- **ramp** (:func:`ramp_critical_speed`): start above the critical speed from a disturbance,
  let the hunting settle, then decelerate slowly; the speed at which the limit cycle vanishes
  (its amplitude falls below the threshold for good) is the nonlinear critical speed from
  above, which is lower than the linear one where the bifurcation is subcritical.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, replace

import numpy as np

from .contact.conicity import equivalent_conicity
from .contact.evaluation import ContactParameters, WheelsetContactModel
from .contact.placement import symmetric_wheelset
from .errors import InputError
from .model import VehicleModel, wheelset_geometry
from .simulation import RunSettings, run
from .track import Track, ideal_straight_track
from .vehicle import Vehicle

METHODS = ("linear", "bisection", "ramp")
LINEARIZATIONS = ("equivalent_conicity", "profiles")


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
        ramp_deceleration_m_per_s2: deceleration of the ramp.
        ramp_settle_m: distance run at the top speed before the ramp starts.
        time_step_s: integration step of the nonlinear runs.
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
    ramp_deceleration_m_per_s2: float = 0.5
    ramp_settle_m: float = 200.0
    time_step_s: float = 0.002

    def __post_init__(self) -> None:
        for m in self.methods:
            if m not in METHODS:
                raise StabilityError(f"unknown method {m!r}; expected some of {', '.join(METHODS)}")
        if self.linearization not in LINEARIZATIONS:
            raise StabilityError(
                f"linearization {self.linearization!r}: expected one of {', '.join(LINEARIZATIONS)}"
            )
        if not 0.0 < self.speed_min_m_per_s < self.speed_max_m_per_s:
            raise StabilityError("need 0 < speed_min < speed_max")
        if not self.tolerance_m_per_s > 0.0:
            raise StabilityError("tolerance must be > 0 m/s")
        if not self.threshold_m > 0.0:
            raise StabilityError("threshold must be > 0 m")
        if self.linear_points < 2:
            raise StabilityError("linear_points must be >= 2")


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
    "time_step",
)


def critical_speed_settings_from_dict(
    data: dict, source: str = "<critical speed>", lines: dict | None = None, path: tuple = ()
) -> CriticalSpeedSettings:
    """Settings from a mapping with units (study files, ``critical_speed:`` section)::

        {methods: [linear, bisection], speed_min: 20 m/s, speed_max: 80 m/s, tolerance: 2 m/s}

    Raises:
        InputError: unknown keys, wrong units or values, naming source, line and key.
    """
    from .inputs import Section

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
        time_step_s=sec.quantity("time_step", "s", default=d.time_step_s, positive=True),
    )
    try:
        return CriticalSpeedSettings(**kwargs)
    except StabilityError as exc:
        sec.fail(str(exc))
        raise  # unreachable


# ---------------------------------------------------------------------------------------------
# Linear analysis
# ---------------------------------------------------------------------------------------------


def profile_equivalent_conicity(vehicle: Vehicle, track: Track, amplitude_m: float) -> float:
    """Equivalent conicity of the first wheelset's profiles on the track's rails (EN 15302,
    harmonic linearisation) at ``amplitude_m``."""
    geometry = wheelset_geometry(vehicle.wheelsets[0], track)
    model = WheelsetContactModel(geometry, vehicle.contact, 10.0)
    return float(equivalent_conicity(model, [amplitude_m], step_m=1e-4)[0][0])


def _cone_for_conicity(vehicle: Vehicle, track: Track, target: float, amplitude: float) -> float:
    """Slope of the cone whose equivalent conicity on the track's rails equals ``target``: a cone
    on a curved rail head rolls with a slightly larger effective conicity than its slope (the
    roll of the wheelset moves the contact across the head)."""
    from scipy.optimize import brentq

    ws = vehicle.wheelsets[0]

    def mismatch(slope: float) -> float:
        geometry = symmetric_wheelset(
            f"cone:{slope!r}",
            track.rail_profile,
            nominal_radius_m=ws.nominal_radius_m,
            inclination="none",
            gauge_m=track.gauge_m,
            flange_back_distance_m=ws.flange_back_distance_m,
        )
        model = WheelsetContactModel(geometry, vehicle.contact, 10.0)
        return float(equivalent_conicity(model, [amplitude], step_m=2.5e-4)[0][0]) - target

    lo, hi = 0.3 * target, 1.2 * target
    return float(brentq(mismatch, lo, hi, xtol=1e-5 * target))


def linear_model_vehicle(vehicle: Vehicle, track: Track, settings: CriticalSpeedSettings):
    """The vehicle and track of the linear analysis: cones of the equivalent conicity on the
    track's rail (upright, so that the cone's slope is the track-frame slope) and Kalker's linear
    creep law. Returns ``(vehicle, track, info)``."""
    gamma = profile_equivalent_conicity(vehicle, track, settings.conicity_amplitude_m)
    if settings.linearization == "profiles":
        lin = replace(vehicle, contact=replace(vehicle.contact, creep_model="kalker_linear"))
        return lin, track, {"equivalent_conicity": gamma, "cone_slope": None}
    slope = _cone_for_conicity(vehicle, track, gamma, settings.conicity_amplitude_m)
    wheelsets = tuple(replace(w, wheel_profile=f"cone:{slope!r}") for w in vehicle.wheelsets)
    contact: ContactParameters = replace(vehicle.contact, creep_model="kalker_linear")
    lin = replace(vehicle, wheelsets=wheelsets, contact=contact)
    lin_track = replace(track, inclination="none")
    return lin, lin_track, {"equivalent_conicity": gamma, "cone_slope": slope}


@dataclass
class LinearPoint:
    """Least damped lateral eigenvalue at one speed."""

    speed_m_per_s: float
    frequency_Hz: float
    damping_ratio: float
    real_part_per_s: float


def lateral_eigenvalues(model: VehicleModel) -> list[tuple[complex, float, float]]:
    """Eigenvalues of the linearised vehicle with their lateral and wheelset participation.

    The system ``M q'' + D q' + K q = 0`` from Exudyn's ``ComputeLinearizedSystem`` (about the
    model's initial state: centred, running at its speed) is written in first-order form. For each
    mode: the share of the lateral and yaw coordinates in its displacement part, and the share of
    the wheelsets' lateral and yaw coordinates (hunting is a motion of the wheelsets; car body
    modes have little of it).
    """
    M, K, D = (np.asarray(m) for m in model.mbs.ComputeLinearizedSystem())
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ D]])
    values, vectors = np.linalg.eig(A)
    lateral = np.zeros(n, dtype=bool)
    wheelset = np.zeros(n, dtype=bool)
    wheelsets = {w.name for w in model.vehicle.wheelsets}
    for name, idx in model.ltg.items():
        is_ws = name in wheelsets
        for j in (1, 4 if is_ws else 5):  # y, and yaw (wheelset: -theta1, body: theta2)
            lateral[idx[j]] = True
            wheelset[idx[j]] = is_ws
    out = []
    for lam, vec in zip(values, vectors.T, strict=True):
        x = np.abs(vec[:n])
        total = float(np.sum(x))
        if total == 0.0:
            continue
        out.append((complex(lam), float(np.sum(x[lateral]) / total),
                    float(np.sum(x[wheelset]) / total)))  # fmt: skip
    return out


def _hunting_mode(eigen: list[tuple[complex, float, float]]) -> tuple[complex, float] | None:
    """The hunting mode: the least damped oscillatory mode (0.05 to 30 Hz) that is mainly lateral
    (share > 1/2) with a substantial part of wheelset motion (share > 1/4)."""
    best = None
    for lam, lat, ws in eigen:
        f = lam.imag / (2.0 * math.pi)
        if lat < 0.5 or ws < 0.25 or not 0.05 < f < 30.0:
            continue
        zeta = -lam.real / abs(lam)
        if best is None or zeta < best[2]:
            best = (lam, lat, zeta)
    return None if best is None else (best[0], best[1])


def linear_stability(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Follow the least damped lateral eigenvalue over speed; find where it crosses zero.

    Returns a dict with ``speeds_m_per_s``, ``frequency_Hz``, ``damping_ratio``,
    ``critical_speed_m_per_s`` (None when the damping ratio keeps one sign over the range:
    ``stable_in_range`` or ``unstable_in_range`` says which), the equivalent conicity used and
    the cone slope.
    """
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    lin_vehicle, lin_track, info = linear_model_vehicle(vehicle, track, settings)

    def point(speed: float) -> LinearPoint:
        model = VehicleModel(lin_vehicle, lin_track, speed, 0.0, 10.0)
        mode = _hunting_mode(lateral_eigenvalues(model))
        if mode is None:
            return LinearPoint(speed, math.nan, math.nan, math.nan)
        lam = mode[0]
        return LinearPoint(speed, lam.imag / (2 * math.pi), -lam.real / abs(lam), lam.real)

    speeds = np.linspace(settings.speed_min_m_per_s, settings.speed_max_m_per_s,
                         settings.linear_points)  # fmt: skip
    points = []
    for v in speeds:
        points.append(point(float(v)))
        if progress:
            progress(f"linear: {v:.1f} m/s, damping ratio {points[-1].damping_ratio:+.4f}")
    zeta = np.array([p.damping_ratio for p in points])
    critical = None
    for i in range(len(points) - 1):
        if zeta[i] > 0.0 >= zeta[i + 1]:
            # refine the crossing by bisection on the damping ratio (secant start)
            lo, hi = points[i].speed_m_per_s, points[i + 1].speed_m_per_s
            z_lo, z_hi = zeta[i], zeta[i + 1]
            for _ in range(8):
                mid = lo + (hi - lo) * z_lo / (z_lo - z_hi)
                mid = min(max(mid, lo + 0.05 * (hi - lo)), hi - 0.05 * (hi - lo))
                z_mid = point(mid).damping_ratio
                if z_mid > 0.0:
                    lo, z_lo = mid, z_mid
                else:
                    hi, z_hi = mid, z_mid
                if hi - lo < 0.01 * settings.tolerance_m_per_s:
                    break
            critical = lo + (hi - lo) * z_lo / (z_lo - z_hi)
            break
    finite = zeta[np.isfinite(zeta)]
    return {
        "critical_speed_m_per_s": critical,
        "stable_in_range": bool(finite.size and np.all(finite > 0.0)),
        "unstable_in_range": bool(finite.size and np.all(finite <= 0.0)),
        "speeds_m_per_s": [p.speed_m_per_s for p in points],
        "frequency_Hz": [p.frequency_Hz for p in points],
        "damping_ratio": [p.damping_ratio for p in points],
        "linearization": settings.linearization,
        "equivalent_conicity": info["equivalent_conicity"],
        "conicity_amplitude_m": settings.conicity_amplitude_m,
        "cone_slope": info["cone_slope"],
        "creep_model": "kalker_linear",
    }


# ---------------------------------------------------------------------------------------------
# Nonlinear methods
# ---------------------------------------------------------------------------------------------


def _lateral_amplitude(ts, fraction: float = 0.1) -> tuple[float, float, bool]:
    """Largest half peak-to-peak lateral motion of any wheelset over the last ``fraction`` of the
    distance, the same over the ``fraction`` before it, and whether the motion grows."""
    x = ts.distance_m
    end = x[-1]
    span = fraction * (end - x[0])
    last = x >= end - span
    before = (x >= end - 2 * span) & ~last
    a_last = a_before = 0.0
    for i in ts.wheelset_indices():
        y = ts[f"ws{i}_lateral_m"]
        if np.any(last):
            a_last = max(a_last, 0.5 * float(np.ptp(y[last])))
        if np.any(before):
            a_before = max(a_before, 0.5 * float(np.ptp(y[before])))
    return a_last, a_before, a_last > 1.05 * a_before


def nonlinear_run_is_stable(
    vehicle: Vehicle, track: Track, speed: float, settings: CriticalSpeedSettings
) -> dict:
    """One run after the lateral disturbance; stable when the lateral motion over the last
    10 % of the distance stays below the threshold and does not grow."""
    result = run(
        vehicle,
        track,
        RunSettings(
            speed_m_per_s=speed,
            distance_m=settings.distance_m,
            initial_lateral_m=settings.initial_lateral_m,
            time_step_s=settings.time_step_s,
            output_interval_s=max(settings.time_step_s, 0.01),
        ),
    )
    state = result.status["state"]
    if state != "completed":
        return {"speed_m_per_s": speed, "stable": False, "amplitude_m": None, "state": state,
                "reason": result.status["reason"]}  # fmt: skip
    amp, before, growing = _lateral_amplitude(result.timeseries)
    stable = amp < settings.threshold_m and not (growing and amp > 0.25 * settings.threshold_m)
    return {
        "speed_m_per_s": speed,
        "stable": bool(stable),
        "amplitude_m": amp,
        "previous_amplitude_m": before,
        "growing": bool(growing),
        "state": state,
    }


def bisection_critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Nonlinear critical speed by bisection between a stable and an unstable run."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    runs = []

    def test(v: float) -> bool:
        r = nonlinear_run_is_stable(vehicle, track, v, settings)
        runs.append(r)
        if progress:
            amp = r["amplitude_m"]
            amp_text = f"{amp * 1e3:.2f} mm" if amp is not None else r["state"]
            progress(f"bisection: {v:.2f} m/s -> {'stable' if r['stable'] else 'unstable'} "
                     f"({amp_text})")  # fmt: skip
        return r["stable"]

    lo, hi = settings.speed_min_m_per_s, settings.speed_max_m_per_s
    out = {
        "critical_speed_m_per_s": None,
        "bracket_m_per_s": None,
        "runs": runs,
        "threshold_m": settings.threshold_m,
        "initial_lateral_m": settings.initial_lateral_m,
    }
    if test(hi):
        out["stable_in_range"] = True
        out["note"] = f"stable up to the highest speed tested, {hi:g} m/s"
        return out
    if not test(lo):
        out["unstable_in_range"] = True
        out["note"] = f"unstable at every speed tested, down to {lo:g} m/s"
        return out
    while hi - lo > settings.tolerance_m_per_s:
        mid = 0.5 * (lo + hi)
        if test(mid):
            lo = mid
        else:
            hi = mid
    out["critical_speed_m_per_s"] = 0.5 * (lo + hi)
    out["bracket_m_per_s"] = [lo, hi]
    return out


def ramp_critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Nonlinear critical speed by the ramp method: settle into hunting at the top speed, then
    decelerate slowly; report the speed at which the limit cycle vanishes.

    The amplitude is taken per half period of the leading wheelset's lateral motion (between
    zero crossings); the critical speed is the speed at the end of the last half period whose
    amplitude exceeds the threshold.
    """
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    v0, v1 = settings.speed_max_m_per_s, settings.speed_min_m_per_s
    a = settings.ramp_deceleration_m_per_s2
    # settle at v0, then decelerate: one run, the deceleration starting after ramp_settle_m is
    # approximated by starting the ramp a little higher (same settle time at v0 + a t/2)
    t_settle = settings.ramp_settle_m / v0
    v_start = v0 + a * t_settle
    distance = (v_start**2 - v1**2) / (2.0 * a)
    if progress:
        progress(f"ramp: {v_start:.1f} -> {v1:.1f} m/s over {distance:.0f} m")
    result = run(
        vehicle,
        track,
        RunSettings(
            speed_m_per_s=v_start,
            distance_m=distance,
            initial_lateral_m=settings.initial_lateral_m,
            time_step_s=settings.time_step_s,
            output_interval_s=max(settings.time_step_s, 0.01),
            deceleration_m_per_s2=a,
        ),
    )
    ts = result.timeseries
    speed = ts["speed_m_per_s"]
    y = ts["ws1_lateral_m"]
    amplitude, at_speed = _half_period_amplitudes(y, speed)
    out = {
        "critical_speed_m_per_s": None,
        "start_speed_m_per_s": v_start,
        "end_speed_m_per_s": v1,
        "deceleration_m_per_s2": a,
        "state": result.status["state"],
        "threshold_m": settings.threshold_m,
        "speeds_m_per_s": at_speed.tolist(),
        "amplitude_m": amplitude.tolist(),
    }
    if result.status["state"] != "completed":
        out["note"] = f"the ramp run stopped: {result.status['reason']}"
        return out
    above = amplitude > settings.threshold_m
    if not np.any(above):
        out["note"] = f"no hunting at the start speed {v_start:g} m/s"
        return out
    if above[-1]:
        out["note"] = f"still hunting at the end of the ramp, {v1:g} m/s"
        out["unstable_in_range"] = True
        return out
    last = int(np.nonzero(above)[0][-1])
    out["critical_speed_m_per_s"] = float(at_speed[last])
    return out


def _half_period_amplitudes(y: np.ndarray, speed: np.ndarray):
    """Largest |y - mean| within each half period (between sign changes) and the speed at its
    end."""
    centred = y - np.mean(y)
    sign = np.signbit(centred)
    cuts = np.nonzero(sign[1:] != sign[:-1])[0] + 1
    edges = np.concatenate([[0], cuts, [len(y)]])
    amps, speeds = [], []
    for i0, i1 in zip(edges[:-1], edges[1:], strict=True):
        if i1 - i0 < 2:
            continue
        amps.append(float(np.max(np.abs(centred[i0:i1]))))
        speeds.append(float(speed[i1 - 1]))
    return np.asarray(amps), np.asarray(speeds)


# ---------------------------------------------------------------------------------------------
# The analysis behind ``railexu critical-speed``
# ---------------------------------------------------------------------------------------------


def critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Critical speed of ``vehicle`` by the chosen methods; returns the content of
    ``critical_speed.json``: ``linear_m_per_s``, ``nonlinear_bisection_m_per_s``,
    ``nonlinear_ramp_m_per_s`` (None where a method was not run or found no crossing in the
    range), one section per method with its details, and the settings used."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    out: dict = {
        "vehicle": vehicle.name,
        "track": track.name,
        "linear_m_per_s": None,
        "nonlinear_bisection_m_per_s": None,
        "nonlinear_ramp_m_per_s": None,
        "settings": asdict(settings),
    }
    if "linear" in settings.methods:
        out["linear"] = linear_stability(vehicle, track, settings, progress)
        out["linear_m_per_s"] = out["linear"]["critical_speed_m_per_s"]
    if "bisection" in settings.methods:
        out["bisection"] = bisection_critical_speed(vehicle, track, settings, progress)
        out["nonlinear_bisection_m_per_s"] = out["bisection"]["critical_speed_m_per_s"]
    if "ramp" in settings.methods:
        out["ramp"] = ramp_critical_speed(vehicle, track, settings, progress)
        out["nonlinear_ramp_m_per_s"] = out["ramp"]["critical_speed_m_per_s"]
    return out


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, float | np.floating):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.integer | np.bool_):
        return obj.item()
    return obj


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
            import difflib

            close = difflib.get_close_matches(m, METHODS, n=1)
            hint = f" Did you mean {close[0]!r}?" if close else ""
            raise StabilityError(f"unknown method {m!r}.{hint} Valid: {', '.join(METHODS)}")
    return methods
