"""The contact filter of the station tables along the track (issue 29, ``railexu.model.sc_filter``).

References outside the code under test:

- the box average of the piecewise-linear interpolant through uniform stations ``h`` apart over
  a window ``L = h`` is the quadratic B-spline: weights ``(1/8, 3/4, 1/8)``; over ``L = 2 h``
  ``(1/4, 1/2, 1/4)`` (integrals of hat functions, by hand);
- moments: the weights sum to 1, reproduce a linear function at the station (a box centred on
  it averages a line to its centre value) and give ``x_i^2 + L^2 / 12 + h^2 / 6`` for ``x^2``
  (the box's variance ``L^2 / 12`` plus the mean of the linear interpolant's error over whole
  intervals, ``h^2 / 6``) where ``L`` is a multiple of ``h``;
- a kink of the rail's slope along the track (the ruled surface between slices: ``alpha``
  rad at ``s_k``, between stations) has the box-filtered height of closed form
  ``alpha (s + L/2 - s_k)^2 / (2 L)`` across it: the linear blend of the filtered stations
  converges to it as ``step^2`` (within ``0.3 alpha / L step^2``, measured 0.16-0.25, for
  kinks anywhere between stations), and its slope jumps at the stations by at most
  ``alpha step / L`` (a C1 surface sampled); without the filter the blend's error is
  ``alpha step / 4`` (first order) and its slope jumps by ``alpha / 2`` or more (the kink
  resolved over one station interval);
- the same through the table pipeline (slices of the track's rail raised along a ruled ramp of
  30 mrad, stations every 4, 2, 1 mm, no effective section): the blended height against the
  ramp's box average by quadrature, 10.0 / 1.25 / 0.32 um (0.25 / 0.13 / 0.13 ``alpha / L
  step^2``); unfiltered with the kinks on stations, the ramp itself within 10 nm;
- a window of one table (a uniform zone, the plain rail between panels) keeps that table to the
  last bit; a filtered table's base columns are the weights' combination and its bound columns
  the envelope (a bound of a convex combination);
- the filter at the wheelset (the default since hG, ``forces.filter_weight``,
  ``forces._filter_station``): the box of the piecewise-linear interpolant centred on any ``s``
  has the weights ``(1/L) int phi_j`` in closed form (the hat functions' integrals): at a
  station the station's filtered weights above; non-negative, summing to 1, a line reproduced
  (the box a linear functional), continuous derivatives in ``s`` (C1: the slope
  ``(PL(s + L/2) - PL(s - L/2)) / L``), where the first form's linear blend jumps; through the
  table pipeline the same ramp's box average as the first form, within the same bound.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest
from sc_store_view import store_view

from railexu.contact import kernel as K
from railexu.errors import InputError
from railexu.model import forces
from railexu.model.forces import filter_weight
from railexu.model.sc_filter import filter_weights, filtered_index, filtered_tables
from railexu.model.sc_tables import filter_windows
from railexu.track.variable_rails import VariableRails


def _as_array(w: dict[int, float], n: int) -> np.ndarray:
    out = np.zeros(n)
    for j, v in w.items():
        out[j] = v
    return out


def test_weights_are_the_quadratic_b_spline_and_its_wider_box():
    x = np.arange(21) * 0.005
    w = _as_array(filter_weights(x, 0.005)[10], x.size)
    assert np.allclose(w[9:12], [1 / 8, 3 / 4, 1 / 8], atol=1e-12)
    assert abs(w.sum() - 1.0) < 1e-12 and np.count_nonzero(w) == 3
    w = _as_array(filter_weights(x, 0.010)[10], x.size)
    assert np.allclose(w[9:12], [1 / 4, 1 / 2, 1 / 4], atol=1e-12)
    # no filter: the station itself
    assert filter_weights(x, 0.0)[7] == {7: 1.0}


@pytest.mark.parametrize("length_m", [0.012, 0.02, 0.035])
def test_weights_moments_on_stations_that_are_not_uniform(length_m):
    rng = np.random.default_rng(5)
    x = np.cumsum(rng.uniform(0.003, 0.02, 60))
    for i, w in enumerate(filter_weights(x, length_m)):
        a = _as_array(w, x.size)
        assert abs(a.sum() - 1.0) < 1e-12 and a.min() >= 0.0
        if x[0] + length_m < x[i] < x[-1] - length_m:  # away from the ends (constant there)
            assert abs(a @ x - x[i]) < 1e-14
    # uniform stations, L a multiple of h: x^2 -> x_i^2 + L^2 / 12 + h^2 / 6
    h = 0.005
    x = np.arange(41) * h
    for m in (1, 2, 4):
        a = _as_array(filter_weights(x, m * h)[20], x.size)
        assert abs(a @ x**2 - (x[20] ** 2 + (m * h) ** 2 / 12 + h**2 / 6)) < 1e-15


def _kink_errors(step_m: float, length_m: float, alpha: float = 0.03, s_k: float = 0.0437):
    """The linear blend of the (filtered) station values of ``alpha max(0, s - s_k)`` against
    the closed-form box average over ``length_m`` (the kink itself for ``length_m = 0``): the
    largest height error [m] and the largest slope jump at a station [rad]."""
    x = np.arange(0.0, 0.1 + 0.5 * step_m, step_m)
    f = alpha * np.maximum(0.0, x - s_k)
    g = np.array([sum(v * f[j] for j, v in w.items()) for w in filter_weights(x, length_m)])
    s = np.linspace(0.02, 0.07, 5001)
    blend = np.interp(s, x, g)
    if length_m > 0.0:
        u = np.clip(s + 0.5 * length_m - s_k, 0.0, length_m)
        exact = alpha * (u**2 / (2 * length_m) + np.maximum(0.0, s - 0.5 * length_m - s_k))
    else:
        exact = alpha * np.maximum(0.0, s - s_k)
    slopes = np.diff(g) / np.diff(x)
    inner = (x[1:-1] > 0.02) & (x[1:-1] < 0.07)
    return float(np.max(np.abs(blend - exact))), float(np.max(np.abs(np.diff(slopes))[inner]))


def test_filtered_blend_converges_as_step_squared_across_a_kink():
    alpha, length = 0.03, 0.012  # a 30 mrad slope jump (the wing rail's rise), a 12 mm box
    steps = np.array([0.004, 0.002, 0.001, 0.0005, 0.00025])
    kinks = (0.0401, 0.0423, 0.0437, 0.045)  # anywhere between stations, or on one
    err = np.array([[_kink_errors(h, length, alpha, k) for k in kinks] for h in steps])
    # second order: within 0.3 (alpha / L) step^2 (measured 0.16-0.25), fitted order 1.8-2.2
    assert np.all(err[:, :, 0] <= 0.3 * alpha / length * steps[:, None] ** 2)
    order = np.polyfit(np.log(steps), np.log(err[:, :, 0].max(axis=1)), 1)[0]
    assert 1.8 < order < 2.2
    # C1 sampled: the slope jumps at the stations are step x F'' at most (F'' <= alpha / L)
    assert np.all(err[:, :, 1] <= alpha * steps[:, None] / length * (1 + 1e-9))
    # without the filter: the kink within one interval, first order (alpha step theta (1 -
    # theta) at the kink's fraction theta of the interval: alpha step / 4 at its middle), and
    # the slope jumps by at least alpha / 2 at a station
    for h in steps:
        raw = [_kink_errors(h, 0.0, alpha, 0.04 + th * h) for th in (0.25, 0.5, 0.75)]
        assert abs(max(e for e, _ in raw) / (alpha * h / 4) - 1) < 0.05  # sampled every 10 um
        assert min(j for _, j in raw) >= 0.5 * alpha * (1 - 1e-9)


def _tables(n: int, rows: int = 6, seed: int = 0) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [rng.normal(size=(rows, K.N_TABLE_COLUMNS)) for _ in range(n)]


def test_filtered_tables_combine_base_columns_and_envelope_bounds():
    source = _tables(4)
    index = np.array([0, 0, 0, 0, 1, 2, 3, 3, 3, 3], dtype=np.int64)  # 0 and 3: plain stretches
    x = np.arange(index.size) * 0.01
    weights = filter_weights(x, 0.012)
    new, keys = filtered_index(index, weights)
    assert new[0] == new[1] == new[2] and new[-1] == new[-2] == new[-3]  # windows of one table
    out = dict(filtered_tables(iter(enumerate(source)), keys))
    assert sorted(out) == list(range(len(keys)))
    assert out[new[0]] is source[0] and out[new[-1]] is source[3]  # to the last bit
    first = K.T_SLOPE_MAX
    mins = [c for c in range(first, K.N_TABLE_COLUMNS) if (c - first) % 4 == 1]
    maxs = [c for c in range(first, K.N_TABLE_COLUMNS) if (c - first) % 4 != 1]
    for i in range(index.size):
        w = weights[i]
        base = sum(v * source[index[j]][:, :first] for j, v in w.items())
        t = out[new[i]]
        assert np.allclose(t[:, :first], base, rtol=0, atol=1e-14)
        used = [source[index[j]] for j in w]
        assert np.array_equal(t[:, mins], np.min([a[:, mins] for a in used], axis=0))
        assert np.array_equal(t[:, maxs], np.max([a[:, maxs] for a in used], axis=0))


def test_contact_filter_length_is_checked():
    with pytest.raises(InputError, match="contact_filter_m"):
        VariableRails(left=object(), contact_filter_m=-0.001)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="contact_filter_m"):
        VariableRails(left=object(), contact_filter_m=float("nan"))  # type: ignore[arg-type]


def test_uniform_zone_filtered_is_the_plain_zone():
    """A zone whose slices are all the track's rail: the filtered station store equals the
    unfiltered one within rounding (every station's table is the same rail; the weights sum
    to 1), so the uniform zone still runs as plain track (tests/test_sc_dynamics.py)."""
    from dataclasses import replace
    from pathlib import Path

    from uniform_zone import uniform_zone

    from railexu.model.assembly import wheelset_geometry
    from railexu.model.sc_tables import sc_kernel_fields
    from railexu.track.track import ideal_straight_track
    from railexu.vehicle.vehicle import load_vehicle

    vehicle = load_vehicle(Path(__file__).resolve().parents[1] / "vehicles" / "wheelset.yaml")
    track = ideal_straight_track()
    zone = replace(uniform_zone(track, station_step_m=0.02), contact_filter_m=0.0)
    geometry = wheelset_geometry(vehicle.wheelsets[0], track)
    width = vehicle.contact.curvature_smoothing_m
    a = sc_kernel_fields(zone, geometry, width)
    b = sc_kernel_fields(replace(zone, contact_filter_m=0.012), geometry, width)
    for side in range(2):
        ta = a["sc_tab"][a["sc_index"][:, side]][:, :, : K.T_SLOPE_MAX]
        tb = b["sc_tab"][b["sc_index"][:, side]][:, :, : K.T_SLOPE_MAX]
        ok = np.isfinite(ta)
        assert np.array_equal(ok, np.isfinite(tb))
        assert np.max(np.abs(ta[ok] - tb[ok])) < 1e-9 * max(1.0, np.max(np.abs(ta[ok])))


_RAMP_START_M = 5.0


def _ramp_zone_fields(
    step_m: float, filter_m: float, rise_m: float = 0.0015, at_stations: bool = False,
    own: bool = False,
):  # fmt: skip
    """The kernel fields of :func:`_ramp_zone_heights`' zone (``own``: and each station's own
    table, ``(n_stations, M, C)``, as computed before the store's bounds envelope others)."""
    from pathlib import Path

    from railexu.model.assembly import wheelset_geometry
    from railexu.model.sc_tables import sc_kernel_fields, station_table_set
    from railexu.profiles import rail_profile
    from railexu.profiles.variable import VariableProfile
    from railexu.profiles.variable.slices import ProfileSlices
    from railexu.track.track import ideal_straight_track
    from railexu.vehicle.vehicle import load_vehicle

    track = ideal_straight_track()
    vehicle = load_vehicle(Path(__file__).resolve().parents[1] / "vehicles" / "wheelset.yaml")
    rail = rail_profile(track.rail_profile)
    y = np.arange(rail.y_min, rail.y_max, 5e-5)
    flat = np.column_stack([y, -rail.height(y)])
    raised = flat - np.array([0.0, rise_m])  # z down: raised by rise_m
    profile = VariableProfile(
        ProfileSlices("ramp", np.array([0.0, 0.05, 0.1, 0.15]), (flat, flat, raised, raised),
                      None, (None,) * 4, ("60E1",))
    )  # fmt: skip
    rails = VariableRails(left=profile, start_m=_RAMP_START_M, station_step_m=step_m, x_max_m=0.0,
                          contact_filter_m=filter_m)  # fmt: skip
    geometry = wheelset_geometry(vehicle.wheelsets[0], track)
    fields = sc_kernel_fields(
        rails, geometry, vehicle.contact.curvature_smoothing_m, filter_at_stations=at_stations
    )
    if not own:
        return fields
    tables, index, _ = station_table_set(
        profile, geometry.pairs[0], rails.stations_m() - rails.start_m, x_max_m=0.0,
        curvature_smoothing_m=vehicle.contact.curvature_smoothing_m,
    )  # fmt: skip
    distinct = dict(tables)
    return fields, np.stack([distinct[int(t)] for t in index])


