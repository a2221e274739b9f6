"""Common helpers of railexu's figures: saving, colours, axes.

Figures are built with :class:`matplotlib.figure.Figure` directly (no pyplot state), so they work
on any backend, in threads and in worker processes.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # matplotlib is imported by the modules that draw (not by a run without plots)
    from matplotlib.figure import Figure

SIDES = ("left", "right")


FORMATS = ("png", "svg")

#: zlib's level for PNG files (Pillow's default is 6). On the seed run's six figures level 3
#: encoded in 0.39 s instead of 0.69 s for files 1-8 % larger; the pixels are the same.
PNG_COMPRESS_LEVEL = 3


def new_figure(**kwargs) -> Figure:
    """A :class:`matplotlib.figure.Figure` (``kwargs`` as its own); matplotlib is imported here,
    at the first figure, so that a module that draws can be imported without it (the run's
    process names its figures and hands them to the processes that draw them,
    :mod:`railexu.report.file_jobs`)."""
    from matplotlib.figure import Figure

    return Figure(**kwargs)


def save_figure(
    fig: Figure, stem: str | Path, dpi: int = 130, formats: tuple[str, ...] = FORMATS
) -> list[Path]:
    """Save ``fig`` as ``stem.png`` and/or ``stem.svg`` (each written under a temporary name and
    renamed into place); returns the paths."""
    from railexu.report.folder import atomic_path

    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = []
    for fmt in formats:
        if fmt not in FORMATS:
            raise ValueError(f"figure format {fmt!r}: expected one of {FORMATS}")
        path = stem.with_suffix(f".{fmt}")
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=fmt, **save_options(fmt))
        paths.append(path)
    return paths


def save_options(fmt: str) -> dict:
    """Keyword arguments of ``Figure.savefig`` for format ``fmt`` beyond the format and dpi."""
    return {"pil_kwargs": {"compress_level": PNG_COMPRESS_LEVEL}} if fmt == "png" else {}


def _colour_for(values):
    """A function from a value to its viridis colour over the range of ``values``."""
    import numpy as np
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    lo, hi = float(np.min(values)), float(np.max(values))
    span = hi - lo if hi > lo else 1.0
    return lambda v: cmap((v - lo) / span)
