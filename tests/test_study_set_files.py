"""A file named by a study's base ``set`` override is read by every case (the wear loop sets
each step's worn wheel profiles that way): its content belongs to the cases' hashes, so that a
resumed study runs its cases again when the file changed (docs/wear.md, "One step")."""

from __future__ import annotations

import textwrap
from pathlib import Path

from railexu.profiles import wheel_profile
from railexu.study.runner import with_input_files
from railexu.study.spec import load_study
from railexu.study.wear.profiles import write_wheel_profile

VEHICLES = Path(__file__).resolve().parents[1] / "vehicles"


def _study(tmp_path: Path, profile: Path):
    text = f"""\
        format_version: 1
        name: set names a file
        base:
          vehicle: {VEHICLES / "wheelset.yaml"}
          run: {{distance: 5 m}}
          set: ["wheelsets.ws1.wheel_profile={{left: '{profile}', right: S1002}}"]
        vary:
          parameters:
            run.speed: [8 m/s]
        """
    path = tmp_path / "study.yaml"
    path.write_text(textwrap.dedent(text))
    return with_input_files(load_study(path))


def test_a_file_named_by_set_changes_the_case_hash(tmp_path):
    s1002 = wheel_profile("S1002")
    s = s1002.lateral_m
    profile = tmp_path / "worn.txt"
    write_wheel_profile(profile, s, s1002.height(s), -0.07)
    first = _study(tmp_path, profile)
    assert str(profile.resolve()) in first.input_files
    same = _study(tmp_path, profile)
    assert same.cases()[0].hash == first.cases()[0].hash
    write_wheel_profile(profile, s, s1002.height(s) - 1e-6, -0.07)  # 1 um of wear
    changed = _study(tmp_path, profile)
    assert changed.cases()[0].hash != first.cases()[0].hash
