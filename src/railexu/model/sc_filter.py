"""The contact filter of a switch-and-crossing zone's station tables along the track (issue 29).

The rails of a crossing between its slices are ruled surfaces (each point moves linearly in
``s`` from one slice to the next, docs/switches-and-crossings.md, "Interpolation between
slices"): their slope along the track jumps at every slice where the rate of change does, and
where an edge moves laterally (the wing rail's raised field side) the height at a fixed lateral
position rises by tens of mrad within a few millimetres. The effective section keeps such a
slope jump as a kink of the wheel's path (a rigid circle touching a kinked surface), and the
stations' linear blend resolves each kink over one station interval: the force of the wheel
meeting it depends on the station step (the loaded Hbbins' wing-rail peak through the
diverging facing turnout: 243 / 224 / 246 kN at 20 / 10 / 5 mm crossing stations and 0.2 ms;
with a 12 mm filter 221.3 / 224.8 / 223.9 kN at 10 / 5 / 2.5 mm, docs/switches-and-crossings.md,
the turnout's "Cost").

A real contact patch is 10-15 mm long and averages the rail's geometry over its length: the
*contact filter* of rail roughness (Remington, J. Acoust. Soc. Am. 81 (1987) 1805-1823;
Thompson, Railway Noise and Vibration, Elsevier 2009, sec. 5.5). railexu's assumption: the
wheel reads the effective section averaged along the track over a window of stated length
``L`` (``VariableRails.contact_filter_m``), a box centred on the wheelset, of the
piecewise-linear interpolant through the stations (constant beyond the zone's ends).

**At the wheelset** (the default since issue 29's hG, 2026-12-08): the kernel evaluates this
box average at the wheelset's own position ``s``,
``sum_j w_j(s) station_j`` with ``w_j(s) = (1/L) int_{s-L/2}^{s+L/2} phi_j``
(:func:`railexu.model.forces.filter_weight`, ``forces._filter_station``): a convex combination
(the bound columns of the rows enveloping each interval's stations stay valid,
:func:`railexu.model.sc_tables.filter_windows`), C1 along the track, and nothing but the box:
the effective filter is the ``L`` box of the stations' interpolant at every ``s``.

**At the stations** (the first form, ``sc_kernel_fields(..., filter_at_stations=True)``): each
station's table is the box average centred on the station (:func:`filter_weights`,
:func:`filtered_index`, :func:`filtered_tables`) and the kernel blends two stations linearly.
Each filtered table is a convex combination of the stations' tables, so its base columns
(height, slope, curvatures, all linear in the surface) are the same combination and its
curvature-bound columns the envelope of theirs (a bound of a convex combination is at most the
combination of the bounds: :func:`railexu.model.sc_tables.pair_envelope_bounds`). The linear
blend of filtered samples keeps slope jumps along the track at the stations of about ``h / L``
of the slices' own (``h`` the station step): with ``h = 10 mm`` and ``L = 12 mm`` little is
smoothed, and the crossing's peaks at 10 mm were 3-9 % below their 2.5 mm values (the nose, the
diverging route trailing's 0-1 m window; docs/switches-and-crossings.md, the turnout's "Cost").
With stations much finer than ``L`` both forms are the filtered surface to ``O(step^2)``; with
``L = 0`` nothing is filtered. A window holding one table only (a uniform zone, the plain rail
between a turnout's panels) keeps that table to the last bit in both.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

import numpy as np

from railexu.contact import kernel as K

#: Weights below this are dropped (and the rest renormalised): a station whose hat function
#: touches the window at a single point [1].
_TINY = 1.0e-12


def filter_weights(stations_m: np.ndarray, length_m: float) -> list[dict[int, float]]:
    """Per station ``i`` the weights ``{j: w_ij}`` (summing to 1) of the box average over
    ``[x_i - L/2, x_i + L/2]`` of the piecewise-linear interpolant through the stations
    ``x`` [m] (increasing; constant beyond the first and the last), ``L = length_m`` [m]:
    ``w_ij = (1/L) int phi_j(u) du``, ``phi_j`` the hat function of station ``j``. Exact:
    the trapezoid rule over the stations inside the window and its ends (the interpolant is
    linear between them). ``length_m <= 0``: ``{i: 1}``."""
    x = np.asarray(stations_m, dtype=float)
    n = x.size
    out: list[dict[int, float]] = []
    for i in range(n):
        if length_m <= 0.0 or n < 2:
            out.append({i: 1.0})
            continue
        a, b = x[i] - 0.5 * length_m, x[i] + 0.5 * length_m
        inner = x[(x > a) & (x < b)]
        points = np.concatenate(([a], inner, [b]))
        w: dict[int, float] = {}
        at = [_hat_weights(x, float(u)) for u in points]
        for k in range(points.size - 1):
            du = 0.5 * (points[k + 1] - points[k]) / length_m
            for end in (at[k], at[k + 1]):
                for j, v in end.items():
                    w[j] = w.get(j, 0.0) + du * v
        w = {j: v for j, v in w.items() if v > _TINY}
        total = sum(w.values())
        out.append({j: v / total for j, v in sorted(w.items())})
    return out


def _hat_weights(x: np.ndarray, u: float) -> dict[int, float]:
    """The interpolant's weights at ``u`` [m]: ``{k: 1 - t, k + 1: t}`` (constant outside)."""
    if u <= x[0]:
        return {0: 1.0}
    if u >= x[-1]:
        return {x.size - 1: 1.0}
    k = int(np.searchsorted(x, u, side="right")) - 1
    t = (u - x[k]) / (x[k + 1] - x[k])
    return {k: 1.0 - t, k + 1: t}


