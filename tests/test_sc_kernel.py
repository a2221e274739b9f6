"""The compiled contact kernel on a variable rail's effective section (issue 29): several rails
of one side in one kernel table, checked against CONTACT's S&C cases and against the plain rail.

Reference numbers: CONTACT (E.A.H. Vollebregt, eve70a/CONTACT, Apache-2.0) output files in
tests/data/switches_crossings/examples_s+c, read number by number.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from contact_ref_out import read_ref_out
from scipy.optimize import brentq

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel, rail_arrays
from railexu.contact.placement import symmetric_wheelset
from railexu.contact.variable_tables import section_rail_arrays
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.slcs import _read_profile_points
from railexu.profiles.variable.slices import ProfileSlices

DATA = Path(__file__).parent / "data" / "switches_crossings"
PACKAGED = Path(__file__).parents[1] / "src" / "railexu" / "data" / "profiles"
#: CONTACT's placement in the cases: rail profile origin 750 mm from the track centre (RAILY0),
#: wheel profile origin at FBDIST/2 - FBPOS = 680 + 70 mm: over the rail's at y_ws = 0.
RAIL_ORIGIN = (0.75, 0.0)


@pytest.fixture(scope="module")
def geometry():
    """Manchester S1002 wheel (r0 = 460 mm, flange backs 1360 mm apart) on the Manchester UIC60
    (its file is canted 1:40 already: no rotation)."""
    return symmetric_wheelset(
        "MBench_S1002",
        "MBench_UIC60",
        nominal_radius_m=0.46,
        inclination="1:40",
        gauge_m=1.435,
        flange_back_distance_m=1.36,
    )


def _points(model, lateral, height):
    r = model.evaluate(lateral, height)
    return [r.raw[0, k] for k in range(K.MAX_POINTS) if r.raw[0, k, K.PF_ACTIVE] > 0]


def _vertical(model, lateral, height):
    return sum(p[K.PF_FTZ] for p in _points(model, lateral, height))


def test_uniform_slices_give_the_plain_rail_table(geometry):
    """Slices that are all the track's rail (the Manchester UIC60 file) give the plain rail's
    kernel table (heights within 0.1 um in the head: two smooth interpolations through the same
    file points, the plain rail's parametric cubic and the slices' monotone cubic resampled at
    0.2 mm; 0.1 um is 0.3 % of the approach at 10 kN) and the same wheel forces within 0.1 % at
    0-6 mm lateral displacement."""
    pts = _read_profile_points(PACKAGED / "x", 0, "MBench_UIC60_v3.prr", 1.0)
    pts = pts[::-1] if pts[0, 0] > pts[-1, 0] else pts
    keep = np.concatenate(([True], np.diff(pts[:, 0]) > 0))
    pts = pts[keep]
    uniform = VariableProfile(ProfileSlices("uniform", np.array([0.0, 100.0]), (pts, pts), None,
                                            (None, None), ("UIC60", "UIC60")))  # fmt: skip
    tab0, info0 = rail_arrays(geometry.left)
    tab1, info1 = section_rail_arrays(uniform, 37.0, geometry.left, x_max_m=0.06)
    g0 = info0[0] + info0[1] * np.arange(int(info0[2]))
    g1 = info1[0] + info1[1] * np.arange(int(info1[2]))
    head = np.linspace(max(g0[0], g1[0]) + 0.01, min(g0[-1], g1[-1]) - 0.005, 500)
    np.testing.assert_allclose(np.interp(head, g1, tab1[:, 0]), np.interp(head, g0, tab0[:, 0]),
                               atol=1e-7)  # fmt: skip
    plain = WheelsetContactModel(geometry)
    sliced = WheelsetContactModel(geometry)
    sliced.rtab_l, sliced.rinfo_l = tab1, info1
    for lateral in (0.0, 0.003, 0.006):
        height = brentq(lambda h: _vertical(plain, lateral, h) - 1e4, 0.45, 0.47, xtol=1e-11)  # noqa: B023
        assert _vertical(sliced, lateral, height) == pytest.approx(1e4, rel=1e-3)


def _model(geometry, slcs, scale, s_m):
    rail = VariableProfile(read_slcs(DATA / "profiles" / slcs, scale_to_mm=scale))
    tab, info = section_rail_arrays(rail, s_m, geometry.left, rail_origin_m=RAIL_ORIGIN,
                                    x_max_m=0.06)  # fmt: skip
    model = WheelsetContactModel(geometry)
    model.rtab_l, model.rinfo_l = tab, info
    return model


@pytest.mark.parametrize(
    ("case", "slcs"), [("cross_brute", "cross_nose.slcs"), ("wing_brute", "wing_rail.slcs")]
)
def test_kernel_on_effective_section_one_rail(geometry, case, slcs):
    """The nose rising 1:10 (touched 46 mm ahead of the axle) and the wing rail: the kernel's
    Hertzian normal force at CONTACT's wheel position within 3 % of CONTACT's non-Hertzian one
    (these patches are nearly elliptical), the lateral position within 0.5 mm."""
    (ref,) = read_ref_out(DATA / "examples_s+c" / f"{case}.ref_out")
    model = _model(geometry, slcs, 1.0, ref["s_m"])
    pts = [p for p in _points(model, ref["y_m"], 0.46 - ref["z_m"]) if p[K.PF_N] > 0]
    assert len(pts) == 1
    assert pts[0][K.PF_N] == pytest.approx(ref["patches"][0]["fn_n"], rel=0.03)
    assert pts[0][K.PF_YRAIL] - RAIL_ORIGIN[0] == pytest.approx(ref["patches"][0]["y_m"], abs=5e-4)


def test_kernel_two_rails_at_once(geometry):
    """two_patches (UK crossing 56E1-R245-1:9.25, 10 kN): the kernel, pressed to 10 kN, touches
    the nose's flank and the wing rail at once; the wheel's height within 2 um of CONTACT's
    (the stiffness is ~ 1 kN/um), the positions within 0.5 mm and the load split within 10 % of
    the total (Hertz on the nose's 44 deg flank gives 15 % more than CONTACT's non-Hertzian
    patch there, 3 % less on the wing rail)."""
    (ref,) = read_ref_out(DATA / "examples_s+c" / "two_patches.ref_out")
    model = _model(geometry, "uk_interrupt_v2.slcs", 1000.0, ref["s_m"])
    y = ref["y_m"]
    height = brentq(lambda h: _vertical(model, y, h) - ref["fz_n"], 0.455, 0.465, xtol=1e-11)
    assert 0.46 - height == pytest.approx(ref["z_m"], abs=2e-6)
    rail = VariableProfile(read_slcs(DATA / "profiles" / "uk_interrupt_v2.slcs", scale_to_mm=1e3))
    (curve,) = rail.curves_at(ref["s_m"])
    y_low = curve[int(np.argmax(curve[:, 1])), 0]  # the flangeway's bottom (z down)
    force = np.zeros(2)
    moment = np.zeros(2)
    for p in _points(model, y, height):
        k = int(p[K.PF_YRAIL] - RAIL_ORIGIN[0] > y_low)  # 0 nose, 1 wing rail
        force[k] += p[K.PF_N]
        moment[k] += p[K.PF_N] * (p[K.PF_YRAIL] - RAIL_ORIGIN[0])
    theirs = sorted(ref["patches"], key=lambda p: p["y_m"])
    assert np.all(force > 0.1 * ref["fz_n"])  # both rails carry load at once
    for k in range(2):
        assert moment[k] / force[k] == pytest.approx(theirs[k]["y_m"], abs=5e-4)
    share = force[0] / force.sum()
    assert share == pytest.approx(theirs[0]["fn_n"] / sum(t["fn_n"] for t in theirs), abs=0.10)


def test_uk_crossing_sweep_along_the_nose_start(geometry):
    """mbench_intrup: the S1002 wheel at a prescribed position (y 0.78 mm, z -0.87 mm) moved
    from s = 110 to 130 mm along the UK crossing, across the slice where the nose begins
    (118.94 mm): at every 7th of CONTACT's 43 positions the kernel on the effective section and
    the quasi-static half-space solution give CONTACT's normal force on the wing rail within
    2.5 % and 1.5 % (Hertz against a nearly elliptical non-Hertzian patch; the half-space solution
    differs by its grid, and by 1.2 % at s = 130 mm where CONTACT's force rises 2.6 % over the last
    3 mm), at its lateral position within 0.5 mm, and no spurious load on the nose."""
    from railexu.contact.variable_rail import WheelSection, patches_at

    cases = read_ref_out(DATA / "examples_s+c" / "mbench_intrup.ref_out")
    assert len(cases) == 43
    rail = VariableProfile(read_slcs(DATA / "profiles" / "uk_interrupt_v2.slcs", scale_to_mm=1e3))
    pts = _read_profile_points(DATA / "profiles" / "x", 0, "MBench_S1002_v3.prw", 1.0)[::-1]
    wheel = WheelSection(np.ascontiguousarray(pts), 0.46, 0.0)
    model = WheelsetContactModel(geometry)
    for ref in cases[::7] + [cases[-1]]:
        (theirs,) = ref["patches"]
        model.rtab_l, model.rinfo_l = section_rail_arrays(
            rail, ref["s_m"], geometry.left, rail_origin_m=RAIL_ORIGIN, x_max_m=0.06
        )
        loaded = [p for p in _points(model, ref["y_m"], 0.46 - ref["z_m"]) if p[K.PF_N] > 50.0]
        assert len(loaded) == 1
        assert loaded[0][K.PF_N] == pytest.approx(theirs["fn_n"], rel=0.025)
        assert loaded[0][K.PF_YRAIL] - RAIL_ORIGIN[0] == pytest.approx(theirs["y_m"], abs=5e-4)
        (patch,) = patches_at(rail, wheel, ref["s_m"], ref["y_m"], ref["z_m"])
        assert patch.normal_force_n == pytest.approx(theirs["fn_n"], rel=0.015)
        assert patch.y_m == pytest.approx(theirs["y_m"], abs=5e-4)
