"""Build the Exudyn multibody system of a vehicle on a track.

Design (measured in ``docs/dev/exudyn-api.md``):

- every body and wheelset is an Exudyn rigid body on a ``NodeRigidBodyRxyz`` node (Tait-Bryan
  angles); a wheelset's axle is its body's third axis, so its spin is the last angle, the contact
  forces do not depend on it and the Newton Jacobian stays valid for thousands of steps;
- linear suspension elements are Exudyn connectors (Cartesian spring-dampers, rigid-body
  spring-dampers for torsion), preloaded with their static forces (:mod:`railexu.statics`) so
  that the vehicle starts in equilibrium at its nominal geometry;
- all wheel-rail forces (and bump stops) come from one ``ObjectGenericODE2`` with a zero mass
  matrix whose force user function calls one compiled function for all wheelsets
  (:func:`railexu.forces.generalized_forces`); Exudyn differentiates it numerically for the
  Jacobian, creep damping included;
- a velocity-level coordinate constraint holds the forward speed of one body (the car body by
  default): the traction needed to run at constant speed;
- the coordinates are those of a vehicle frame that runs along the track's centre line with
  the speed body and turns with the track's heading (:mod:`railexu.forces`, ``docs/curving.md``):
  the first coordinate of a node is the distance along the track, the others its lateral and
  vertical position and its angles relative to the local track direction, so no angle grows with
  the heading (a 300 m curve over 600 m turns the track by 115 degrees; the Tait-Bryan angles stay
  small) and the frame's inertial forces are added in the compiled force function; on straight
  track the frame does not turn and these are exactly the absolute coordinates;
- wheelsets spin freely under their creep forces.
"""

from __future__ import annotations

import math

import numpy as np

from .alignment import Alignment, straight_alignment
from .contact import kernel as K
from .contact.evaluation import WheelsetContactModel, rail_arrays, wheel_arrays
from .contact.hertz import hertz_table
from .contact.kalker import kalker_table_for_poisson
from .contact.placement import WheelsetGeometry, symmetric_wheelset
from .contact.placement import wheelset_geometry as placed_wheelset
from .contact.quasistatic import free_rolling_spin_rate, press_wheelset
from .errors import InputError
from .forces import BS_NREAL, FR_SIZE, WL_SIZE, KernelData, generalized_forces, jacobian
from .statics import StaticSolution, attachment_point, static_equilibrium
from .suspension_forces import kernel_arrays, kernel_elements
from .track import Track
from .vehicle import BumpStop, SpringDamper, TorsionSpring, Vehicle, Wheelset, linear_part

