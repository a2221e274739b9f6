"""The study plots of an output folder."""

from __future__ import annotations

import json
from pathlib import Path

from railexu.study.errors import StudyError
from railexu.study.folder import PLOTS_DIR, RESULTS_CSV, STUDY_JSON, is_study_folder
from railexu.study.table import read_results


def plot_study(out_dir: str | Path) -> list[Path]:
    """Draw the study plots of an output folder from its ``study.json`` and ``results.csv``
    into ``out_dir/plots/`` (PNG and SVG; see :func:`railexu.plots.study_figures`).

    Returns:
        The files written (none if no case has a numeric result yet).

    Raises:
        StudyError: the folder holds no study output.
    """
    from railexu.report.figures import save_figure
    from railexu.report.study_figures import study_figures

    out = Path(out_dir)
    if not is_study_folder(out):
        raise StudyError(f"{out}: no study.json and results.csv (not an output folder of a study)")
    try:
        meta = json.loads((out / STUDY_JSON).read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise StudyError(f"{out / STUDY_JSON}: cannot read: {exc}") from None
    if not isinstance(meta, dict):
        raise StudyError(f"{out / STUDY_JSON}: expected a JSON object, got {type(meta).__name__}")
    rows = read_results(out / RESULTS_CSV)  # a damaged table: StudyError naming the line
    written: list[Path] = []
    for name, fig in study_figures(rows, meta).items():
        written.extend(save_figure(fig, out / PLOTS_DIR / name))
    return written
