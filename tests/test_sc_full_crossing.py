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

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.variable_tables import section_rail_arrays
from railexu.model.assembly import wheelset_geometry
from railexu.profiles.variable import VariableProfile
from railexu.profiles.variable.rails import rail_index
from railexu.profiles.variable.slices import ProfileSlices
from railexu.results.run import RunSettings, run
from railexu.track.track import load_track
from railexu.track.variable_rails import VariableRails
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
        y = [max(m.evaluate(lateral, h).raw[0], key=lambda p: p[K.PF_N])[K.PF_YRAIL]
             for m, h in ((plain, h_plain), (zone, h_zone))]  # fmt: skip
        assert y[1] == pytest.approx(y[0], abs=5e-4)


def _per_rail(model, rails, geometry, s_m, lateral, height):
    """Vertical force [N] of nose (0) and wing rail (1) on the left wheel, by rail_index."""
    f = np.zeros(2)
    for p in model.evaluate(lateral, height).raw[0]:
        if p[K.PF_ACTIVE] > 0 and p[K.PF_N] > 0:
            y = np.array([p[K.PF_YRAIL] - geometry.left.rail_origin_track_m[0]])
            f[rail_index(rails.left, s_m, y)[0]] += p[K.PF_FTZ]
    return f


def _touch_and_pressed(facing, geometry, s_grid, lateral=0.0):
    """Per position: the rigid wheel's touch height on each rail (where it carries 1 N: the
    approach at 1 N is ~0.1 um, the geometry alone), the height pressed with the static load,
    and the two rails' forces there (the compiled kernel on the effective sections)."""
    rails = facing.variable_rails
    model = WheelsetContactModel(geometry)
    r0 = geometry.left.nominal_radius_m
    touch, pressed, forces = [], [], []
    for s in s_grid:
        model.rtab_l, model.rinfo_l = section_rail_arrays(
            rails.left, s, geometry.left, x_max_m=rails.x_max_m
        )

        def height(k, target, s=s):
            def f(h_m):
                v = _per_rail(model, rails, geometry, s, lateral, h_m)
                return (v.sum() if k is None else v[k]) - target

            try:
                return brentq(f, r0 - 0.005, r0 + 0.005, xtol=1e-11)
            except ValueError:  # the rail lies below the other one's reach: no touch
                return np.nan

        h = height(None, WHEEL_LOAD_N)
        pressed.append(h)
        forces.append(_per_rail(model, rails, geometry, s, lateral, h))
        touch.append([height(0, 1.0), height(1, 1.0)])
    return np.array(touch), np.array(pressed), np.array(forces)


@pytest.fixture(scope="module")
def sweep(facing, geometry):
    s_grid = np.arange(0.240, 0.3201, 0.005)
    return (s_grid, *_touch_and_pressed(facing, geometry, s_grid))


def test_quasi_static_transfer_from_wing_rail_to_nose(sweep):
    """The centred EU07 wheel (r0 = 625 mm, S1002) pressed with 98.1 kN, moved along the whole
    crossing from s = 240 to 320 mm: the two rails' vertical forces sum to the wheel load (0.1 %,
    which the pressing imposes); the nose's share rises monotonically from 0 to 1; its 50 %
    point lies within 2 mm of the point where the rigid wheel touches both rails at once, from
    the touch heights alone (the nose's rises past the wing rail's at ~17 mm per metre apart,
    and the Hertz approach is ~0.15 mm: the rails share the load over ~9 mm, symmetric about
    that point to first order); the pressed wheel follows the higher touch height within the
    approach (no jump)."""
    s_grid, touch, pressed, forces = sweep
    assert np.allclose(forces.sum(axis=1), WHEEL_LOAD_N, rtol=1e-3)
    share = forces[:, 0] / forces.sum(axis=1)
    assert share[0] < 0.01 and share[-1] > 0.99
    assert np.all(np.diff(share) >= -1e-3)
    gap = touch[:, 0] - touch[:, 1]  # nose above the wing rail where > 0
    assert np.all(np.diff(gap) > 0.0)
    s_star = np.interp(0.0, gap, s_grid)
    assert np.interp(0.5, share, s_grid) == pytest.approx(s_star, abs=2e-3)
    approach = np.nanmax(touch, axis=1) - pressed
    assert np.all((approach > 0.0) & (approach < 2e-4))


#: The wheelset (vehicles/wheelset.yaml): mass [kg], roll inertia [kg m^2].
WHEELSET_MASS_KG, WHEELSET_ROLL_KG_M2 = 4250.0, 1500.0


