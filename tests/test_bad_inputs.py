"""Malformed, hostile and absurd inputs: each gives an InputError that says what is wrong,
never another exception, a hang or a large allocation.

Two searches: a corpus of files in ``tests/data/bad_inputs/`` (each starts with ``# expect:`` and
the text its error must contain; see the README there), and property-based tests (hypothesis)
that feed the loaders random YAML text, random values in every line of a shipped file and random
overrides.
"""

from __future__ import annotations

import contextlib
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from railexu.errors import InputError
from railexu.inputs import apply_overrides, load_yaml, parse_yaml
from railexu.operation.run_settings import RunSettings, RunSettingsError, run_settings_from_dict
from railexu.study.spec import load_study
from railexu.track.track import load_track, track_from_dict
from railexu.vehicle.vehicle import load_vehicle, vehicle_from_dict

ROOT = Path(__file__).resolve().parent.parent
CORPUS = Path(__file__).parent / "data" / "bad_inputs"
LOADERS = {"vehicle": load_vehicle, "track": load_track}
SPECIAL = {"binary.yaml": "binary", "utf16.yaml": "UTF-16", "latin1.yaml": "not UTF-8"}


def _corpus() -> list[Path]:
    return sorted(CORPUS.glob("*/*.yaml"))


def _expected(path: Path) -> str:
    if path.name in SPECIAL:
        return SPECIAL[path.name]
    first = path.read_text(encoding="utf-8").splitlines()[0]
    assert first.startswith("# expect:"), path
    return first.removeprefix("# expect:").strip()


def test_corpus_is_there():
    files = _corpus()
    assert len(files) >= 70
    assert {p.parent.name for p in files} == set(LOADERS)


@pytest.mark.parametrize("path", _corpus(), ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_each_bad_file_gives_an_input_error_naming_the_file(path):
    with pytest.raises(InputError) as info:
        LOADERS[path.parent.name](path)
    message = str(info.value)
    assert message.startswith(str(path)), message  # the error names the file first
    assert _expected(path) in message


def test_a_folder_where_a_file_goes(tmp_path):
    folder = tmp_path / "car.yaml"
    folder.mkdir()
    for loader in (load_vehicle, load_track, load_yaml, load_study):
        with pytest.raises(InputError, match="folder"):
            loader(folder)


def test_a_file_too_large_is_refused_before_reading(tmp_path):
    from railexu.inputs import reader

    big = tmp_path / "big.yaml"
    big.write_bytes(b"#" * (reader.MAX_FILE_BYTES + 1))
    with pytest.raises(InputError, match="too large"):
        load_yaml(big)


# -- unquoted 1:40 --------------------------------------------------------------------------------
def test_unquoted_ratio_is_the_ratio_it_means():
    """YAML 1.1 reads 1:40 as 1 x 60 + 40 = 100; railexu keeps the text and reads the ratio."""
    base = (ROOT / "tracks" / "straight.yaml").read_text()
    for written in ("1:40", '"1:40"', "1/40"):
        data, lines = parse_yaml(base.replace("inclination: 1:40", f"inclination: {written}"))
        track = track_from_dict(data, "t.yaml", lines)
        assert track.inclination_rad == pytest.approx(math.atan(1 / 40), rel=1e-12)
    data, lines = parse_yaml(base.replace("inclination: 1:40", "inclination: 1.4321 deg"))
    # 1.4321 deg = 0.024995 rad, the angle of 1:40 to 4 digits
    assert track_from_dict(data, "t.yaml", lines).inclination_rad == pytest.approx(
        math.atan(1 / 40), rel=1e-4
    )


def test_sexagesimal_number_in_a_number_field_is_refused():
    text = (ROOT / "vehicles" / "wheelset.yaml").read_text().replace("mass: 4.25 t", "mass: 4:15")
    data, lines = parse_yaml(text, "w.yaml")
    with pytest.raises(InputError, match=r"w.yaml:\d+: wheelsets.ws1.mass: .4:15. is a ratio"):
        vehicle_from_dict(data, "w.yaml", lines, ROOT / "vehicles")


# -- time step against speed ----------------------------------------------------------------------
def test_step_too_coarse_for_the_speed_names_the_step_needed():
    """10 ms at 140 m/s is 1.4 m per step; the rule allows 0.3 m, i.e. 0.3 / 140 = 2.14 ms."""
    with pytest.raises(RunSettingsError, match=r"1.4 m per step.*at most 2.14 ms"):
        RunSettings(speed_m_per_s=140.0, time_step_s=0.010)
    RunSettings(speed_m_per_s=140.0, time_step_s=0.3 / 140.0)  # exactly at the limit: accepted
    RunSettings(speed_m_per_s=10.0, time_step_s=0.010)  # 0.1 m per step


def test_step_rule_in_a_mapping_points_at_the_line():
    with pytest.raises(InputError, match=r"s.yaml:7: base.run.time_step: .*at most 2.14 ms"):
        run_settings_from_dict(
            {"speed": "140 m/s", "time_step": "10 ms"},
            "s.yaml",
            {("base", "run", "time_step"): 7, ("base", "run"): 6},
            ("base", "run"),
        )


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"distance_m": 1e12}, "distance"),
        ({"distance_m": math.inf}, "finite"),
        ({"speed_m_per_s": math.nan}, "finite"),
        ({"distance_m": 150_000.0, "speed_m_per_s": 0.01, "time_step_s": 1e-5}, "steps"),
        ({"output_interval_s": math.inf}, "finite"),
        ({"time_step_s": 0.0}, "time_step"),
    ],
)
def test_absurd_run_sizes_are_refused(kwargs, match):
    with pytest.raises(RunSettingsError, match=match):
        RunSettings(**kwargs)


