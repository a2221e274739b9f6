"""Wheel-rail contact: geometry, normal (Hertz) and tangential (Kalker, Polach, FASTSIM) forces."""

from railexu.runtime.compiled_cache import refresh as _refresh_compiled_cache

# numba's cache of the compiled contact and force functions follows their current sources
_refresh_compiled_cache()
