"""Rolling contact fatigue indices (docs/wear.md, "Rolling contact fatigue").

* :func:`fi_surf`: Ekberg's surface fatigue index (A. Ekberg, E. Kabo, H. Andersson, Fatigue
  Fract. Engng Mater. Struct. 25 (2002) 899-909), ``FI_surf = f - 2 pi a b k / (3 F_z)`` with
  the traction coefficient ``f = sqrt(F_x^2 + F_y^2) / F_z`` and the shear yield ``k``. Since
  the Hertz peak pressure is ``p0 = 3 F_z / (2 pi a b)``, ``FI_surf = f - k / p0``: positive
  beyond the surface ratchetting line ``f = k / p0`` of Johnson's shakedown map, where
  surface-initiated RCF is predicted.
* :func:`wlrm_damage`: Burstow's Whole Life Rail Model damage per axle passage from the wear
  number ``T gamma`` (M. C. Burstow, AEATR-ES-2004-880, 2004): zero below 15 N, linear to the
  peak at 65 N, linear to zero at 175 N (wear removes the initiated cracks), zero beyond.

The parameters are in ``railexu/data/wear_rcf.yaml`` (the WLRM's peak scale and ``k`` are
marked as railexu's assumptions there).
"""

from __future__ import annotations

import math

import numpy as np

from railexu.contact.wear.coefficients import Coefficients, load_coefficients


def fi_surf(Fx_N, Fy_N, N_N, a_m, b_m, shear_yield_Pa: float | None = None) -> np.ndarray:
    """Ekberg's surface fatigue index [-] per contact (module doc); NaN where unloaded.

    Args:
        Fx_N, Fy_N: tangential forces in the contact plane [N].
        N_N: normal force [N].
        a_m, b_m: Hertz semi-axes [m].
        shear_yield_Pa: yield stress in pure shear ``k`` (default: the coefficients file).
    """
    if shear_yield_Pa is None:
        shear_yield_Pa = load_coefficients().fi_surf.shear_yield_Pa
    fx, fy, n = (np.asarray(v, dtype=float) for v in (Fx_N, Fy_N, N_N))
    a, b = np.asarray(a_m, dtype=float), np.asarray(b_m, dtype=float)
    loaded = (n > 0.0) & (a > 0.0) & (b > 0.0)
    safe_n = np.where(loaded, n, 1.0)
    f = np.hypot(fx, fy) / safe_n
    index = f - 2.0 * math.pi * a * b * shear_yield_Pa / (3.0 * safe_n)
    return np.where(loaded, index, np.nan)


def wlrm_damage(tgamma_N, coef: Coefficients | None = None) -> np.ndarray:
    """Burstow's WLRM RCF damage per axle passage [-] at the wear number ``T gamma`` [N]
    (module doc)."""
    w = (coef or load_coefficients()).wlrm
    t = np.asarray(tgamma_N, dtype=float)
    rise = w.peak_damage * (t - w.threshold_N) / (w.peak_N - w.threshold_N)
    fall = w.peak_damage * (w.zero_N - t) / (w.zero_N - w.peak_N)
    d = np.where(t <= w.peak_N, rise, fall)
    return np.clip(d, 0.0, None)
