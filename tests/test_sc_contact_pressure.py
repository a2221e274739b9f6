"""Peak pressure of the quasi-static S&C contact (issue 29) against CONTACT's PMAX.

Reference: CONTACT (E.A.H. Vollebregt, eve70a/CONTACT, Apache-2.0) output files
tests/data/switches_crossings/examples_s+c/*.ref_out (PMAX per patch, N/mm^2), on CONTACT's own
grid for these cases (DX 0.2 mm along the track, DS 0.05 mm laterally). The patches lie on
rounded rail corners (radius ~ 5 mm) given by points 0.2-0.5 mm apart, so the peak depends on
the curve drawn between the points:

- **no kinks between the resampled points.** A variable profile is resampled every 0.2 mm along
  each slice; straight lines between these points put a kink (a wedge, slope change ~ 0.03 rad
  on a 5 mm corner) every 0.2 mm, and a wedge gives the half-space pressure a logarithmic peak
  on grids finer than the points (`cross_brute` 3.82 GPa at 0.05 mm against 3.03 GPa with the
  points 10 times closer). The contact's fine grid reads the curves as monotone cubics between
  the points (``heights_on_grid(smooth=True)``): the peak then within 3 % of the one on points
  10 times closer (measured +1.6 %; the rest is PCHIP's own slopes between the points).
- **the curve through a slice's points.** railexu's default is a monotone cubic (PCHIP) in arc
  length; CONTACT draws an interpolating spline. On the nose's rounded corner in `cross+wing`
  (points 0.5 mm apart) and `cw_interrupt` case 2 the two put their curvature differently
  between the points, and the peak follows it: with ``curve="spline"`` railexu's peak is
  CONTACT's PMAX within 3 % (measured +0.9 % and -0.5 %; 3 %: the grids' offset against the
  corner and the solver's pressure at element centres, as CONTACT's), with PCHIP 31 % and
  12 % above it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from contact_ref_out import read_ref_out

from railexu.contact import variable_rail
from railexu.contact.variable_rail import ContactSettings, WheelSection, patches_at
from railexu.profiles.core import ProfileError
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.slcs import _read_profile_points

DATA = Path(__file__).parent / "data" / "switches_crossings"
#: CONTACT's grid for the single-patch cases: DX 0.2 mm, DS 0.05 mm.
CONTACT_GRID = ContactSettings(dx_m=2e-4, dy_m=5e-5)


@pytest.fixture(scope="module")
def wheel() -> WheelSection:
    """The Manchester S1002 wheel placed as in the cases, r0 = 460 mm."""
    pts = _read_profile_points(DATA / "profiles" / "x", 0, "MBench_S1002_v3.prw", 1.0)[::-1]
    return WheelSection(np.ascontiguousarray(pts), 0.46, 0.0)


def _pmax_ref_pa(case: str) -> list[float]:
    """CONTACT's PMAX [Pa] per patch of each case (the line under ``FN/G ... PMAX``)."""
    lines = (DATA / "examples_s+c" / f"{case}.ref_out").read_text(errors="replace").splitlines()
    return [float(lines[i + 1].split()[4]) * 1e6 for i, ln in enumerate(lines) if "PMAX" in ln]


def _peak_pa(monkeypatch, rail, wheel, ref) -> tuple[float, object]:
    """The largest element pressure [Pa] of the single patch at CONTACT's wheel position, and
    the patch."""
    seen = []
    solve = variable_rail.solve_normal

    def spy(*args, **kwargs):
        p = solve(*args, **kwargs)
        seen.append(float(p.max()))
        return p

    monkeypatch.setattr(variable_rail, "solve_normal", spy)
    (patch,) = patches_at(rail, wheel, ref["s_m"], ref["y_m"], ref["z_m"], CONTACT_GRID)
    # at equal force (4 %: the spline's curve on cw_interrupt carries +3.1 %; the peak of a
    # patch of fixed shape grows as the force's cube root, so 4 % is 1.3 % of the peak)
    assert patch.normal_force_n == pytest.approx(ref["patches"][0]["fn_n"], rel=0.04)
    return max(seen), patch


def test_no_kink_peaks_between_resampled_points(monkeypatch, wheel):
    """`cross_brute` (the nose's 5 mm corner): the peak on the default 0.2 mm resampling equals
    the peak on a 0.02 mm resampling of the same curves within 3 % (straight lines between the
    points gave 3.82 against 3.03 GPa, +26 %)."""
    ref = read_ref_out(DATA / "examples_s+c" / "cross_brute.ref_out")[0]
    slices = read_slcs(DATA / "profiles" / "cross_nose.slcs")
    coarse, _ = _peak_pa(monkeypatch, VariableProfile(slices), wheel, ref)
    fine, _ = _peak_pa(monkeypatch, VariableProfile(slices, spacing_m=2e-5), wheel, ref)
    assert coarse == pytest.approx(fine, rel=0.03)


@pytest.mark.parametrize(("case", "slcs", "index"), [
    ("cross+wing", "cross+wing", 0),
    ("cw_interrupt", "cross+wing_extd", 1),
])  # fmt: skip
def test_peak_pressure_with_contacts_spline(monkeypatch, wheel, case, slcs, index):
    """With CONTACT's spline through the slices' points the peak is CONTACT's PMAX within 3 %,
    and the largest undeformed overlap CONTACT's APPROACH within 0.2 um (the same surfaces:
    measured 0.00 and +0.03 um; the grids' offset moves the sampled maximum by up to half an
    element: 200 / m * (25 um)^2 / 2 = 0.06 um laterally on the 5 mm corner, 0.01 um along the
    wheel; 0.2 um is 3 times that, 0.6 % of the 31-39 um approach)."""
    ref = read_ref_out(DATA / "examples_s+c" / f"{case}.ref_out")[index]
    rail = VariableProfile(read_slcs(DATA / "profiles" / f"{slcs}.slcs"), curve="spline")
    pmax = _pmax_ref_pa(case)[index]
    peak, patch = _peak_pa(monkeypatch, rail, wheel, ref)
    assert peak == pytest.approx(pmax, rel=0.03)
    assert patch.max_overlap_m == pytest.approx(ref["patches"][0]["approach_m"], abs=2e-7)


def test_unknown_slice_curve_is_refused():
    """A slice curve that is not offered is refused by name."""
    slices = read_slcs(DATA / "profiles" / "cross_nose.slcs")
    with pytest.raises(ProfileError, match="'akima': not one of pchip, spline"):
        VariableProfile(slices, curve="akima")
