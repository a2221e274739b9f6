"""The compact binary state of a run, ``state.npz``: what an animation needs, without re-running.

``write_run`` writes it beside ``timeseries.csv``; ``railexu animate`` and ``railexu report``
read it. It holds, at every output time,

- the pose of every wheelset (lateral, vertical, roll, yaw; front wheelset first, as ``ws1``
  of the time series) and the lateral position and yaw of every body;
- the wheel and rail profiles of every wheelset, placed in the track (``docs/conventions.md``:
  the left-type frame; the right side is the mirror image), with the rail offsets of the track
  irregularities under each wheelset;
- the contact points of every wheel: position in the track's cross-section, contact angle,
  semi-axes of the ellipse, normal and tangential forces.

Contact points are those the run's kernel found, kept by the recorder at every output time
(``RunResult.contact_points``: ``contact_source = "kernel"``), or the recorder's per-point
columns (``ws{i}_{side}_p{k}_...``, ``"recorded"``) of a run read back from its files. Without
either they are found again from each
recorded pose with the run's own contact kernel (:class:`railexu.contact.evaluation.
WheelsetContactModel`); the pose does not hold the velocities, so the forces of each wheel are
then the recorded totals ``Y`` and ``Q`` shared between its points in proportion to their normal
forces from the penetration, and the ellipse is scaled to the shared load with Hertz's
``a, b ~ N^(1/3)`` (Johnson 1985, *Contact Mechanics*, eq. 4.41): ``contact_source =
"pose"``.

Body yaw is read from a ``{body}_yaw_rad`` column when the run wrote one; otherwise it is the
slope of the lateral positions of what the body rests on (wheelsets or bodies joined to it by a
suspension element at another longitudinal position), a kinematic estimate that ignores the
deflection of the suspension between them.
"""

from __future__ import annotations

import hashlib
import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from railexu.errors import InputError

if TYPE_CHECKING:
    from railexu.results import TimeSeries
    from railexu.simulation.simulate import RunResult

STATE_FILE = "state.npz"
FORMAT_VERSION = 1
#: zlib's level for the arrays in ``state.npz`` (``numpy.savez_compressed`` uses 6). On the seed
#: run (3751 output times, 2.9 MB of contact points in float32) level 1 wrote the file in 0.076 s
#: instead of 0.12 s for a file 1 % larger (2.53 MB against 2.51 MB); a study writes one per case
COMPRESS_LEVEL = 1
SIDES = ("left", "right")
MAX_POINTS = 3  # contact points per wheel: railexu.contact.kernel.MAX_POINTS

# fields of a contact point (last axis of RunState.contacts), SI units, track frame
CONTACT_FIELDS = (
    "active",  # 1 where a loaded contact point exists
    "wheel_s_m",  # position on the wheel profile, from the tape circle, outwards positive
    "y_m",  # lateral position of the point in the track cross-section (y to the left)
    "z_m",  # height of the point (z = 0 top of undisturbed rail)
    "angle_rad",  # contact angle, positive towards the flange
    "N_N",  # normal force
    "a_m",  # semi-axis of the ellipse along the rail
    "b_m",  # lateral semi-axis
    "Fx_N",  # tangential force on the wheel along the rolling direction
    "Fy_N",  # tangential force on the wheel, lateral in the contact plane
    "FY_N",  # total force on the wheel, track y
    "FZ_N",  # total force on the wheel, track z
)
CF = {name: k for k, name in enumerate(CONTACT_FIELDS)}
# the fields the file holds; the others follow from them and the pose (:func:`complete_contacts`)
STORED_FIELDS = ("active", "wheel_s_m", "angle_rad", "N_N", "a_m", "b_m", "Fx_N", "Fy_N")


@dataclass
class ProfileCurves:
    """The placed profiles of one wheelset (left-type frame, ``docs/conventions.md``)."""

    wheel_s_m: np.ndarray  # wheel profile lateral coordinate, from the tape circle, outwards
    wheel_F_m: np.ndarray  # radius increase at wheel_s_m
    rail_outline_m: np.ndarray  # (m, 2): the placed rail's outline, y and z in the track frame
    tape_circle_lateral_m: float
    nominal_radius_m: float
    wheel_name: str = ""
    rail_name: str = ""


