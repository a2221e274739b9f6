"""The vehicle file's schema: every key declared once (unit, range, default, one line of doc).

:mod:`railexu.vehicle.vehicle` reads files with it, ``--set`` paths find their units in it, and the
key tables of ``docs/vehicle-format.md`` are generated from it (``python -m railexu.schema
--write-docs``). Contact defaults are those of
:class:`~railexu.contact.evaluation.ContactParameters`, declared there once.
"""

from __future__ import annotations

from railexu.contact.parameters import CREEP_MODELS, DAMPING_MODELS, ContactParameters
from railexu.contact.standard_gauge import STANDARD_FLANGE_BACK_M
from railexu.inputs import OPTIONAL, Field, Schema

#: The format this railexu writes; :data:`READ_VERSIONS` are the ones it reads.
FORMAT_VERSION = 2
READ_VERSIONS = (1, 2)
AXES = ("x", "y", "z")
_C = ContactParameters()

#: Positions of bodies, elements and loads: a vehicle is shorter than 100 m, narrower than 5 m.
_POS = dict(minimum=-100.0, maximum=100.0)
_ESTIMATE = Field("estimate", "basis of values no public source gives", "text", default="")
_NOTES = Field("notes", "free text", "text", default="")

# -- contact ------------------------------------------------------------------------------------
POLACH_2005 = Schema(
    "polach_2005",
    (
        Field("k_a", "reduction of Kalker's coefficient in the adhesion area (Polach 2005)",
              unit="1", default=_C.polach_2005[0], positive=True, maximum=1.0),
        Field("k_s", "reduction of Kalker's coefficient in the slip area (Polach 2005)",
              unit="1", default=_C.polach_2005[1], positive=True, maximum=1.0),
        Field("A", "ratio of the limit friction at infinite slip to the static one",
              unit="1", default=_C.polach_2005[2], positive=True, maximum=1.0),
        Field("B", "exponential decay rate of friction with slip velocity",
              unit="s/m", default=_C.polach_2005[3], minimum=0.0, maximum=100.0),
    ),
    "Polach (2005), falling friction with slip velocity; dry rail by default (Table 2).",
)  # fmt: skip
_NO_PARAMETERS = Schema("none", ())
CREEP_LAWS = {
    name: POLACH_2005 if name == "polach_2005" else _NO_PARAMETERS for name in CREEP_MODELS
}

NORMAL_DAMPING = {
    "hunt_crossley": Schema(
        "hunt_crossley",
        (
            Field(
                "coefficient",
                "chi of N = K d^1.5 (1 + chi d'): hysteresis damping (Hunt and Crossley 1975)",
                unit="s/m",
                default=_C.damping,
                minimum=0.0,
                maximum=100.0,
            ),
        ),
    ),  # fmt: skip
    "linear": Schema(
        "linear",
        (
            Field(
                "coefficient",
                "D of N = K d^1.5 + D d' (jumps to D d' at first touch); default ~5 % of critical "
                "for 1 t on a 1e9 N/m contact",
                unit="N s/m",
                default=1.0e5,
                minimum=0.0,
                maximum=1.0e8,
            ),
        ),
    ),  # fmt: skip
}
assert set(NORMAL_DAMPING) == set(DAMPING_MODELS)

CONTACT = Schema(
    "contact",
    (
        Field("friction", "friction coefficient mu (mu0 of Polach 2005)", unit="1",
              default=_C.friction, minimum=0.0, maximum=1.0),
        Field("creep", "creep law by name, its parameters nested: {model: polach_2005, k_a: ...}",
              "model", default={"model": _C.creep_model}, models=CREEP_LAWS),
        Field("shear_modulus", "combined shear modulus G of wheel and rail steel", unit="Pa",
              default=_C.shear_modulus_Pa, minimum=1e9, maximum=1e12),
        Field("poisson", "Poisson's ratio of wheel and rail steel", unit="1",
              default=_C.poisson, minimum=0.0, maximum=0.499),
        Field("normal_damping", "damping law of the normal force by name, with its coefficient",
              "model", default={"model": _C.damping_model}, models=NORMAL_DAMPING),
        Field("scan_step", "step of the coarse scan for contact points along the wheel",
              unit="m", default=_C.scan_step_m, minimum=1e-5, maximum=5e-3),
    ),
)  # fmt: skip

