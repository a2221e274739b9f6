"""The recorded signals of a run: :class:`railexu.simulation.timeseries.TimeSeries` (re-exported
here)."""

from railexu.simulation.timeseries import *  # noqa: F403
from railexu.simulation.timeseries import ResultsError as ResultsError
from railexu.simulation.timeseries import TimeSeries as TimeSeries