@dataclass
class RunState:
    """The content of ``state.npz`` (all SI; ``n`` output times, front wheelset first)."""

    time_s: np.ndarray  # (n,)
    distance_m: np.ndarray  # (n,)
    speed_m_per_s: np.ndarray  # (n,)
    wheelset_names: list[str]
    wheelset_x_m: np.ndarray  # (n_ws,) position along the vehicle, forwards positive
    wheelset_pose: np.ndarray  # (n, n_ws, 4): lateral, vertical, roll, yaw
    wheel_forces_N: np.ndarray  # (n, n_ws, 2, 2): [left, right] x [Y, Q]
    body_names: list[str]
    body_x_m: np.ndarray  # (n_b,)
    body_lateral_m: np.ndarray  # (n, n_b)
    body_yaw_rad: np.ndarray  # (n, n_b)
    body_size_m: np.ndarray  # (n_b, 2): length and width of the body's outline in plan view
    profiles: list[ProfileCurves]
    profile_index: np.ndarray  # (n_ws,) index into profiles
    rail_offsets_m: np.ndarray  # (n, n_ws, 4): dy_left, dz_left, dy_right, dz_right
    contacts: np.ndarray  # (n, n_ws, 2, MAX_POINTS, len(CONTACT_FIELDS))
    contact_source: str = "pose"
    track_x_m: np.ndarray | None = None  # track centre line; None: straight along x
    track_y_m: np.ndarray | None = None
    track_heading_rad: np.ndarray | None = None
    meta: dict = field(default_factory=dict)

    @property
    def n_wheelsets(self) -> int:
        return len(self.wheelset_names)

    def wheel_outline(self, frame: int, ws: int, side: str) -> tuple[np.ndarray, np.ndarray]:
        """The wheel's running profile in the track cross-section at output ``frame`` [m]."""
        prof = self.profiles[int(self.profile_index[ws])]
        lat, vert, roll, _ = self.wheelset_pose[frame, ws]
        return wheel_points(prof, SIDES.index(side), prof.wheel_s_m, lat, vert, roll)

    def rail_outline(self, frame: int, ws: int, side: str) -> tuple[np.ndarray, np.ndarray]:
        """The rail's outline in the track cross-section, moved by its irregularity [m]."""
        prof = self.profiles[int(self.profile_index[ws])]
        k = SIDES.index(side)
        dy, dz = self.rail_offsets_m[frame, ws, 2 * k : 2 * k + 2]
        m = 1.0 if k == 0 else -1.0
        return m * prof.rail_outline_m[:, 0] + dy, prof.rail_outline_m[:, 1] + dz


def wheel_points(
    prof: ProfileCurves, side: int, s_m: np.ndarray, lateral_m, vertical_m, roll_rad
) -> tuple[np.ndarray, np.ndarray]:
    """Track-frame ``(y, z)`` of the wheel profile points ``s_m`` (lowest generatrix) of one
    wheel for a wheelset pose; yaw is left out (it moves the points along the track and their
    lateral position only by a term of second order in the yaw angle).

    In wheelset axes the point is ``(m (e + s), -(r0 + F(s)))`` with ``m = +1`` on the left and
    ``-1`` on the right; roll turns it by ``R_x(phi)`` about the wheelset centre, which lies at
    ``(lateral, vertical)``: the coordinates of the recorder and of the contact kernel.
    """
    m = 1.0 if side == 0 else -1.0
    s = np.asarray(s_m, dtype=float)
    radius = prof.nominal_radius_m + np.interp(s, prof.wheel_s_m, prof.wheel_F_m)
    py = m * (prof.tape_circle_lateral_m + s)
    pz = -radius
    c, sn = np.cos(roll_rad), np.sin(roll_rad)
    return lateral_m + c * py - sn * pz, vertical_m + sn * py + c * pz