# -- bodies, wheelsets, elements, loads -----------------------------------------------------------
BODY = Schema(
    "body",
    (
        Field("mass", "mass", unit="kg", positive=True, maximum=1e6),
        Field("inertia", "principal moments of inertia about the centre of gravity", "vector",
              "kg m^2", components=("roll", "pitch", "yaw"), positive=True, maximum=1e9),
        Field("position", "centre of gravity, vehicle axes", "vector", "m", **_POS),
        _ESTIMATE,
        _NOTES,
    ),
    "A rigid body other than a wheelset (car body, bogie frame), by name under `bodies:`.",
)  # fmt: skip

WHEELSET = Schema(
    "wheelset",
    (
        Field("position", "x of the axle; its centre is at the nominal radius above the rails",
              "vector", "m", components=("x",), **_POS),
        Field("mass", "mass of the wheelset (and what rotates with it)", unit="kg",
              positive=True, maximum=1e5),
        Field("inertia", "principal moments of inertia about the centre", "vector", "kg m^2",
              components=("roll", "yaw", "spin"), positive=True, maximum=1e6),
        Field("wheel_profile", "built-in name or a profile file (relative to this file); "
              "{left: ..., right: ...} for different wheels", "sided"),
        Field("nominal_radius", "rolling radius at the tape circle; {left:, right:} allowed",
              "sided", "m", minimum=0.2, maximum=1.0),
        Field("flange_back_distance", "distance between the backs of the two flanges",
              unit="m", default=STANDARD_FLANGE_BACK_M, minimum=0.9, maximum=1.7),
        Field("axle_load", "declared static axle load, checked against the statics (2 %)",
              unit="N", default=OPTIONAL, positive=True, maximum=1e7),
        _ESTIMATE,
        _NOTES,
    ),
    "A wheelset (axle along y), by name under `wheelsets:`; at least one.",
)  # fmt: skip

# Physical bounds of suspension values (their reasons: docs/vehicle-format.md, "Ranges").
#: Largest stiffness of a spring or a table's slope [N/m]: a steel block 0.1 m^2 x 0.2 m is
#: 1e11 N/m; 1e10 N/m is a rigid stop whose 1 t mass rings at 500 Hz, beyond what any step
#: resolves.
MAX_STIFFNESS = 1.0e10
#: Largest damping of a damper or a damper table's slope [N s/m]: hydraulic dampers are 1e4
#: to 1e6 N s/m; 1e9 N s/m on a 1 t body has a time constant of 1 us.
MAX_DAMPING = 1.0e9
#: Smallest stiffness in series with a damper or a friction slider [N/m]: rubber bushes and
#: friction contacts before sliding are 1e6 to 1e8 N/m; at 10 kN/m a 100 kN s/m damper acts
#: only below 0.016 Hz and a 3 kN slider would move 0.3 m before sliding.
MIN_SERIES_STIFFNESS = 1.0e4
#: Smallest regularising slip velocity of a friction element [m/s]: below 0.01 mm/s the
#: slope F_c / v_s of the regularised law (4e8 N s/m for 4 kN) is a damping the step cannot
#: follow.
MIN_SLIP_VELOCITY = 1.0e-5
#: Smallest effective pendulum length of UIC links [m]: the links are 0.1 to 0.3 m; at 10 mm
#: the pendulum stiffness W / L of a 60 kN load is 6 MN/m, stiffer than the links' stick.
MIN_PENDULUM_LENGTH = 0.01

#: Interpolation of characteristic tables between their points.
INTERPOLATIONS = ("linear", "smooth")
_BODIES = Field("bodies", "the two bodies it connects, [upper, lower]", "text_list")
_POSITION = Field("position", "attachment point, vehicle axes", "vector", "m", **_POS)
_MIRROR = Field("mirror_y", "also at -y: makes NAME_left and NAME_right", "boolean",
                default=False)  # fmt: skip
