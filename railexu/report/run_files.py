"""The output folder of a run: ``timeseries.csv``, ``summary.json`` and the figures."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..results import write_summary

if TYPE_CHECKING:
    from ..simulation import RunResult


def write_run(result: RunResult, out_dir: str | Path, plots: bool = True) -> list[Path]:
    """Write ``timeseries.csv``, ``summary.json`` and the plots of a run into ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    path = out / "timeseries.csv"
    result.timeseries.to_csv(path)
    written.append(path)
    path = out / "summary.json"
    write_summary(result.summary, path)
    written.append(path)
    if plots:
        from .figures import save_figure
        from .run_figures import run_figures

        title = f"{result.vehicle.name} at {result.settings.speed_m_per_s:g} m/s"
        for name, fig in run_figures(result.timeseries, result.summary, title).items():
            written.extend(save_figure(fig, out / name))
        alignment = getattr(result.track, "alignment", None)
        if alignment is not None and not alignment.is_straight:
            from .curving_figures import curving_figure
            from .track_figures import track_figure

            written.extend(save_figure(track_figure(alignment, result.track.name), out / "track"))
            written.extend(
                save_figure(curving_figure(result.timeseries, alignment, title), out / "curving")
            )
    return written