def contact_point_position(
    prof: ProfileCurves, side: int, s_m, lateral_m, vertical_m, roll_rad, yaw_rad
) -> tuple[np.ndarray, np.ndarray]:
    """Track-frame ``(y, z)`` of the contact point at ``s_m`` on one wheel, on the contact locus
    of the kernel (``railexu.contact.kernel``, step a): on a yawed wheelset the point of the
    circle at ``s`` whose normal can meet a straight rail's lies at the angle ``theta`` from the
    bottom with ``sin(theta) = -r'(s) tan(psi)``, which moves it ahead of or behind the axle and,
    on a steep flange, by up to a tenth of a millimetre sideways and up (``r r' psi^2``).

    In the left-type frame of the wheel (the right wheel mirrored: ``y``, roll and yaw change
    sign) the point is ``R_x(phi) R_z(psi) (r sin(theta), e + s, -r cos(theta))`` from the
    wheelset centre (``docs/conventions.md``).
    """
    m = 1.0 if side == 0 else -1.0
    s = np.asarray(s_m, dtype=float)
    radius = prof.nominal_radius_m + np.interp(s, prof.wheel_s_m, prof.wheel_F_m)
    slope = np.interp(s, prof.wheel_s_m, np.gradient(prof.wheel_F_m, prof.wheel_s_m))
    psi, phi = m * np.asarray(yaw_rad), m * np.asarray(roll_rad)
    theta = np.arcsin(np.clip(-slope * np.tan(psi), -1.0, 1.0))
    px, py, pz = radius * np.sin(theta), prof.tape_circle_lateral_m + s, -radius * np.cos(theta)
    qy = np.sin(psi) * px + np.cos(psi) * py
    y = np.cos(phi) * qy - np.sin(phi) * pz
    z = np.sin(phi) * qy + np.cos(phi) * pz
    return lateral_m + m * y, vertical_m + z


# ----------------------------------------------------------------------------------------------
# building the state of a finished run
# ----------------------------------------------------------------------------------------------


def state_from_run(result: RunResult) -> RunState:
    """The state of a run from its :class:`~railexu.simulation.simulate.RunResult` (which must hold
    the model: ``result.model``)."""
    from railexu.simulation.simulate import wheelset_order

    model = result.model
    if model is None:
        raise ValueError("the run result holds no model: cannot write its state file")
    ts = result.timeseries
    vehicle = result.vehicle
    order = wheelset_order(vehicle)
    n, n_ws = len(ts), len(order)
    t = ts["time_s"]
    speed = (
        ts["speed_m_per_s"] if "speed_m_per_s" in ts else np.full(n, result.settings.speed_m_per_s)
    )
    pose = np.stack(
        [np.stack([_col(ts, f"ws{i + 1}_{k}", n) for k in _POSE], axis=1) for i in range(n_ws)],
        axis=1,
    )
    forces = np.zeros((n, n_ws, 2, 2))
    for i in range(n_ws):
        for k, side in enumerate(SIDES):
            forces[:, i, k, 0] = _col(ts, f"ws{i + 1}_{side}_Y_N", n)
            forces[:, i, k, 1] = _col(ts, f"ws{i + 1}_{side}_Q_N", n)
    x_start = model.x_start_m
    ws_x = np.array([model.centre[vehicle.wheelsets[j].name][0] - x_start for j in order])
    profiles, index = _profiles(model, order)
    ws_track_x = model.x_start_m + ws_x[None, :] + ts["distance_m"][:, None]
    offsets = _rail_offsets(model, ws_track_x)
    elastic = _add_rail_deflections(offsets, ts)
    state = RunState(
        time_s=t.copy(),
        distance_m=ts["distance_m"].copy(),
        speed_m_per_s=np.asarray(speed, dtype=float).copy(),
        wheelset_names=[vehicle.wheelsets[j].name for j in order],
        wheelset_x_m=ws_x,
        wheelset_pose=pose,
        wheel_forces_N=forces,
        body_names=[b.name for b in vehicle.bodies],
        body_x_m=np.array([model.centre[b.name][0] - x_start for b in vehicle.bodies]),
        body_lateral_m=np.zeros((n, len(vehicle.bodies))),
        body_yaw_rad=np.zeros((n, len(vehicle.bodies))),
        body_size_m=np.zeros((len(vehicle.bodies), 2)),
        profiles=profiles,
        profile_index=index,
        rail_offsets_m=offsets,
        contacts=np.zeros((n, n_ws, 2, MAX_POINTS, len(CONTACT_FIELDS))),
        meta={**_meta(result), "elastic_rails": elastic, "track_s0_m": float(model.x_start_m)},
    )
    _centre_line(state, result.track, float(ws_track_x.min()), float(ws_track_x.max()))
    for j, b in enumerate(vehicle.bodies):
        state.body_lateral_m[:, j] = _col(ts, f"{b.name}_lateral_m", n)
    _body_yaw(state, ts, vehicle)
    points = getattr(result, "contact_points", None)
    if points is not None and points.shape[0] == n:
        _kernel_contacts(state, points)
    else:
        _pose_contacts(state, model, order)
        if _has_point_columns(ts):
            _recorded_contacts(state, ts)
    return state


