"""The wear loop's smoothing of the depth normal to the surface (docs/wear.md, "One step",
"Long loops on the shipped routes"): area kept, a normal offset on a straight flank, and the
flange kept monotone where smoothing the height change wore the flange root flat."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railexu.profiles import wheel_profile
from railexu.study.wear.profiles import (
    profile_check,
    profile_slope,
    removed_area,
    smooth_depth,
    smooth_normal_depth,
    worn_profile,
    write_wheel_profile,
)

#: the loop's lateral depth grid (results/wear.py): -75 mm in 0.2 mm steps
STEP_M = 2e-4
GRID_Y_M = -0.075 + STEP_M * np.arange(726)


def test_normal_depth_smoothing_keeps_the_area_and_is_the_height_smoothing_on_a_flat():
    """The worn area (the sum of the height change) is kept exactly; on a flat profile (slope 0)
    the normal depth is the height change and the two smoothings agree (to 1e-15 m)."""
    depth = np.zeros(GRID_Y_M.size)
    depth[300:303] = 1e-5
    slope = np.linspace(-3.0, 0.1, GRID_Y_M.size)
    out = smooth_normal_depth(depth, STEP_M, 3e-3, slope)
    assert out.sum() == pytest.approx(depth.sum(), rel=1e-12)
    flat = smooth_normal_depth(depth, STEP_M, 3e-3, np.zeros(GRID_Y_M.size))
    assert np.max(np.abs(flat - smooth_depth(depth, STEP_M, 3e-3))) < 1e-15
    assert np.array_equal(smooth_normal_depth(depth, STEP_M, 0.0, slope), depth)
    with pytest.raises(ValueError, match="slope"):
        smooth_normal_depth(depth, STEP_M, 3e-3, slope[:-1])


@pytest.mark.parametrize("angle_deg", [20.0, 45.0, 70.0])
def test_uniform_normal_depth_offsets_a_straight_flank(tmp_path, angle_deg):
    """A straight flank of angle ``a`` worn by a uniform normal depth ``d`` (the patch's
    deposit: the height change ``d / cos(a)`` per lateral step) is the flank offset along its
    normal: at a fixed height it moves ``d / sin(a)`` sideways (analytic; the 3 mm smoothing
    leaves a uniform normal depth unchanged 4 sigma inside the worn band). Checked within
    0.1 % (measured 0.7e-4, 1.5e-4, 1.7e-4 at 20, 45, 70 deg: the re-read points' spline)."""
    a = math.radians(angle_deg)
    s = np.arange(-0.05, 0.05 + 1e-9, 5e-5)
    flank = write_wheel_profile(tmp_path / "flank.txt", s, -math.tan(a) * s, -0.07)
    p0 = wheel_profile(flank)
    d = 2e-4
    band = np.abs(GRID_Y_M) < 0.03
    deposit = np.where(band, d / math.cos(a), 0.0)
    smoothed = smooth_normal_depth(deposit, STEP_M, 3e-3, profile_slope(p0, GRID_Y_M))
    p1 = worn_profile(p0, GRID_Y_M, smoothed, tmp_path / "worn.txt")
    # the lateral position where the worn flank has the new flank's height at s = 0 (height 0)
    y = np.linspace(-0.01, 0.0, 100001)
    h = np.asarray(p1.height(y))
    shift = -float(y[np.argmin(np.abs(h))])
    assert shift == pytest.approx(d / math.sin(a), rel=1e-3)
    assert float(p0.height(0.0) - p1.height(0.0)) == pytest.approx(d / math.cos(a), rel=1e-3)


def _flank_wear(smoothing, n_steps: int) -> np.ndarray:
    """The cumulated height change of S1002 worn as the wagon's loop on curvy_10.yaml wore
    its front wheels (docs/wear.md, "Long loops"): every step a deposit 0.2 mm wide (sigma;
    the flank contact's narrow patch) on the 70 deg flank, moving from s = -38.8 to -41 mm over
    80 steps, the smoothed step's largest height change 0.1 mm (the loop's rule)."""
    p0 = wheel_profile("S1002")
    slope0 = profile_slope(p0, GRID_Y_M)
    total = np.zeros(GRID_Y_M.size)
    for k in range(n_steps):
        centre = -0.0388 - 0.0022 * k / 79
        deposit = np.exp(-0.5 * ((GRID_Y_M - centre) / 2e-4) ** 2)
        step = smoothing(deposit, slope0 - np.gradient(total, GRID_Y_M))
        total += step * (1e-4 / step.max())
    return total


def test_smooth_flank_wear_keeps_the_flange_monotone(tmp_path):
    """60 steps of the loop's flank wear (``_flank_wear``): smoothing the height change by
    3 mm along y carries the flank's height change (1 / cos(70 deg) = 2.9 times its normal
    depth) onto the flange root and wears it flat (the flange not monotone, at s = -35.4 mm;
    the wagon's loop stopped so at s = -35.8 mm), smoothing the normal depth keeps the flange
    monotone (its flank at s = -36 mm still falls, slope -0.14 measured, below -0.1 asserted)
    and conserves the area
    (the profile read back against the deposit: within 1e-5, measured 2.5e-8; the loop's limit
    is 1 %)."""
    p0 = wheel_profile("S1002")
    height = _flank_wear(lambda d, slope: smooth_depth(d, STEP_M, 3e-3), 60)
    normal = _flank_wear(lambda d, slope: smooth_normal_depth(d, STEP_M, 3e-3, slope), 60)
    worn_height = worn_profile(p0, GRID_Y_M, height, tmp_path / "height.txt")
    worn_normal = worn_profile(p0, GRID_Y_M, normal, tmp_path / "normal.txt")
    assert not profile_check(worn_height, p0)["flange_monotone"]
    assert profile_check(worn_normal, p0)["flange_monotone"]
    # the flange root (s = -36 mm) keeps falling towards the tread
    assert float(worn_normal.slope(-0.036)) < -0.1
    expected = float(normal.sum() * STEP_M)
    assert removed_area(p0, worn_normal) == pytest.approx(expected, rel=1e-5)


def test_flank_rise_measures_a_dip_in_the_flange(tmp_path):
    """``profile_check``'s ``flank_rise_m``: 0 on the new S1002; a groove 0.2 mm deep and
    0.6 mm wide (sigma 0.3 mm) worn into the flange root at s = -27 mm, where the flange falls
    with slope 0.25, leaves a dip that the radius climbs out of again by tens of um (the
    Gaussian's steepest slope 0.4 over the flank's 0.25)."""
    p0 = wheel_profile("S1002")
    assert profile_check(p0, p0)["flank_rise_m"] == 0.0
    groove = 2e-4 * np.exp(-0.5 * ((GRID_Y_M + 0.027) / 3e-4) ** 2)
    check = profile_check(worn_profile(p0, GRID_Y_M, groove, tmp_path / "g.txt"), p0)
    assert not check["flange_monotone"]
    assert 2e-5 < check["flank_rise_m"] < 6e-5


@pytest.mark.parametrize("value", [-1e-6, 2e-3, math.nan])
def test_flank_rise_tolerance_is_checked(tmp_path, value):
    from railexu.errors import InputError
    from railexu.study.wear.loop import wear_loop

    with pytest.raises(InputError, match="flank_rise_tolerance|0 .. 1 mm"):
        wear_loop("wheelset", tmp_path / "none.yaml", 1.0, tmp_path / "out",
                  flank_rise_tolerance_m=value)  # fmt: skip
