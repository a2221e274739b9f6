"""The turnout's crossing panel is the whole UK crossing with its check rail (issue 29): the
panels join the plain track without a step, for both routes and both directions.

Reference outside the code under test: the plain track's own rail (the crossing's 56E1,
``tracks/uk_crossing/uk_56e1_plain.txt``, uninclined), read by the contact model as on plain
track, without any slices. At each panel boundary (switch panel, crossing, check rail; each
side) the rigid wheelset's wheel on that side is pressed with the static wheel load on the
section just before and just after the boundary (no effective length: the surface itself); its
height must equal the plain rail's within 1 um (the benchmark's own plain slices agree with
the plain rail file to ~0.1 um; slices 41-60 alone began 1.01 mm higher: the entry step this
replaces).
"""

from __future__ import annotations

import pytest
from scipy.optimize import brentq

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.variable_tables import section_rail_arrays
from railexu.model.assembly import wheelset_geometry
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

#: The wheelset vehicle's static wheel load (EU07: 196.2 kN per axle) [N].
WHEEL_LOAD_N = 98.1e3
ROUTES = [f"{r}_{d}" for r in ("through", "diverging") for d in ("facing", "trailing")]


def _pressed_height(model: WheelsetContactModel, side: int, r0: float) -> float:
    """Height [m] of the centred wheelset at which the wheel on ``side`` (0 left, 1 right)
    carries the static wheel load."""

    def fz(h):
        raw = model.evaluate(0.0, h).raw
        return sum(p[K.PF_FTZ] for p in raw[side] if p[K.PF_ACTIVE] > 0)

    return brentq(lambda h: fz(h) - WHEEL_LOAD_N, r0 - 0.005, r0 + 0.005, xtol=1e-11)


@pytest.mark.parametrize("route", ROUTES)
def test_panels_join_the_plain_track_without_a_step(route):
    track = load_track(f"turnout_uk_r245_{route}")
    rails = track.variable_rails
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
    r0 = geometry.left.nominal_radius_m
    plain = WheelsetContactModel(geometry)
    names = []
    for side, profile in enumerate(rails.sides()):
        if profile is None:
            continue
        pair = geometry.left if side == 0 else geometry.right
        h_plain = _pressed_height(plain, side, r0)
        for panel in profile.panels:
            names.append(panel.profile.slices.source)
            for boundary in panel.range_m:
                for s in (boundary - 1e-5, boundary + 1e-5):
                    zone = WheelsetContactModel(geometry)
                    tables = section_rail_arrays(profile, s, pair, x_max_m=0.0)
                    if side == 0:
                        zone.rtab_l, zone.rinfo_l = tables
                    else:
                        zone.rtab_r, zone.rinfo_r = tables
                    h = _pressed_height(zone, side, r0)
                    assert h == pytest.approx(h_plain, abs=1e-6), (panel, boundary, s)
    # the switch panel and the whole crossing on the route's side, the check rail opposite
    assert sum("switch panel" in n for n in names) == 1
    assert sum(n.endswith("uk_crossing_full.yaml") for n in names) == 1
    assert sum(n.endswith("check_rail_thr.yaml") for n in names) == 1


def test_plain_stations_share_one_table_to_the_last_bit():
    """Stations whose effective section lies on the plain rail between the panels get the one
    plain table computed once (``station_tables(share_plain=True)``), the same numbers as
    computing every station: across the switch panel's end (its last slices, the boundary,
    the plain stretch) the tables are identical to the last bit, so a run's wheel forces are
    the same."""
    import numpy as np

    from railexu.contact.variable_tables import station_tables

    track = load_track("turnout_uk_r245_through_facing")
    rails = track.variable_rails
    pair = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track).left
    end = rails.left.panels[0].range_m[1]  # the switch panel's last slice
    stations = end + rails.station_step_m * np.arange(-4, 12)
    plain = [rails.left.is_plain_over(s - rails.x_max_m, s + rails.x_max_m) for s in stations]
    assert 5 <= sum(plain) < len(stations)
    shared, info_a = station_tables(rails.left, pair, stations, x_max_m=rails.x_max_m)
    each, info_b = station_tables(rails.left, pair, stations, x_max_m=rails.x_max_m,
                                  share_plain=False)  # fmt: skip
    np.testing.assert_array_equal(info_a, info_b)
    np.testing.assert_array_equal(shared, each)


def test_shared_rows_give_the_same_run_through_the_switch_panel(monkeypatch):
    """The kernel's station store keeps one row for the stations with the same table (the
    plain rail between the panels) and each station reads its row by index: a run of the
    wheelset through the switch panel and onto the plain stretch gives the same wheel forces
    with the shared store as with one row per station (the store before issue 29's change),
    to the last bit (the same numbers blended the same way)."""
    import functools

    import numpy as np

    from railexu.model import assembly, sc_tables
    from railexu.results.run import RunSettings, run

    real = sc_tables.station_table_set
    built: dict = {}

    def once(profile, pair, stations, **kw):  # both runs read the same tables: build them once
        key = (id(profile), stations.size)
        if key not in built:
            built[key] = real(profile, pair, stations, **kw)
        return built[key]

    monkeypatch.setattr(sc_tables, "station_table_set", once)
    # coarse stations, the crossing's too (the shipped 10 mm: 242 s, most of it the crossing's
    # tables built twice, shared and one row per station): the run ends 3 m past the switch
    # panel, the crossing is never reached; the shared store is what is checked
    sets = ["turnout.station_step=0.25 m", "turnout.crossing_station_step=0.25 m"]
    lo, _ = load_track("turnout_uk_r245_through_facing", sets).variable_rails.zone_m()
    track = load_track("turnout_uk_r245_through_facing", [*sets, f"start={lo - 2.0} m"])
    rails = track.variable_rails
    end = rails.start_m + rails.left.panels[0].range_m[1]  # the switch panel's last slice
    settings = RunSettings(speed_m_per_s=10.0, distance_m=end + 3.0 - (lo - 1.0),
                           initial_lateral_m=0.0)  # fmt: skip
    vehicle = load_vehicle("wheelset")
    out = {}
    for share in (True, False):
        fields = functools.partial(sc_tables.sc_kernel_fields, share_rows=share)
        monkeypatch.setattr(assembly, "sc_kernel_fields", fields)
        out[share] = run(vehicle, track, settings)
    # the store: every station and side reads the same table from the shared rows, in fewer
    geometry = wheelset_geometry(vehicle.wheelsets[0], track)
    stores = [sc_tables.sc_kernel_fields(rails, geometry, 5.0e-4, share_rows=share)
              for share in (True, False)]  # fmt: skip
    for k in range(2):
        rows = [f["sc_tab"][f["sc_index"][:, k]] for f in stores]
        np.testing.assert_array_equal(rows[0], rows[1])
    assert stores[0]["sc_tab"].shape[0] < 0.8 * stores[1]["sc_tab"].shape[0]
    for share, result in out.items():
        assert result.status["state"] == "completed", (share, result.status)
    shared, each = out[True].timeseries, out[False].timeseries
    s = np.asarray(shared["ws1_s_m"])
    assert s.max() > end + 2.0  # onto the plain stretch
    for column in ("ws1_left_Q_N", "ws1_left_Y_N", "ws1_right_Q_N", "ws1_right_Y_N"):
        np.testing.assert_array_equal(np.asarray(shared[column]), np.asarray(each[column]))