def _kernel_contacts(state: RunState, points: np.ndarray) -> None:
    """Contact points as the run's kernel found them (``RunResult.contact_points``, fields
    :data:`railexu.simulation.simulate.POINT_FIELDS`): nothing recomputed, nothing estimated."""
    from railexu.simulation.simulate import POINT_FIELDS

    c = state.contacts
    c[...] = 0.0
    active = points[..., list(POINT_FIELDS).index("N_N")] > 0.0
    for k, name in enumerate(POINT_FIELDS):
        if name in CF:
            c[..., CF[name]] = np.where(active, points[..., k], 0.0)
    c[..., CF["active"]] = active
    state.contact_source = "kernel"


_POSE = ("lateral_m", "vertical_m", "roll_rad", "yaw_rad")


def _col(ts: TimeSeries, name: str, n: int) -> np.ndarray:
    return ts[name] if name in ts else np.zeros(n)


def _profiles(model, order: list[int]) -> tuple[list[ProfileCurves], np.ndarray]:
    profiles: list[ProfileCurves] = []
    seen: dict[int, int] = {}
    index = np.zeros(len(order), dtype=int)
    for i, j in enumerate(order):
        geom = model.geometries[j]
        key = id(geom)
        if key not in seen:
            pair = geom.left
            wheel = pair.wheel
            s = np.linspace(wheel.y_min, wheel.y_max, 2000)
            seen[key] = len(profiles)
            profiles.append(
                ProfileCurves(
                    wheel_s_m=s,
                    wheel_F_m=np.asarray(wheel.height(s), dtype=float),
                    rail_outline_m=np.asarray(pair.rail_outline_track_m, dtype=float),
                    tape_circle_lateral_m=float(pair.tape_circle_lateral_m),
                    nominal_radius_m=float(pair.nominal_radius_m),
                    wheel_name=str(wheel.name),
                    rail_name=str(pair.rail.name),
                )
            )
        index[i] = seen[key]
    return profiles, index


def _rail_offsets(model, x_m: np.ndarray) -> np.ndarray:
    """Rail offsets ``(dy_l, dz_l, dy_r, dz_r)`` of the irregularities at track positions ``x_m``
    (linear between the 5 cm samples the model uses; zero outside the record)."""
    values = np.asarray(model.irr_values)
    grid = model.irr_start + model.irr_step * np.arange(values.shape[0])
    out = np.zeros((*x_m.shape, 4))
    for c in range(4):
        out[..., c] = np.interp(x_m, grid, values[:, c], left=0.0, right=0.0)
    return out


def _add_rail_deflections(offsets: np.ndarray, ts: TimeSeries) -> bool:
    """Add the deflections of an elastic track's rails under each wheelset (the recorder's
    ``ws{i}_{side}_rail_lateral_m``, ``_rail_vertical_m``) to the rail offsets; True if the run
    recorded them."""
    found = False
    for i in range(offsets.shape[1]):
        for k, side in enumerate(SIDES):
            for c, what in enumerate(("lateral", "vertical")):
                name = f"ws{i + 1}_{side}_rail_{what}_m"
                if name in ts:
                    offsets[:, i, 2 * k + c] += ts[name]
                    found = True
    return found


def _centre_line(state: RunState, track, s_min: float, s_max: float) -> None:
    """The track centre line under the run (x, y, heading every 0.5 m) when the track has a
    curved design alignment (``track.alignment`` with ``position(s)`` and ``heading(s)``)."""
    alignment = getattr(track, "alignment", None)
    if alignment is None or getattr(alignment, "is_straight", True):
        return
    s = np.arange(min(0.0, s_min - 30.0), s_max + 30.0, 0.5)
    x, y = alignment.position(s)
    state.track_x_m = np.asarray(x, dtype=float)
    state.track_y_m = np.asarray(y, dtype=float)
    state.track_heading_rad = np.asarray(alignment.heading(s), dtype=float)
    state.meta["track_centre_s0_m"] = float(s[0])


