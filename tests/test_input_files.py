"""Vehicle and track files: the shipped files, and clear errors for bad ones (file, line, key)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from railexu.inputs import InputError, apply_overrides, parse_yaml
from railexu.model.statics import static_equilibrium
from railexu.track.track import load_track
from railexu.units import UnitError, to_si
from railexu.vehicle.vehicle import BumpStop, SpringDamper, TorsionSpring, load_vehicle

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
    message = _error(tmp_path, _eu07_text().replace("format_version: 2", "format_version: 7"))
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


# ----------------------------------------------------------------------------------------------
# A vehicle changed in code, derived quantities, shipped names (issue 7)
# ----------------------------------------------------------------------------------------------


def test_replace_returns_a_new_validated_vehicle_with_set_paths():
    eu07 = load_vehicle("eu07")  # a shipped name
    soft = eu07.replace("suspension.primary_ws*.stiffness.x", "4 MN/m")
    primaries = [el for el in soft.suspension if el.name.startswith("primary_ws")]
    assert len(primaries) == 8 and all(el.stiffness_N_per_m[0] == 4e6 for el in primaries)
    assert all(el.stiffness_N_per_m[0] == 8e6 for el in eu07.suspension[:8])  # unchanged
    # several pairs, in three spellings, with Python values or text with units
    a = eu07.replace("bodies.car_body.mass", "47 t", "wheelsets.ws1.mass", 4300.0)
    b = eu07.replace({"bodies.car_body.mass": "47 t", "wheelsets.ws1.mass": 4300.0})
    c = eu07.replace(("bodies.car_body.mass", 47000), ("wheelsets.ws1.mass", "4.3 t"))
    for v in (a, b, c):
        assert v.bodies[0].mass_kg == 47000.0 and v.wheelset("ws1").mass_kg == 4300.0
        assert v.total_mass_kg == pytest.approx(80000.0 + 600.0 + 50.0)
    # validated like a file: a bad value or path is an InputError
    with pytest.raises(InputError, match="must be > 0 kg"):
        eu07.replace("bodies.car_body.mass", "-1 t")
    with pytest.raises(InputError, match="Did you mean 'bodies'"):
        eu07.replace("bodys.car_body.mass", "47 t")


def test_derived_quantities_of_the_eu07():
    eu07 = load_vehicle("eu07")
    # 2 k_x b^2 per wheelset: two axleboxes of 8 MN/m at b = 1.05 m (file values)
    assert eu07.primary_yaw_stiffness_N_m_per_rad == pytest.approx(
        {f"ws{i}": 2 * 8e6 * 1.05**2 for i in range(1, 5)}, rel=1e-12
    )
    assert eu07.wheelbases_m == pytest.approx({"bogie_1": 3.0, "bogie_2": 3.0}, abs=1e-12)
    from railexu.model.statics import static_axle_loads_N

    # 80 t on four axles: 196.2 kN each (force balance of the statics, 1e-6 relative)
    loads = static_axle_loads_N(eu07)
    assert loads == pytest.approx({f"ws{i}": 80000 * 9.81 / 4 for i in range(1, 5)}, rel=1e-6)


def test_one_override_string_is_one_override():
    """A single string is one override, not a sequence of one-character overrides."""
    v = load_vehicle(VEHICLES / "eu07.yaml", overrides="bodies.car_body.mass=47 t")
    assert v.bodies[0].mass_kg == 47000.0
    t = load_track("straight", overrides="gauge=1.437 m")
    assert t.gauge_m == pytest.approx(1.437)


def test_shipped_names_and_paths():
    assert load_vehicle("eu07") == load_vehicle(VEHICLES / "eu07.yaml")
    assert load_track("straight_irregular").irregularity.spectrum == "german_low"
    with pytest.raises(InputError, match="Did you mean 'eu07'"):
        load_vehicle("eu70")
    with pytest.raises(InputError, match="file not found"):
        load_vehicle("no/such.yaml")


def test_asymmetric_wheelset_per_side():
    text = (VEHICLES / "wheelset.yaml").read_text()
    text = text.replace("wheel_profile: S1002", "wheel_profile: {left: S1002, right: S1002}")
    text = text.replace("nominal_radius: 0.625 m", "nominal_radius: {left: 625 mm, right: 0.62}")
    data, lines = parse_yaml(text)
    from railexu.vehicle.vehicle import vehicle_from_dict

    ws = vehicle_from_dict(data, "w.yaml", lines, VEHICLES).wheelsets[0]
    assert (ws.nominal_radius_m, ws.radius_right_m) == (0.625, 0.62)
    assert ws.wheel_profile == ws.profile_right == "S1002" and not ws.symmetric
    # a plain value means both sides
    plain = load_vehicle("wheelset").wheelsets[0]
    assert plain.radius_right_m == plain.nominal_radius_m == 0.625 and plain.symmetric


def test_format_version_1_is_read_as_version_2():
    """Version 1 contact keys (creep_model, polach_2005, damping_model, normal_damping whose
    unit followed damping_model) give the same contact parameters as version 2's nested ones."""
    v1 = """\
format_version: 1
name: w
category: locomotive
contact:
  creep_model: polach_2005
  polach_2005: {k_a: 0.5, k_s: 0.2, A: 0.3, B: 0.1 s/m}
  damping_model: linear
  normal_damping: 20 kN s/m
wheelsets:
  ws1: {position: [0], mass: 1 t, inertia: [500, 500, 100], wheel_profile: S1002,
        nominal_radius: 0.5}
"""
    v2 = v1.replace("format_version: 1", "format_version: 2").replace(
        """  creep_model: polach_2005
  polach_2005: {k_a: 0.5, k_s: 0.2, A: 0.3, B: 0.1 s/m}
  damping_model: linear
  normal_damping: 20 kN s/m""",
        """  creep: {model: polach_2005, k_a: 0.5, k_s: 0.2, A: 0.3, B: 0.1 s/m}
  normal_damping: {model: linear, coefficient: 20 kN s/m}""",
    )
    from railexu.vehicle.vehicle import vehicle_from_dict

    one, two = (vehicle_from_dict(*parse_yaml(t)).contact for t in (v1, v2))
    assert one == two
    assert (two.creep_model, two.polach_2005, two.damping_model, two.damping) == (
        "polach_2005", (0.5, 0.2, 0.3, 0.1), "linear", 20e3,
    )  # fmt: skip


