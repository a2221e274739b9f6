"""Stations that are not uniform in a switch-and-crossing zone (issue 29).

The dynamics blends the rail tables of the two stations around a wheelset
(:func:`railexu.model.forces._station_interval`, :func:`railexu.model.forces._blend_station`).
References outside the code under test:

- a uniform zone: the blend's interval and fraction as they were computed before the stations
  became an array (``u = (s - start) / step``, ``i = int(u)``, ``t = u - i``, written out here)
  and the tables blended with them: equal to the last bit (the same IEEE operations);
- a zone with parts of their own step: the definition of the union of uniform grids (each
  part's ``a + k h`` from its start, its end included; the zone's default grid outside; both
  zone ends), and the blend fraction's definition ``t = (s - x_i) / (x_{i+1} - x_i)``: 0 at a
  station, 1/2 halfway (within 1e-12: the rounding of track distances of ~70 m, 1e-14 m, over
  intervals of 10 mm);
- the blend writes only the four base columns and the kernel reads the curvature-bound columns
  from station ``i``'s own row: against the one table the blend made before (base columns
  blended, bound columns copied from that row), the same contact points and forces to the last
  bit;
- refusals name the file, the line and the key.
"""

from __future__ import annotations

from pathlib import Path

import numba
import numpy as np
import pytest
from sc_store_view import StoreView, store_view
from scipy.optimize import brentq

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.errors import InputError
from railexu.model import forces
from railexu.model.assembly import wheelset_geometry
from railexu.model.sc_tables import sc_kernel_fields
from railexu.track.track import load_track
from railexu.track.variable_rails import SAME_STATION_M, VariableRails
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
TURNOUT = "turnout_uk_r245_diverging_facing"


#: The force function's station search and blend compiled here with its flags but without
#: numba's cache: a cached overload for this module's type would be pickled into the package's
#: cache index, which other processes (without this test module) could not load.
_FLAGS = {k: v for k, v in K.JIT_NO_REFCOUNT.items() if k != "cache"}
_station_interval = numba.njit(**_FLAGS)(forces._station_interval.py_func)
_blend_station = numba.njit(**_FLAGS)(forces._blend_station.py_func)


def _data(fields: dict) -> StoreView:
    return store_view(fields)


def _old_interval(s: float, start: float, step: float, n: int) -> tuple[int, float]:
    """The blend's interval and fraction as computed before issue 29's station array."""
    u = (s - start) / step
    if u >= 0.0 and u <= n - 1.0:
        i = min(int(u), n - 2)
        return i, u - i
    return -1, 0.0


def _blended(d: StoreView, i: int, t: float, side: int) -> np.ndarray:
    _blend_station(d, 0, i, t, side)
    return d.sc_cache[0, d.sc_side[side]].copy()


@pytest.fixture(scope="module")
def switch_zone():
    """The turnout's switch panel alone at 0.25 m stations (a small store)."""
    sets = ["turnout.panels=switch", "turnout.station_step=0.25 m"]
    track = load_track(TURNOUT, sets)
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
    return track.variable_rails, geometry


def test_uniform_zone_blends_as_before_to_the_last_bit(switch_zone):
    rails, geometry = switch_zone
    fields = sc_kernel_fields(rails, geometry, 5.0e-4)
    assert rails.uniform and fields["sc_step"] == rails.station_step_m
    d = _data(fields)
    n = d.sc_index.shape[0]
    lo, hi = d.sc_stations[0], d.sc_stations[-1]
    rng = np.random.default_rng(29)
    s_all = np.concatenate([
        rng.uniform(lo - 0.5, hi + 0.5, 400), d.sc_stations, d.sc_stations + 1e-9,
        np.nextafter(d.sc_stations, -np.inf), [lo, hi, np.nan],
    ])  # fmt: skip
    side = int(np.flatnonzero(d.sc_side >= 0)[0])
    for s in s_all:
        before = _old_interval(float(s), fields["sc_start"], rails.station_step_m, n)
        after = _station_interval(d, float(s))
        assert after[0] == before[0] and (after[0] < 0 or after[1] == before[1]), (s, after)
        if before[0] >= 0:
            d.sc_key[:] = -1  # a fresh blend each time
            old = _blended(d, before[0], before[1], side)
            d.sc_key[:] = -1
            new = _blended(d, *after, side)
            assert np.array_equal(old, new), s


