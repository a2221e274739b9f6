"""The generated switch panel's interpolation between its slices (issue 29;
docs/switches-and-crossings.md, "The switch panel").

The UK 56E1-R245-1:9.25 turnout's switch panel (``tracks/turnout_uk_r245_*_facing.yaml``, both
routes), its blade and stock rail generated from the track's rail by the design's planing rule
every 25 mm. Both rails are the plain rail moved rigidly (the blade lowered, the stock rail moved
to the field side by ``d(s)``); the slices' feature points tie the same material points of each
rail together, so that the interpolation between two slices pairs the same points of a rail.
Before they did, the stock rail's part began at its visible start, which jumps from the foot of
its continued gauge face to its head where the blade's gauge face takes over (0.850-0.875 m from
the toe): the arc-length fractions paired points 27 mm apart, and the stock rail's top under a
centred wheel dipped by 84 um within that interval (the rigid wheel's height -43, +41, -39 um at
0.850, 0.865, 0.875 m; 5.7 mm vertically, 3.3 mm normal to the surface on the gauge face).

Checked against things outside the interpolation: the slices themselves (between two slices
the surface lies between their heights), the planing rule at the intervals' midpoints (the
generator's own slices at 12.5 mm), and the rigid wheel's touch height along the takeover
(smooth and monotone: the stock rail only moves away, by 3.5 mm per m there).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.spatial import cKDTree

from railexu.contact.variable_rail import WheelSection, rail_touch_heights
from railexu.model.assembly import wheelset_geometry
from railexu.profiles.variable.switch_panel import SwitchPlaning, switch_panel_slices
from railexu.track.track import load_track
from railexu.track.turnout import TurnoutGeometry
from railexu.track.turnout_file import RAIL_POINT_STEP_M
from railexu.vehicle.vehicle import load_vehicle

#: The running band in the panel rail's axes [m]: from the blade's gauge corner (a flange root
#: at y = -34 mm, tests/test_sc_switch_transfer.py) to 30 mm on the field side, within 10 mm of
#: the top (as tests/test_sc_full_crossing.py).
BAND_Y_M = (-0.036, 0.030)
BAND_DEPTH_M = 0.010


class Panel:
    """A route's switch panel (facing, the crossing panel left out), the plain rail it is made
    from and the wheelset vehicle's wheel on its side."""

    def __init__(self, route: str) -> None:
        track = load_track(f"turnout_uk_r245_{route}_facing", ["turnout.panels=switch"])
        rails = track.variable_rails
        side = 0 if rails.left is not None else 1
        (panel,) = rails.sides()[side].panels
        self.profile = panel.profile  # s from the toe
        pair = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track).pairs[side]
        self.wheel = WheelSection.from_pair(pair)
        y = np.arange(pair.rail.y_min, pair.rail.y_max, RAIL_POINT_STEP_M)
        self.head = np.column_stack([y, -pair.rail.height(y)])  # as the turnout file's
        # the design's R 245 m, 1:9.25 (tracks/turnouts/uk_56e1_r245_1v9.25.yaml)
        self.radius_m = TurnoutGeometry(245.0, 9.25).switch_rail_radius_m(route)


@pytest.fixture(scope="module", params=["through", "diverging"])
def panel(request):
    return Panel(request.param)


def _blade_end_y(profile, s_m: float) -> float | None:
    """Lateral position [m] of the blade's visible end (where the stock rail comes on top)."""
    curves = profile.curves_at(s_m)
    return float(curves[0][-1, 0]) if len(curves) == 2 else None


def test_surface_between_slices_lies_between_them(panel):
    """At a quarter, half and three quarters of every slice interval, the surface's height on
    the running band lies between the two slices' heights within 5 um (measured: 4.1 um through,
    4.0 um diverging, both at 5.25 m on the blade's field corner next to its back, whose end
    moves 0.54 mm per slice: the chord between the points a part's moving end pairs; below
    0.05 um up to 3.4 m; 0.000 um in 0.850-0.875 m, 5.7 mm before the material features). Left
    out: the strip the blade's visible end sweeps within the interval (+-0.25 mm, the grid),
    where the top surface at a fixed ``y`` changes from one rail to the other (from 3.5 m the
    blade's back stands above the stock rail's gauge face: an edge, and the rail under it
    moves, so the true surface between two slices is not between their heights there; the
    next test checks it against the planing rule). 5 um: 1/20 of the Hertz approach at the
    static wheel load (~0.1 mm)."""
    profile = panel.profile
    s = profile.positions_m
    y = np.arange(BAND_Y_M[0], BAND_Y_M[1] + 1e-9, 2.5e-4)
    z = profile.heights_on_grid(s, y)
    worst = np.zeros(s.size - 1)
    for i in range(s.size - 1):
        a, b = z[i], z[i + 1]
        band = np.isfinite(a) & np.isfinite(b) & (np.minimum(a, b) < BAND_DEPTH_M)
        ends = [_blade_end_y(profile, x) for x in (s[i], s[i + 1])]
        ends = [e for e in ends if e is not None]
        if ends:
            band &= (y < min(ends) - 2.5e-4) | (y > max(ends) + 2.5e-4)
        for w in (0.25, 0.5, 0.75):
            mid = profile.heights_on_grid([(1 - w) * s[i] + w * s[i + 1]], y)[0]
            assert np.all(np.isfinite(mid[band])), (i, w)
            out = np.maximum(mid - np.maximum(a, b), np.minimum(a, b) - mid)[band]
            worst[i] = max(worst[i], float(out.max(initial=0.0)))
    assert worst.max() < 5e-6, (s[np.argmax(worst)], worst.max())
    takeover = int(np.argmin(np.abs(s - 0.850)))
    assert worst[takeover] < 1e-6  # where the blade's gauge face takes over


