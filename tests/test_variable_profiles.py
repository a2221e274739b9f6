"""Variable rail profiles (issue 29): CONTACT's .slcs and railexu's YAML slices, interpolation
that keeps the features, refusals that name the file, the slice and why.

The reference numbers are the geometry the test bank's files state in their headers (a nose
rising 1:10, a wing rail moving sideways 1:10: CONTACT, eve70a/CONTACT, Apache-2.0, see
tests/data/switches_crossings/README.md), not earlier output of railexu.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.profiles.core import ProfileError
from railexu.profiles.variable import VariableProfile, read_slcs, read_yaml_slices

DATA = Path(__file__).parent / "data" / "switches_crossings" / "profiles"


def _top_z(curve: np.ndarray) -> float:
    return float(curve[:, 1].min())


def test_nose_rising_1_in_10_between_slices():
    """cross_nose.slcs: 'crossing nose rising at rate 1:10', top at z = -s/10. Between slices
    the interpolated top follows the same line: linear interpolation is exact for a linear
    change; tolerance 1 um (the files' 6 decimals in mm and the resampling at 0.2 mm of a
    rounded top, whose height error is (0.1 mm)^2 / (2 R), R >= 10 mm)."""
    vp = VariableProfile(read_slcs(DATA / "cross_nose.slcs"))
    for s in (-0.0937, -0.037, 0.0, 0.0123, 0.0951):
        (curve,) = vp.curves_at(s)
        assert _top_z(curve) == pytest.approx(-s / 10.0, abs=1.0e-6)


def test_wing_rail_moving_sideways_1_in_10():
    """wing_rail.slcs: 'wing rail shifting sideways at 1:10'. The gauge face (where the surface
    is 14 mm below its top) moves by s/10 laterally; tolerance 5 um (the face's slope makes a
    0.2 mm resampling error in z a few um in y)."""
    vp = VariableProfile(read_slcs(DATA / "wing_rail.slcs"))

    def face_y(s: float) -> float:
        (c,) = vp.curves_at(s)
        z_ref = _top_z(c) + 0.014
        top = int(np.argmin(c[:, 1]))
        left = c[: top + 1]  # gauge face: points before the top, z decreasing
        return float(np.interp(z_ref, left[::-1, 1], left[::-1, 0]))

    y0 = face_y(0.0)
    shift_per_m = (face_y(0.2) - y0) / 0.2
    assert abs(shift_per_m) == pytest.approx(0.1, abs=1.0e-3)
    for s in (0.0137, 0.0777, 0.151):
        assert face_y(s) - y0 == pytest.approx(shift_per_m * s, abs=5.0e-6)


def test_features_stay_edges_between_slices():
    """cross+wing.slcs: the feature points (nose start, wing rail edges) of the interpolated
    profile lie at the features' interpolated positions, so a real edge stays an edge instead
    of being smeared over the arc length; and every curve is a graph z(y)."""
    sl = read_slcs(DATA / "cross+wing.slcs")
    vp = VariableProfile(sl)
    s = 0.5 * (sl.positions_m[3] + sl.positions_m[4])
    feats = vp.features_at(s)
    fa = vp.features_at(sl.positions_m[3])
    fb = vp.features_at(sl.positions_m[4])
    assert feats.shape == fa.shape == fb.shape == (10, 2)
    np.testing.assert_allclose(feats, 0.5 * (fa + fb), atol=1e-12)
    for c in vp.curves_at(s):
        assert np.all(np.diff(c[:, 0]) > 0.0)


def test_uniform_slices_reproduce_the_profile():
    """A track given as identical slices is the same profile at every s (to rounding)."""
    sl = read_slcs(DATA / "cross_nose.slcs")
    from railexu.profiles.variable.slices import ProfileSlices

    same = ProfileSlices("uniform", np.array([0.0, 1.0, 2.5]), (sl.points_m[0],) * 3, None,
                         (None,) * 3, ("a",) * 3)  # fmt: skip
    vp = VariableProfile(same)
    y = np.linspace(sl.points_m[0][0, 0] + 1e-9, sl.points_m[0][-1, 0] - 1e-9, 301)
    z = vp.heights_on_grid(np.array([0.0, 0.3, 1.7, 2.5, 9.0]), y)
    z_ref = np.interp(y, sl.points_m[0][:, 0], sl.points_m[0][:, 1])
    assert np.array_equal(z, np.broadcast_to(z[0], z.shape))  # the same at every s, exactly
    # against the file's polyline: the smooth curve through its points (0.2 mm apart) departs
    # from the chords by at most ~(0.2 mm)^2 / (8 R), 1 um for R = 5 mm
    np.testing.assert_allclose(z[0], z_ref, atol=1.0e-6)


def test_interrupted_nose_begins_at_its_slice():
    """uk_interrupt_v2.slcs: the nose's parts are absent (-1) in slices 1-7: between slices 7
    and 8 the profile is the wing rail alone, from slice 8 on it reaches over the nose."""
    sl = read_slcs(DATA / "uk_interrupt_v2.slcs", scale_to_mm=1000.0)
    vp = VariableProfile(sl)
    s7, s8 = sl.positions_m[6], sl.positions_m[7]
    (before,) = vp.curves_at(0.5 * (s7 + s8))
    assert before[0, 0] > -0.01
    after = vp.curves_at(s8 + 1e-4)
    assert min(c[0, 0] for c in after) < -0.04


def test_yaml_slices_equal_slcs(tmp_path):
    """railexu's YAML slices give the same surface as the same slices in a .slcs file."""
    sl = read_slcs(DATA / "cross_nose.slcs")
    lines = ["text_unit: mm", "slices:"]
    for k in range(sl.n_slices):
        feats = ", ".join(f"{v * 1e3:.4f}" for v in sl.features_m[k])
        lines += [f"  - s_m: {sl.positions_m[k]:.6f}", f"    profile: {DATA / sl.names[k]}",
                  f"    features_mm: [{feats}]"]  # fmt: skip
    path = tmp_path / "nose.yaml"
    path.write_text("\n".join(lines) + "\n")
    vy = VariableProfile(read_yaml_slices(path))
    vs = VariableProfile(sl)
    y = np.linspace(-0.004, 0.04, 200)
    s = np.array([-0.1, -0.033, 0.05])
    np.testing.assert_allclose(vy.heights_on_grid(s, y), vs.heights_on_grid(s, y), atol=1e-9)


