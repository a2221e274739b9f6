"""Which rail carries a contact point in a switch-and-crossing zone (issue 29,
``railexu.profiles.variable.rails`` and ``railexu.simulation.sc_outputs``): the rail whose
surface is the top one at the point's lateral position in the slices at that station, per
panel (switch: blade, stock rail; crossing: nose,
wing rail; the other side: check rail, stock rail), checked against the slices' own geometry;
the per-rail forces sum to the wheel's; the summary names each rail with its largest Q.

A first version split a zoned profile's section at its deepest point: past the wing rail's end
(s > 1.0585 m, the nose alone, widened on its field side) it gave the nose's load to the wing
rail in the turnout's runs.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from railexu.contact import kernel as K
from railexu.profiles.variable.rails import carrier_rails, labelled_curves, panel_names, rail_index
from railexu.simulation.sc_outputs import crossing_summary, sc_columns
from railexu.track.track import load_track

#: The wing rail's last slice (slice 95) of the shipped crossing [m].
WING_END_M = 1.0585
#: The nose's first slice (slice 48) [m].
NOSE_START_M = 0.11894


@pytest.fixture(scope="module")
def turnout():
    """The through route, facing: the switch panel and the crossing on the left, the check rail
    on the right (zoned profiles, the plain rail between the panels)."""
    return load_track("turnout_uk_r245_through_facing").variable_rails


@pytest.fixture(scope="module")
def crossing_track():
    return load_track("uk_crossing_facing").variable_rails


def _crossing_panel(zoned):
    (panel,) = [p for p in zoned.panels if p.profile.slices.rail_names == ("nose", "wing rail")]
    return panel


def test_panels_and_their_rails_are_named(turnout, crossing_track):
    left = [p["rails"] for p in panel_names(turnout.left)]
    right = [p["rails"] for p in panel_names(turnout.right)]
    assert left == [["none", "plain rail"], ["blade", "stock rail"], ["nose", "wing rail"]]
    assert right == [["none", "plain rail"], ["check rail", "stock rail"]]
    assert panel_names(crossing_track.left)[1]["rails"] == ["nose", "wing rail"]


@pytest.mark.parametrize("which", ["turnout", "crossing_track"])
def test_nose_past_the_wing_rails_end_and_wing_rail_before_the_nose(request, which):
    """Past the wing rail's end the slices hold the nose alone (its field side widened to
    y = +26 mm and beyond): every point there is the nose's (rail 0), on the zoned profile of
    the turnout as on the crossing track's own; before the nose starts the slices hold the wing
    rail alone: every point is the wing rail's (rail 1); while both exist the flangeway parts
    them. With and without the search along the effective section (60 mm)."""
    rails = request.getfixturevalue(which)
    profile = rails.left
    s0 = _crossing_panel(profile).s0_m if which == "turnout" else 0.0
    y = np.array([-0.020, 0.0, 0.020, 0.026])
    for s, expected in ((1.2, [0, 0, 0, 0]), (1.5, [0, 0, 0, 0]), (0.05, [1, 1, 1, 1]),
                        (0.2, [0, 0, 1, 1])):  # fmt: skip
        curves = labelled_curves(profile, s0 + s)
        on = [c for c, lab in curves if c[0, 0] <= 0.026 <= c[-1, 0]]
        assert on, s  # a rail lies under the points
        assert rail_index(profile, s0 + s, y).tolist() == expected, s
        got = carrier_rails(profile, np.full(4, s0 + s), y, np.full(4, 0.46), rails.x_max_m)
        assert got.tolist() == expected, s
    # past the wing rail's end no point of the slices is the wing rail's at all
    for s in (WING_END_M + 0.01, 1.5, 2.0):
        assert all(np.all(lab == 0) for _, lab in labelled_curves(profile, s0 + s))


def test_the_nose_ahead_of_the_axle_carries(crossing_track):
    """The axle 10 mm before the nose's first slice: at y = -27 mm (the nose's tip) the
    section at the axle holds the wing rail only, but the wheel's circle meets the nose 10 mm
    ahead, higher than anything at the axle: the carrier is the nose."""
    profile = crossing_track.left
    s = NOSE_START_M - 0.010
    y = np.array([-0.027])
    assert rail_index(profile, s, y).tolist() == [1]
    assert carrier_rails(profile, np.array([s]), y, np.array([0.46]), 0.06).tolist() == [0]
    # the carrying station is the nose's, ahead of the axle within the effective section; it
    # names the panel (sc_outputs: a point carried past a panel's last slice is the plain rail's)
    rail, at = carrier_rails(profile, np.array([s]), y, np.array([0.46]), 0.06, with_station=True)
    assert rail.tolist() == [0] and NOSE_START_M - 0.0025 <= at[0] <= s + 0.06 + 1e-9


def test_switch_panel_and_check_rail(turnout):
    """Switch panel 3 m from the toe: the blade (gauge side) and the stock rail beside it; the
    check rail's face and the stock rail on the other side, parted by the flangeway."""
    sw = turnout.left.panels[0]
    (blade, stock) = labelled_curves(turnout.left, sw.s0_m + 3.0)
    assert np.all(blade[1] == 0) and np.all(stock[1] == 1)
    y = np.array([0.5 * (blade[0][0, 0] + blade[0][-1, 0]), stock[0][-1, 0] - 0.02])
    assert rail_index(turnout.left, sw.s0_m + 3.0, y).tolist() == [0, 1]
    check = turnout.right.panels[0]
    s = 0.5 * sum(check.range_m)
    assert rail_index(turnout.right, s, np.array([-0.090, -0.076, 0.0])).tolist() == [0, 0, 1]


