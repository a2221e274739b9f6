"""Tests of railexu.profiles: analytic S1002 and 60E1, readers, sampled tables, registry.

The external checks are the published S1002 check values and arc data (docs/theory.md 2.2, 2.3)
and the Manchester benchmark files, which were made independently of this code.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from railexu.profiles import (
    MAX_SLOPE,
    MAX_SLOPE_DEG,
    Profile,
    ProfileError,
    SampledProfile,
    cone_wheel,
    flat_rail,
    mbench_s1002,
    mbench_uic60,
    rail_60e1,
    rail_60e1_geometry_mm,
    rail_profile,
    read_simpack_profile,
    read_xy_profile,
    round_rail,
    s1002,
    s1002_analytic,
    wheel_profile,
)

MM = 1e-3
CANT_1_40 = math.atan(1.0 / 40.0)


# ---------------------------------------------------------------------------------------------
# S1002
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("s_mm", "f_mm", "tol_mm"),
    [
        # published check values, given to 3 or 5 decimals: tolerance half a unit of the last digit
        (-55.0, 28.000, 5e-4),
        (-37.5, 10.000, 5e-4),
        (-20.0, 1.59656, 5e-6),
        (20.0, -0.31176, 5e-6),
    ],
)
def test_s1002_check_values(s_mm, f_mm, tol_mm):
    w = s1002()
    assert abs(float(w.height(s_mm * MM)) / MM - f_mm) <= tol_mm


def test_s1002_flange_back_flank_and_domain():
    w = s1002()
    assert w.kind == "wheel" and w.flange_back_m == pytest.approx(-0.070)
    # flange back: the outline starts at F(-70) = 9.51926 mm with a vertical tangent
    assert w.outline_m[0, 0] == pytest.approx(-0.070, abs=1e-12)
    assert w.outline_m[0, 1] / MM == pytest.approx(9.51926, abs=5e-6)
    assert w.outline_m[-1, 0] == pytest.approx(0.060)
    # flank: 70.0 deg (atan 2.747477), falling towards the tread
    flank = math.degrees(math.atan(-float(w.slope(-39.0 * MM))))
    assert flank == pytest.approx(70.0, abs=5e-5)
    # graph cut on the R20.5 flange back where the slope reaches tan 80 deg:
    # s = -49.5 - 20.5 sin 80 deg
    assert w.y_min / MM == pytest.approx(-49.5 - 20.5 * math.sin(math.radians(80.0)), abs=1e-9)
    assert float(w.slope(w.y_min)) == pytest.approx(MAX_SLOPE, rel=1e-9)
    assert w.y_max == pytest.approx(0.060)
    # every flange angle a contact needs (up to ~72-78 deg) is in the graph
    ang = np.degrees(np.arctan(np.abs(w.slope(np.linspace(w.y_min, w.y_max, 20001)))))
    assert ang.max() == pytest.approx(MAX_SLOPE_DEG, abs=1e-6)


def test_s1002_smoothed_stays_on_published_definition():
    """The graph follows the published sections; the blends at -26 / -35 mm stay between the
    two sections, so the deviation is at most the published jump (1.2e-4 mm)."""
    w = s1002()
    s = np.linspace(w.y_min, w.y_max, 400001)
    dev = np.abs(w.height(s) / MM - s1002_analytic(s / MM))
    assert np.nanmax(dev) <= 1.2e-4
    # away from the two blend bands the graph is the analytic curve to interpolation accuracy
    far = (np.abs(s / MM + 26.0) > 0.5) & (np.abs(s / MM + 35.0) > 0.5)
    assert np.nanmax(dev[far]) <= 1e-7  # mm; quintic Hermite error on 0.1 mm nodes


@pytest.mark.parametrize("s_j", [-26.0, -35.0])
def test_s1002_junctions_are_smooth(s_j):
    w = s1002()
    # the published definition jumps there ...
    jump = s1002_analytic(s_j) - s1002_analytic(s_j - 1e-9)
    assert abs(jump) > 3e-5
    # ... the smoothed graph is continuous in value, slope and curvature (C2). With eps = 1 nm
    # the differences of a smooth function are <= 2 eps max|derivative|.
    eps = 1e-9
    y0, y1 = (s_j * MM - eps), (s_j * MM + eps)
    assert abs(float(w.height(y1) - w.height(y0))) <= 2 * eps * 1.0
    assert abs(float(w.slope(y1) - w.slope(y0))) <= 2 * eps * 1e3
    d2 = w.second_derivative(np.array([y0, y1]))
    assert abs(d2[1] - d2[0]) <= 1e-5 * abs(d2[0])
    # slope continuous over the whole blend band: no step between 1 um neighbours larger than
    # the curvature allows
    y = np.linspace(s_j - 0.6, s_j + 0.6, 1201) * MM
    steps = np.abs(np.diff(w.slope(y)))
    assert steps.max() <= np.abs(w.second_derivative(y)).max() * 1e-3 * MM * 1.01


# ---------------------------------------------------------------------------------------------
# 60E1
# ---------------------------------------------------------------------------------------------


def test_60e1_top_and_symmetry():
    r = rail_60e1()
    assert r.kind == "rail" and r.inclination_rad == 0.0
    assert float(r.height(0.0)) == pytest.approx(0.0, abs=1e-15)
    assert float(r.slope(0.0)) == pytest.approx(0.0, abs=1e-12)
    y = np.linspace(0.0, r.y_max, 5001)
    assert np.max(np.abs(r.height(y) - r.height(-y))) <= 1e-15
    assert np.max(np.abs(r.slope(y) + r.slope(-y))) <= 1e-9
    assert r.y_min == pytest.approx(-r.y_max, abs=1e-15)
    # the outline too: mirror image of itself
    o = r.outline_m
    assert np.allclose(o[::-1, 0], -o[:, 0], atol=1e-15) and np.allclose(o[::-1, 1], o[:, 1])
    # the crown is the highest point
    assert np.max(r.height(np.linspace(r.y_min, r.y_max, 20001))) <= 1e-15


def test_60e1_arcs_are_tangent_and_have_published_radii():
    r = rail_60e1()
    g = rail_60e1_geometry_mm()
    # centres within 0.3 um of the published (rounded) ones
    assert np.allclose(g["c80"], [7.700, -80.135], atol=3e-4)
    assert np.allclose(g["c13"], [23.016, -14.909], atol=3e-4)
    # published tangent abscissae
    assert g["t300_80"][0] == pytest.approx(10.500, abs=1e-4)
    assert g["t80_13"][0] == pytest.approx(25.988, abs=1e-3)
    eps = 1e-9
    for y_t, (r_in, r_out) in ((10.500e-3, (300, 80)), (25.98775e-3, (80, 13))):
        y_t = float(g["t300_80"][0] if r_in == 300 else g["t80_13"][0]) * MM
        for sign in (1.0, -1.0):
            a, b = sign * (y_t - eps), sign * (y_t + eps)
            # tangent: value and slope continuous
            assert abs(float(r.height(b) - r.height(a))) <= 2 * eps * 1.0
            assert abs(float(r.slope(b) - r.slope(a))) <= 2 * eps * 100.0
            # curvature -1/R on each side (convex head)
            assert float(r.curvature(a)) * r_in * MM == pytest.approx(-1.0, rel=1e-6)
            assert float(r.curvature(b)) * r_out * MM == pytest.approx(-1.0, rel=1e-6)
    # the graph is cut on the R13 arc where the slope is tan 80 deg: |y| = 23.016 + 13 cos 10 deg
    assert r.y_max / MM == pytest.approx(23.016 + 13 * math.cos(math.radians(10.0)), abs=1e-3)


def _outline_halfwidth_at(profile: Profile, depth_m: float, side: float) -> float:
    """Lateral position where the outline crosses ``depth_m`` below its top on one side."""
    o = profile.outline_m
    z = o[:, 1] - o[:, 1].max()
    sel = (o[:, 0] * side > 0) & (np.sign(np.diff(z, append=z[-1])) != 0)
    ys, zs = o[sel, 0], z[sel]
    k = np.nonzero(np.diff(np.sign(zs + depth_m)))[0][0]
    t = (-depth_m - zs[k]) / (zs[k + 1] - zs[k])
    return float(ys[k] + t * (ys[k + 1] - ys[k]))


def test_60e1_head_width_and_gauge_point():
    r = rail_60e1()
    g = rail_60e1_geometry_mm()
    # head width 72 mm where the R13 arcs meet the side faces
    assert 2 * g["t13_face"][0] == pytest.approx(72.0, abs=1e-3)
    depth_t = -g["t13_face"][1] * MM
    width = _outline_halfwidth_at(r, depth_t, 1.0) - _outline_halfwidth_at(r, depth_t, -1.0)
    assert width / MM == pytest.approx(72.0, abs=1e-3)
    # gauge point 14 mm below the top lies on the R13 arc: y = 23.016 + sqrt(13^2 - 0.909^2)
    y14 = _outline_halfwidth_at(r, 0.014, -1.0)
    assert -y14 / MM == pytest.approx(23.016 + math.sqrt(13**2 - 0.909**2), abs=1e-3)
    # the side faces widen downwards at 1:20 to 25 mm below the top
    assert r.outline_m[0, 1] / MM == pytest.approx(-25.0)
    y20, y24 = (_outline_halfwidth_at(r, d, 1.0) for d in (0.020, 0.024))
    assert (y24 - y20) / 0.004 == pytest.approx(1 / 20, rel=1e-9)


# ---------------------------------------------------------------------------------------------
# Canting, cones, simple shapes
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", [CANT_1_40, math.atan(1 / 20), -0.03])
def test_canting_flat_rail_rotates_slope(angle):
    r = flat_rail(0.072)
    c = r.canted(angle)
    y = np.linspace(c.y_min, c.y_max, 101)
    assert np.allclose(np.arctan(c.slope(y)), angle, atol=1e-13)
    assert np.allclose(c.second_derivative(y), 0.0, atol=1e-9)
    assert c.inclination_rad == pytest.approx(angle)
    # tilted towards the gauge side (-y): the field-side end is higher
    assert (c.height(c.y_max) > c.height(c.y_min)) == (angle > 0)


def test_canting_60e1_rotates_points_and_tangents():
    r = rail_60e1()
    a = CANT_1_40
    c = r.canted(a)
    assert c.inclination_rad == pytest.approx(a)
    y = np.linspace(-30e-3, 30e-3, 601)
    z = r.height(y)
    yc, zc = math.cos(a) * y - math.sin(a) * z, math.sin(a) * y + math.cos(a) * z
    assert np.max(np.abs(c.height(yc) - zc)) <= 1e-12
    assert np.allclose(np.arctan(c.slope(yc)), np.arctan(r.slope(y)) + a, atol=1e-9)
    # geometric curvature is invariant under rotation
    assert np.allclose(c.curvature(yc), r.curvature(y), rtol=1e-6)
    # the canted head is steeper on the gauge side: graph cut moves inwards there
    assert c.y_min > r.y_min and c.y_max > r.y_max
    # the highest point moves outwards by 300 sin(a) on the R300 crown
    yy = np.linspace(0.0, 0.010, 100001)
    assert yy[np.argmax(c.height(yy))] / MM == pytest.approx(300 * math.sin(a), abs=1e-3)


def test_canting_a_wheel_is_refused():
    with pytest.raises(ValueError, match="only rails"):
        s1002().canted(0.01)


@pytest.mark.parametrize("conicity", [0.025, 0.05, 0.2])
def test_cone_slope(conicity):
    w = cone_wheel(conicity)
    s = np.linspace(w.y_min, w.y_max, 101)
    assert np.allclose(w.slope(s), -conicity, atol=1e-14)
    assert np.allclose(w.height(s), -conicity * s, atol=1e-16)
    assert np.allclose(w.curvature(s), 0.0, atol=1e-9)
    assert w.flange_back_m == pytest.approx(-0.070)


def test_round_rail_curvature_and_cut():
    r = round_rail(0.3, 0.072)
    y = np.linspace(r.y_min, r.y_max, 101)
    assert np.allclose(r.height(y), np.sqrt(0.09 - y * y) - 0.3, atol=1e-15)
    assert np.allclose(r.curvature(y), -1 / 0.3, rtol=1e-9)
    small = round_rail(0.010, 0.0199)  # steeper than 80 deg near the ends: cut
    assert small.y_max == pytest.approx(0.010 * math.sin(math.radians(80.0)), rel=1e-12)
    assert small.outline_m[-1, 0] == pytest.approx(0.00995)


def test_profile_from_knots_and_linear_extension():
    y = np.linspace(-0.01, 0.01, 21)
    p = Profile(
        name="parabola",
        kind="rail",
        lateral_m=y,
        height_m=-(y**2),
        flange_back_m=None,
        inclination_rad=0.0,
        source="test",
        smoothing="not-a-knot cubic through the knots",
        outline_m=np.column_stack([y, -(y**2)]),
    )
    assert float(p.height(0.003)) == pytest.approx(-9e-6, abs=1e-15)  # cubic reproduces it
    assert float(p.second_derivative(0.0)) == pytest.approx(-2.0)
    # outside the domain: linear continuation
    assert float(p.height(0.012)) == pytest.approx(-1e-4 - 0.02 * 0.002)
    assert float(p.second_derivative(0.012)) == 0.0
    with pytest.raises(ValueError):
        p.lateral_m[0] = 1.0  # read-only
    assert p.canted(0.01).inclination_rad == pytest.approx(0.01)


# ---------------------------------------------------------------------------------------------
# Sampled tables
# ---------------------------------------------------------------------------------------------


def _hermite_constants() -> dict[str, float]:
    """Peano-kernel constants of cubic Hermite interpolation on a unit cell for a jump of the
    2nd / 3rd derivative at sigma: max over t, sigma of |g - Hg| / m! (value) and of
    |g' - (Hg)'| / m! (slope), g = (t - sigma)_+^m. Computed here independently of the code."""
    t = np.linspace(0, 1, 1001)[:, None]
    sg = np.linspace(0, 1, 1001)[None, :]
    out = {}
    for m in (2, 3):
        g = np.maximum(t - sg, 0) ** m
        g1 = m * np.maximum(t - sg, 0) ** (m - 1)
        z1, d1 = (1 - sg) ** m, m * (1 - sg) ** (m - 1)
        h_val = (-2 * t**3 + 3 * t**2) * z1 + (t**3 - t**2) * d1
        h_der = (6 * t - 6 * t**2) * z1 + (3 * t**2 - 2 * t) * d1
        out[f"v{m}"] = np.abs(g - h_val).max() / math.factorial(m) * 1.001
        out[f"d{m}"] = np.abs(g1 - h_der).max() / math.factorial(m) * 1.001
    return out


@pytest.mark.parametrize("which", ["s1002", "60e1", "mbench_s1002"])
def test_sampled_table_reproduces_spline(which):
    """Cubic Hermite look-ups on the 0.1 mm grid against the graph spline, with the rigorous
    error bound (Peano kernel): value <= h^4/384 max|z''''| + C3 h^3 sum|jump z'''| +
    C2 h^2 sum|jump z''|, slope <= sqrt(3)/216 h^3 max|z''''| + C3' h^2 sum|jump z'''| +
    C2' h sum|jump z''|; linear z'': <= h^2/8 max|z''''| + h/4 sum|jump z'''| + sum|jump z''|
    (jumps at the spline breakpoints inside the cell)."""
    p = {"s1002": s1002, "60e1": rail_60e1, "mbench_s1002": mbench_s1002}[which]()
    h = 1e-4
    tab = p.sampled(h)
    assert isinstance(tab, SampledProfile)
    assert tab.y0_m == p.y_min and p.y_max - h < tab.y_end_m <= p.y_max
    # nodes carry the spline values exactly
    assert np.array_equal(tab.z, p.height(tab.y_m))
    assert np.array_equal(tab.dz, p.slope(tab.y_m))
    pp = p.spline
    x, c = pp.x, pp.c  # c[:, i]: coefficients of piece i in powers of (y - x_i), highest first
    der = [pp.derivative(m) for m in range(5)]
    inner = x[1:-1]
    hl = np.diff(x)[:-1]  # length of the piece left of each inner breakpoint

    def left_derivative(m):
        return np.array([np.polyval(np.polyder(c[:, i], m), hl[i]) for i in range(inner.size)])

    j3 = np.abs(der[3](inner) - left_derivative(3))  # jumps of the 3rd derivative
    j2 = np.abs(der[2](inner) - left_derivative(2))  # jumps of z'' (C1 junctions only)
    k = _hermite_constants()
    n_cells = tab.n - 1
    lo = tab.y0_m + h * np.arange(n_cells)
    hi = lo + h
    # per cell: jumps inside, max |z''''| (linear on each quintic piece: at ends and breakpoints)
    a = np.searchsorted(inner, lo, side="left")
    b = np.searchsorted(inner, hi, side="right")
    s3 = np.array([j3[i:j].sum() for i, j in zip(a, b, strict=True)])
    s2 = np.array([j2[i:j].sum() for i, j in zip(a, b, strict=True)])
    f4 = np.maximum(np.abs(der[4](lo)), np.abs(der[4](hi)))
    f4_right = np.abs(der[4](inner))
    f4_left = np.abs(left_derivative(4))
    for i, (ia, ib) in enumerate(zip(a, b, strict=True)):
        if ib > ia:
            f4[i] = max(f4[i], f4_right[ia:ib].max(), f4_left[ia:ib].max())
    bound_v = h**4 / 384 * f4 + k["v3"] * h**3 * s3 + k["v2"] * h**2 * s2
    bound_d = math.sqrt(3) / 216 * h**3 * f4 + k["d3"] * h**2 * s3 + k["d2"] * h * s2
    bound_2 = h**2 / 8 * f4 + h / 4 * s3 + s2
    for t in (0.13, 0.37, 0.5, 0.71, 0.94):
        y = lo + t * h
        z, dz, d2z = tab.lookup(y)
        tiny = 1e-15 + 1e-12 * np.abs(p.height(y))  # rounding of the evaluation itself
        assert np.all(np.abs(z - p.height(y)) <= bound_v + tiny)
        assert np.all(np.abs(dz - p.slope(y)) <= bound_d + 1e-9 * (1 + np.abs(p.slope(y))))
        assert np.all(np.abs(d2z - p.second_derivative(y)) <= bound_2 + 1e-6 * (1 + np.abs(d2z)))
    # on the tread (|slope| < 0.1) the table is exact to 2 nm (largest: 60E1 R300/R80
    # tangency, 0.016 h^2 (1/80 - 1/300) / mm = 1.5 nm); the largest errors overall sit in the
    # cells holding a big curvature jump (S1002 R13 arc / 70 deg flank: 0.2 um at h = 0.1 mm)
    tread = np.abs(tab.dz[:-1]) < 0.1
    y = lo[tread] + 0.5 * h
    assert np.max(np.abs(tab.lookup(y)[0] - p.height(y))) < 2e-9
    # outside the table: no value
    assert np.all(np.isnan(tab.lookup([tab.y0_m - 1e-6, tab.y_end_m + 1e-6])[0]))


# ---------------------------------------------------------------------------------------------
# Manchester benchmark files (external check of the reader and of the analytic profiles)
# ---------------------------------------------------------------------------------------------


def test_mbench_wheel_file_coincides_with_analytic_s1002():
    m = mbench_s1002()
    assert m.kind == "wheel" and m.flange_back_m == pytest.approx(-0.070)
    # after mirror.y and inversion the points run from the flange back outwards
    o = m.outline_m / MM
    assert o[0, 0] == pytest.approx(-69.612628) and o[-1, 0] == pytest.approx(60.0)
    assert np.all(np.diff(o[:, 0]) > 0)
    # the points themselves lie on the published S1002: 8 significant digits, so within half a
    # unit of the last digit of z plus slope (<= 5) times that of y: 5e-6 mm
    assert np.max(np.abs(o[:, 1] - s1002_analytic(o[:, 0]))) <= 5e-6
    # the graph through them: within 1e-3 mm of the analytic graph over the whole common domain
    # (cubic interpolation of 0.4 mm spaced points across the curvature jumps of the flank)
    w = s1002()
    s = np.linspace(max(m.y_min, w.y_min), min(m.y_max, w.y_max), 200001)
    dev = np.abs(m.height(s) - w.height(s)) / MM
    assert dev.max() <= 1e-3
    tread = (s > -30 * MM) & (s < 60 * MM)
    assert dev[tread].max() <= 3e-5


def _fit_rail_file(file_profile: Profile, analytic: Profile, mirror: bool = False):
    """Least-squares lateral shift d (tops aligned): file(y) ~ analytic(+-y - d)."""
    sign = -1.0 if mirror else 1.0
    yf = np.linspace(file_profile.y_min, file_profile.y_max, 100001)
    ya_grid = np.linspace(analytic.y_min, analytic.y_max, 100001)
    top_f = file_profile.height(yf).max()
    top_a = analytic.height(ya_grid).max()

    def residual(d):
        ya = sign * yf - d
        sel = (ya > analytic.y_min) & (ya < analytic.y_max)
        return (file_profile.height(yf[sel]) - top_f) - (analytic.height(ya[sel]) - top_a)

    opt = minimize_scalar(
        lambda d: np.mean(residual(d) ** 2),
        bounds=(-0.02, 0.02),
        method="bounded",
        options={"xatol": 1e-11},
    )
    r = residual(opt.x)
    return opt.x, float(np.sqrt(np.mean(r**2))), float(np.max(np.abs(r))), top_f, top_a


def test_mbench_rail_file_is_canted_60e1_with_gauge_side_negative():
    f = mbench_uic60()
    assert f.kind == "rail" and f.inclination_rad == pytest.approx(CANT_1_40)
    a = rail_60e1().canted(CANT_1_40)
    d, rms, mx, top_f, top_a = _fit_rail_file(f, a)
    # the file's origin is the highest point of the canted head, which lies 300 sin(cant) =
    # 7.498 mm outwards of the rail axis on the R300 crown (the crown is flat to 0.1 um over
    # +-0.02 mm there, so the file places it to some um)
    assert d / MM == pytest.approx(-300 * math.sin(CANT_1_40), abs=0.02)
    assert abs(top_f) < 1e-9  # file: top of rail at height 0
    assert rms < 1e-6 and mx < 5e-6  # m: sub-micrometre agreement of two independent builds
    # mirrored (gauge side at +y), the two do not fit: the file's gauge side is at -y
    _, rms_m, _, _, _ = _fit_rail_file(f, a, mirror=True)
    assert rms_m > 1e-4
    # outline including the steep gauge face: normal distance of every file point (down to
    # 23 mm below the top) to the analytic outline
    pts = f.outline_m - [d, top_f - top_a]
    pts = pts[(top_a - pts[:, 1]) < 0.023]
    A = a.outline_m
    seg_a, seg_b = A[:-1], A[1:]
    ab = seg_b - seg_a
    dist = []
    for p in pts:
        t = np.clip(((p - seg_a) * ab).sum(1) / (ab * ab).sum(1), 0.0, 1.0)
        dist.append(np.min(np.hypot(*(p - seg_a - t[:, None] * ab).T)))
    assert max(dist) < 1e-6
    # graph domains correspond after the shift: the file ends where the analytic canted one does
    assert f.y_min == pytest.approx(a.y_min + d, abs=0.02 * MM)
    assert f.y_max == pytest.approx(a.y_max + d, abs=0.02 * MM)


# ---------------------------------------------------------------------------------------------
# Readers: SIMPACK processing, text files, errors
# ---------------------------------------------------------------------------------------------

_PRR_HEAD = """! test file
  header.begin
    version = 1
    type = {type}
  header.end
  spline.begin
{keys}
    point.begin
