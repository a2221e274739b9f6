r"""Kik-Piotrowski non-Hertzian normal contact (virtual penetration), for one contact point.

Source: J. Piotrowski and W. Kik, "A simplified model of wheel/rail contact mechanics for
non-Hertzian problems and its application in rail vehicle dynamic simulations", Vehicle System
Dynamics 46 (2008) 27-48 (eqs. 7-13 there).

Given the undeformed separation ``h(eta) >= 0`` of wheel and rail across the contact (``eta``
lateral in the contact plane, measured from the point of first contact where ``h = 0``), the
approach ``delta`` and the longitudinal gap coefficient ``A`` (gap ``A x^2`` along the rolling
direction; ``1 / (2 r)`` for a wheel of rolling radius ``r`` on a straight rail):

* virtual penetration ``delta0 = eps delta`` with ``eps = 0.55`` (the paper's value; it absorbs
  the elastic deformation outside the interpenetration region);
* interpenetration ``g(eta) = max(delta0 - h(eta), 0)``: the patch is where ``g > 0``, with the
  half-length ``x_f(eta) = sqrt(g / A)`` (front edge);
* pressure semi-elliptical along the rolling direction, ``p(x, eta) = C sqrt(x_f^2 - x^2)``;
* the normal force from the surface displacement at the point of first contact (Boussinesq):
  ``N = pi E* delta I2 / I1`` with ``I2 = int (pi/2) x_f^2 d eta`` and
  ``I1 = int J(eta) d eta``, ``J = int sqrt(x_f^2 - x^2) / sqrt(x^2 + eta^2) dx``
  ``= 2 sqrt(x_f^2 + eta^2) (K(m) - E(m))``, ``m = x_f^2 / (x_f^2 + eta^2)`` (complete elliptic
  integrals; derived here, checked against quadrature in the tests); ``E* = G / (1 - nu)``;
* ``C = N / I2`` and the pressure maximum ``p_max = C max(x_f)``.

The eta-integrals are taken by the midpoint rule on ``n`` cells across the patch (the log
singularity of ``J`` at ``eta = 0`` is integrable; midpoints never hit it).

Not wired into the compiled kernel or the dynamics: ``ContactParameters.normal_model`` accepts
only ``"hertz"``. :func:`wheel_point_patch` evaluates the patch of a wheel's contact point from
the profiles for comparison with Hertz (``docs/validation.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ellipe, ellipk

from . import kernel as K
from .evaluation import WheelsetContactModel

__all__ = ["KP_EPSILON", "KikPiotrowskiPatch", "kik_piotrowski_patch", "wheel_point_patch"]

#: Ratio of virtual to real penetration (Piotrowski and Kik 2008).
KP_EPSILON = 0.55


@dataclass(frozen=True)
class KikPiotrowskiPatch:
    """The non-Hertzian patch of one contact.

    Attributes:
        normal_force_N: normal force for the given approach [N].
        p_max_Pa: pressure maximum [Pa].
        half_length_m: largest half-length along the rolling direction [m].
        lateral_extent_m: ``(lo, hi)`` of the patch across, relative to the first contact [m].
        area_m2: patch area [m^2].
    """

    normal_force_N: float
    p_max_Pa: float
    half_length_m: float
    lateral_extent_m: tuple[float, float]
    area_m2: float


def kik_piotrowski_patch(
    lateral_m: np.ndarray,
    separation_m: np.ndarray,
    approach_m: float,
    gap_coefficient_per_m: float | np.ndarray,
    e_star_Pa: float,
    epsilon: float = KP_EPSILON,
    n_cells: int = 2000,
) -> KikPiotrowskiPatch:
    """Kik-Piotrowski patch from a separation table (module doc for the equations).

    Args:
        lateral_m: increasing lateral coordinates in the contact plane [m].
        separation_m: undeformed separation there [m]; its minimum is taken as first contact.
        approach_m: approach (rigid overlap at the first contact) [m], > 0.
        gap_coefficient_per_m: ``A`` of the longitudinal gap ``A x^2`` [1/m] (scalar or per
            lateral coordinate).
        e_star_Pa: ``E* = G / (1 - nu)`` for two bodies of the same steel [Pa].
        epsilon: virtual penetration ratio.
        n_cells: cells across the patch.
    """
    y = np.asarray(lateral_m, dtype=float)
    h = np.asarray(separation_m, dtype=float)
    h = h - float(np.min(h))
    y_c = float(y[int(np.argmin(h))])
    d0 = epsilon * approach_m
    inside = np.nonzero(h < d0)[0]
    if inside.size == 0 or not approach_m > 0.0:
        return KikPiotrowskiPatch(0.0, 0.0, 0.0, (0.0, 0.0), 0.0)
    step = float(y[1] - y[0])
    lo = float(y[max(inside[0] - 1, 0)])
    hi = float(y[min(inside[-1] + 1, y.size - 1)])
    edges = np.linspace(lo, hi, n_cells + 1)
    mid = 0.5 * (edges[1:] + edges[:-1])
    dy = (hi - lo) / n_cells
    g = np.maximum(d0 - np.interp(mid, y, h), 0.0)
    coef = np.interp(mid, y, np.broadcast_to(gap_coefficient_per_m, y.shape))
    xf = np.sqrt(g / coef)
    eta = mid - y_c
    r2 = xf * xf + eta * eta
    m = np.divide(xf * xf, r2, out=np.zeros_like(r2), where=r2 > 0.0)
    j = np.where(xf > 0.0, 2.0 * np.sqrt(r2) * (ellipk(m) - ellipe(m)), 0.0)
    i1 = float(np.sum(j) * dy)
    i2 = float(np.sum(0.5 * math.pi * xf * xf) * dy)
    normal = math.pi * e_star_Pa * approach_m * i2 / i1
    loaded = mid[g > 0.0]
    del step
    return KikPiotrowskiPatch(
        normal_force_N=normal,
        p_max_Pa=normal / i2 * float(np.max(xf)),
        half_length_m=float(np.max(xf)),
        lateral_extent_m=(float(loaded.min() - y_c), float(loaded.max() - y_c)),
        area_m2=float(np.sum(2.0 * xf) * dy),
    )


def wheel_point_patch(
    model: WheelsetContactModel,
    side: str,
    lateral_m: float,
    vertical_m: float,
    roll_rad: float,
    yaw_rad: float,
    wheel_lateral_m: float,
    contact_angle_rad: float,
    half_width_m: float = 0.012,
) -> KikPiotrowskiPatch:
    """Kik-Piotrowski patch of one wheel's contact point at a wheelset pose.

    The vertical gap along the wheel's contact locus (the kernel's geometry) within
    ``+-half_width_m`` of the point is turned into the contact plane: separation
    ``(g - g_min) cos(gamma)`` at the in-plane coordinate ``(y_rail - y_c) / cos(gamma)``; the
    approach is ``-g_min cos(gamma)``; the longitudinal gap coefficient ``cos(gamma) / (2 r)``
    with the wheel's rolling radius at each circle (the normal curvature of a surface of
    revolution along its circle is ``cos(gamma) / r``; straight rail).
    """
    if side not in ("left", "right"):
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    m = 1.0 if side == "left" else -1.0
    right = side == "right"
    wtab = model.wtab_r if right else model.wtab_l
    winfo = model.winfo_r if right else model.winfo_l
    rtab = model.rtab_r if right else model.rtab_l
    rinfo = model.rinfo_r if right else model.rinfo_l
    ctx = K._make_ctx(winfo, rinfo, m * lateral_m, vertical_m, m * roll_rad, m * yaw_rad)
    s_all = wheel_lateral_m + np.linspace(-half_width_m, half_width_m, 961)
    gaps, ys, radii = [], [], []
    for s in s_all:
        f, f1, f2, ok = K._hermite(wtab, winfo[K.WI_S0], winfo[K.WI_STEP], int(winfo[K.WI_N]), s)
        if not ok:
            continue
        g, _, py, _, _, _, _, ok = K._locus_gap(s, f, f1, f2, rtab, ctx)
        if ok:
            gaps.append(g)
            ys.append(py)
            radii.append(winfo[K.WI_R0] + f)
    gaps, ys, radii = np.array(gaps), np.array(ys), np.array(radii)
    order = np.argsort(ys)
    gaps, ys, radii = gaps[order], ys[order], radii[order]
    c = abs(math.cos(contact_angle_rad))
    k = int(np.argmin(gaps))
    approach = -float(gaps[k]) * c
    return kik_piotrowski_patch(
        (ys - ys[k]) / c,
        (gaps - gaps[k]) * c,
        approach,
        c / (2.0 * radii),
        model.parameters.effective_modulus_Pa,
    )