def _meta(result: RunResult) -> dict:
    meta = {
        "format_version": FORMAT_VERSION,
        "vehicle": result.vehicle.name,
        "track": result.track.name,
        "status": dict(result.status),
    }
    for what, obj in (("vehicle", result.vehicle), ("track", result.track)):
        source = getattr(obj, "source", "") or ""
        if source and Path(source).is_file():
            meta[f"{what}_file"] = str(Path(source).resolve())
            meta[f"{what}_sha256"] = file_sha256(source)
    return meta


def file_sha256(path: str | Path) -> str:
    """The SHA-256 of a file's bytes (hex)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _body_yaw(state: RunState, ts: TimeSeries, vehicle) -> None:
    """Body yaw: recorded, or the slope of the lateral positions of the body's supports."""
    ws_index = {name: i for i, name in enumerate(state.wheelset_names)}
    body_index = {name: i for i, name in enumerate(state.body_names)}
    below: dict[str, set[str]] = {b: set() for b in state.body_names}
    for element in vehicle.suspension:
        a, b = element.bodies
        for top, low in ((a, b), (b, a)):
            if top in below and low != top:
                below[top].add(low)
    # a body rests on wheelsets, or on bodies lower than itself (bogies under a car body)
    height = {b.name: b.position_m[2] for b in vehicle.bodies}
    for name, j in body_index.items():
        xs, ys = [], []
        on_wheelsets = any(low in ws_index for low in below[name])
        for low in sorted(below[name]):
            if low in ws_index:
                xs.append(state.wheelset_x_m[ws_index[low]])
                ys.append(state.wheelset_pose[:, ws_index[low], 0])
            elif low in body_index and height[low] < height[name]:
                xs.append(state.body_x_m[body_index[low]])
                ys.append(state.body_lateral_m[:, body_index[low]])
        # outline for the plan view: a bogie frame spans its wheelsets and a little more, a car
        # body its bogies and an overhang (the vehicle files give no outline dimensions)
        span = float(np.ptp(xs)) if xs else float(np.ptp(state.wheelset_x_m))
        state.body_size_m[j] = (span + 1.2, 2.0) if on_wheelsets else (span + 5.0, 2.9)
        if f"{name}_yaw_rad" in ts:
            state.body_yaw_rad[:, j] = ts[f"{name}_yaw_rad"]
        elif len(xs) >= 2 and np.ptp(xs) > 0.1:
            x = np.asarray(xs) - np.mean(xs)
            y = np.stack(ys, axis=1)
            state.body_yaw_rad[:, j] = (y @ x) / float(x @ x)  # least-squares slope dy/dx


def _has_point_columns(ts: TimeSeries) -> bool:
    return "ws1_left_p1_N_N" in ts


def _recorded_contacts(state: RunState, ts: TimeSeries) -> None:
    """Contact points from the recorder's per-point columns."""
    n = len(ts)
    pose = state.contacts.copy()
    c = state.contacts
    c[...] = 0.0
    for i in range(state.n_wheelsets):
        prof = state.profiles[int(state.profile_index[i])]
        lat, vert, roll, yaw = (state.wheelset_pose[:, i, k] for k in range(4))
        for k, side in enumerate(SIDES):
            m = 1.0 if k == 0 else -1.0
            for p in range(MAX_POINTS):
                stem = f"ws{i + 1}_{side}_p{p + 1}_"
                if stem + "N_N" not in ts:
                    break
                normal = ts[stem + "N_N"]
                s = _col(ts, stem + "wheel_y_m", n)
                gamma = _col(ts, stem + "angle_rad", n)
                fx, fy = _col(ts, stem + "Fx_N", n), _col(ts, stem + "Fy_N", n)
                y, z = contact_point_position(prof, k, s, lat, vert, roll, yaw)
                row = c[:, i, k, p]
                row[:, CF["active"]] = normal > 0.0
                row[:, CF["wheel_s_m"]] = s
                row[:, CF["y_m"]] = y
                row[:, CF["z_m"]] = z
                row[:, CF["angle_rad"]] = gamma
                row[:, CF["N_N"]] = normal
                row[:, CF["Fx_N"]] = fx
                row[:, CF["Fy_N"]] = fy
                fy_track, fz_track = track_force(m, gamma, normal, fy)
                row[:, CF["FY_N"]] = fy_track
                row[:, CF["FZ_N"]] = fz_track
                _ellipse_of_nearest(row, pose[:, i, k])
    state.contact_source = "recorded"


