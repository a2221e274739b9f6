"""Build the Exudyn multibody system of a vehicle on a track.

Design (measured in ``../shared/reference/exudyn-notes.md`` and ``docs/dev/exudyn-api.md``):

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
- the vehicle runs in absolute coordinates along the track's x axis (curved track can follow
  without changing this), wheelsets spinning freely under their creep forces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .contact import kernel as K
from .contact.evaluation import WheelsetContactModel, rail_arrays, wheel_arrays
from .contact.hertz import hertz_table
from .contact.kalker import kalker_table_for_poisson
from .contact.placement import WheelsetGeometry, symmetric_wheelset
from .contact.quasistatic import free_rolling_spin_rate, press_wheelset
from .errors import InputError
from .forces import BS_NREAL, generalized_forces, jacobian
from .statics import StaticSolution, attachment_point, static_equilibrium
from .track import Track
from .vehicle import BumpStop, SpringDamper, TorsionSpring, Vehicle, Wheelset

#: Distance of the rearmost wheelset from the start of the track at t = 0 [m].
START_MARGIN_M = 1.0


def wheelset_geometry(wheelset: Wheelset, track: Track) -> WheelsetGeometry:
    """The wheelset's wheel profiles placed on the track's rails (gauge, inclination, flange-back
    distance, nominal rolling radius), with the contact tables of both wheels."""
    return symmetric_wheelset(
        wheelset.wheel_profile,
        track.rail_profile,
        nominal_radius_m=wheelset.nominal_radius_m,
        inclination=track.inclination,
        gauge_m=track.gauge_m,
        flange_back_distance_m=wheelset.flange_back_distance_m,
    )


class ModelError(InputError):
    """A vehicle/track combination that cannot be built (e.g. a wheel that cannot carry its
    load)."""


@dataclass
class ModelLayout:
    """Everything the simulation needs to read the model's state and compute outputs."""

    wheelset_nodes: list[int]
    body_nodes: dict[str, int]
    ode2_index: dict[int, np.ndarray] = field(default_factory=dict)  # node -> global coordinates
    x_start_m: float = 0.0


