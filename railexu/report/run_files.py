"""The output folder of a run: ``timeseries.csv``, ``summary.json`` and the figures."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..results import write_summary
from .folder import OutputFolder, atomic_path

if TYPE_CHECKING:
    from ..simulation import RunResult


def write_run(
    result: RunResult,
    out_dir: str | Path | OutputFolder,
    plots: bool = True,
    formats: tuple[str, ...] = ("png",),
) -> list[Path]:
    """Write ``timeseries.csv``, ``summary.json``, ``state.npz`` and the figures of a run into
    ``out_dir``.

    Each file is written under a temporary name and renamed into place; the files of an older
    run in the same folder that this run does not write again (figures of another format, a
    figure this run does not draw) are removed. ``out_dir`` may be an :class:`OutputFolder`
    already prepared (and locked) before the run, as ``railexu run`` does.

    Args:
        plots: draw the figures.
        formats: figure formats, ``"png"`` and/or ``"svg"``.

    Raises:
        InputError: the folder is not writable, is being written by another process, or holds
            the output of another kind of job.
    """
    if isinstance(out_dir, OutputFolder):
        return _write_into(result, out_dir, plots, formats)
    with OutputFolder(out_dir, "run") as folder:
        return _write_into(result, folder, plots, formats)


def _write_into(
    result: RunResult, folder: OutputFolder, plots: bool, formats: tuple[str, ...]
) -> list[Path]:
    path = folder.file("timeseries.csv")
    with atomic_path(path) as tmp:
        result.timeseries.to_csv(tmp)
    path = folder.file("summary.json")
    with atomic_path(path) as tmp:
        write_summary(result.summary, tmp)
    if result.model is not None:  # the state the animations read (railexu animate)
        from .state_file import STATE_FILE, write_state

        with atomic_path(folder.file(STATE_FILE)) as tmp:
            write_state(result, tmp)
    if plots:
        from .run_figures import run_figures

        title = f"{result.vehicle.name} at {result.settings.speed_m_per_s:g} m/s"
        for name, fig in run_figures(result.timeseries, result.summary, title).items():
            _save(folder, fig, name, formats)
        alignment = getattr(result.track, "alignment", None)
        if alignment is not None and not alignment.is_straight:
            from .curving_figures import curving_figure
            from .track_figures import track_figure

            _save(folder, track_figure(alignment, result.track.name), "track", formats)
            _save(folder, curving_figure(result.timeseries, alignment, title), "curving", formats)
    return list(folder.written)


def _save(folder: OutputFolder, fig, name: str, formats: tuple[str, ...]) -> None:
    from .figures import save_figure

    for path in save_figure(fig, folder.path / name, formats=formats):
        folder.file(path.name)