"""
_PRR_TAIL = """    point.end
  spline.end
"""


def _write_simpack(tmp_path, name, points, keys="", type_=0, tail=_PRR_TAIL):
    text = _PRR_HEAD.format(type=type_, keys=keys)
    text += "".join(f"{y:.9f}  {z:.9f}\n" for y, z in points) + tail
    path = tmp_path / name
    path.write_text(text)
    return path


def _round_head_points(shift=(0.0, 0.0)):
    """A R300 head, 72 mm wide, in SIMPACK rail axes (z down), mm."""
    y = np.linspace(-36.0, 36.0, 145)
    z = 300.0 - np.sqrt(300.0**2 - y**2)  # down positive
    return np.column_stack([y - shift[0], z - shift[1]])


def test_simpack_processing_order(tmp_path):
    # shift (step 2) happens before mirroring (step 5) and the unit factor (step 7): data
    # shifted by (+5, -1) mm in the file and mirrored; the shift keys bring it back.
    pts = _round_head_points()
    pts_file = np.column_stack([-(pts[:, 0]) - 5.0, pts[:, 1] + 1.0])
    keys = "    shift.y = +5.0\n    shift.z = -1.0\n    mirror.y = 1\n    units.len.f = 1000\n"
    p = read_simpack_profile(_write_simpack(tmp_path, "r.prr", pts_file, keys))
    ref = round_rail(0.3, 0.072)
    y = np.linspace(-0.03, 0.03, 61)
    assert np.max(np.abs(p.height(y) - ref.height(y))) < 1e-9
    # rotation (step 3) about x: y' = y cos a - z sin a, z' = y sin a + z cos a (z down), in
    # degrees with units.ang.f; a head rotated by -a in the file comes back upright
    a = math.radians(2.0)
    yr = pts[:, 0] * math.cos(-a) - pts[:, 1] * math.sin(-a)
    zr = pts[:, 0] * math.sin(-a) + pts[:, 1] * math.cos(-a)
    keys = f"    rotate = {math.degrees(a):.12f}\n    units.ang.f = {180 / math.pi:.15f}\n"
    p = read_simpack_profile(_write_simpack(tmp_path, "rot.prr", np.column_stack([yr, zr]), keys))
    assert np.max(np.abs(p.height(y) - ref.height(y))) < 1e-9
    # bounds (step 4) in file units, after the shift: keep |y| <= 20 mm
    keys = "    bound.y.min = -20\n    bound.y.max = 20\n"
    p = read_simpack_profile(_write_simpack(tmp_path, "b.prr", pts, keys))
    assert p.outline_m[0, 0] == pytest.approx(-0.020) and p.outline_m[-1, 0] == pytest.approx(0.020)
    # units in metres
    p = read_simpack_profile(_write_simpack(tmp_path, "m.prr", pts * 1e-3, "    units.len.f = 1\n"))
    assert np.max(np.abs(p.height(y) - ref.height(y))) < 1e-9


def test_simpack_approx_smooth_uses_a_smoothing_spline(tmp_path):
    text = (
        (Path(__file__).resolve().parents[1] / "src" / "railexu" / "data" / "profiles")
        .joinpath("MBench_S1002_v3.prw")
        .read_text()
    )
    w = s1002()
    s = np.linspace(-60e-3, 59e-3, 5001)
    devs = []
    for lam in (1e-3, 1.0):  # lambda in the file's units (mm^3)
        path = tmp_path / f"smooth{lam:g}.prw"
        path.write_text(
            text.replace("approx.smooth  = +0.000000000000000e+00", f"approx.smooth  = {lam}")
        )
        p = read_simpack_profile(path)
        assert "make_smoothing_spline" in p.smoothing
        devs.append(np.max(np.abs(p.height(s) - w.height(s))))
    # light smoothing stays on the profile (1 um), heavy smoothing departs from it
    assert devs[0] < 1e-6 < devs[1]


def test_simpack_commented_points_are_skipped(tmp_path):
    pts = _round_head_points()
    path = _write_simpack(tmp_path, "c.prr", pts)
    lines = path.read_text().splitlines()
    i = lines.index("    point.begin") + 1
    lines.insert(i, "!-50.0  99.0   ! a commented-out point")
    lines.insert(i + 5, "  ! a comment line inside the block")
    path.write_text("\n".join(lines) + "\n")
    p = read_simpack_profile(path)
    assert p.outline_m.shape[0] == pts.shape[0]
    assert p.outline_m[0, 0] == pytest.approx(-0.036)


def test_simpack_errors_name_file_and_line(tmp_path):
    pts = _round_head_points()
    # missing point block
    path = tmp_path / "nopoints.prr"
    path.write_text(
        _PRR_HEAD.format(type=0, keys="").replace("    point.begin\n", "") + "  spline.end\n"
    )
    with pytest.raises(ProfileError, match=r"nopoints\.prr, line 8: no point block: expected"):
        read_simpack_profile(path)
    # unknown type, on line 4
    path = _write_simpack(tmp_path, "type.prr", pts, type_=2)
    with pytest.raises(ProfileError, match=r"type\.prr, line 4: header type = 2: expected 0"):
        read_simpack_profile(path)
    # type contradicting the extension
    path = _write_simpack(tmp_path, "wheel.prw", pts, type_=0)
    with pytest.raises(ProfileError, match=r"wheel\.prw, line 4: .*contradicts the extension"):
        read_simpack_profile(path)
    # a bad point line: line = 8 (first point line) + 3
    path = _write_simpack(tmp_path, "bad.prr", pts)
    lines = path.read_text().splitlines()
    lines[10] = "1.0 abc"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ProfileError, match=r"bad\.prr, line 11: '1.0 abc': expected a point line"):
        read_simpack_profile(path)
    # non-monotonic lateral data on the flat top: point 41 (line 8 + 40) goes back
    zig = pts.copy()
    zig[40, 0] = zig[38, 0]
    path = _write_simpack(tmp_path, "zig.prr", zig)
    with pytest.raises(
        ProfileError,
        match=r"zig\.prr, line 48: lateral coordinate goes back.*"
        r"expected increasing",
    ):
        read_simpack_profile(path)
    # an unclosed block
    path = _write_simpack(tmp_path, "open.prr", pts, tail="    point.end\n")
    with pytest.raises(ProfileError, match=r"open\.prr, line \d+: 'spline.begin' of line 6 is not"):
        read_simpack_profile(path)


def test_steep_parts_are_kept_in_outline_only(tmp_path):
    # the 60E1 head with its gauge faces, plus the underside of the head going back inwards
    # (a fold-back beyond the steep part, allowed): the graph stops at the slope limit on the
    # R13 arcs as for the analytic profile, the outline keeps every point
    r = rail_60e1()
    o = r.outline_m[::4] / MM
    under = np.column_stack([o[-1, 0] - np.arange(1, 6) * 2.0, np.full(5, o[-1, 1] - 0.5)])
    pts = np.vstack([under[::-1] * [-1, 1], o, under])
    p = read_simpack_profile(_write_simpack(tmp_path, "head.prr", pts * [1, -1]))
    assert p.outline_m.shape[0] == pts.shape[0]
    assert p.y_min == pytest.approx(r.y_min, abs=1e-6)
    assert p.y_max == pytest.approx(r.y_max, abs=1e-6)
    y = np.linspace(p.y_min, p.y_max, 2001)
    assert np.max(np.abs(p.height(y) - r.height(y))) < 1e-7


def test_xy_reader_conventions_and_flips(tmp_path):
    s = np.arange(-69.5, 60.0001, 0.1)
    f = s1002_analytic(s)
    # file: flange at +y, from the field side inwards, comma separated, with comments
    text = "# S1002 sampled, lateral flipped\n" + "".join(
        f"{-a:.9f}, {b:.9f}   # pt\n" if i % 50 == 0 else f"{-a:.9f},{b:.9f}\n"
        for i, (a, b) in enumerate(zip(s, f, strict=True))
    )
    path = tmp_path / "s1002_flipped.txt"
    path.write_text(text)
    p = read_xy_profile(path, "wheel", unit="mm", flip_lateral=True, flange_back_m=-0.070)
    assert p.name == "s1002_flipped" and p.kind == "wheel" and p.flange_back_m == -0.070
    w = s1002()
    y = np.linspace(-60e-3, 59e-3, 20001)
    # 0.1 mm points: the cubic spline cannot follow the curvature jumps of the flank exactly,
    # error ~ 0.016 h^2 |jump z''| = 0.3 um at the R13 / 70 deg junction
    assert np.max(np.abs(p.height(y) - w.height(y))) < 1e-6
    # on the tread: 0.02 um, largest in the -26 mm blend band where z''' is large
    tread = (y > -30e-3) & (y < 30e-3)
    assert np.max(np.abs(p.height(y[tread]) - w.height(y[tread]))) < 5e-8
    # metres and a flipped height column (z down)
    path2 = tmp_path / "rail_m.dat"
    pts = _round_head_points() * 1e-3
    path2.write_text("".join(f"{a:.17g} {b:.17g}\n" for a, b in pts))
    r = read_xy_profile(path2, "rail", unit="m", flip_height=True)
    yy = np.linspace(-0.03, 0.03, 61)
    assert np.max(np.abs(r.height(yy) - round_rail(0.3, 0.072).height(yy))) < 1e-9


def test_xy_reader_errors(tmp_path):
    path = tmp_path / "three.txt"
    path.write_text("# comment\n0 0\n1 0 5\n2 0\n3 0\n")
    with pytest.raises(ProfileError, match=r"three\.txt, line 3: '1 0 5': expected two numbers"):
        read_xy_profile(path, "rail")
    path = tmp_path / "zigzag.txt"
    path.write_text("".join(f"{y} 0.0\n" for y in (-10, -5, 0, 5, 3, 10, 15)))
    with pytest.raises(ProfileError, match=r"zigzag\.txt, line 5: lateral coordinate goes back"):
        read_xy_profile(path, "rail")
    with pytest.raises(ValueError, match="unit"):
        read_xy_profile(path, "rail", unit="inch")
    path = tmp_path / "metres_by_mistake.txt"
    path.write_text("".join(f"{y * 1e-3} 0.0\n" for y in range(-30, 31, 5)))
    with pytest.raises(ProfileError, match=r"lateral extent.*check the length unit"):
        read_xy_profile(path, "rail", unit="mm")


# ---------------------------------------------------------------------------------------------
# Registry
# ---------------------------------------------------------------------------------------------


def test_registry_builtins_case_insensitive():
    assert wheel_profile("S1002") is s1002()
    assert wheel_profile("s1002") is s1002()
    assert rail_profile("uic60") is rail_60e1()
    assert rail_profile("60e1") is rail_60e1()
    assert rail_profile(" MBench_UIC60 ") is mbench_uic60()
    assert wheel_profile("mbench_s1002") is mbench_s1002()


def test_registry_did_you_mean():
    with pytest.raises(
        ProfileError,
        match=r"unknown wheel profile 'S1003'\. Did you mean 'S1002'"
        r".*Built-in wheel profiles: S1002, MBench_S1002",
    ):
        wheel_profile("S1003")
    with pytest.raises(ProfileError, match=r"Did you mean '60E1'.*UIC60, 60E1, MBench_UIC60"):
        rail_profile("60E2")
    with pytest.raises(ProfileError, match=r"unknown rail profile 'banana'\. Built-in"):
        rail_profile("banana")


def test_registry_paths(tmp_path):
    path = _write_simpack(tmp_path, "head.prr", _round_head_points())
    assert rail_profile(path).kind == "rail"
    assert rail_profile(str(path)).name == "head"
    with pytest.raises(ProfileError, match=r"head\.prr: this is a rail profile, expected a wheel"):
        wheel_profile(path)
    txt = tmp_path / "cone.txt"
    declaration = (
        "# railexu profile: wheel, unit = mm, lateral = outwards, height = radius_increase, "
        "flange_back = -60\n"
    )
    txt.write_text(declaration + "".join(f"{s} {-0.05 * s}\n" for s in range(-60, 61, 5)))
    w = wheel_profile(txt)  # text declaring its conventions
    assert np.allclose(w.slope(np.linspace(-0.05, 0.05, 11)), -0.05, atol=1e-12)
    with pytest.raises(ProfileError, match="does not exist"):
        rail_profile(tmp_path / "missing.prr")


# ---------------------------------------------------------------------------------------------
# Text profiles declare their conventions
# ---------------------------------------------------------------------------------------------


def _s1002_text(flip_lateral=False, flip_height=False, declaration=""):
    s = np.arange(-69.5, 60.0001, 0.5)
    f = s1002_analytic(s)
    a = -s if flip_lateral else s
    b = -f if flip_height else f
    return declaration + "".join(f"{x:.9f} {z:.9f}\n" for x, z in zip(a, b, strict=True))


def test_text_wheel_with_flange_on_the_field_side_is_refused(tmp_path):
    """A mirrored S1002 read as it is would have its flange at +y: refused, saying so (such a
    file used to be accepted and gave an equivalent conicity of 0.003)."""
    path = tmp_path / "mirrored.txt"
    path.write_text(_s1002_text(flip_lateral=True))
    with pytest.raises(ProfileError, match="on the field side.*flip_lateral"):
        read_xy_profile(path, "wheel")
    # read with the flip it is S1002 again (0.5 mm points: cubic spline within 5 um)
    p = read_xy_profile(path, "wheel", flip_lateral=True)
    y = np.linspace(-0.05, 0.05, 101)
    assert np.max(np.abs(p.height(y) - s1002().height(y))) < 5e-6


def test_text_wheel_with_heights_of_the_wrong_sign_is_refused(tmp_path):
    path = tmp_path / "z_down.txt"
    path.write_text(_s1002_text(flip_height=True))
    with pytest.raises(ProfileError, match="wrong sign.*flip_height"):
        read_xy_profile(path, "wheel")


def test_registry_text_profile_needs_its_declaration(tmp_path):
    path = tmp_path / "s1002.txt"
    path.write_text(_s1002_text())
    with pytest.raises(ProfileError, match="no '# railexu profile:' line"):
        wheel_profile(path)
    path.write_text(_s1002_text(declaration="# railexu profile: wheel, unit = mm\n"))
    with pytest.raises(ProfileError, match="line 1: missing lateral, height, flange_back"):
        wheel_profile(path)
    decl = (
        "# railexu profile: wheel, unit = mm, lateral = inwards, height = radius_decrease, "
        "flange_back = 70\n"
    )
    path.write_text(_s1002_text(flip_lateral=True, flip_height=True, declaration=decl))
    p = wheel_profile(path)
    assert p.flange_back_m == pytest.approx(-0.070)
    y = np.linspace(-0.05, 0.05, 101)
    assert np.max(np.abs(p.height(y) - s1002().height(y))) < 5e-6


def test_registry_text_rail_declares_its_cant(tmp_path):
    pts = _round_head_points()
    path = tmp_path / "head.txt"
    decl = "# railexu profile: rail, unit = mm, lateral = outwards, height = down, canted = 1:40\n"
    path.write_text(decl + "".join(f"{a:.12g} {b:.12g}\n" for a, b in pts))
    r = rail_profile(path)
    assert r.inclination_rad == pytest.approx(np.arctan(1 / 40), rel=1e-12)
    path.write_text(decl.replace("1:40", "maybe") + "".join(f"{a} {b}\n" for a, b in pts))
    with pytest.raises(ProfileError, match="canted = 'maybe'"):
        rail_profile(path)
