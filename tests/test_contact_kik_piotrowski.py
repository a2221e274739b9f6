"""Kik-Piotrowski non-Hertzian normal contact against CONTACT (exact half-space theory).

References: CONTACT's ``conformal`` case 1 (tests/data/contact_validation/) and the Manchester
benchmark A-2.2 (tests/data/contact_mbench_reference.csv: normal force, pressure maximum, patch
length along x and width along the surface from CONTACT's element map, +-0.2 mm). The model is
an approximation (Piotrowski and Kik 2008 report a few % on the normal force); the tolerances
below are its measured accuracy with margin, not a claim of exactness.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ellipe, ellipk

from railexu.contact.evaluation import ContactParameters, WheelsetContactModel
from railexu.contact.hertz import hertz_contact
from railexu.contact.kik_piotrowski import kik_piotrowski_patch, wheel_point_patch
from railexu.contact.placement import symmetric_wheelset

DATA = Path(__file__).parent / "data"
G, NU = 82.0e9, 0.28
E_STAR = G / (1.0 - NU)


def test_inner_integral_closed_form():
    """int sqrt(xf^2 - x^2)/sqrt(x^2 + eta^2) dx = 2 sqrt(xf^2 + eta^2)(K(m) - E(m)),
    m = xf^2/(xf^2 + eta^2): against adaptive quadrature to 1e-9."""
    for xf, eta in ((1.0, 0.3), (2.0, 0.01), (0.5, 3.0)):
        numeric = quad(
            lambda x, xf=xf, eta=eta: np.sqrt(xf * xf - x * x) / np.hypot(x, eta), -xf, xf,
            limit=200,
        )  # fmt: skip
        m = xf * xf / (xf * xf + eta * eta)
        closed = 2.0 * np.sqrt(xf * xf + eta * eta) * (ellipk(m) - ellipe(m))
        assert closed == pytest.approx(numeric[0], rel=1e-9)


def test_conformal_case_quadratic_gap():
    """CONTACT ``conformal`` case 1: gap A x^2 + B y^2, approach 0.09089 mm -> 100 kN, p_max
    912.8 MPa (exact for this quadratic gap is Hertz: a = 7.84, b = 6.67 mm). Kik-Piotrowski,
    measured: N +4.8 %, p_max -4.8 %, a +2.8 %, b +7.0 %; tolerances 6 %, 6 %, 4 %, 8 %."""
    with (DATA / "contact_validation" / "conformal_case1_reference.csv").open() as fh:
        row = next(csv.DictReader(fh))
    a_coef, b_coef = float(row["A_per_mm"]) * 1e3, float(row["B_per_mm"]) * 1e3
    approach = float(row["approach_mm"]) * 1e-3
    y = np.linspace(-0.02, 0.02, 4001)
    kp = kik_piotrowski_patch(y, b_coef * y * y, approach, a_coef, E_STAR)
    hz = hertz_contact(a_coef, b_coef, float(row["FN_N"]), E_STAR)
    assert kp.normal_force_N == pytest.approx(float(row["FN_N"]), rel=0.06)
    assert kp.p_max_Pa == pytest.approx(float(row["pmax_MPa"]) * 1e6, rel=0.06)
    assert kp.half_length_m == pytest.approx(hz.a_m, rel=0.04)
    half_width = 0.5 * (kp.lateral_extent_m[1] - kp.lateral_extent_m[0])
    assert half_width == pytest.approx(hz.b_m, rel=0.08)


def _mbench_rows():
    with (DATA / "contact_mbench_reference.csv").open() as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    return [r for r in rows if "two" not in r.get("note", "").lower()]


@pytest.fixture(scope="module")
def mbench_model():
    geometry = symmetric_wheelset(
        "MBench_S1002", "MBench_UIC60", nominal_radius_m=0.46, inclination="1:40"
    )
    return WheelsetContactModel(geometry, ContactParameters(), 2.0)


def _patch(model, row):
    pose = dict(
        lateral_m=-float(row["y_ws_mm"]) / 1e3,
        vertical_m=(460.0 - float(row["z_ws_mm"])) / 1e3,
        roll_rad=float(row["roll_ws_inp_rad"]),
        yaw_rad=-float(row["yaw_ws_rad"]),
    )
    res = model.evaluate(**pose)
    loaded = [q for q in res.wheel(row["side"]) if q.loaded]
    p = max(loaded, key=lambda q: q.normal_force_N)
    return len(loaded), wheel_point_patch(
        model, row["side"], *pose.values(), p.wheel_lateral_m, p.contact_angle_rad
    )


def test_two_point_tread_contact_is_one_wide_patch(mbench_model):
    """Centred wheelset (case 1): new S1002 on 1:40 touches at two tread points 11 mm apart and
    CONTACT finds one patch 15.8 mm wide with 10.0 kN, p_max 338 MPa; Hertz on the deeper point
    gives a 10 mm ellipse with 8.8 kN. Kik-Piotrowski, measured: 15.5 mm, 9.66 kN, 312 MPa;
    tolerances: width 0.6 mm (CONTACT's map +-0.2 mm plus the model), force 5 %, p_max 10 %."""
    row = next(r for r in _mbench_rows() if r["side"] == "left" and r["case"] == "1")
    _, kp = _patch(mbench_model, row)
    width = kp.lateral_extent_m[1] - kp.lateral_extent_m[0]
    assert width == pytest.approx(float(row["s_extent_mm"]) * 1e-3, abs=6e-4)
    assert kp.normal_force_N == pytest.approx(float(row["fn_N"]), rel=0.05)
    assert kp.p_max_Pa == pytest.approx(float(row["pmax_N_per_mm2"]) * 1e6, rel=0.10)


@pytest.mark.parametrize("row", _mbench_rows(), ids=lambda r: f"{r['side']}-{r['case']}")
def test_mbench_patches(mbench_model, row):
    """Every single-patch case at CONTACT's poses.

    Normal force within 7 % (measured -3 .. +5.5 %: the virtual penetration's known bias).
    Patch length along x within 15 % (tread 0 .. 13 %, flange -10 %: the flange's longitudinal
    curvature is taken at the point only). Pressure maximum: tread within 12 % (measured -4 ..
    -10 %); flange root and flange (CONTACT's contact angle > 0.25 rad, patches 0.8-1.4 mm wide)
    within 30 % (measured -14 .. -26 %), the model's known weakness there, where its virtual
    penetration widens the patch (1.1 mm against 0.8). The 14 mm wide patch of the right wheel
    at 0.5 mm, where two tread lobes merge: force 13 %, p_max 18 % (measured -11.8 %, -14.8 %).
    Positions where railexu's geometry has two points on the wheel are skipped.
    """
    n_points, kp = _patch(mbench_model, row)
    if n_points != 1:
        pytest.skip("two points in railexu's geometry: CONTACT's one patch is not comparable")
    wide = float(row["s_extent_mm"]) > 10.0  # two tread lobes merging (right wheel, 0.5 mm)
    assert kp.normal_force_N == pytest.approx(float(row["fn_N"]), rel=0.13 if wide else 0.07)
    assert 2.0 * kp.half_length_m == pytest.approx(float(row["x_extent_mm"]) * 1e-3, rel=0.15)
    flange = abs(float(row["deltcp_tr_rad"])) > 0.25
    assert kp.p_max_Pa == pytest.approx(
        float(row["pmax_N_per_mm2"]) * 1e6, rel=0.30 if flange else (0.18 if wide else 0.12)
    )


def test_conformal_creep_forces_on_the_patch():
    """FASTSIM on the Kik-Piotrowski patch (strips, the patch's own pressure as bound), CONTACT
    ``conformal`` case 1: within 10 % of mu Q per component (the issue's acceptance; measured
    Fx -0.6 %, Fy -3.2 %). Limits: full slip |F| = mu N within 0.5 % (midpoint cells), linear
    Fx = Kalker's G a b c11 xi of the equivalent ellipse within 0.1 %."""
    from railexu.contact.kalker import kalker_coefficients
    from railexu.contact.kik_piotrowski import patch_creep_forces

    with (DATA / "contact_validation" / "conformal_case1_reference.csv").open() as fh:
        row = next(csv.DictReader(fh))
    y = np.linspace(-0.02, 0.02, 4001)
    kp = kik_piotrowski_patch(
        y, float(row["B_per_mm"]) * 1e3 * y * y, float(row["approach_mm"]) * 1e-3,
        float(row["A_per_mm"]) * 1e3, E_STAR,
    )  # fmt: skip
    mu_q = float(row["mu"]) * float(row["FN_N"])
    fx, fy, _ = patch_creep_forces(
        kp, float(row["xi"]), float(row["eta"]), float(row["phi_per_mm"]) * 1e3, 0.3, G, NU
    )
    assert abs(fx - float(row["FX_N"])) < 0.10 * mu_q
    assert abs(fy - float(row["FY_N"])) < 0.10 * mu_q
    full = patch_creep_forces(kp, 0.05, 0.0, 0.0, 0.3, G, NU)
    assert np.hypot(full[0], full[1]) == pytest.approx(0.3 * kp.normal_force_N, rel=5e-3)
    a = kp.half_length_m
    b = 0.5 * (kp.lateral_extent_m[1] - kp.lateral_extent_m[0])
    c11 = kalker_coefficients(a / b, NU)[0]
    lin = patch_creep_forces(kp, 1e-6, 0.0, 0.0, 0.3, G, NU)[0]
    assert lin == pytest.approx(-G * a * b * c11 * 1e-6, rel=1e-3)


@pytest.mark.parametrize("row", _mbench_rows(), ids=lambda r: f"{r['side']}-{r['case']}")
def test_mbench_creep_forces_on_the_patch(mbench_model, row):
    """Creep forces on the Kik-Piotrowski patch at CONTACT's poses and pitch rate, creepages from
    railexu's contact point: within 8 % of mu N per component (measured up to 6.5 %; Hertz with
    the default law: up to 8 %), the merged 14 mm patch of the right wheel at 0.5 mm within 30 %
    (measured 18 % and 28 %, Hertz 34 %)."""
    from railexu.contact.kik_piotrowski import patch_creep_forces

    phi, psi = float(row["roll_ws_inp_rad"]), -float(row["yaw_ws_rad"])
    axle = np.array([-np.sin(psi), np.cos(phi) * np.cos(psi), np.sin(phi) * np.cos(psi)])
    pose = dict(
        lateral_m=-float(row["y_ws_mm"]) / 1e3,
        vertical_m=(460.0 - float(row["z_ws_mm"])) / 1e3,
        roll_rad=phi,
        yaw_rad=psi,
    )
    omega = tuple(-float(row["vpitch_rad_per_s"]) * axle)
    res = mbench_model.evaluate(**pose, angular_velocity_rad_per_s=omega)
    loaded = [q for q in res.wheel(row["side"]) if q.loaded]
    if len(loaded) != 1:
        pytest.skip("two points in railexu's geometry: CONTACT's one patch is not comparable")
    p = loaded[0]
    kp = wheel_point_patch(
        mbench_model, row["side"], *pose.values(), p.wheel_lateral_m, p.contact_angle_rad
    )
    fx, fy, _ = patch_creep_forces(kp, p.creep_long, p.creep_lat, p.spin_per_m, 0.3, G, NU)
    mu_n = 0.3 * float(row["fn_N"])
    tol = 0.30 if float(row["s_extent_mm"]) > 10.0 else 0.08
    # CONTACT's forces act on the rail, in its frame: on the wheel Fx = -fx, Fy = +fs
    assert abs(fx + float(row["fx_N"])) < tol * mu_n
    assert abs(fy - float(row["fs_N"])) < tol * mu_n
