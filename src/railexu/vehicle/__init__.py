"""Layer 4, the vehicle: bodies, wheelsets, suspension elements, loads, measurement points.

:mod:`~railexu.vehicle.parts` (the parts a vehicle is made of), :mod:`~railexu.vehicle.vehicle`
(:class:`Vehicle`, :func:`load_vehicle`), its schema (:mod:`~railexu.vehicle.schema`) and the
checks of its topology (:mod:`~railexu.vehicle.checks`). ``docs/vehicle-format.md`` documents
the file.
"""