ELEMENTS = {
    "spring_damper": Schema(
        "spring_damper",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("stiffness", "stiffness along the track axes (missing components 0)",
                  "vector", "N/m", default=(0.0, 0.0, 0.0), minimum=0.0, maximum=1e10),
            Field("damping", "viscous damping along the track axes (missing components 0)",
                  "vector", "N s/m", default=(0.0, 0.0, 0.0), minimum=0.0, maximum=1e9),
            _ESTIMATE, _NOTES,
        ),
        "Linear spring and damper at one point (bushing, coil spring, damper).",
    ),
    "torsion_spring": Schema(
        "torsion_spring",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("axis", "axis of rotation", "text", choices=AXES),
            Field("stiffness", "rotational stiffness", unit="N m/rad", default=0.0,
                  minimum=0.0, maximum=1e10),
            Field("damping", "rotational damping", unit="N m s/rad", default=0.0,
                  minimum=0.0, maximum=1e9),
            _ESTIMATE, _NOTES,
        ),
        "Rotational spring and damper about one axis (secondary yaw); not on wheelsets.",
    ),
    "bump_stop": Schema(
        "bump_stop",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("direction", "direction of the stop", "text", choices=AXES),
            Field("clearance", "free play on each side", unit="m", minimum=0.0, maximum=1.0),
            Field("stiffness", "stiffness beyond the clearance", unit="N/m", positive=True,
                  maximum=1e10),
            Field("damping", "damping beyond the clearance", unit="N s/m", default=0.0,
                  minimum=0.0, maximum=1e9),
            _ESTIMATE, _NOTES,
        ),
        "No force within +-clearance, then a linear spring (and damper).",
    ),
    "nonlinear_spring": Schema(
        "nonlinear_spring",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("direction", "direction of the element (track axes)", "text", choices=AXES),
            Field("deflection", "table: deflection, second body's point minus the first's "
                  "along the direction (z: [upper, lower] gives compression > 0), increasing",
                  "number_list", "m", minimum=-1.0, maximum=1.0),
            Field("force", "table: force of the element at each deflection (pushes the bodies "
                  "back: -F on the second body), non-decreasing", "number_list", "N",
                  minimum=-1e8, maximum=1e8),
            Field("symmetric", "the table gives deflection >= 0 only (from 0, 0): F(-d) = -F(d)",
                  "boolean", default=False),
            Field("interpolation", "between table points: linear, or smooth (monotone cubic, "
                  "Fritsch-Carlson / PCHIP)", "text", default="linear", choices=INTERPOLATIONS),
            Field("damping", "parallel viscous damping", unit="N s/m", default=0.0,
                  minimum=0.0, maximum=1e9),
            _ESTIMATE, _NOTES,
        ),
        "Force against deflection from a table along one axis (progressive bump stops, "
        "rubber springs, leaf springs); outside the table the end slopes continue.",
    ),
    "damper": Schema(
        "damper",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("direction", "direction of the damper (track axes)", "text", choices=AXES),
            Field("damping", "linear damping coefficient (or give velocity and force)",
                  unit="N s/m", default=OPTIONAL, positive=True, maximum=1e9),
            Field("velocity", "table: relative velocity of the second body's point along the "
                  "direction, increasing", "number_list", "m/s", default=OPTIONAL,
                  minimum=-100.0, maximum=100.0),
            Field("force", "table: damper force at each velocity (-F on the second body), "
                  "non-decreasing (e.g. blow-off)", "number_list", "N", default=OPTIONAL,
                  minimum=-1e8, maximum=1e8),
            Field("symmetric", "the table gives velocity >= 0 only (from 0, 0): F(-v) = -F(v)",
                  "boolean", default=False),
            Field("interpolation", "between table points: linear or smooth (PCHIP)", "text",
                  default="linear", choices=INTERPOLATIONS),
            Field("series_stiffness", "stiffness of the end bushes in series with the damper "
                  "(a Maxwell element with one internal coordinate); absent: rigid",
                  unit="N/m", default=OPTIONAL, positive=True, minimum=MIN_SERIES_STIFFNESS,
                  maximum=1e10),
            _ESTIMATE, _NOTES,
        ),
        "A hydraulic damper along one axis: linear or from a force-velocity table, optionally "
        "in series with its bush stiffness (yaw dampers, lateral and vertical dampers).",
    ),
    "friction": Schema(
        "friction",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("direction", "direction of sliding (track axes)", "text", choices=AXES),
            Field("friction_force", "sliding (Coulomb) friction force", unit="N",
                  positive=True, maximum=1e7),
            Field("slip_velocity", "regularisation: F = F_c tanh(v / slip_velocity); with a "
                  "stick stiffness the slider flows at (|f| - F_c) / eta, eta = F_c / (1e4 "
                  "slip_velocity)", unit="m/s", default=1.0e-3, positive=True,
                  minimum=MIN_SLIP_VELOCITY, maximum=1.0),
            Field("stick_stiffness", "stiffness of the contact before sliding (stick-slip "
                  "model: spring in series with the slider, one internal coordinate); absent: "
                  "regularised Coulomb friction only", unit="N/m", default=OPTIONAL,
                  positive=True, minimum=MIN_SERIES_STIFFNESS, maximum=1e10),
            _ESTIMATE, _NOTES,
        ),
        "Dry (Coulomb) friction along one axis: friction wedges, leaf-spring friction, side "
        "bearers.",
    ),
    "uic_link": Schema(
        "uic_link",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("pendulum_length", "effective pendulum length of the links, longitudinal "
                  "and lateral", "vector", "m", components=("x", "y"), positive=True,
                  minimum=MIN_PENDULUM_LENGTH, maximum=2.0),
            Field("friction_coefficient", "friction coefficient of the link joints "
                  "(friction force = coefficient x vertical load), longitudinal and lateral",
                  "vector", "1", components=("x", "y"), minimum=0.0, maximum=1.0),
            Field("stick_stiffness", "stiffness of the suspension before the links slide, "
                  "longitudinal and lateral", "vector", "N/m", components=("x", "y"),
                  positive=True, minimum=MIN_SERIES_STIFFNESS, maximum=1e10),
            Field("vertical_load", "vertical load W on the link suspension; absent: the "
                  "static load of the elements with vertical stiffness between the same "
                  "bodies at the same point", unit="N", default=OPTIONAL, positive=True,
                  maximum=1e7),
            Field("slip_velocity", "regularisation of the sliding: the links slide at "
                  "(|f| - mu W) / eta, eta = mu W / (1e4 slip_velocity)", unit="m/s",
                  default=1.0e-3, positive=True, minimum=MIN_SLIP_VELOCITY, maximum=1.0),
            _ESTIMATE, _NOTES,
        ),
        "The UIC double-link (pendulum) suspension of two-axle freight wagons, longitudinal "
        "and lateral: pendulum stiffness W / L in parallel with a stick-slip friction element "
        "(Piotrowski 2003). The vertical (leaf) spring is a separate element.",
    ),
    "air_spring": Schema(
        "air_spring",
        (
            _BODIES, _POSITION, _MIRROR,
            Field("vertical_stiffness", "static vertical stiffness k1 (bag with its reservoir, "
                  "the stiffness at zero frequency)", unit="N/m", positive=True, maximum=1e9),
            Field("reservoir_stiffness", "stiffness k2 in series with the orifice damping: "
                  "the stiffness at infinite frequency is k1 + k2", unit="N/m", minimum=0.0,
                  maximum=1e9),
            Field("orifice_damping", "damping c of the flow between bag and reservoir",
                  unit="N s/m", positive=True, maximum=1e8),
            Field("lateral_stiffness", "shear stiffness of the bag, longitudinal and lateral",
                  "vector", "N/m", components=("x", "y"), default=(0.0, 0.0), minimum=0.0,
                  maximum=1e9),
            Field("lateral_damping", "shear damping of the bag, longitudinal and lateral",
                  "vector", "N s/m", components=("x", "y"), default=(0.0, 0.0), minimum=0.0,
                  maximum=1e8),
            _ESTIMATE, _NOTES,
        ),
        "An air spring with its reservoir, vertical: k1 in parallel with k2 in series with c "
        "(the linear reservoir model; Berg 1999 adds friction); it carries its static load.",
    ),
    "anti_roll_bar": Schema(
        "anti_roll_bar",
        (
            _BODIES, _POSITION,
            Field("stiffness", "roll stiffness: moment per relative roll angle of the bodies",
                  unit="N m/rad", positive=True, maximum=1e10),
            Field("damping", "roll damping", unit="N m s/rad", default=0.0, minimum=0.0,
                  maximum=1e9),
            _ESTIMATE, _NOTES,
        ),
        "A torsion bar between car body and bogie resisting their relative roll only; not on "
        "wheelsets.",
    ),
}  # fmt: skip
ELEMENT_TYPE = Field("type", "kind of element", "text", choices=tuple(ELEMENTS))

