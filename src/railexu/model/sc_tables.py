"""The kernel data of a switch-and-crossing zone: rail tables at stations along it (issue 29).

For a track with :class:`~railexu.track.variable_rails.VariableRails`, the stations
``start + i step`` cover the zone; each side with a variable profile gets the kernel table of
its effective section at every station (:func:`railexu.contact.variable_tables.station_tables`,
placed on that side's rail like the track's rail profile). :mod:`railexu.model.forces` blends the
two stations around a wheelset linearly. The effective section depends on the wheel's radius:
the first wheelset's wheels are used for all (a vehicle's wheels usually share profile and
radius). Memory: ``n_stations x sides x rows x columns x 8`` bytes (a 0.6 m zone at 10 mm
with a 150 mm wide crossing: ~ 40 MB).
"""

from __future__ import annotations

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.placement import WheelsetGeometry
from railexu.contact.variable_tables import station_tables
from railexu.track.variable_rails import VariableRails


def sc_kernel_fields(
    rails: VariableRails | None,
    geometry: WheelsetGeometry,
    curvature_smoothing_m: float,
    n_wheelsets: int = 1,
) -> dict:
    """The ``sc_*`` fields of :class:`railexu.model.forces.KernelData` (empty: no zone): the
    station tables with pair-envelope bounds (:func:`pair_envelope_bounds`) and each
    wheelset's blend cache (``sc_cache``: its blended table per side; ``sc_key``: the station
    ``i`` whose bounds it holds, -1 none; ``sc_t``: the blend fraction of its base columns)."""
    if rails is None:
        return {}
    lo, hi = rails.zone_m()
    n = int(np.floor((hi - lo) / rails.station_step_m)) + 1
    stations = lo + rails.station_step_m * np.arange(max(n, 2))
    tabs, infos, side_index = [], np.zeros((2, 3)), np.full(2, -1, dtype=np.int64)
    for k, (profile, pair) in enumerate(zip(rails.sides(), geometry.pairs, strict=True)):
        if profile is None:
            continue
        tab, info = station_tables(
            profile, pair, stations - rails.start_m, rail_origin_m=rails.rail_origin_m,
            x_max_m=rails.x_max_m, curvature_smoothing_m=curvature_smoothing_m,
        )  # fmt: skip
        side_index[k] = len(tabs)
        tabs.append(tab)
        infos[k] = info
    rows = max(t.shape[1] for t in tabs)
    out = np.zeros((stations.size, len(tabs), rows, tabs[0].shape[2]))
    for j, tab in enumerate(tabs):
        out[:, j, : tab.shape[1]] = tab
        out[:, j, tab.shape[1] :] = tab[:, -1:]  # rows beyond a shorter grid: never read
    pair_envelope_bounds(out)
    return {
        "sc_cache": np.zeros((n_wheelsets, len(tabs), rows, out.shape[3])),
        "sc_key": np.full((n_wheelsets, 2), -1, dtype=np.int64),
        "sc_t": np.full((n_wheelsets, 2), np.nan),
        "sc_start": float(stations[0]),
        "sc_step": float(rails.station_step_m),
        "sc_tab": out,
        "sc_side": side_index,
        "sc_info": infos,
    }


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
