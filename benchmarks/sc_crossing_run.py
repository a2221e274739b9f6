"""Cost of a run over the whole UK crossing against the same run on plain track (issue 29).

Three measurements:

1. **Per call, the station-table blend** inside an S&C zone (model/forces.py; processor
   time): before (main up to d0e3487: every force evaluation blended all 28 columns of both
   stations' tables, per side with a variable profile), then (up to 05bea86: each wheelset
   kept its blended table, the bound columns, pair envelopes of two stations, copied when the
   wheelset passed a station, the four base columns re-blended from their own contiguous copy
   only when its track position changed, nothing when it did not: the solver's Newton
   iterations and its Jacobian's columns at one position) against now (the same without the
   bound columns' copy: the kernel reads them from the station's own row). Timed on the
   shipped crossing's tables of the left side (wing rail and nose) and of the right side (check
   rail), per call; a new station "hot" alternates two stations (their rows stay in the
   processor's caches), "cold" walks through every station of the store in turn (each row read
   from memory, as a run does: a ~1 GB store, 32 MB of L3 cache).
2. **Per call, the contact kernel** on plain rail and on the crossing's effective section with
   the wheel on nose and wing rail (``benchmarks/sc_contact.py``'s kernel_costs measures the
   same on CONTACT's short crossing).
3. **A run**: the wheelset at 10 m/s over the shipped ``uk_crossing_facing`` (2.0 m of it,
   s = -0.3 ... +1.7 m: the wing rail, the nose's start and landing, the check rail) against
   the same distance of straight plain track, wall times of building the model (the zone's
   station tables) and of integrating, and their ratio.

Run: ``python benchmarks/sc_crossing_run.py [--blend-only]`` (2 cores shared: timings vary
by tens of percent between runs; interleave and repeat before concluding; ``--blend-only``:
the first measurement alone).
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from typing import NamedTuple

import numba
import numpy as np

from railexu.contact import kernel as K
from railexu.model import forces
from railexu.model.assembly import wheelset_geometry
from railexu.model.sc_tables import sc_kernel_fields
from railexu.results.run import RunSettings, run
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle


@numba.njit(cache=True)
def _old_blend(tab, i, t, j, out):
    """main's blend (d0e3487): every column of station ``i`` and ``i + 1``."""
    a = tab[i, j]
    b = tab[i + 1, j]
    for r in range(out.shape[0]):
        for c in range(out.shape[1]):
            out[r, c] = a[r, c] + t * (b[r, c] - a[r, c])


@numba.njit(cache=True)
def _copy_blend(tab, base, cache, key, tcache, i, t, j):
    """model/forces.py's ``_blend_station`` up to 05bea86 on plain arrays (same loops; the base
    columns read from their own contiguous copy ``base``, as ``KernelData.sc_base``; the bound
    columns copied at a new station)."""
    out = cache[j]
    a = tab[i, j]
    if key[j] != i:
        for r in range(out.shape[0]):
            for c in range(K.T_SLOPE_MAX, out.shape[1]):
                out[r, c] = a[r, c]
        key[j] = i
        tcache[j] = np.nan
    if tcache[j] != t:
        a = base[i, j]
        b = base[i + 1, j]
        for r in range(out.shape[0]):
            for c in range(K.T_SLOPE_MAX):
                out[r, c] = a[r, c] + t * (b[r, c] - a[r, c])
        tcache[j] = t


@numba.njit(cache=True)
def _base_blend(tab, base, cache, key, tcache, i, t, j):
    """model/forces.py's ``_blend_station`` now on plain arrays: the four base columns only,
    when ``i`` or ``t`` changed (the kernel reads the bound columns from station ``i``'s row)."""
    if key[j] != i or tcache[j] != t:
        out = cache[j]
        a = base[i, j]
        b = base[i + 1, j]
        for r in range(out.shape[0]):
            for c in range(K.T_SLOPE_MAX):
                out[r, c] = a[r, c] + t * (b[r, c] - a[r, c])
        key[j] = i
        tcache[j] = t


@numba.njit(cache=True)
def _loop_old(n, tab, i, t, j, out):
    for k in range(n):
        _old_blend(tab, i, t + 1e-9 * (k % 2), j, out)
    return out[0, 0]


