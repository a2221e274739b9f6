"""Vehicle and track files: the shipped files, and clear errors for bad ones (file, line, key)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from railexu.inputs import InputError, apply_overrides, parse_yaml
from railexu.statics import static_equilibrium
from railexu.track import load_track
from railexu.units import UnitError, to_si
from railexu.vehicle import BumpStop, SpringDamper, TorsionSpring, load_vehicle

ROOT = Path(__file__).resolve().parents[1]
VEHICLES = ROOT / "vehicles"
TRACKS = ROOT / "tracks"


@pytest.mark.parametrize("name", ["eu07", "eu07_bogie", "wheelset", "manchester_coach"])
def test_shipped_vehicles_load_and_stand_in_equilibrium(name):
    vehicle = load_vehicle(VEHICLES / f"{name}.yaml")
    statics = static_equilibrium(vehicle, [0.75] * len(vehicle.wheelsets))
    weight = vehicle.total_mass_kg * vehicle.gravity_m_per_s2
    external = -sum(load.force_N[2] for load in vehicle.loads)
    # the wheel loads carry the weight and the vertical loads (force balance, 1e-9 relative)
    assert np.sum(statics.wheel_loads_N) == pytest.approx(weight + external, rel=1e-9)
    # symmetric vehicles: left = right on every axle
    np.testing.assert_allclose(statics.wheel_loads_N[:, 0], statics.wheel_loads_N[:, 1], rtol=1e-9)


def test_eu07_data():
    """80 t, Bo'Bo', 1250 mm wheels, S1002; 196.2 kN per axle; every value that no public source
    gives is marked as an estimate with its basis."""
    vehicle = load_vehicle(VEHICLES / "eu07.yaml")
    assert vehicle.total_mass_kg == pytest.approx(80000.0, rel=1e-9)
    assert len(vehicle.wheelsets) == 4 and len(vehicle.bodies) == 3
    for ws in vehicle.wheelsets:
        assert ws.nominal_radius_m == pytest.approx(0.625)
        assert ws.wheel_profile == "S1002"
        assert ws.estimate
    for body in vehicle.bodies:
        assert body.estimate
    statics = static_equilibrium(vehicle, [0.75] * 4)
    np.testing.assert_allclose(statics.wheel_loads_N.sum(axis=1), 80000 * 9.81 / 4, rtol=1e-6)
    raw = vehicle.raw
    for name, entry in raw["suspension"].items():
        assert "estimate" in entry or "<<" in entry or name.endswith(("_2", "ws2", "ws3", "ws4"))
    kinds = {type(el) for el in vehicle.suspension}
    assert kinds == {SpringDamper, TorsionSpring, BumpStop}


def test_manchester_coach_data():
    vehicle = load_vehicle(VEHICLES / "manchester_coach.yaml")
    assert vehicle.total_mass_kg == pytest.approx(32000 + 2 * 2615 + 4 * 1813)
    primary = next(el for el in vehicle.suspension if el.name == "primary_ws1_left")
    assert primary.stiffness_N_per_m == pytest.approx((31391e3, 3884e3, 1220e3))


def test_tracks_load():
    ideal = load_track(TRACKS / "straight.yaml")
    assert ideal.irregularity.type == "none"
    assert ideal.inclination_rad == pytest.approx(np.arctan(1 / 40))
    irregular = load_track(TRACKS / "straight_irregular.yaml")
    profile = irregular.irregularities(200.0)
    assert irregular.irregularity.spectrum == "german_low"
    # German low level, 3-150 m: lateral rms ~2 mm (the band integral of the spectrum)
    x = np.linspace(20.0, 190.0, 3401)
    dy_left, _ = profile.left_rail_offsets(x)
    assert 0.5e-3 < np.std(dy_left) < 5e-3
    # same seed, same track
    again = load_track(TRACKS / "straight_irregular.yaml").irregularities(200.0)
    np.testing.assert_array_equal(profile.lateral_m, again.lateral_m)


def test_units():
    assert to_si("80 t", "kg") == 80000.0
    assert to_si("1220 kN/m", "N/m") == pytest.approx(1.22e6)
    assert to_si("4 kN s/m", "N s/m") == pytest.approx(4000.0)
    assert to_si("10.5 kN m/rad", "N m/rad") == pytest.approx(10500.0)
    assert to_si("1120 kg m^2", "kg m^2") == 1120.0
    assert to_si("125 km/h", "m/s") == pytest.approx(34.7222, rel=1e-5)
    assert to_si("1e9", "N/m") == 1e9  # YAML 1.1 reads 1e9 as text
    assert to_si(0.625, "m") == 0.625
    with pytest.raises(UnitError, match="wrong dimension"):
        to_si("80 m", "kg")
    with pytest.raises(UnitError, match="unknown unit"):
        to_si("3 furlongs", "m")


def _write(tmp_path: Path, text: str, name: str = "bad.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _eu07_text() -> str:
    return (VEHICLES / "eu07.yaml").read_text()


def _error(tmp_path, text) -> str:
    with pytest.raises(InputError) as info:
        load_vehicle(_write(tmp_path, text))
    return str(info.value)


def test_missing_key_names_file_line_and_key(tmp_path):
    text = _eu07_text().replace("    mass: 46.4 t\n", "")
    message = _error(tmp_path, text)
    assert re.search(r"bad\.yaml:\d+: bodies\.car_body: missing key 'mass'", message)


def test_wrong_type(tmp_path):
    message = _error(tmp_path, _eu07_text().replace("mass: 46.4 t", "mass: heavy"))
    assert "bodies.car_body.mass" in message and "expected '<number> <unit>'" in message


def test_negative_mass(tmp_path):
    message = _error(tmp_path, _eu07_text().replace("mass: 46.4 t", "mass: -46.4 t"))
    assert "bodies.car_body.mass: must be > 0 kg" in message


def test_wrong_unit(tmp_path):
    message = _error(tmp_path, _eu07_text().replace("mass: 46.4 t", "mass: 46.4 m"))
    assert "wrong dimension: expected a value in kg" in message


def test_unknown_key_did_you_mean(tmp_path):
    message = _error(tmp_path, _eu07_text().replace("    mass: 46.4 t", "    mas: 46.4 t"))
    assert "bodies.car_body.mas: unknown key. Did you mean 'mass'?" in message
    line = int(re.search(r"bad\.yaml:(\d+):", message).group(1))
    assert _eu07_text().splitlines()[line - 1].strip().startswith("mass")


def test_unknown_profile(tmp_path):
    message = _error(tmp_path, _eu07_text().replace("wheel_profile: S1002", "wheel_profile: S1020"))
    assert "wheelsets.ws1.wheel_profile" in message and "Did you mean 'S1002'" in message


def test_unknown_body_in_suspension(tmp_path):
    message = _error(
        tmp_path, _eu07_text().replace("bodies: [bogie_1, ws1]", "bodies: [bogie1, ws1]")
    )
    assert (
        "suspension.primary_ws1.bodies: unknown body 'bogie1'. Did you mean 'bogie_1'?" in message
    )


def test_unphysical_inertia(tmp_path):
    text = _eu07_text().replace("roll: 59000 kg m^2", "roll: 5900 kg m^2")
    message = _error(tmp_path, text.replace("pitch: 896000 kg m^2", "pitch: 800000 kg m^2"))
    assert "triangle inequality" in message


def test_yaml_syntax_error_has_line(tmp_path):
    message = _error(tmp_path, "format_version: 1\nname: [unclosed\n")
    assert "bad.yaml:" in message and "YAML syntax error" in message


def test_wrong_format_version(tmp_path):
    message = _error(tmp_path, _eu07_text().replace("format_version: 1", "format_version: 7"))
    assert "format_version 7 is not supported" in message


def test_missing_file():
    with pytest.raises(InputError, match="file not found"):
        load_vehicle(ROOT / "vehicles" / "no_such_vehicle.yaml")


def test_overrides():
    vehicle = load_vehicle(VEHICLES / "eu07.yaml", ["bodies.car_body.mass=50 t"])
    assert vehicle.bodies[0].mass_kg == 50000.0
    data, _ = parse_yaml("a: {b: 1, c: [1, 2]}")
    assert apply_overrides(data, ["a.c.1=5"])["a"]["c"] == [1, 5]
    with pytest.raises(InputError, match="Did you mean 'bodies'"):
        load_vehicle(VEHICLES / "eu07.yaml", ["bodys.car_body.mass=50 t"])
    with pytest.raises(InputError, match="no list item"):
        apply_overrides(data, ["a.c.7=1"])


def test_bad_track(tmp_path):
    text = (TRACKS / "straight_irregular.yaml").read_text().replace("german_low", "german_lo")
    with pytest.raises(InputError, match="german_low"):
        load_track(_write(tmp_path, text, "track.yaml"))
    text = (
        (TRACKS / "straight.yaml")
        .read_text()
        .replace("type: none", "type: measured\n  file: x.csv")
    )
    with pytest.raises(InputError, match="x.csv' not found"):
        load_track(_write(tmp_path, text, "track2.yaml"))