def _ramp_zone_heights(
    step_m: float, filter_m: float, rise_m: float = 0.0015, at_stations: bool = False
):
    """A 0.15 m zone of the track's rail whose slices at s = 0, 0.05, 0.1, 0.15 m are the
    rail, the rail and the rail raised by ``rise_m`` twice (the ruled surface between them:
    slope 0, ``rise_m / 0.05``, 0: kinks at 0.05 and 0.1 m), with no effective section
    (``x_max_m = 0``: the table is the surface itself): ``s`` [m, from the zone's start] over
    0.02-0.13 m and the table's height at the rail's top there minus the plain rail's [m]:
    the contact filter at ``s`` (:func:`railexu.model.forces.filter_weight`, the default) or,
    ``at_stations``, the filtered stations blended linearly (the first form)."""
    f = _ramp_zone_fields(step_m, filter_m, rise_m, at_stations)
    heights = f["sc_tab"][f["sc_index"][:, 0]][:, :, 0]
    row = int(np.nanargmax(heights[0]))  # the rail's top
    x = f["sc_stations"] - _RAMP_START_M
    s = np.linspace(0.02, 0.13, 2201)
    top = heights[:, row] - heights[0, row]
    if f["sc_filter"] == 0.0:
        return s, np.interp(s, x, top)
    assert f["sc_filter"] == filter_m
    w = np.array([[filter_weight(x, j, v, filter_m) for j in range(x.size)] for v in s])
    return s, w @ top


