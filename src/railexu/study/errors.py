"""The exceptions and warnings of parameter studies."""

from railexu.errors import InputError


class StudyError(InputError):
    """A study cannot run as asked: its output folder holds another study's results, another
    study is running in it, bad worker settings."""


class StudyWarning(UserWarning):
    """Something in a study's results to look at (a ``collect`` path missing from a result)."""
