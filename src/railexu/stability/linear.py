"""Linear critical speed: the vehicle linearised about centred running, every named lateral mode
followed over speed (wheelset and bogie hunting, car-body lateral, yaw and roll), each with the
speed where its damping ratio crosses zero."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from railexu.contact.conicity import equivalent_conicity
from railexu.contact.evaluation import ContactParameters, WheelsetContactModel
from railexu.contact.placement import symmetric_wheelset
from railexu.model.assembly import VehicleModel, wheelset_geometry
from railexu.stability.settings import CriticalSpeedSettings
from railexu.track.track import Track, ideal_straight_track
from railexu.vehicle.vehicle import Vehicle


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