def test_filtered_ramp_of_slices_converges_to_the_box_average():
    """Through the table pipeline (slices -> station tables -> filter -> linear blend): the
    blended height along a ruled ramp against its box average computed here by quadrature of
    the known ramp (``rise clip((s - 0.05) / 0.05, 0, 1)`` averaged over 12 mm; the slices'
    raise is in the rail's axes, inclined 1:40 on the track: ``rise cos(atan(1/40))`` in the
    track's vertical). Unfiltered with the kinks on stations (2 and 1 mm) the blend is the
    ramp itself within 10 nm."""
    rise, length = 0.0015, 0.012  # 30 mrad along the track, a 12 mm filter
    vertical = rise * np.cos(np.arctan(1 / 40))
    ramp = lambda u: vertical * np.clip((u - 0.05) / 0.05, 0.0, 1.0)  # noqa: E731
    u = np.linspace(-0.5, 0.5, 4001) * length
    steps = (0.004, 0.002, 0.001)
    alpha = rise / 0.05
    for at_stations in (True, False):
        errors = []
        for h in steps:
            s, blend = _ramp_zone_heights(h, length, rise, at_stations)
            exact = np.array([np.trapezoid(ramp(v + u), u) / length for v in s])
            errors.append(np.max(np.abs(blend - exact)))
        for h, e in zip(steps, errors, strict=True):
            assert e <= 0.3 * alpha / length * h**2  # as the kink above (measured 0.16-0.25)
        assert errors[0] / errors[2] > 8.0  # second order over two halvings
    s, blend = _ramp_zone_heights(0.002, 0.0, rise)
    assert np.max(np.abs(blend - ramp(s))) < 1e-8


