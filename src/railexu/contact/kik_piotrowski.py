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
from dataclasses import dataclass, field

import numba
import numpy as np
from scipy.special import ellipe, ellipk

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel

__all__ = [
    "KP_EPSILON",
    "KikPiotrowskiPatch",
    "kik_piotrowski_patch",
    "patch_creep_forces",
    "wheel_point_patch",
]

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
        strip_lateral_m: centres of the lateral cells, relative to the first contact [m].
        strip_half_length_m: half-length ``x_f`` of each cell [m].
        strip_width_m: width of the cells [m].
    """

    normal_force_N: float
    p_max_Pa: float
    half_length_m: float
    lateral_extent_m: tuple[float, float]
    area_m2: float
    strip_lateral_m: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    strip_half_length_m: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    strip_width_m: float = 0.0

    @property
    def pressure_coefficient_Pa_per_m(self) -> float:
        """``C`` of ``p = C sqrt(x_f^2 - x^2)`` [Pa/m]."""
        i2 = float(np.sum(0.5 * math.pi * self.strip_half_length_m**2) * self.strip_width_m)
        return self.normal_force_N / i2 if i2 > 0.0 else 0.0


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
        strip_lateral_m=eta,
        strip_half_length_m=xf,
        strip_width_m=dy,
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
    s_all = wheel_lateral_m + np.linspace(-half_width_m, half_width_m, 961)
    gaps, ys, radii = np.empty(s_all.size), np.empty(s_all.size), np.empty(s_all.size)
    n = _locus_profile(
        wtab, winfo, rtab, rinfo, m * lateral_m, vertical_m, m * roll_rad, m * yaw_rad, s_all,
        gaps, ys, radii,
    )  # fmt: skip
    gaps, ys, radii = gaps[:n], ys[:n], radii[:n]
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


def patch_creep_forces(
    patch: KikPiotrowskiPatch,
    xi: float,
    eta: float,
    phi: float,
    friction: float,
    shear_modulus_Pa: float,
    poisson: float,
    n_strips: int = 40,
    n_points: int = 40,
) -> tuple[float, float, float]:
    """Creep forces and spin moment on the wheel on a Kik-Piotrowski patch: FASTSIM on strips.

    Kalker's simplified theory (Kalker, VSD 11 (1982) 1-13) marched along each strip of the
    patch from its leading edge ``x = +x_f``, with the traction bound ``mu p(x, y)`` of the
    patch's own (semi-elliptical along x) pressure; the flexibilities ``L1, L2, L3`` are those of
    the ellipse with ``a = max x_f`` and ``b`` = half the patch width (the usual choice for
    non-Hertzian FASTSIM). Spin turns about the point of first contact. Same signs as
    :func:`railexu.contact.fastsim.fastsim_forces`.

    Returns:
        ``(Fx, Fy, Mz)`` on the wheel [N, N, N m].
    """
    from railexu.contact.kalker import kalker_coefficients

    if patch.normal_force_N <= 0.0:
        return 0.0, 0.0, 0.0
    y_all, xf_all, dy_all = patch.strip_lateral_m, patch.strip_half_length_m, patch.strip_width_m
    # coarsen the cells into n_strips strips of equal width (rms half-length keeps sum xf^2 dy)
    bounds = np.linspace(0, y_all.size, min(n_strips, y_all.size) + 1).astype(np.int64)
    counts = np.diff(bounds)
    y = np.add.reduceat(y_all, bounds[:-1]) / counts
    xf = np.sqrt(np.add.reduceat(xf_all**2, bounds[:-1]) / counts)
    dy = dy_all * counts.astype(float)
    a = float(np.max(xf))
    b = 0.5 * (patch.lateral_extent_m[1] - patch.lateral_extent_m[0])
    c11, c22, c23 = kalker_coefficients(a / b, poisson)
    g = shear_modulus_Pa
    kx = xi * 3.0 * c11 * g / (8.0 * a)
    ky = eta * 3.0 * c22 * g / (8.0 * a)
    ks = phi * 4.0 * c23 * g / (math.pi * a * math.sqrt(a / b))
    coef = friction * patch.pressure_coefficient_Pa_per_m
    fx, fy, mz = _strip_fastsim(y, xf, dy, kx, ky, ks, coef, int(n_points))
    return float(fx), float(fy), float(mz)


@numba.njit(cache=True)
def _strip_fastsim(y, xf, dy, kx, ky, ks, coef, n_points):
    """FASTSIM march on strips of half-length ``xf`` with the bound ``coef sqrt(xf^2 - x^2)``."""
    fx = 0.0
    fy = 0.0
    mz = 0.0
    for j in range(y.size):
        if xf[j] <= 0.0:
            continue
        dx = 2.0 * xf[j] / n_points
        px = 0.0
        py = 0.0
        x_prev = xf[j]
        for i in range(n_points):
            xc = xf[j] - (i + 0.5) * dx
            h = x_prev - xc
            xm = 0.5 * (x_prev + xc)
            px -= h * (kx - ks * y[j])
            py -= h * (ky + ks * xm)
            q = xf[j] * xf[j] - xc * xc
            bound = coef * math.sqrt(q) if q > 0.0 else 0.0
            mag2 = px * px + py * py
            if mag2 > bound * bound:
                scale = bound / math.sqrt(mag2)
                px *= scale
                py *= scale
            w = dx * dy[j]
            fx += px * w
            fy += py * w
            mz += (xc * py - y[j] * px) * w
            x_prev = xc
    return fx, fy, mz


@numba.njit(cache=True)
def _locus_profile(wtab, winfo, rtab, rinfo, cy, cz, phi, psi, s_all, gaps, ys, radii):
    """Vertical gap, rail lateral position and rolling radius along the contact locus at the
    wheel coordinates ``s_all`` (the kernel's geometry); returns how many are on both tables."""
    ctx = K._make_ctx(winfo, rinfo, cy, cz, phi, psi)
    n = 0
    for s in s_all:
        f, f1, f2, ok = K._hermite(wtab, winfo[K.WI_S0], winfo[K.WI_STEP], int(winfo[K.WI_N]), s)
        if not ok:
            continue
        g, _, py, _, _, _, _, ok = K._locus_gap(s, f, f1, f2, rtab, ctx)
        if ok:
            gaps[n] = g
            ys[n] = py
            radii[n] = winfo[K.WI_R0] + f
            n += 1
    return n
