"""The kernel data of a switch-and-crossing zone: rail tables at stations along it (issue 29).

For a track with :class:`~railexu.track.variable_rails.VariableRails`, the stations
(:meth:`~railexu.track.variable_rails.VariableRails.stations_m`: ``start + i step``, or the
union of uniform grids of parts with their own step) cover the zone; each side with a variable
profile gets the kernel table of its effective section at every station
(:func:`railexu.contact.variable_tables.station_tables`, placed on that side's rail like the
track's rail profile). :mod:`railexu.model.forces` blends the two stations around a wheelset
linearly or, with the contact filter, combines the stations the filter's box at the wheelset
reads (:mod:`railexu.model.sc_filter`). The effective section depends on the wheel's radius:
the first wheelset's wheels are used for all (a vehicle's wheels usually share profile and
radius). Memory: ``n_distinct x rows x columns x 8`` bytes, one row per station and side whose
table (with its neighbours' bounds) is
not another's: the plain rail between a turnout's panels is one row (a 0.6 m zone at 10 mm with
a 150 mm wide crossing: ~ 40 MB).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.placement import WheelRailPair, WheelsetGeometry
from railexu.contact.variable_tables import (
    station_table_plan,
    station_tables_in_order,
    table_grid,
)
from railexu.model.sc_filter import filter_weights, filtered_index, filtered_tables
from railexu.profiles.variable import VariableProfile
from railexu.profiles.variable.zoned import ZonedProfile
from railexu.track.variable_rails import VariableRails


def sc_kernel_fields(
    rails: VariableRails | None,
    geometry: WheelsetGeometry,
    curvature_smoothing_m: float,
    n_wheelsets: int = 1,
    *,
    share_tables: bool = True,
    share_rows: bool = True,
    filter_at_stations: bool = False,
) -> dict:
    """The ``sc_*`` fields of :class:`railexu.model.forces.KernelData` (empty: no zone): the
    stations' track distances (``sc_stations``; ``sc_step`` their step if uniform, else 0), the
    distinct station tables with pair-envelope bounds (``sc_tab``, :func:`envelope_rows`),
    which of them each station and side reads (``sc_index``, -1: plain rail there) and each
    wheelset's blend cache (``sc_cache``: its blended base columns per side, the bound columns
    read by the kernel from station ``i``'s own row; ``sc_key``: the station ``i`` of its
    blend, -1 none; ``sc_t``: the blend fraction;
    ``sc_base``: the store's four base columns as their own contiguous array, which the blend
    reads at every new track position: 2.5 times faster than from the 28-column rows, for
    1/7 more memory).

    Stations with the same table (the plain rail between a turnout's panels) have it computed
    once (``share_tables``, :func:`railexu.contact.variable_tables.station_table_set`) and
    share one row of ``sc_tab`` (``share_rows``); ``False`` computes, or stores, each
    station's own (the same numbers: for checks and the benchmark's "before").

    The contact filter (``rails.contact_filter_m > 0``, :mod:`railexu.model.sc_filter`) is
    applied at the wheelset's position (``sc_filter``, ``sc_window``:
    :func:`railexu.model.forces.filter_weight`): the stored tables are the stations' own, each
    row's bounds enveloping the stations its interval's filter reads (:func:`filter_windows`).
    ``filter_at_stations``: the first form instead, each station's table filtered at the build
    and the two stations around the wheelset blended linearly (for the comparison of
    docs/switches-and-crossings.md, the turnout's "Cost")."""
    if rails is None:
        return {}
    stations = rails.stations_m()
    sets, infos, side_index = [], np.zeros((2, 3)), np.full(2, -1, dtype=np.int64)
    for k, (profile, pair) in enumerate(zip(rails.sides(), geometry.pairs, strict=True)):
        if profile is None:
            continue
        tables, index, info = station_table_set(
            profile, pair, stations - rails.start_m, rail_origin_m=rails.rail_origin_m,
            x_max_m=rails.x_max_m, curvature_smoothing_m=curvature_smoothing_m,
            share_plain=share_tables,
        )  # fmt: skip
        if rails.contact_filter_m > 0.0 and filter_at_stations:  # sc_filter's first form
            index, keys = filtered_index(index, filter_weights(stations, rails.contact_filter_m))
            tables = _InOrder(lambda source=tables, keys=keys: filtered_tables(source, keys))
        if not share_rows:  # every station its own row
            tables = _per_station(tables, index)
            index = np.arange(index.size, dtype=np.int64)
        side_index[k] = len(sets)
        sets.append((k, tables, index, int(info[2])))
        infos[k] = info
    rows = max(m for _, _, _, m in sets)
    at_wheel = rails.contact_filter_m > 0.0 and not filter_at_stations
    windows = filter_windows(stations, rails.contact_filter_m if at_wheel else 0.0)
    table, station_rows = envelope_rows(sets, rows, stations.size, windows)
    return {
        "sc_cache": np.zeros((n_wheelsets, len(sets), rows, K.T_SLOPE_MAX)),
        "sc_key": np.full((n_wheelsets, 2), -1, dtype=np.int64),
        "sc_t": np.full((n_wheelsets, 2), np.nan),
        "sc_start": float(stations[0]),
        # uniform: the blend's interval by division (the numbers of the uniform grid to the last
        # bit); 0: not uniform, by a binary search in sc_stations
        "sc_step": float(rails.station_step_m) if rails.uniform else 0.0,
        "sc_stations": np.ascontiguousarray(stations, dtype=float),
        "sc_tab": table,
        # the base columns on their own: the blend reads them at every new track position
        "sc_base": np.ascontiguousarray(table[:, :, : K.T_SLOPE_MAX]),
        "sc_index": station_rows,
        "sc_side": side_index,
        "sc_info": infos,
        # the contact filter at the wheelset's position (forces._filter_station); 0: linear
        "sc_filter": float(rails.contact_filter_m) if at_wheel else 0.0,
        "sc_window": windows,
    }


def filter_windows(stations_m: np.ndarray, length_m: float) -> np.ndarray:
    """Per interval ``i`` (``x_i <= s <= x_{i+1}``) the first and last station whose hat
    function can meet the contact filter's box ``[s - L/2, s + L/2]``, ``L = length_m`` [m]:
    ``(n, 2)`` int64, the last station's ``(n - 1, n - 1)``; ``L = 0``: ``(i, i + 1)``, the
    linear blend's pair. Station ``j`` meets the box where ``x_{j+1} > s - L/2`` and
    ``x_{j-1} < s + L/2`` (:func:`railexu.model.forces.filter_weight`)."""
    x = np.asarray(stations_m, dtype=float)
    n = x.size
    i = np.arange(n)
    nxt = np.minimum(i + 1, n - 1)
    # the largest j with x_j <= x_i - L/2, the smallest with x_j >= x_{i+1} + L/2
    lo = np.searchsorted(x, x - 0.5 * length_m, side="right") - 1
    hi = np.searchsorted(x, x[nxt] + 0.5 * length_m, side="left")
    out = np.empty((n, 2), dtype=np.int64)
    out[:, 0] = np.clip(np.minimum(lo, i), 0, n - 1)
    out[:, 1] = np.clip(np.maximum(hi, nxt), 0, n - 1)
    return out


def station_table_set(
    profile: VariableProfile | ZonedProfile, pair: WheelRailPair, stations_m: np.ndarray,
    **options,
) -> tuple[Iterable[tuple[int, np.ndarray]], np.ndarray, np.ndarray]:  # fmt: skip
    """One side's station tables as :func:`railexu.contact.variable_tables.station_table_set`
    gives them (``tables, index, info``), but ``tables`` computed as they are read: an iterable
    of ``(number, table)`` in station order (each pass computes them again), so that the store
    (:func:`envelope_rows`) is written without holding every table of the zone."""
    rail_origin_m = options.pop("rail_origin_m", None)
    x_max_m = options.pop("x_max_m", 0.06)
    share_plain = options.pop("share_plain", True)
    grid = table_grid(profile, pair, stations_m, rail_origin_m=rail_origin_m, x_max_m=x_max_m)
    index = station_table_plan(profile, stations_m, x_max_m=x_max_m, share_plain=share_plain)
    tables = _InOrder(
        lambda: station_tables_in_order(
            profile, pair, stations_m, index, grid, rail_origin_m=rail_origin_m,
            x_max_m=x_max_m, **options,
        )
    )  # fmt: skip
    return tables, index, np.array([grid[0], pair.rail_table.step_m, float(grid[1])])


class _InOrder:
    """A re-iterable over a generator function's items (each pass calls it again)."""

    def __init__(self, make: Callable[[], Iterator[tuple[int, np.ndarray]]]):
        self._make = make

    def __iter__(self) -> Iterator[tuple[int, np.ndarray]]:
        return self._make()


def _per_station(tables: Iterable[tuple[int, np.ndarray]], index: np.ndarray):
    """The distinct tables of ``tables`` as one per station, numbered by station."""
    stations_of: dict[int, list[int]] = {}
    for i, t in enumerate(index):
        stations_of.setdefault(int(t), []).append(i)
    for t, table in tables:
        for i in stations_of[t]:
            yield i, table


def envelope_rows(
    sets: list[tuple], rows: int, n_stations: int, windows: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's station store: ``(n_rows, rows, columns)`` tables and ``(n_stations, 2)``
    the row each station and side reads (-1: no variable profile on that side).

    Station ``i``'s row is its table with bound columns enveloping stations ``i`` and
    ``i + 1`` (:func:`pair_envelope_bounds`), so it depends on the pair of their distinct
    tables only: one row per distinct pair (the plain stretch between panels: one row). With
    ``windows`` (:func:`filter_windows`) the bounds envelope the stations ``windows[i, 0] ..
    windows[i, 1]`` instead, and a row is one per distinct station table and set of tables of
    its window.

    Memory: the store is allocated once and each row written when both its tables have been
    computed; a table is dropped when every row that reads it is written (a station's own
    table after its own and its predecessor's rows), so that beside the store only the shared
    tables and the last two are held (the tables of a whole zone, as large as the store, were
    held and copied twice before: 2.0 GB peak for the 0.42 GB store of the shipped crossing).

    Args:
        sets: per side ``(side, tables, table of each station[, rows of the side's grid])``:
            ``tables`` the distinct tables ``(n_tables, m, C)`` or ``(number, table)`` pairs
            in the order of their numbers (:func:`railexu.contact.variable_tables.
            station_tables_in_order`).
        rows: the common number of rows (a side's shorter grid padded with its last row: rows
            beyond a side's grid are never read).
        n_stations: the number of stations.
    """
    station_rows = np.full((n_stations, 2), -1, dtype=np.int64)
    # (position in sets, table i, the other tables its bounds envelope)
    keys: list[tuple[int, int, tuple[int, ...]]] = []
    for j, (side, _, index, *_) in enumerate(sets):
        seen: dict[tuple, int] = {}
        for i in range(n_stations):
            if windows is None:
                others = (int(index[i + 1]),) if i + 1 < n_stations else ()
            else:
                lo, hi = int(windows[i, 0]), int(windows[i, 1])
                others = tuple(sorted({int(t) for t in index[lo : hi + 1]} - {int(index[i])}))
            key = (int(index[i]), others)
            if key not in seen:
                seen[key] = len(keys)
                keys.append((j, *key))
            station_rows[i, side] = seen[key]
    out = np.empty((len(keys), rows, K.N_TABLE_COLUMNS))
    for j, (_, tables, _, *_) in enumerate(sets):
        rows_of: dict[int, list[int]] = {}  # the rows that read each table
        for r, (jj, a, others) in enumerate(keys):
            if jj == j:
                for t in {a, *others}:
                    rows_of.setdefault(t, []).append(r)
        waiting = {t: len(rs) for t, rs in rows_of.items()}  # rows not yet written, per table
        alive: dict[int, np.ndarray] = {}
        items = enumerate(tables) if isinstance(tables, np.ndarray) else tables
        for number, table in items:
            alive[number] = table
            for r in rows_of.get(number, []):
                jj, a, others = keys[r]
                if jj == j and a in alive and all(t in alive for t in others):
                    _write_row(out[r], alive[a], [alive[t] for t in others])
                    for t in {a, *others}:
                        waiting[t] -= 1
                    keys[r] = (-1, a, others)  # written
            for t in [t for t in alive if waiting.get(t, 0) <= 0]:
                del alive[t]
    return out, station_rows


def _write_row(out: np.ndarray, a: np.ndarray, others: list[np.ndarray]) -> None:
    """Station table ``a`` (padded with its last row) with bounds enveloping ``others``'."""
    m = a.shape[0]
    out[:m] = a
    out[m:] = a[-1]
    if not others:
        return
    first = K.T_SLOPE_MAX
    groups = out[:, first:].reshape(out.shape[0], -1, 4)  # a view: (|slope|, min z'', ...)
    padded = np.empty_like(out)
    for b in others:
        padded[: b.shape[0]] = b
        padded[b.shape[0] :] = b[-1]
        g = padded[:, first:].reshape(groups.shape)
        np.maximum(groups[..., 0], g[..., 0], out=groups[..., 0])
        np.minimum(groups[..., 1], g[..., 1], out=groups[..., 1])
        np.maximum(groups[..., 2:], g[..., 2:], out=groups[..., 2:])


def pair_envelope_bounds(tabs: np.ndarray) -> None:
    """Make station ``i``'s curvature-bound columns (``kernel.T_SLOPE_MAX`` on) bound the
    stations ``i`` and ``i + 1`` together (in place; ``tabs``: ``(n_stations, sides, M, C)``).

    Every bound column is a largest ``|slope|``, a smallest or a largest curvature, or a
    largest curvature change over a run of rows; of a blend ``(1 - t) a + t b`` each is bounded
    by the larger (smaller) of ``a``'s and ``b``'s. So the blend of the two stations needs only
    its four base columns blended, and station ``i``'s bounds serve for any ``t`` (looser
    bounds only prune less: the kernel's search result is the same).
    """
    first = K.T_SLOPE_MAX
    mins = [c for c in range(first, tabs.shape[3]) if (c - first) % 4 == 1]  # smallest z''
    maxs = [c for c in range(first, tabs.shape[3]) if (c - first) % 4 != 1]
    for i in range(tabs.shape[0] - 1):
        a, b = tabs[i], tabs[i + 1]
        a[..., maxs] = np.maximum(a[..., maxs], b[..., maxs])
        a[..., mins] = np.minimum(a[..., mins], b[..., mins])
