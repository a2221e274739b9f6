"""The output folder of a critical-speed analysis: ``critical_speed.json`` and the figures."""

from __future__ import annotations

import json
from pathlib import Path

from railexu.stability import _jsonable


def write_critical_speed(result: dict, out_dir: str | Path, plots: bool = True) -> list[Path]:
    """Write ``critical_speed.json`` and the plots (PNG and SVG) into ``out_dir``."""

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "critical_speed.json"
    path.write_text(json.dumps(_jsonable(result), indent=2) + "\n")
    written = [path]
    if plots:
        from railexu.report.figures import save_figure
        from railexu.report.stability_figures import critical_speed_figures

        for name, fig in critical_speed_figures(result).items():
            written.extend(save_figure(fig, out / name))
    return written