def _ellipse_of_nearest(row: np.ndarray, pose: np.ndarray) -> None:
    """Semi-axes of a recorded point (not recorded themselves): those of the pose's point
    nearest on the wheel profile, scaled to the recorded normal force with Hertz's
    ``a, b ~ N^(1/3)``."""
    dist = np.where(pose[:, :, CF["active"]] > 0, 0.0, np.inf) + np.abs(
        pose[:, :, CF["wheel_s_m"]] - row[:, None, CF["wheel_s_m"]]
    )
    near = np.argmin(dist, axis=1)
    pick = pose[np.arange(row.shape[0]), near]
    ok = np.isfinite(dist.min(axis=1)) & (pick[:, CF["N_N"]] > 0.0) & (row[:, CF["N_N"]] > 0.0)
    scale = np.cbrt(np.where(ok, row[:, CF["N_N"]] / np.where(ok, pick[:, CF["N_N"]], 1.0), 0.0))
    row[:, CF["a_m"]] = pick[:, CF["a_m"]] * scale
    row[:, CF["b_m"]] = pick[:, CF["b_m"]] * scale


def track_force(m: float, gamma, normal, tangential_lat):
    """Track-frame ``(F_y, F_z)`` on a wheel from its normal force ``N`` and lateral tangential
    force ``F_y`` (contact frame) at contact angle ``gamma`` (``docs/conventions.md``: the rail
    normal ``n = (0, -m sin gamma, cos gamma)`` points from the rail into the wheel, ``m = +1``
    left and ``-1`` right, and ``t_y = n x t_x = (0, cos gamma, m sin gamma)``)."""
    s, c = np.sin(gamma), np.cos(gamma)
    return -m * s * normal + c * tangential_lat, c * normal + m * s * tangential_lat


def _pose_contacts(state: RunState, model, order: list[int]) -> None:
    """Contact points from each recorded pose with the run's contact kernel; the forces are the
    recorded wheel totals shared in proportion to the normal forces (see the module text)."""
    from railexu.contact import kernel as K

    raw = _evaluate_poses(state, model, order)
    _K_S, _K_Y, _K_Z, _K_ANGLE = K.PF_S, K.PF_Y, K.PF_Z, K.PF_ANGLE
    _K_N, _K_A, _K_B = K.PF_N, K.PF_A, K.PF_B
    c = state.contacts
    active = raw[..., _K_N] > 0.0
    c[..., CF["active"]] = active
    for name, src in (("wheel_s_m", _K_S), ("y_m", _K_Y), ("z_m", _K_Z), ("angle_rad", _K_ANGLE)):
        c[..., CF[name]] = raw[..., src]
    normal = np.where(active, raw[..., _K_N], 0.0)
    total = normal.sum(axis=-1, keepdims=True)
    share = np.divide(normal, total, out=np.zeros_like(normal), where=total > 0.0)
    Y = state.wheel_forces_N[..., 0][..., None]
    Q = state.wheel_forces_N[..., 1][..., None]
    c[..., CF["FY_N"]] = share * Y
    c[..., CF["FZ_N"]] = share * Q
    # the normal force that, with the lateral tangential force, gives the shared Y and Q:
    # invert track_force for (N, F_y) at each point's contact angle
    m = np.array([1.0, -1.0])[None, None, :, None]
    gamma = raw[..., _K_ANGLE]
    s, co = np.sin(gamma), np.cos(gamma)
    fy_track, fz_track = share * Y, share * Q
    n_from = -m * s * fy_track + co * fz_track
    t_from = co * fy_track + m * s * fz_track
    c[..., CF["N_N"]] = np.where(active, n_from, 0.0)
    c[..., CF["Fy_N"]] = np.where(active, t_from, 0.0)
    c[..., CF["Fx_N"]] = np.nan  # not known from a pose
    scale = np.cbrt(np.divide(np.maximum(n_from, 0.0), normal, out=np.ones_like(normal),
                              where=normal > 0.0))  # fmt: skip
    c[..., CF["a_m"]] = np.where(active, raw[..., _K_A] * scale, 0.0)
    c[..., CF["b_m"]] = np.where(active, raw[..., _K_B] * scale, 0.0)
    state.contact_source = "pose"


