"""A turnout as a track (issue 29): geometry against the plan's own construction, the switch
panel's planing rule, facing against trailing, refusals, and a uniform track given as panels
against the same track as one profile.

References outside the code under test: the intersection of the gauge lines is checked by the
alignment module's independent integration of the route's plan (Gauss-Legendre quadrature of
the heading), the crossing angle against atan(1/9.25); the blade and stock rail against the
planing rule's formulas written out here; the zoned and the single profile must give the same
kernel tables bit for bit (the same points interpolated the same way).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from railexu.contact.placement import place_wheel_rail
from railexu.contact.variable_tables import station_tables
from railexu.errors import InputError
from railexu.profiles import ProfileError, rail_profile
from railexu.profiles.variable import ProfileSlices, VariableProfile
from railexu.profiles.variable.switch_panel import (
    SwitchPlaning,
    divergence_m,
    extended_gauge_face,
    switch_panel_slices,
)
from railexu.profiles.variable.zoned import Panel, ZonedProfile
from railexu.track.track import load_track, track_from_dict
from railexu.track.turnout import TurnoutGeometry, route_layout, turnout_side

ROOT = Path(__file__).resolve().parents[1]
TRACKS = ROOT / "tracks"
GAUGE = 1.435


def _plain_points(name="MBench_UIC60"):
    rail = rail_profile(name)
    y = np.arange(rail.y_min, rail.y_max, 5e-5)
    return np.column_stack([y, -rail.height(y)])


def test_the_r245_circle_meets_the_1_in_9_25_crossing():
    """The diverging route's outer gauge line (the alignment's centre line offset by g/2 to the
    right, integrated by the alignment module) crosses the through route's left gauge line
    (y = +g/2) at the IP the turnout computes, at the crossing angle atan(1/9.25)."""
    geo = TurnoutGeometry(245.0, 9.25, GAUGE)
    layout = route_layout(geo, "diverging", "facing", "left", approach_m=10.0, run_out_m=5.0,
                          s0_from_ip_m=0.0, crossing_range_m=(-0.1, 0.2))  # fmt: skip
    sections = [dict(p) for p in layout.sections]
    data = {"format_version": 1, "name": "t", "rail_profile": "MBench_UIC60",
            "geometry": {"type": "sections", "sections": sections}}  # fmt: skip
    alignment = track_from_dict(data).alignment
    x_ip, s_ip_div, angle = geo.intersection()
    s = layout.ip_m
    assert s == pytest.approx(10.0 + s_ip_div, abs=1e-12)
    x, y = alignment.position(s)
    psi = float(alignment.heading(s))
    # the right rail's gauge line: g/2 to the right of the centre line
    gx, gy = x + 0.5 * GAUGE * math.sin(psi), y - 0.5 * GAUGE * math.cos(psi)
    assert gy == pytest.approx(0.5 * GAUGE, abs=1e-9)  # on the through route's left gauge line
    assert gx - 10.0 == pytest.approx(x_ip, abs=1e-9)
    assert angle == pytest.approx(math.atan(1 / 9.25), rel=1e-12)
    assert psi == pytest.approx(math.atan(1 / 9.25), rel=1e-12)
    # the circle ends where the heading reaches the crossing angle: 245 atan(1/9.25) = 26.384 m
    assert layout.curve_m == pytest.approx((10.0, 10.0 + 26.38402), abs=1e-5)
    assert float(alignment.curvature(10.0 + 13.0)) == pytest.approx(1 / 245.0, rel=1e-12)


def test_sides_and_directions():
    """Left-hand turnout: the through route's switch and crossing on the left facing, on the
    right trailing; the diverging route's the other way round; a right-hand turnout mirrors."""
    assert turnout_side("through", "facing", "left") == "left"
    assert turnout_side("through", "trailing", "left") == "right"
    assert turnout_side("diverging", "facing", "left") == "right"
    assert turnout_side("diverging", "trailing", "left") == "left"
    assert turnout_side("diverging", "facing", "right") == "left"