def _slcs(tmp_path, rows: list[str], features: list[str] | None = None) -> Path:
    nfeat = len(features[0].split()) - 1 if features else 0
    text = ["% test", "0.0 1.0  U_OFFSET U_SCALE", f"{len(rows)}  NSLC", f"{nfeat} 0 0",
            "1  U_INTPOL", *rows, *(features or [])]  # fmt: skip
    path = tmp_path / "bad.slcs"
    path.write_text("\n".join(text) + "\n")
    return path


def _nose(k: int) -> str:
    return str(DATA / "cross_nose" / f"nose_{k}.prr")


@pytest.mark.parametrize(
    ("rows", "words"),
    [
        ([f"0.0 '{_nose(1)}'", f"-10.0 '{_nose(2)}'"], ["line 7", "slice 2", "out of order"]),
        ([f"0.0 '{_nose(1)}'", f"0.0 '{_nose(2)}'"], ["line 7", "slice 2", "overlaps"]),
        ([f"0.0 '{_nose(1)}'", "10.0 'missing.prr'"], ["line 7", "missing.prr", "not found"]),
    ],
)
def test_bad_slices_are_refused_with_file_line_slice(tmp_path, rows, words):
    path = _slcs(tmp_path, rows)
    with pytest.raises(ProfileError) as err:
        read_slcs(path)
    assert str(path) in str(err.value)
    for w in words:
        assert w in str(err.value)


def test_nan_and_non_graph_profiles_are_refused(tmp_path):
    (tmp_path / "nan.txt").write_text("0 1\n1 nan\n2 0\n3 1\n")
    (tmp_path / "back.txt").write_text("0 1\n2 0.5\n1 0\n3 1\n")
    for name, why in (("nan.txt", "not finite"), ("back.txt", "does not increase")):
        path = _slcs(tmp_path, [f"0.0 '{_nose(1)}'", f"10.0 '{name}'"])
        with pytest.raises(ProfileError, match=why) as err:
            read_slcs(path)
        assert "slice 2" in str(err.value) and "line 7" in str(err.value)


def test_features_out_of_order_refused(tmp_path):
    path = _slcs(
        tmp_path,
        [f"0.0 '{_nose(1)}'", f"10.0 '{_nose(2)}'"],
        ["0.0 0.0 40.0 30.0 299", "10.0 0.0 30.0 40.0 299"],
    )
    with pytest.raises(ProfileError, match="do not increase") as err:
        read_slcs(path)
    assert "slice 1" in str(err.value)


def test_rail_appearing_without_features_is_not_interpolable(tmp_path):
    """CONTACT's uk_crossing.slcs has no feature points; between its slices 47 (wing rail, 107 mm
    of curve) and 48 (wing rail and nose, 218 mm) arc-length fractions would morph the wing
    rail into the nose. Refused, pointing to feature points."""
    text = ["0.0 1000.0", "2", "0 0 0", "1",
            f"0.11395 '{DATA / 'uk_crossing' / 'Crossing_47.txt'}'",
            f"0.11894 '{DATA / 'uk_crossing' / 'Crossing_48.txt'}'"]  # fmt: skip
    path = tmp_path / "uk.slcs"
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(ProfileError, match="appears or disappears") as err:
        read_slcs(path, scale_to_mm=1000.0)
    assert "slice 2" in str(err.value)


def test_yaml_feature_count_mismatch_refused(tmp_path):
    path = tmp_path / "v.yaml"
    path.write_text(
        f"slices:\n  - s_m: 0.0\n    profile: {_nose(1)}\n    features_mm: [0, 30, 299]\n"
        f"  - s_m: 0.01\n    profile: {_nose(2)}\n    features_mm: [0, 299]\n"
    )
    with pytest.raises(ProfileError, match="expected 3") as err:
        read_yaml_slices(path)
    assert "line 5" in str(err.value) and "slices.1" in str(err.value)


def test_variable_rails_refuse_bad_zones():
    """A zone needs a profile on at least one side and sensible station spacing."""
    from railexu.errors import InputError
    from railexu.track.variable_rails import VariableRails

    vp = VariableProfile(read_slcs(DATA / "cross_nose.slcs"))
    with pytest.raises(InputError, match="left or right"):
        VariableRails()
    with pytest.raises(InputError, match="station_step_m"):
        VariableRails(left=vp, station_step_m=0.0)
    with pytest.raises(InputError, match="finite"):
        VariableRails(left=vp, start_m=float("nan"))
    zone = VariableRails(right=vp, start_m=10.0)
    assert zone.zone_m() == pytest.approx((9.9, 10.1))
