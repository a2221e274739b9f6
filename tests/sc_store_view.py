"""The station store's fields that :mod:`railexu.model.forces`' station functions read
(``_station_interval``, ``_blend_station``, ``_filter_station``), as one typed tuple for tests
that call uncached compiled copies of them (tests/test_sc_stations.py, tests/test_sc_filter.py)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class StoreView(NamedTuple):
    """The ``sc_*`` fields of :class:`railexu.model.forces.KernelData` those functions read."""

    sc_start: float
    sc_step: float
    sc_stations: np.ndarray
    sc_index: np.ndarray
    sc_side: np.ndarray
    sc_tab: np.ndarray
    sc_base: np.ndarray
    sc_cache: np.ndarray
    sc_key: np.ndarray
    sc_t: np.ndarray
    sc_info: np.ndarray
    sc_filter: float
    sc_window: np.ndarray


def store_view(fields: dict) -> StoreView:
    """The view of :func:`railexu.model.sc_tables.sc_kernel_fields`' output."""
    return StoreView(**{k: fields[k] for k in StoreView._fields})
