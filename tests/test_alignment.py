"""Track design geometry (railexu.track.alignment) against closed-form geometry: circle, clothoid
(Fresnel's integrals), continuity, heading changes, file parsing errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import fresnel

from railexu.errors import InputError
from railexu.inputs import parse_yaml
from railexu.track.alignment import (
    TAB_KAPPA,
    TAB_PSI,
    TAB_X,
    TAB_Y,
    alignment_from_dict,
    alignment_from_sections,
)


def _sections(*items):
    return alignment_from_sections([dict(i) for i in items])


CURVE = _sections(
    {"type": "straight", "length_m": 100.0},
    {"type": "transition", "length_m": 60.0},
    {"type": "curve", "length_m": 300.0, "curvature_1_per_m": 1 / 600, "cant_m": 0.1},
    {"type": "transition", "length_m": 60.0, "shape": "bloss"},
    {"type": "straight", "length_m": 100.0},
)


def test_circle_is_exact():
    a = _sections({"type": "curve", "length_m": 600.0, "curvature_1_per_m": 1 / 300, "cant_m": 0})
    s = np.linspace(0.0, 600.0, 61)
    x, y = a.position(s)
    # a circle of radius R starting at the origin along x, turning left
    np.testing.assert_allclose(x, 300 * np.sin(s / 300), atol=1e-9)  # rounding of 300 m values
    np.testing.assert_allclose(y, 300 * (1 - np.cos(s / 300)), atol=1e-9)
    # R = 300 m over 600 m turns the track by 2 rad = 114.6 degrees
    assert math.degrees(float(a.heading(600.0))) == pytest.approx(114.59, abs=0.01)


def test_clothoid_against_fresnel_integrals():
    # clothoid with A^2 = R L: x = A sqrt(pi) C(l / (A sqrt(pi))), y = A sqrt(pi) S(...)
    a_param = math.sqrt(600.0 * 60.0)
    u = np.linspace(0.0, 60.0, 31)
    s_f, c_f = fresnel(u / (a_param * math.sqrt(math.pi)))
    x, y = CURVE.position(100.0 + u)
    np.testing.assert_allclose(x - 100.0, a_param * math.sqrt(math.pi) * c_f, atol=1e-9)
    np.testing.assert_allclose(y, a_param * math.sqrt(math.pi) * s_f, atol=1e-9)
    np.testing.assert_allclose(CURVE.curvature(100.0 + u), u / (600.0 * 60.0), atol=1e-15)
    np.testing.assert_allclose(CURVE.cant(100.0 + u), 0.1 * u / 60.0, atol=1e-15)


def test_position_and_heading_are_continuous_at_every_joint():
    for joint in (100.0, 160.0, 460.0, 520.0):
        eps = 1e-7
        xa, ya = CURVE.position(joint - eps)
        xb, yb = CURVE.position(joint + eps)
        assert math.hypot(xb - xa, yb - ya) == pytest.approx(2 * eps, abs=1e-9)
        assert abs(CURVE.heading(joint + eps) - CURVE.heading(joint - eps)) < 1e-9
        assert abs(CURVE.curvature(joint + eps) - CURVE.curvature(joint - eps)) < 1e-9
        assert abs(CURVE.cant(joint + eps) - CURVE.cant(joint - eps)) < 1e-8


def test_heading_is_the_integral_of_curvature_and_position_of_heading():
    s = np.linspace(-20.0, 700.0, 2001)
    psi = CURVE.heading(s)
    k = CURVE.curvature(s)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(s))])
    np.testing.assert_allclose(psi, integral, atol=1e-6)  # trapezoidal rule, h = 0.36 m
    # total heading change: two transitions of L/(2R) and the curve of L/R
    assert float(CURVE.heading(700.0)) == pytest.approx(60 / 600 + 300 / 600, rel=1e-12)
    x, y = CURVE.position(s)
    h = 1e-4
    xp, yp = CURVE.position(s + h)
    xm, ym = CURVE.position(s - h)
    np.testing.assert_allclose((xp - xm) / (2 * h), np.cos(psi), atol=1e-7)
    np.testing.assert_allclose((yp - ym) / (2 * h), np.sin(psi), atol=1e-7)


def test_s_curve_turns_back_and_table_matches():
    a = _sections(
        {"type": "straight", "length_m": 50.0},
        {"type": "transition", "length_m": 40.0},
        {"type": "curve", "length_m": 100.0, "curvature_1_per_m": 1 / 400, "cant_m": 0.08},
        {"type": "transition", "length_m": 80.0},
        {"type": "curve", "length_m": 100.0, "curvature_1_per_m": -1 / 400, "cant_m": -0.08},
        {"type": "transition", "length_m": 40.0},
        {"type": "straight", "length_m": 50.0},
    )
    assert float(a.heading(500.0)) == pytest.approx(0.0, abs=1e-12)  # symmetric S
    assert float(a.cant(230.0)) == pytest.approx(0.0, abs=1e-15)  # ramp passes through zero
    start, step, tab = a.table(-10.0, 500.0, 0.5)
    s = start + step * np.arange(tab.shape[0])
    x, y = a.position(s)
    np.testing.assert_array_equal(tab[:, TAB_X], x)
    np.testing.assert_array_equal(tab[:, TAB_Y], y)
    np.testing.assert_array_equal(tab[:, TAB_PSI], a.heading(s))
    np.testing.assert_array_equal(tab[:, TAB_KAPPA], a.curvature(s))


def test_file_section_parsing_and_errors():
    text = """
geometry:
  type: sections
  sections:
    - {type: straight, length: 100 m}
    - {type: transition, length: 70 m}
    - {type: curve, length: 200 m, radius: 300 m, cant: 150 mm, direction: right}
"""
    data, lines = parse_yaml(text, "t.yaml")
    a = alignment_from_dict(data["geometry"], "t.yaml", lines)
    assert float(a.curvature(200.0)) == pytest.approx(-1 / 300)
    assert float(a.cant(200.0)) == pytest.approx(-0.15)
    assert float(a.cant_angle(200.0)) == pytest.approx(math.asin(0.1))  # left rail lower
    bad = text.replace("direction: right", "direction: rihgt")
    data, lines = parse_yaml(bad, "t.yaml")
    with pytest.raises(InputError, match=r"t.yaml:7: geometry.sections.2.direction.*'right'"):
        alignment_from_dict(data["geometry"], "t.yaml", lines)
    bad = text.replace("radius:", "radus:")
    data, lines = parse_yaml(bad, "t.yaml")
    with pytest.raises(InputError, match="unknown key.*radius"):
        alignment_from_dict(data["geometry"], "t.yaml", lines)


def test_measured_geometry(tmp_path):
    f = tmp_path / "g.csv"
    f.write_text("distance_m,curvature_1_per_m,cant_m\n0,0,0\n50,0.002,0.06\n150,0.002,0.06\n")
    a = alignment_from_dict({"type": "measured", "file": str(f)}, "t.yaml")
    assert float(a.curvature(25.0)) == pytest.approx(0.001)
    assert float(a.cant(100.0)) == pytest.approx(0.06)
    f.write_text("0,0,0\n50,x,0\n")
    with pytest.raises(InputError, match="g.csv:2"):
        alignment_from_dict({"type": "measured", "file": str(f)}, "t.yaml")
