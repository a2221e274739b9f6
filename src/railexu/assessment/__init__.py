"""Assessment of a run: the quantities an engineer reports, each with its limit and source.

- :mod:`.signals`: sliding means and rms, windowed means, percentiles, zero crossings, amplitude;
- :mod:`.filters`: Butterworth low and band pass, EN 12299 / ISO 2631 weightings (scipy.signal);
- :mod:`.en14363`: EN 14363 on-track quantities (Y/Q, sum Y, running stability) and limits;
- :mod:`.safety`: derailment criteria beyond Y/Q (wheel unloading, flange climb);
- :mod:`.comfort`: EN 12299 mean comfort N_MV and Sperling's ride index;
- :mod:`.hunting`: hunting told apart from track-forced response;
- :mod:`.criterion`: the :class:`Criterion` record (value, limit, where, window, rule, pass).

``docs/assessment.md`` explains each quantity and limit with the clause of its standard.
"""

from railexu.assessment.criterion import Criterion

__all__ = ["Criterion"]
