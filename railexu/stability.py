"""Critical speed: linear eigenvalues, nonlinear bisection, and the ramp method.

Above its critical speed a railway vehicle hunts: a self-excited lateral oscillation of its
wheelsets and bogies. Three ways to find it (``docs/assessment.md`` and ``docs/validation.md``):

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

from .assessment.signals import amplitude
from .contact.conicity import equivalent_conicity
from .contact.evaluation import ContactParameters, WheelsetContactModel
from .contact.placement import symmetric_wheelset
from .model import VehicleModel, wheelset_geometry
from .simulation import RunSettings, run
from .track import Track, ideal_straight_track
from .vehicle import Vehicle

METHODS = ("linear", "bisection", "ramp")
LINEARIZATIONS = ("equivalent_conicity", "profiles")


class StabilityError(ValueError):
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


#: The names of the lateral modes the linear analysis follows (participation decides).
MODE_NAMES = ("wheelset hunting", "bogie hunting", "car-body lateral", "car-body yaw",
              "car-body roll")  # fmt: skip
HUNTING_MODES = ("wheelset hunting", "bogie hunting")
#: Oscillatory modes between these frequencies (Hz) are followed.
MODE_FREQUENCY_HZ = (0.05, 30.0)
#: A mode is followed when this share of its kinetic energy is in the lateral plane (lateral
#: displacement, yaw and roll of the bodies and wheelsets).
LATERAL_ENERGY_SHARE = 0.5


@dataclass
class Mode:
    """One eigenvalue of the linearised vehicle with its name and participation."""

    eigenvalue: complex
    name: str
    shares: dict

    @property
    def frequency_Hz(self) -> float:
        return self.eigenvalue.imag / (2.0 * math.pi)

    @property
    def damping_ratio(self) -> float:
        return -self.eigenvalue.real / abs(self.eigenvalue)


def body_roles(vehicle: Vehicle) -> dict[str, str]:
    """``"wheelset"``, ``"bogie"`` or ``"car_body"`` for every body and wheelset, from the
    suspension's topology: a body joined to a wheelset and to another body is a bogie frame, and
    so is a body joined to wheelsets only whose name says ``bogie`` or ``frame`` (a bogie
    alone); any other body (joined to bogies only, or the body of a two-axle vehicle) is a car
    body."""
    wheelsets = {w.name for w in vehicle.wheelsets}
    bodies = {b.name for b in vehicle.bodies}
    to_wheelset = {n: False for n in bodies}
    to_body = {n: False for n in bodies}
    for el in vehicle.suspension:
        a, b = el.bodies
        for one, other in ((a, b), (b, a)):
            if one in bodies:
                to_wheelset[one] |= other in wheelsets
                to_body[one] |= other in bodies
    roles = {w: "wheelset" for w in wheelsets}
    for n in bodies:
        frame_name = any(word in n.lower() for word in ("bogie", "frame"))
        bogie = to_wheelset[n] and (to_body[n] or frame_name)
        roles[n] = "bogie" if bogie else "car_body"
    return roles


def _coordinate_groups(model: VehicleModel) -> dict[str, list[int]]:
    """Indices of the model's coordinates by ``role:motion`` (motion: lateral, yaw, roll,
    other). Wheelset coordinates are (x, y, z, roll, -yaw, spin), body coordinates (x, y, z,
    roll, pitch, yaw)."""
    roles = body_roles(model.vehicle)
    groups: dict[str, list[int]] = {}
    for name, idx in model.ltg.items():
        role = roles.get(name, "car_body")
        yaw = 4 if role == "wheelset" else 5
        for j, i in enumerate(idx):
            motion = {1: "lateral", 3: "roll", yaw: "yaw"}.get(j, "other")
            groups.setdefault(f"{role}:{motion}", []).append(int(i))
    return groups


def name_mode(shares: dict) -> str | None:
    """The name of a mode from the shares of its kinetic energy (``role:motion`` -> share):
    None when less than half of it is lateral (lateral, yaw, roll); hunting when the wheelsets'
    and bogie frames' lateral and yaw motion holds at least half of the lateral part (bogie
    hunting when the frames hold more of it than the wheelsets); else the car body's largest
    motion (lateral, yaw or roll)."""
    lateral = {k: v for k, v in shares.items() if not k.endswith(":other")}
    total_lateral = sum(lateral.values())
    if total_lateral < LATERAL_ENERGY_SHARE:
        return None
    wheelsets = shares.get("wheelset:lateral", 0.0) + shares.get("wheelset:yaw", 0.0)
    bogies = shares.get("bogie:lateral", 0.0) + shares.get("bogie:yaw", 0.0)
    if wheelsets + bogies >= 0.5 * total_lateral:
        return "bogie hunting" if bogies > wheelsets else "wheelset hunting"
    body = {m: shares.get(f"car_body:{m}", 0.0) for m in ("lateral", "yaw", "roll")}
    return f"car-body {max(body, key=body.get)}"


def lateral_modes(model: VehicleModel) -> list[Mode]:
    """The named oscillatory lateral modes of the linearised vehicle (positive frequencies).

    The system ``M q'' + D q' + K q = 0`` from Exudyn's ``ComputeLinearizedSystem`` (about the
    model's initial state: centred, running at its speed) is written in first-order form. Each
    mode's participation is the share of its kinetic energy ``M_ii |v_i|^2`` (``v = lambda
    x``, the velocity part of the eigenvector) in each group of coordinates (body role and
    motion); :func:`name_mode` names it."""
    M, K, D = (np.asarray(m) for m in model.mbs.ComputeLinearizedSystem())
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    values, vectors = np.linalg.eig(A)
    mass = np.abs(np.diag(M))
    groups = _coordinate_groups(model)
    modes = []
    for lam, vec in zip(values, vectors.T, strict=True):
        f = lam.imag / (2.0 * math.pi)
        if not MODE_FREQUENCY_HZ[0] < f < MODE_FREQUENCY_HZ[1]:
            continue
        energy = mass * np.abs(vec[n:]) ** 2
        total = float(np.sum(energy))
        if total == 0.0:
            continue
        shares = {g: float(np.sum(energy[idx]) / total) for g, idx in groups.items()}
        name = name_mode(shares)
        if name is not None:
            modes.append(Mode(complex(lam), name, shares))
    return modes


def _least_damped(modes: list[Mode]) -> dict[str, Mode]:
    """The least damped mode of each name."""
    out: dict[str, Mode] = {}
    for m in modes:
        if m.name not in out or m.damping_ratio < out[m.name].damping_ratio:
            out[m.name] = m
    return out


def _crossing(speeds, zeta, point, tolerance: float) -> float | None:
    """The lowest speed where ``zeta`` goes from positive to zero or below, refined by secant
    steps on ``point(speed) -> damping ratio``."""
    for i in range(len(speeds) - 1):
        z_lo, z_hi = zeta[i], zeta[i + 1]
        if not (math.isfinite(z_lo) and math.isfinite(z_hi) and z_lo > 0.0 >= z_hi):
            continue
        lo, hi = speeds[i], speeds[i + 1]
        for _ in range(8):
            mid = lo + (hi - lo) * z_lo / (z_lo - z_hi)
            mid = min(max(mid, lo + 0.05 * (hi - lo)), hi - 0.05 * (hi - lo))
            z_mid = point(mid)
            if not math.isfinite(z_mid):
                break
            if z_mid > 0.0:
                lo, z_lo = mid, z_mid
            else:
                hi, z_hi = mid, z_mid
            if hi - lo < 0.01 * tolerance:
                break
        return lo + (hi - lo) * z_lo / (z_lo - z_hi)
    return None


def linear_stability(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Follow every named lateral mode over speed; find where each one's damping crosses zero.

    At each speed the linearised vehicle's oscillatory lateral modes are named by their
    participation (:func:`name_mode`: wheelset hunting, bogie hunting, car-body lateral, yaw,
    roll); each name is followed by its least damped mode. Returns a dict with:

    - ``critical_speed_m_per_s``: the lowest speed at which any named mode's damping ratio
      crosses zero, and ``critical_mode`` its name (None when no mode crosses in the range);
    - ``modes``: per name ``critical_speed_m_per_s``, ``damping_ratio`` and ``frequency_Hz`` at
      every speed (None where the mode was not found), ``stable_in_range``,
      ``unstable_in_range``;
    - ``hunting_critical_speed_m_per_s``: the lowest crossing of a hunting mode;
    - ``speeds_m_per_s``, ``frequency_Hz``, ``damping_ratio``: the least damped hunting mode at
      each speed (as before the modes were named); ``stable_in_range``/``unstable_in_range`` of
      it;
    - ``root_locus``: every named mode at every speed as ``[speed, frequency, damping, name]``;
    - the equivalent conicity used and the cone slope.
    """
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    lin_vehicle, lin_track, info = linear_model_vehicle(vehicle, track, settings)
    cache: dict[float, list[Mode]] = {}

    def modes_at(speed: float) -> list[Mode]:
        if speed not in cache:
            cache[speed] = lateral_modes(VehicleModel(lin_vehicle, lin_track, speed, 0.0, 10.0))
        return cache[speed]

    grid = np.linspace(
        settings.speed_min_m_per_s, settings.speed_max_m_per_s, settings.linear_points
    )
    speeds = [float(v) for v in grid]
    table: list[dict[str, Mode]] = []
    for v in speeds:
        table.append(_least_damped(modes_at(v)))
        if progress:
            text = ", ".join(f"{k} {m.damping_ratio:+.3f}" for k, m in sorted(table[-1].items()))
            progress(f"linear: {v:.1f} m/s, damping ratio {text}")
    modes_out: dict[str, dict] = {}
    for name in MODE_NAMES:
        zeta = [row[name].damping_ratio if name in row else math.nan for row in table]
        if all(math.isnan(z) for z in zeta):
            continue

        def zeta_of(v: float, name: str = name) -> float:
            m = _least_damped(modes_at(v)).get(name)
            return m.damping_ratio if m else math.nan

        finite = [z for z in zeta if math.isfinite(z)]
        modes_out[name] = {
            "critical_speed_m_per_s": _crossing(speeds, zeta, zeta_of, settings.tolerance_m_per_s),
            "damping_ratio": zeta,
            "frequency_Hz": [row[name].frequency_Hz if name in row else math.nan for row in table],
            "stable_in_range": bool(finite and all(z > 0.0 for z in finite)),
            "unstable_in_range": bool(finite and all(z <= 0.0 for z in finite)),
        }
    crossings = {k: m["critical_speed_m_per_s"] for k, m in modes_out.items()
                 if m["critical_speed_m_per_s"] is not None}  # fmt: skip
    critical_mode = min(crossings, key=crossings.get) if crossings else None
    hunting = [min((row[k] for k in HUNTING_MODES if k in row), key=lambda m: m.damping_ratio,
                   default=None) for row in table]  # fmt: skip
    h_zeta = np.array([m.damping_ratio if m else math.nan for m in hunting])
    h_finite = h_zeta[np.isfinite(h_zeta)]
    h_cross = [crossings[k] for k in HUNTING_MODES if k in crossings]
    return {
        "critical_speed_m_per_s": crossings.get(critical_mode) if critical_mode else None,
        "critical_mode": critical_mode,
        "hunting_critical_speed_m_per_s": min(h_cross) if h_cross else None,
        "modes": modes_out,
        "stable_in_range": bool(h_finite.size and np.all(h_finite > 0.0)),
        "unstable_in_range": bool(h_finite.size and np.all(h_finite <= 0.0)),
        "speeds_m_per_s": speeds,
        "frequency_Hz": [m.frequency_Hz if m else math.nan for m in hunting],
        "damping_ratio": h_zeta.tolist(),
        "root_locus": [
            [v, m.frequency_Hz, m.damping_ratio, m.name] for v in speeds for m in modes_at(v)
        ],  # fmt: skip
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
        a_last = max(a_last, amplitude(y[last]))
        a_before = max(a_before, amplitude(y[before]))
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
    """The amplitude (:func:`~railexu.assessment.signals.amplitude`, half peak to peak) of each
    full period that ends at a sign change of ``y - mean``, and the speed at its end: one value
    per half period, each over the last full period."""
    centred = y - np.mean(y)
    sign = np.signbit(centred)
    cuts = np.nonzero(sign[1:] != sign[:-1])[0] + 1
    edges = np.concatenate([[0], cuts, [len(y)]])
    amps, speeds = [], []
    for i0, i1 in zip(edges[:-2], edges[2:], strict=True):
        if i1 - i0 < 3:
            continue
        amps.append(amplitude(y[i0:i1]))
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
        out["linear_mode"] = out["linear"]["critical_mode"]
    if "bisection" in settings.methods:
        out["bisection"] = bisection_critical_speed(vehicle, track, settings, progress)
        out["nonlinear_bisection_m_per_s"] = out["bisection"]["critical_speed_m_per_s"]
    if "ramp" in settings.methods:
        out["ramp"] = ramp_critical_speed(vehicle, track, settings, progress)
        out["nonlinear_ramp_m_per_s"] = out["ramp"]["critical_speed_m_per_s"]
    out["comparison"] = compare_linear_nonlinear(out, settings)
    return out


#: Linear and nonlinear critical speeds that differ by more than this fraction get an
#: explanation in words.
COMPARISON_TOLERANCE = 0.25


def compare_linear_nonlinear(result: dict, settings: CriticalSpeedSettings) -> str | None:
    """Why the linear and a nonlinear critical speed differ by more than 25 %, in words (None
    when they agree, or when one of them is missing).

    The reasons, in the order they are checked: the linear value belongs to a car-body mode
    (weakly damped, a motion of the car body on its secondary suspension: the wheelsets'
    amplitude, which the nonlinear runs judge, stays below the threshold within the run); the
    nonlinear value is the lower one (a subcritical bifurcation: the wheel-rail contact's
    nonlinearity lets a large disturbance settle into a limit cycle below the linear value); the
    nonlinear value is the higher one (the linearisation's equivalent conicity, taken at one
    amplitude, is larger than what the run's small motion sees, or the motion grows too slowly
    to reach the threshold within the distance run)."""
    linear = result.get("linear_m_per_s")
    nonlinear = {k: result.get(f"nonlinear_{k}_m_per_s") for k in ("bisection", "ramp")}
    nonlinear = {k: v for k, v in nonlinear.items() if v is not None}
    if linear is None or not nonlinear:
        return None
    method, value = min(nonlinear.items(), key=lambda kv: abs(kv[1] - linear))
    if abs(value - linear) <= COMPARISON_TOLERANCE * value:
        return None
    lin = result.get("linear") or {}
    mode = lin.get("critical_mode") or "hunting"
    gap = abs(value - linear) / value
    head = (
        f"The linear critical speed ({linear:.1f} m/s, {mode} mode) and the nonlinear one "
        f"({method}, {value:.1f} m/s) differ by {gap:.0%}: "
    )
    if mode not in HUNTING_MODES:
        hunting = lin.get("hunting_critical_speed_m_per_s")
        tail = " No hunting mode crosses zero in the range."
        if hunting is not None:
            tail = f" The hunting modes' damping crosses zero at {hunting:.1f} m/s."
        return head + (
            f"the linear value belongs to the weakly damped {mode} mode, a motion of the car body "
            "on its secondary suspension. It grows slowly and moves the wheelsets little, so in "
            f"the nonlinear runs the wheelsets' amplitude stays below the "
            f"{settings.threshold_m * 1e3:g} mm threshold within {settings.distance_m:g} m." + tail
        )
    if value < linear:
        return head + (
            "the nonlinear value is lower: a subcritical bifurcation. The wheel-rail contact is "
            "nonlinear (the conicity grows with the amplitude towards the flange), so a "
            f"disturbance of {settings.initial_lateral_m * 1e3:g} mm settles into a limit cycle "
            "below the speed at which small motions become unstable; the ramp method shows "
            "where that limit cycle vanishes."
        )
    return head + (
        "the nonlinear value is higher: the linear analysis uses the equivalent conicity at "
        f"{settings.conicity_amplitude_m * 1e3:g} mm, larger than the conicity the run's small "
        "motion sees near the centre, or the motion grows too slowly to reach the "
        f"{settings.threshold_m * 1e3:g} mm threshold within {settings.distance_m:g} m."
    )


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
