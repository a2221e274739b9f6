"""Figures of a critical-speed analysis: the named modes' damping against speed, the root
locus, and the nonlinear runs' amplitude against speed."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

_MODE_STYLE = {
    "wheelset hunting": ("tab:red", "o"),
    "bogie hunting": ("tab:orange", "s"),
    "wheelset yaw": ("tab:brown", "o"),
    "bogie yaw": ("tab:cyan", "s"),
    "car-body lateral": ("tab:blue", "^"),
    "car-body yaw": ("tab:green", "D"),
    "car-body roll": ("tab:purple", "v"),
}


def critical_speed_figures(result: dict) -> dict[str, Figure]:
    """Figures of ``critical_speed.json`` content:

    - ``"linear_stability"``: damping ratio and frequency of every named lateral mode against
      speed, each mode's zero-damping speed marked;
    - ``"root_locus"``: every named mode at every speed, damping ratio against frequency,
      coloured by speed (one marker shape per mode);
    - ``"nonlinear_stability"``: amplitude of the bisection runs and of the ramp against speed;
    - ``"bifurcation_diagram"``: the limit-cycle branches (fitted amplitude of the deciding
      wheelset against speed, sustained and growing filled, decaying runs open, each branch
      found joined by a line), the fold of the branch followed from the top speed as a shaded
      bracket (with its verdict: a jump, or not refined), the ramp's windows at both rates where
      the ramp was run too, the nonlinear and the linear critical speeds marked.
    """
    figs: dict[str, Figure] = {}
    title = f"{result.get('vehicle', '')}: critical speed"
    lin = result.get("linear")
    if lin:
        figs["linear_stability"] = _linear_figure(lin, title)
        if lin.get("root_locus"):
            figs["root_locus"] = _root_locus_figure(lin, title)
    if result.get("bisection") or result.get("ramp"):
        figs["nonlinear_stability"] = _nonlinear_figure(result, title)
    if result.get("branch"):
        figs["bifurcation_diagram"] = _bifurcation_figure(result, title)
    return figs


_CLASS_STYLE = {
    "limit cycle": ("tab:red", "o", "limit cycle (sustained)"),
    "growing": ("tab:red", "^", "growing"),
    "large broad-band": ("tab:red", "x", "large, irregular"),
    "decaying": ("tab:blue", "v", "decaying (no limit cycle)"),
    "small limit cycle": ("tab:red", "s", "small limit cycle (sustained, below 1 mm)"),
    "below floor": ("tab:blue", "o", "below floor"),
}


def _bifurcation_figure(result: dict, title: str) -> Figure:
    branch = result["branch"]
    fig = Figure(figsize=(8, 4.5))
    fig.subplots_adjust(left=0.11, right=0.97, bottom=0.12, top=0.9)
    ax = fig.subplots()
    seen: set[str] = set()
    for p in branch["branch"]:
        amp = p.get("amplitude_m")
        colour, marker, label = _CLASS_STYLE.get(p.get("classification"), ("0.4", "s", "other"))
        filled = colour == "tab:red"
        face = colour if filled else "none"
        ax.plot(p["speed_m_per_s"], (amp or 0.0) * 1e3, marker, ms=8, color=colour, mfc=face,
                label=None if label in seen else label)  # fmt: skip
        seen.add(label)
    for b in branch.get("branches") or []:
        amps = [(a or 0.0) * 1e3 for a in b["amplitude_m"]]
        ax.plot(b["speeds_m_per_s"], amps, "-", color=f"C{b['index'] % 10}", alpha=0.6,
                label=f"branch {b['index'] + 1}")  # fmt: skip
    _ramp_lines(ax, result.get("ramp") or {})
    fold = branch.get("fold")
    if fold:
        lo, hi = fold["bracket_m_per_s"]
        how = {"jump": "a jump", "not refined": "not refined"}.get(fold.get("discontinuity"), "")
        ax.axvspan(lo, hi, color="tab:orange", alpha=0.2,
                   label=f"fold of branch 1: {lo:.2f}-{hi:.2f} m/s"
                   + (f" ({how})" if how else ""))  # fmt: skip
    crit = branch.get("critical_speed_m_per_s")
    if crit is not None:
        ax.axvline(crit, color="tab:red", ls="--", label=f"nonlinear (branch): {crit:.1f} m/s")
    lin = result.get("linear") or {}
    lines = {"linear": (lin.get("critical_speed_m_per_s"), ":")}
    persistent = lin.get("persistent_critical_speed_m_per_s")
    if persistent is not None and persistent != lines["linear"][0]:
        lines["linear, stays unstable above"] = (persistent, "-.")
    for text, (v, style) in lines.items():
        if v is not None:
            ax.axvline(v, color="k", ls=style, label=f"{text}: {v:.1f} m/s")
    ax.set_xlabel("speed [m/s]")
    ax.set_ylabel("amplitude of the lateral oscillation [mm]")
    note = "" if branch.get("converged") else " - NOT CONVERGED"
    ax.set_title(f"{title}: limit-cycle branch as speed falls{note}")
    ax.grid(True, alpha=0.4)
    ax.legend(loc="upper left", fontsize="small")
    return fig


def _ramp_lines(ax, ramp: dict) -> None:
    """The ramp method's windows (fitted amplitude at each window's end speed), one thin line
    per rate, where the ramp was run with the branch."""
    for k, r in enumerate(ramp.get("ramps") or []):
        windows = r.get("windows") or []
        if not windows:
            continue
        v = [w["speed_m_per_s"] for w in windows]
        amp = [(w.get("amplitude_m") or 0.0) * 1e3 for w in windows]
        ax.plot(v, amp, "-", lw=0.8, color=("0.35", "0.65")[k % 2],
                label=f"ramp at {r['deceleration_m_per_s2']:g} m/s^2 (windows)")  # fmt: skip


def _modes(lin: dict) -> dict:
    if lin.get("modes"):
        return lin["modes"]
    # a result written before the modes were named: its one hunting mode
    return {"hunting": {"damping_ratio": lin["damping_ratio"], "frequency_Hz": lin["frequency_Hz"],
                        "critical_speed_m_per_s": lin.get("critical_speed_m_per_s")}}  # fmt: skip


def _linear_figure(lin: dict, title: str) -> Figure:
    fig = Figure(figsize=(8, 7))
    fig.subplots_adjust(left=0.11, right=0.97, bottom=0.08, top=0.92, hspace=0.3)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    v = np.asarray(lin["speeds_m_per_s"], dtype=float)
    for name, mode in _modes(lin).items():
        colour, marker = _MODE_STYLE.get(mode.get("name", name), ("k", "o"))
        zeta = np.asarray(mode["damping_ratio"], dtype=float)
        freq = np.asarray(mode["frequency_Hz"], dtype=float)
        crit = mode.get("critical_speed_m_per_s")
        label = name + (f" (zero damping at {crit:.1f} m/s)" if crit is not None else "")
        ax1.plot(v, zeta, "-", marker=marker, ms=4, color=colour, label=label)
        ax2.plot(v, freq, "-", marker=marker, ms=4, color=colour, label=name)
        if crit is not None:
            ax1.plot([crit], [0.0], "*", ms=14, color=colour, mec="k")
    ax1.axhline(0.0, color="k", lw=0.8)
    ax1.set_ylabel("damping ratio [-]")
    gamma = lin.get("equivalent_conicity")
    extra = f", equivalent conicity {gamma:.3f}" if gamma is not None else ""
    ax1.set_title(f"{title} (linear{extra})")
    ax1.grid(True, alpha=0.4)
    ax1.legend(fontsize="small", loc="upper right")
    ax2.set_xlabel("speed [m/s]")
    ax2.set_ylabel("frequency [Hz]")
    ax2.grid(True, alpha=0.4)
    return fig


def _root_locus_figure(lin: dict, title: str) -> Figure:
    fig = Figure(figsize=(8, 6), layout="constrained")
    ax = fig.subplots()
    points = lin["root_locus"]
    speeds = np.array([p[0] for p in points], dtype=float)
    lo, hi = float(np.min(speeds)), float(np.max(speeds))
    mappable = None
    for name in dict.fromkeys(p[3] for p in points):
        sel = [p for p in points if p[3] == name]
        _, marker = _MODE_STYLE.get(name.rstrip("0123456789 "), ("k", "o"))
        mappable = ax.scatter([p[1] for p in sel], [p[2] for p in sel], c=[p[0] for p in sel],
                              cmap="viridis", vmin=lo, vmax=hi, marker=marker, s=28,
                              edgecolors="k", linewidths=0.3, label=name)  # fmt: skip
    ax.axhline(0.0, color="k", lw=0.8)
    if mappable is not None:
        fig.colorbar(mappable, ax=ax, label="speed [m/s]")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("damping ratio [-]")
    ax.set_title(f"{title}: root locus of the lateral modes (below 0 = unstable)")
    ax.grid(True, alpha=0.4)
    ax.legend(fontsize="small", loc="best")
    return fig


def _nonlinear_figure(result: dict, title: str) -> Figure:
    bis, ramp = result.get("bisection"), result.get("ramp")
    fig = Figure(figsize=(8, 4.5))
    fig.subplots_adjust(left=0.11, right=0.97, bottom=0.12, top=0.9)
    ax = fig.subplots()
    if ramp and ramp.get("speeds_m_per_s"):
        ax.plot(ramp["speeds_m_per_s"], np.asarray(ramp["amplitude_m"]) * 1e3, ".", ms=3,
                color="0.5", label="ramp: fitted amplitude per window")  # fmt: skip
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
        ax.axhline(bis["threshold_m"] * 1e3, color="k", lw=0.8, ls=":", label="threshold")
    ax.set_xlabel("speed [m/s]")
    ax.set_ylabel("lateral amplitude at the end [mm]")
    ax.set_title(f"{title} (nonlinear: o stable, x unstable)")
    ax.grid(True, alpha=0.4)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", fontsize="small")
    return fig
