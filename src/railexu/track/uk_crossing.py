"""The shipped UK crossing 56E1-R245-1:9.25 as variable rails, for a route and a direction.

The interface for tracks that place the crossing themselves (a turnout: the switch panel before
it, issue 29): :func:`crossing_rails` returns the crossing's
:class:`~railexu.track.variable_rails.VariableRails` (the wing rail and nose on the crossing
side, the check rail beside the opposite stock rail) from the shipped track files
``tracks/uk_crossing_{facing,trailing}.yaml`` (docs/switches-and-crossings.md). Their plain rail
is the crossing's own vertical 56E1 (``tracks/uk_crossing/uk_56e1_plain.txt``): a track that
carries the crossing should carry that rail, uninclined, so that the zone starts and ends
without a step.
"""

from __future__ import annotations

from railexu.errors import InputError
from railexu.track.track import load_track
from railexu.track.variable_rails import VariableRails

ROUTES = ("through",)
DIRECTIONS = ("facing", "trailing")


def crossing_rails(
    route: str = "through", direction: str = "facing", start_m: float = 30.0
) -> VariableRails:
    """The crossing's variable rails with the slices' ``s = 0`` at track distance ``start_m``
    [m] (the crossing side on the left, as the shipped files; the zone spans ``s`` from -2.9 to
    +2.8 m, the check rail's extent).

    Raises:
        InputError: an unknown route or direction (the diverging route's crossing slices are
            not in the benchmark's data).
    """
    if route not in ROUTES:
        raise InputError(f"UK crossing: route {route!r}: expected one of {ROUTES}")
    if direction not in DIRECTIONS:
        raise InputError(f"UK crossing: direction {direction!r}: expected one of {DIRECTIONS}")
    track = load_track(f"uk_crossing_{direction}", overrides=f"variable_rails.start={start_m} m")
    return track.variable_rails
