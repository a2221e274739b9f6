"""The ``railexu plot`` sub-command: redraw the figures of a run or a study folder."""

from __future__ import annotations

import argparse

from railexu.cli.common import CliError


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "plot",
        help="redraw the plots of a run (or a study) from its files",
        description=(
            "Redraw the plots of a run folder (timeseries.csv, summary.json) or of a study "
            "folder (results.csv, study.json: each result against each varied value, maps "
            "when two vary)."
        ),
    )
    p.add_argument("folder", help="output folder of railexu run or railexu study")
    p.add_argument(
        "--plots", default="png", metavar="FORMATS", help="figure formats: png, svg or png,svg"
    )
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    from pathlib import Path

    from railexu.cli.run import plot_formats
    from railexu.report.figures import save_figure
    from railexu.report.folder import add_to_manifest
    from railexu.report.folder_check import check_output_folder
    from railexu.report.run_figures import run_figures
    from railexu.report.run_folder import read_run_summary
    from railexu.results import TimeSeries
    from railexu.study import is_study_folder
    from railexu.study.plots import plot_study

    folder = Path(args.folder)
    formats = plot_formats(args.plots) or ("png",)
    if is_study_folder(folder):
        written = plot_study(folder)
        print(f"railexu plot: wrote {len(written)} study plots to {folder}")
        return 0
    # an incomplete or damaged folder is refused (railexu.report.folder_check)
    check_output_folder(folder, "run", ("timeseries.csv",))
    ts_path = folder / "timeseries.csv"
    if not ts_path.exists():
        raise CliError(f"{folder}: no timeseries.csv (not an output folder of railexu run)")
    ts = TimeSeries.from_csv(ts_path)
    summary = read_run_summary(folder) if (folder / "summary.json").exists() else None
    title = ""
    if summary:
        speed = (summary.get("settings") or {}).get("speed_m_per_s")
        title = f"{summary.get('vehicle', '')}" + (f" at {speed:g} m/s" if speed else "")
    written = []
    figures = run_figures(ts, summary, title)
    figures.update(_curved_track_figures(ts, summary, title))
    if "track_elevation_m" in ts.columns:  # a track with a vertical profile
        from railexu.report.track_figures import vertical_run_figure

        figures["track_vertical"] = vertical_run_figure(ts, str((summary or {}).get("track", "")))
    for name, fig in figures.items():
        written.extend(save_figure(fig, folder / name, formats=formats))
    add_to_manifest(folder, [p.name for p in written])
    print(f"railexu plot: wrote {len(written)} files to {folder}")
    return 0


def _curved_track_figures(ts, summary: dict | None, title: str) -> dict:
    """The track and curving figures of a run on a curved track, from the design geometry
    that ``summary.json`` keeps (``curving.geometry``); none for straight track or a summary
    written before the geometry was kept there."""
    from railexu.errors import InputError
    from railexu.report.curving_figures import curved_track_figures
    from railexu.track.alignment import alignment_from_record

    record = ((summary or {}).get("curving") or {}).get("geometry")
    if record is None:
        return {}
    try:
        alignment = alignment_from_record(record)
    except InputError as exc:
        raise CliError(f"summary.json: {exc}") from None
    return curved_track_figures(ts, alignment, str((summary or {}).get("track", "")), title)