LOAD = Schema(
    "load",
    (
        Field("body", "the body it acts on", "text"),
        _POSITION,
        Field("force", "force, vehicle axes", "vector", "N", minimum=-1e8, maximum=1e8),
        _MIRROR,
        Field("static", "part of the rest state; false: applied suddenly at t = 0", "boolean",
              default=True),
        _ESTIMATE,
        _NOTES,
    ),
    "A constant force on a body at a point, by name under `loads:`.",
)  # fmt: skip

#: Vehicle categories of EN 14363 (the track-shifting limit's alpha depends on them).
CATEGORIES = ("locomotive", "coach", "multiple_unit", "wagon")

MEASUREMENT_POINT = Schema(
    "measurement_point",
    (
        Field("body", "the body the point is fixed to", "text"),
        Field("position", "the point, vehicle axes (on the car body floor for EN 12299)",
              "vector", "m", **_POS),
    ),
    "A point whose lateral and vertical accelerations are recorded (ride comfort, EN 12299); "
    "by name under `measurement_points:`. Default: on the floor (1.2 m above the rails) of the "
    "first body, above each bogie pivot (`body_front`, `body_rear`) and at its centre "
    "(`body_centre`); and on each bogie frame (a body other than the first that carries "
    "wheelsets) above its outermost wheelsets at the frame's centre height "
    "(`<frame>_above_<wheelset>`: EN 14363's simplified measuring method). Ride comfort "
    "(EN 12299) is evaluated at the points on the car body (the heaviest body) only.",
)  # fmt: skip

