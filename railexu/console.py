"""The ``railexu`` console script (``[project.scripts]`` in ``pyproject.toml``): starts the
command as cheaply as it can, then runs :func:`railexu.cli.entry_point`.

Before anything imports numpy it sets BLAS to one thread (:mod:`railexu.blas_threads`) and
pauses the cyclic garbage collector for the command's start-up (:mod:`railexu.gc_pause`).
"""

from __future__ import annotations

from . import (
    blas_threads,  # noqa: F401  (before numpy loads)
    gc_pause,
)


def entry_point() -> None:
    """The ``railexu`` command."""
    gc_pause.pause()
    from .cli import entry_point as command

    command()