def _evaluate_poses(state: RunState, model, order: list[int]) -> np.ndarray:
    """Kernel points ``(n, n_ws, 2, MAX_POINTS, N_POINT_FIELDS)`` at every recorded pose, the
    rails moved by their irregularities (velocities: rolling at V, no other motion)."""
    from railexu.contact import kernel as K
    from railexu.contact.evaluation import WheelsetContactModel

    n = state.time_s.size
    out = np.zeros((n, state.n_wheelsets, 2, K.MAX_POINTS, K.N_POINT_FIELDS))
    rails = np.zeros(8)
    for i, j in enumerate(order):
        cm = WheelsetContactModel(model.geometries[j], model.contact_params, model.speed)
        spin = model.speed / model.geometries[j].left.nominal_radius_m
        for f in range(n):
            lat, vert, roll, yaw = state.wheelset_pose[f, i]
            dy_l, dz_l, dy_r, dz_r = state.rail_offsets_m[f, i]
            rails[0], rails[1], rails[4], rails[5] = dy_l, dz_l, dy_r, dz_r
            v = state.speed_m_per_s[f]
            st = np.array([0.0, lat, vert, roll, yaw, v, 0.0, 0.0,
                           -spin * np.sin(yaw), spin * np.cos(roll) * np.cos(yaw),
                           spin * np.sin(roll) * np.cos(yaw)])  # fmt: skip
            cm.evaluate_raw(st, rails)
            out[f, i] = cm._points
    return out


# ----------------------------------------------------------------------------------------------
# file
# ----------------------------------------------------------------------------------------------


def save_state(state: RunState, path: str | Path) -> Path:
    """Write ``state`` as a compressed ``.npz`` (float32 where millimetres suffice; zlib level
    :data:`COMPRESS_LEVEL`), readable by ``numpy.load``."""
    arrays: dict[str, np.ndarray] = {
        "time_s": state.time_s,
        "distance_m": state.distance_m,
        "speed_m_per_s": state.speed_m_per_s,
        "wheelset_names": np.array(state.wheelset_names, dtype=str),
        "wheelset_x_m": state.wheelset_x_m,
        "wheelset_pose": state.wheelset_pose,
        "wheel_forces_N": state.wheel_forces_N.astype(np.float32),
        "body_names": np.array(state.body_names, dtype=str),
        "body_x_m": state.body_x_m,
        "body_lateral_m": state.body_lateral_m,
        "body_yaw_rad": state.body_yaw_rad,
        "body_size_m": state.body_size_m,
        "profile_index": state.profile_index,
        "rail_offsets_m": state.rail_offsets_m.astype(np.float32),
        "contacts": state.contacts[..., [CF[f] for f in STORED_FIELDS]].astype(np.float32),
        "contact_fields": np.array(STORED_FIELDS, dtype=str),
        "contact_source": np.array(state.contact_source),
        "meta_json": np.array(json.dumps(state.meta)),
    }
    for k, prof in enumerate(state.profiles):
        arrays[f"profile{k}_wheel_s_m"] = prof.wheel_s_m
        arrays[f"profile{k}_wheel_F_m"] = prof.wheel_F_m
        arrays[f"profile{k}_rail_outline_m"] = prof.rail_outline_m
        arrays[f"profile{k}_scalars"] = np.array(
            [prof.tape_circle_lateral_m, prof.nominal_radius_m]
        )
        arrays[f"profile{k}_names"] = np.array([prof.wheel_name, prof.rail_name], dtype=str)
    if state.track_x_m is not None:
        arrays["track_x_m"] = state.track_x_m
        arrays["track_y_m"] = state.track_y_m
        arrays["track_heading_rad"] = state.track_heading_rad
    path = Path(path)
    with path.open("wb") as fh:
        _write_npz(fh, arrays, COMPRESS_LEVEL)
    return path


