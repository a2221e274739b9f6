"""Figures and tables of docs/vehicles.md from the runs of docs/make_vehicle_figures.sh.

Usage: ``python docs/vehicle_figures.py RUNS_FOLDER IMAGE_FOLDER``. Reads each vehicle's
``*_seed``, ``*_r300``, ``*_r600`` and ``*_cs`` folders, writes ``vehicles_seed_lateral.png`` and
``vehicles_curves.png`` (R 600 m; small PNGs) and prints the Markdown tables of the results section.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from matplotlib.figure import Figure

from railexu.simulation.timeseries import TimeSeries

VEHICLES = {
    "hbbins_empty": "Hbbins empty",
    "hbbins_loaded": "Hbbins loaded",
    "manchester_coach_extended": "Manchester coach extended",
}
COACH = "manchester_coach_extended"
DPI = 90


def _summary(folder: Path) -> dict:
    return json.loads((folder / "summary.json").read_text(encoding="utf-8"))


def seed_table(runs: Path) -> str:
    """The seed scenario: leading wheelset's motion, hunting verdict, largest Y/Q."""
    rows = [
        "| vehicle | ws1 max lateral after 15 m [mm] | final amplitude [mm] | frequency [Hz] |"
        " hunting | flange contact | max Y/Q (EN 14363) |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, label in VEHICLES.items():
        s = _summary(runs / f"{name}_seed")
        ws1 = s["wheelsets"][0]
        hunting = s["hunting"]
        rows.append(
            f"| {label} | {1e3 * ws1['max_abs_lateral_m']:.2f} |"
            f" {1e3 * ws1['final_amplitude_m']:.2f} | {hunting['frequency_Hz'] or math.nan:.2f} |"
            f" {hunting['verdict']} | {'yes' if s['flange_contact']['occurred'] else 'no'} |"
            f" {s['max_Y_over_Q']['value_en14363']:.3f} |"
        )
    return "\n".join(rows)


def curve_table(runs: Path, curve_name: str) -> str:
    """A curve: quasi-static (50 %) and largest values in the circular curve."""
    rows = [
        "| vehicle | wheelset | Y outer q.s. / max [kN] | sum Y q.s. / max [kN] |"
        " Y/Q outer q.s. / max | angle of attack q.s. [mrad] | lateral q.s. [mm] |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, label in VEHICLES.items():
        s = _summary(runs / f"{name}_{curve_name}")
        state = s["status"]["state"]
        if state not in ("completed", "completed_with_exceedances"):
            where = f"{state} at {s['status']['distance_m']:.1f} m: {s['status']['reason']}"
            rows.append(f"| {label} | run stopped, {where} | | | | | |")
            continue
        curve = s["curving"]["curves"][0]
        for ws in curve["wheelsets"]:
            y, sy, yq = ws["Y_outer_N"], ws["sum_Y_N"], ws["Y_over_Q_outer"]
            rows.append(
                f"| {label} | {ws['name']} | {y['quasi_static'] / 1e3:.1f} / {y['max'] / 1e3:.1f}"
                f" | {sy['quasi_static'] / 1e3:.1f} / {sy['max'] / 1e3:.1f}"
                f" | {yq['quasi_static']:.3f} / {yq['max']:.3f}"
                f" | {1e3 * ws['angle_of_attack_rad']['quasi_static']:.2f}"
                f" | {1e3 * ws['lateral_m']['quasi_static']:.1f} |"
            )
    return "\n".join(rows)


def critical_speed_table(runs: Path) -> str:
    """Linear critical speed (least damped mode crossing zero), nonlinear bisection and ramp."""
    rows = [
        "| vehicle | linear [m/s] (mode) | linear hunting [m/s] | equivalent conicity |"
        " nonlinear bisection [m/s] | ramp [m/s] |",
        "|---|---|---|---|---|---|",
    ]

    def speed(v: float | None) -> str:
        return "none in range" if v is None else f"{v:.1f} ({3.6 * v:.0f} km/h)"

    folders = {
        **{n: f"{n}_cs" for n in VEHICLES},
        "rigid": f"{COACH}_rigid_bushes_cs",
    }
    labels = {
        **VEHICLES,
        "rigid": "coach, rigid yaw-damper bushes",
    }
    for name, folder in folders.items():
        path = runs / folder / "critical_speed.json"
        if not path.is_file():
            continue
        cs = json.loads(path.read_text(encoding="utf-8"))
        lin = cs.get("linear")
        linear = "-" if not lin else f"{speed(cs.get('linear_m_per_s'))} ({cs.get('linear_mode')})"
        hunting = "-" if not lin else speed(lin.get("hunting_critical_speed_m_per_s"))
        conicity = "-" if not lin else f"{lin['equivalent_conicity']:.3f}"
        methods = cs["settings"]["methods"]
        bisection = speed(cs["nonlinear_bisection_m_per_s"]) if "bisection" in methods else "-"
        ramp = speed(cs["nonlinear_ramp_m_per_s"]) if "ramp" in methods else "-"
        cells = (labels[name], linear, hunting, conicity, bisection, ramp)
        rows.append("| " + " | ".join(cells) + " |")
    return "\n".join(rows)


def seed_figure(runs: Path) -> Figure:
    """Lateral displacement of the leading wheelset in the seed scenario."""
    fig = Figure(figsize=(7.0, 3.2))
    ax = fig.add_subplot()
    for name, label in VEHICLES.items():
        ts = TimeSeries.from_csv(runs / f"{name}_seed" / "timeseries.csv")
        ax.plot(ts.distance_m, 1e3 * ts["ws1_lateral_m"], lw=0.8, label=label)
    ax.set_xlabel("distance [m]")
    ax.set_ylabel("ws1 lateral [mm]")
    ax.set_title("seed scenario: 10 m/s, 2 mm initial offset, straight track")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def curve_figure(runs: Path) -> Figure:
    """The R 600 m curve (left): Y/Q of the leading wheelset's outer (right) wheel and its angle
    of attack (positive pointing outwards)."""
    fig = Figure(figsize=(7.0, 4.6))
    ax_q, ax_a = fig.subplots(2, 1, sharex=True)
    for name, label in VEHICLES.items():
        ts = TimeSeries.from_csv(runs / f"{name}_r600" / "timeseries.csv")
        ax_q.plot(ts.distance_m, ts["ws1_right_Y_N"] / ts["ws1_right_Q_N"], lw=0.8, label=label)
        ax_a.plot(ts.distance_m, -1e3 * ts["ws1_yaw_rad"], lw=0.8, label=label)
    ax_q.set_ylabel("ws1 outer Y/Q [-]")
    ax_a.set_ylabel("ws1 angle of attack [mrad]")
    ax_a.set_xlabel("distance [m]")
    ax_q.set_title("R 600 m, 100 mm cant, 100 km/h (97 mm cant deficiency)", fontsize=9)
    for ax in (ax_q, ax_a):
        ax.grid(True, lw=0.3)
    ax_q.legend(fontsize=8)
    fig.tight_layout()
    return fig


def yaw_damper_table(runs: Path) -> str:
    """Damping ratio of the coach's least damped wheelset-hunting mode over speed, with the
    yaw dampers' 6 MN/m bushes and with rigid ones (linear analysis)."""
    cases = {"6 MN/m bushes": f"{COACH}_cs", "rigid bushes": f"{COACH}_rigid_bushes_cs"}
    data = {}
    for label, folder in cases.items():
        path = runs / folder / "critical_speed.json"
        lin = json.loads(path.read_text(encoding="utf-8"))["linear"]
        data[label] = (lin["speeds_m_per_s"], lin["modes"]["wheelset hunting"]["damping_ratio"])
    speeds = data["6 MN/m bushes"][0]
    picks = [i for i, v in enumerate(speeds) if i % 5 == 0 and v >= 40.0]
    rows = ["| speed [m/s] | " + " | ".join(f"{speeds[i]:.0f}" for i in picks) + " |"]
    rows.append("|---|" + "---|" * len(picks))
    for label, (_, zeta) in data.items():
        cells = " | ".join("-" if zeta[i] is None else f"{zeta[i]:.3f}" for i in picks)
        rows.append(f"| {label} | {cells} |")
    return "\n".join(rows)


def main(argv: list[str]) -> None:
    runs, images = Path(argv[1]), Path(argv[2])
    seed_figure(runs).savefig(images / "vehicles_seed_lateral.png", dpi=DPI)
    curve_figure(runs).savefig(images / "vehicles_curves.png", dpi=DPI)
    tables = (seed_table(runs), curve_table(runs, "r300"), curve_table(runs, "r600"))
    print(*tables, critical_speed_table(runs), yaw_damper_table(runs), sep="\n\n")


if __name__ == "__main__":
    main(sys.argv)
