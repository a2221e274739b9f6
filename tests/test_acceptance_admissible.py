"""The vehicle's admissible speed and cant deficiency given on the command line (issue 27):
the straight zone at EN 14363's maximum test speed (1.1 times the admissible speed), the curve
zones' sections up to the admissible cant deficiency and evaluated at it, each section's speed
from EN 13803's relation checked by hand. No simulation: the programme is read, not run."""

from __future__ import annotations

import math
import re

import pytest

from railexu.assessment.acceptance.admissible import admissible_overrides
from railexu.assessment.acceptance.programme import load_programme
from railexu.cli import main
from railexu.cli.common import EXIT_INPUT
from railexu.errors import InputError

G = 9.81  # m/s^2, as programme.speed_for
B = 1.5  # m, the cant base of EN 13803


def test_the_admissible_values_set_the_zones_conditions():
    """Coach programme, V_adm 140 km/h and I_adm 130 mm: straight track at 1.1 x 38.89 =
    42.78 m/s; every curve section at a cant deficiency of at most 130 mm and the evaluation at
    130 mm; the section with the largest cant deficiency runs at sqrt(g R (I + D) / b)."""
    base = load_programme("coach")
    items = admissible_overrides(base, 140.0 / 3.6, 0.130)
    prog = load_programme("coach", overrides=items)
    assert prog.zone("straight").speed_m_per_s == pytest.approx(1.1 * 140.0 / 3.6, rel=1e-12)
    for zone in prog.zones:
        if zone.kind != "curve":
            continue
        assert zone.cant_deficiency_m[1] == pytest.approx(0.130)
        assert zone.evaluate_at[0] == pytest.approx(0.130)
        sections = zone.sections()
        top = max(sections, key=lambda s: s.cant_deficiency_m)
        assert top.cant_deficiency_m <= 0.130 + 1e-12
        assert top.cant_deficiency_m > 0.125  # the spread reaches near the admissible value
        v = math.sqrt(G * top.radius_m * (top.cant_deficiency_m + top.cant_m) / B)
        assert top.speed_m_per_s == pytest.approx(v, rel=1e-9)
        # the radius spread and the other conditions are the file's
        assert zone.radius_m == base.zone(zone.name).radius_m


def test_a_users_own_programme_change_wins():
    """``--set-programme`` items come after the admissible ones: the user's straight-track speed
    replaces 1.1 V_adm."""
    items = admissible_overrides(load_programme("coach"), 140.0 / 3.6, None)
    prog = load_programme("coach", overrides=(*items, "zones.straight.speed=120 km/h"))
    assert prog.zone("straight").speed_m_per_s == pytest.approx(120.0 / 3.6)


@pytest.mark.parametrize(
    ("speed", "cant", "message"),
    [
        (float("nan"), None, "admissible speed"),
        (-10.0, None, "admissible speed"),
        (0.0, None, "admissible speed"),
        (200.0, None, "(0, 136.364]"),  # 1.1 x 200 m/s is above 150 m/s
        (True, None, "expected a number"),
        (None, float("inf"), "admissible cant deficiency"),
        (None, 0.5, "(0, 0.3]"),
        (None, 0.03, "cant_deficiency_min"),  # below the programme's 60 mm
    ],
)
def test_absurd_admissible_values_are_refused(speed, cant, message):
    with pytest.raises(InputError, match=re.escape(message)):
        admissible_overrides(load_programme("coach"), speed, cant)


def test_the_command_line_wants_units_and_refuses_before_running(tmp_path, capsys):
    """``--admissible-speed 160`` (no unit: m/s or km/h?) and a cant deficiency below the
    programme's lowest are bad input (exit 2), refused before any section runs."""
    out = tmp_path / "acc"
    assert main(["acceptance", "manchester_coach_extended", "--out", str(out),
                 "--admissible-speed", "160"]) == EXIT_INPUT  # fmt: skip
    assert "give the unit" in capsys.readouterr().err
    assert main(["acceptance", "manchester_coach_extended", "--out", str(out),
                 "--admissible-cant-deficiency", "20mm"]) == EXIT_INPUT  # fmt: skip
    err = capsys.readouterr().err
    assert "zones.curve_large_radius.cant_deficiency_min" in err and "coach.yaml" in err
    assert main(["acceptance", "manchester_coach_extended", "--out", str(out),
                 "--admissible-speed", "160 N"]) == EXIT_INPUT  # fmt: skip
    assert "--admissible-speed" in capsys.readouterr().err
    assert not out.exists()


def test_acceptance_json_records_what_the_admissible_values_changed(tmp_path, monkeypatch):
    """``run_acceptance(admissible_...)`` runs the changed programme and writes the values and
    the programme items they became into ``acceptance.json`` (``programme.admissible``); the
    zones' runs are replaced by a stub here (what is checked is the programme they receive)."""
    from railexu.study.acceptance import runner

    seen = {}

    def no_run(zone, prog, *args, **kwargs):
        seen[zone.name] = zone
        return {"study": {"cases": zone.n_sections}, "error": "not run in this test"}

    monkeypatch.setattr(runner, "_run_zone", no_run)
    (tmp_path / "acc").mkdir()  # the zones' studies would create it
    result = runner.run_acceptance(
        "manchester_coach_extended", tmp_path / "acc", quasi_static=False,
        admissible_speed_m_per_s=140.0 / 3.6, admissible_cant_deficiency_m=0.13,
        programme_overrides=("zones.curve_small_radius.evaluate_at.cant_deficiency=120 mm",),
        progress=lambda line: None,
    )  # fmt: skip
    assert seen["straight"].speed_m_per_s == pytest.approx(1.1 * 140.0 / 3.6)
    assert seen["curve_large_radius"].cant_deficiency_m[1] == pytest.approx(0.13)
    assert seen["curve_small_radius"].evaluate_at[0] == pytest.approx(0.12)  # the user's wins
    admissible = result.data["programme"]["admissible"]
    assert admissible["speed_m_per_s"] == pytest.approx(140.0 / 3.6)
    assert admissible["cant_deficiency_m"] == 0.13
    assert "zones.straight.speed=" in admissible["overrides"][0]
    assert result.verdict == "incomplete"  # no zone evaluated, no quasi-static test
    written = (tmp_path / "acc" / "acceptance.json").read_text()
    assert '"admissible"' in written
