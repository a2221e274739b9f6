"""The output folder of a critical-speed analysis: ``critical_speed.json`` and the figures."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..stability import _jsonable


def write_critical_speed(result: dict, out_dir: str | Path, plots: bool = True) -> list[Path]:
    """Write ``critical_speed.json`` and the plots (PNG and SVG) into ``out_dir``."""

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "critical_speed.json"
    path.write_text(json.dumps(_jsonable(result), indent=2) + "\n")
    written = [path]
    if plots:
        from .figures import save_figure

        for name, fig in critical_speed_figures(result).items():
            written.extend(save_figure(fig, out / name))
    return written


def critical_speed_figures(result: dict) -> dict:
    """Figures of a critical-speed analysis: damping ratio and frequency of the hunting mode
    against speed (linear), the amplitude of the bisection runs and of the ramp against speed."""

    figs = {}
    title = f"{result.get('vehicle', '')}: critical speed"
    lin = result.get("linear")
    if lin:
        fig = Figure(figsize=(8, 6.5))
        fig.subplots_adjust(left=0.11, right=0.97, bottom=0.09, top=0.92, hspace=0.35)
        ax1, ax2 = fig.subplots(2, 1, sharex=True)
        v = np.asarray(lin["speeds_m_per_s"], dtype=float)
        zeta = np.asarray(lin["damping_ratio"], dtype=float)
        freq = np.asarray(lin["frequency_Hz"], dtype=float)
        ax1.plot(v, zeta, "o-", ms=3)
        ax1.axhline(0.0, color="k", lw=0.8)
        if lin.get("critical_speed_m_per_s"):
            for ax in (ax1, ax2):
                ax.axvline(lin["critical_speed_m_per_s"], color="tab:red", ls="--", lw=1.0)
        ax1.set_ylabel("damping ratio of the hunting mode [-]")
        ax1.set_title(f"{title} (linear, equivalent conicity {lin['equivalent_conicity']:.3f})")
        ax1.grid(True, alpha=0.4)
        ax2.plot(v, freq, "o-", ms=3, color="tab:green")
        ax2.set_xlabel("speed [m/s]")
        ax2.set_ylabel("frequency [Hz]")
        ax2.grid(True, alpha=0.4)
        figs["linear_stability"] = fig
    bis = result.get("bisection")
    ramp = result.get("ramp")
    if bis or ramp:
        fig = Figure(figsize=(8, 4.5))
        fig.subplots_adjust(left=0.11, right=0.97, bottom=0.12, top=0.9)
        ax = fig.subplots()
        if ramp and ramp.get("speeds_m_per_s"):
            ax.plot(ramp["speeds_m_per_s"], np.asarray(ramp["amplitude_m"]) * 1e3, ".",
                    ms=3, color="0.5", label="ramp: amplitude per half period")  # fmt: skip
            if ramp.get("critical_speed_m_per_s"):
                ax.axvline(ramp["critical_speed_m_per_s"], color="tab:orange", ls="--",
                           label=f"ramp: {ramp['critical_speed_m_per_s']:.1f} m/s")  # fmt: skip
        if bis:
            for r in bis["runs"]:
                amp = r.get("amplitude_m")
                y = amp * 1e3 if amp is not None else np.nan
                ax.plot(r["speed_m_per_s"], y, "o" if r["stable"] else "x",
                        color="tab:blue" if r["stable"] else "tab:red", ms=7)  # fmt: skip
            if bis.get("critical_speed_m_per_s"):
                ax.axvline(bis["critical_speed_m_per_s"], color="tab:red", ls="--",
                           label=f"bisection: {bis['critical_speed_m_per_s']:.1f} m/s")  # fmt: skip
            ax.axhline(bis["threshold_m"] * 1e3, color="k", lw=0.8, ls=":",
                       label="threshold")  # fmt: skip
        ax.set_xlabel("speed [m/s]")
        ax.set_ylabel("lateral amplitude at the end [mm]")
        ax.set_title(f"{title} (nonlinear: o stable, x unstable)")
        ax.grid(True, alpha=0.4)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", fontsize="small")
        figs["nonlinear_stability"] = fig
    return figs
