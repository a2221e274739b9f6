"""railexu.model.record_row: the compiled derailment check against its definition written out with
numpy (rise of each wheel above its static height; lateral displacement from the track centre
line), for random wheelset poses, with and without irregularities."""

from __future__ import annotations

import numpy as np

from railexu.model.forces import WL_LATERAL, WL_ROLL, WL_S, WL_SIZE, WL_VERTICAL
from railexu.model.record_row import ROW_KEPT, ROW_OFF_TRACK, ROW_WHEEL_ROSE, derailment


def _reference(loc, z0, sin_roll0, e, lift, cx, cy, lateral_limit):
    droll = e * (np.sin(loc[:, WL_ROLL]) - sin_roll0)
    left = loc[:, WL_VERTICAL] - z0 + droll
    right = loc[:, WL_VERTICAL] - z0 - droll
    rise = np.maximum(left, right)
    centre = np.interp(loc[:, WL_S], cx, cy, left=0.0, right=0.0) if cx.size else 0.0
    y = loc[:, WL_LATERAL] - centre
    if (rise > lift).any():
        w = int(np.argmax(rise > lift))
        return ROW_WHEEL_ROSE, w, 0 if left[w] > right[w] else 1, rise[w], y[w]
    if (np.abs(y) > lateral_limit).any():
        w = int(np.argmax(np.abs(y) > lateral_limit))
        return ROW_OFF_TRACK, w, 0, 0.0, y[w]
    return ROW_KEPT, 0, 0, 0.0, 0.0


def test_the_compiled_check_matches_its_definition():
    rng = np.random.default_rng(7)
    verdicts = set()
    for trial in range(400):
        n = 4
        loc = np.zeros((n, WL_SIZE))
        loc[:, WL_S] = rng.uniform(0.0, 120.0, n)
        loc[:, WL_LATERAL] = rng.normal(0.0, 0.02, n)
        loc[:, WL_VERTICAL] = rng.normal(0.0, 0.01, n)
        loc[:, WL_ROLL] = rng.normal(0.0, 0.01, n)
        z0 = rng.normal(0.0, 0.001, n)
        sin_roll0 = np.sin(rng.normal(0.0, 0.001, n))
        e = np.full(n, 0.75)
        lift = np.full(n, 0.012)
        if trial % 2:
            cx = np.linspace(0.0, 100.0, 201)
            cy = rng.normal(0.0, 0.01, cx.size)
        else:
            cx = cy = np.zeros(0)
        got = derailment(loc, z0, sin_roll0, e, lift, cx, cy, 0.04)
        want = _reference(loc, z0, sin_roll0, e, lift, cx, cy, 0.04)
        assert got[:3] == want[:3]
        np.testing.assert_allclose(got[3:], want[3:], rtol=1e-12, atol=1e-15)
        verdicts.add(got[0])
    assert verdicts == {ROW_KEPT, ROW_OFF_TRACK, ROW_WHEEL_ROSE}  # every branch exercised
