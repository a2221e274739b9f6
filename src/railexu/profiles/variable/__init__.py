"""Rail profiles that vary along the track: switches and crossings (issue 29).

A *variable rail profile* is a sequence of profile slices at stated track positions ``s``
(switch blade and stock rail through the switch panel, wing rail and nose through the crossing),
read from CONTACT's ``.slcs`` files (:mod:`.slcs`) or railexu's own YAML (:mod:`.yaml_slices`),
checked (:mod:`.slices`: slices in order, not overlapping, interpolable) and interpolated between
slices (:mod:`.interpolate`) so that the surface is smooth where it is smooth and keeps its real
edges (blade tip, nose start) where the slices' *feature points* mark them.

Coordinates (those of CONTACT and SIMPACK profiles, in metres): ``y`` lateral, towards the field
side for a right rail; ``z`` *downwards* (a rail's top has the smallest ``z``). ``s`` is the
distance along the track [m].
"""

from railexu.profiles.variable.interpolate import VariableProfile
from railexu.profiles.variable.slcs import read_slcs
from railexu.profiles.variable.slices import ProfileSlices, check_slices
from railexu.profiles.variable.yaml_slices import read_yaml_slices

__all__ = [
    "ProfileSlices",
    "VariableProfile",
    "check_slices",
    "read_slcs",
    "read_yaml_slices",
]
