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