def test_irregularity_record_too_long_for_the_run_is_refused():
    """No record length in the file: the run's distance decides, and is checked before the
    synthesis allocates anything."""
    track = load_track("straight_irregular")
    with pytest.raises(InputError, match="longer than"):
        track.irregularities(1e12)


# -- studies --------------------------------------------------------------------------------------
STUDY_HEAD = f"""\
format_version: 1
name: t
base:
  vehicle: {ROOT / "vehicles" / "wheelset.yaml"}
vary:
  parameters:
"""


@pytest.mark.parametrize(
    "parameter, match",
    [
        ("run.speed: {from: 10, to: .inf, step: 1}", "finite"),
        ("run.speed: {from: 10 m/s, to: .inf, step: 1 m/s}", "same kind"),
        ("run.speed: {from: 10, to: .nan, step: 1}", "finite"),
        ("run.speed: {from: 10, to: 20, step: .nan}", "finite"),
        ("run.speed: {from: 10, to: 20, step: 0}", "step must be > 0"),
        ("run.speed: {from: 0 m/s, to: 1e18 m/s, step: 1 m/s}", "more than 10000"),
        ("run.speed: {from: 1, to: 2, step: 1e-300}", "more than 10000"),
        ("run.speed: [10 m/s, .inf]", "finite"),
        ("run.distance: [.nan]", "finite"),
    ],
)
def test_study_ranges_to_infinity_or_nan_are_refused_at_load(tmp_path, parameter, match):
    path = tmp_path / "s.yaml"
    path.write_text(STUDY_HEAD + "    " + parameter + "\n")
    with pytest.raises(InputError, match=match) as info:
        load_study(path)
    assert str(info.value).startswith(f"{path}:7:")


def test_study_too_many_cases_says_so(tmp_path):
    path = tmp_path / "s.yaml"
    grid = "{from: 1, to: 400, step: 1}"
    path.write_text(STUDY_HEAD + f"    run.speed: {grid}\n    vehicle.wheelsets.ws1.mass: {grid}\n")
    with pytest.raises(InputError, match="160000 cases is more than 100000"):
        load_study(path)


def test_study_value_error_names_the_study_line_not_the_vehicle_file(tmp_path):
    """Issue 8, group 4: a case's bad value is reported at the study's parameter line."""
    path = tmp_path / "s.yaml"
    path.write_text(STUDY_HEAD + "    vehicle.wheelsets.ws1.mass: [4 t, -1 t]\n")
    study = load_study(path)
    case = study.cases()[1]
    with pytest.raises(InputError) as info:
        load_vehicle(study.vehicle, study.vehicle_overrides(case))
    assert str(info.value) == (
        f"{path} (case_0001):7: wheelsets.ws1.mass: must be > 0 kg, got '-1 t'"
    )
    # base overrides point at their line of base.set too
    path.write_text(
        textwrap.dedent(f"""\
        format_version: 1
        name: t
        base:
          vehicle: {ROOT / "vehicles" / "wheelset.yaml"}
          set: ["wheelsets.ws1.mass=5 t"]
        vary:
          parameters:
            run.speed: [10 m/s]
        """)
    )
    overrides = load_study(path).vehicle_overrides(load_study(path).cases()[0])
    assert (overrides[0].source, overrides[0].line) == (str(path), 5)


