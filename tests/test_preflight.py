"""The initial lateral offset of a run, checked against the wheel and rail profiles."""

from __future__ import annotations

from pathlib import Path

import pytest

from railexu.errors import InputError
from railexu.operation.run_settings import RunSettings
from railexu.simulation.preflight import check_initial_offset
from railexu.track.track import ideal_straight_track
from railexu.vehicle.vehicle import load_vehicle

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"


@pytest.fixture(scope="module")
def eu07():
    return load_vehicle(VEHICLES / "eu07.yaml")


def test_the_seed_offset_starts_on_the_tread(eu07):
    assert check_initial_offset(eu07, ideal_straight_track(), RunSettings()) == []


@pytest.mark.parametrize("offset_m", [0.007, -0.007])
def test_an_offset_into_flange_contact_is_warned_with_the_flange_onset(eu07, offset_m):
    warnings = check_initial_offset(
        eu07, ideal_straight_track(), RunSettings(initial_lateral_m=offset_m)
    )
    assert len(warnings) == 4  # one per wheelset
    assert "flange contact" in warnings[0]
    # S1002 on UIC60 1:40 with 1360 mm flange back: flange contact begins between 6 and 7 mm
    # of lateral shift (the Manchester benchmark's flange onset, Shackleton and Iwnicki 2008,
    # 6.0-7.0 mm; the scan's resolution is 0.25 mm)
    onset_mm = float(warnings[0].split("flange contact begins at ")[1].split(" mm")[0])
    assert 5.75 <= abs(onset_mm) <= 7.0
    assert onset_mm * offset_m > 0  # on the side of the offset


@pytest.mark.parametrize("offset_m", [0.015, 0.019, -0.019])
def test_an_offset_that_lifts_a_wheel_up_its_flange_is_refused(eu07, offset_m):
    with pytest.raises(InputError, match="initial_lateral: .* up its flange") as info:
        check_initial_offset(eu07, ideal_straight_track(), RunSettings(initial_lateral_m=offset_m))
    assert "flange contact begins at" in str(info.value)
