"""The wear loop: a vehicle's wheel profiles worn over a route's mileage (docs/wear.md).

* :mod:`.route`: the route file (sections with their mileage shares, both directions) and the
  track file of each section's case;
* :mod:`.profiles`: smoothing of the worn depth, the profile update (files railexu reads back),
  flange height, flange thickness and qR;
* :mod:`.loop`: :func:`~.loop.wear_loop` (``railexu wear``).
"""