def _run_over_the_crossing(facing, time_step_s):
    """The wheelset at 10 m/s, centred, from plain rail over the crossing's slices 4-85 (s up
    to 0.623 m: the wing rail, the nose's start and the landing on it), on the left rail."""
    rails = facing.variable_rails
    full = rails.left.slices
    n = 85 - 4 + 1
    sub = ProfileSlices(full.source, full.positions_m[:n], full.points_m[:n],
                        full.features_m[:n], full.lines[:n], full.names[:n])  # fmt: skip
    start = 3.0
    zone = VariableRails(left=VariableProfile(sub), start_m=start, station_step_m=0.01)
    settings = RunSettings(speed_m_per_s=10.0, distance_m=start + 0.9, initial_lateral_m=0.0,
                           time_step_s=time_step_s, output_interval_s=time_step_s)  # fmt: skip
    result = run(load_vehicle("wheelset"), replace(facing, variable_rails=zone), settings)
    assert result.status["state"] == "completed"
    ts = result.timeseries
    return {k: np.asarray(ts[c]) for k, c in (("s", "ws1_s_m"), ("q", "ws1_left_Q_N"),
            ("nose", "ws1_left_rail1_Q_N"), ("wing", "ws1_left_rail2_Q_N"),
            ("inside", "ws1_left_in_zone"))} | {"s0": start}  # fmt: skip


def test_run_into_and_over_the_crossing(facing, sweep):
    """The wheelset at 10 m/s over the whole crossing's first 1.6 m, time steps 0.4, 0.2 ms.
    No entry step: from the zone's start (the plain rail, slice 4) to s = -0.75 m, just before
    the wing rail begins to rise (slice 12 at -0.718 m), the wheel load stays within 0.5 % of
    the static 98.1 kN (slices 41-60 alone gave 254 kN at 2 m/s there). The rails' forces sum
    to the wheel's (bookkeeping). The impact where the wheel lands on the nose lies within 20
    mm after the quasi-static transfer point and converges with the step (within 5 % between
    the two steps), and it is within a factor 1.3 either way of Jenkins et al.'s P1 force for a
    rigid track (Jenkins, Stephenson, Clayton, Morland, Lyon 1974, The effect of track and
    vehicle parameters on wheel/rail vertical dynamic forces, Railway Engineering Journal 3: P1
    = P0 + 2 alpha V sqrt(k_H m_e / (1 + m_e / m_u)) with the track's mass m_e infinite): P1 =
    P0 + 2 alpha V sqrt(k_H m), with the dip angle 2 alpha the change of slope of the rigid
    wheel's touch heights on wing rail and nose (the slices' geometry), k_H = 1.5 P0 / approach
    (the linearised Hertz stiffness at P0) and m the wheelset's mass at one wheel, 1 / (1 / M +
    b^2 / I_roll) with b = 0.75 m. A factor 1.3: the formula takes the slope change as sudden,
    while the two rails share the load over ~9 mm, and the wheel arrives still oscillating from
    the wing rail's rise (its load 32-139 kN just before the nose)."""
    s_grid, touch, pressed, forces = sweep
    peaks = []
    for dt in (4e-4, 2e-4):
        r = _run_over_the_crossing(facing, dt)
        s = r["s"] - r["s0"]
        inside = r["inside"] > 0.5
        assert np.max(np.abs(r["nose"] + r["wing"] - r["q"])[inside]) < 1e-6 * WHEEL_LOAD_N
        entry = (s >= -0.99474) & (s <= -0.75)
        assert np.count_nonzero(entry) > 50
        assert np.allclose(r["q"][entry], WHEEL_LOAD_N, rtol=5e-3)
        near = (s > 0.22) & (s < 0.40)
        j = int(np.argmax(r["q"][near]))
        peaks.append((r["q"][near][j], s[near][j]))
    gap = touch[:, 0] - touch[:, 1]
    s_star = np.interp(0.0, gap, s_grid)
    for _, at in peaks:
        assert s_star <= at <= s_star + 0.020
    assert peaks[0][0] == pytest.approx(peaks[1][0], rel=0.05)
    before = (s_grid >= s_star - 0.035) & (s_grid <= s_star - 0.005)
    after = (s_grid >= s_star + 0.005) & (s_grid <= s_star + 0.035)
    dip = (
        np.polyfit(s_grid[after], touch[after, 0], 1)[0]
        - np.polyfit(s_grid[before], touch[before, 1], 1)[0]
    )
    approach = touch[after, 0][0] - pressed[after][0]
    k_hertz = 1.5 * WHEEL_LOAD_N / approach
    mass = 1.0 / (1.0 / WHEELSET_MASS_KG + 0.75**2 / WHEELSET_ROLL_KG_M2)
    p1 = WHEEL_LOAD_N + dip * 10.0 * np.sqrt(k_hertz * mass)
    assert 0.010 < dip < 0.025  # ~17 mrad: 7 descending on the wing rail, 10 rising on the nose
    assert 1.0 / 1.3 < peaks[1][0] / p1 < 1.3, (peaks, p1, dip, k_hertz)