def test_topology_errors_point_at_the_key():
    bogie = (VEHICLES / "eu07_bogie.yaml").read_text()
    from railexu.vehicle.vehicle import vehicle_from_dict

    def error(text: str) -> str:
        with pytest.raises(InputError) as info:
            data, lines = parse_yaml(text, "b.yaml")
            vehicle_from_dict(data, "b.yaml", lines, VEHICLES)
        return str(info.value)

    # wheelsets 0.1 m apart with 0.625 m wheels: the wheels overlap
    msg = error(bogie.replace("    position: [-1.5]", "    position: [1.4]"))
    assert re.match(r"b.yaml:\d+: wheelsets.ws1.position: wheelsets ws2 and ws1 are 0.1 m", msg)
    # the primary springs' vertical stiffness removed: nothing carries the frame
    msg = error(bogie.replace("z: 1.1 MN/m}", "z: 0}"))
    assert "bodies.bogie_1: this body is not carried" in msg
    # an axlebox 10.5 m from the centre line (a slipped decimal point)
    msg = error(bogie.replace("position: [1.5, 1.05, 0.625]", "position: [1.5, 10.5, 0.625]"))
    assert "suspension.primary_ws1.position: the point" in msg and "along y" in msg
    # the shipped vehicles pass, including the body-less wheelset
    for name in ("eu07", "eu07_bogie", "wheelset", "manchester_coach"):
        load_vehicle(name)


def test_box_half_sizes_recover_a_box():
    """The extent estimate inverts I = m (a^2 + b^2) / 12 exactly for a homogeneous box."""
    from railexu.vehicle.checks import box_half_sizes_m
    from railexu.vehicle.vehicle import Body

    m, (length, w, h) = 1000.0, (15.0, 3.0, 2.5)
    inertia = (m * (w**2 + h**2) / 12, m * (length**2 + h**2) / 12, m * (length**2 + w**2) / 12)
    body = Body("box", m, inertia, (0.0, 0.0, 1.0))
    assert box_half_sizes_m(body) == pytest.approx((length / 2, w / 2, h / 2), rel=1e-12)


def test_different_wheels_left_and_right_reach_the_model_geometry():
    """A wheelset with wheels of 1250 and 1248 mm: the placed geometry carries each radius, and
    the wheelset rolls freely off-centre, towards the smaller wheel (EN 15302's asymmetric
    cases; the contact layer's equilibrium)."""
    from railexu.contact.conicity import equilibrium_lateral
    from railexu.contact.evaluation import WheelsetContactModel
    from railexu.contact.quasistatic import rolling_radius_difference
    from railexu.model.assembly import wheelset_geometry
    from railexu.track.track import ideal_straight_track

    vehicle = load_vehicle("wheelset", ["wheelsets.ws1.nominal_radius={left: 0.625, right: 0.624}"])
    ws = vehicle.wheelsets[0]
    assert not ws.symmetric and ws.radius_right_m == 0.624
    geometry = wheelset_geometry(ws, ideal_straight_track())
    assert geometry.left.nominal_radius_m == 0.625 and geometry.right.nominal_radius_m == 0.624
    model = WheelsetContactModel(geometry)
    # centred, the larger left wheel rolls on the larger radius; the wheelset rolls freely where
    # the radii are equal, shifted towards the smaller (right) wheel
    assert rolling_radius_difference(model, [0.0])[0] > 0.0
    y_eq = equilibrium_lateral(model)
    assert y_eq < 0.0
    assert rolling_radius_difference(model, [y_eq])[0] == pytest.approx(0.0, abs=2e-5)
    # and dataclasses.replace of the profile changes both wheels
    from dataclasses import replace

    both = replace(vehicle.wheelsets[0], wheel_profile="cone:0.05", nominal_radius_right_m=0.0)
    assert both.profile_right == "cone:0.05" and both.symmetric