def test_turnout_key_sets_the_filter_and_refuses_a_bad_length():
    from railexu.track.track import load_track

    track = load_track("turnout_uk_r245_diverging_facing", ["turnout.contact_filter=12 mm"])
    assert track.variable_rails.contact_filter_m == pytest.approx(0.012)
    assert load_track("turnout_uk_r245_diverging_facing").variable_rails.contact_filter_m == 0.012
    off = load_track("turnout_uk_r245_diverging_facing", ["turnout.contact_filter=0 mm"])
    assert off.variable_rails.contact_filter_m == 0.0
    with pytest.raises(InputError, match="contact_filter"):
        load_track("turnout_uk_r245_diverging_facing", ["turnout.contact_filter=-1 mm"])


def _weights_at(x: np.ndarray, s: float, length: float) -> np.ndarray:
    return np.array([filter_weight(x, j, s, length) for j in range(x.size)])


def test_filter_at_the_wheel_against_the_stations_closed_form():
    """The contact filter at the wheelset's position (:func:`forces.filter_weight`, the
    kernel's): at a station the same weights as the station's filtered table
    (:func:`filter_weights`, the trapezoid rule) within 1e-14; everywhere non-negative, summing
    to 1 within 1e-14, a line reproduced within 1e-14 away from the zone's ends (the filter's
    box a linear functional), inside the interval's window (:func:`filter_windows`); C1 along
    the track: the one-sided derivatives of every weight at each station and at each
    ``station +- L/2`` (where the box's ends cross a station) agree within 1e-5 of ``1/L``,
    where the linear blend of the filtered stations (the first form) jumps by more than
    ``1/L``; random stations 4-30 mm apart."""
    rng = np.random.default_rng(7)
    x = np.cumsum(np.r_[0.0, rng.uniform(0.004, 0.03, 25)])
    length = 0.012
    reference = filter_weights(x, length)
    for i in range(x.size):
        expected = np.zeros(x.size)
        for j, v in reference[i].items():
            expected[j] = v
        assert np.max(np.abs(_weights_at(x, x[i], length) - expected)) < 1e-14
    windows = filter_windows(x, length)
    for s in np.linspace(x[0], x[-1], 1501):
        w = _weights_at(x, s, length)
        assert w.min() >= 0.0 and abs(w.sum() - 1.0) < 1e-14
        i = min(int(np.searchsorted(x, s, side="right")) - 1, x.size - 2)
        nonzero = np.nonzero(w)[0]
        assert windows[i, 0] <= nonzero.min() and nonzero.max() <= windows[i, 1]
        if x[0] + length / 2 <= s <= x[-1] - length / 2:
            assert abs(w @ (3.0 * x - 0.2) - (3.0 * s - 0.2)) < 1e-14
    eps = 1e-6  # one-sided second-order differences: exact on the weights' quadratic pieces
    for p in np.concatenate([x[2:-2], x[2:-2] + length / 2, x[2:-2] - length / 2]):
        at = [_weights_at(x, p + k * eps, length) for k in (-2, -1, 0, 1, 2)]
        left = (3.0 * at[2] - 4.0 * at[1] + at[0]) / (2.0 * eps)
        right = (-3.0 * at[2] + 4.0 * at[3] - at[4]) / (2.0 * eps)
        assert np.max(np.abs(left - right)) < 1e-5 / length
    # the linear blend of the filtered stations (the first form) has slope jumps there
    w_mid = np.array([[reference[i].get(j, 0.0) for j in range(x.size)] for i in range(x.size)])
    i = 10
    left = (w_mid[i] - w_mid[i - 1]) / (x[i] - x[i - 1])
    right = (w_mid[i + 1] - w_mid[i]) / (x[i + 1] - x[i])
    assert np.max(np.abs(left - right)) > 1.0 / length


