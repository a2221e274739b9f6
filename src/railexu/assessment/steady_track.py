"""The parts of a run in which the track under a wheelset does not change its curvature: where
the sustained oscillations of the wheelsets are fitted (issue 28).

In a curve transition the curvature and the cant change along the track and every wheelset
follows them quasi-statically: its lateral position and its angle of attack move from their
straight-track values to their values in the curve within the time the transition takes
(2 s for 60 m at 30 m/s). To the oscillation fit (:mod:`railexu.assessment.oscillation`) that
slow change looks like a fraction of a period of a 0.3 Hz "oscillation" whose envelope grows;
it is the track's quasi-static response, not a motion of the vehicle's own. The rule (railexu's
choice): a wheelset's oscillations are fitted only over the longest part of the evaluation
window in which the track's curvature under that wheelset is constant (a straight or a
constant-radius curve), transitions excluded."""

from __future__ import annotations

import numpy as np

#: Curvature changes smaller than this between two samples count as none [1/m] (rounding; a
#: clothoid of 60 m to R 600 m changes by 2.8e-5 1/m per metre run).
CURVATURE_TOLERANCE_1_PER_M = 1.0e-9

RULE = (
    "each wheelset's oscillations are fitted over the longest part of the evaluation window in "
    "which the track's curvature under that wheelset is constant (curve transitions excluded: "
    "their quasi-static change is the track's, not an oscillation; railexu's choice)"
)


def curvature_under(
    s_m: np.ndarray, track_s_m: np.ndarray, curvature_1_per_m: np.ndarray
) -> np.ndarray:
    """The track's curvature [1/m] at the distances ``s_m`` (a wheelset's), from the curvature
    recorded at ``track_s_m`` (the leading wheelset's distances, increasing)."""
    return np.interp(s_m, track_s_m, curvature_1_per_m)


def longest_constant_span(curvature_1_per_m: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """Mask of the longest run of consecutive samples within ``inside`` at which the curvature
    does not change from the sample before nor to the sample after (all False when none)."""
    k = np.asarray(curvature_1_per_m, dtype=float)
    steady = np.asarray(inside, dtype=bool).copy()
    if k.size > 1:
        change = np.abs(np.diff(k)) > CURVATURE_TOLERANCE_1_PER_M
        steady[1:] &= ~change
        steady[:-1] &= ~change
    mask = np.zeros_like(steady)
    if not np.any(steady):
        return mask
    edges = np.diff(np.concatenate([[0], steady.astype(np.int8), [0]]))
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0]
    j = int(np.argmax(ends - starts))
    mask[starts[j] : ends[j]] = True
    return mask