def test_study_names_shipped_vehicle_and_track(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(
        "format_version: 1\nname: t\nbase: {vehicle: wheelset, track: straight}\n"
        "vary: {parameters: {run.speed: [10 m/s]}}\n"
    )
    study = load_study(path)
    assert study.vehicle.name == "wheelset.yaml" and study.track.name == "straight.yaml"


# -- property-based: random text, random values, random overrides ---------------------------------
_YAML_CHARS = st.sampled_from(list("ab01.e-+:[]{}&*!<>?|,'\"#% \n\t~@`=") + ["<<: ", "&a ", "*a"])
_NASTY = st.one_of(
    st.sampled_from([
        ".inf", "-.inf", ".nan", "1e400", "-1", "0", "1:40", "[]", "{}", "~", "yes", "*a", "!t x",
        "'1e12 m'", "1e9 m", "'-5 mm'", "[1, 2]", "{x: 1}", "<<: 5", "? [a]", "'' ", "|", "%",
        "1 furlong", "'3 s/m'", "2001-01-01", "0x10", "0o17", "12 kN s/m", "1:0",
    ]),
    st.text(min_size=0, max_size=12),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
)  # fmt: skip
_SETTINGS = settings(
    max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@_SETTINGS
@given(st.lists(_YAML_CHARS, max_size=80).map("".join))
def test_random_yaml_text_parses_or_gives_an_input_error(text):
    try:
        parse_yaml(text, "random.yaml")
    except InputError as exc:
        assert str(exc).startswith("random.yaml")


def _mutated(base: str, index: int, value: str) -> str:
    lines = base.splitlines()
    candidates = [i for i, line in enumerate(lines) if ":" in line and not line.startswith("#")]
    i = candidates[index % len(candidates)]
    key = lines[i].split(":", 1)[0]
    lines[i] = f"{key}: {value}"
    return "\n".join(lines) + "\n"


@_SETTINGS
@given(st.integers(min_value=0, max_value=10_000), _NASTY)
def test_any_value_in_any_line_of_a_vehicle_loads_or_gives_an_input_error(index, value):
    base = (ROOT / "vehicles" / "eu07_bogie.yaml").read_text()
    text = _mutated(base, index, value)
    try:
        data, lines = parse_yaml(text, "v.yaml")
        vehicle_from_dict(data, "v.yaml", lines, ROOT / "vehicles")
    except InputError as exc:
        assert str(exc).startswith(("v.yaml", "--set")), str(exc)


@_SETTINGS
@given(st.integers(min_value=0, max_value=10_000), _NASTY)
def test_any_value_in_any_line_of_a_track_loads_or_gives_an_input_error(index, value):
    base = (ROOT / "tracks" / "straight_irregular.yaml").read_text()
    try:
        data, lines = parse_yaml(_mutated(base, index, value), "t.yaml")
        track = track_from_dict(data, "t.yaml", lines, ROOT / "tracks")
        track.irregularities(100.0)
    except InputError as exc:
        assert str(exc).startswith(("t.yaml", "track irregularities")), str(exc)


_PATHS = st.sampled_from([
    "bodies.bogie_1.mass", "wheelsets.ws1.nominal_radius", "wheelsets.*.position.0",
    "suspension.primary_ws*.stiffness.x", "contact.creep", "contact.normal_damping.coefficient",
    "loads.car_body_share.force.2", "wheelsets.ws1.wheel_profile", "nothing.here", "a.*.b",
    "wheelsets.ws1.position.7", "", "suspension.primary_ws1.bodies.1", "speed_body",
])  # fmt: skip


@_SETTINGS
@given(_PATHS, _NASTY)
def test_any_override_applies_or_gives_an_input_error(path, value):
    vehicle = load_vehicle(ROOT / "vehicles" / "eu07_bogie.yaml")
    with contextlib.suppress(InputError):
        vehicle.replace(path, value)
    with contextlib.suppress(InputError):
        apply_overrides(vehicle.raw, f"{path}={value}")


_STUDY_PARAMETERS = st.sampled_from([
    "run.speed", "run.distance", "run.time_step", "vehicle.wheelsets.ws1.mass", "run.sped",
    "vehicle.wheelsets.*.nominal_radius", "vehicle.contact.friction", "track.gauge", "nothing",
])  # fmt: skip
_STUDY_VALUES = st.one_of(
    _NASTY.map(lambda v: f"[{v}]"),
    st.tuples(_NASTY, _NASTY, _NASTY).map(lambda t: f"{{from: {t[0]}, to: {t[1]}, step: {t[2]}}}"),
)


@_SETTINGS
@given(_STUDY_PARAMETERS, _STUDY_VALUES)
def test_any_study_parameter_loads_or_gives_an_input_error(tmp_path_factory, parameter, values):
    path = tmp_path_factory.mktemp("study") / "s.yaml"
    path.write_text(STUDY_HEAD + f"    {parameter}: {values}\n", encoding="utf-8")
    try:
        study = load_study(path)
    except InputError as exc:
        assert str(exc).startswith(str(path)), str(exc)
    else:
        assert 1 <= len(study.cases()) <= 10_000


# -- issue 26, parts 4, 5, 7: every input of every command ----------------------------------------
def _cli(argv: list[str], capsys) -> tuple[int, str]:
    from railexu.cli import main

    try:
        status = main(argv)
    except SystemExit as exc:  # argparse's own refusals (a value that is not a quantity)
        status = exc.code
    captured = capsys.readouterr()
    return status, captured.out + captured.err


CREEP = ["creep", "--load", "50 kN", "--semi-axes", "6 mm", "4 mm"]


@pytest.mark.parametrize(
    "extra, match",
    [
        (["--xi", "nan"], "expected a finite value"),
        (["--eta", "inf"], "expected a finite value"),
        (["--friction", "5"], "--friction 5: must be >= 0 and <= 1"),
        (["--spin", "1e6"], "--spin 1e+06: must be >= -100 and <= 100 1/m"),
        (["--speed", "0"], "--speed 0: must be > 0 and <= 150 m/s"),
        (["--xi", "2"], "--xi 2: must be >= -1 and <= 1"),
        (["--load", "1e9"], "--load 1e+09"),
        (["--shear-modulus", "1"], "--shear-modulus 1"),
    ],
)
def test_creep_absurd_options_are_refused(capsys, extra, match):
    """On main these printed forces (NaN creepage -> 0 N, friction 5, spin 1e6 1/m)."""
    status, text = _cli([*CREEP, *extra], capsys)
    assert status == 2 and match in text and "Traceback" not in text, text


def test_creep_semi_axes_of_a_kilometre_are_refused(capsys):
    status, text = _cli(["creep", "--load", "50 kN", "--semi-axes", "1 km", "1 km"], capsys)
    assert status == 2 and "--semi-axes 1000: must be > 0 and <= 0.1 m" in text, text


def test_creep_wide_numbers_keep_their_columns(capsys):
    """Kalker's linear law at xi = 0.9 with G = 1e12 Pa gives about 1e8 N: scientific notation,
    one space at least between columns, so that ``split()`` reads every column."""
    argv = [*CREEP, "--xi", "0.9", "--shear-modulus", "1e12", "--creep", "kalker_linear"]
    status, text = _cli(argv, capsys)
    line = next(ln for ln in text.splitlines() if ln.startswith("kalker_linear"))
    assert status == 0 and len(line.split()) == 5, line
    # Fx = -G a b c11 xi = -1e12 * 6e-3 * 4e-3 * c11 * 0.9 with c11(1.5, 0.28) = 4.724 (printed)
    assert float(line.split()[1]) == pytest.approx(-1e12 * 6e-3 * 4e-3 * 4.7241 * 0.9, rel=1e-3)


def test_contact_with_every_position_skipped_fails_clearly(tmp_path, capsys):
    """Wheels 50-60 mm off centre are off their rails: exit 1 and one message, no results, no
    raw RuntimeWarning (on main: exit 0 and Python's warnings)."""
    import warnings

    out = tmp_path / "c"
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        status, text = _cli(
            ["contact", "--lateral", "0.05:0.06:0.005", "--amplitudes", "0.003", "--out",
             str(out)], capsys,
        )  # fmt: skip
    assert status == 1 and "every lateral position (3) was skipped" in text, text
    assert "RuntimeWarning" not in text and not out.exists()


@pytest.mark.parametrize(
    "extra, match",
    [
        (["--gauge", "14.35 m"], "--gauge 14.35"),
        (["--radius", "46"], "--radius 46"),
        (["--friction", "nan"], "expected a finite value"),
        (["--flange-back", "1.5", "--gauge", "1.435"], "less than --gauge"),
    ],
)
def test_contact_absurd_options_are_refused(tmp_path, capsys, extra, match):
    status, text = _cli(["contact", *extra, "--out", str(tmp_path / "c")], capsys)
    assert status == 2 and match in text and "Traceback" not in text, text


def test_critical_speed_options_take_units():
    """On main ``--speed-max "200 km/h"`` was refused as an invalid float."""
    import argparse

    from railexu.cli import critical_speed

    parser = argparse.ArgumentParser()
    critical_speed.add_parser(parser.add_subparsers())
    argv = ["critical-speed", "v.yaml", "--out", "o", "--speed-max", "200 km/h"]
    args = parser.parse_args([*argv, "--threshold", "3 mm", "--distance", "0.3 km"])
    assert args.speed_max == pytest.approx(200 / 3.6) and args.threshold == pytest.approx(3e-3)
    assert args.distance == pytest.approx(300.0)


def test_critical_speed_range_above_the_run_limit_is_refused():
    from railexu.stability.settings import CriticalSpeedSettings

    with pytest.raises(InputError, match="speed_max <= 150 m/s"):
        CriticalSpeedSettings(speed_max_m_per_s=200.0)


def test_speed_profile_above_the_run_speed_limit_is_refused():
    from railexu.operation.speed_profile import SpeedProfile

    with pytest.raises(InputError, match="point 2 .*<= 150 m/s"):
        SpeedProfile(((0.0, 140.0), (2000.0, 160.0)))
    SpeedProfile(((0.0, 140.0), (2000.0, 150.0)))  # the limit itself: accepted


def test_a_run_beyond_the_end_of_the_geometry_is_refused_before_it_starts():
    """curve_r300: 640 m of geometry. The rearmost wheelset starts 1 m beyond ``start``; the
    single wheelset has no wheelbase: 1 + 600 m fits, 1 + 640 m and a start at 700 m do not."""
    from railexu.simulation.preflight import check_run_within_track

    vehicle = load_vehicle("wheelset")
    track = load_track("curve_r300")
    check_run_within_track(vehicle, track, RunSettings(distance_m=600.0))
    with pytest.raises(InputError, match=r"to 641 m, beyond the end .* at 640 m; at most 639"):
        check_run_within_track(vehicle, track, RunSettings(distance_m=640.0))
    beyond = load_track("curve_r300", ["start=700 m"])
    with pytest.raises(InputError, match="start: .* is beyond the end"):
        check_run_within_track(vehicle, beyond, RunSettings(distance_m=10.0))
    check_run_within_track(vehicle, load_track("straight"), RunSettings(distance_m=1e5))


def test_vehicle_without_category_names_the_choices():
    text = (ROOT / "vehicles" / "wheelset.yaml").read_text().replace("category: locomotive", "")
    data, lines = parse_yaml(text, "w.yaml")
    with pytest.raises(InputError, match="missing key 'category'.*locomotive, coach, multiple"):
        vehicle_from_dict(data, "w.yaml", lines, ROOT / "vehicles")


def test_every_shipped_vehicle_names_its_category():
    for path in sorted((ROOT / "vehicles").glob("*.yaml")):
        assert load_vehicle(path).category in ("locomotive", "coach", "multiple_unit", "wagon")


def test_format_1_contact_keys_in_format_2_show_the_new_form():
    text = (ROOT / "vehicles" / "wheelset.yaml").read_text() + "contact: {damping_model: linear}\n"
    data, lines = parse_yaml(text, "w.yaml")
    with pytest.raises(InputError, match=r"renamed key: write 'normal_damping: \{model: NAME"):
        vehicle_from_dict(data, "w.yaml", lines, ROOT / "vehicles")


def test_study_out_naming_the_study_file_or_an_impossible_place(tmp_path, capsys):
    path = tmp_path / "s.yaml"
    path.write_text(STUDY_HEAD + "    run.speed: [10 m/s]\n")
    before = path.read_text()
    status, text = _cli(["study", str(path), "--out", str(path)], capsys)
    assert status == 2 and "is the study file itself" in text and "Traceback" not in text
    assert path.read_text() == before
    (tmp_path / "file").write_text("x")
    status, text = _cli(["study", str(path), "--out", str(tmp_path / "file" / "sub")], capsys)
    assert status == 2 and "cannot create the folder" in text and "Traceback" not in text, text


# -- property-based: the newer formats ------------------------------------------------------------
_TRACK_HEAD = "format_version: 1\nname: t\n"


@_SETTINGS
@given(st.sampled_from(["rail_mass", "lateral_stiffness", "lateral_damping", "vertical_stiffness",
                        "vertical_damping", "nothing"]), _NASTY)  # fmt: skip
def test_any_elastic_track_value_loads_or_gives_an_input_error(key, value):
    text = _TRACK_HEAD + f"track_model:\n  type: elastic\n  {key}: {value}\n"
    try:
        data, lines = parse_yaml(text, "t.yaml")
        track = track_from_dict(data, "t.yaml", lines, ROOT / "tracks")
    except InputError as exc:
        assert str(exc).startswith("t.yaml"), str(exc)
    else:
        model = track.elastic  # an unknown key ("nothing") is refused: elastic here
        for name in ("lateral_stiffness_N_per_m", "vertical_stiffness_N_per_m"):
            assert 1e6 <= getattr(model, name) <= 1e10


_CELL = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["nan", "inf", "-inf", "", "x", "1e400", "0.02", "-0.02", "0.021", "1"]),
)


