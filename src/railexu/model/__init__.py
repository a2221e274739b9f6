"""Layer 5, the model: the Exudyn multibody model of a vehicle on its track.

:mod:`~railexu.model.assembly` builds it (bodies on trajectory coordinates that follow the
track, connectors and spring-dampers); :mod:`~railexu.model.forces` holds the compiled
generalized forces of all wheelsets' contacts (one Exudyn user-function object) and of the bump
stops; :mod:`~railexu.model.suspension_forces` those of the nonlinear suspension elements, with
their characteristics in :mod:`~railexu.model.characteristics`; :mod:`~railexu.model.statics`
the static equilibrium; :mod:`~railexu.model.record_row` the recorder's compiled copy.
"""
