"""railexu's own exception types: the bottom of the package, imported by every layer.

:class:`InputError` is the one type for bad input (a file, an option, a value out of its
physical range). The command line turns it, and only it, into a short message naming the file,
the line and the key, with exit code 2; any other exception is a defect of railexu and is shown
with its traceback.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad input: the message names file, line and key and says what was expected.

    Every loader and check of railexu raises this type (or a subclass of it) for input that is
    malformed, unknown or physically absurd.
    """

    def __init__(self, message: str, *, source: str = "", line: int | None = None, key: str = ""):
        where = source
        if line is not None:
            where = f"{where}:{line}" if where else f"line {line}"
        prefix = ": ".join(p for p in (where, key) if p)
        super().__init__(f"{prefix}: {message}" if prefix else message)
        self.source = source
        self.line = line
        self.key = key
        self.detail = message


def did_you_mean(name: str, choices, cutoff: float = 0.6, n: int = 1, known: bool = True) -> str:
    """`` Did you mean 'x'?`` for the closest of ``choices`` (up to ``n``, case-insensitive),
    else `` Known: a, b, c`` (or nothing when ``known`` is false).

    The one did-you-mean helper of railexu (loaders, registries, overrides, the command line).
    Returns a string that starts with a space, ready to append to a message.
    """
    import difflib

    names = [str(c) for c in choices]
    lower = {c.lower(): c for c in names}
    close = difflib.get_close_matches(str(name).lower(), list(lower), n=n, cutoff=cutoff)
    if close:
        return " Did you mean " + " or ".join(repr(lower[c]) for c in close) + "?"
    return f" Known: {', '.join(names)}" if names and known else ""


class ComputationError(RuntimeError):
    """A computation that could not be completed for a physical or numerical reason (no
    equilibrium found, a contact that cannot be pressed): reported as a failure (exit code 1),
    not as a defect."""


class RunInterrupted(KeyboardInterrupt):
    """A run or a study stopped by Ctrl-C (SIGINT): raised by ``railexu.run`` and
    ``railexu.run_study`` after they kept what was done, so that a script (a loop of runs, a
    test runner) stops instead of carrying on with its next line.

    A subclass of :class:`KeyboardInterrupt`: ``except Exception`` does not swallow it, and
    ``except KeyboardInterrupt`` catches it as it catches any Ctrl-C.

    Attributes:
        result: what was done: the interrupted run's ``RunResult`` (status ``interrupted``, the
            time series up to the stop, the summary; ``railexu.write_run`` writes it) or the
            study's ``StudyResult`` (the finished cases); None when the stop came before there
            was any.
        signal_name: ``"SIGINT"`` or ``"SIGTERM"``.
    """

    signal_name = "SIGINT"

    def __init__(self, message: str = "", result: object = None) -> None:
        super().__init__(message or f"interrupted ({self.signal_name})")
        self.result = result


class RunTerminated(RunInterrupted):
    """A run or a study stopped by SIGTERM (``kill``, ``timeout``, a container or a CI job
    stopped): as :class:`RunInterrupted` (whose subclass it is, so that one ``except`` clause
    handles both stops), with ``signal_name`` ``"SIGTERM"``."""

    signal_name = "SIGTERM"


def interruption(signal_name: str, result: object = None) -> RunInterrupted:
    """The exception for a stop by ``signal_name`` (``"SIGINT"`` or ``"SIGTERM"``)."""
    kind = RunTerminated if signal_name == "SIGTERM" else RunInterrupted
    return kind(result=result)
