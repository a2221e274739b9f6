"""The recorded signals of a run: :class:`railexu.timeseries.TimeSeries` (re-exported here)."""

from ..timeseries import *  # noqa: F403
from ..timeseries import ResultsError as ResultsError
from ..timeseries import TimeSeries as TimeSeries
