"""Common helpers of railexu's figures: saving, colours, axes.

Figures are built with :class:`matplotlib.figure.Figure` directly (no pyplot state), so they work
on any backend, in threads and in worker processes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

SIDES = ("left", "right")


def save_figure(fig: Figure, stem: str | Path, dpi: int = 130) -> list[Path]:
    """Save ``fig`` as ``stem.png`` and ``stem.svg``; returns both paths."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".png"), stem.with_suffix(".svg")]
    fig.savefig(paths[0], dpi=dpi)
    fig.savefig(paths[1])
    return paths


def _colour_for(values: np.ndarray):
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    lo, hi = float(np.min(values)), float(np.max(values))
    span = hi - lo if hi > lo else 1.0
    return lambda v: cmap((v - lo) / span)
