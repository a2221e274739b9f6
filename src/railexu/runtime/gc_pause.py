"""The ``railexu`` command's start-up without cyclic garbage collection.

While numpy, scipy, numba, Exudyn and railexu import, Python's cyclic garbage collector runs
again and again over the growing heap (some 200 000 objects, nearly all of them kept for the
process's life): in a seed run it cost about 0.4 s of the command (``docs/performance.md``). The
console script (:mod:`railexu.console`) pauses it before the first import; the command resumes
it (:func:`resume`) once its imports are done, with the objects made so far frozen
(``gc.freeze``: never searched for cycles again). ``railexu run`` resumes it after forking its
warm process, which keeps it paused for its short life (it imports and draws, then ends); every
other command as soon as its arguments are parsed. Nothing changes for a script that calls
:func:`railexu.cli.main` or the public functions: only the console script pauses.
"""

from __future__ import annotations

import gc

_paused = False


def pause() -> None:
    """Stop cyclic garbage collection until :func:`resume` (the console script's first step)."""
    global _paused
    gc.disable()
    _paused = True


def resume() -> None:
    """Freeze the objects made so far and collect cycles again, if :func:`pause` stopped it;
    otherwise nothing."""
    global _paused
    if not _paused:
        return
    _paused = False
    gc.freeze()
    gc.enable()
