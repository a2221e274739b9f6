"""Layer 6, one run: checks of its start (:mod:`~railexu.simulation.preflight`), the
integration (:mod:`~railexu.simulation.simulate`), the recorder and its signals
(:mod:`~railexu.simulation.recorder`, :mod:`~railexu.simulation.longitudinal`,
:mod:`~railexu.simulation.timeseries`) and the track-relative curving quantities
(:mod:`~railexu.simulation.curving`).
"""
