"""What a plain `pip install` (not editable) ships: every package, the shipped vehicles, tracks
and studies, the packaged profiles."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_every_code_folder_of_railexu_is_a_listed_package():
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"][
        "packages"
    ])  # fmt: skip
    found = {
        ".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "railexu").rglob("__init__.py")
    }
    assert found <= listed, f"not listed in pyproject.toml: {sorted(found - listed)}"


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> zipfile.ZipFile:
    out = tmp_path_factory.mktemp("wheel")
    done = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q",
         "-w", str(out), str(ROOT)],
        capture_output=True,
        text=True,
        timeout=300,
    )  # fmt: skip
    if done.returncode != 0:
        pytest.skip(f"cannot build a wheel here: {done.stderr.strip()[-300:]}")
    return zipfile.ZipFile(next(out.glob("railexu-*.whl")))


def test_the_wheel_ships_the_vehicles_tracks_studies_and_profiles(wheel):
    names = set(wheel.namelist())
    for folder, kind in (("vehicles", "railexu/vehicles"), ("tracks", "railexu/tracks"),
                         ("studies", "railexu/studies")):  # fmt: skip
        for path in (ROOT / folder).glob("*.yaml"):
            assert f"{kind}/{path.name}" in names, path.name
    assert "railexu/data/profiles/MBench_S1002_v3.prw" in names
    assert "railexu/cli/__init__.py" in names and "railexu/report/folder.py" in names