def _write_npz(fh, arrays: dict[str, np.ndarray], level: int) -> None:
    """What ``numpy.savez_compressed`` writes (one ``NAME.npy`` per array in a deflated zip),
    with zlib's ``level`` chosen."""
    with zipfile.ZipFile(fh, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=level) as zf:
        for name, array in arrays.items():
            with zf.open(f"{name}.npy", "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.asanyarray(array), allow_pickle=False)


def load_state(path: str | Path) -> RunState:
    """Read a ``state.npz`` written by :func:`save_state`.

    Raises:
        InputError: the file is missing, unreadable or of another format.
    """
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except FileNotFoundError:
        raise InputError(
            f"{path}: no state file; it is written by `railexu run` (rerun the case to make it)"
        ) from None
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        # empty (EOFError), cut short (BadZipFile, ValueError), a member missing (KeyError)
        raise InputError(
            f"{path}: cannot read the state file ({exc or type(exc).__name__}); it is damaged "
            "or cut short: run the case again"
        ) from None
    try:
        return _state_from_arrays(path, data)
    except InputError:
        raise
    except (KeyError, IndexError, ValueError, TypeError, AttributeError) as exc:
        raise InputError(
            f"{path}: the state file is damaged ({type(exc).__name__}: {exc}): run the case again"
        ) from None


def _state_from_arrays(path: Path, data: dict) -> RunState:
    """The :class:`RunState` of the arrays of a state file (a missing array: ``KeyError``)."""
    meta = json.loads(str(data.get("meta_json", "{}")))
    if not isinstance(meta, dict):
        raise ValueError("meta_json is not a JSON object")
    if meta.get("format_version") != FORMAT_VERSION or "contacts" not in data:
        raise InputError(
            f"{path}: state file of format {meta.get('format_version')!r}, this railexu reads "
            f"format {FORMAT_VERSION}"
        )
    fields = tuple(str(f) for f in data["contact_fields"])
    if fields != STORED_FIELDS:
        raise InputError(f"{path}: unknown contact fields {fields}")
    profiles = []
    k = 0
    while f"profile{k}_wheel_s_m" in data:
        scalars = data[f"profile{k}_scalars"]
        names = [str(x) for x in data[f"profile{k}_names"]]
        profiles.append(
            ProfileCurves(
                wheel_s_m=data[f"profile{k}_wheel_s_m"],
                wheel_F_m=data[f"profile{k}_wheel_F_m"],
                rail_outline_m=data[f"profile{k}_rail_outline_m"],
                tape_circle_lateral_m=float(scalars[0]),
                nominal_radius_m=float(scalars[1]),
                wheel_name=names[0],
                rail_name=names[1],
            )
        )
        k += 1
    stored = data["contacts"].astype(float)
    contacts = np.zeros((*stored.shape[:-1], len(CONTACT_FIELDS)))
    contacts[..., [CF[f] for f in STORED_FIELDS]] = stored
    state = RunState(
        time_s=data["time_s"],
        distance_m=data["distance_m"],
        speed_m_per_s=data["speed_m_per_s"],
        wheelset_names=[str(x) for x in data["wheelset_names"]],
        wheelset_x_m=data["wheelset_x_m"],
        wheelset_pose=data["wheelset_pose"],
        wheel_forces_N=data["wheel_forces_N"].astype(float),
        body_names=[str(x) for x in data["body_names"]],
        body_x_m=data["body_x_m"],
        body_lateral_m=data["body_lateral_m"],
        body_yaw_rad=data["body_yaw_rad"],
        body_size_m=data["body_size_m"],
        profiles=profiles,
        profile_index=data["profile_index"],
        rail_offsets_m=data["rail_offsets_m"].astype(float),
        contacts=contacts,
        contact_source=str(data["contact_source"]),
        track_x_m=data.get("track_x_m"),
        track_y_m=data.get("track_y_m"),
        track_heading_rad=data.get("track_heading_rad"),
        meta=meta,
    )
    complete_contacts(state)
    return state


def complete_contacts(state: RunState) -> None:
    """Fill the derived contact fields: the point's place in the cross-section from its
    position on the wheel profile and the pose (:func:`contact_point_position`), and the track-frame
    force from the normal and lateral tangential forces (:func:`track_force`)."""
    c = state.contacts
    for i in range(state.n_wheelsets):
        prof = state.profiles[int(state.profile_index[i])]
        lat, vert, roll, yaw = (state.wheelset_pose[:, i, k][:, None] for k in range(4))
        for k in range(2):
            m = 1.0 if k == 0 else -1.0
            w = c[:, i, k]
            w[..., CF["y_m"]], w[..., CF["z_m"]] = contact_point_position(
                prof, k, w[..., CF["wheel_s_m"]], lat, vert, roll, yaw
            )
            w[..., CF["FY_N"]], w[..., CF["FZ_N"]] = track_force(
                m, w[..., CF["angle_rad"]], w[..., CF["N_N"]], w[..., CF["Fy_N"]]
            )


def write_state(result: RunResult, path: str | Path) -> Path:
    """Build the state of ``result`` and write it to ``path`` (``state.npz``)."""
    return save_state(state_from_run(result), path)
