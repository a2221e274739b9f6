"""Checks shared by the wear-loop tests (issue 30)."""

from __future__ import annotations


def assert_steps_conserve_volume(steps, keys=("ws1_left", "ws1_right"), tolerance=0.01) -> None:
    """Every step after the first and every wheel ``keys``: some area was worn and the area
    between the old and the new profile equals the integral of the patches' volume rates within
    ``tolerance`` (the issue's 1 %; ``steps.csv``'s ``_conservation_error``)."""
    assert steps
    for row in steps:
        for key in keys:
            assert row[f"{key}_area_mm2"] > 0.0
            assert abs(row[f"{key}_conservation_error"]) < tolerance, (key, row)