#: Distance of the rearmost wheelset from the start of the track at t = 0 [m].
START_MARGIN_M = 1.0


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
            track follows it; :class:`railexu.run_settings.RunSettings`).
    """

    def __init__(
        self,
        vehicle: Vehicle,
        track: Track,
        speed_m_per_s: float,
        initial_lateral_m: float = 0.0,
        distance_m: float = 100.0,
        deceleration_m_per_s2: float = 0.0,
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
        self.alignment: Alignment = getattr(track, "alignment", None) or straight_alignment()
        self.curved = not self.alignment.is_straight
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
        self.initial_wheelsets = []
        self.initial_spin_rates: list[float] = []
        for ws, geom, loads in zip(
            vehicle.wheelsets, self.geometries, self.statics.wheel_loads_N, strict=True
        ):
            cm = WheelsetContactModel(geom, vehicle.contact, self.speed)
            try:
                st = press_wheelset(cm, self.initial_lateral_m, 0.0, (loads[0], loads[1]))
            except RuntimeError as exc:
                raise ModelError(f"wheelset {ws.name}: {exc}") from exc
            self.initial_wheelsets.append(st)
            self.initial_spin_rates.append(
                free_rolling_spin_rate(cm, st.lateral_m, st.vertical_m, st.roll_rad, 0.0)
            )

        # --- the Exudyn system
        self.SC = exu.SystemContainer()
        self.mbs = self.SC.AddSystem()
        self._build()

    # ------------------------------------------------------------------------------------------
    def _pack_tables(self) -> None:
        n_ws = len(self.geometries)
        width = self.contact_params.curvature_smoothing_m
        wheel = [
            [wheel_arrays(g.left, width), wheel_arrays(g.right, width)] for g in self.geometries
        ]
        n_max = max(t.shape[0] for pair in wheel for t, _ in pair)
        self.wtab = np.zeros((n_ws, 2, n_max, 4))
        self.winfo = np.zeros((n_ws, 2, 5))
        for i, pair in enumerate(wheel):
            for s, (tab, info) in enumerate(pair):
                self.wtab[i, s, : tab.shape[0]] = tab
                self.winfo[i, s] = info
        rails = [
            rail_arrays(self.geometries[0].left, width),
            rail_arrays(self.geometries[0].right, width),
        ]
        m_max = max(t.shape[0] for t, _ in rails)
        self.rtab = np.zeros((2, m_max, 4))
        self.rinfo = np.zeros((2, 3))
        for s, (tab, info) in enumerate(rails):
            self.rtab[s, : tab.shape[0]] = tab
            self.rinfo[s] = info
        self.htab = hertz_table()
        self.ktab = kalker_table_for_poisson(self.contact_params.poisson)

    # ------------------------------------------------------------------------------------------
    def _build(self) -> None:
        """The Exudyn system in named steps: bodies, wheelsets, suspension, loads, the contact
        element (with the sampled track), the speed constraint."""
        veh = self.vehicle
        self.x_start_m = START_MARGIN_M - min(w.position_x_m for w in veh.wheelsets)
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

    def _centre_line_offset(self, x: float) -> float:
        """Lateral position of the track centre line in the vehicle frame at the start, at the
        distance ``x`` along the track [m] (zero on straight track)."""
        if not self.curved:
            return 0.0
        a = self.alignment
        s0 = self.frame_start_m
        x0, y0 = a.position(s0)
        x1, y1 = a.position(x)
        psi = float(a.heading(s0))
        return float(-(x1 - x0) * math.sin(psi) + (y1 - y0) * math.cos(psi))

    def _add_rigid_body(self, name, mass, inertia, centre, rotation, velocities=None) -> None:
        import exudyn as exu
        from exudyn.rigidBodyUtilities import RigidBodyInertia

        res = self.mbs.CreateRigidBody(
            inertia=RigidBodyInertia(mass, np.diag(inertia)),
            nodeType=exu.NodeType.RotationRxyz,
            referencePosition=list(centre),
            referenceRotationMatrix=rotation,
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
        """Car bodies and bogie frames at their nominal positions (plus the initial offset)."""
        y0 = self.initial_lateral_m
        for b in self.vehicle.bodies:
            x = self.x_start_m + b.position_m[0]
            y = b.position_m[1] + y0 + self._centre_line_offset(x)
            c = np.array([x, y, b.position_m[2]])
            self._add_rigid_body(b.name, b.mass_kg, b.inertia_kg_m2, c, np.eye(3))

    def _add_wheelsets(self) -> None:
        """Wheelsets pressed onto the rails, spinning at their free-rolling rate; the axle is
        the body's third axis (spin is the last angle)."""
        from exudyn.rigidBodyUtilities import RotationMatrixX

        V = self.speed
        for ws, st, spin_rate in zip(
            self.vehicle.wheelsets, self.initial_wheelsets, self.initial_spin_rates, strict=True
        ):
            x = self.x_start_m + ws.position_x_m
            c = np.array([x, st.lateral_m + self._centre_line_offset(x), st.vertical_m])
            rot = RotationMatrixX(st.roll_rad - 0.5 * math.pi)
            # free rolling: the spin at which the wheelset carries no longitudinal creep force
            self._add_rigid_body(
                ws.name, ws.mass_kg, ws.inertia_kg_m2, c, rot, [V, 0, 0, 0, 0, spin_rate]
            )

    def _local_point(self, body: str, p_vehicle) -> tuple[np.ndarray, np.ndarray]:
        """(local position on the body, initial global position) of an attachment point."""
        veh = self.vehicle
        p = attachment_point(veh, body, p_vehicle)
        if body in {w.name for w in veh.wheelsets}:
            local = np.array([0.0, 0.0, p[1]])  # on the axle (body z)
        else:
            local = np.array([p[0], p[1], p[2]]) - np.asarray(
                next(b.position_m for b in veh.bodies if b.name == body)
            )
        return local, self.centre[body] + self.rotation[body] @ local

    def _add_suspension(self) -> None:
        """Linear springs and dampers (and the linear parts of air springs, anti-roll bars) as
        Exudyn connectors preloaded with their static forces; bump stops and the nonlinear
        elements (:mod:`railexu.suspension_forces`) are collected for the compiled force
        function, with one internal coordinate per series spring."""
        self.bump_stops: list[tuple] = []
        for el in self.vehicle.suspension:
            lin = linear_part(el)
            if isinstance(lin, SpringDamper):
                self._add_spring_damper(lin)
            elif isinstance(lin, TorsionSpring):
                self._add_torsion_spring(lin)
            elif isinstance(el, BumpStop):
                a, b = el.bodies
                la, ga = self._local_point(a, el.position_m)
                lb, gb = self._local_point(b, el.position_m)
                axis = "xyz".index(el.direction)
                self.bump_stops.append((a, b, la, lb, axis, el, float(gb[axis] - ga[axis])))
        try:
            self.kernel_elements = kernel_elements(self.vehicle, self.statics)
        except InputError as exc:
            raise ModelError(str(exc)) from exc
        self._add_internal_coordinates()

    def _add_internal_coordinates(self) -> None:
        """One Exudyn ``NodeGenericODE2`` with the internal coordinates of the series springs
        (Maxwell dampers, stick-slip friction, air-spring reservoirs) and their small masses
        ``m_i = k_s / omega_i^2`` (:mod:`railexu.suspension_forces`)."""
        from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2

        masses = [e.internal_mass_kg() for e in self.kernel_elements if e.internal]
        self.internal_node: int | None = None
        if not masses:
            return
        n = len(masses)
        self.internal_node = self.mbs.AddNode(
            NodeGenericODE2(
                referenceCoordinates=[0.0] * n,
                initialCoordinates=[0.0] * n,
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
        for e in self.kernel_elements:
            a, b = e.bodies
            la, ga = self._local_point(a, e.position_m)
            lb, gb = self._local_point(b, e.position_m)
            local[e.name] = ((la, lb), float(gb[e.axis] - ga[e.axis]))
        body_slot = {name: slot[node] for name, node in self.node.items() if node in slot}
        start = 6 * len(slot) + 4 * len(self.rail_node)
        return kernel_arrays(self.kernel_elements, body_slot, local, start)

    def _add_spring_damper(self, el: SpringDamper) -> None:
        from exudyn.itemInterface import MarkerBodyPosition, ObjectConnectorCartesianSpringDamper

        mbs = self.mbs
        a, b = el.bodies
        la, ga = self._local_point(a, el.position_m)
        lb, gb = self._local_point(b, el.position_m)
        ma = mbs.AddMarker(MarkerBodyPosition(bodyNumber=self.body[a], localPosition=la))
        mb = mbs.AddMarker(MarkerBodyPosition(bodyNumber=self.body[b], localPosition=lb))
        k = np.asarray(el.stiffness_N_per_m)
        f_b = np.asarray(self.statics.element_forces[el.name])
        offset = gb - ga
        nz = k > 0.0
        offset[nz] += f_b[nz] / k[nz]
        mbs.AddObject(
            ObjectConnectorCartesianSpringDamper(
                markerNumbers=[ma, mb],
                stiffness=list(k),
                damping=list(el.damping_N_s_per_m),
                offset=list(offset),
            )
        )

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
        stiffness and damping to the ground (:mod:`railexu.track_model`)."""
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

        def contact_forces(mbs_, t, item, q, q_t):
            if set_time is not None:
                set_time(t)
            generalized_forces(np.array(q), np.array(q_t), data, out, points, ws_force)
            return out

        jac = np.zeros((n_coords, n_coords))
        jac_points = np.zeros_like(points)
        jac_force = np.zeros_like(ws_force)

        def contact_jacobian(mbs_, t, item, q, q_t, f_q, f_v):
            if set_time is not None:
                set_time(t)
            jacobian(np.array(q), np.array(q_t), data, f_q, f_v, jac, jac_points, jac_force)
            return jac

        self._user_function = contact_forces
        self._jacobian_function = contact_jacobian
        mbs.AddObject(
            ObjectGenericODE2(
                nodeNumbers=ode_nodes,
                massMatrix=np.zeros((n_coords, n_coords)),
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
            bs_int[i] = [slot[self.node[a]], slot[self.node[b]], 0, 0]
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
            wtab=self.wtab, winfo=self.winfo, rtab=self.rtab, rinfo=self.rinfo, htab=self.htab,
            ktab=self.ktab, params=self.params,
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
            se_int=se_int, se_real=se_real, se_table=se_table,
        )  # fmt: skip

    def set_time(self, t: float) -> None:
        """Move the vehicle frame to time ``t`` (distance, speed and acceleration along the
        track of the speed body's nominal motion)."""
        a = self.deceleration
        frame = self.kernel.frame
        frame[0] = self.frame_start_m + self.speed * t - 0.5 * a * t * t
        frame[1] = self.speed - a * t

    def _add_speed_constraint(self) -> None:
        """Constant forward speed of one body: a velocity-level constraint on its first
        coordinate (distance along the track), whose force is the traction."""
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

    def _name_of(self, node: int) -> str:
        return next(k for k, v in self.node.items() if v == node)

    def warm_up(self) -> None:
        """Call the compiled force and Jacobian functions once at the initial state, so that
        their just-in-time compilation (first run after installation) or loading from numba's
        cache happens before the integration starts and is not counted in its timing."""
        q = self.mbs.systemData.GetODE2Coordinates()[self.object_ltg]
        qt = self.mbs.systemData.GetODE2Coordinates_t()[self.object_ltg]
        self._user_function(self.mbs, 0.0, 0, list(q), list(qt))
        self._jacobian_function(self.mbs, 0.0, 0, list(q), list(qt), 1.0, 0.0)

    def evaluate(self, q_all: np.ndarray, qt_all: np.ndarray, t: float, out, points, ws_force):
        """Evaluate the compiled forces at a full system state and time ``t`` into the given
        arrays (for outputs); ``self.kernel.ws_local`` then holds the wheelsets' track-relative
        pose."""
        if self.curved:
            self.set_time(t)
        generalized_forces(
            q_all[self.object_ltg], qt_all[self.object_ltg], self.kernel, out, points, ws_force
        )