def _contacts_when_pushed(model, geometry, lateral_m):
    """Loaded contact points ``(side, y in that rail's axes [m], Fy [N])`` of the wheelset
    pressed with its static axle load at ``lateral_m`` (towards the left, the crossing side)."""
    r0 = geometry.left.nominal_radius_m

    def fz(h):
        raw = model.evaluate(lateral_m, h).raw
        return sum(p[K.PF_FTZ] for s in range(2) for p in raw[s] if p[K.PF_ACTIVE] > 0)

    h = brentq(lambda h: fz(h) - 2.0 * WHEEL_LOAD_N, r0 - 5e-4, r0 + 6e-3, xtol=1e-11)
    out = []
    for side, pair in enumerate((geometry.left, geometry.right)):
        for p in model.evaluate(lateral_m, h).raw[side]:
            if p[K.PF_ACTIVE] > 0 and p[K.PF_N] > 0:
                out.append((side, p[K.PF_YRAIL] - pair.rail_origin_track_m[0], p[K.PF_FTY]))
    return out


def test_check_rail_takes_the_back_of_the_flange(facing, geometry):
    """The check rail beside the opposite (right) stock rail, at s = 0 (the check rail's middle,
    opposite the nose's start), the crossing side plain: the wheelset pressed with its axle
    load and pushed towards the crossing side in 0.5 mm steps. The contact search finds the
    right wheel's back of the flange on the check rail's face (the check rail's slices: its
    face at y = -75.5 mm, 15-33 mm below its top) once the wheelset has moved by the gap
    between the flange's back (680 mm from the track centre: flange backs 1360 mm apart) and
    the face (752.5 - 75.5 = 677 mm), ~3 mm plus the back's slope: between 2.5 and 5 mm; the
    check rail pushes the wheelset back (Fy < 0); and it does so at least 1 mm before the left
    wheel's flange reaches its rail's gauge face (the check rail keeps the flange off the
    nose). At the check rail's flared end (s = -2.897 m, its face 25 mm further away) the same
    push finds no contact on it."""
    rails = facing.variable_rails
    model = WheelsetContactModel(geometry)

    def first(s_m, predicate):
        model.rtab_r, model.rinfo_r = section_rail_arrays(
            rails.right, s_m, geometry.right, x_max_m=rails.x_max_m
        )
        for lateral in np.arange(0.0, 0.0081, 0.0005):
            try:
                points = _contacts_when_pushed(model, geometry, lateral)
            except ValueError:  # wedged against a rail: no height carries the load
                return None, []
            hits = [p for p in points if predicate(p)]
            if hits:
                return lateral, hits
        return None, []

    on_check = lambda p: p[0] == 1 and p[1] < -0.060  # noqa: E731
    on_flange = lambda p: p[0] == 0 and p[1] < -0.025  # noqa: E731
    lateral, hits = first(0.0, on_check)
    assert lateral is not None and 0.0025 <= lateral <= 0.005
    assert all(abs(y + 0.0755) < 0.003 and fy < 0.0 for _, y, fy in hits)
    flange, _ = first(0.0, on_flange)
    assert flange is None or flange >= lateral + 0.001
    assert first(-2.897, on_check)[0] is None


def test_crossing_rails_for_a_route_and_direction():
    """The interface for tracks that place the crossing themselves: the zone at the given
    distance, the trailing one the facing one reversed (s -> -s), the diverging route refused
    (the benchmark has no slices of the crossing for it)."""
    from railexu.errors import InputError
    from railexu.track.uk_crossing import crossing_rails

    facing = crossing_rails("through", "facing", start_m=12.5)
    trailing = crossing_rails("through", "trailing", start_m=12.5)
    assert facing.zone_m() == pytest.approx((12.5 - 2.897, 12.5 + 2.793))
    assert trailing.zone_m() == pytest.approx((12.5 - 2.793, 12.5 + 2.897))
    assert trailing.left.s_range_m == pytest.approx((-2.25764, 0.99474))
    with pytest.raises(InputError, match="route 'diverging'"):
        crossing_rails("diverging")


def test_rail_attribution_along_the_whole_crossing_both_directions(facing):
    """Which rail a point is on, from the slices' geometry: the wing rail alone before the nose
    starts (slice 48), the nose on the gauge side and the wing rail on the field side of the
    flangeway while both exist, the nose alone after the wing rail ends (slice 95) and where
    it has become the plain rail; the same at -s on the trailing track (a first version called
    the trailing track's nose the wing rail: its slices run in the other order)."""
    trailing = load_track("uk_crossing_trailing").variable_rails.left
    y = np.array([-0.020, 0.026])  # the nose's top, the wing rail's (or the nose's) field half
    # at 0.05 m the nose does not exist yet: both lateral positions lie on the wing rail (a
    # first version called y = -20 mm the nose there, by the side of the flangeway's start)
    expected = {-0.5: [1, 1], 0.05: [1, 1], 0.2: [0, 1], 0.5: [0, 0], 1.5: [0, 0], 2.2: [0, 0]}
    for s, rails in expected.items():
        assert rail_index(facing.variable_rails.left, s, y).tolist() == rails, s
        assert rail_index(trailing, -s, y).tolist() == rails, s
