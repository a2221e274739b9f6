"""A run through the shipped UK crossing (issue 29) and its outputs per rail.

Checked against things outside the code: which rail a contact point belongs to, against the
slices' own geometry (the nose's and the wing rail's tops on either side of the flangeway's
bottom, read from the profile points in the test); the 50 % transfer point of a prescribed
linear load transfer (analytic: the middle of the ramp); and in a dynamic run the bookkeeping
(the rails' vertical forces sum to the wheel's, to rounding) and the rail that carries the wheel
inside slices 41-60 against the quasi-static kernel's answer for a centred wheel (the wing rail:
the nose is still below the wheel's tread there, tests/test_sc_kernel.py's mbench_intrup case).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.profiles.variable.rails import rail_index
from railexu.results.run import RunSettings, run
from railexu.simulation.sc_outputs import crossing_summary
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

TRACKS = Path(__file__).resolve().parents[1] / "tracks"
#: CONTACT's short crossing (slices 41-60 of the UK crossing, uk_interrupt_v2.slcs, on the
#: benchmark's UIC60 canted 1:40, CONTACT's placement), as the shipped crossing tracks were
#: before the whole crossing: these tests check the per-rail outputs and the transfer inside
#: it (the whole crossing: tests/test_sc_full_crossing.py).
SHORT_CROSSING = f"""format_version: 1
name: UK crossing slices 41-60, facing
rail_profile: MBench_UIC60
inclination: "1:40"
gauge: 1.435 m
geometry:
  type: straight
variable_rails:
  type: slices
  start: 3 m
  direction: facing
  left: {TRACKS / "uk_crossing" / "uk_interrupt_v2.slcs"}
  text_unit: m
  rail_origin: [0.75 m, 0 m]
  station_step: 10 mm
  effective_length: 60 mm
irregularities:
  type: none
"""


@pytest.fixture(scope="module")
def facing(tmp_path_factory):
    path = tmp_path_factory.mktemp("short_crossing") / "short_crossing.yaml"
    path.write_text(SHORT_CROSSING)
    return load_track(path)


def test_rail_index_against_the_slices_geometry(facing):
    profile = facing.variable_rails.left
    (curve,) = profile.curves_at(0.16)  # nose and wing rail on one curve through the flangeway
    y, z = curve[:, 0], curve[:, 1]
    bottom = y[int(np.argmax(z))]
    nose_top = y[y < bottom][int(np.argmin(z[y < bottom]))]
    wing_top = y[y > bottom][int(np.argmin(z[y > bottom]))]
    assert nose_top < bottom < wing_top
    assert list(rail_index(profile, 0.16, np.array([nose_top, wing_top]))) == [0, 1]
    # before the nose starts (118.94 mm) the side has the wing rail only: every point on rail 2
    (before,) = profile.curves_at(0.05)
    top = before[int(np.argmin(before[:, 1])), 0]
    assert rail_index(profile, 0.05, np.array([top, top + 0.01])).tolist() == [1, 1]


def test_transfer_point_of_a_linear_ramp():
    """The nose's share rising linearly from 0 at 1.0 m to 1 at 2.0 m crosses 50 % at 1.5 m
    (to rounding); the largest force and its place are the ramp's end."""
    s = np.linspace(0.0, 3.0, 301)
    share = np.clip(s - 1.0, 0.0, 1.0)
    load = 1.0e5 * (1.0 + 0.2 * (np.abs(s - 2.5) < 1e-9))
    cols = {
        "ws1_s_m": s,
        "ws1_left_in_zone": ((s >= 0.5) & (s <= 2.8)).astype(float),
        "ws1_left_rail1_Q_N": share * load,
        "ws1_left_rail2_Q_N": (1.0 - share) * load,
        "ws1_left_rail1_Tgamma_N": 10.0 * share,
        "ws1_left_rail2_Tgamma_N": 20.0 * (1.0 - share),
    }
    out = crossing_summary(cols, (1.0, 2.0), 1)["ws1_left"]
    assert out["transfer_at_m"] == pytest.approx(1.5, abs=1e-9)
    assert out["max_Q_N"] == pytest.approx(1.2e5) and out["max_Q_at_m"] == pytest.approx(2.5)
    assert out["max_Q_rail"] == 1
    assert out["Tgamma_max_N"] == pytest.approx([10.0, 20.0])


