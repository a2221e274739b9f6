"""Build the Exudyn multibody system of a vehicle on a track.

Design (measured in ``docs/dev/exudyn-api.md``):

- every body and wheelset is an Exudyn rigid body on a ``NodeRigidBodyRxyz`` node (Tait-Bryan
  angles); a wheelset's axle is its body's third axis, so its spin is the last angle, the contact
  forces do not depend on it and the Newton Jacobian stays valid for thousands of steps;
- linear suspension elements are Exudyn connectors (Cartesian spring-dampers, rigid-body
  spring-dampers for torsion), preloaded with their static forces (:mod:`railexu.model.statics`) so
  that the vehicle starts in equilibrium at its nominal geometry;
- all wheel-rail forces (and bump stops) come from one ``ObjectGenericODE2`` with a zero mass
  matrix whose force user function calls one compiled function for all wheelsets
  (:func:`railexu.model.forces.generalized_forces`); Exudyn differentiates it numerically for the
  Jacobian, creep damping included;
- a velocity-level coordinate constraint holds the forward speed of one body (the car body by
  default): the traction needed to run at constant speed or to follow a speed profile; with
  traction and braking demands instead (:class:`railexu.operation.traction.Traction`) the forward
  motion is free and torques on the wheelsets drive and brake it (``docs/traction-and-braking.md``);
- the coordinates are those of a vehicle frame that runs along the track's centre line with
  the speed body and turns with the track's heading (:mod:`railexu.model.forces`,
  ``docs/curving.md``):
  the first coordinate of a node is the distance along the track, the others its lateral and
  vertical position and its angles relative to the local track direction, so no angle grows with
  the heading (a 300 m curve over 600 m turns the track by 115 degrees; the Tait-Bryan angles stay
  small) and the frame's inertial forces are added in the compiled force function; on straight
  track the frame does not turn and these are exactly the absolute coordinates;
- wheelsets spin freely under their creep forces.
"""

from __future__ import annotations

import math
import time

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel, rail_arrays, wheel_arrays
from railexu.contact.hertz import hertz_table
from railexu.contact.kalker import kalker_table_for_poisson
from railexu.contact.placement import WheelsetGeometry, symmetric_wheelset
from railexu.contact.placement import wheelset_geometry as placed_wheelset
from railexu.contact.quasistatic import free_rolling_spin_rate, press_wheelset
from railexu.errors import InputError
from railexu.model.curve_start import Support, carries_statically, chord_placements, rz
from railexu.model.forces import (
    BS_NREAL,
    FR_SIZE,
    WL_SIZE,
    KernelData,
    compiled_entry,
    generalized_forces,
    generalized_forces_threaded,
    jacobian,
)
from railexu.model.sc_tables import sc_kernel_fields
from railexu.model.statics import StaticSolution, attachment_point, static_equilibrium
from railexu.model.suspension_forces import (
    SI_INTERNAL,
    KernelElement,
    element_deflection,
    kernel_arrays,
    kernel_elements,
)
from railexu.model.vertical_forces import VerticalForces
from railexu.operation.speed_profile import SpeedProfile
from railexu.operation.traction import Traction
from railexu.runtime.thread_choice import WINDOW_CALLS, ThreadChoice
from railexu.runtime.threads import contact_threads, use_threads
from railexu.track.alignment import Alignment, straight_alignment
from railexu.track.track import Track
from railexu.vehicle.vehicle import (
    BumpStop,
    SpringDamper,
    TorsionSpring,
    Vehicle,
    Wheelset,
    linear_part,
)

#: A wheelset whose roll moment at the start is out of balance by more than this share of
#: its static wheel load times the half distance of its contact points is pressed again with
#: loads that balance it (:meth:`VehicleModel._balance_start_loads`; railexu's choice: on level
#: track the residual is round-off and nothing changes).
START_ROLL_BALANCE_SHARE = 0.02
#: An internal coordinate (series branch) is started relaxed at the start's geometry where that
#: moves it by more than this from 0 [m] (:meth:`VehicleModel._relaxed_internal_coordinates`).
START_INTERNAL_TOLERANCE_M = 1.0e-6
#: Distance of the rearmost wheelset from the start of the run (the track's ``start``, 0 by
#: default) at t = 0 [m].
START_MARGIN_M = 1.0
#: A free run (traction and braking) ends when its speed falls below this [m/s]: the creepages
#: are normalised by the speed, and a standing vehicle is outside the model.
MIN_FREE_SPEED_M_PER_S = 0.5
#: The vertical profile's loads are set again when the vehicle has run this far since they were
#: last set [m] (railexu.model.vertical_forces): 1/20 of the 1 m over which the vertical
#: curvature's jumps are rounded; the gradient changes by at most 0.05 m / R_v between updates
#: (0.2 per mille at the smallest radius, 250 m).
VERTICAL_UPDATE_M = 0.05
#: Natural frequency of the vehicle frame's follower of the speed body in a free run on curved
#: track [rad/s] (1 Hz, critically damped: a lag of a / w^2 = 2.5 cm at 1 m/s^2).
FRAME_FOLLOW_RAD_PER_S = 2.0 * math.pi


def wheelset_geometry(wheelset: Wheelset, track: Track) -> WheelsetGeometry:
    """The wheelset's wheel profiles placed on the track's rails (gauge, inclination, flange-back
    distance, nominal rolling radius; a profile and a radius per wheel when the wheelset is not
    symmetric), with the contact tables of both wheels."""
    common = dict(
        inclination=track.inclination,
        gauge_m=track.gauge_m,
        flange_back_distance_m=wheelset.flange_back_distance_m,
    )
    if wheelset.symmetric:
        return symmetric_wheelset(
            wheelset.wheel_profile,
            track.rail_profile,
            nominal_radius_m=wheelset.nominal_radius_m,
            **common,
        )
    return placed_wheelset(
        {"left": wheelset.wheel_profile, "right": wheelset.profile_right},
        track.rail_profile,
        nominal_radius_m={
            "left": wheelset.nominal_radius_m,
            "right": wheelset.radius_right_m,
        },  # fmt: skip
        **common,
    )


class ModelError(InputError):
    """A vehicle/track combination that cannot be built (e.g. a wheel that cannot carry its
    load)."""


