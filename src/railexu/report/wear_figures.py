"""Figures of the wear loop (docs/wear.md): the profile sequence of every wheel and the flange
measures, the conicity, the removed area, the RCF indices and the rail wear against the
mileage, from the loop's folder
(``steps.csv`` and each step's accepted profiles, its ``profiles_folder``: ``step_NNN/profiles/``
or, for a step made again, ``step_NNN/profiles_again1/`` ...)."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from railexu.profiles import wheel_profile
from railexu.report.figures import new_figure, save_figure

__all__ = ["read_steps", "wear_figures"]


def read_steps(out: str | Path) -> dict[str, np.ndarray]:
    """The columns of a wear loop's ``steps.csv`` (numbers; text columns left out)."""
    with open(Path(out) / "steps.csv", newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    cols: dict[str, np.ndarray] = {}
    for key in rows[0] if rows else ():
        try:
            cols[key] = np.array([float(r[key]) if r[key] != "" else np.nan for r in rows])
        except ValueError:
            continue
    return cols


def _profile_folders(out: Path) -> dict[int, str]:
    """Each step's accepted profile folder (``steps.csv``'s ``profiles_folder``; the first
    attempt's ``step_NNN/profiles`` for a loop written before that column)."""
    with open(out / "steps.csv", newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    folders = {}
    for r in rows:
        k = int(float(r["step"]))
        folders[k] = r.get("profiles_folder") or f"step_{k:03d}/profiles"
    return folders


def _profile_sequence(out: Path, steps: np.ndarray, wheels: list[str], first: dict) -> Path:
    folders = _profile_folders(out)
    fig = new_figure(figsize=(10, 3.2 * len(wheels)))
    for j, key in enumerate(wheels):
        ax, ax2 = (
            fig.add_subplot(len(wheels), 2, 2 * j + 1),
            fig.add_subplot(len(wheels), 2, 2 * j + 2),
        )
        new = wheel_profile(first[key])
        s = np.linspace(new.lateral_m[0], new.lateral_m[-1], 1500)
        for k in steps.astype(int):
            path = out / folders.get(k, f"step_{k:03d}/profiles") / f"{key}.txt"
            if k == 0 or not path.is_file():
                continue
            p = wheel_profile(path)
            sk = np.clip(s, p.lateral_m[0], p.lateral_m[-1])
            ax.plot(s * 1e3, p.height(sk) * 1e3, lw=0.8)
            ax2.plot(s * 1e3, (new.height(s) - p.height(sk)) * 1e3, lw=0.8, label=f"step {k}")
        ax.plot(s * 1e3, new.height(s) * 1e3, "k", lw=1.0, label="new")
        ax.set(xlabel="lateral from the tape circle s [mm]", ylabel="radius increase F [mm]",
               title=f"{key}: profiles")  # fmt: skip
        ax2.set(xlabel="lateral from the tape circle s [mm]", ylabel="worn depth (graph) [mm]",
                title=f"{key}: removed since new")  # fmt: skip
        ax.grid(True, lw=0.3)
        ax2.grid(True, lw=0.3)
    fig.tight_layout()
    return save_figure(fig, out / "figures" / "profiles", formats=("png",))[0]


def _measures(out: Path, cols: dict, wheels: list[str], wheelsets: list[str]) -> Path:
    km = cols["mileage_km"]
    fig = new_figure(figsize=(10, 10.5))
    panels = [
        ("flange_height_mm", "flange height Sh [mm]"),
        ("flange_thickness_mm", "flange thickness Sd [mm]"),
        ("qR_mm", "qR [mm]"),
    ]
    for i, (name, label) in enumerate(panels):
        ax = fig.add_subplot(3, 3, i + 1)
        for key in wheels:
            ax.plot(km, cols[f"{key}_{name}"], "o-", ms=3, lw=0.9, label=key)
        ax.set(xlabel="mileage [km]", ylabel=label)
        ax.grid(True, lw=0.3)
    ax = fig.add_subplot(3, 3, 4)
    for ws in wheelsets:
        ax.plot(km, cols[f"{ws}_conicity"], "o-", ms=3, lw=0.9, label=ws)
    ax.set(xlabel="mileage [km]", ylabel="equivalent conicity (EN 15302, 3 mm) [-]")
    ax.grid(True, lw=0.3)
    ax = fig.add_subplot(3, 3, 5)
    for key in wheels:
        area = np.nan_to_num(cols.get(f"{key}_area_mm2", np.zeros_like(km)))
        ax.plot(km, np.cumsum(area), "o-", ms=3, lw=0.9, label=key)
    ax.set(xlabel="mileage [km]", ylabel="removed area (cumulated) [mm^2]")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7)
    ax = fig.add_subplot(3, 3, 6)
    for key in wheels:
        ax.plot(km, cols.get(f"{key}_tape_circle_change_mm", km * np.nan), "o-", ms=3, lw=0.9)
    ax.set(xlabel="mileage [km]", ylabel="radius change at the tape circle [mm]")
    ax.grid(True, lw=0.3)
    _rcf_panels(fig, cols, wheels)
    fig.tight_layout()
    return save_figure(fig, out / "figures" / "measures", formats=("png",))[0]


def _rcf_panels(fig, cols: dict, wheels: list[str]) -> None:
    """The RCF and rail wear panels (the figure's third row): each step's values (from the
    route at the profiles it started from) against the mileage where it started."""
    km = cols["mileage_km"] - cols.get("step_km", np.zeros_like(cols["mileage_km"]))
    panels = [
        ([f"{k}_fi_surf_max_dimensionless" for k in wheels], wheels,
         "largest FI_surf (Ekberg) [-]"),
        ([f"{k}_wlrm_damage_per_km" for k in wheels], wheels, "WLRM damage per km [1/km]"),
        ([f"rail_{s}_area_per_axle_um2" for s in ("left", "right")], ["rail left", "rail right"],
         "rail area removed per axle [um^2]"),
    ]  # fmt: skip
    for i, (names, labels, ylabel) in enumerate(panels):
        ax = fig.add_subplot(3, 3, 7 + i)
        for name, label in zip(names, labels, strict=True):
            if name in cols:
                ax.plot(km[1:], cols[name][1:], "o-", ms=3, lw=0.9, label=label)
        ax.set(xlabel="mileage at the step's start [km]", ylabel=ylabel)
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7)


def wear_figures(out: str | Path, first_profiles: dict[str, str]) -> list[Path]:
    """Draw ``figures/profiles.png`` and ``figures/measures.png`` of a wear loop's folder.

    Args:
        out: the loop's folder.
        first_profiles: each wheel's profile before the first step (name or file), by
            ``ws{k}_{side}``.
    """
    out = Path(out)
    cols = read_steps(out)
    wheels = sorted(first_profiles)
    wheelsets = sorted({k.rsplit("_", 1)[0] for k in wheels})
    return [
        _profile_sequence(out, cols["step"], wheels, first_profiles),
        _measures(out, cols, wheels, wheelsets),
    ]
