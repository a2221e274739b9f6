"""The output folder of a run: ``timeseries.csv``, ``summary.json`` and the figures."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from railexu.report.file_jobs import FileJob, write_jobs
from railexu.report.folder import OutputFolder, atomic_path, writing_errors
from railexu.results import write_summary

if TYPE_CHECKING:
    from railexu.runtime.warm_process import WarmProcess
    from railexu.simulation.simulate import RunResult


def write_run(
    result: RunResult,
    out_dir: str | Path | OutputFolder,
    plots: bool = True,
    formats: tuple[str, ...] = ("png",),
    warm: WarmProcess | None = None,
    processes: int | None = None,
) -> list[Path]:
    """Write ``timeseries.csv``, ``state.npz``, the figures and then ``summary.json`` of a run
    into ``out_dir``; for a run worn by its settings (``wear_law``, ``result.wear``) also
    ``wear.csv``, ``wear.json`` and the figure ``wear`` (docs/wear.md, "Per run").

    The folder is marked incomplete before its first file changes; each file is written under a
    temporary name and renamed into place, the data files first and ``summary.json`` last; the
    files of an older run in the same folder that this run does not write again (figures of
    another format, a figure this run does not draw) are removed, and the manifest marking the
    folder complete is written at the very end (:meth:`OutputFolder.finish`). A write stopped by
    an error or a signal leaves the folder marked incomplete. ``out_dir`` may be an
    :class:`OutputFolder` already prepared (and locked) before the run, as ``railexu run`` does:
    its caller then calls :meth:`OutputFolder.finish`.

    Args:
        plots: draw the figures.
        formats: figure formats, ``"png"`` and/or ``"svg"``.
        warm: a process started before the run that draws the figures
            (:class:`~railexu.runtime.warm_process.WarmProcess`, as ``railexu run`` does); by
            default a child forked now shares the writing.
        processes: 1 to write every file in this process (no helper process); None: up to two
            (:func:`railexu.report.file_jobs.write_jobs`).

    Raises:
        InputError: the folder is not writable, is being written by another process, or holds
            the output of another kind of job; a file could not be written (a full disk: the
            folder stays marked incomplete).
    """
    if isinstance(out_dir, OutputFolder):
        return _write_into(result, out_dir, plots, formats, warm, processes)
    with OutputFolder(out_dir, "run") as folder:
        return _write_into(result, folder, plots, formats, warm, processes)


def _write_into(
    result: RunResult,
    folder: OutputFolder,
    plots: bool,
    formats: tuple[str, ...],
    warm: WarmProcess | None,
    processes: int | None = None,
) -> list[Path]:
    with writing_errors(folder):
        # every name first: the manifest marks the folder incomplete with all of them listed
        summary_path = folder.file("summary.json")
        jobs = [FileJob("timeseries", _csv_writer(result, folder.file("timeseries.csv")), 0.4)]
        if result.model is not None:  # the state the animations read (railexu animate)
            from railexu.report.state_file import STATE_FILE

            jobs.append(FileJob("state", _state_writer(result, folder.file(STATE_FILE)), 0.4))
        if getattr(result, "wear", None):  # the settings asked for the wear (wear_law)
            paths = (folder.file("wear.csv"), folder.file("wear.json"))
            jobs.append(FileJob("wear", _wear_writer(result, *paths), 0.2))
        if plots:
            jobs += _figure_jobs(result, folder, formats)
        write_jobs(jobs, processes, warm, partial(_remove_temporaries, folder.path))
        # the summary (what the run claims) after the data it describes
        with atomic_path(summary_path) as tmp:
            write_summary(result.summary, tmp)
    return list(folder.written)


def _remove_temporaries(folder: Path, pids: list[int]) -> None:
    """Remove what helper processes ended in the middle of a job left: their temporary files
    (:func:`railexu.report.folder.atomic_path` names them ``.STEM.PID.tmpSUFFIX``)."""
    for pid in pids:
        for path in folder.glob(f".*.{pid}.tmp*"):
            path.unlink(missing_ok=True)


def _csv_writer(result: RunResult, path: Path) -> Callable[[], None]:
    def write() -> None:
        with atomic_path(path) as tmp:
            result.timeseries.to_csv(tmp)

    return write


def _wear_writer(result: RunResult, csv_path: Path, json_path: Path) -> Callable[[], None]:
    def write() -> None:
        from railexu.contact.wear.coefficients import COEFFICIENTS_FILE
        from railexu.report.wear_files import write_wear_files

        block = result.summary.get("wear") or {}
        coefficients = block.get("coefficients_file") or str(COEFFICIENTS_FILE)
        law = result.settings.wear_law
        write_wear_files(csv_path, json_path, result.wear, law, coefficients)

    return write


def _state_writer(result: RunResult, path: Path) -> Callable[[], None]:
    def write() -> None:
        from railexu.report.state_file import write_state

        with atomic_path(path) as tmp:
            write_state(result, tmp)

    return write


def _figure_jobs(
    result: RunResult, folder: OutputFolder, formats: tuple[str, ...]
) -> list[FileJob]:
    """One job per figure (each builds and saves its figure, from its own data: a job can be
    pickled to another process); the figure files are recorded in ``folder`` here, whichever
    process writes them."""
    from railexu.report.run_figures import run_figure_names

    title = f"{result.vehicle.name} at {result.settings.speed_m_per_s:g} m/s"
    ts = result.timeseries
    builders: dict[str, Callable] = {}
    for name in run_figure_names(ts):
        builders[name] = partial(_run_figure, ts, result.summary, title, name)
    alignment = getattr(result.track, "alignment", None)
    if alignment is not None and not alignment.is_straight:
        builders["track"] = partial(_track_figure, alignment, result.track.name)
        builders["curving"] = partial(_curving_figure, ts, alignment, title)
    if "track_elevation_m" in ts.columns:
        builders["track_vertical"] = partial(_vertical_figure, ts, result.track.name)
    rails = getattr(result.track, "variable_rails", None)
    if rails is not None:
        builders["crossing"] = partial(_crossing_figure, ts, rails.zone_m(), title)
    if getattr(result, "wear", None):
        builders["wear"] = partial(_wear_figure, result.wear, result.settings.wear_law, title)
    jobs = []
    for name, build in builders.items():
        for fmt in formats:
            folder.file(f"{name}.{fmt}")
        cost = _FIGURE_COST.get(name, 1.0)
        save = partial(_save, folder.path / name, build, formats)
        jobs.append(FileJob(name, save, cost, portable=True))
    return jobs


#: relative drawing times of the figures (measured on the EU07; only their ratios matter)
_FIGURE_COST = {
    "wheel_load": 1.4,
    "lateral_force": 1.2,
    "curving": 1.2,
    "y_over_q": 1.0,
    "sum_y": 1.0,
    "accelerations": 0.7,
    "track": 0.5,
    "lateral_displacement": 0.4,
}


def _run_figure(ts, summary, title: str, name: str):
    from railexu.report.run_figures import run_figures

    return run_figures(ts, summary, title, names=[name])[name]


def _track_figure(alignment, track_name: str):
    from railexu.report.track_figures import track_figure

    return track_figure(alignment, track_name)


def _vertical_figure(ts, track_name: str):
    from railexu.report.track_figures import vertical_run_figure

    return vertical_run_figure(ts, track_name)


def _curving_figure(ts, alignment, title: str):
    from railexu.report.curving_figures import curving_figure

    return curving_figure(ts, alignment, title)


def _crossing_figure(ts, zone_m, title: str):
    from railexu.report.sc_figures import crossing_figure

    return crossing_figure(ts, zone_m, title)


def _wear_figure(wears: list, law: str, title: str):
    from railexu.report.run_wear_figure import run_wear_figure

    return run_wear_figure(wears, law, title)


def _save(stem: Path, build: Callable, formats: tuple[str, ...]) -> None:
    from railexu.report.figures import save_figure

    save_figure(build(), stem, formats=formats)