def test_columns_sum_to_the_wheel_and_summary_names_rails(crossing_track):
    """Synthetic contact points of one wheelset on the crossing side at five positions (before
    the nose, both rails, past the wing rail's end): the two rails' Q sum to the wheel's total
    to round-off, each point is on the rail under it, the panel column says where the wheel
    is, and the summary names each rail with its largest Q."""
    rails = crossing_track
    s_loc = np.array([0.05, 0.2, 0.2, 1.2, 1.5])
    ys = [(0.0, None), (-0.020, 0.026), (-0.020, None), (0.020, -0.010), (0.026, None)]
    n = s_loc.size
    pts = np.zeros((n, 1, 2, K.MAX_POINTS, K.N_POINT_FIELDS))
    origin = 0.75
    for t, pair in enumerate(ys):
        for k, y in enumerate(pair):
            if y is None:
                continue
            pts[t, 0, 0, k, K.PF_N] = 5.0e4 + 1.0e4 * k + t
            pts[t, 0, 0, k, K.PF_FTZ] = 4.9e4 + 1.0e4 * k + t
            pts[t, 0, 0, k, K.PF_FTY] = 1.0e3
            pts[t, 0, 0, k, K.PF_YRAIL] = origin + y
            pts[t, 0, 0, k, K.PF_RADIUS] = 0.46
    geometry = SimpleNamespace(pairs=[SimpleNamespace(rail_origin_track_m=(origin, 0.0))] * 2)
    s_ws = (rails.start_m + s_loc)[:, None]
    cols = sc_columns(rails, geometry, pts, s_ws)
    total = pts[:, 0, 0, :, K.PF_FTZ].sum(axis=-1)
    q1, q2 = cols["ws1_left_rail1_Q_N"], cols["ws1_left_rail2_Q_N"]
    assert q1 + q2 == pytest.approx(total, rel=1e-12)
    assert q1.tolist() == pytest.approx([0.0, pts[1, 0, 0, 0, K.PF_FTZ], total[2], total[3],
                                         total[4]])  # fmt: skip
    assert cols["ws1_left_panel"].tolist() == [1.0] * n
    cols["ws1_s_m"] = s_ws[:, 0]
    panels = {"left": panel_names(rails.left)}
    out = crossing_summary(cols, rails.zone_m(), 1, panels)["ws1_left"]
    named = {r["rail"]: r["max_Q_N"] for r in out["rails"] if r["panel"] == 1}
    assert named == pytest.approx({"nose": q1.max(), "wing rail": q2.max()})
    assert out["max_Q_rail_name"] == ("nose" if q1.max() >= q2.max() else "wing rail")


