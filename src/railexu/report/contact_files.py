"""The output folder of a contact check: ``contact.csv``, ``conicity.csv``, ``delta_r.csv``,
``settings.json`` and the figures."""

from __future__ import annotations

import csv
from dataclasses import asdict
from pathlib import Path

import numpy as np

from railexu.contact.check import ContactCheckResult, _fmt


def write_contact_check(result: ContactCheckResult, out_dir: str | Path) -> list[Path]:
    """Write ``contact.csv``, ``conicity.csv``, ``delta_r.csv``, ``settings.json`` and the plots.

    Returns the paths written.
    """
    import json

    from railexu.report.contact_figures import contact_check_figures
    from railexu.report.figures import save_figure

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    path = out / "contact.csv"
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=result.columns, extrasaction="ignore")
        writer.writeheader()
        for row in result.rows:
            writer.writerow({k: _fmt(v) for k, v in row.items()})
    written.append(path)
    for name, header, columns in (
        ("conicity.csv", "amplitude_m,equivalent_conicity",
         (result.conicity_amplitude_m, result.conicity)),
        ("delta_r.csv", "lateral_m,delta_r_m", (result.delta_r_lateral_m, result.delta_r_m)),
    ):  # fmt: skip
        path = out / name
        np.savetxt(path, np.column_stack(columns), delimiter=",", header=header, comments="",
                   fmt="%.10g")  # fmt: skip
        written.append(path)
    settings = asdict(result.settings)
    settings["lateral_m"] = list(settings["lateral_m"])
    settings["conicity_amplitudes_m"] = list(settings["conicity_amplitudes_m"])
    path = out / "settings.json"
    path.write_text(json.dumps(settings, indent=2, default=str) + "\n")
    written.append(path)
    for name, fig in contact_check_figures(result).items():
        written.extend(save_figure(fig, out / name))
    return written