def test_parts_of_their_own_step_give_the_union_of_grids():
    track = load_track(TURNOUT, ["turnout.crossing_station_step=10 mm"])
    rails = track.variable_rails
    lo, hi = rails.zone_m()
    (a, b, h), = rails.station_steps_m  # fmt: skip
    assert h == 0.01 and lo < a < b == hi  # the crossing panel ends the zone (facing)
    x = rails.stations_m()
    assert x[0] == lo and x[-1] == hi and a in x and b in x
    assert np.all(np.diff(x) > SAME_STATION_M)
    inside, outside = x[x >= a], x[x <= a]
    # the crossing's grid from its first slice, every 10 mm, its last slice included
    k = np.arange(inside.size - 1)
    np.testing.assert_allclose(inside[:-1], a + h * k, rtol=0, atol=1e-12)
    assert 0.0 < inside[-1] - inside[-2] <= h + 1e-12
    # the default 50 mm grid from the zone's start up to the crossing panel
    np.testing.assert_allclose(outside[:-1], lo + 0.05 * np.arange(outside.size - 1), atol=1e-12)
    assert 0.0 < a - outside[-2] <= 0.05
    # the same without the part: the uniform grid, 50 mm from the zone's start
    # (the shipped file sets 20 mm in the crossing: a step equal to the default is no part)
    plain = load_track(TURNOUT, ["turnout.crossing_station_step=50 mm"]).variable_rails
    assert plain.uniform
    np.testing.assert_array_equal(
        plain.stations_m(), lo + 0.05 * np.arange(plain.stations_m().size)
    )
    assert x.size == outside.size - 1 + inside.size
    # a switch part as well: both parts' ends are stations
    both = load_track(TURNOUT, ["turnout.switch_station_step=0.1 m",
                                "turnout.crossing_station_step=20 mm"]).variable_rails  # fmt: skip
    xs = both.stations_m()
    assert len(both.station_steps_m) == 2
    for a2, b2, _ in both.station_steps_m:
        assert a2 in xs and b2 in xs


def test_blend_fraction_at_and_between_non_uniform_stations(switch_zone):
    rails, geometry = switch_zone
    lo, hi = rails.zone_m()
    fine = VariableRails(
        left=rails.left, right=rails.right, start_m=rails.start_m, station_step_m=0.25,
        x_max_m=rails.x_max_m, station_steps_m=((lo + 1.0, lo + 1.6, 0.1),),
    )  # fmt: skip
    fields = sc_kernel_fields(fine, geometry, 5.0e-4)
    assert fields["sc_step"] == 0.0
    d = _data(fields)
    x = d.sc_stations
    np.testing.assert_array_equal(x, fine.stations_m())
    assert x.size == d.sc_index.shape[0]
    j = int(np.searchsorted(x, lo + 1.0))
    expected = [0.75, 1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.75]
    np.testing.assert_allclose(x[j - 1 : j + 8] - lo, expected, atol=1e-12)
    side = int(np.flatnonzero(d.sc_side >= 0)[0])
    for i in range(x.size - 1):
        assert _station_interval(d, float(x[i])) == (i, 0.0)
        mid = 0.5 * (x[i] + x[i + 1])
        k, t = _station_interval(d, float(mid))
        assert k == i and t == pytest.approx(0.5, abs=1e-12)
        # at a station the blend is that station's table (base columns), to the last bit
        d.sc_key[:] = -1
        table = _blended(d, i, 0.0, side)
        base = d.sc_base[d.sc_index[i, side]]
        assert np.array_equal(table[:, : base.shape[1]], base)
    assert _station_interval(d, float(x[-1])) == (x.size - 2, 1.0)
    for s in (x[0] - 1e-9, x[-1] + 1e-9, np.nan):
        assert _station_interval(d, float(s))[0] == -1


def test_bounds_from_the_station_row_give_the_copied_tables_contact(switch_zone):
    """The switch panel (blade and stock rail; 0.25 m stations, the module's small store): at
    random stations, blend fractions and wheelset poses (lateral +-10 mm: tread and flange,
    one rail and two), the kernel with the blended base columns and the station row's bounds
    (the force function since issue 29's speed stop) gives the contact points and the forces of
    the kernel on one table holding both (the blend before it: the bound columns copied into
    the blended table), to the last bit."""
    rails, geometry = switch_zone
    d = _data(sc_kernel_fields(rails, geometry, 5.0e-4))
    assert d.sc_cache.shape[-1] == K.T_SLOPE_MAX < d.sc_tab.shape[-1]
    model = WheelsetContactModel(geometry)
    wtab = (model.wtab_l, model.wtab_r)
    winfo = (model.winfo_l, model.winfo_r)
    plain = ((model.rtab_l, model.rinfo_l), (model.rtab_r, model.rinfo_r))
    scratch = np.empty(K.wheelset_scratch_size(model.winfo_l, model.winfo_r))
    spin = 10.0 / geometry.left.nominal_radius_m
    rng = np.random.default_rng(2929)
    n_st = d.sc_index.shape[0]
    loaded_points = []
    for _ in range(80):
        i, t = int(rng.integers(0, n_st - 1)), float(rng.uniform(0.0, 1.0))
        y = rng.uniform(-0.010, 0.010)
        roll, yaw = rng.uniform(-2e-3, 2e-3), rng.uniform(-3e-3, 3e-3)
        # the height at which the wheels touch the plain rails (1 N), pressed 0 to 0.2 mm lower
        touch = brentq(lambda z, y=y, r=roll, p=yaw: model.evaluate(y, z, r, p).force_N[2] - 1.0,
                       0.3, 1.0, xtol=1e-10)  # fmt: skip
        state = np.array([0.0, y, touch - rng.uniform(0.0, 2e-4), roll, yaw, 10.0, 0.0, 0.0,
                          0.0, spin, 0.0])  # fmt: skip
        new, old, info = [], [], []
        for side in range(2):
            if d.sc_side[side] < 0:  # the track's rail on this side
                new.append(plain[side][:1] * 2)
                old.append(plain[side][:1] * 2)
                info.append(plain[side][1])
                continue
            _blend_station(d, 0, i, t, side)
            base = d.sc_cache[0, d.sc_side[side]].copy()
            row = d.sc_tab[d.sc_index[i, side]]
            whole = row.copy()
            whole[:, : K.T_SLOPE_MAX] = base
            new.append((base, row))
            old.append((whole, whole))
            info.append(d.sc_info[side])
        out = []
        for tables in (new, old):
            points = np.zeros((2, K.MAX_POINTS, K.N_POINT_FIELDS))
            force = np.zeros(6)
            K.wheelset_contact_with_scratch(
                wtab[0], winfo[0], tables[0][0], info[0], wtab[1], winfo[1], tables[1][0],
                info[1], model.htab, model.ktab, model.params, state, np.zeros(8), points,
                force, scratch, tables[0][1], tables[1][1],
            )  # fmt: skip
            out.append((points, force))
        (p_new, f_new), (p_old, f_old) = out
        assert np.array_equal(p_new, p_old, equal_nan=True) and np.array_equal(f_new, f_old)
        loaded_points.append(int((p_new[..., K.PF_N] > 0.0).sum(axis=1).max()))
    # the poses load one rail and two (some none: the blade lower than the plain rail)
    assert max(loaded_points) >= 2 and sum(n >= 1 for n in loaded_points) >= 40, loaded_points


