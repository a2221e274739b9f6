"""Linear critical speed: the vehicle linearised about centred running, every lateral mode
followed over speed by its shape (:mod:`railexu.stability.modes`: MAC between neighbouring
speeds), named from where its kinetic and strain energy sit (wheelset and bogie hunting,
car-body lateral, yaw and roll; the bodies by the vehicle's own names), each with the speeds
where its damping ratio crosses zero and the bands in which it is unstable."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from railexu.contact.conicity import equivalent_conicity
from railexu.contact.evaluation import ContactParameters, WheelsetContactModel
from railexu.contact.placement import symmetric_wheelset
from railexu.model.assembly import VehicleModel, wheelset_geometry
from railexu.stability.modes import (
    MAC_MIN,
    label_branches,
    least_damped_table,
    track_branches,
    unstable_bands,
)
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
MODE_NAMES = ("wheelset hunting", "bogie hunting", "wheelset yaw", "bogie yaw",
              "car-body lateral", "car-body yaw", "car-body roll")  # fmt: skip
HUNTING_MODES = ("wheelset hunting", "bogie hunting")
#: How a role is written in a mode's name.
ROLE_WORDS = {"car_body": "car-body", "bogie": "bogie", "wheelset": "wheelset"}
#: Oscillatory modes between these frequencies (Hz) are followed.
MODE_FREQUENCY_HZ = (0.05, 30.0)
#: A mode is followed when this share of its kinetic energy is in the lateral plane (lateral
#: displacement, yaw and roll of the bodies and wheelsets).
LATERAL_ENERGY_SHARE = 0.5


#: Parts of a mode's energy listed with it (the largest first), and the smallest share listed.
ENERGY_PARTS = 4
ENERGY_PART_MIN = 0.05


@dataclass
class Mode:
    """One eigenvalue of the linearised vehicle with its name and participation: ``shares``
    by ``role:motion`` (the mean of the kinetic and the strain energy shares, which name it),
    ``parts`` by ``body motion`` with the vehicle's own names of bodies, and ``shape`` (the
    mass-weighted position part of the eigenvector, for the MAC)."""

    eigenvalue: complex
    name: str
    shares: dict
    parts: dict = field(default_factory=dict)
    shape: np.ndarray | None = None

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


def _coordinate_groups(model: VehicleModel, by_body: bool = False) -> dict[str, list[int]]:
    """Indices of the model's coordinates by ``role:motion`` (motion: lateral, yaw, roll,
    other), or with ``by_body`` by ``body motion`` (the vehicle's names). Wheelset coordinates
    are (x, y, z, roll, -yaw, spin), body coordinates (x, y, z, roll, pitch, yaw)."""
    roles = body_roles(model.vehicle)
    groups: dict[str, list[int]] = {}
    for name, idx in model.ltg.items():
        role = roles.get(name, "car_body")
        yaw = 4 if role == "wheelset" else 5
        for j, i in enumerate(idx):
            motion = {1: "lateral", 3: "roll", yaw: "yaw"}.get(j, "other")
            key = f"{name} {motion}" if by_body else f"{role}:{motion}"
            groups.setdefault(key, []).append(int(i))
    return groups


#: A running-gear mode in which one motion of one kind of part (the frames' yaw, say) holds at
#: least this share of the running gear's lateral and yaw energy is named by it ("bogie yaw"),
#: not hunting (railexu's choice; in hunting the lateral motion carries most of the kinetic
#: energy, the yaw little: ``I psi'^2 / m y'^2`` is ``(I / m) (2 pi / L)^2``, a few per cent).
SINGLE_MOTION_SHARE = 0.8


def name_mode(shares: dict) -> str | None:
    """The name of a mode from the shares of its energy (``role:motion`` -> share): None when
    less than half of it is lateral (lateral, yaw, roll). When the wheelsets' and bogie frames'
    lateral and yaw motion hold at least half of the lateral part it is a running-gear mode,
    of the bogies when the frames hold more of it than the wheelsets: hunting, unless the yaw
    of the frames (or of the wheelsets) alone holds :data:`SINGLE_MOTION_SHARE` of it (``bogie
    yaw``, ``wheelset yaw``). Else the largest share's part and motion (``car-body yaw``,
    ``bogie roll``): only parts the vehicle has appear in a name."""
    lateral = {k: v for k, v in shares.items() if not k.endswith(":other")}
    total_lateral = sum(lateral.values())
    if total_lateral < LATERAL_ENERGY_SHARE:
        return None
    wheelsets = shares.get("wheelset:lateral", 0.0) + shares.get("wheelset:yaw", 0.0)
    bogies = shares.get("bogie:lateral", 0.0) + shares.get("bogie:yaw", 0.0)
    gear = wheelsets + bogies
    if gear >= 0.5 * total_lateral:
        part = "bogie" if bogies > wheelsets else "wheelset"
        if shares.get(f"{part}:yaw", 0.0) >= SINGLE_MOTION_SHARE * gear:
            return f"{part} yaw"
        return f"{part} hunting"
    largest = max(lateral, key=lateral.get)
    role, motion = largest.split(":")
    return f"{ROLE_WORDS.get(role, role)} {motion}"


def _energy_shares(M, Ks, lam: complex, x: np.ndarray) -> np.ndarray:
    """Per coordinate the mean of its kinetic energy share ``M_ii |lambda x_i|^2 / sum`` and its
    strain energy share ``|Re(conj(x_i) (K_s x)_i)| / sum`` (``K_s`` the symmetric part of the
    stiffness matrix: springs, gravity and the conicity's creep stiffness)."""
    kinetic = np.abs(np.diag(M)) * np.abs(lam * x) ** 2
    strain = np.abs(np.real(np.conj(x) * (Ks @ x)))
    out = np.zeros(x.size)
    for e in (kinetic, strain):
        total = float(np.sum(e))
        if total > 0.0:
            out += 0.5 * e / total
    return out


def lateral_modes(model: VehicleModel) -> list[Mode]:
    """The named oscillatory lateral modes of the linearised vehicle (positive frequencies).

    The system ``M q'' + D q' + K q = 0`` from Exudyn's ``ComputeLinearizedSystem`` (about the
    model's initial state: centred, running at its speed) is written in first-order form. Each
    mode's participation is the mean of its kinetic energy shares ``M_ii |lambda x_i|^2`` and
    its strain energy shares ``|Re(conj(x_i) (K_s x)_i)|`` (:func:`_energy_shares`) in each
    group of coordinates (body role and motion); :func:`name_mode` names it; ``parts`` lists the
    largest shares by the vehicle's body names; ``shape`` is ``sqrt(M_ii) x_i``, normalised."""
    M, K, D = (np.asarray(m) for m in model.mbs.ComputeLinearizedSystem())
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    values, vectors = np.linalg.eig(A)
    Ks = 0.5 * (K + K.T)
    root_mass = np.sqrt(np.abs(np.diag(M)))
    groups = _coordinate_groups(model)
    by_body = _coordinate_groups(model, by_body=True)
    modes = []
    for lam, vec in zip(values, vectors.T, strict=True):
        f = lam.imag / (2.0 * math.pi)
        if not MODE_FREQUENCY_HZ[0] < f < MODE_FREQUENCY_HZ[1]:
            continue
        x = vec[:n]
        energy = _energy_shares(M, Ks, complex(lam), x)
        if not np.sum(energy) > 0.0:
            continue
        shares = {g: float(np.sum(energy[idx])) for g, idx in groups.items()}
        name = name_mode(shares)
        if name is None:
            continue
        parts = {g: float(np.sum(energy[idx])) for g, idx in by_body.items()
                 if not g.endswith(" other")}  # fmt: skip
        top = sorted(parts.items(), key=lambda kv: -kv[1])[:ENERGY_PARTS]
        shape = root_mass * x
        shape = shape / np.linalg.norm(shape)
        parts = {k: v for k, v in top if v >= ENERGY_PART_MIN}
        modes.append(Mode(complex(lam), name, shares, parts, shape))
    return modes


def linear_stability(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Follow every lateral mode over speed by its shape; find where each one's damping crosses
    zero and in which speed bands it is unstable.

    At each speed the linearised vehicle's oscillatory lateral modes are named by their energy
    (:func:`name_mode`: wheelset hunting, bogie hunting, car-body lateral, yaw, roll) and linked
    to the modes at the neighbouring speeds by their shapes (:func:`~railexu.stability.modes.
    track_branches`, MAC). Returns a dict with:

    - ``critical_speed_m_per_s``: the lowest speed at which a followed mode's damping ratio
      crosses zero, ``critical_mode`` its label, ``critical_band_m_per_s`` the band in which it
      is unstable (``[from, None]``: unstable up to the highest speed), ``critical_mode_stays_
      unstable`` whether it stays unstable above (up to the highest speed analysed);
    - ``persistent_critical_speed_m_per_s`` and ``persistent_mode``: the lowest speed from which
      a mode stays unstable up to the highest speed analysed (None when none does);
    - ``modes``: per label (the name, numbered when two branches share it) ``name``,
      ``critical_speed_m_per_s``, ``unstable_bands_m_per_s``, ``stays_unstable_above``,
      ``damping_ratio`` and ``frequency_Hz`` at every speed (NaN where not followed),
      ``energy`` (largest shares by body and motion where it is least damped), ``min_mac``
      (the smallest MAC that linked it), ``stable_in_range``, ``unstable_in_range``;
    - ``least_damped``: per speed the least damped modes (label, frequency, damping ratio);
    - ``hunting_critical_speed_m_per_s``: the lowest crossing of a hunting mode;
    - ``speeds_m_per_s``, ``frequency_Hz``, ``damping_ratio``: the least damped hunting mode at
      each speed; ``stable_in_range``/``unstable_in_range`` of it;
    - ``root_locus``: every followed mode at every speed as ``[speed, frequency, damping,
      label]``;
    - the equivalent conicity used and the cone slope, and ``car_body_suspension``: the
      suspension elements joined to the car bodies (for the explanation of car-body modes).
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
    per_speed = []
    for v in speeds:
        per_speed.append(modes_at(v))
        if progress:
            least = sorted(per_speed[-1], key=lambda m: m.damping_ratio)[:3]
            text = ", ".join(f"{m.name} {m.frequency_Hz:.2f} Hz {m.damping_ratio:+.3f}"
                             for m in least)  # fmt: skip
            progress(f"linear: {v:.1f} m/s, least damped: {text}")
    branches = track_branches(per_speed)
    label_branches(branches)
    modes_out = {b.label: _branch_summary(b, speeds, modes_at, settings) for b in branches}
    modes_out = dict(sorted(modes_out.items(), key=_mode_order))
    out = _critical_of(modes_out)
    hunting = [min((b.modes[k] for b in branches if k in b.modes and b.modes[k].name in
                    HUNTING_MODES), key=lambda m: m.damping_ratio, default=None)
               for k in range(len(speeds))]  # fmt: skip
    h_zeta = np.array([m.damping_ratio if m else math.nan for m in hunting])
    h_finite = h_zeta[np.isfinite(h_zeta)]
    h_cross = [
        m["critical_speed_m_per_s"]
        for m in modes_out.values()
        if m["name"] in HUNTING_MODES and m["critical_speed_m_per_s"] is not None
    ]
    return {
        **out,
        "hunting_critical_speed_m_per_s": min(h_cross) if h_cross else None,
        "modes": modes_out,
        "least_damped": least_damped_table(speeds, branches),
        "mode_tracking": f"MAC of mass-weighted shapes between neighbouring speeds, >= {MAC_MIN}",
        "stable_in_range": bool(h_finite.size and np.all(h_finite > 0.0)),
        "unstable_in_range": bool(h_finite.size and np.all(h_finite <= 0.0)),
        "speeds_m_per_s": speeds,
        "frequency_Hz": [m.frequency_Hz if m else math.nan for m in hunting],
        "damping_ratio": h_zeta.tolist(),
        "root_locus": [
            [speeds[k], m.frequency_Hz, m.damping_ratio, b.label]
            for b in branches
            for k, m in sorted(b.modes.items())
        ],  # fmt: skip
        "linearization": settings.linearization,
        "equivalent_conicity": info["equivalent_conicity"],
        "conicity_amplitude_m": settings.conicity_amplitude_m,
        "cone_slope": info["cone_slope"],
        "creep_model": "kalker_linear",
        "car_body_suspension": car_body_suspension(vehicle),
    }


def car_body_suspension(vehicle: Vehicle) -> list[str]:
    """Names of the suspension elements joined to a car body (:func:`body_roles`)."""
    roles = body_roles(vehicle)
    return [el.name for el in vehicle.suspension
            if any(roles.get(b) == "car_body" for b in el.bodies)]  # fmt: skip


def _branch_summary(branch, speeds: list[float], modes_at, settings) -> dict:
    """One followed mode's entry in ``modes`` (see :func:`linear_stability`)."""
    zeta = [branch.modes[k].damping_ratio if k in branch.modes else math.nan
            for k in range(len(speeds))]  # fmt: skip
    freq = [branch.modes[k].frequency_Hz if k in branch.modes else math.nan
            for k in range(len(speeds))]  # fmt: skip
    bands = unstable_bands(speeds, branch, modes_at, settings.tolerance_m_per_s)
    first = next((b[0] for b in bands if b[0] is not None), None)
    least = min(branch.modes.values(), key=lambda m: m.damping_ratio)
    finite = [z for z in zeta if math.isfinite(z)]
    top = max(branch.modes)
    return {
        "name": least.name,
        "critical_speed_m_per_s": first,
        "unstable_bands_m_per_s": bands,
        "stays_unstable_above": bool(
            bands and bands[-1][1] is None and top == len(speeds) - 1
        ),  # fmt: skip
        "damping_ratio": zeta,
        "frequency_Hz": freq,
        "energy": dict(least.parts),
        "min_mac": min(branch.macs) if branch.macs else None,
        "stable_in_range": bool(finite and all(z > 0.0 for z in finite)),
        "unstable_in_range": bool(finite and all(z <= 0.0 for z in finite)),
    }


def _mode_order(item) -> tuple:
    """Modes that become unstable first (by speed), then the others by their least damping."""
    _, m = item
    crit = m["critical_speed_m_per_s"]
    least = min((z for z in m["damping_ratio"] if math.isfinite(z)), default=math.inf)
    return (crit is None, crit if crit is not None else 0.0, least)


def _critical_of(modes: dict) -> dict:
    """The lowest zero crossing of any mode with its band, and the lowest speed from which a
    mode stays unstable up to the highest speed analysed."""
    crossings = {k: m["critical_speed_m_per_s"] for k, m in modes.items()
                 if m["critical_speed_m_per_s"] is not None}  # fmt: skip
    mode = min(crossings, key=crossings.get) if crossings else None
    bands = modes[mode]["unstable_bands_m_per_s"] if mode else []
    band = next((b for b in bands if b[0] is not None), None)
    persistent = {
        k: m["unstable_bands_m_per_s"][-1][0]
        for k, m in modes.items()
        if m["stays_unstable_above"] and m["unstable_bands_m_per_s"][-1][0] is not None
    }
    p_mode = min(persistent, key=persistent.get) if persistent else None
    return {
        "critical_speed_m_per_s": crossings.get(mode) if mode else None,
        "critical_mode": mode,
        "critical_band_m_per_s": band,
        "critical_mode_stays_unstable": bool(mode and band and band[1] is None),
        "persistent_critical_speed_m_per_s": persistent.get(p_mode) if p_mode else None,
        "persistent_mode": p_mode,
    }