class VehicleModel:
    """The Exudyn system of a vehicle running on a track at constant speed.

    Args:
        vehicle: the vehicle.
        track: the track.
        speed_m_per_s: forward speed V.
        initial_lateral_m: lateral offset of the whole vehicle at the start [m] (the seed's
            initial excursion).
        distance_m: distance the run will cover (sizes the irregularity record) [m].
    """

    def __init__(
        self,
        vehicle: Vehicle,
        track: Track,
        speed_m_per_s: float,
        initial_lateral_m: float = 0.0,
        distance_m: float = 100.0,
    ) -> None:
        import exudyn as exu

        if not speed_m_per_s > 0.0:
            raise ModelError(f"speed must be > 0 m/s, got {speed_m_per_s}")
        self.vehicle = vehicle
        self.track = track
        self.speed = float(speed_m_per_s)
        self.initial_lateral_m = float(initial_lateral_m)
        self.distance_hint = float(distance_m)
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
        import exudyn as exu
        from exudyn.itemInterface import (
            LoadForceVector,
            MarkerBodyPosition,
            MarkerBodyRigid,
            MarkerNodeCoordinate,
            NodePointGround,
            ObjectConnectorCartesianSpringDamper,
            ObjectConnectorCoordinate,
            ObjectConnectorRigidBodySpringDamper,
            ObjectGenericODE2,
        )
        from exudyn.rigidBodyUtilities import RigidBodyInertia, RotationMatrixX

        mbs = self.mbs
        veh = self.vehicle
        V = self.speed
        y0 = self.initial_lateral_m
        g = veh.gravity_m_per_s2
        x_start = START_MARGIN_M - min(w.position_x_m for w in veh.wheelsets)
        self.x_start_m = x_start

        # positions (global, initial) and reference rotations of every body
        self.centre: dict[str, np.ndarray] = {}
        self.rotation: dict[str, np.ndarray] = {}
        self.node: dict[str, int] = {}
        self.body: dict[str, int] = {}
        for b in veh.bodies:
            c = np.array([x_start + b.position_m[0], b.position_m[1] + y0, b.position_m[2]])
            res = mbs.CreateRigidBody(
                inertia=RigidBodyInertia(b.mass_kg, np.diag(b.inertia_kg_m2)),
                nodeType=exu.NodeType.RotationRxyz,
                referencePosition=list(c),
                referenceRotationMatrix=np.eye(3),
                initialVelocity=[V, 0.0, 0.0],
                gravity=[0.0, 0.0, -g],
                returnDict=True,
            )
            self.centre[b.name] = c
            self.rotation[b.name] = np.eye(3)
            self.node[b.name] = res["nodeNumber"]
            self.body[b.name] = res["bodyNumber"]
        for ws, st, spin_rate in zip(
            veh.wheelsets, self.initial_wheelsets, self.initial_spin_rates, strict=True
        ):
            c = np.array([x_start + ws.position_x_m, st.lateral_m, st.vertical_m])
            rot = RotationMatrixX(st.roll_rad - 0.5 * math.pi)
            res = mbs.CreateRigidBody(
                inertia=RigidBodyInertia(ws.mass_kg, np.diag(ws.inertia_kg_m2)),
                nodeType=exu.NodeType.RotationRxyz,
                referencePosition=list(c),
                referenceRotationMatrix=rot,
                initialVelocity=[V, 0.0, 0.0],
                gravity=[0.0, 0.0, -g],
                returnDict=True,
            )
            n = res["nodeNumber"]
            # free rolling: the spin at which the wheelset carries no longitudinal creep force
            mbs.SetNodeParameter(n, "initialVelocities", [V, 0, 0, 0, 0, spin_rate])
            self.centre[ws.name] = c
            self.rotation[ws.name] = np.asarray(rot)
            self.node[ws.name] = n
            self.body[ws.name] = res["bodyNumber"]
        wheelset_names = [w.name for w in veh.wheelsets]

        def local_point(body: str, p_vehicle) -> tuple[np.ndarray, np.ndarray]:
            """(local position on the body, initial global position) of an attachment."""
            p = attachment_point(veh, body, p_vehicle)
            if body in wheelset_names:
                local = np.array([0.0, 0.0, p[1]])  # on the axle (body z)
            else:
                local = np.array([p[0], p[1], p[2]]) - np.asarray(
                    next(b.position_m for b in veh.bodies if b.name == body)
                )
            glob = self.centre[body] + self.rotation[body] @ local
            return local, glob

        # suspension
        self.bump_stops: list[tuple] = []
        for el in veh.suspension:
            a, b = el.bodies
            la, ga = local_point(a, el.position_m)
            lb, gb = local_point(b, el.position_m)
            if isinstance(el, SpringDamper):
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
            elif isinstance(el, TorsionSpring):
                if a in wheelset_names or b in wheelset_names:
                    raise ModelError(f"torsion spring {el.name}: cannot act on a spinning wheelset")
                ma = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[a], localPosition=la))
                mb = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[b], localPosition=lb))
                axis = "xyz".index(el.axis)
                stiff = np.zeros((6, 6))
                damp = np.zeros((6, 6))
                stiff[3 + axis, 3 + axis] = el.stiffness_N_m_per_rad
                damp[3 + axis, 3 + axis] = el.damping_N_m_s_per_rad
                offset = np.zeros(6)
                if el.stiffness_N_m_per_rad > 0.0:
                    offset[3 + axis] = self.statics.element_forces[el.name] / (
                        el.stiffness_N_m_per_rad
                    )
                mbs.AddObject(
                    ObjectConnectorRigidBodySpringDamper(
                        markerNumbers=[ma, mb],
                        stiffness=stiff,
                        damping=damp,
                        offset=list(offset),
                    )
                )
            elif isinstance(el, BumpStop):
                axis = "xyz".index(el.direction)
                self.bump_stops.append((a, b, la, lb, axis, el, float(gb[axis] - ga[axis])))

        # external loads
        for load in veh.loads:
            local, _ = local_point(load.body, load.position_m)
            m = mbs.AddMarker(
                MarkerBodyPosition(bodyNumber=self.body[load.body], localPosition=local)
            )
            mbs.AddLoad(LoadForceVector(markerNumber=m, loadVector=list(load.force_N)))

        # contact (and bump stop) generalized forces
        ode_nodes = [self.node[n] for n in wheelset_names]
        for a, b, *_ in self.bump_stops:
            for name in (a, b):
                if self.node[name] not in ode_nodes:
                    ode_nodes.append(self.node[name])
        self.ode_nodes = ode_nodes
        slot = {node: i for i, node in enumerate(ode_nodes)}
        self.ws_slots = np.array([slot[self.node[n]] for n in wheelset_names], dtype=np.int64)
        self.qref = np.concatenate(
            [np.asarray(mbs.GetNodeParameter(n, "referenceCoordinates"), float) for n in ode_nodes]
        )
        self.bs_int = np.zeros((len(self.bump_stops), 4), dtype=np.int64)
        self.bs_real = np.zeros((len(self.bump_stops), BS_NREAL))
        for i, (a, b, la, lb, axis, el, d0) in enumerate(self.bump_stops):
            self.bs_int[i] = [slot[self.node[a]], slot[self.node[b]], 0, 0]
            self.bs_real[i, 0:3] = la
            self.bs_real[i, 3:6] = lb
            self.bs_real[i, 6] = axis
            self.bs_real[i, 7] = el.clearance_m
            self.bs_real[i, 8] = el.stiffness_N_per_m
            self.bs_real[i, 9] = el.damping_N_s_per_m
            self.bs_real[i, 10] = d0
        n_coords = 6 * len(ode_nodes)
        self._out = np.zeros(n_coords)
        n_ws = len(wheelset_names)
        self.points = np.zeros((n_ws, 2, K.MAX_POINTS, K.N_POINT_FIELDS))
        self.ws_force = np.zeros((n_ws, 6))

        # irregularities, sampled along the whole run; their distance 0 is where the leading
        # wheelset starts, so that every wheelset starts on undisturbed rails (the static state
        # it was pressed into) and meets the faded-in irregularities as it runs
        x_lead = x_start + max(w.position_x_m for w in veh.wheelsets)
        self.irregularity_origin_m = x_lead
        self.irregularities = self.track.irregularities(self.distance_hint + 20.0)
        sampled = self.irregularities.sampled(0.05)
        self.irr_start = x_lead + sampled.start_m
        self.irr_step = sampled.step_m
        self.irr_values = np.ascontiguousarray(sampled.values)
        self.irr_slopes = np.ascontiguousarray(sampled.slopes)

        args = self.kernel_args()
        out = self._out
        points = self.points
        ws_force = self.ws_force

        def contact_forces(mbs_, t, item, q, q_t):
            generalized_forces(np.array(q), np.array(q_t), *args, out, points, ws_force)
            return out

        jac = np.zeros((n_coords, n_coords))
        jac_points = np.zeros_like(points)
        jac_force = np.zeros_like(ws_force)

        def contact_jacobian(mbs_, t, item, q, q_t, f_q, f_v):
            jacobian(np.array(q), np.array(q_t), *args, f_q, f_v, jac, jac_points, jac_force)
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

        # constant forward speed of one body
        ground = mbs.AddNode(NodePointGround(referenceCoordinates=[0.0, 0.0, 0.0]))
        m0 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
        m1 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=self.node[veh.speed_body], coordinate=0))
        self.speed_constraint = mbs.AddObject(
            ObjectConnectorCoordinate(markerNumbers=[m0, m1], velocityLevel=True, offset=V)
        )
        mbs.Assemble()
        self.ltg = {
            name: np.asarray(mbs.systemData.GetNodeLTGODE2(n), dtype=np.int64)
            for name, n in self.node.items()
        }
        self.object_ltg = np.concatenate([self.ltg[self._name_of(n)] for n in ode_nodes])

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

    def kernel_args(self) -> tuple:
        """Arguments of :func:`railexu.forces.generalized_forces` after ``q, qt``."""
        return (
            self.qref, self.ws_slots, self.wtab, self.winfo, self.rtab, self.rinfo, self.htab,
            self.ktab, self.params, self.irr_start, self.irr_step, self.irr_values,
            self.irr_slopes, self.bs_int, self.bs_real,
        )  # fmt: skip

    def evaluate_forces(self, q_all: np.ndarray, qt_all: np.ndarray):
        """Contact points and wheelset forces at a full system state (for outputs).

        Returns ``(points, ws_force)``: ``(n_ws, 2, MAX_POINTS, N_POINT_FIELDS)`` and
        ``(n_ws, 6)`` arrays (copies).
        """
        points = np.zeros_like(self.points)
        ws_force = np.zeros_like(self.ws_force)
        out = np.zeros_like(self._out)
        generalized_forces(
            q_all[self.object_ltg], qt_all[self.object_ltg], *self.kernel_args(), out, points,
            ws_force,
        )  # fmt: skip
        return points, ws_force
