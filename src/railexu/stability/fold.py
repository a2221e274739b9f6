"""Where a followed limit cycle ends, with no chosen factor: a fold is a discontinuity of the
cycle's amplitude in speed, detected by refinement (issue 28).

A limit cycle followed down in speed (each speed starting from the settled cycle of the speed
above) changes its amplitude continuously along its branch: across a speed bracket of width h
the change shrinks with h (in proportion for a smooth branch). Across a fold (a saddle-node of
periodic solutions, True 1999, "On the theory of nonlinear dynamics and its applications in
vehicle systems dynamics", Vehicle System Dynamics 31) the cycle ceases to exist and the motion
falls onto another attractor (a smaller cycle, or rest): the change across the bracket that
holds the fold stays the whole jump however narrow the bracket is.

So a bracket is refined (stepped again in equal sub-steps, each starting from the state of the
sub-step above) and the changes of the attractor's amplitude across the sub-steps are compared
(:func:`concentrated`): where the largest fall exceeds all the other changes together, the
change did not spread over the sub-steps as it does on a continuous branch (there the largest
of n equal sub-steps carries about 1/n of the whole); the fold then lies in that sub-step, which
is refined in turn. A plateau that is not stable is on an attractor of its fitted amplitude; a
stable one (decaying, the envelope still falling towards a lower attractor, or at rest)
counts as amplitude 0: the motion has left every cycle at or above its fitted amplitude. The
comparison is between measured changes: there is no factor to choose, and the verdict does not
depend on the number of sub-steps (``tests/test_stability_fold.py`` runs it with quarters and
thirds)."""

from __future__ import annotations


def attractor_amplitude(plateau: dict) -> float | None:
    """The amplitude [m] of the attractor a plateau's motion is on: its fitted amplitude when it
    is not stable (a sustained or growing cycle), 0 when it is stable (decaying or at rest:
    module docstring), None when it has no verdict (not reached, too short)."""
    stable = plateau.get("stable")
    if stable is None:
        return None
    if stable:
        return 0.0
    return float(plateau.get("amplitude_m") or 0.0)


def largest_fall(amplitudes_m: list[float]) -> int | None:
    """Index j of the largest fall ``amplitudes_m[j] - amplitudes_m[j + 1] > 0`` (speeds
    falling along the list), None when the amplitude never falls."""
    best, at = 0.0, None
    for j in range(len(amplitudes_m) - 1):
        fall = amplitudes_m[j] - amplitudes_m[j + 1]
        if fall > best:
            best, at = fall, j
    return at


def concentrated(amplitudes_m: list[float]) -> dict:
    """Whether the change of amplitude along one refined bracket (``amplitudes_m`` at equally
    spaced falling speeds, the bracket's ends included) sits in one sub-step: ``index`` (the
    sub-step of the largest fall, None if none falls), ``largest_fall_m``, ``other_change_m``
    (the sum of the absolute changes across the other sub-steps) and ``jump`` (the largest fall
    exceeds the other changes together: a discontinuity at this resolution)."""
    j = largest_fall(amplitudes_m)
    if j is None:
        return {"index": None, "largest_fall_m": 0.0, "other_change_m": None, "jump": False}
    changes = [abs(a - b) for a, b in zip(amplitudes_m[:-1], amplitudes_m[1:], strict=True)]
    fall = changes[j]
    other = sum(changes) - fall
    return {"index": j, "largest_fall_m": fall, "other_change_m": other, "jump": fall > other}


def nearer_to_upper(amplitude_m: float | None, upper_m: float, lower_m: float) -> bool:
    """A restart with ``amplitude_m`` is on the upper attractor (amplitude ``upper_m``) rather than
    the lower one (``lower_m``): nearer to it."""
    if amplitude_m is None:
        return False
    return abs(amplitude_m - upper_m) < abs(amplitude_m - lower_m)
