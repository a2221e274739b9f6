"""Contact parameters and the Python-level evaluation of one wheelset.

:class:`ContactParameters` gathers the material, friction, damping and creep-law settings;
:class:`WheelsetContactModel` packs a :class:`~railexu.contact.placement.WheelsetGeometry` and the
parameters into the arrays the compiled kernel reads, and evaluates a wheelset from its position
and velocity, returning every contact point with its geometry, creepages and forces.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.hertz import hertz_table
from railexu.contact.kalker import kalker_table_for_poisson
from railexu.contact.parameters import (  # noqa: F401 (re-exported: the old import path)
    DAMPING_MODELS,
    ContactParameterError,
    ContactParameters,
)
from railexu.contact.placement import WheelRailPair, WheelsetGeometry


def _smoothed(d2z: np.ndarray, step_m: float, width_m: float) -> np.ndarray:
    """Second derivative averaged with a Gaussian of standard deviation ``width_m``."""
    if width_m <= 0.0:
        return d2z.copy()
    from scipy.ndimage import gaussian_filter1d

    return gaussian_filter1d(d2z, width_m / step_m, mode="nearest")


def wheel_arrays(
    pair: WheelRailPair, curvature_smoothing_m: float = 5.0e-4
) -> tuple[np.ndarray, np.ndarray]:
    """Kernel table ``[F, F', F'', F''_smooth]`` with the kernel's curvature-bound columns
    (:func:`railexu.contact.kernel.with_block_bounds`) and info row ``(s0, step, n, r0, tape)``.
    """
    t = pair.wheel_table
    smooth = _smoothed(np.asarray(t.d2z), t.step_m, curvature_smoothing_m)
    tab = K.with_block_bounds(np.column_stack([t.z, t.dz, t.d2z, smooth]), t.step_m)
    info = np.array([t.y0_m, t.step_m, t.z.size, pair.nominal_radius_m, pair.tape_circle_lateral_m])
    return tab, info


def rail_arrays(
    pair: WheelRailPair, curvature_smoothing_m: float = 5.0e-4
) -> tuple[np.ndarray, np.ndarray]:
    """Kernel table ``[z, z', z'', z''_smooth]`` over track ``y`` with the kernel's
    curvature-bound columns (:func:`railexu.contact.kernel.with_block_bounds`) and info
    ``(y0, step, n)``."""
    t = pair.rail_table
    smooth = _smoothed(np.asarray(t.d2z), t.step_m, curvature_smoothing_m)
    tab = K.with_block_bounds(np.column_stack([t.z, t.dz, t.d2z, smooth]), t.step_m)
    return tab, np.array([t.y0_m, t.step_m, t.z.size])


@dataclass(frozen=True)
class ContactPoint:
    """One contact point of one wheel (track frame, SI; see ``docs/conventions.md``)."""

    side: str
    point: int
    wheel_lateral_m: float
    rail_lateral_m: float
    position_m: tuple[float, float, float]
    rolling_radius_m: float
    contact_angle_rad: float
    gap_m: float
    penetration_m: float
    normal_force_N: float
    a_m: float
    b_m: float
    creep_long: float
    creep_lat: float
    spin_per_m: float
    force_long_N: float
    force_lat_N: float
    force_track_N: tuple[float, float, float]
    wheel_curvature_long_per_m: float
    wheel_curvature_lat_per_m: float
    rail_curvature_lat_per_m: float
    weight: float = 1.0

    @property
    def loaded(self) -> bool:
        return self.normal_force_N > 0.0


@dataclass(frozen=True)
class WheelsetContactResult:
    """Contact points of both wheels and the resultant on the wheelset."""

    points: list[ContactPoint]
    force_N: np.ndarray  # (3,) track frame
    torque_Nm: np.ndarray  # (3,) about the wheelset centre, track frame
    raw: np.ndarray = field(repr=False)  # (2, MAX_POINTS, N_POINT_FIELDS) kernel output

    def wheel(self, side: str) -> list[ContactPoint]:
        return [p for p in self.points if p.side == side]

    def wheel_force_N(self, side: str) -> np.ndarray:
        """Total contact force on one wheel (track frame) [N]."""
        pts = self.wheel(side)
        if not pts:
            return np.zeros(3)
        return np.sum([p.force_track_N for p in pts], axis=0)


class WheelsetContactModel:
    """A wheelset's contact geometry and parameters packed for the compiled kernel.

    Args:
        geometry: the placed wheel/rail pairs of both sides.
        parameters: contact parameters.
        speed_m_per_s: rolling speed V used for the creepages [m/s].
    """

    def __init__(
        self,
        geometry: WheelsetGeometry,
        parameters: ContactParameters | None = None,
        speed_m_per_s: float = 10.0,
    ) -> None:
        self.geometry = geometry
        self.parameters = parameters or ContactParameters()
        width = self.parameters.curvature_smoothing_m
        self.wtab_l, self.winfo_l = wheel_arrays(geometry.left, width)
        self.rtab_l, self.rinfo_l = rail_arrays(geometry.left, width)
        self.wtab_r, self.winfo_r = wheel_arrays(geometry.right, width)
        self.rtab_r, self.rinfo_r = rail_arrays(geometry.right, width)
        self.htab = hertz_table()
        self.ktab = kalker_table_for_poisson(self.parameters.poisson)
        self.params = self.parameters.kernel_vector(speed_m_per_s)
        self._points = np.zeros((2, K.MAX_POINTS, K.N_POINT_FIELDS))
        self._force = np.zeros(6)

    @property
    def speed_m_per_s(self) -> float:
        return float(self.params[K.P_SPEED])

    def set_speed(self, speed_m_per_s: float) -> None:
        """Change the rolling speed V [m/s]."""
        self.params = self.parameters.kernel_vector(speed_m_per_s)

    def evaluate_raw(self, state: np.ndarray, rails: np.ndarray | None = None) -> np.ndarray:
        """Kernel call; returns the 6 force/torque entries (track frame) and keeps the points."""
        if rails is None:
            rails = np.zeros(8)
        K.wheelset_contact(
            self.wtab_l, self.winfo_l, self.rtab_l, self.rinfo_l,
            self.wtab_r, self.winfo_r, self.rtab_r, self.rinfo_r,
            self.htab, self.ktab, self.params, np.asarray(state, dtype=float),
            np.asarray(rails, dtype=float), self._points, self._force,
        )  # fmt: skip
        return self._force.copy()

    def evaluate(
        self,
        lateral_m: float = 0.0,
        vertical_m: float = 0.0,
        roll_rad: float = 0.0,
        yaw_rad: float = 0.0,
        *,
        velocity_m_per_s: tuple[float, float, float] | None = None,
        angular_velocity_rad_per_s: tuple[float, float, float] | None = None,
        longitudinal_m: float = 0.0,
        rails: np.ndarray | None = None,
    ) -> WheelsetContactResult:
        """Evaluate the wheelset at a pose and velocity.

        By default the wheelset rolls forward at the model's speed V and spins about its axle
        at ``V / r0`` (left wheel's r0), with no other motion.
        """
        speed = self.speed_m_per_s
        if velocity_m_per_s is None:
            velocity_m_per_s = (speed, 0.0, 0.0)
        if angular_velocity_rad_per_s is None:
            # spin V / r0 about the axle, whose direction is R e_y with R = Rx(roll) Rz(yaw)
            spin = speed / self.geometry.left.nominal_radius_m
            angular_velocity_rad_per_s = (
                -spin * np.sin(yaw_rad),
                spin * np.cos(roll_rad) * np.cos(yaw_rad),
                spin * np.sin(roll_rad) * np.cos(yaw_rad),
            )
        state = np.array(
            [longitudinal_m, lateral_m, vertical_m, roll_rad, yaw_rad,
             *velocity_m_per_s, *angular_velocity_rad_per_s]
        )  # fmt: skip
        forces = self.evaluate_raw(state, rails)
        return self._result(forces)

    def _result(self, forces: np.ndarray) -> WheelsetContactResult:
        raw = self._points.copy()
        pts: list[ContactPoint] = []
        for side_index, side in enumerate(("left", "right")):
            pair = self.geometry.pairs[side_index]
            number = 0
            for k in range(K.MAX_POINTS):
                row = raw[side_index, k]
                if row[K.PF_ACTIVE] == 0.0:
                    continue
                number += 1
                # rail position in the rail profile's own axes
                z_track = pair.rail_height(row[K.PF_YRAIL])
                y_own, _ = pair.rail_track_to_own(row[K.PF_YRAIL], z_track)
                pts.append(
                    ContactPoint(
                        side=side,
                        point=number,
                        wheel_lateral_m=float(row[K.PF_S]),
                        rail_lateral_m=float(y_own),
                        position_m=(float(row[K.PF_X]), float(row[K.PF_Y]), float(row[K.PF_Z])),
                        rolling_radius_m=float(row[K.PF_RADIUS]),
                        contact_angle_rad=float(row[K.PF_ANGLE]),
                        gap_m=float(row[K.PF_GAP]),
                        penetration_m=float(row[K.PF_DELTA]),
                        normal_force_N=float(row[K.PF_N]),
                        a_m=float(row[K.PF_A]),
                        b_m=float(row[K.PF_B]),
                        creep_long=float(row[K.PF_XI]),
                        creep_lat=float(row[K.PF_ETA]),
                        spin_per_m=float(row[K.PF_SPIN]),
                        force_long_N=float(row[K.PF_FX]),
                        force_lat_N=float(row[K.PF_FY]),
                        force_track_N=(
                            float(row[K.PF_FTX]),
                            float(row[K.PF_FTY]),
                            float(row[K.PF_FTZ]),
                        ),
                        wheel_curvature_long_per_m=float(row[K.PF_KWX]),
                        wheel_curvature_lat_per_m=float(row[K.PF_KWY]),
                        rail_curvature_lat_per_m=float(row[K.PF_KRY]),
                        weight=float(row[K.PF_WEIGHT]),
                    )
                )
        return WheelsetContactResult(
            points=pts, force_N=forces[:3].copy(), torque_Nm=forces[3:].copy(), raw=raw
        )

    def gap_candidates(
        self, side: str, lateral_m: float, vertical_m: float, roll_rad: float, yaw_rad: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Refined local minima of the gap of one wheel: ``(s, gap)`` arrays, sorted by ``s``.

        The wheelset pose is in the real track frame; ``side`` is ``"left"`` or ``"right"``.
        """
        if side == "left":
            m, wtab, winfo, rtab, rinfo = 1.0, self.wtab_l, self.winfo_l, self.rtab_l, self.rinfo_l
        elif side == "right":
            m, wtab, winfo, rtab, rinfo = -1.0, self.wtab_r, self.winfo_r, self.rtab_r, self.rinfo_r
        else:
            raise ValueError(f"side must be 'left' or 'right', got {side!r}")
        cs = np.empty(K.MAX_POINTS)
        cg = np.empty(K.MAX_POINTS)
        ch = np.empty(K.MAX_POINTS)
        n = K.find_contact_candidates(
            wtab, winfo, rtab, rinfo, m * lateral_m, vertical_m, m * roll_rad, m * yaw_rad,
            self.params[K.P_SCAN], cs, cg, ch,
        )  # fmt: skip
        return cs[:n].copy(), cg[:n].copy()
