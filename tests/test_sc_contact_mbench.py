"""CONTACT's ``mbench_brute`` and ``mbench_locus`` on the whole UK crossing (issue 29): the S1002
wheel pressed with 10 kN at s = 239 mm and moved laterally from 0.81 to 1.15 mm, the load
passing from the wing rail's raised field side (y = +38.6 mm) to the nose's gauge corner
(y = -28.2 mm, 18 degrees).

Reference: CONTACT (E.A.H. Vollebregt, eve70a/CONTACT, Apache-2.0) output files
``tests/data/switches_crossings/examples_s+c/mbench_{brute,locus}.ref_out`` (the two contact
searches of CONTACT on the same geometry; they agree within 0.03 mm and 0.5 %), read number by
number. CONTACT reads ``uk_crossing.slcs`` (no feature points, which railexu refuses: its
arc-length fractions would morph the wing rail into the nose between slices 47 and 48);
railexu reads the same slices 4-145 with the feature points of
``tracks/uk_crossing/uk_crossing_full.yaml`` (the shipped crossing). The same grid (0.2 x 0.2 mm)
and material (G = 82 GPa, nu = 0.28). Tolerances and their physical reasons:

- **rail height between slices, 10 um.** Both contacts lie between slices 70 and 71 (s = 228.71
  and 248.36 mm, 19.65 mm apart), where the slices do not say what the surface is. At the nose's
  contact (s = 243.5 mm, y = -28.28 mm) reasonable interpolations differ by 9 um: CONTACT's
  surface 3.3686 mm, railexu's 3.3775 mm (arc length between feature points, linear in s),
  the slices' heights at that y linear in s 3.3747 mm and a cubic spline in s 3.3708 mm (the
  nose falls 206 um between the two slices and its slope along s changes from 12.0 to
  10.5 um/mm). At the wing rail's contact the two surfaces agree within 1 um.
- **wheel height at 10 kN**: the difference of the two surfaces at CONTACT's contact point,
  within 2 um (the rest: the two grids' patches and CONTACT's friction, which carries ~ 0.4 %
  of the load vertically on the nose's flank; 2 um is ~ 4 % of the 33 um approach).
- **contact position 0.5 mm laterally** (as ``test_sc_contact.py``: the pressure centre against
  CONTACT's reference point, both inside the patch), **1 mm along the track on the nose**: its
  patch lies on the rising nose's gauge corner, long and thin (as ``two_patches``' 0.56 mm).
- **contact angle 0.04 rad**: both patches lie on rounded corners whose slope changes by
  0.07 rad (the wing rail's field corner) and 0.15 rad (the nose's gauge corner) per mm
  laterally; railexu takes the slope at the deepest grid cell (0.2 mm cells), CONTACT at its
  reference point; 0.04 rad is 0.3-0.6 mm of position on these corners.
- **normal force 1.5 %**, compared with CONTACT's frictionless equivalent ``FN + FS tan(delta)``
  (the normal force that carries the same vertical force without friction: CONTACT solves
  with friction, full slip, and its lateral tangential force FS carries 380 N of the 10 kN
  on the nose's 18 degree flank; railexu's normal problem is frictionless). 1.5 %: the same
  grid and a surface 1 um apart leave the plane's tilt (railexu) against CONTACT's curved
  reference surface.
- **the transfer's 50 % point within 0.05 mm** of lateral displacement: the two rails' touch
  heights part at ``tan|delta_nose| - tan|delta_wing|`` ~ 0.23 per unit of lateral
  displacement, so the 9 um between the surfaces at the nose moves it by 0.04 mm; **its width**
  (nose share 10 % to 90 %) within 15 %: set by the elastic approach at 10 kN (~ 33 um) over
  that rate, the same in both solutions.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from contact_ref_out import read_ref_out

from railexu.contact.variable_rail import ContactSettings, WheelSection, press_wheel
from railexu.profiles.variable import VariableProfile, read_yaml_slices
from railexu.profiles.variable.slcs import _read_profile_points

DATA = Path(__file__).parent / "data" / "switches_crossings"
CROSSING = Path(__file__).resolve().parents[1] / "tracks" / "uk_crossing" / "uk_crossing_full.yaml"
CASES = ("mbench_brute", "mbench_locus")
#: The reference's lateral positions computed here [mm]: the ends and every 0.02 mm across the
#: transfer (35 positions 0.01 mm apart in the reference; 1.2 s each).
Y_MM = (0.81, 0.83, *np.round(np.arange(0.85, 1.151, 0.02), 2).tolist())


@pytest.fixture(scope="module")
def ours() -> dict[float, tuple[float, list]]:
    """railexu's quasi-static contact at 10 kN at the positions ``Y_MM``: ``(z_ws, patches)``."""
    pts = _read_profile_points(DATA / "profiles" / "x", 0, "MBench_S1002_v3.prw", 1.0)[::-1]
    wheel = WheelSection(np.ascontiguousarray(pts), 0.46, 0.0)
    rail = VariableProfile(read_yaml_slices(CROSSING))
    settings = ContactSettings(dx_m=2e-4, dy_m=2e-4)
    out = {}
    for y in Y_MM:
        z, patches = press_wheel(rail, wheel, 0.239, y * 1e-3, 1.0e4, settings)
        out[y] = (z, patches, rail)
    return out


