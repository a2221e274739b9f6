"""Critical speed: linear eigenvalues, the limit-cycle branch, bisection and the ramp method.

Above its critical speed a railway vehicle hunts: a self-excited lateral oscillation of its
wheelsets and bogies. Four ways to find it (``docs/assessment.md`` and ``docs/validation.md``):

- **linear** (:func:`linear_stability`): linearise the vehicle about centred running at a speed
  with Exudyn (``ComputeLinearizedSystem``: stiffness, damping and mass matrices, the creep
  damping included through the contact force's numerical Jacobian) and follow every lateral
  mode over speed by its shape (:mod:`.modes`: MAC between neighbouring speeds), each named by
  its kinetic and strain energy (wheelset or bogie hunting, bogie yaw, car-body lateral, yaw
  or roll; the bodies by the vehicle's names); the critical speed is the lowest at which a
  mode's damping ratio crosses zero, reported with the mode, its unstable band and whether it
  stays unstable above. As
  the classical linear analysis does, the wheel profiles are replaced by cones with the
  *equivalent conicity* of the profile pair (EN 15302, harmonic linearisation at a given
  amplitude, 3 mm by default), and creep follows Kalker's linear theory. (``linearization =
  "profiles"`` linearises the real profile contact instead, whose slope at the centre can be far
  from the equivalent conicity.)
- **nonlinear bisection** (:func:`bisection_critical_speed`): runs of the full model after a
  lateral disturbance (an initial lateral offset of the whole vehicle); a run is *unstable*
  when its oscillation grows or is sustained, a limit cycle of any amplitude above the 0.1 mm
  floor (:func:`classify_run`, growth rate of the fitted envelope; no amplitude threshold
  decides); bisection between a stable and an unstable speed, saying where its unstable edge
  is a bounded cycle and of what amplitude. Deterministic: the same inputs give the same speed.
- **branch** (:func:`branch_critical_speed`): the limit-cycle branch followed as speed
  falls (settle, measure, lower the speed, restart from the amplitude found); each run
  classified by the growth rate of its fitted envelope (:func:`classify_run`); the lowest
  speed with a sustained cycle is the nonlinear critical speed (with its amplitude), and the
  fold of the branch followed from the top speed is bracketed. Bisection judges its runs the
  same way.
- **ramp** (:func:`ramp_critical_speed`): start above the critical speed from a disturbance,
  let the hunting settle, then decelerate slowly (0.2 m/s^2 by default, from the 1 % per
  period drift rule, and twice that as the check of rate independence); windows of 16 periods
  classified by growth rate; the last window with a sustained cycle gives the nonlinear
  critical speed from above, the end of the cycle followed from the start its fold.

Modules: :mod:`.settings` (settings and their parsing), :mod:`.linear`, :mod:`.modes` (mode
tracking by shape, unstable bands), :mod:`.nonlinear`,
:mod:`.analysis` (:func:`critical_speed` and the comparison of linear and nonlinear values).
"""

from railexu.stability.analysis import (
    COMPARISON_TOLERANCE,
    _jsonable,
    compare_linear_nonlinear,
    critical_speed,
)
from railexu.stability.branch import branch_critical_speed
from railexu.stability.linear import (
    HUNTING_MODES,
    MODE_NAMES,
    Mode,
    body_roles,
    lateral_modes,
    linear_model_vehicle,
    linear_stability,
    name_mode,
    profile_equivalent_conicity,
)
from railexu.stability.nonlinear import (
    bisection_critical_speed,
    classify_run,
    classify_window,
    nonlinear_run_is_stable,
)
from railexu.stability.ramp import ramp_critical_speed
from railexu.stability.settings import (
    CRITICAL_SPEED_KEYS,
    LINEARIZATIONS,
    METHODS,
    CriticalSpeedSettings,
    StabilityError,
    critical_speed_settings_from_dict,
    parse_methods,
    print_messages,
)

__all__ = [
    "COMPARISON_TOLERANCE",
    "CRITICAL_SPEED_KEYS",
    "HUNTING_MODES",
    "LINEARIZATIONS",
    "METHODS",
    "MODE_NAMES",
    "CriticalSpeedSettings",
    "Mode",
    "StabilityError",
    "_jsonable",
    "bisection_critical_speed",
    "branch_critical_speed",
    "classify_run",
    "classify_window",
    "body_roles",
    "compare_linear_nonlinear",
    "critical_speed",
    "critical_speed_settings_from_dict",
    "lateral_modes",
    "linear_model_vehicle",
    "linear_stability",
    "name_mode",
    "nonlinear_run_is_stable",
    "parse_methods",
    "print_messages",
    "profile_equivalent_conicity",
    "ramp_critical_speed",
]
