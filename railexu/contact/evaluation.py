"""Contact parameters and the Python-level evaluation of one wheelset.

:class:`ContactParameters` gathers the material, friction, damping and creep-law settings;
:class:`WheelsetContactModel` packs a :class:`~railexu.contact.placement.WheelsetGeometry` and the
parameters into the arrays the compiled kernel reads, and evaluates a wheelset from its position
and velocity, returning every contact point with its geometry, creepages and forces.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from . import kernel as K
from .creep import creep_model_code
from .hertz import hertz_table
from .kalker import kalker_table_for_poisson
from .placement import WheelRailPair, WheelsetGeometry

#: Damping laws of the normal force, selected by name.
DAMPING_MODELS = {
    # seed eq. (2): N = K delta^1.5 + D delta_dot, D in N s/m
    "linear": 0,
    # Hunt-Crossley: N = K delta^1.5 (1 + chi delta_dot), chi in s/m
    "hunt_crossley": 1,
}


class ContactParameterError(InputError):
    """Invalid contact parameters."""


def _choice(kind: str, name: str, valid) -> str:
    if name in valid:
        return name
    close = difflib.get_close_matches(name, list(valid), n=1)
    hint = f" Did you mean {close[0]!r}?" if close else ""
    raise ContactParameterError(f"unknown {kind} {name!r}.{hint} Valid: {', '.join(sorted(valid))}")


@dataclass(frozen=True)
class ContactParameters:
    """Material, friction, damping and creep-law settings of the wheel-rail contact.

    Attributes:
        shear_modulus_Pa: combined shear modulus G of wheel and rail steel [Pa].
        poisson: Poisson's ratio of both bodies [-].
        friction: friction coefficient mu (mu0 of Polach 2005) [-].
        creep_model: ``"polach"`` (1999, with spin), ``"polach_2005"`` (falling friction),
            ``"kalker_linear"`` or ``"fastsim"``.
        polach_2005: ``(k_a, k_s, A, B)`` of Polach 2005 (B in s/m); dry rail by default
            (Polach 2005, Table 2).
        damping_model: ``"hunt_crossley"`` (default): the seed's eq. (2) with the hysteresis
            damping ``D = chi K delta^1.5``, i.e. ``N = K d^1.5 (1 + chi d_dot)``, which starts
            from zero at first touch and dissipates the energy of the impact; or ``"linear"``,
            ``N = K d^1.5 + D d_dot`` with a constant D, which jumps to ``D d_dot`` at first
            touch (a discontinuity Newton's method dislikes).
        damping: chi [s/m] for ``hunt_crossley`` (default 3 s/m: about 10 % of critical damping
            for a wheel of ~2 t on its Hertz contact at 100 kN), D [N s/m] for ``linear``.
        scan_step_m: step of the coarse scan for contact points along the wheel profile [m].
        curvature_smoothing_m: width (standard deviation of a Gaussian) over which the profiles'
            lateral curvature is averaged for Hertz's ellipse [m]. A contact patch is several mm
            wide on the tread (0.4 mm at a flange), so the curvature at one point, which jumps
            where two arcs of a profile meet, would make the normal stiffness jump as the point
            crosses the junction; averaged over 0.5 mm it varies continuously and the flange's
            narrow ellipse is kept (the Manchester comparison holds from 0.3 to 0.5 mm). The
            geometry itself (gap, contact angle) is not smoothed.
        tangential: compute creep forces (False: normal forces only).
    """

    shear_modulus_Pa: float = 82.0e9
    poisson: float = 0.28
    friction: float = 0.3
    creep_model: str = "polach"
    polach_2005: tuple[float, float, float, float] = (1.0, 0.4, 0.4, 0.6)
    damping_model: str = "hunt_crossley"
    damping: float = 3.0
    scan_step_m: float = 1.0e-3
    curvature_smoothing_m: float = 5.0e-4
    tangential: bool = True

    def __post_init__(self) -> None:
        if not self.shear_modulus_Pa > 0:
            raise ContactParameterError(
                f"shear modulus must be > 0 Pa, got {self.shear_modulus_Pa}"
            )
        if not 0.0 <= self.poisson < 0.5:
            raise ContactParameterError(f"Poisson's ratio must be in [0, 0.5), got {self.poisson}")
        if not self.friction >= 0.0:
            raise ContactParameterError(f"friction must be >= 0, got {self.friction}")
        if not self.damping >= 0.0:
            raise ContactParameterError(f"contact damping must be >= 0, got {self.damping}")
        if not 0.0 <= self.curvature_smoothing_m <= 5.0e-3:
            raise ContactParameterError(
                f"curvature smoothing must be within 0 .. 5 mm, got {self.curvature_smoothing_m} m"
            )
        if not 1.0e-5 <= self.scan_step_m <= 5.0e-3:
            raise ContactParameterError(
                f"scan step must be within 0.01 .. 5 mm, got {self.scan_step_m} m"
            )
        _choice("damping model", self.damping_model, DAMPING_MODELS)
        creep_model_code(self.creep_model)  # raises with did-you-mean

    @property
    def young_modulus_Pa(self) -> float:
        """Young's modulus E = 2 G (1 + nu) [Pa]."""
        return 2.0 * self.shear_modulus_Pa * (1.0 + self.poisson)

    @property
    def effective_modulus_Pa(self) -> float:
        """Hertz's E* for two bodies of the same steel: E / (2 (1 - nu^2)) = G / (1 - nu) [Pa]."""
        return self.shear_modulus_Pa / (1.0 - self.poisson)

    def kernel_vector(self, speed_m_per_s: float) -> np.ndarray:
        """The parameter vector the compiled kernel reads (``kernel.P_*`` indices)."""
        if not speed_m_per_s > 0.0:
            raise ContactParameterError(f"rolling speed must be > 0 m/s, got {speed_m_per_s}")
        p = np.zeros(K.N_PARAMS)
        p[K.P_ESTAR] = self.effective_modulus_Pa
        p[K.P_SHEAR] = self.shear_modulus_Pa
        p[K.P_MU] = self.friction
        k_a, k_s, fric_a, fric_b = self.polach_2005
        if self.creep_model == "polach_2005":
            p[K.P_KA], p[K.P_KS], p[K.P_FRIC_A], p[K.P_FRIC_B] = k_a, k_s, fric_a, fric_b
        else:
            p[K.P_KA], p[K.P_KS], p[K.P_FRIC_A], p[K.P_FRIC_B] = 1.0, 1.0, 1.0, 0.0
        p[K.P_SPEED] = speed_m_per_s
        p[K.P_DAMP_MODEL] = DAMPING_MODELS[self.damping_model]
        p[K.P_DAMP] = self.damping
        p[K.P_CREEP] = creep_model_code(self.creep_model)
        p[K.P_SCAN] = self.scan_step_m
        p[K.P_TANGENTIAL] = 1.0 if self.tangential else 0.0
        return p


def _smoothed(d2z: np.ndarray, step_m: float, width_m: float) -> np.ndarray:
    """Second derivative averaged with a Gaussian of standard deviation ``width_m``."""
    if width_m <= 0.0:
        return d2z.copy()
    from scipy.ndimage import gaussian_filter1d

    return gaussian_filter1d(d2z, width_m / step_m, mode="nearest")


def wheel_arrays(
    pair: WheelRailPair, curvature_smoothing_m: float = 5.0e-4
) -> tuple[np.ndarray, np.ndarray]:
    """Kernel table ``[F, F', F'', F''_smooth]`` and info row ``(s0, step, n, r0, tape)``."""
    t = pair.wheel_table
    smooth = _smoothed(np.asarray(t.d2z), t.step_m, curvature_smoothing_m)
    tab = np.ascontiguousarray(np.column_stack([t.z, t.dz, t.d2z, smooth]), dtype=np.float64)
    info = np.array([t.y0_m, t.step_m, t.z.size, pair.nominal_radius_m, pair.tape_circle_lateral_m])
    return tab, info


def rail_arrays(
    pair: WheelRailPair, curvature_smoothing_m: float = 5.0e-4
) -> tuple[np.ndarray, np.ndarray]:
    """Kernel table ``[z, z', z'', z''_smooth]`` over track ``y`` and info ``(y0, step, n)``."""
    t = pair.rail_table
    smooth = _smoothed(np.asarray(t.d2z), t.step_m, curvature_smoothing_m)
    tab = np.ascontiguousarray(np.column_stack([t.z, t.dz, t.d2z, smooth]), dtype=np.float64)
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
