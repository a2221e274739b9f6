"""A run's wear and RCF files (docs/wear.md, "Per run"): ``wear.csv`` (each wheel's depth per
km on the wheel grid, each rail's depth and WLRM damage per axle passage on the rail grid) and
``wear.json`` (the scalars of every wheel with their window and rule, the law and its source
file), written atomically into a run's folder and added to its manifest."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from railexu.report.folder import add_to_manifest, atomic_path

__all__ = ["write_run_wear", "write_wear_files"]


def write_run_wear(folder: str | Path, wears: list, law: str, coefficients_file: str) -> list[Path]:
    """Write ``wear.csv`` and ``wear.json`` for ``wears``
    (:func:`railexu.results.wear.run_wear`) into ``folder`` and add them to its manifest;
    returns the paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    csv_path, json_path = folder / "wear.csv", folder / "wear.json"
    write_wear_files(csv_path, json_path, wears, law, coefficients_file)
    add_to_manifest(folder, [csv_path.name, json_path.name])
    return [csv_path, json_path]


def write_wear_files(
    csv_path: Path, json_path: Path, wears: list, law: str, coefficients_file: str
) -> None:
    """Write ``csv_path`` (the grids [m]; per wheel the depth per km [m], the WLRM damage per
    km and the largest FI_surf [-] on the wheel grid; per rail the depth [m] and the WLRM
    damage per axle passage on the rail grid) and ``json_path`` (each wheel's scalars, the law
    and the coefficients file), each atomically; no manifest (``railexu run`` lists them in
    its folder's)."""
    cols = {"wheel_lateral_m": wears[0].lateral_m, "rail_lateral_m": wears[0].rail_lateral_m}
    for w in wears:
        key = f"{w.wheelset}_{w.side}"
        cols[f"{key}_wheel_depth_per_km_m"] = w.depth_per_km_m
        cols[f"{key}_wheel_wlrm_per_km"] = w.wlrm_wheel_per_km
        if w.fi_surf_wheel_max is not None:
            cols[f"{key}_wheel_fi_surf_max"] = w.fi_surf_wheel_max
        cols[f"{key}_rail_depth_per_axle_m"] = w.rail_depth_per_axle_m
        cols[f"{key}_rail_wlrm_per_axle"] = w.wlrm_rail_per_axle
    n = max(len(v) for v in cols.values())
    table = np.full((n, len(cols)), np.nan)
    for j, v in enumerate(cols.values()):
        table[: len(v), j] = v
    with atomic_path(csv_path) as tmp:
        np.savetxt(tmp, table, delimiter=",", header=",".join(cols), comments="", fmt="%.9g")
    info = {"law": law, "coefficients": coefficients_file,
            "wheels": [w.summary() for w in wears]}  # fmt: skip
    with atomic_path(json_path) as tmp:
        Path(tmp).write_text(json.dumps(info, indent=1, allow_nan=False) + "\n", encoding="utf-8")