@numba.njit(cache=True)
def _loop_new(n, tab, base, cache, key, tcache, i, t, j, mode, copy):
    m = tab.shape[0] - 1
    for k in range(n):
        if mode == 0:  # one track position: Newton iterations, Jacobian columns
            ik, tk = i, t
        elif mode == 1:  # a new position every call, between the same stations
            ik, tk = i, t + 1e-9 * (k % 2)
        elif mode == 2:  # a new station every call, two in turn (hot)
            ik, tk = i + (k % 2), t
        else:  # a new station every call, walking through the store (cold)
            ik, tk = k % m, t
        if copy:
            _copy_blend(tab, base, cache, key, tcache, ik, tk, j)
        else:
            _base_blend(tab, base, cache, key, tcache, ik, tk, j)
    return cache[j, 0, 0]


def _best(f, repeat: int = 5) -> float:
    """Best processor time of the thread over ``repeat`` calls (on a shared machine the wall
    clock counts other processes' time)."""
    best = np.inf
    for _ in range(repeat):
        t0 = time.thread_time()
        f()
        best = min(best, time.thread_time() - t0)
    return best


def blend_costs(fields: dict, n: int = 2000) -> None:
    """Per call of the blend, before and now, per side's station tables."""
    # the per-station view of the store (rows read per station and side: model/sc_tables.py)
    sides = [k for k in range(2) if fields["sc_side"][k] >= 0]
    tab = np.stack([fields["sc_tab"][fields["sc_index"][:, k]] for k in sides], axis=1)
    print(f"station tables: {tab.shape[0]} stations x {tab.shape[1]} sides x {tab.shape[2]} rows "
          f"x {tab.shape[3]} columns ({tab.nbytes / 1e6:.0f} MB)")  # fmt: skip
    base = np.ascontiguousarray(tab[..., : K.T_SLOPE_MAX])
    i, t = tab.shape[0] // 2, 0.37
    for j, name in enumerate(("left (wing rail, nose)", "right (check rail)")[: tab.shape[1]]):
        out = np.zeros(tab.shape[2:])
        _loop_old(2, tab, i, t, j, out)
        old = _best(lambda: _loop_old(n, tab, i, t, j, out)) / n  # noqa: B023
        print(f"  {name:<24s} before (d0e3487) {old * 1e6:7.2f} us per call")
        for copy, label in ((True, "bound columns copied (05bea86)"), (False, "now")):
            cache = np.zeros((tab.shape[1], tab.shape[2], tab.shape[3] if copy else K.T_SLOPE_MAX))
            key = np.full(tab.shape[1], -1, dtype=np.int64)
            tcache = np.full(tab.shape[1], np.nan)
            _loop_new(2, tab, base, cache, key, tcache, i, t, j, 0, copy)
            new = [
                _best(lambda m=m, c=copy, x=cache, y=key, z=tcache, jj=j:
                      _loop_new(n, tab, base, x, y, z, i, t, jj, m, c)) / n
                for m in (0, 1, 2, 3)
            ]  # fmt: skip
            print(f"    {label:<31s} same position {new[0] * 1e6:6.3f} us, new position "
                  f"{new[1] * 1e6:6.2f} us, new station: hot {new[2] * 1e6:6.2f} us, cold "
                  f"{new[3] * 1e6:6.2f} us")  # fmt: skip


class _Zone(NamedTuple):
    """What model/forces.py's ``_blend_station`` and ``_filter_station`` read."""

    sc_stations: np.ndarray
    sc_index: np.ndarray
    sc_side: np.ndarray
    sc_tab: np.ndarray
    sc_base: np.ndarray
    sc_cache: np.ndarray
    sc_key: np.ndarray
    sc_t: np.ndarray
    sc_filter: float
    sc_window: np.ndarray


_FLAGS = {k: v for k, v in K.JIT_NO_REFCOUNT.items() if k != "cache"}
_blend_station = numba.njit(**_FLAGS)(forces._blend_station.py_func)
_filter_station = numba.njit(**_FLAGS)(forces._filter_station.py_func)


