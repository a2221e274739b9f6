"""Wheel-rail contact: geometry, normal (Hertz) and tangential (Kalker, Polach, FASTSIM) forces."""
