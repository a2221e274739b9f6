"""`python -m railexu.cli`: the same as the `railexu` command."""

from . import entry_point

entry_point()