def test_surface_between_slices_follows_the_planing_rule(panel):
    """Halfway between the 25 mm slices the interpolated curves lie within 0.1 mm (normal
    distance) of the planing rule's own section there (the generator's slices at 12.5 mm) on
    the running band: measured 25 um (through) and 59 um (diverging) at most, at the blade's
    back at 5.29-5.31 m (an edge moving 0.55 mm per slice), 18-22 um at 2.39 m where the stock
    rail comes on top of the blade's head; 2.5 um at 0.8625 m, where the blade's gauge face
    takes over (3.3 mm before the material features: the takeover is no edge, the two
    continued gauge faces are parallel and meet there, the surface only changes its rail)."""
    profile = panel.profile
    coarse = switch_panel_slices(panel.head, panel.radius_m, SwitchPlaning(), "25 mm")
    for a, b in zip(coarse.points_m, profile.slices.points_m, strict=True):
        np.testing.assert_array_equal(a, b)  # the panel's own rule and rail
    half_step = replace(SwitchPlaning(), slice_step_m=0.0125)
    fine = switch_panel_slices(panel.head, panel.radius_m, half_step, "12.5 mm")
    s = profile.positions_m
    worst = {}
    for k in range(fine.n_slices):
        s_mid = float(fine.positions_m[k])
        if not (0.0 < s_mid < s[-2]) or round(s_mid / 0.0125) % 2 == 0:
            continue  # a midpoint of the 25 mm slices only
        exact = _dense(fine.points_m[k])
        pts = np.vstack(profile.curves_at(s_mid))
        band = ((pts[:, 0] >= BAND_Y_M[0]) & (pts[:, 0] <= BAND_Y_M[1])
                & (pts[:, 1] < BAND_DEPTH_M))  # fmt: skip
        dist, _ = cKDTree(exact).query(pts[band])
        worst[s_mid] = float(dist.max(initial=0.0))
    assert len(worst) > 150
    assert max(worst.values()) < 1e-4, max(worst.items(), key=lambda kv: kv[1])
    assert worst[min(worst, key=lambda x: abs(x - 0.8625))] < 1e-5


def _dense(points: np.ndarray, step_m: float = 5e-6) -> np.ndarray:
    """The polyline sampled every ``step_m`` along it (for a normal distance by nearest point)."""
    a = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))))
    t = np.arange(0.0, a[-1], step_m)
    return np.column_stack([np.interp(t, a, points[:, 0]), np.interp(t, a, points[:, 1])])


def test_rigid_wheel_smooth_where_the_blade_face_takes_over(panel):
    """The rigid wheel (the wheelset vehicle's S1002) at fixed lateral positions on the tread
    (-8, 0, +4 mm), moved along 0.80-0.95 m every 5 mm: its touch height (the geometry alone)
    changes monotonically and smoothly as the stock rail's head under it moves away (by
    d'(s) x 5 mm = 17.5 um per step): every step within 2.5 um (that shift times a tread
    contact slope below 1:7; measured 0.27-1.46 um) and every second difference within 0.2 um
    (measured 0.08 um at most). Before the material features the centred wheel sank by 84 um
    and rose back within 0.850-0.875 m (up to 60 um per 2.5 mm)."""
    s = np.arange(0.80, 0.9501, 0.005)
    for y in (-0.008, 0.0, 0.004):
        z = np.array([np.nanmin(rail_touch_heights(panel.profile, panel.wheel, x, y)) for x in s])
        step = np.diff(z)
        assert np.all(step >= -5e-8) or np.all(step <= 5e-8), (y, step)  # 0.05 um: round-off
        assert np.max(np.abs(step)) < 2.5e-6, (y, step)
        assert np.max(np.abs(np.diff(z, 2))) < 2e-7, (y, np.diff(z, 2))