def test_facing_and_trailing_tracks_are_the_same_rails_run_both_ways():
    """The trailing track is the facing one from its other end: the same length, the curve
    turning the other way at mirrored distances, and the zone's rails at track distance T
    facing equal those at (end - T) trailing, on the other side (for 10 positions across the
    switch panel and the crossing)."""
    for route in ("through", "diverging"):
        f = load_track(
            TRACKS / f"turnout_uk_r245_{route}_facing.yaml",
            ["turnout.run_out=40 m", "turnout.approach=30 m"],
        )
        t = load_track(TRACKS / f"turnout_uk_r245_{route}_trailing.yaml")
        end = f.alignment.end_m
        assert t.alignment.end_m == pytest.approx(end, abs=1e-9)
        fz, tz = f.variable_rails, t.variable_rails
        fp = fz.left if route == "through" else fz.right
        tp = tz.right if route == "through" else tz.left
        assert fp is not None and tp is not None
        for d in (30.6, 31.1, 33.3, 37.9, 56.5, 56.6, 56.65, 56.7, 56.75, 56.8):  # not at a slice
            a = fp.curves_at(d - fz.start_m)
            b = tp.curves_at(end - d - tz.start_m)
            assert len(a) == len(b)
            for ca, cb in zip(a, b, strict=True):
                np.testing.assert_allclose(ca, cb, atol=1e-12)
        if route == "diverging":
            mid_f = 30.0 + 13.0
            assert float(f.alignment.curvature(mid_f)) == pytest.approx(1 / 245.0)
            assert float(t.alignment.curvature(end - mid_f)) == pytest.approx(-1 / 245.0)


def test_switch_panel_follows_the_planing_rule():
    """The top surface is the higher of the blade (the head's gauge side to w = w_tip + d(s),
    d = R (1 - cos(s/R)), lowered by drop_tip (1 - s/L_rise)) and the stock rail (the head
    moved by d(s)), checked at slices against those formulas: each visible point lies on its
    rail, and no point of the other rail lies above it; the blade hidden at the toe, the plain
    rail before the toe and beyond the stock rail's reach."""
    head = _plain_points()
    plain = extended_gauge_face(head)  # the gauge face continued down to 45 mm
    assert plain[0, 1] == pytest.approx(float(np.min(head[:, 1])) + 0.045, abs=1e-9)
    radius = 245.0 + 0.5 * GAUGE
    rule = SwitchPlaning()
    profile = VariableProfile(switch_panel_slices(head, radius, rule, "test"))
    y_g, y_f = head[0, 0], head[-1, 0]
    for s in (-0.5, 0.0):  # the blade does not show at the toe (10 mm low, under the head)
        (c,) = profile.curves_at(s)
        _assert_on(c, plain)
    for s in (1.0, 2.0, 3.0, 5.0):  # at slices: exact
        d = radius * (1 - math.cos(s / radius))
        assert float(divergence_m(s, radius)) == pytest.approx(d, rel=1e-12)
        blade, stock = profile.curves_at(s)
        w = min(rule.tip_width_m + d, y_f - y_g)
        drop = rule.tip_drop_m * max(0.0, 1 - s / rule.rise_length_m)
        assert blade[0, 0] == pytest.approx(plain[0, 0], abs=1e-12)
        assert blade[-1, 0] <= y_g + w + 1e-9
        assert stock[0, 0] - blade[-1, 0] == pytest.approx(1e-6, abs=1e-9)
        z_blade = np.interp(blade[:, 0], plain[:, 0], plain[:, 1]) + drop
        np.testing.assert_allclose(blade[:, 1], z_blade, atol=5e-6)  # as _assert_on
        z_stock = np.interp(stock[:, 0] - d, plain[:, 0], plain[:, 1])
        np.testing.assert_allclose(stock[:, 1], z_stock, atol=5e-6)
        # the other rail is not above the visible one (z down), where both exist; 50 um: the
        # meeting point is found on a 10 um grid, on flanks of slope 5
        under = stock[:, 0] <= y_g + w
        z_other = np.interp(stock[under, 0], plain[:, 0], plain[:, 1]) + drop
        assert np.all(stock[under, 1] <= z_other + 5e-5)
        over = blade[:, 0] >= plain[0, 0] + d
        assert np.all(blade[over, 1] <= np.interp(blade[over, 0] - d, plain[:, 0], plain[:, 1])
                      + 5e-5)  # fmt: skip
    beyond = profile.curves_at(9.0)
    assert len(beyond) == 1 and beyond[0][-1, 0] == pytest.approx(y_f, abs=1e-12)
    _assert_on(beyond[0], plain)


def _assert_on(curve, plain, atol=5e-6):
    """The resampled curve's points lie on the plain rail's polyline (within 5 um: PCHIP
    against straight 50 um segments, on the head's flanks of slope ~5 and more)."""
    z = np.interp(curve[:, 0], plain[:, 0], plain[:, 1])
    np.testing.assert_allclose(curve[:, 1], z, atol=atol)


