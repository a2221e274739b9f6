"""`python -m railexu.cli`: the same as the `railexu` command."""

from railexu.cli import entry_point

entry_point()