#: Height of the default measurement points above the top of the rails [m]: a typical floor
#: height of locomotives and coaches (EN 12299 measures on the floor).
DEFAULT_FLOOR_HEIGHT_M = 1.2

VEHICLE = Schema(
    "vehicle",
    (
        Field("format_version", f"format of the file ({FORMAT_VERSION}; 1 is still read)",
              "integer", choices=READ_VERSIONS),
        Field("name", "short name", "text"),
        Field("description", "one paragraph", "text", default=""),
        Field("category", "EN 14363 category: the track-shifting limit's alpha depends on it",
              "text", choices=CATEGORIES),
        Field("admissible_speed", "the vehicle's admissible speed V_adm: `railexu acceptance` "
              "runs its programme up to 1.1 V_adm (EN 14363:2016's maximum test speed) unless "
              "the command line gives it", unit="m/s", default=OPTIONAL, positive=True,
              maximum=150.0 / 1.1),
        Field("admissible_cant_deficiency", "the vehicle's admissible cant deficiency I_adm: "
              "`railexu acceptance` runs its curve sections up to it and evaluates them at it "
              "unless the command line gives it", unit="m", default=OPTIONAL, positive=True,
              maximum=0.3),
        Field("sources", "where the data come from", "text_list", default=()),
        Field("speed_body", "body held at the forward speed (default: the first body, or the "
              "first wheelset)", "text", default=OPTIONAL),
        Field("gravity", "acceleration of gravity", unit="m/s^2", default=9.81, minimum=9.7,
              maximum=9.9),
        Field("contact", "wheel-rail contact parameters", "section", default={}, schema=CONTACT),
        Field("bodies", "rigid bodies other than wheelsets, by name", "named", default={},
              schema=BODY),
        Field("wheelsets", "wheelsets, by name", "named", schema=WHEELSET),
        Field("suspension", "suspension elements, by name; `type:` chooses the kind", "named",
              default={}, models=ELEMENTS, selector="type"),
        Field("loads", "constant external forces, by name", "named", default={}, schema=LOAD),
        Field("measurement_points", "points whose accelerations are recorded, by name "
              "(default: the car body floor above each pivot and at the centre, and each bogie "
              "frame above its outermost wheelsets)", "named",
              default={}, schema=MEASUREMENT_POINT),
    ),
    "The top level of a vehicle file.",
)  # fmt: skip

#: ``(heading, schema)`` of every table of ``docs/vehicle-format.md``.
DOC_TABLES = (
    ("Top level", VEHICLE),
    ("`contact`", CONTACT),
    ("`contact.creep` model `polach_2005` (other creep laws take no parameters)", POLACH_2005),
    ("`contact.normal_damping` model `hunt_crossley` (default)", NORMAL_DAMPING["hunt_crossley"]),
    ("`contact.normal_damping` model `linear`", NORMAL_DAMPING["linear"]),
    ("`bodies.NAME`", BODY),
    ("`wheelsets.NAME`", WHEELSET),
    *((f"`suspension.NAME` with `type: {k}`", s) for k, s in ELEMENTS.items()),
    ("`loads.NAME`", LOAD),
    ("`measurement_points.NAME`", MEASUREMENT_POINT),
)
