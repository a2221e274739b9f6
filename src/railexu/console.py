"""The ``railexu`` console script (``[project.scripts]`` in ``pyproject.toml``): starts the
command as cheaply as it can, then runs :func:`railexu.cli.entry_point`.

Before anything imports numpy it pauses the cyclic garbage collector for the command's
start-up (:mod:`railexu.runtime.gc_pause`); :mod:`railexu.cli` then sets BLAS to one thread first
(:mod:`railexu.runtime.blas_threads`).
"""

from __future__ import annotations

from railexu.runtime import gc_pause


def entry_point() -> None:
    """The ``railexu`` command."""
    gc_pause.pause()
    from railexu.cli import entry_point as command

    command()