@numba.njit(cache=False)
def _loop_zone(n, d, i, s, t, side, mode, box):
    """``n`` calls of the linear blend (``box`` False) or the contact filter at the wheel:
    mode 0 one position, 1 a new position each call, 2 a new interval each call."""
    x = d.sc_stations
    for k in range(n):
        ii, ss, tt = i, s, t
        if mode >= 1:
            ss = s + 1e-9 * (k % 2)
            tt = t + 1e-9 * (k % 2)
        if mode == 2:
            ii = i + (k % 2)
            ss = x[ii] + t * (x[ii + 1] - x[ii])
        if box:
            _filter_station(d, 0, ii, ss, side)
        else:
            _blend_station(d, 0, ii, tt, side)
    return d.sc_cache[0, 0, 0, 0]


def filter_costs(fields: dict, n: int = 2000) -> None:
    """Per call and side, the store's blend as the kernel does it: the linear blend of two
    stations (``contact_filter_m = 0``, or the filter at the stations: its first form) against
    the contact filter at the wheelset's position (``sc_filter > 0``: 3-4 stations at 10 mm,
    4-5 at 5 mm), at one position, a new position, a new interval every call."""
    d = _Zone(**{k: fields[k] for k in _Zone._fields})
    x = d.sc_stations
    i = int(np.searchsorted(x, 0.5 * (x[0] + x[-1])))  # the zone's middle (the crossing)
    for t in (0.5, 0.05):
        s = x[i] + t * (x[i + 1] - x[i])
        for side in [k for k in range(2) if d.sc_side[k] >= 0]:
            out = []
            for box in (False, True):
                for mode in (0, 1, 2):
                    d.sc_key[:] = -1
                    _loop_zone(2, d, i, s, t, side, mode, box)
                    out.append(
                        _best(lambda m=mode, b=box: _loop_zone(n, d, i, s, t, side, m, b)) / n  # noqa: B023
                    )  # fmt: skip
            print(f"  side {side} at t = {t}: linear blend {out[0] * 1e6:.3f} / "
                  f"{out[1] * 1e6:.2f} / {out[2] * 1e6:.2f} us, filter at the wheel "
                  f"{out[3] * 1e6:.3f} / {out[4] * 1e6:.2f} / {out[5] * 1e6:.2f} us "
                  "(same position / new position / new interval)")  # fmt: skip


def run_costs(distance_m: float = 2.0) -> None:
    """The wheelset over the crossing against plain track: build and integration wall times."""
    vehicle = load_vehicle("wheelset")
    crossing = load_track("uk_crossing_facing", overrides="variable_rails.start=4 m")
    plain = replace(crossing, variable_rails=None)
    settings = RunSettings(
        speed_m_per_s=10.0, distance_m=4.0 + distance_m - 0.3, initial_lateral_m=0.0
    )
    times = {}
    for label, track in (("plain", plain), ("crossing", crossing), ("plain again", plain)):
        t0 = time.perf_counter()
        result = run(vehicle, track, settings)
        wall = time.perf_counter() - t0
        timings = result.summary.get("timings_s", {})
        integ = float(timings.get("integration_s", float("nan")))
        times[label] = (wall, integ)
        print(f"  {label:<12s} run {wall:7.1f} s ({result.status['state']}), of which "
              f"integration {integ:6.1f} s; timings {timings}")  # fmt: skip
    base = [min(times["plain"][k], times["plain again"][k]) for k in (0, 1)]
    print(
        f"  ratio crossing / plain: whole run (the zone's tables included) "
        f"{times['crossing'][0] / base[0]:.2f}, integration {times['crossing'][1] / base[1]:.2f}"
    )


def main() -> None:
    track = load_track("uk_crossing_facing")
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
    t0 = time.perf_counter()
    fields = sc_kernel_fields(track.variable_rails, geometry, 5.0e-4)
    print(f"building the shipped crossing's station tables: {time.perf_counter() - t0:.1f} s")
    blend_costs(fields)
    print(f"the blend and the contact filter at the wheel per call (filter "
          f"{fields['sc_filter']} m, {fields['sc_stations'].size} stations)")  # fmt: skip
    filter_costs(fields)
    del fields
    if "--blend-only" in sys.argv[1:]:
        return
    print("the wheelset at 10 m/s: 4 m of plain track (check rail from 1.1 m), 1.7 m of crossing")
    run_costs()


if __name__ == "__main__":
    main()
