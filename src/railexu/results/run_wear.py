"""The wear and RCF a run's settings ask for (``wear:`` in the run settings, ``railexu run
--wear LAW``): :func:`railexu.results.wear.run_wear` of the run just made, and the ``wear`` block
of its ``summary.json`` (docs/wear.md, "Per run").

The block names the law, the coefficients file and the sources of the blocks used, the
evaluation window and its rule, and per wheel (wheelsets from the front, left and right) and per
rail under it:

* wheel: the removed area per km run [mm^2/km] (and the patches' integrated volume rate, its
  conservation reference), the largest depth per km [um/km] and where on the profile
  (``s`` from the tape circle [mm]), the largest FI_surf and where, the share of loaded samples
  with FI_surf > 0, the WLRM damage per km summed across the profile;
* rail: the same per axle passage: removed area [um^2], the largest depth [nm] and where (from
  the gauge line, outwards positive [mm]), the largest FI_surf and where on the rail, the WLRM
  damage summed across the rail and its largest bin and where.

A run that did not complete (derailed, diverged, interrupted) is worn over the window of what
was recorded, and the block says so (``complete: false``, ``note``); where nothing can be worn
(no loaded contact point, a run stopped at its start) ``computed`` is false and ``reason`` says
why: the run's own files are written all the same.
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from railexu.contact.wear.coefficients import COEFFICIENTS_FILE, load_coefficients
from railexu.errors import InputError
from railexu.results.wear import WheelWear, run_wear

if TYPE_CHECKING:
    from railexu.simulation.simulate import RunResult

__all__ = ["WEAR_FILES", "wear_block", "wear_of_run"]

#: the files a worn run adds to its folder (railexu.report.wear_files)
WEAR_FILES = ("wear.csv", "wear.json")
#: the states of a run that reached its end (railexu.simulation.simulate.COMPLETED_STATES)
_COMPLETED = ("completed", "completed_with_exceedances")


def coefficients_name(path: str | Path) -> str:
    """The coefficients file as the summary names it: the shipped file by its place in the
    package (``railexu/data/wear_rcf.yaml``), another by its path."""
    p = Path(path).resolve()
    if p == COEFFICIENTS_FILE.resolve():
        return "railexu/data/wear_rcf.yaml (shipped)"
    return str(p)


@lru_cache(maxsize=4)
def coefficient_sources(path: str) -> dict[str, str]:
    """The ``source`` of each block of a coefficients file (block name -> citation)."""
    import yaml

    data = yaml.safe_load(Path(path).read_text(encoding="utf-8")) or {}
    return {k: " ".join(str(v.get("source", "")).split()) for k, v in data.items()
            if isinstance(v, dict)}  # fmt: skip


def wear_of_run(result: RunResult) -> tuple[list[WheelWear] | None, dict]:
    """The wear and RCF of ``result`` by its settings' ``wear_law`` and the summary's block.

    Returns:
        ``(wears, block)``: the :class:`~railexu.results.wear.WheelWear` of every wheel (None
        where nothing could be worn: the block's ``reason`` says why) and the ``wear`` block of
        ``summary.json`` (module doc).
    """
    settings = result.settings
    law = settings.wear_law
    coef = load_coefficients()
    state = str(result.status.get("state", ""))
    complete = state in _COMPLETED
    try:
        wears = run_wear(
            result.timeseries, result.vehicle, law, coef,
            evaluate_from_m=settings.evaluate_from_m, evaluate_to_m=settings.evaluate_to_m,
            gauge_m=float(getattr(result.track, "gauge_m", 1.435)),
        )  # fmt: skip
        start, end = wears[0].window[:2] if wears else (math.nan, math.nan)
        if not end - start > 0.0:
            raise InputError(f"the evaluation window holds no distance ({start:g} .. {end:g} m)")
    except (InputError, ValueError) as exc:  # the run's own files are written all the same
        return None, wear_block(None, law, coef.path, state, complete, reason=str(exc),
                                stopped_at_m=result.status.get("distance_m"))  # fmt: skip
    block = wear_block(wears, law, coef.path, state, complete,
                       stopped_at_m=result.status.get("distance_m"))  # fmt: skip
    return wears, block


def wear_block(
    wears: list[WheelWear] | None,
    law: str,
    coefficients_path: str,
    state: str = "completed",
    complete: bool = True,
    reason: str = "",
    stopped_at_m: float | None = None,
) -> dict:
    """The ``wear`` block of a run's ``summary.json`` (module doc; JSON-ready, None where a
    value is not finite)."""
    sources = coefficient_sources(str(coefficients_path))
    block: dict = {
        "law": law,
        "coefficients_file": coefficients_name(coefficients_path),
        "sources": {k: sources.get(k, "") for k in (law, "fi_surf", "wlrm")},
        "run_state": state,
        "complete": complete,
        "computed": wears is not None,
    }
    if not complete:
        where = f" at {stopped_at_m:.1f} m" if stopped_at_m is not None else ""
        block["note"] = (
            f"the run stopped{where} ({state}): the wear is that of the recorded part's "
            "evaluation window, not of the whole distance asked for"
        )
    if wears is None:
        block["reason"] = reason
        return block
    first = wears[0].summary()
    block.update(
        files=list(WEAR_FILES),
        window_m=first["window_m"],
        window_rule=first["window_rule"],
        wheels=[_wheel(w) for w in wears],
        rails=[_rail(w) for w in wears],
    )
    return block


def _wheel(w: WheelWear) -> dict:
    s = w.summary()
    return _finite({
        "wheelset": w.wheelset, "side": w.side,
        "removed_area_per_km_mm2": s["wheel_area_per_km_mm2"],
        "patch_volume_rate_per_km_mm2": w.volume_rate_per_km_m2 * 1e6,
        "max_depth_per_km_um": s["wheel_max_depth_per_km_um"],
        "max_depth_at_mm": _at(s["wheel_max_depth_at_mm"], s["wheel_max_depth_per_km_um"]),
        "fi_surf_max": s["fi_surf_max"], "fi_surf_max_at_mm": s["fi_surf_max_at_mm"],
        "fi_surf_share_above_0": s["fi_surf_share_above_0"],
        "wlrm_damage_per_km": s["wlrm_wheel_per_km"],
    })  # fmt: skip


def _rail(w: WheelWear) -> dict:
    s = w.summary()
    return _finite({
        "wheelset": w.wheelset, "side": w.side,
        "removed_area_per_axle_um2": s["rail_area_per_axle_um2"],
        "max_depth_per_axle_nm": s["rail_max_depth_per_axle_nm"],
        "max_depth_at_mm": _at(s["rail_max_depth_at_mm"], s["rail_max_depth_per_axle_nm"]),
        "fi_surf_max": s["fi_surf_max"], "fi_surf_max_at_mm": s["fi_surf_max_rail_at_mm"],
        "wlrm_damage_per_axle": s["wlrm_rail_per_axle"],
        "wlrm_max_per_axle": s["wlrm_rail_max_per_axle"],
        "wlrm_max_at_mm": _at(s["wlrm_rail_max_at_mm"], s["wlrm_rail_max_per_axle"]),
    })  # fmt: skip


def _at(where_mm: float, peak: float) -> float | None:
    """Where a peak lies; None where nothing is worn or damaged (every node 0)."""
    return where_mm if peak > 0.0 else None


def _finite(d: dict) -> dict:
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in d.items()}