def _uniform_slices(points, positions, name):
    n = len(positions)
    return ProfileSlices(name, np.asarray(positions, dtype=float), (points,) * n, None,
                         (None,) * n, (name,) * n)  # fmt: skip


def test_uniform_track_as_panels_equals_one_profile():
    """A uniform track (the plain rail everywhere) given as panels of slices along a zone
    (ZonedProfile: two panels, the plain rail between) and as one profile of two slices gives
    the same kernel tables at 13 stations (panels, their ends, the plain stretch), identical to
    the last bit."""
    plain = _plain_points()
    one = VariableProfile(_uniform_slices(plain, [0.0, 3.0], "one"))
    panels = ZonedProfile(
        [Panel(VariableProfile(_uniform_slices(plain, [0.0, 0.4, 0.7, 1.0], "a"))),
         Panel(VariableProfile(_uniform_slices(plain, [-0.5, 0.0, 0.5], "b")), 2.5)],
        plain, "zoned",
    )  # fmt: skip
    pair = place_wheel_rail("S1002", "MBench_UIC60", nominal_radius_m=0.46, inclination="1:40")
    stations = np.arange(0.0, 3.0001, 0.25)
    a, info_a = station_tables(one, pair, stations)
    b, info_b = station_tables(panels, pair, stations)
    np.testing.assert_array_equal(info_a, info_b)
    np.testing.assert_array_equal(a, b)


def _write(tmp_path, text, name="t.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return p


_TRACK = """format_version: 1
name: t
rail_profile: MBench_UIC60
turnout:
  design: {design}
  route: {route}
  direction: facing
{extra}"""


@pytest.mark.parametrize(
    ("route", "extra", "expected"),
    [
        ("sideways", "", "turnout.route"),
        ("through", "geometry: {type: straight}\n", "geometry"),
        ("through", "variable_rails: none\n", "variable_rails"),
        ("through", "start: 39 m\n", "turnout"),
    ],
)
def test_track_refusals_name_the_key(tmp_path, route, extra, expected):
    design = TRACKS / "turnouts" / "uk_56e1_r245_1v9.25.yaml"
    p = _write(tmp_path, _TRACK.format(design=design, route=route, extra=extra))
    with pytest.raises(InputError) as err:
        load_track(p)
    assert expected in str(err.value)
    assert "t.yaml" in str(err.value)


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (('crossing_angle: "1:9.25"', 'crossing_angle: "1:0"'), "crossing_angle"),
        (("radius: 245 m", "radius: .nan"), "radius"),
        (("tip_width: 6 mm", "tip_width: 60 mm"), "switch.tip_width"),
        (("hand: left", "hand: up"), "hand"),
        (("slices: ../uk_crossing/", "slices: ../nowhere/"), "crossing"),
    ],
)
def test_design_refusals_name_the_file_line_and_key(tmp_path, change, expected):
    text = (TRACKS / "turnouts" / "uk_56e1_r245_1v9.25.yaml").read_text()
    assert change[0] in text
    (tmp_path / "turnouts").mkdir()
    design = _write(tmp_path / "turnouts", text.replace(*change), "d.yaml")
    (tmp_path / "uk_crossing").symlink_to(TRACKS / "uk_crossing")
    p = _write(tmp_path, _TRACK.format(design=design, route="through", extra=""))
    with pytest.raises(InputError) as err:
        load_track(p)
    message = str(err.value)
    assert "d.yaml" in message and expected in message, message


def test_zoned_profile_panels_and_plain_stretches():
    """Panels must not overlap (refused, naming both); the plain stretches between them are
    reported as such (a table store may keep their one table once)."""
    plain = _plain_points()
    a = VariableProfile(_uniform_slices(plain, [0.0, 1.0], "a"))
    b = VariableProfile(_uniform_slices(plain, [-0.5, 0.5], "b"))
    zoned = ZonedProfile([Panel(b, 2.5), Panel(a)], plain, "z")
    assert zoned.s_range_m == (0.0, 3.0)
    assert zoned.is_plain_over(1.01, 1.99)
    assert not zoned.is_plain_over(0.95, 1.5)
    assert not zoned.is_plain_over(1.5, 2.0)
    assert zoned.panel_at(1.5) is None and zoned.panel_at(2.2).s0_m == 2.5
    with pytest.raises(ProfileError, match="overlap"):
        ZonedProfile([Panel(a), Panel(b, 1.2)], plain, "z")
