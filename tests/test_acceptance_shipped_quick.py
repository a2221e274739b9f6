"""Every shipped vehicle through the quick (reduced) programme of its category (issue 27):
``railexu.acceptance(name, quick=True)``, 15 sections in 4 zones and both quasi-static tests,
about half a minute each on 2 cores (``benchmarks/acceptance.py VEHICLE --quick``).

What is checked is what must hold whatever the vehicle: every section runs to its end, every
zone is evaluated (the quick programme's minimum of sections), the quasi-static tests complete,
and the verdict is never ``pass`` (a quick programme is a trend). One physical check per curve
zone: the car body's quasi-static lateral acceleration at the zone's limit conditions is the
accelerometer's ``g I / b`` (I the cant deficiency, b = 1.5 m the distance of the rails'
contact points: the uncompensated lateral acceleration in the track plane) plus the body's
outward roll on its suspension, which adds a share of it (the flexibility coefficient s of
EN 15273 / UIC 505: 0.1-0.4 for these vehicles). The bound ``g I / b <= a <= 1.4 g I / b`` is
that physical range; the estimate is the two-dimensional regression of four sections without a
dispersion term.
"""

from __future__ import annotations

import json

import pytest

G = 9.81  # m/s^2
B_M = 1.5  # m, lateral distance of the rails' contact points (standard gauge)

SHIPPED = ("eu07", "manchester_coach_extended", "hbbins_loaded", "hbbins_empty")


@pytest.mark.slow
@pytest.mark.parametrize("vehicle", SHIPPED)
def test_a_shipped_vehicle_through_its_quick_programme(tmp_path, vehicle):
    from railexu.study.acceptance import run_acceptance

    out = tmp_path / "acc"
    result = run_acceptance(vehicle, out, quick=True, workers=2, progress=lambda line: None)
    data = json.loads((out / "acceptance.json").read_text())
    assert result.verdict in ("fail", "incomplete") and data["programme"]["quick"] is True
    assert "quick" in data["verdict"]["missing"][0]
    for name, zone in data["zones"].items():
        assert not zone.get("error"), f"{vehicle} {name}: {zone.get('error')}"
        counts = zone["study"]["counts"]
        finished = counts.get("completed", 0) + counts.get("completed_with_exceedances", 0)
        assert finished == zone["sections_run"] >= 3, f"{vehicle} {name}: {counts}"
        if zone["conditions"]["kind"] != "curve":
            continue
        at = dict(zip(zone["conditions"]["regressors"], zone["conditions"]["evaluate_at"],
                      strict=True))  # fmt: skip
        uncompensated = G * at["cant_deficiency"] / B_M
        measured = zone["criteria"]["car_body_acc_y_qst"]["value"]
        assert uncompensated <= measured <= 1.4 * uncompensated, (vehicle, name, measured)
    assert data["twist_test"]["status"] == "completed"
    assert data["yaw_resistance_test"]["status"] in ("completed", "not_applicable")