@pytest.mark.parametrize(
    ("line", "expected"),
    [
        ("  crossing_station_step: 0 m", "turnout.crossing_station_step"),
        ("  switch_station_step: 2 m", "turnout.switch_station_step"),
        ("  crossing_station_step: 0.05 mm", "turnout.crossing_station_step"),
        ("  crossing_step: 10 mm", "crossing_step"),
    ],
)
def test_bad_panel_step_refused_with_file_line_and_key(tmp_path, line, expected):
    design = ROOT / "tracks" / "turnouts" / "uk_56e1_r245_1v9.25.yaml"
    text = (
        "format_version: 1\nname: t\nrail_profile: MBench_UIC60\nturnout:\n"
        f"  design: {design}\n  route: through\n  direction: facing\n{line}\n"
    )
    p = tmp_path / "t.yaml"
    p.write_text(text)
    with pytest.raises(InputError) as err:
        load_track(p)
    message = str(err.value)
    assert "t.yaml" in message and expected in message and "8" in message, message


def test_variable_rails_parts_refused():
    rails = load_track(TURNOUT, ["turnout.panels=switch"]).variable_rails
    lo, _ = rails.zone_m()
    for parts, expected in (
        (((lo, lo + 1.0, 0.0),), "0.1 mm .. 1 m"),
        (((lo + 1.0, lo, 0.01),), "from < to"),
        (((lo, lo + 1.0, 0.01), (lo + 0.5, lo + 2.0, 0.02)), "overlap"),
    ):
        with pytest.raises(InputError, match=expected):
            VariableRails(left=rails.left, right=rails.right, start_m=rails.start_m,
                          station_steps_m=parts)  # fmt: skip


def test_non_uniform_store_keeps_the_plain_rail_once():
    """The whole turnout with a finer crossing: the plain stretch between the panels (and the
    side without a switch panel up to the check rail) reads one row per side, as uniform.
    Not filtered (named: the shipped default filters over 12 mm): with 0.5 m stations a plain
    station next to a panel's last station reads a little of that station's table through the
    interpolant between them (the filter's one-table window: tests/test_sc_filter.py); the
    sharing of the store is what is checked."""
    sets = ["turnout.station_step=0.5 m", "turnout.crossing_station_step=0.25 m",
            "turnout.contact_filter=0 mm"]  # fmt: skip
    track = load_track(TURNOUT, sets)
    rails = track.variable_rails
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
    fields = sc_kernel_fields(rails, geometry, 5.0e-4)
    x = fields["sc_stations"]
    assert fields["sc_step"] == 0.0 and x.size == fields["sc_index"].shape[0]
    route_side = next(p for p in rails.sides() if p is not None and len(p.panels) == 2)
    switch_end = rails.start_m + route_side.panels[0].range_m[1]  # facing: the toe first
    crossing_start = rails.station_steps_m[0][0]
    plain = (x > switch_end + 0.5) & (x < crossing_start - 0.5)
    assert plain.sum() > 10
    for k in range(2):
        if fields["sc_side"][k] >= 0:
            assert np.unique(fields["sc_index"][plain, k]).size == 1
    assert fields["sc_tab"].shape[0] < 0.5 * 2 * x.size


def test_turnout_with_too_many_stations_refused(tmp_path):
    """1 mm stations (the smallest the turnout takes) over its 27 m zone: about 27 000
    stations, refused naming the turnout's step keys before any table is built."""
    with pytest.raises(InputError) as err:
        load_track(TURNOUT, ["turnout.station_step=1 mm"])
    assert "at most 5000" in str(err.value) and "turnout" in str(err.value)
