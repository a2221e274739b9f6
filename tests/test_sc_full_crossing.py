"""The whole UK crossing 56E1-R245-1:9.25 (issue 29): the benchmark's 142 slices from the plain
rail to the plain rail with feature points derived by ``tracks/uk_crossing/make_full_slices.py``,
and the check rail beside the opposite stock rail.

Checked against things outside the interpolation: the slices' own points (the surface between
two slices lies between them; the nose appears with the edge of its first slice), the plain rail
the track carries outside the zone (the zone's first and last sections carry the wheel at the
plain rail's height: no step), the rigid wheel's touch heights on nose and wing rail (the load
transfer), and the track's geometry (check gauge: the back of the flange meets the check rail
before the other wheel's flange meets the nose). Source data: CONTACT, E.A.H. Vollebregt,
eve70a/CONTACT, Apache-2.0 (tracks/uk_crossing/README.md).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.variable_tables import section_rail_arrays
from railexu.model.assembly import wheelset_geometry
from railexu.simulation.sc_outputs import rail_index
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

SLICES = Path(__file__).resolve().parents[1] / "tracks" / "uk_crossing" / "uk_crossing"
#: The wheelset vehicle's static wheel load (EU07: 196.2 kN per axle) [N].
WHEEL_LOAD_N = 98.1e3


@pytest.fixture(scope="module")
def facing():
    return load_track("uk_crossing_facing")


@pytest.fixture(scope="module")
def geometry(facing):
    return wheelset_geometry(load_vehicle("wheelset").wheelsets[0], facing)


def test_the_nose_starts_with_its_edge(facing):
    """Before the first two-rail slice (slice 48, s = 118.94 mm) the flangeway holds no rail;
    just after it the nose stands at slice 48's own height (an edge, not a ramp from the wing
    rail), and the wing rail ends after slice 95 (s = 1.0585 m) the same way."""
    profile = facing.variable_rails.left
    y = np.array([-0.030, -0.025])  # on the nose's tip in slice 48
    before = profile.heights_on_grid([0.11894 - 1e-6], y)[0]
    after = profile.heights_on_grid([0.11894 + 1e-6], y)[0]
    assert np.all(np.isinf(before))
    tip = np.loadtxt(SLICES / "Crossing_48.txt")  # the file's points, 0.5 mm apart at most
    assert after == pytest.approx(np.interp(y, tip[:, 0], tip[:, 1]), abs=1e-5)
    wing = np.array([0.130, 0.140])  # on the wing rail in slice 95
    assert np.all(np.isfinite(profile.heights_on_grid([1.0585 - 1e-4], wing)[0]))
    assert np.all(np.isinf(profile.heights_on_grid([1.0585 + 1e-4], wing)[0]))


def test_surface_between_slices_lies_between_them(facing):
    """At a quarter, half and three quarters between every pair of neighbouring slices, the
    surface's height at each lateral position of the running band (|y| <= 30 mm, the tread's
    contacts on the wing rail, the nose and the plain rail; within 10 mm of the top) lies
    between the two slices' heights there within 0.1 mm: no dip or bump beyond the slices' own
    (arc-length fractions without feature points, or with the rails' field corners placed by a
    slope threshold alone, gave 1-6 mm). 0.1 mm: the largest found is 94 um, on the wing rail's
    top between slices 41 and 42 where its field half rises 0.9 mm (the Hertz approach at the
    static wheel load is ~0.1 mm); beyond 30 mm, at the rails' field corners, up to 0.13 mm
    (slices 22-23, the wing rail's head widening) and 0.65 mm at y = 58 mm on the nose (slices
    105-106, the recess between point and splice rail opening: docs/switches-and-crossings.md)."""
    profile = facing.variable_rails.left
    s = profile.positions_m
    y = np.arange(-0.030, 0.0301, 0.0005)
    z = profile.heights_on_grid(s, y)
    worst = 0.0
    for i in range(s.size - 1):
        for w in (0.25, 0.5, 0.75):
            mid = profile.heights_on_grid([(1 - w) * s[i] + w * s[i + 1]], y)[0]
            a, b = z[i], z[i + 1]
            band = np.isfinite(a) & np.isfinite(b) & (np.minimum(a, b) < 0.010)
            assert np.all(np.isfinite(mid[band])), (i, w)
            out = np.maximum(mid[band] - np.maximum(a, b)[band], np.minimum(a, b)[band] - mid[band])
            worst = max(worst, float(out.max(initial=0.0)))
    assert worst < 1e-4


def _pressed_height(model, lateral, load, r0):
    def fz(h):
        raw = model.evaluate(lateral, h).raw
        return sum(p[K.PF_FTZ] for p in raw[0] if p[K.PF_ACTIVE] > 0)

    return brentq(lambda h: fz(h) - load, r0 - 0.005, r0 + 0.005, xtol=1e-11)


@pytest.mark.parametrize("s_m", [-0.99474, 2.25764])
def test_the_zone_ends_on_the_plain_rail(facing, geometry, s_m):
    """At the zone's first and last slice (slices 4 and 145, the plain rail of the benchmark)
    the effective section carries the centred and a 5 mm displaced wheel at the height the
    track's plain rail (MBench_UIC60 placed as the slices) does within 1 um (slices 41-60 alone
    began 1.01 mm higher: the entry step), and the lateral contact position within 0.5 mm."""
    rails = facing.variable_rails
    plain = WheelsetContactModel(geometry)
    zone = WheelsetContactModel(geometry)
    zone.rtab_l, zone.rinfo_l = section_rail_arrays(
        rails.left, s_m, geometry.left, rail_origin_m=rails.rail_origin_m, x_max_m=rails.x_max_m
    )
    r0 = geometry.left.nominal_radius_m
    for lateral in (0.0, 0.005):
        h_plain = _pressed_height(plain, lateral, WHEEL_LOAD_N, r0)
        h_zone = _pressed_height(zone, lateral, WHEEL_LOAD_N, r0)
        assert h_zone == pytest.approx(h_plain, abs=1e-6)
        y = [max(plain.evaluate(lateral, h_plain).raw[0], key=lambda p: p[K.PF_N])[K.PF_YRAIL],
             max(zone.evaluate(lateral, h_zone).raw[0], key=lambda p: p[K.PF_N])[K.PF_YRAIL]]  # fmt: skip
        assert y[1] == pytest.approx(y[0], abs=5e-4)