def filtered_index(
    index: np.ndarray, weights: list[dict[int, float]]
) -> tuple[np.ndarray, list[tuple]]:
    """The filtered stations' distinct tables: ``(new index, keys)``, ``keys[k]`` the
    ``((table, weight), ...)`` of filtered table ``k`` (numbered in the order of their first
    station, as :func:`railexu.contact.variable_tables.station_table_plan`), the weights of a
    window's stations that share a table summed; a window of one table is that table."""
    new = np.empty(index.size, dtype=np.int64)
    seen: dict[tuple, int] = {}
    keys: list[tuple] = []
    for i, w in enumerate(weights):
        merged: dict[int, float] = {}
        for j, v in w.items():
            t = int(index[j])
            merged[t] = merged.get(t, 0.0) + v
        key = (next(iter(merged)),) if len(merged) == 1 else tuple(sorted(merged.items()))
        if key not in seen:
            seen[key] = len(keys)
            keys.append(key)
        new[i] = seen[key]
    return new, keys


def filtered_tables(
    tables: Iterable[tuple[int, np.ndarray]], keys: list[tuple]
) -> Iterator[tuple[int, np.ndarray]]:
    """Yield ``(number, table)`` of each filtered table of ``keys`` (:func:`filtered_index`)
    in the order of their numbers, from the source tables ``(number, table)`` in the order of
    theirs; a source table is dropped when every filtered table that reads it is made."""
    uses: dict[int, int] = {}
    for key in keys:
        for t in _tables_of(key):
            uses[t] = uses.get(t, 0) + 1
    alive: dict[int, np.ndarray] = {}
    done = 0
    last = -1
    for number, table in tables:
        alive[number] = table
        last = max(last, number)
        while done < len(keys) and max(_tables_of(keys[done])) <= last:
            yield done, _combine(keys[done], alive, uses)
            done += 1
    while done < len(keys):
        yield done, _combine(keys[done], alive, uses)
        done += 1


def _tables_of(key: tuple) -> list[int]:
    """The source tables a filtered table's key reads."""
    return [key[0]] if len(key) == 1 else [t for t, _ in key]


def _combine(key: tuple, alive: dict[int, np.ndarray], uses: dict[int, int]) -> np.ndarray:
    """The convex combination of ``key``'s tables: base columns combined, bounds enveloped."""
    if len(key) == 1:
        out = alive[key[0]]
    else:
        first = K.T_SLOPE_MAX
        a0 = alive[key[0][0]]
        out = np.empty_like(a0)
        # the bound columns in groups of four: (largest |slope|, smallest z'', largest z'',
        # largest change), as :func:`railexu.model.sc_tables.pair_envelope_bounds` reads them
        groups = out[:, first:].reshape(out.shape[0], -1, 4)
        out[:, :first] = 0.0
        out[:, first:] = a0[:, first:]
        for t, w in key:
            a = alive[t]
            out[:, :first] += w * a[:, :first]
            g = a[:, first:].reshape(groups.shape)
            np.minimum(groups[..., 1], g[..., 1], out=groups[..., 1])
            np.maximum(groups[..., 0], g[..., 0], out=groups[..., 0])
            np.maximum(groups[..., 2:], g[..., 2:], out=groups[..., 2:])
    for t in _tables_of(key):
        uses[t] -= 1
        if uses[t] == 0:
            del alive[t]
    return out