def _refs(case: str) -> dict[float, dict]:
    cases = read_ref_out(DATA / "examples_s+c" / f"{case}.ref_out")
    assert len(cases) == 35
    return {round(c["y_m"] * 1e3, 2): c for c in cases}


def _vertical(p: dict) -> float:
    """CONTACT's vertical force of a patch [N]: its normal and lateral tangential force."""
    return p["fn_n"] * math.cos(p["delta_rad"]) + p["fs_n"] * math.sin(p["delta_rad"])


def _nose_share(patches, vertical) -> float:
    nose = sum(vertical(p) for p in patches if _is_nose(p))
    return nose / sum(vertical(p) for p in patches)


def _is_nose(p) -> bool:
    y = p.y_m if hasattr(p, "y_m") else p["y_m"]
    return y < 0.0  # the nose lies on the gauge side of the flangeway (y < 0 here)


def _half_and_width(y, share) -> tuple[float, float]:
    """The lateral position [mm] of the 50 % share and the width from 10 % to 90 % [mm]."""
    y, share = np.asarray(y), np.asarray(share)
    assert np.all(np.diff(share) >= -1e-3)
    at = [float(np.interp(v, share, y)) for v in (0.1, 0.5, 0.9)]
    return at[1], at[2] - at[0]


@pytest.mark.parametrize("case", CASES)
def test_one_patch_on_the_wing_rail_and_on_the_nose(ours, case):
    """Where CONTACT finds one patch (wing rail at 0.81-0.83 mm, nose at 1.13-1.15 mm): the
    wheel height differs by the surfaces' difference at CONTACT's contact point; position,
    angle and normal force as CONTACT's."""
    refs = _refs(case)
    for y in (0.81, 0.83, 1.13, 1.15):
        z, patches, rail = ours[y]
        (theirs,) = refs[y]["patches"]
        (patch,) = [p for p in patches if p.vertical_force_n > 50.0]
        assert _is_nose(patch) == _is_nose(theirs) == (y > 1.0)
        s_cp = refs[y]["s_m"] + theirs["x_m"]
        z_rail = float(rail.heights_on_grid([s_cp], [theirs["y_m"]])[0, 0])
        assert z_rail - theirs["z_m"] == pytest.approx(0.0, abs=1.0e-5)  # between slices
        assert z - refs[y]["z_m"] == pytest.approx(z_rail - theirs["z_m"], abs=2.0e-6)
        assert patch.y_m == pytest.approx(theirs["y_m"], abs=5e-4)
        assert patch.x_m == pytest.approx(theirs["x_m"], abs=1e-3 if y > 1.0 else 5e-4)
        assert patch.angle_rad == pytest.approx(theirs["delta_rad"], abs=0.04)
        frictionless = theirs["fn_n"] + theirs["fs_n"] * math.tan(theirs["delta_rad"])
        assert patch.normal_force_n == pytest.approx(frictionless, rel=0.015)


@pytest.mark.parametrize("case", CASES)
def test_transfer_from_wing_rail_to_nose(ours, case):
    """Across the transfer: two patches (nose's gauge corner, wing rail's field side) where
    CONTACT has two, at CONTACT's lateral positions; the nose's share of the vertical load rises
    monotonically, its 50 % point within 0.05 mm of CONTACT's and its 10-90 % width within 15 %;
    the vertical forces sum to the load (which the pressing imposes)."""
    refs = _refs(case)
    ys = sorted(refs)
    theirs = [_nose_share(refs[y]["patches"], _vertical) for y in ys]
    mine = [_nose_share(ours[y][1], lambda p: p.vertical_force_n) for y in Y_MM]
    half_ref, width_ref = _half_and_width(ys, theirs)
    half, width = _half_and_width(Y_MM, mine)
    assert half == pytest.approx(half_ref, abs=0.05)
    assert width == pytest.approx(width_ref, rel=0.15)
    for y in Y_MM:
        z, patches, _ = ours[y]
        assert sum(p.vertical_force_n for p in patches) == pytest.approx(1.0e4, rel=1e-3)
        both = [p for p in patches if p.vertical_force_n > 500.0]
        ref = [p for p in refs[y]["patches"] if _vertical(p) > 500.0]
        if len(both) == len(ref) == 2:
            for a, b in zip(sorted(both, key=lambda p: p.y_m), sorted(ref, key=lambda p: p["y_m"]),
                            strict=True):  # fmt: skip
                assert a.y_m == pytest.approx(b["y_m"], abs=5e-4)
                assert a.angle_rad == pytest.approx(b["delta_rad"], abs=0.04)
