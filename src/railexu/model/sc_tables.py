"""The kernel data of a switch-and-crossing zone: rail tables at stations along it (issue 29).

For a track with :class:`~railexu.track.variable_rails.VariableRails`, the stations
(:meth:`~railexu.track.variable_rails.VariableRails.stations_m`: ``start + i step``, or the
union of uniform grids of parts with their own step) cover the zone; each side with a variable
profile gets the kernel table of its effective section at every station
(:func:`railexu.contact.variable_tables.station_tables`, placed on that side's rail like the
track's rail profile). :mod:`railexu.model.forces` blends the two stations around a wheelset
linearly. The effective section depends on the wheel's radius: the first wheelset's wheels are
used for all (a vehicle's wheels usually share profile and radius). Memory: ``n_distinct x rows
x columns x 8`` bytes, one row per station and side whose table (with its neighbour's bounds) is
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
    station's own (the same numbers: for checks and the benchmark's "before")."""
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
        if rails.contact_filter_m > 0.0:  # the contact filter along the track (sc_filter)
            index, keys = filtered_index(index, filter_weights(stations, rails.contact_filter_m))
            tables = _InOrder(lambda source=tables, keys=keys: filtered_tables(source, keys))
        if not share_rows:  # every station its own row
            tables = _per_station(tables, index)
            index = np.arange(index.size, dtype=np.int64)
        side_index[k] = len(sets)
        sets.append((k, tables, index, int(info[2])))
        infos[k] = info
    rows = max(m for _, _, _, m in sets)
    table, station_rows = envelope_rows(sets, rows, stations.size)
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
    }


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


def envelope_rows(sets: list[tuple], rows: int, n_stations: int) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's station store: ``(n_rows, rows, columns)`` tables and ``(n_stations, 2)``
    the row each station and side reads (-1: no variable profile on that side).

    Station ``i``'s row is its table with bound columns enveloping stations ``i`` and
    ``i + 1`` (:func:`pair_envelope_bounds`), so it depends on the pair of their distinct
    tables only: one row per distinct pair (the plain stretch between panels: one row).

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
    keys: list[tuple[int, int, int]] = []  # (position in sets, table i, table i + 1)
    for j, (side, _, index, *_) in enumerate(sets):
        seen: dict[tuple[int, int], int] = {}
        for i in range(n_stations):
            key = (int(index[i]), int(index[i + 1]) if i + 1 < n_stations else -1)
            if key not in seen:
                seen[key] = len(keys)
                keys.append((j, *key))
            station_rows[i, side] = seen[key]
    out = np.empty((len(keys), rows, K.N_TABLE_COLUMNS))
    for j, (_, tables, _, *_) in enumerate(sets):
        rows_of: dict[int, list[int]] = {}  # the rows that read each table
        for r, (jj, a, b) in enumerate(keys):
            if jj == j:
                for t in {a, b} - {-1}:
                    rows_of.setdefault(t, []).append(r)
        waiting = {t: len(rs) for t, rs in rows_of.items()}  # rows not yet written, per table
        alive: dict[int, np.ndarray] = {}
        items = enumerate(tables) if isinstance(tables, np.ndarray) else tables
        for number, table in items:
            alive[number] = table
            for r in rows_of.get(number, []):
                jj, a, b = keys[r]
                if jj == j and a in alive and (b < 0 or b in alive):
                    _write_row(out[r], alive[a], alive[b] if b >= 0 else None)
                    for t in {a, b} - {-1}:
                        waiting[t] -= 1
                    keys[r] = (-1, a, b)  # written
            for t in [t for t in alive if waiting.get(t, 0) <= 0]:
                del alive[t]
    return out, station_rows


def _write_row(out: np.ndarray, a: np.ndarray, b: np.ndarray | None) -> None:
    """Station table ``a`` (padded with its last row) with bounds enveloping ``b``'s."""
    m = a.shape[0]
    out[:m] = a
    out[m:] = a[-1]
    if b is not None:
        pair = np.empty((2, 1, *out.shape))
        pair[0, 0] = out
        pair[1, 0, : b.shape[0]] = b
        pair[1, 0, b.shape[0] :] = b[-1]
        pair_envelope_bounds(pair)
        out[:] = pair[0, 0]


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
