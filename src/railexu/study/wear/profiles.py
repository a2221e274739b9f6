"""Worn wheel profiles: smoothing of the worn depth, the update, the files, the flange measures.

* :func:`smooth_depth`: a Gaussian moving average of the worn depth across the profile (the
  patch-by-patch deposit is rough where few contact positions were visited); the worn area is
  kept exactly (renormalised);
* :func:`smooth_normal_depth`: what the loop smooths: the depth normal to the surface (the
  deposit's height change times ``cos(a)``, ``a`` the flank angle of the current profile),
  spread along ``y`` by :func:`smooth_depth` and turned back into the height change with the
  angle averaged by the same Gaussian; the worn area kept exactly;
* :func:`worn_profile`: ``F_new(s) = F(s) - depth(s)`` on the profile's graph domain, written as
  a two-column text profile with its ``# railexu profile:`` declaration (railexu reads it back
  with :func:`railexu.profiles.wheel_profile`) and read back; the loop always takes the
  *cumulated* depth off the *new* profile (never the re-read worn one), so the re-splining of
  the points does not accumulate over the steps, and writes the points every 0.05 mm (the
  re-read S1002 then lies within 0.08 um of the built-in, 2.3 um with 0.2 mm points);
* :func:`profile_check`: what a measured profile must show, checked on every worn profile: a
  graph (increasing lateral points), the flange flank monotone (the radius falls from the flange
  tip to the tape circle), and the largest change of the lateral curvature against the new
  profile (bounded by the smoothing: about ``depth / sigma^2`` in the graph's second
  derivative);
* :func:`flange_measures`: flange height ``Sh``, flange thickness ``Sd`` and ``qR`` as EN 15313
  defines them on the profile: ``Sh`` the flange tip's radius increase over the tape circle;
  ``Sd`` from the flange back to the flank point 10 mm above the tape circle; ``qR`` the lateral
  distance between that point and the flank point 2 mm below the flange tip. New S1002 (flange
  back 70 mm from the tape circle): Sh 28.0 mm, Sd 32.5 mm, qR 10.8 mm (checked in the tests).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from railexu.profiles import Profile, wheel_profile

#: height of the Sd point above the tape circle (EN 15313) [m]
SD_HEIGHT_M = 0.010
#: depth of the qR point below the flange tip (EN 15313) [m]
QR_DEPTH_M = 0.002
#: distance from a curvature jump of the new profile within which profile_check does not
#: bound the curvature change [m]
JUMP_GUARD_M = 3.0e-4
#: the lateral step of the worn profiles' points [m] (module doc: 0.05 mm keeps the re-read
#: profile within 0.1 um of the one written; 0.2 mm left 2.3 um and slope errors of 0.05 at
#: S1002's curvature jumps)
POINT_STEP_M = 5.0e-5


def smooth_depth(depth_m: np.ndarray, step_m: float, width_m: float) -> np.ndarray:
    """The depth averaged with a Gaussian of standard deviation ``width_m`` on its uniform grid
    (``step_m``); the sum (the worn area) is kept exactly. ``width_m = 0``: unchanged."""
    depth = np.asarray(depth_m, dtype=float)
    if width_m <= 0.0 or depth.sum() <= 0.0:
        return depth.copy()
    half = int(math.ceil(4.0 * width_m / step_m))
    u = np.arange(-half, half + 1) * step_m / width_m
    kernel = np.exp(-0.5 * u * u)
    kernel /= kernel.sum()
    out = np.convolve(depth, kernel, mode="same")
    return out * (depth.sum() / out.sum())


def smooth_normal_depth(
    depth_m: np.ndarray, step_m: float, width_m: float, slope: np.ndarray
) -> np.ndarray:
    """The worn depth smoothed as the contact's lateral wander spreads it: along ``y``, as the
    depth **normal to the surface** (module doc), returned as the graph's height change [m].

    ``depth_m`` is the deposit's area per lateral grid step (the height the graph loses,
    :func:`railexu.contact.wear.patch.wear_on_profile`); on the profile's flank of slope
    ``slope = dF/dy`` (at the grid nodes) the patch wore ``depth cos(a)`` along the normal,
    ``tan(a) = |slope|``. That normal depth is smoothed by :func:`smooth_depth` (a Gaussian of
    standard deviation ``width_m`` along ``y``) and turned back into the height change
    ``d_n / cos(a)`` with ``cos(a)`` averaged by the same Gaussian (a smooth normal direction:
    :func:`_gaussian_mean`), the sum (the worn area) kept exactly. A uniform
    normal depth ``d`` on a straight flank stays uniform: the flank moves ``d / cos(a)`` down
    and ``d / sin(a)`` sideways, as a normal offset does. (Smoothing the height change itself
    carried the steep flank's height change, ``1 / cos(a)`` times its normal depth, onto the
    flatter flange root below it: the wagon's loop on ``curvy_10.yaml`` wore the root flat at
    s = -35.8 mm, 3.37 mm of height change where the contacts had worn 0.045 mm, and stopped at
    31.35 km; docs/wear.md, "Long loops".) ``width_m = 0``: unchanged.
    """
    depth = np.asarray(depth_m, dtype=float)
    if width_m <= 0.0 or depth.sum() <= 0.0:
        return depth.copy()
    cos_a = 1.0 / np.sqrt(1.0 + np.asarray(slope, dtype=float) ** 2)
    if cos_a.shape != depth.shape:
        raise ValueError(f"slope has {cos_a.shape} values, the depth {depth.shape}")
    out = smooth_depth(depth * cos_a, step_m, width_m) / _gaussian_mean(cos_a, step_m, width_m)
    return out * (depth.sum() / out.sum())


def _gaussian_mean(values: np.ndarray, step_m: float, width_m: float) -> np.ndarray:
    """``values`` averaged by the Gaussian of :func:`smooth_depth` (the ends continued with
    their end values). The normal depth is turned back into a height change with the flank
    angle averaged over the smoothing's width: at S1002's curvature jumps (the flange root's
    arc meets the 70 deg flank at s = -38.42 mm) ``1 / cos(a)`` has a kink, which the local
    angle put into the worn profile (its curvature changed by 85 1/m there after 8.4 km of the
    wagon's loop, against 14 1/m with the former smoothing)."""
    half = int(math.ceil(4.0 * width_m / step_m))
    u = np.arange(-half, half + 1) * step_m / width_m
    kernel = np.exp(-0.5 * u * u)
    kernel /= kernel.sum()
    padded = np.concatenate([np.full(half, values[0]), values, np.full(half, values[-1])])
    return np.convolve(padded, kernel, mode="valid")


def profile_slope(profile: Profile, grid_y_m: np.ndarray) -> np.ndarray:
    """``dF/dy`` of a wheel profile at the grid nodes [-]; beyond its graph domain the end
    slopes (where the depth grid is longer than the profile, no contact wears)."""
    lo, hi = float(profile.lateral_m[0]), float(profile.lateral_m[-1])
    return np.asarray(profile.slope(np.clip(np.asarray(grid_y_m, dtype=float), lo, hi)),
                      dtype=float)  # fmt: skip


def worn_points(profile: Profile, grid_y_m: np.ndarray, depth_m: np.ndarray):
    """``(s, F - depth)`` of the worn wheel on the profile's graph domain [m]: points every
    :data:`POINT_STEP_M` and its two ends (the depth interpolated by a cubic spline through its
    grid, zero outside the grid)."""
    lo, hi = float(profile.lateral_m[0]), float(profile.lateral_m[-1])
    inner = np.arange(math.ceil(lo / POINT_STEP_M), math.floor(hi / POINT_STEP_M) + 1)
    s = np.unique(np.concatenate([[lo], inner * POINT_STEP_M, [hi]]))
    s = s[(s >= lo) & (s <= hi)]
    # a cubic spline through the depth's grid (finer points than the grid must not put kinks
    # into the profile: linear interpolation between 0.2 mm nodes did, 30 1/m of curvature)
    grid = np.asarray(grid_y_m, dtype=float)
    inside = (s >= grid[0]) & (s <= grid[-1])
    d = np.zeros_like(s)
    d[inside] = CubicSpline(grid, np.asarray(depth_m, dtype=float))(s[inside])
    return s, np.asarray(profile.height(s), dtype=float) - d


def write_wheel_profile(path: Path, s_m: np.ndarray, f_m: np.ndarray, flange_back_m: float,
                        note: str = "") -> Path:  # fmt: skip
    """Write a wheel profile as declared two-column text in mm (railexu's axes)."""
    lines = [
        f"# worn wheel profile written by railexu's wear loop{': ' + note if note else ''}",
        "# railexu profile: wheel, unit = mm, lateral = outwards, height = radius_increase, "
        f"flange_back = {flange_back_m * 1e3:.6f}",
    ]
    lines += [f"{a * 1e3:.6f} {b * 1e3:.7f}" for a, b in zip(s_m, f_m, strict=True)]
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
    tmp.replace(path)
    return path


def worn_profile(
    profile: Profile, grid_y_m: np.ndarray, depth_m: np.ndarray, path: Path, note: str = ""
) -> Profile:
    """The worn profile (module doc), written to ``path`` and read back."""
    s, f = worn_points(profile, grid_y_m, depth_m)
    fb = profile.flange_back_m if profile.flange_back_m is not None else float(s[0])
    write_wheel_profile(path, s, f, fb, note)
    return wheel_profile(path)


def _flank_crossing(s: np.ndarray, f: np.ndarray, level: float) -> float:
    """The lateral position where the flank (from the flange tip towards the tread) comes down
    to ``level`` (linear between samples); NaN if it does not."""
    tip = int(np.argmax(f))
    fl, sl = f[tip:], s[tip:]
    below = np.flatnonzero(fl <= level)
    if below.size == 0 or below[0] == 0:
        return math.nan
    j = below[0]
    t = (fl[j - 1] - level) / (fl[j - 1] - fl[j])
    return float(sl[j - 1] + t * (sl[j] - sl[j - 1]))


def flange_measures(profile: Profile) -> dict:
    """``Sh``, ``Sd``, ``qR`` [m] of a wheel profile (module doc) and the tape-circle radius
    change ``F(0)`` [m]."""
    lo, hi = float(profile.lateral_m[0]), float(profile.lateral_m[-1])
    s = np.linspace(lo, hi, int(round((hi - lo) / 1e-5)) + 1)
    f = np.asarray(profile.height(s), dtype=float)
    f0 = float(profile.height(0.0))
    tip = float(f.max())
    s_sd = _flank_crossing(s, f, f0 + SD_HEIGHT_M)
    s_qr = _flank_crossing(s, f, tip - QR_DEPTH_M)
    fb = profile.flange_back_m if profile.flange_back_m is not None else lo
    return {
        "flange_height_m": tip - f0,
        "flange_thickness_m": s_sd - fb,
        "qR_m": s_sd - s_qr,
        "tape_circle_change_m": f0,
    }


def removed_area(old: Profile, new: Profile, step_m: float = 1e-5) -> float:
    """The area between two wheel profiles over the old one's graph domain [m^2] (the new one
    continued with its end values where its domain is shorter)."""
    lo, hi = float(old.lateral_m[0]), float(old.lateral_m[-1])
    s = np.linspace(lo, hi, int(round((hi - lo) / step_m)) + 1)
    nlo, nhi = float(new.lateral_m[0]), float(new.lateral_m[-1])
    sn = np.clip(s, nlo, nhi)
    diff = np.asarray(old.height(s), dtype=float) - np.asarray(new.height(sn), dtype=float)
    return float(np.trapezoid(diff, s))


def profile_check(profile: Profile, reference: Profile) -> dict:
    """Checks of a worn wheel profile against its new ``reference`` (module doc).

    Returns ``flange_monotone`` (bool: the radius increase falls strictly from the flange tip
    to the tape circle, sampled every 0.01 mm), ``flank_rise_m`` (how far the radius rises
    again on the way from the flange tip to the tape circle, the largest ``F(s2) - F(s1)`` with
    ``s1 < s2`` [m]: 0 on a monotone flange, the depth of a dip or flat worn into it
    otherwise), ``max_curvature_change_1_per_m`` (the largest
    change of the profile curve's curvature ``F'' / (1 + F'^2)^1.5`` on the tread and flange,
    ``s`` from the flange tip to +50 mm, except within :data:`JUMP_GUARD_M` of the new
    profile's curvature jumps) and where it is (``s`` [m]).
    """
    lo, hi = float(profile.lateral_m[0]), float(profile.lateral_m[-1])
    s = np.linspace(lo, hi, int(round((hi - lo) / 1e-5)) + 1)
    f = np.asarray(profile.height(s), dtype=float)
    tip = int(np.argmax(f))
    flank = f[tip : int(np.searchsorted(s, 0.0)) + 1]
    monotone = bool(flank.size > 1 and np.all(np.diff(flank) < 0.0))
    rise = float(np.max(flank - np.minimum.accumulate(flank))) if flank.size else 0.0
    band = (s >= s[tip]) & (s <= 0.05)
    sb = s[band]

    def curvature(p: Profile) -> np.ndarray:
        d1 = np.asarray(p.slope(sb), dtype=float)
        return np.asarray(p.second_derivative(sb), dtype=float) / (1.0 + d1 * d1) ** 1.5

    k_ref = curvature(reference)
    change = np.abs(curvature(profile) - k_ref)
    # within JUMP_GUARD_M of a curvature jump of the reference (S1002's arc/line junctions) the
    # re-read points' C2 spline cannot follow the jump: left out of the bound
    jumps = sb[1:][np.abs(np.diff(k_ref)) > 5.0]
    if jumps.size:
        near = np.min(np.abs(sb[:, None] - jumps[None, :]), axis=1) <= JUMP_GUARD_M
        change = np.where(near, 0.0, change)
    i = int(np.argmax(change))
    return {
        "flange_monotone": monotone,
        "flank_rise_m": rise,
        "max_curvature_change_1_per_m": float(change[i]),
        "max_curvature_change_at_m": float(sb[i]),
    }
