"""Figures of docs/switches-and-crossings.md, "Runs": a vehicle through the whole turnout.

Usage: ``python docs/turnout_run_figures.py RUN_FOLDER IMAGE_FOLDER [--vehicle eu07]``, where
RUN_FOLDER holds what ``python benchmarks/turnout_vehicles.py --save RUN_FOLDER`` wrote (each
run's per-rail columns ``<vehicle>_<route>.npz`` and ``table.jsonl``). Writes:

- ``turnout_crossing_runs.png``: the vehicle's leading wheelset on the crossing side of each
  route and direction: Q per rail (nose, wing rail) and their sum, the contact position per rail
  (the transfer from wing rail to nose), Tgamma per rail, against the wheelset's distance from
  the crossing slices' ``s = 0`` in the direction of travel;
- ``turnout_switch_runs.png``: the same wheelset on the switch side: Q and |Y| per rail (blade,
  stock rail) against the distance from the toe's first slice met;
- ``turnout_impacts.png``: per vehicle and route, the largest Q on the blade and the stock
  rail, the crossing-side wheel's (both rails) in three windows of the crossing, and on the nose
  and on the wing rail past the wing rail's end, against the static wheel load.

The rails are named as the run's line names them (``rails`` per panel, the slices'
``rail_names``: a contact is the rail's whose surface is on top at its lateral position).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

DPI = 90
ROUTES = ("through_facing", "through_trailing", "diverging_facing", "diverging_trailing")
#: Rail names of a line saved before the benchmark named them (gauge side first).
DEFAULT_RAILS = {"switch": ["blade", "stock rail"], "crossing": ["nose", "wing rail"],
                 "check": ["check rail", "stock rail"]}  # fmt: skip


def _lines(folder: Path) -> dict[tuple[str, str], dict]:
    out = {}
    for text in (folder / "table.jsonl").read_text().splitlines():
        line = json.loads(text)
        out[(line["vehicle"], line["route"])] = line
    return out


def rail_names(line: dict, panel: str) -> list[str]:
    """The names of a panel's two rails in a run's line, gauge side first."""
    return line["panels"][panel].get("rails", DEFAULT_RAILS[panel])


def _panel_trace(data, line: dict, panel: str, ws: int = 1):
    """``(x [m] from the panel's first slice met, side, {name: array})`` of one wheelset."""
    p = line["panels"][panel]
    side, (lo, hi) = p["side"], p["range_m"]
    s = data[f"ws{ws}_s_m"]
    win = (s >= lo - 0.5) & (s <= hi + 0.5)
    cols = {k[len(f"ws{ws}_{side}_"):]: data[k][win] for k in data.files
            if k.startswith(f"ws{ws}_{side}_")}  # fmt: skip
    return s[win] - lo, side, cols


def crossing_figure(folder: Path, vehicle: str, path: Path) -> None:
    """Q, contact position and Tgamma per rail through the crossing, the four routes."""
    lines = _lines(folder)
    fig = Figure(figsize=(11.0, 7.5))
    axes = fig.subplots(3, 4, sharex="col")
    for j, route in enumerate(ROUTES):
        line = lines.get((vehicle, route))
        file = folder / f"{vehicle}_{route}.npz"
        if line is None or not file.exists() or "crossing" not in line["panels"]:
            continue
        x, side, c = _panel_trace(np.load(file), line, "crossing")
        for r, name, color in zip((1, 2), rail_names(line, "crossing"), ("C0", "C1"), strict=True):
            q = c[f"rail{r}_Q_N"]
            axes[0, j].plot(x, q / 1e3, lw=0.8, color=color, label=name)
            y = np.where(q > 0.0, c[f"rail{r}_contact_y_m"] * 1e3, np.nan)
            axes[1, j].plot(x, y, ".", ms=1.5, color=color, label=name)
            axes[2, j].plot(x, c[f"rail{r}_Tgamma_N"], lw=0.8, color=color, label=name)
        axes[0, j].plot(x, c["Q_N"] / 1e3, lw=0.5, color="k", alpha=0.5, label="sum")
        axes[0, j].set_title(f"{vehicle}, {route.replace('_', ' ')}\n(ws1, {side} wheel)",
                             fontsize=9)  # fmt: skip
        axes[2, j].set_xlabel("distance from the crossing's first slice met [m]", fontsize=8)
    axes[0, 0].set_ylabel("Q per rail [kN]")
    axes[1, 0].set_ylabel("contact y [mm]\n(rail axes, field +)")
    axes[2, 0].set_ylabel("Tgamma [N]")
    axes[0, 0].legend(fontsize=7)
    for ax in axes.flat:
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


def switch_figure(folder: Path, vehicle: str, path: Path) -> None:
    """Q and |Y| per rail through the switch panel, the four routes."""
    lines = _lines(folder)
    fig = Figure(figsize=(11.0, 5.2))
    axes = fig.subplots(2, 4, sharex="col")
    for j, route in enumerate(ROUTES):
        line = lines.get((vehicle, route))
        file = folder / f"{vehicle}_{route}.npz"
        if line is None or not file.exists() or "switch" not in line["panels"]:
            continue
        x, side, c = _panel_trace(np.load(file), line, "switch")
        for r, name, color in zip((1, 2), rail_names(line, "switch"), ("C0", "C1"), strict=True):
            axes[0, j].plot(x, c[f"rail{r}_Q_N"] / 1e3, lw=0.8, color=color, label=name)
            axes[1, j].plot(x, np.abs(c[f"rail{r}_Y_N"]) / 1e3, lw=0.8, color=color, label=name)
        axes[0, j].set_title(f"{vehicle}, {route.replace('_', ' ')}\n(ws1, {side} wheel)",
                             fontsize=9)  # fmt: skip
        axes[1, j].set_xlabel("distance from the panel's first slice met [m]", fontsize=8)
    axes[0, 0].set_ylabel("Q per rail [kN]")
    axes[1, 0].set_ylabel("|Y| per rail [kN]")
    axes[0, 0].legend(fontsize=7)
    for ax in axes.flat:
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


def _static_wheel_load(file: Path) -> float | None:
    """The mean wheel load at the run's start (on straight track: the static one) [N]."""
    if not file.exists():
        return None
    d = np.load(file)
    q = [d[k][0] for k in d.files if k.endswith(("_left_Q_N", "_right_Q_N")) and "rail" not in k]
    return float(np.mean(q))


def impacts_figure(folder: Path, path: Path, y_max: float = 7.0) -> None:
    """The largest Q over the static wheel load per vehicle and route: on the blade and the
    stock rail, the crossing-side wheel's (both rails) in the three windows of
    :func:`crossing_windows` and on each crossing rail past the wing rail's end
    (:func:`past_wing_end`) (bars raw, dots low-passed at 20 Hz where given; a bar beyond
    ``y_max`` is clipped and labelled)."""
    lines = _lines(folder)
    vehicles = sorted({v for v, _ in lines})
    past = f"s > {WING_END_S_M:.2f} m"
    titles = ("blade", "stock rail", "crossing, s < 0", "crossing, 0-1 m", "crossing, > 1 m",
              f"nose, {past}", f"rail 2 column, {past}")  # fmt: skip
    fig = Figure(figsize=(15.0, 4.6))
    axes = fig.subplots(1, len(titles), sharey=True)
    for k, route in enumerate(ROUTES):
        x = np.arange(len(vehicles)) + 0.2 * (k - 1.5)
        raw = np.full((len(titles), len(vehicles)), np.nan)
        low = np.full((len(titles), len(vehicles)), np.nan)
        for j, v in enumerate(vehicles):
            line = lines.get((v, route))
            file = folder / f"{v}_{route}.npz"
            q0 = _static_wheel_load(file)
            if line is None or not q0:
                continue
            sw = line["panels"].get("switch")
            if sw:
                raw[0, j], raw[1, j] = (q / q0 for q in sw["Q_max_N"])
            if "crossing" in line["panels"]:
                for w, (a, b) in enumerate(crossing_windows(file, line)):
                    raw[2 + w, j], low[2 + w, j] = a / q0, b / q0
                nose, wing, end = past_wing_end(file, line)
                raw[5, j], raw[6, j] = nose / q0, max(wing, end) / q0
        for n, ax in enumerate(axes):
            ax.bar(x, np.minimum(raw[n], y_max), width=0.2, color=f"C{k}",
                   label=route.replace("_", " "))  # fmt: skip
            ax.plot(x, low[n], "k.", ms=3)
            for xi, r in zip(x, raw[n], strict=True):
                if r > y_max:
                    ax.text(xi, y_max * 0.97, f"{r:.0f}", fontsize=6, ha="center", va="top",
                            rotation=90)  # fmt: skip
    for ax, title in zip(axes, titles, strict=True):
        ax.set_xticks(np.arange(len(vehicles)), vehicles, rotation=60, fontsize=6, ha="right")
        ax.set_title(f"largest Q,\n{title}", fontsize=8)
        ax.set_ylim(0.0, y_max)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("Q_max / static wheel load Q0 [-] (dots: 20 Hz)")
    axes[0].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


#: The crossing slices' first and last s [m] (tracks/uk_crossing/uk_crossing_full.yaml).
CROSSING_S_M = (-0.995, 2.258)
#: The wing rail's end in the crossing slices' s [m]: its last slice (slice 95 of
#: ``uk_crossing.slcs``); beyond it the nose alone (docs/switches-and-crossings.md).
WING_END_S_M = 1.0585
#: How far before the crossing's last slice the carrier search may find its station past it
#: [m]: the effective section's half-length, 60 mm, and the search's 5 mm station grid
#: (``railexu.profiles.variable.rails.carrier_rails``).
END_MARGIN_M = 0.065
#: EN 14363's low-pass of the wheel forces [Hz].
LOWPASS_HZ = 20.0


def crossing_windows(file: Path, line: dict) -> list[list[float]]:
    """The largest vertical force of the crossing-side wheel [N] (both rails, every wheelset),
    raw and low-passed at 20 Hz (EN 14363's filter; a landing's single-step spike is not
    converged with the step, its 20 Hz value is steadier), in
    three windows of the slices' ``s``: below 0 (the wing rail's rise, its field side lifted
    1.6-3.4 mm), 0 to 1 m (the transfer to the nose and its impact), beyond 1 m (the wing
    rail's end and the nose's end, where its raised field side falls back to the plain rail)."""
    cr = line["panels"]["crossing"]
    lo, hi = cr["range_m"]
    facing = line["route"].endswith("facing")
    s0 = lo - CROSSING_S_M[0] if facing else hi + CROSSING_S_M[0]
    from railexu.assessment.filters import lowpass

    d = np.load(file)
    fs = 1.0 / float(np.median(np.diff(d["time_s"])))
    out = [[0.0, 0.0] for _ in range(3)]
    i = 1
    while f"ws{i}_s_m" in d.files:
        s = d[f"ws{i}_s_m"]
        s_sl = s - s0 if facing else s0 - s
        inside = (s >= lo) & (s <= hi)
        q = d[f"ws{i}_{cr['side']}_Q_N"]
        q20 = lowpass(q, fs, LOWPASS_HZ)
        for k, w in enumerate((s_sl < 0.0, (s_sl >= 0.0) & (s_sl < 1.0), s_sl >= 1.0)):
            if np.any(w & inside):
                out[k][0] = max(out[k][0], float(q[w & inside].max()))
                out[k][1] = max(out[k][1], float(q20[w & inside].max()))
        i += 1
    return out


def _slices_s(line: dict, s_m: np.ndarray) -> np.ndarray:
    """The crossing slices' s [m] of track distances ``s_m`` [m] (either direction)."""
    lo, hi = line["panels"]["crossing"]["range_m"]
    if line["route"].endswith("facing"):
        return s_m - (lo - CROSSING_S_M[0])
    return (hi + CROSSING_S_M[0]) - s_m


def past_wing_end(file: Path, line: dict) -> list[float]:
    """The crossing-side wheel's largest Q [N] past the wing rail's end (slices'
    ``s > WING_END_S_M``), every wheelset, inside the panel, raw: on the nose; in the rail-2
    column (the wing rail's) up to :data:`END_MARGIN_M` before the crossing's last slice; in the
    rail-2 column within that margin. The labels by the top surface give the wing rail nothing
    past its end; within the margin a contact whose carrying station lies past the last slice
    is on the plain rail beyond the panel, which counts as rail 2 (``sc_outputs``)."""
    cr = line["panels"]["crossing"]
    lo, hi = cr["range_m"]
    d = np.load(file)
    out = [0.0, 0.0, 0.0]
    end = CROSSING_S_M[1] - END_MARGIN_M
    i = 1
    while f"ws{i}_s_m" in d.files:
        s = d[f"ws{i}_s_m"]
        s_sl = _slices_s(line, s)
        w = (s >= lo) & (s <= hi) & (s_sl > WING_END_S_M)
        q1, q2 = (d[f"ws{i}_{cr['side']}_rail{r}_Q_N"] for r in (1, 2))
        for k, (q, v) in enumerate(((q1, w), (q2, w & (s_sl < end)), (q2, w & (s_sl >= end)))):
            if np.any(v):
                out[k] = max(out[k], float(q[v].max()))
        i += 1
    return out


def transfer_s(file: Path, line: dict, window_m: tuple[float, float] = (0.0, 0.8)) -> float | None:
    """Where the leading wheelset's load passes between wing rail and nose, in the slices' s
    [m]: the nose's share of the crossing-side wheel's Q crossing 50 % inside ``window_m``
    (facing: rising, trailing: falling), interpolated; None where it does not."""
    cr = line["panels"]["crossing"]
    lo, hi = cr["range_m"]
    facing = line["route"].endswith("facing")
    s0 = lo - CROSSING_S_M[0] if facing else hi + CROSSING_S_M[0]
    d = np.load(file)
    key = f"ws1_{cr['side']}"
    s_sl = d["ws1_s_m"] - s0 if facing else s0 - d["ws1_s_m"]
    q1, q2 = d[f"{key}_rail1_Q_N"], d[f"{key}_rail2_Q_N"]
    w = (s_sl >= window_m[0]) & (s_sl <= window_m[1]) & (q1 + q2 > 0.0)
    x, share = s_sl[w], q1[w] / (q1[w] + q2[w])
    above = share >= 0.5
    change = np.nonzero(above[1:] != above[:-1])[0]
    if change.size == 0:
        return None
    j = int(change[0])
    return float(x[j] + (0.5 - share[j]) / (share[j + 1] - share[j]) * (x[j + 1] - x[j]))


def markdown_table(folder: Path) -> str:
    """The runs table of docs/switches-and-crossings.md from ``table.jsonl`` and the runs'
    columns: per run the state, the static wheel load, the largest Q on blade and stock rail and
    the largest |Y| on the blade [kN] (every wheelset), the crossing-side wheel's largest Q in
    the windows of :func:`crossing_windows` [kN], the leading wheelset's transfer to the nose
    (facing) or from it (trailing) in the slices' s [mm], the largest Tgamma on the nose and on
    the wing rail [N], the largest Q on the nose and on the wing rail past the wing rail's end
    and in the rail-2 column at the crossing's end (:func:`past_wing_end`) [kN], the largest Q
    on the check rail [kN] and the integration time [s]."""
    past = f"Q s > {WING_END_S_M:.2f} m: nose / wing rail; end"
    head = ("| vehicle | route | state | Q0 [kN] | blade Q / abs Y | stock rail Q | crossing Q "
            "s < 0 | crossing Q 0-1 m | crossing Q > 1 m | ws1 transfer at s [mm] | Tgamma "
            f"nose / wing rail [N] | {past} | check rail Q | integration [s] |\n"
            + "|---" * 14 + "|")  # fmt: skip
    rows = [head]
    lines = _lines(folder)
    order = sorted(lines.items(), key=lambda kv: (kv[0][0], ROUTES.index(kv[0][1])))
    for (v, route), line in order:
        p = line["panels"]
        file = folder / f"{v}_{route}.npz"
        q0 = _static_wheel_load(file)
        sw, cr, ch = p.get("switch", {}), p.get("crossing", {}), p.get("check", {})
        t = transfer_s(file, line) if cr else None
        transfer = "-" if t is None else f"{t * 1e3:.0f}"
        windows = ([f"{a / 1e3:.0f} ({b / 1e3:.0f})" for a, b in crossing_windows(file, line)]
                   if cr else ["-"] * 3)  # fmt: skip

        def kn(d, key, r):
            return f"{d[key][r] / 1e3:.0f}" if d else "-"

        cells = [
            v, route.replace("_", " "), line["state"], f"{(q0 or float('nan')) / 1e3:.0f}",
            f"{kn(sw, 'Q_max_N', 0)} / {kn(sw, 'Y_absmax_N', 0)}", kn(sw, "Q_max_N", 1),
            *windows, transfer,
            f"{cr['Tgamma_max_N'][0]:.0f} / {cr['Tgamma_max_N'][1]:.0f}" if cr else "-",
            "{:.0f} / {:.0f}; {:.0f}".format(*(q / 1e3 for q in past_wing_end(file, line)))
            if cr else "-",
            kn(ch, "Q_max_N", 0), f"{line['timings_s']['integration_s']:.0f}",
        ]  # fmt: skip
        rows.append("| " + " | ".join(cells) + " |")
    return "\n".join(rows)


def sum_check(folder: Path) -> str:
    """The largest ``|Q_rail1 + Q_rail2 - Q|`` [N] over the runs, per panel (the labels split
    each wheel's load, so the sum must equal the wheel's total: round-off), from the lines'
    ``Q_sum_residual_N``; with the largest wheel load in the same panels for scale."""
    worst: dict[str, list[float]] = {}
    for line in _lines(folder).values():
        for name, p in line["panels"].items():
            if "Q_sum_residual_N" not in p:
                continue
            w = worst.setdefault(name, [0.0, 0.0])
            w[0] = max(w[0], p["Q_sum_residual_N"])
            w[1] = max(w[1], *p["Q_max_N"])
    return "Q sum check: " + "; ".join(
        f"{n}: largest |Q1 + Q2 - Q| {r:.3g} N (largest rail Q {q / 1e3:.0f} kN)"
        for n, (r, q) in sorted(worst.items())
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", type=Path)
    ap.add_argument("images", type=Path)
    ap.add_argument("--vehicle", default="eu07")
    ap.add_argument("--table", action="store_true", help="print the markdown runs table only")
    a = ap.parse_args()
    if a.table:
        print(markdown_table(a.runs))
        print(sum_check(a.runs))
        return
    crossing_figure(a.runs, a.vehicle, a.images / "turnout_crossing_runs.png")
    switch_figure(a.runs, a.vehicle, a.images / "turnout_switch_runs.png")
    impacts_figure(a.runs, a.images / "turnout_impacts.png")


if __name__ == "__main__":
    main()