@_SETTINGS
@given(st.lists(st.tuples(_CELL, _CELL, _CELL), min_size=0, max_size=6))
def test_any_measured_geometry_loads_or_gives_an_input_error(tmp_path_factory, rows):
    folder = tmp_path_factory.mktemp("geometry")
    (folder / "g.csv").write_text("".join(f"{d},{k},{c}\n" for d, k, c in rows))
    text = _TRACK_HEAD + "geometry: {type: measured, file: g.csv}\n"
    try:
        data, lines = parse_yaml(text, "t.yaml")
        track = track_from_dict(data, "t.yaml", lines, folder)
    except InputError as exc:
        assert str(exc).startswith("t.yaml"), str(exc)
    else:
        k = track.alignment.k0
        assert np.all(np.isfinite(k)) and np.all(np.abs(k) <= 1.0 / 50.0)


@_SETTINGS
@given(st.lists(st.tuples(_NASTY, _NASTY), min_size=0, max_size=4))
def test_any_speed_profile_loads_or_gives_an_input_error(points):
    table = ", ".join(f"[{s}, {v}]" for s, v in points)
    text = f"run:\n  distance: 100 m\n  speed_profile: [{table}]\n"
    try:
        data, lines = parse_yaml(text, "s.yaml")
        settings = run_settings_from_dict(data["run"], "s.yaml", lines, ("run",))
    except InputError as exc:
        assert str(exc).startswith("s.yaml"), str(exc)
    else:
        profile = settings.speed_profile
        if profile is not None:
            assert 0.0 < profile.max_speed_m_per_s <= 150.0


_ELEMENT_PATHS = st.sampled_from([
    "suspension.primary_ws*.stiffness.x", "suspension.primary_ws*.stiffness.z",
    "suspension.primary_ws*.damping.z", "suspension.primary_ws*.points.0",
    "suspension.primary_ws*.bodies.0", "suspension.primary_ws*.type",
    "suspension.primary_ws*.bump_stop", "suspension.primary_ws*.deflection",
])  # fmt: skip


@_SETTINGS
@given(_ELEMENT_PATHS, _NASTY)
def test_any_suspension_element_value_loads_or_gives_an_input_error(path, value):
    try:
        load_vehicle(ROOT / "vehicles" / "eu07_bogie.yaml", [f"{path}={value}"])
    except InputError as exc:
        assert str(exc).startswith(("--set", str(ROOT / "vehicles"))), str(exc)
