"""No flange, no flange-climb verdict (issue 26): a wheel without a flange has nothing to climb,
so Nadal's criterion does not apply to it. Before, a cone got "flange climb ... EXCEEDED"
against the negative Nadal value of its tread slope, tan(g) < mu: (0.05 - 0.3) / (1 + 0.015)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railexu.assessment.en14363 import nadal_limit
from railexu.assessment.safety import (
    MIN_FLANGE_HEIGHT_M,
    flange_climb_criterion,
    flange_climb_not_applicable,
    has_flange,
)
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.track.track import track_from_dict
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


def test_a_cone_gets_no_flange_climb_verdict():
    """The cone's Nadal value is negative (the old false alarm); its criterion is reported as
    not applicable and cannot be exceeded, while the same Y/Q on a flanged wheel is judged."""
    assert nadal_limit(np.arctan(0.05), 0.3) < 0.0
    x = np.linspace(0.0, 20.0, 401)
    yq = {"ws1_left": np.full_like(x, 0.1)}
    flanged = flange_climb_criterion(x, yq, nadal_limit(np.radians(70.0), 0.3), 0.0, 20.0)
    assert flanged.passed is True and flanged.details["applicable"] is True
    cone = flange_climb_not_applicable(0.0035)
    assert cone.value is None and cone.limit is None and cone.passed is None
    assert not cone.exceeded and cone.details["applicable"] is False
    assert "no flange" in cone.details["note"]
    assert has_flange(0.028) and has_flange(None) and not has_flange(0.5 * MIN_FLANGE_HEIGHT_M)


def test_a_run_on_cones_reports_flange_climb_not_applicable():
    """A wheelset with 1:20 cones (a 3.5 mm rise over 70 mm: no flange) on round rails: the
    summary has no Nadal limit and the criterion not applicable; with S1002 wheels (28 mm
    flange) the criterion is evaluated."""
    track = track_from_dict({"format_version": 1, "name": "straight",
                             "rail_profile": "round:0.05", "inclination": "none"})  # fmt: skip
    for wheel, applicable in (("cone:0.05", False), ("S1002", True)):
        vehicle = load_vehicle(ROOT / "vehicles" / "wheelset.yaml",
                               [f"wheelsets.ws1.wheel_profile={wheel}"])  # fmt: skip
        if applicable:
            track = track_from_dict({"format_version": 1, "name": "straight"})
        result = run(vehicle, track, RunSettings(speed_m_per_s=5.0, distance_m=5.0,
                                                 initial_lateral_m=0.0))  # fmt: skip
        assert result.status["state"] in COMPLETED_STATES, result.status
        climb = result.summary.flange_climb
        assert climb.details["applicable"] is applicable, wheel
        assert (result.summary.nadal_limit is not None) is applicable, wheel
        assert (climb.passed is None) is not applicable, wheel
        if not applicable:
            assert "flange_climb" not in result.summary.exceedances
            assert result.summary.to_dict()["max_Y_over_Q"]["nadal_limit"] is None