def test_wheelset_through_the_facing_crossing(facing):
    """The wheelset, 3 m at 2 m/s over the crossing (zone at 2.91-3.18 m)."""
    result = run(load_vehicle("wheelset"), facing,
                 RunSettings(speed_m_per_s=2.0, distance_m=3.0, initial_lateral_m=0.0))  # fmt: skip
    assert result.status["state"] == "completed"
    ts = result.timeseries
    q = np.asarray(ts["ws1_left_Q_N"])
    r1, r2 = np.asarray(ts["ws1_left_rail1_Q_N"]), np.asarray(ts["ws1_left_rail2_Q_N"])
    inside = np.asarray(ts["ws1_left_in_zone"]) > 0.5
    for name in ts.names:  # no NaN: a non-finite value would mark a diverged run
        assert np.all(np.isfinite(np.asarray(ts[name]))), name
    s = np.asarray(ts["ws1_s_m"])
    lo, hi = facing.variable_rails.zone_m()
    # defined where the model reads the zone's station tables (every 10 mm from the first slice)
    last = lo + np.floor((hi - lo) / 0.01) * 0.01
    assert np.all(inside == ((s >= lo) & (s <= last)))
    assert np.count_nonzero(inside) >= int((last - lo) / (2.0 * 0.008))  # outputs every 8 mm
    # bookkeeping: every loaded point is on one of the two rails
    assert np.max(np.abs(r1[inside] + r2[inside] - q[inside])) < 1e-6 * 1e5
    # inside slices 41-60 (before the wheel passes the last slice) the centred wheel runs on the
    # wing rail: the nose carries nothing
    assert np.all(r1[inside] == 0.0)
    summary = result.summary["switches_crossings"]["ws1_left"]
    assert summary["max_Q_rail"] == 2 and lo <= summary["max_Q_at_m"] <= hi
    assert summary["transfer_at_m"] is None


def test_quasi_static_transfer_onto_the_nose(facing):
    """The EU07 wheel (r0 = 625 mm, S1002) 4 mm to the field side, pressed with 98.1 kN by the
    compiled kernel on the zone's effective sections, moved from s = 130 to 150 mm: the load
    passes from the wing rail (rail 2) to the nose (rail 1), attributed by
    :func:`rail_index`. Checks: the nose's share rises monotonically from 0 to 1; the wheel's
    height changes per step as the higher of the rigid wheel's touch heights on the two rails
    within the Hertz approach at 98 kN (~ 0.1 mm, measured on the wing rail alone: the most
    that sharing the load between two patches can change; no jump);
    the 50 % point lies within 5 mm of where the rigid wheel touches both rails at once (from
    the touch heights alone: the nose's rises past the wing rail's). 5 mm: the touch heights
    part at ~ 1:25 and the approach is ~ 0.1 mm, so the rails share load over ~ 3 mm of track.
    A centred wheel stays on the wing rail throughout slices 41-60 (the dynamic run above)."""
    from scipy.optimize import brentq

    from railexu.contact import kernel as K
    from railexu.contact.evaluation import WheelsetContactModel
    from railexu.contact.variable_tables import section_rail_arrays
    from railexu.model.assembly import wheelset_geometry

    rails = facing.variable_rails
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], facing)
    model = WheelsetContactModel(geometry)
    r0, lateral, load = geometry.left.nominal_radius_m, 0.004, 98.1e3

    def per_rail(s, h):
        raw = model.evaluate(lateral, h).raw[0]
        f = np.zeros(2)
        for p in raw:
            if p[K.PF_ACTIVE] > 0 and p[K.PF_N] > 0:
                y = np.array([p[K.PF_YRAIL] - rails.rail_origin_m[0]])
                f[rail_index(rails.left, s, y)[0]] += p[K.PF_FTZ]
        return f

    def height(f, target):
        return brentq(lambda h: f(h) - target, r0 - 0.003, r0 + 0.003, xtol=1e-10)

    s_grid = np.arange(0.130, 0.1501, 0.0025)
    share, pressed, touch = [], [], []
    for s in s_grid:
        model.rtab_l, model.rinfo_l = section_rail_arrays(
            rails.left, s, geometry.left, rail_origin_m=rails.rail_origin_m, x_max_m=rails.x_max_m
        )
        h = height(lambda hh, s=s: per_rail(s, hh).sum(), load)
        f = per_rail(s, h)
        assert f.sum() == pytest.approx(load, rel=1e-3)
        share.append(f[0] / f.sum())
        pressed.append(h)
        # rigid touch height of each rail: where it carries 1 N (approach ~ 0.1 um)
        touch.append([height(lambda hh, s=s, k=k: per_rail(s, hh)[k], 1.0) for k in range(2)])
    share, pressed, touch = np.array(share), np.array(pressed), np.array(touch)
    assert share[0] < 0.02 and share[-1] > 0.98
    assert np.all(np.diff(share) >= -1e-3)
    # no jump: per step the pressed wheel follows the rigid wheel within the elastic approach
    # at the full load (the most the sharing between two patches can change; 0.10 mm here)
    approach = touch[0].max() - pressed[0]
    assert 5e-5 < approach < 2e-4
    assert np.max(np.abs(np.diff(pressed) - np.diff(touch.max(axis=1)))) < approach
    gap = touch[:, 0] - touch[:, 1]  # nose above the wing rail where > 0
    s_star = np.interp(0.0, gap, s_grid)
    assert np.all(np.diff(gap) > 0.0)
    assert np.interp(0.5, share, s_grid) == pytest.approx(s_star, abs=5e-3)
