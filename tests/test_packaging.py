"""What a plain `pip install` (not editable) ships, and that `import railexu` finds the installed
package from any folder (the src layout): every package, the shipped vehicles, tracks and
studies, the packaged profiles."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "railexu"


def test_every_code_folder_of_railexu_is_a_package():
    """setuptools finds packages by their ``__init__.py``: a folder of code without one would be
    left out of a wheel."""
    missing = [
        str(folder.relative_to(ROOT))
        for folder in [PACKAGE, *(p for p in PACKAGE.rglob("*") if p.is_dir())]
        if any(folder.glob("*.py")) and not (folder / "__init__.py").is_file()
    ]
    assert not missing, f"folders with code but no __init__.py: {missing}"


def test_the_shipped_inputs_are_links_to_the_top_level_folders():
    for name in ("vehicles", "tracks", "studies", "programmes"):
        link = PACKAGE / name
        assert link.is_symlink(), f"{link} must be a symbolic link to ../../{name}"
        assert link.resolve() == (ROOT / name).resolve()


def _import_from(folder: Path) -> subprocess.CompletedProcess:
    code = (
        "import railexu, railexu.results.run\n"
        "print(railexu.__file__)\n"
        "print(railexu.load_vehicle('eu07').name)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    return subprocess.run(
        [sys.executable, "-c", code], cwd=folder, capture_output=True, text=True, env=env,
        timeout=120,
    )  # fmt: skip


def test_import_railexu_finds_the_installed_package_from_any_folder(tmp_path):
    """From the parent folder of a clone named ``railexu`` (which Python would otherwise take for
    a namespace package), from a clone's own root with a ``runs/`` output folder in it, and from
    anywhere else, ``import railexu`` gives the installed package with its front door."""
    parent = tmp_path / "parent"
    parent.mkdir()
    (parent / "railexu").symlink_to(ROOT, target_is_directory=True)
    clone_like = tmp_path / "clone"
    (clone_like / "runs" / "eu07").mkdir(parents=True)
    (clone_like / "railexu").mkdir()  # an output folder with the package's name
    for folder in (parent, clone_like, tmp_path):
        done = _import_from(folder)
        assert done.returncode == 0, f"from {folder}: {done.stderr[-800:]}"
        file, name = done.stdout.split()
        assert Path(file).name == "__init__.py" and Path(file).parent.name == "railexu"
        assert name.lower() == "eu07"


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


def test_the_wheel_ships_every_package_the_inputs_and_profiles(wheel):
    names = set(wheel.namelist())
    for folder in ("vehicles", "tracks", "studies", "programmes"):
        for path in (ROOT / folder).glob("*.yaml"):
            assert f"railexu/{folder}/{path.name}" in names, path.name
    assert "railexu/data/profiles/MBench_S1002_v3.prw" in names
    for init in PACKAGE.rglob("__init__.py"):
        if {"vehicles", "tracks", "studies", "programmes"} & set(init.parts):
            continue
        assert str(init.relative_to(PACKAGE.parent)) in names, init
    assert not any(n.startswith("src/") for n in names)