@pytest.mark.parametrize("value", ["[nose]", "[nose, 3]", "nose", "[a, b, c]"])
def test_rail_names_refused_with_file_and_line(tmp_path, value):
    """A YAML slices file's ``rails`` must name two rails: refused naming the file, the line and
    the key."""
    from railexu.profiles.core import ProfileError
    from railexu.profiles.variable import read_yaml_slices

    (tmp_path / "p.txt").write_text("-10 0\n0 0.1\n10 0\n")
    text = f"text_unit: mm\nrails: {value}\nslices:\n"
    text += "".join(f"  - s_m: {s}\n    profile: p.txt\n" for s in (0.0, 1.0))
    (tmp_path / "s.yaml").write_text(text)
    with pytest.raises(ProfileError, match=r"s\.yaml, line 2: rails = .*expected the two rails"):
        read_yaml_slices(tmp_path / "s.yaml")


def test_run_through_the_turnouts_crossing_labels_the_nose():
    """The wheelset at 10 m/s over the turnout's crossing (through route, facing; the crossing
    panel and the check rail only): past the wing rail's end the nose carries the whole wheel
    (a first version gave 99 % of it to the wing rail there); before the nose starts the wing
    rail does; the two rails' Q sum to the wheel's; the summary names the rails with their
    largest Q, the run's largest on the nose. Crossing stations of 10 mm, not the default 5 mm:
    the labels do not depend on the station step, and 10 mm halve the tables' build."""
    from railexu.results.run import RunSettings, run
    from railexu.vehicle.vehicle import load_vehicle

    sets = ["turnout.panels=crossing", "start=62 m", "turnout.crossing_station_step=10 mm"]
    track = load_track("turnout_uk_r245_through_facing", sets)
    rails = track.variable_rails
    settings = RunSettings(speed_m_per_s=10.0, distance_m=7.0, initial_lateral_m=0.0)
    result = run(load_vehicle("wheelset"), track, settings)
    assert result.status["state"] == "completed"
    ts = result.timeseries
    cross = _crossing_panel(rails.left)
    s = np.asarray(ts["ws1_s_m"]) - rails.start_m - cross.s0_m
    inside = np.asarray(ts["ws1_left_in_zone"]) > 0.5
    q = np.asarray(ts["ws1_left_Q_N"])
    nose, wing = np.asarray(ts["ws1_left_rail1_Q_N"]), np.asarray(ts["ws1_left_rail2_Q_N"])
    assert np.max(np.abs(nose + wing - q)[inside]) < 1e-6 * 1e5
    past = inside & (s > WING_END_M + 0.01)
    before = inside & (s < NOSE_START_M - 0.06)
    assert np.count_nonzero(past) > 20  # outputs every 50 mm over 1.2 m
    assert np.all(wing[past] == 0.0)
    assert nose[past] == pytest.approx(q[past], abs=1e-6)
    assert np.all(nose[before] == 0.0)
    panel = np.asarray(ts["ws1_left_panel"])
    assert np.all(panel[inside & (np.abs(s) < 0.5)] == 1.0)  # the crossing, the left's only panel
    out = result.summary["switches_crossings"]["ws1_left"]
    named = {r["rail"]: r["max_Q_N"] for r in out["rails"]}
    assert named["nose"] == pytest.approx(nose[inside].max())
    assert named["wing rail"] == pytest.approx(wing[inside & (panel == 1.0)].max())
    assert out["max_Q_rail_name"] == "nose"