class VehicleModel:
    """The Exudyn system of a vehicle running on a track at constant speed.

    Args:
        vehicle: the vehicle.
        track: the track.
        speed_m_per_s: forward speed V.
        initial_lateral_m: lateral offset of the whole vehicle at the start [m] (the seed's
            initial excursion).
        distance_m: distance the run will cover (sizes the irregularity record) [m].
        deceleration_m_per_s2: constant deceleration of the speed (the frame's motion along the
            track follows it; :class:`railexu.operation.run_settings.RunSettings`).
        speed_profile: a prescribed speed along the track instead (its start speed is
            ``speed_m_per_s``).
        traction: traction and brake demands with the forward motion free (no speed
            constraint; ``speed_m_per_s`` is the start speed).
    """

    def __init__(
        self,
        vehicle: Vehicle,
        track: Track,
        speed_m_per_s: float,
        initial_lateral_m: float = 0.0,
        distance_m: float = 100.0,
        deceleration_m_per_s2: float = 0.0,
        speed_profile: SpeedProfile | None = None,
        traction: Traction | None = None,
    ) -> None:
        import exudyn as exu

        if not speed_m_per_s > 0.0:
            raise ModelError(f"speed must be > 0 m/s, got {speed_m_per_s}")
        self.vehicle = vehicle
        self.track = track
        self.speed = float(speed_m_per_s)
        self.initial_lateral_m = float(initial_lateral_m)
        self.distance_hint = float(distance_m)
        self.deceleration = float(deceleration_m_per_s2)
        self.profile = speed_profile
        self.traction = traction
        self.alignment: Alignment = getattr(track, "alignment", None) or straight_alignment()
        self.curved = not self.alignment.is_straight
        vertical = getattr(track, "vertical", None)
        #: the track's vertical profile (None: level track, no vertical forces)
        self.vertical = None if vertical is None or vertical.is_level else vertical
        self.contact_params = vehicle.contact
        self.params = vehicle.contact.kernel_vector(self.speed)

        # --- contact geometry of every wheelset (cached by profile, radius, flange back)
        cache: dict = {}
        self.geometries: list[WheelsetGeometry] = []
        for ws in vehicle.wheelsets:
            key = (ws.wheel_profile, ws.nominal_radius_m, ws.flange_back_distance_m)
            if key not in cache:
                cache[key] = wheelset_geometry(ws, track)
            self.geometries.append(cache[key])
        self._pack_tables()

        # --- statics: wheel loads and spring preloads
        tape = [g.left.tape_circle_lateral_m for g in self.geometries]
        self.statics: StaticSolution = static_equilibrium(vehicle, tape)
        if np.any(self.statics.wheel_loads_N <= 0.0):
            bad = [
                vehicle.wheelsets[i].name
                for i in range(len(vehicle.wheelsets))
                if np.any(self.statics.wheel_loads_N[i] <= 0.0)
            ]
            raise ModelError(f"wheelsets {bad} carry no load at rest: check masses and loads")
        self.axle_load_warnings = []
        for ws, loads in zip(vehicle.wheelsets, self.statics.wheel_loads_N, strict=True):
            if ws.axle_load_N is not None:
                got = float(np.sum(loads))
                if abs(got - ws.axle_load_N) > 0.02 * ws.axle_load_N:
                    self.axle_load_warnings.append(
                        f"wheelset {ws.name}: declared axle load {ws.axle_load_N / 1e3:.1f} kN, "
                        f"masses and loads give {got / 1e3:.1f} kN"
                    )

        # --- wheelsets pressed onto the rails at the initial lateral offset
        #: the wheel loads the wheelsets were pressed with at the start [N], (n_ws, 2)
        self.start_wheel_loads_N = np.array(self.statics.wheel_loads_N, dtype=float)
        self._press_wheelsets()

        # --- the Exudyn system
        self.SC = exu.SystemContainer()
        self.mbs = self.SC.AddSystem()
        #: the internal coordinates at the start [m] (None: zeros, the nominal geometry)
        self.start_internal_m: np.ndarray | None = None
        self._build()
        relaxed = self._relaxed_internal_coordinates()
        if self._balance_start_loads() or relaxed:
            self._press_wheelsets()
            self.SC = exu.SystemContainer()
            self.mbs = self.SC.AddSystem()
            self._build()

    def _press_wheelsets(self) -> None:
        """Every wheelset pressed onto its rails at the initial lateral offset under
        :attr:`start_wheel_loads_N`, spinning at its free-rolling rate."""
        self.initial_wheelsets = []
        self.initial_spin_rates: list[float] = []
        for ws, geom, loads in zip(
            self.vehicle.wheelsets, self.geometries, self.start_wheel_loads_N, strict=True
        ):
            cm = WheelsetContactModel(geom, self.vehicle.contact, self.speed)
            try:
                st = press_wheelset(cm, self.initial_lateral_m, 0.0, (loads[0], loads[1]))
            except RuntimeError as exc:
                raise ModelError(f"wheelset {ws.name}: {exc}") from exc
            self.initial_wheelsets.append(st)
            self.initial_spin_rates.append(
                free_rolling_spin_rate(cm, st.lateral_m, st.vertical_m, st.roll_rad, 0.0)
            )

    def _relaxed_internal_coordinates(self) -> bool:
        """Set :attr:`start_internal_m` so that every series branch (a damper's bushes, a
        friction slider's stick spring, an air spring's reservoir) carries no force at the
        start, as after a long rest, where that moves an internal coordinate by more than
        :data:`START_INTERNAL_TOLERANCE_M`; True if any moved.

        On level track the nominal geometry is the start's and the internal coordinates are
        0. On a twisted track the ends of an element separate at ``t = 0`` (the loaded
        Hbbins' UIC links by 9.9 mm laterally at 4 per mille: the wheelsets are placed with the
        cant under each, the car body with the cant under its centre); with ``u = 0`` their stick
        springs would start at 20 kN, twice the links' friction limit, and push the wheelsets
        sideways in the first step (the empty Hbbins climbed its flange in 5 ms)."""
        if self.internal_node is None:
            return False
        q = np.asarray(self.mbs.systemData.GetODE2Coordinates(), dtype=float)[self.object_ltg]
        d = self.kernel
        u = np.zeros(len(self.internal_ltg))
        first = q.shape[0] - u.shape[0]  # the internal coordinates come last
        for e in range(d.se_int.shape[0]):
            iu = int(d.se_int[e, SI_INTERNAL])
            if iu >= 0:
                u[iu - first] = element_deflection(e, q, d.qref, d.se_int, d.se_real)
        if np.max(np.abs(u)) <= START_INTERNAL_TOLERANCE_M:
            return False
        self.start_internal_m = u
        return True

    def _balance_start_loads(self) -> bool:
        """Move load between each wheelset's wheels so that the contact balances the roll
        moment on the wheelset at the start, where that residual exceeds
        :data:`START_ROLL_BALANCE_SHARE` times ``b Q0``; True if any load moved.

        The statics hold on level, untwisted track. A vehicle started on a twisted track (the
        EN 14363 twist test, ``railexu.assessment.acceptance.twist``) has its springs warped at
        ``t = 0``: with the statics' loads each wheelset meets a roll moment its contact does
        not carry (63 kN m on the loaded Hbbins at 4 per mille), rolls on its Hertz contacts
        (about 200 Hz) within one step and bounces its wheels off the rails. The residual
        roll moment ``R`` of the compiled forces (contact, suspension, frame) on the wheelset
        at ``t = 0`` is carried by the loads ``Q_L - R / (2 b)``, ``Q_R + R / (2 b)`` (contact
        points at ``+-b``, the tape circles; their sum, the vertical balance, unchanged)."""
        n = self._out.shape[0]
        q = np.asarray(self.mbs.systemData.GetODE2Coordinates(), dtype=float)
        qt = np.asarray(self.mbs.systemData.GetODE2Coordinates_t(), dtype=float)
        if self.start_internal_m is not None:  # the series branches as they will start
            q[self.internal_ltg] = self.start_internal_m
        out = np.zeros(n)
        self.evaluate(q, qt, 0.0, out, self.points.copy(), self.ws_force.copy())
        moved = False
        for w, geom in enumerate(self.geometries):
            b = geom.left.tape_circle_lateral_m
            q0 = float(np.mean(self.statics.wheel_loads_N[w]))
            residual = float(out[6 * int(self.kernel.ws_slots[w]) + 3])
            if abs(residual) > START_ROLL_BALANCE_SHARE * b * q0:
                shift = -residual / (2.0 * b)  # the contact's moment b (Q_L - Q_R) takes -R
                self.start_wheel_loads_N[w] += [shift, -shift]
                moved = True
        if moved and np.any(self.start_wheel_loads_N <= 0.0):
            bad = [w.name for w, q_w in zip(self.vehicle.wheelsets, self.start_wheel_loads_N,
                                             strict=True) if np.any(q_w <= 0.0)]  # fmt: skip
            raise ModelError(f"wheelsets {bad}: at the start on this track (twisted under the "
                             "vehicle) a wheel carries no load at rest")  # fmt: skip
        return moved

    # ------------------------------------------------------------------------------------------
    def _pack_tables(self) -> None:
        n_ws = len(self.geometries)
        width = self.contact_params.curvature_smoothing_m
        wheel = [
            [wheel_arrays(g.left, width), wheel_arrays(g.right, width)] for g in self.geometries
        ]
        n_max = max(t.shape[0] for pair in wheel for t, _ in pair)
        # one table per distinct wheel (a vehicle's wheels mostly share one profile): the
        # compiled search reads one table of about 0.6 MB instead of eight copies, which
        # stays in the processor's cache when two runs share it (docs/performance.md)
        distinct: list[np.ndarray] = []
        self.wtab_index = np.zeros((n_ws, 2), dtype=np.int64)
        self.winfo = np.zeros((n_ws, 2, 5))
        for i, pair in enumerate(wheel):
            for s, (tab, info) in enumerate(pair):
                j = next((j for j, t in enumerate(distinct) if np.array_equal(t, tab)), None)
                if j is None:
                    j = len(distinct)
                    distinct.append(tab)
                self.wtab_index[i, s] = j
                self.winfo[i, s] = info
        self.wtab = np.zeros((len(distinct), n_max, wheel[0][0][0].shape[1]))
        for j, tab in enumerate(distinct):
            self.wtab[j, : tab.shape[0]] = tab
        rails = [
            rail_arrays(self.geometries[0].left, width),
            rail_arrays(self.geometries[0].right, width),
        ]
        m_max = max(t.shape[0] for t, _ in rails)
        self.rtab = np.zeros((2, m_max, rails[0][0].shape[1]))
        self.rinfo = np.zeros((2, 3))
        for s, (tab, info) in enumerate(rails):
            self.rtab[s, : tab.shape[0]] = tab
            self.rinfo[s] = info
        self.sc_fields = sc_kernel_fields(
            getattr(self.track, "variable_rails", None), self.geometries[0], width,
            n_wheelsets=len(self.geometries),
        )  # fmt: skip
        self.htab = hertz_table()
        self.ktab = kalker_table_for_poisson(self.contact_params.poisson)

    # ------------------------------------------------------------------------------------------
    def _build(self) -> None:
        """The Exudyn system in named steps: bodies, wheelsets, suspension, loads, the contact
        element (with the sampled track), the speed constraint."""
        veh = self.vehicle
        # the rearmost wheelset starts START_MARGIN_M beyond the track's start distance
        start = float(getattr(self.track, "start_m", 0.0))
        self.x_start_m = start + START_MARGIN_M - min(w.position_x_m for w in veh.wheelsets)
        speed_body = next((b for b in veh.bodies if b.name == veh.speed_body), None)
        x_speed = (
            speed_body.position_m[0]
            if speed_body is not None
            else next(w.position_x_m for w in veh.wheelsets if w.name == veh.speed_body)
        )
        #: distance along the track of the vehicle frame's origin at t = 0 [m]
        self.frame_start_m = self.x_start_m + x_speed
        self.centre: dict[str, np.ndarray] = {}
        self.rotation: dict[str, np.ndarray] = {}
        self.node: dict[str, int] = {}
        self.body: dict[str, int] = {}
        self.inertia: dict[str, tuple[float, np.ndarray]] = {}
        self._add_bodies()
        self._add_wheelsets()
        self._add_suspension()
        self._add_loads()
        self._add_vertical_loads()
        self._sample_track()
        self._add_rail_masses()
        self._add_contact_element()
        self._add_speed_constraint()
        self.mbs.Assemble()
        self.ltg = {
            name: np.asarray(self.mbs.systemData.GetNodeLTGODE2(n), dtype=np.int64)
            for name, n in self.node.items()
        }
        self.rail_ltg = {
            name: np.asarray(self.mbs.systemData.GetNodeLTGODE2(n), dtype=np.int64)
            for name, n in self.rail_node.items()
        }
        if self.vertical_forces is not None:
            self.update_vertical_loads()
        rail_of = {n: name for name, n in self.rail_node.items()}
        self.internal_ltg = (
            np.asarray(self.mbs.systemData.GetNodeLTGODE2(self.internal_node), dtype=np.int64)
            if self.internal_node is not None
            else np.zeros(0, dtype=np.int64)
        )
        self.object_ltg = np.concatenate(
            [self.rail_ltg[rail_of[n]] if n in rail_of
             else self.internal_ltg if n == self.internal_node
             else self.ltg[self._name_of(n)]
             for n in self.ode_nodes]
        )  # fmt: skip

    def _track_pose(self, x: float) -> tuple[np.ndarray, np.ndarray]:
        """The local track frame at the distance ``x`` along the track, in the vehicle frame at
        the start: ``(origin, rotation)``, the origin (centre line at the top of rail) relative
        to the frame's origin and the rotation ``R_F^T R_x`` with ``R = Rz(heading) Rx(roll)``.

        The vehicle frame rolls by its smoothed roll and the contact's local frame by the
        rounded cant (:meth:`railexu.track.alignment.Alignment.table`), taken from the same table
        the kernel reads, so that a vehicle placed inside a curve or a transition starts with every
        wheelset on its local, canted rails, tangent to the track (angle of attack zero)."""
        from railexu.track.alignment import TAB_CANT, TAB_FROLL, TAB_PSI

        a = self.alignment
        s0 = self.frame_start_m
        if not hasattr(self, "_start_table"):
            reach = self.vehicle_length_m() + 40.0  # > 4 smoothing lengths beyond the vehicle
            self._start_table = a.table(s0 - reach, s0 + reach)
        start, step, tab = self._start_table
        grid = start + step * np.arange(tab.shape[0])

        def rotation(s: float, roll_column: int) -> np.ndarray:
            psi = float(np.interp(s, grid, tab[:, TAB_PSI]))
            roll = float(np.interp(s, grid, tab[:, roll_column]))
            cz, sz, cx, sx = math.cos(psi), math.sin(psi), math.cos(roll), math.sin(roll)
            rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
            rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
            return rz @ rx

        frame = rotation(s0, TAB_FROLL)
        (x0, y0), (x1, y1) = a.position(s0), a.position(x)
        origin = frame.T @ np.array([float(x1 - x0), float(y1 - y0), 0.0])
        return origin, frame.T @ rotation(x, TAB_CANT)

    def _placed(
        self,
        x: float,
        local: np.ndarray,
        rotation: np.ndarray,
        chord: tuple[float, float] = (0.0, 0.0),
    ):
        """Nominal centre (straight track: ``(x, local y, local z)``) and, on a curved track,
        the initial displacement and rotation that put a body with its centre at ``local``
        (lateral and vertical, in the local track frame at ``x``; moved laterally by
        ``chord[0]`` and yawed by ``chord[1]`` in it: the chord placement) and the reference
        rotation ``rotation`` onto the track: ``(centre, displacement | None, rotation | None)``.

        The nominal centre stays the reference position, so that the suspension's unstressed
        lengths are those of straight track; the curve's placement is the initial state."""
        centre = np.array([x, local[1], local[2]])
        if not self.curved:
            return centre, None, None
        origin, turn = self._track_pose(x)
        local = local + np.array([0.0, chord[0], 0.0])
        if chord[1] != 0.0:
            turn = turn @ rz(chord[1])
        placed = np.array([self.frame_start_m, 0.0, 0.0]) + origin + turn @ local
        return centre, placed - centre, rotation.T @ turn @ rotation

    def _add_rigid_body(
        self, name, mass, inertia, centre, rotation, velocities=None, displacement=None, turn=None
    ) -> None:
        import exudyn as exu
        from exudyn.rigidBodyUtilities import RigidBodyInertia

        res = self.mbs.CreateRigidBody(
            inertia=RigidBodyInertia(mass, np.diag(inertia)),
            nodeType=exu.NodeType.RotationRxyz,
            referencePosition=list(centre),
            referenceRotationMatrix=rotation,
            initialDisplacement=None if displacement is None else list(displacement),
            initialRotationMatrix=turn,
            initialVelocity=[self.speed, 0.0, 0.0],
            gravity=[0.0, 0.0, -self.vehicle.gravity_m_per_s2],
            returnDict=True,
        )
        if velocities is not None:
            self.mbs.SetNodeParameter(res["nodeNumber"], "initialVelocities", velocities)
        self.centre[name] = centre
        self.rotation[name] = np.asarray(rotation)
        self.node[name] = res["nodeNumber"]
        self.body[name] = res["bodyNumber"]
        self.inertia[name] = (float(mass), np.asarray(inertia, dtype=float))

    def _add_bodies(self) -> None:
        """Car bodies and bogie frames at their nominal positions (plus the initial offset),
        on a curved track placed on the local track frame under them, on the chord of what
        carries them (:mod:`railexu.model.curve_start`)."""
        y0 = self.initial_lateral_m
        chord = self._chord_placements() if self.curved else {}
        for b in self.vehicle.bodies:
            x = self.x_start_m + b.position_m[0]
            local = np.array([0.0, b.position_m[1] + y0, b.position_m[2]])
            c, d, turn = self._placed(x, local, np.eye(3), chord.get(b.name, (0.0, 0.0)))
            self._add_rigid_body(b.name, b.mass_kg, b.inertia_kg_m2, c, np.eye(3), None, d, turn)

    def _chord_placements(self) -> dict[str, tuple[float, float]]:
        """Each body's lateral offset and yaw in its local track frame at the start inside a
        curve: on the chord of what carries it (:func:`~railexu.model.curve_start.
        chord_placements`)."""
        x0, y0 = self.x_start_m, self.initial_lateral_m  # y0: every body's offset already
        wheelsets = {ws.name: (x0 + ws.position_x_m, st.lateral_m - y0)
                     for ws, st in zip(self.vehicle.wheelsets, self.initial_wheelsets,
                                       strict=True)}  # fmt: skip
        bodies = {b.name: x0 + b.position_m[0] for b in self.vehicle.bodies}
        supports = [Support(tuple(el.bodies), x0 + el.position_m[0])
                    for el in self.vehicle.suspension if carries_statically(el)]  # fmt: skip
        return chord_placements(wheelsets, bodies, supports, self._track_pose)

    def _add_wheelsets(self) -> None:
        """Wheelsets pressed onto the rails, spinning at their free-rolling rate; the axle is
        the body's third axis (spin is the last angle). On a curved track each is placed on
        its local rails, tangent to the track."""
        from exudyn.rigidBodyUtilities import RotationMatrixX

        V = self.speed
        for ws, st, spin_rate in zip(
            self.vehicle.wheelsets, self.initial_wheelsets, self.initial_spin_rates, strict=True
        ):
            x = self.x_start_m + ws.position_x_m
            rot = RotationMatrixX(st.roll_rad - 0.5 * math.pi)
            c, d, turn = self._placed(x, np.array([0.0, st.lateral_m, st.vertical_m]), rot)
            # free rolling: the spin at which the wheelset carries no longitudinal creep force
            self._add_rigid_body(
                ws.name, ws.mass_kg, ws.inertia_kg_m2, c, rot, [V, 0, 0, 0, 0, spin_rate], d, turn
            )

    def _on_axlebox(self, body: str) -> bool:
        """Whether an element's point on ``body`` is on a wheelset's axlebox: every element
        acts on a wheelset through its axlebox, at the declared height above the axle (on the
        axle at the axle's height), which passes the force and its moment into the axle but
        not the moment about the axle (``docs/suspension.md``, "Elements at a wheelset"); the
        force acts at the midpoint of the element's two ends, whose lever from the axle's
        centre is never along the axle alone once the ends separate."""
        return any(w.name == body for w in self.vehicle.wheelsets)

    def _local_point(
        self, body: str, p_vehicle, axlebox: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """(local position on the body, initial global position) of an attachment point; with
        ``axlebox`` a wheelset's point keeps its declared height above the axle, in the
        wheelset's axes without spin (the second axis points down at rest: ``(0, -dz, y)``)."""
        veh = self.vehicle
        p = attachment_point(veh, body, p_vehicle)
        if axlebox:
            dz = float(p_vehicle[2]) - veh.wheelset(body).nominal_radius_m
            local = np.array([0.0, -dz, p[1]])
        elif body in {w.name for w in veh.wheelsets}:
            local = np.array([0.0, 0.0, p[1]])  # on the axle (body z)
        else:
            local = np.array([p[0], p[1], p[2]]) - np.asarray(
                next(b.position_m for b in veh.bodies if b.name == body)
            )
        return local, self.centre[body] + self.rotation[body] @ local

    def _add_suspension(self) -> None:
        """Torsion springs (and anti-roll bars) as Exudyn connectors preloaded with their
        static moments; linear springs and dampers (and the linear parts of air springs) as
        compiled linear elements, bump stops and the nonlinear elements
        (:mod:`railexu.model.suspension_forces`) collected for the compiled force function,
        with one internal coordinate per series spring. Every element's forces act at the
        midpoint of its two ends (no couple when they separate, ``docs/suspension.md``)."""
        self.bump_stops: list[tuple] = []
        self.bump_stop_axlebox: list[tuple[bool, bool]] = []
        spring_dampers: list[SpringDamper] = []
        for el in self.vehicle.suspension:
            lin = linear_part(el)
            if isinstance(lin, SpringDamper):
                spring_dampers.append(lin)
            elif isinstance(lin, TorsionSpring):
                self._add_torsion_spring(lin)
            elif isinstance(el, BumpStop):
                a, b = el.bodies
                box = self._element_on_axlebox(el)
                la, ga = self._local_point(a, el.position_m, box[0])
                lb, gb = self._local_point(b, el.position_m, box[1])
                axis = "xyz".index(el.direction)
                self.bump_stops.append((a, b, la, lb, axis, el, float(gb[axis] - ga[axis])))
                self.bump_stop_axlebox.append(box)
        try:
            self.kernel_elements = kernel_elements(self.vehicle, self.statics)
        except InputError as exc:
            raise ModelError(str(exc)) from exc
        for lin in spring_dampers:
            self.kernel_elements += self._compiled_spring_damper(lin)
        self._add_internal_coordinates()

    def _element_on_axlebox(self, el) -> tuple[bool, bool]:
        """Whether the element's point on its first and on its second body is on a wheelset's
        axlebox."""
        return tuple(self._on_axlebox(b) for b in el.bodies)

    def _compiled_spring_damper(self, el: SpringDamper) -> list[KernelElement]:
        """A linear spring-damper as compiled linear elements, one per axis with stiffness or
        damping: its equal and opposite forces act at the midpoint of its two ends (an Exudyn
        Cartesian spring-damper applies them at its two markers and leaves the couple
        ``(p_b - p_a) x F`` of separated ends unbalanced), and on a wheelset through its
        axlebox (``docs/suspension.md``). Preloaded with its static force
        (``F = k (d + d_s)``, ``d_s = -f_b / k``)."""
        f_b = np.asarray(self.statics.element_forces[el.name], dtype=float)
        out = []
        for axis in range(3):
            k = float(el.stiffness_N_per_m[axis])
            c = float(el.damping_N_s_per_m[axis])
            if k == 0.0 and c == 0.0:
                continue
            out.append(
                KernelElement(
                    f"{el.name}_{'xyz'[axis]}", bodies=el.bodies,
                    position_m=el.position_m, axis=axis, parallel_stiffness_N_per_m=k,
                    parallel_damping_N_s_per_m=c,
                    static_deflection_m=-f_b[axis] / k if k > 0.0 else 0.0,
                )
            )  # fmt: skip
        return out

    def _add_internal_coordinates(self) -> None:
        """One Exudyn ``NodeGenericODE2`` with the internal coordinates of the series springs
        (Maxwell dampers, stick-slip friction, air-spring reservoirs) and their small masses
        ``m_i = k_s / omega_i^2`` (:mod:`railexu.model.suspension_forces`)."""
        from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2

        masses = [e.internal_mass_kg() for e in self.kernel_elements if e.internal]
        self.internal_node: int | None = None
        if not masses:
            return
        n = len(masses)
        start = [0.0] * n if self.start_internal_m is None else list(self.start_internal_m)
        self.internal_node = self.mbs.AddNode(
            NodeGenericODE2(
                referenceCoordinates=[0.0] * n,
                initialCoordinates=start,
                initialCoordinates_t=[0.0] * n,
                numberOfODE2Coordinates=n,
            )
        )
        self.mbs.AddObject(
            ObjectGenericODE2(nodeNumbers=[self.internal_node], massMatrix=np.diag(masses))
        )

    def _suspension_kernel_arrays(self, slot: dict[int, int]):
        """``(se_int, se_real, se_table)`` of the nonlinear elements for :class:`KernelData`;
        the internal coordinates follow the bodies' and the rail masses' coordinates."""
        local = {}
        axlebox = {}
        for e in self.kernel_elements:
            a, b = e.bodies
            box = self._element_on_axlebox(e)
            la, ga = self._local_point(a, e.position_m, box[0])
            lb, gb = self._local_point(b, e.position_m, box[1])
            local[e.name] = ((la, lb), float(gb[e.axis] - ga[e.axis]))
            axlebox[e.name] = box
        body_slot = {name: slot[node] for name, node in self.node.items() if node in slot}
        start = 6 * len(slot) + 4 * len(self.rail_node)
        return kernel_arrays(self.kernel_elements, body_slot, local, start, axlebox)

    def _add_torsion_spring(self, el: TorsionSpring) -> None:
        from exudyn.itemInterface import MarkerBodyRigid, ObjectConnectorRigidBodySpringDamper

        mbs = self.mbs
        a, b = el.bodies
        if {a, b} & {w.name for w in self.vehicle.wheelsets}:
            raise ModelError(f"torsion spring {el.name}: cannot act on a spinning wheelset")
        la, _ = self._local_point(a, el.position_m)
        lb, _ = self._local_point(b, el.position_m)
        ma = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[a], localPosition=la))
        mb = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[b], localPosition=lb))
        axis = "xyz".index(el.axis)
        stiff = np.zeros((6, 6))
        damp = np.zeros((6, 6))
        stiff[3 + axis, 3 + axis] = el.stiffness_N_m_per_rad
        damp[3 + axis, 3 + axis] = el.damping_N_m_s_per_rad
        offset = np.zeros(6)
        if el.stiffness_N_m_per_rad > 0.0:
            offset[3 + axis] = self.statics.element_forces[el.name] / el.stiffness_N_m_per_rad
        mbs.AddObject(
            ObjectConnectorRigidBodySpringDamper(
                markerNumbers=[ma, mb], stiffness=stiff, damping=damp, offset=list(offset)
            )
        )

    def _add_loads(self) -> None:
        from exudyn.itemInterface import LoadForceVector, MarkerBodyPosition

        for load in self.vehicle.loads:
            local, _ = self._local_point(load.body, load.position_m)
            m = self.mbs.AddMarker(
                MarkerBodyPosition(bodyNumber=self.body[load.body], localPosition=local)
            )
            self.mbs.AddLoad(LoadForceVector(markerNumber=m, loadVector=list(load.force_N)))

    def _add_vertical_loads(self) -> None:
        """On a track with a vertical profile, a force and a torque on every body and wheelset
        for its gradient and vertical curvature (:mod:`railexu.model.vertical_forces`), set at
        the start and again every :data:`VERTICAL_UPDATE_M` of run (:meth:`update_vertical_loads`
        from :meth:`begin_step`)."""
        from exudyn.itemInterface import LoadForceVector, LoadTorqueVector, MarkerBodyRigid

        self.vertical_forces: VerticalForces | None = None
        if self.vertical is None:
            return
        names = list(self.node)
        wheelsets = set(self.wheelset_names())
        # a wheelset's axle is its body's third axis (its spin inertia is about the lateral)
        pitch = [self.inertia[n][1][2 if n in wheelsets else 1] for n in names]
        self.vertical_forces = VerticalForces(
            self.vertical, np.array([self.inertia[n][0] for n in names]), np.array(pitch),
            self.vehicle.gravity_m_per_s2,
        )  # fmt: skip
        self.vertical_loads: list[tuple[str, int, int]] = []
        for name in names:
            m = self.mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[name]))
            force = self.mbs.AddLoad(LoadForceVector(markerNumber=m, loadVector=[0.0] * 3))
            torque = self.mbs.AddLoad(
                LoadTorqueVector(markerNumber=m, loadVector=[0.0] * 3, bodyFixed=False)
            )
            self.vertical_loads.append((name, force, torque))

    def update_vertical_loads(self, t: float = 0.0) -> None:
        """Set the vertical profile's forces and torques from the current state at time ``t``
        (each body's distance along the track and forward speed; the vehicle frame's cant roll
        on curved track): constant until the vehicle has run :data:`VERTICAL_UPDATE_M` further
        (:meth:`begin_step`), a few centimetres of a profile that changes over metres."""
        data = self.mbs.systemData
        q = data.GetODE2Coordinates()
        qt = data.GetODE2Coordinates_t()
        s = np.array([self.centre[n][0] + q[self.ltg[n][0]] for n, _, _ in self.vertical_loads])
        v = np.array([qt[self.ltg[n][0]] for n, _, _ in self.vertical_loads])
        roll = 0.0
        if self.curved:
            from railexu.track.alignment import TAB_FROLL

            start, step, tab = self.align_sampled
            u = (self.kernel.frame[0] - start) / step
            roll = float(np.interp(u, np.arange(tab.shape[0]), tab[:, TAB_FROLL]))
        forces, torques = self.vertical_forces.loads(s, v, roll)
        self._vertical_next_time_s = t + VERTICAL_UPDATE_M / max(float(np.max(np.abs(v))), 0.5)
        for k, (_, force, torque) in enumerate(self.vertical_loads):
            self.mbs.SetLoadParameter(force, "loadVector", forces[k].tolist())
            self.mbs.SetLoadParameter(torque, "loadVector", torques[k].tolist())

    def _sample_track(self) -> None:
        """Irregularities and design geometry sampled along the whole run.

        The irregularities' distance 0 is where the leading wheelset starts, so that every
        wheelset starts on undisturbed rails (the static state it was pressed into) and meets
        the faded-in irregularities as it runs."""
        veh = self.vehicle
        x_lead = self.x_start_m + max(w.position_x_m for w in veh.wheelsets)
        self.irregularity_origin_m = x_lead
        self.irregularities = self.track.irregularities(self.distance_hint + 20.0)
        sampled = self.irregularities.sampled(0.05)
        self.irr_start = x_lead + sampled.start_m
        self.irr_step = sampled.step_m
        self.irr_values = np.ascontiguousarray(sampled.values)
        self.irr_slopes = np.ascontiguousarray(sampled.slopes)
        length = max(self.vehicle_length_m(), 1.0)
        self.align_sampled = self.alignment.table(
            -length - 10.0, self.x_start_m + self.distance_hint + 2.0 * length + 20.0
        )

    def vehicle_length_m(self) -> float:
        """Longitudinal extent of the bodies' and wheelsets' centres [m]."""
        xs = [b.position_m[0] for b in self.vehicle.bodies]
        xs += [w.position_x_m for w in self.vehicle.wheelsets]
        return float(max(xs) - min(xs))

    def _add_rail_masses(self) -> None:
        """Elastic track: under each wheelset a node of 4 coordinates (left rail lateral and
        vertical, right rail lateral and vertical, track frame) with the co-running rail mass,
        stiffness and damping to the ground (:mod:`railexu.track.elastic`)."""
        from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2

        self.rail_node: dict[str, int] = {}
        et = getattr(self.track, "elastic", None)
        if et is None:
            return
        mass = np.eye(4) * et.rail_mass_kg
        k_y, k_z = et.lateral_stiffness_N_per_m, et.vertical_stiffness_N_per_m
        c_y, c_z = et.lateral_damping_N_s_per_m, et.vertical_damping_N_s_per_m
        stiffness = np.diag([k_y, k_z, k_y, k_z])
        damping = np.diag([c_y, c_z, c_y, c_z])
        for ws in self.wheelset_names():
            n = self.mbs.AddNode(
                NodeGenericODE2(
                    referenceCoordinates=[0.0] * 4,
                    initialCoordinates=[0.0] * 4,
                    initialCoordinates_t=[0.0] * 4,
                    numberOfODE2Coordinates=4,
                )
            )
            self.mbs.AddObject(
                ObjectGenericODE2(
                    nodeNumbers=[n], massMatrix=mass, stiffnessMatrix=stiffness,
                    dampingMatrix=damping,
                )
            )  # fmt: skip
            self.rail_node[ws] = n

    def wheelset_names(self) -> list[str]:
        """Names of the wheelsets in the vehicle file's order."""
        return [w.name for w in self.vehicle.wheelsets]

    def _add_contact_element(self) -> None:
        """One ObjectGenericODE2 over the wheelsets (and the bodies joined by bump stops; on
        curved track all bodies, for the frame's inertial forces) with the compiled forces."""
        import exudyn as exu
        from exudyn.itemInterface import ObjectGenericODE2

        mbs = self.mbs
        wheelset_names = [w.name for w in self.vehicle.wheelsets]
        ode_nodes = [self.node[n] for n in wheelset_names]
        extra = [n for a, b, *_ in self.bump_stops for n in (a, b)]
        extra += [n for e in self.kernel_elements for n in e.bodies]
        if self.curved:
            extra += list(self.node)
        for name in extra:
            if self.node[name] not in ode_nodes:
                ode_nodes.append(self.node[name])
        slot = {node: i for i, node in enumerate(ode_nodes)}
        n_internal = sum(e.internal for e in self.kernel_elements)
        n_coords = 6 * len(ode_nodes) + 4 * len(self.rail_node) + n_internal
        ode_nodes += [self.rail_node[n] for n in wheelset_names if n in self.rail_node]
        if self.internal_node is not None:
            ode_nodes.append(self.internal_node)
        self.ode_nodes = ode_nodes
        self._out = np.zeros(n_coords)
        n_ws = len(wheelset_names)
        self.points = np.zeros((n_ws, 2, K.MAX_POINTS, K.N_POINT_FIELDS))
        self.ws_force = np.zeros((n_ws, 6))
        self.kernel = self._kernel_data(slot)
        data = self.kernel
        out = self._out
        points = self.points
        ws_force = self.ws_force
        set_time = self.set_time if self.curved else None
        # the compiled functions, replaced by their machine-code entries in warm_up()
        self._compiled = compiled = {"forces": generalized_forces, "jacobian": jacobian}
        #: threads of the wheelsets' contacts in the force function (railexu.runtime.threads), and
        #: the simulated time from which they were used (None: never)
        self.contact_threads = 1
        self.contact_threads_from_s: float | None = None
        self._threaded: tuple | None = None  # (threads, compiled entry) prepared by warm_up

        #: calls of the force function and the seconds spent in it (outputs, benchmarks)
        self.force_calls = counter = np.zeros(2)
        clock = time.perf_counter

        # Exudyn passes the coordinates as lists: np.fromiter with the count converts one in
        # half the time of np.array (0.45 against 0.93 us for 42 numbers, twice per call)
        as_array = np.fromiter

        # with threads: the measured choice between the threaded and the one-thread function
        # (railexu.runtime.thread_choice), fed the wall time of every WINDOW_CALLS calls
        self._choice_box = choice_box = [None]
        window = [0, 0.0]

        def contact_forces(mbs_, t, item, q, q_t):
            start = clock()
            if set_time is not None:
                set_time(t)
            compiled["forces"](
                as_array(q, float, n_coords), as_array(q_t, float, n_coords), data, out, points,
                ws_force,
            )  # fmt: skip
            elapsed = clock() - start
            counter[0] += 1.0
            counter[1] += elapsed
            chooser = choice_box[0]
            if chooser is not None:
                window[0] += 1
                window[1] += elapsed
                if window[0] >= WINDOW_CALLS:
                    compiled["forces"] = chooser.window_done(window[1], window[0])
                    window[0] = 0
                    window[1] = 0.0
            return out

        jac = np.zeros((n_coords, n_coords))
        jac_points = np.zeros_like(points)
        jac_force = np.zeros_like(ws_force)
        self._jacobian_arrays = (jac, jac_points, jac_force)

        def contact_jacobian(mbs_, t, item, q, q_t, f_q, f_v):
            if set_time is not None:
                set_time(t)
            compiled["jacobian"](
                as_array(q, float, n_coords), as_array(q_t, float, n_coords), data, float(f_q),
                float(f_v), jac, jac_points, jac_force,
            )  # fmt: skip
            return jac

        self._user_function = contact_forces
        self._jacobian_function = contact_jacobian
        mbs.AddObject(
            ObjectGenericODE2(
                nodeNumbers=ode_nodes,
                # no mass of its own: an empty matrix container, which Exudyn skips when it
                # assembles the mass matrix (a dense zero matrix was added at every update)
                massMatrix=exu.MatrixContainer(),
                forceUserFunction=contact_forces,
                jacobianUserFunction=contact_jacobian,
            )
        )

    def _kernel_data(self, slot: dict[int, int]) -> KernelData:
        """The named inputs of the compiled force functions."""
        mbs = self.mbs
        wheelset_names = [w.name for w in self.vehicle.wheelsets]
        qref = np.concatenate(
            [np.asarray(mbs.GetNodeParameter(n, "referenceCoordinates"), float)
             for n in self.ode_nodes]
        )  # fmt: skip
        bs_int = np.zeros((len(self.bump_stops), 4), dtype=np.int64)
        bs_real = np.zeros((len(self.bump_stops), BS_NREAL))
        for i, (a, b, la, lb, axis, el, d0) in enumerate(self.bump_stops):
            box_a, box_b = self.bump_stop_axlebox[i]
            bs_int[i] = [slot[self.node[a]], slot[self.node[b]], int(box_a), int(box_b)]
            bs_real[i, 0:3] = la
            bs_real[i, 3:6] = lb
            bs_real[i, 6] = axis
            bs_real[i, 7] = el.clearance_m
            bs_real[i, 8] = el.stiffness_N_per_m
            bs_real[i, 9] = el.damping_N_s_per_m
            bs_real[i, 10] = d0
        names = list(self.node) if self.curved else []
        n_rigid = len(slot)
        rail_index = np.array(
            [6 * n_rigid + 4 * i for i in range(len(self.rail_node))], dtype=np.int64
        )
        se_int, se_real, se_table = self._suspension_kernel_arrays(slot)
        frame = np.zeros(FR_SIZE)
        frame[:] = [self.frame_start_m, self.speed, -self.deceleration,
                    0.5 * self.alignment.cant_base_m, self.vehicle.gravity_m_per_s2]  # fmt: skip
        align_start, align_step, align = self.align_sampled
        return KernelData(
            qref=qref,
            ws_slots=np.array([slot[self.node[n]] for n in wheelset_names], dtype=np.int64),
            wtab=self.wtab, wtab_index=self.wtab_index, winfo=self.winfo, rtab=self.rtab,
            rinfo=self.rinfo, htab=self.htab, ktab=self.ktab, params=self.params,
            irr_start=float(self.irr_start), irr_step=float(self.irr_step),
            irr_values=self.irr_values, irr_slopes=self.irr_slopes,
            bs_int=bs_int, bs_real=bs_real,
            curved=bool(self.curved), align_start=align_start, align_step=align_step,
            align=align, frame=frame,
            body_slots=np.array([slot[self.node[n]] for n in names], dtype=np.int64),
            body_mass=np.array([self.inertia[n][0] for n in names], dtype=float),
            body_inertia=np.array([self.inertia[n][1] for n in names], dtype=float).reshape(-1, 3),
            ws_local=np.zeros((len(wheelset_names), WL_SIZE)),
            rail_index=rail_index,
            rail_preload=np.ascontiguousarray(self.statics.wheel_loads_N, dtype=float),
            se_int=se_int, se_real=se_real, se_table=se_table, **self.sc_fields,
        )  # fmt: skip

    def set_time(self, t: float) -> None:
        """Move the vehicle frame to time ``t`` (distance, speed and acceleration along the
        track of the speed body's nominal motion; with free motion, of the frame that follows
        the speed body, :meth:`begin_step`)."""
        frame = self.kernel.frame
        if self.traction is not None:
            t0, s0, v0, a0 = self._frame_step
            dt = t - t0
            frame[0] = s0 + v0 * dt + 0.5 * a0 * dt * dt
            frame[1] = v0 + a0 * dt
            frame[2] = a0
        elif self.profile is not None:
            frame[0] = self.frame_start_m + self.profile.distance_at(t)
            frame[1] = self.profile.speed_at(t)
            frame[2] = self.profile.acceleration_at(t)
        else:
            a = self.deceleration
            frame[0] = self.frame_start_m + self.speed * t - 0.5 * a * t * t
            frame[1] = self.speed - a * t

    def _add_speed_constraint(self) -> None:
        """Constant forward speed of one body: a velocity-level constraint on its first
        coordinate (distance along the track), whose force is the traction; its offset
        follows a speed profile (:meth:`begin_step`). With traction demands instead, the
        forward motion is free: no constraint, torques on the wheelsets
        (:meth:`_add_traction`)."""
        if self.traction is not None:
            self.speed_constraint = None
            self._add_traction()
            return
        from exudyn.itemInterface import (
            MarkerNodeCoordinate,
            NodePointGround,
            ObjectConnectorCoordinate,
        )

        mbs = self.mbs
        ground = mbs.AddNode(NodePointGround(referenceCoordinates=[0.0, 0.0, 0.0]))
        m0 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
        m1 = mbs.AddMarker(
            MarkerNodeCoordinate(nodeNumber=self.node[self.vehicle.speed_body], coordinate=0)
        )
        self.speed_constraint = mbs.AddObject(
            ObjectConnectorCoordinate(markerNumbers=[m0, m1], velocityLevel=True, offset=self.speed)
        )

    def _add_traction(self) -> None:
        """Free forward motion: a torque about the axle of each wheelset (traction on the driven
        ones minus the tread brakes' ``force x nominal radius`` on every one), set at the start
        of every step (:meth:`begin_step`), and its reaction on the body the wheelset is
        suspended from (the motor and the brake rigging sit there); a wheelset suspended from
        nothing (a single wheelset) takes the torque from outside the vehicle."""
        from exudyn.itemInterface import LoadTorqueVector, MarkerBodyRigid

        mbs = self.mbs
        names = self.wheelset_names()
        driven = set(self.traction.driven(names))
        self.traction_loads: list[tuple[int, int | None, bool, float]] = []
        for ws in self.vehicle.wheelsets:
            m = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[ws.name]))
            load = mbs.AddLoad(LoadTorqueVector(markerNumber=m, loadVector=[0.0, 0.0, 0.0],
                                                bodyFixed=True))  # fmt: skip
            parent = self._parent_body(ws.name)
            reaction = None
            if parent is not None:
                mp = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[parent]))
                reaction = mbs.AddLoad(LoadTorqueVector(markerNumber=mp, bodyFixed=True,
                                                        loadVector=[0.0, 0.0, 0.0]))  # fmt: skip
            radius = 0.5 * (ws.nominal_radius_m + (ws.radius_right_m or ws.nominal_radius_m))
            self.traction_loads.append((load, reaction, ws.name in driven, radius))
        s0 = self.frame_start_m
        self._frame_step = (0.0, s0, self.speed, 0.0)
        self.axle_torques_N_m = np.zeros(len(names))
        self.stop_reason = ""

    def _parent_body(self, wheelset: str) -> str | None:
        """The body a wheelset is suspended from (the other body of its first suspension
        element), or None."""
        for el in self.vehicle.suspension:
            if wheelset in el.bodies:
                other = [b for b in el.bodies if b != wheelset]
                if other and other[0] not in self.wheelset_names():
                    return other[0]
        return None

    def _speed_body_state(self) -> tuple[float, float, float]:
        """(distance along the track, speed, acceleration) of the speed body's centre now."""
        i = self.ltg[self.vehicle.speed_body][0]
        data = self.mbs.systemData
        x = float(self.mbs.GetNodeParameter(self.node[self.vehicle.speed_body],
                                            "referenceCoordinates")[0])  # fmt: skip
        return (
            x + float(data.GetODE2Coordinates()[i]),
            float(data.GetODE2Coordinates_t()[i]),
            float(data.GetODE2Coordinates_tt()[i]),
        )

    def speed_at(self, t: float) -> float:
        """Forward speed at time ``t`` [m/s]: prescribed, or (free motion) the speed body's
        now."""
        if self.traction is not None:
            return self._speed_body_state()[1]
        if self.profile is not None:
            return self.profile.speed_at(t)
        return self.speed - self.deceleration * t

    def distance_at(self, t: float) -> float:
        """Distance run at time ``t`` [m]: prescribed, or (free motion) the speed body's now."""
        if self.traction is not None:
            return self._speed_body_state()[0] - self.frame_start_m
        if self.profile is not None:
            return self.profile.distance_at(t)
        return self.speed * t - 0.5 * self.deceleration * t * t

    def begin_step(self, t_end: float, h: float, distance_m: float = math.inf) -> bool:
        """Prepare the step that ends at ``t_end`` (Exudyn's pre-step function): the speed it
        must reach (prescribed motion: the constraint's offset, the creepages' normalising
        speed), or (free motion) the torques, the normalising speed and the frame's motion.
        Returns False when a free run has covered ``distance_m`` or stopped."""
        if self.vertical_forces is not None and t_end - h >= self._vertical_next_time_s:
            self.update_vertical_loads(t_end - h)
        if self.traction is None:
            v_next = self.speed_at(t_end)
            self.mbs.SetObjectParameter(self.speed_constraint, "offset", v_next)
            self.params[K.P_SPEED] = v_next  # creepages are normalised by the current speed
            return True
        return self._begin_free_step(t_end - h, t_end, distance_m)

    def _begin_free_step(self, t0: float, t1: float, distance_m: float) -> bool:
        s_b, v_b, a_b = self._speed_body_state()
        distance = s_b - self.frame_start_m
        if distance >= distance_m:
            return False
        if v_b < MIN_FREE_SPEED_M_PER_S:
            self.stop_reason = (
                f"the vehicle stopped (speed {v_b:.2f} m/s < {MIN_FREE_SPEED_M_PER_S:g} m/s) "
                f"at {distance:.1f} m"
            )
            return False
        # creepages normalised by the speed expected at the end of the step
        self.params[K.P_SPEED] = max(v_b + a_b * (t1 - t0), MIN_FREE_SPEED_M_PER_S)
        self._set_torques(t0, distance)
        if self.curved:
            self._follow(t0, s_b, v_b)
        return True

    def _set_torques(self, t: float, distance: float) -> None:
        """Traction on the driven wheelsets minus the tread brakes on all, about each axle,
        constant over the step; the reactions on the bodies they hang from."""
        tr = self.traction
        torque = tr.torque_N_m.value(t, distance)
        brake = tr.brake_force_N.value(t, distance)
        qt = self.mbs.systemData.GetODE2Coordinates_t()
        for k, (load, reaction, driven, radius) in enumerate(self.traction_loads):
            spin = qt[self.ltg[self.wheelset_names()[k]][5]]
            total = (torque if driven else 0.0) - 2.0 * brake * radius * float(np.sign(spin))
            self.axle_torques_N_m[k] = total
            # the axle is the wheelset body's third axis; the parent body's lateral is its y
            self.mbs.SetLoadParameter(load, "loadVector", [0.0, 0.0, total])
            if reaction is not None:
                self.mbs.SetLoadParameter(reaction, "loadVector", [0.0, -total, 0.0])

    def _follow(self, t0: float, s_b: float, v_b: float) -> None:
        """Steer the vehicle frame (curved track) towards the speed body over the next step:
        its distance and speed stay continuous (the coordinates are relative to it), its
        acceleration is constant within the step, a critically damped follower of the speed
        body (natural frequency :data:`FRAME_FOLLOW_RAD_PER_S`)."""
        t_prev, s_prev, v_prev, a_prev = self._frame_step
        dt = t0 - t_prev
        s_f = s_prev + v_prev * dt + 0.5 * a_prev * dt * dt
        v_f = v_prev + a_prev * dt
        w = FRAME_FOLLOW_RAD_PER_S
        a_f = 2.0 * w * (v_b - v_f) + w * w * (s_b - s_f)
        self._frame_step = (t0, s_f, v_f, a_f)

    def _name_of(self, node: int) -> str:
        return next(k for k, v in self.node.items() if v == node)

    def warm_up(self, threads_now: bool = True) -> None:
        """Call the compiled force and Jacobian functions once at the initial state, so that
        their just-in-time compilation (first run after installation) or loading from numba's
        cache happens before the integration starts and is not counted in its timing.

        Args:
            threads_now: put the wheelsets' contacts on threads at once where
                :func:`railexu.runtime.threads.contact_threads` allows it; False: prepare them and
                wait for :meth:`start_threads` (the same results either way).
        """
        q = np.array(self.mbs.systemData.GetODE2Coordinates()[self.object_ltg], dtype=float)
        qt = np.array(self.mbs.systemData.GetODE2Coordinates_t()[self.object_ltg], dtype=float)
        if self.curved:
            self.set_time(0.0)
        jac, jac_points, jac_force = self._jacobian_arrays
        self._compiled["jacobian"] = compiled_entry(
            jacobian, q, qt, self.kernel, 1.0, 0.0, jac, jac_points, jac_force
        )
        args = (q, qt, self.kernel, self._out, self.points, self.ws_force)
        planned = contact_threads(self.points.shape[0])
        self._threaded = None
        self._serial_entry = compiled_entry(generalized_forces, *args)
        self._compiled["forces"] = self._serial_entry
        if planned > 1:
            use_threads(planned)
            self._threaded = (planned, compiled_entry(generalized_forces_threaded, *args))
        if planned > 1 and threads_now:
            self.start_threads(0.0)

    @property
    def threads_pending(self) -> bool:
        """Threads were prepared by :meth:`warm_up` and not started yet."""
        return self._threaded is not None and self.contact_threads == 1

    def start_threads(self, t: float) -> None:
        """From now on (simulated time ``t`` [s]) the wheelsets' contacts run on the threads
        that :meth:`warm_up` prepared (nothing happens if it prepared none)."""
        if self._threaded is None:
            return
        self.contact_threads, threaded = self._threaded
        self._compiled["forces"] = threaded
        self._choice_box[0] = ThreadChoice(self._serial_entry, threaded)
        self.contact_threads_from_s = t

    @property
    def thread_choice(self) -> ThreadChoice | None:
        """The measured choice between the threaded and the one-thread force function, once
        the threads have started (None before and without threads)."""
        return self._choice_box[0]

    def evaluate(self, q_all: np.ndarray, qt_all: np.ndarray, t: float, out, points, ws_force):
        """Evaluate the compiled forces at a full system state and time ``t`` into the given
        arrays (for outputs); ``self.kernel.ws_local`` then holds the wheelsets' track-relative
        pose."""
        if self.curved:
            self.set_time(t)
        generalized_forces(
            q_all[self.object_ltg], qt_all[self.object_ltg], self.kernel, out, points, ws_force
        )
