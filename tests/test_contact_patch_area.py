"""The patch's approach and Hertz's curvature bound from the overlap of its valley (issue 30).

The kernel's normal load of a patch is Hertz's ``N = K(A, B) delta^1.5`` with the approach
``delta`` the largest depth along the normal ``-g cos(gamma)`` over the overlap of the minimum's
valley, and ``B`` the minimum's half relative lateral curvature, bounded within a factor
``PATCH_CURVATURE_RATIO`` by the one the overlap's area implies
(``kernel.patch_curvature``). Checked here against closed forms:

- a parabolic gap ``-d + B t^2`` overlaps over ``|t| < sqrt(d / B)`` with the area
  ``(4/3) d^1.5 / sqrt(B)``, so ``patch_curvature`` returns ``B`` from ``(d, area)`` and keeps
  the minimum's curvature inside the band, clamps it outside;
- a Hertzian patch (the new S1002's tread, the inner (left) wheel of the wagon's leading
  wheelset in R 250 m at three lateral positions) carries exactly Hertz's load of the
  minimum's own approach ``-g cos(gamma)``: the approach found over the valley exceeds it
  only by the normal's turning along the rail's curvature (second order: < 1e-5 relative).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.hertz import hertz_coefficients_nb
from railexu.model.assembly import wheelset_geometry
from railexu.study.wear.route import load_route
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("b_min", [2.0, 5.0, 9.0, 20.0, 50.0])
def test_patch_curvature_of_a_parabolic_overlap(b_min):
    """``(d, area)`` of the parabola ``-d + B t^2`` give ``B``; the minimum's curvature is kept
    within the band and clamped to its edge outside it (closed form)."""
    d = 1.0e-4  # approach [m]
    b = 8.0  # the parabola's half relative curvature [1/m]
    area = 4.0 / 3.0 * d**1.5 / np.sqrt(b)
    ratio = K.PATCH_CURVATURE_RATIO
    step = 1.0e-5  # the overlap's half-width (3.5 mm) spans many steps: the bound is trusted
    expected = min(max(b_min, b / ratio), b * ratio)
    assert K.patch_curvature(b_min, d, area, step) == pytest.approx(expected, rel=1e-12)


def test_patch_curvature_fades_out_on_a_coarse_lattice():
    """An overlap narrower than three lattice steps is not resolved: the minimum's curvature."""
    d = 1.0e-4
    area = 4.0 / 3.0 * d**1.5 / np.sqrt(8.0)  # half-width 3.5 mm
    assert K.patch_curvature(50.0, d, area, 2.0e-3) == 50.0


@pytest.fixture(scope="module")
def new_model(tmp_path_factory) -> WheelsetContactModel:
    route = load_route(ROOT / "studies" / "wear" / "curvy_10.yaml")
    case = next(c for c in route.cases if c.name == "R250" and c.direction == "forward")
    track = load_track(case.write_track(route, tmp_path_factory.mktemp("patch_area")))
    vehicle = load_vehicle(ROOT / "vehicles" / "hbbins_loaded.yaml")
    return WheelsetContactModel(wheelset_geometry(vehicle.wheelsets[0], track), vehicle.contact,
                                15.0)  # fmt: skip


@pytest.mark.parametrize("lateral_m", [-6.0e-3, -3.0e-3, 0.0])
def test_a_hertzian_patch_carries_hertz_load(new_model, lateral_m):
    """The left (tread) wheel's single loaded point: ``N = K(A, B) delta^1.5`` with the
    minimum's own curvatures (no bound) to rounding, and ``delta`` the minimum's
    ``-g cos(gamma)`` within 1e-5 (the normal's turning over the patch, second order)."""
    vertical, roll, yaw = 0.46001, -0.000535, -0.0209
    result = new_model.evaluate(lateral_m, vertical, roll, yaw)
    raw = result.raw[0]
    loaded = [k for k in range(K.MAX_POINTS) if raw[k, K.PF_N] > 0.0]
    assert len(loaded) == 1
    p = raw[loaded[0]]
    s_min, gaps = new_model.gap_candidates("left", lateral_m, vertical, roll, yaw)
    k = int(np.argmin(gaps))
    ctx = K._make_ctx(new_model.winfo_l, new_model.rinfo_l, lateral_m, vertical, roll, yaw)
    g, cos_gamma, ok = K._gap_cos_at(s_min[k], new_model.wtab_l, new_model.rtab_l, ctx)
    assert ok and g == pytest.approx(p[K.PF_GAP], rel=1e-12)
    assert p[K.PF_DELTA] == pytest.approx(-g * cos_gamma, rel=1e-5)
    assert p[K.PF_DELTA] >= -g * cos_gamma
    b_lat = 0.5 * (p[K.PF_KWY] + p[K.PF_KRY])
    kh = hertz_coefficients_nb(new_model.htab, 0.5 * p[K.PF_KWX], b_lat,
                               new_model.params[K.P_ESTAR])[0]  # fmt: skip
    assert p[K.PF_N] == pytest.approx(kh * p[K.PF_DELTA] ** 1.5, rel=1e-12)