def test_filter_windows_of_a_uniform_grid():
    """The stations an interval's filter reads: 10 mm stations and a 12 mm box reach one
    station beyond each end of the interval (``x_i - 6 mm`` lies in the interval before),
    50 mm stations the same (the box's halves shorter than a step); no filter: the pair."""
    x = 0.01 * np.arange(8)
    w = filter_windows(x, 0.012)
    assert w[3].tolist() == [2, 5] and w[0].tolist() == [0, 2] and w[-1].tolist() == [6, 7]
    assert filter_windows(0.05 * np.arange(8), 0.012)[3].tolist() == [2, 5]
    assert filter_windows(x, 0.0)[3].tolist() == [3, 4]
    assert filter_windows(0.005 * np.arange(8), 0.012)[3].tolist() == [1, 6]


#: Compiled here without numba's cache (as tests/test_sc_stations.py: a cached overload for this
#: module's type could not be loaded by other processes).
_filter_station = numba.njit(**{k: v for k, v in K.JIT_NO_REFCOUNT.items() if k != "cache"})(
    forces._filter_station.py_func
)


def test_kernel_filter_is_the_weighted_store_with_enveloping_bounds():
    """The compiled filter at the wheelset (``forces._filter_station``) on a zone's store
    (the ruled 30 mrad ramp of slices, 4 mm stations, the 12 mm filter): its base columns are
    ``sum_j w_j(s)`` of the stations' tables within 1e-12 of the columns' scale (summation
    order), at 300 positions across the zone and at every station; the bound columns the kernel
    reads are row ``i``'s of the store (not copied into the cache), which envelope every
    station of the interval's window (largest |slope|, largest curvature and change at least
    theirs, smallest curvature at most): valid for any convex combination the interval reads,
    so the kernel's search is exact with them."""
    fields, station = _ramp_zone_fields(0.004, 0.012, own=True)
    assert fields["sc_filter"] == 0.012
    d = store_view(fields)
    x = d.sc_stations
    first = K.T_SLOPE_MAX
    store = fields["sc_tab"][fields["sc_index"][:, 0]]  # the row each station reads
    assert np.array_equal(store[:, :, :first], station[:, :, :first])  # its own base columns
    maxs = [c for c in range(first, station.shape[2]) if (c - first) % 4 != 1]
    mins = [c for c in range(first, station.shape[2]) if (c - first) % 4 == 1]
    points = np.concatenate([np.linspace(x[0], x[-1], 300), x])
    for s in points:
        i = min(int(np.searchsorted(x, s, side="right")) - 1, x.size - 2)
        _filter_station(d, 0, i, float(s), 0)
        got = d.sc_cache[0, 0]
        w = np.array([filter_weight(x, j, float(s), 0.012) for j in range(x.size)])
        expected = np.tensordot(w, station[:, :, :first], axes=1)
        scale = np.max(np.abs(station[:, :, :first]), axis=(0, 1))
        assert np.all(np.abs(got[:, :first] - expected) <= 1e-12 * scale)
        assert got.shape[1] == first  # the cache holds the base columns only
        bounds = fields["sc_tab"][fields["sc_index"][i, 0]]  # the kernel reads row i's
        lo, hi = fields["sc_window"][i]
        window = station[lo : hi + 1]
        assert np.all(bounds[:, maxs] >= window[:, :, maxs].max(axis=0))
        assert np.all(bounds[:, mins] <= window[:, :, mins].min(axis=0))
