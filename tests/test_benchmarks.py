"""What the benchmarks assume about railexu (their timings are never asserted here)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# the third-party packages and SciPy's public sub-packages a process has loaded
_LOADED = """
import sys
std = set(sys.stdlib_module_names)
top = {m.split(".")[0] for m in sys.modules}
third = {m for m in top if m not in std and not m.startswith("_") and m != "railexu"}
sci = {m for m in sys.modules
       if m.startswith("scipy.") and m.count(".") == 1 and not m.startswith("scipy._")}
print(sorted(third | sci))
"""


def _overhead_floor():
    spec = importlib.util.spec_from_file_location(
        "overhead_floor", ROOT / "benchmarks" / "overhead_floor.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _loaded_after(code: str) -> str:
    done = subprocess.run([sys.executable, "-c", code + _LOADED], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip().splitlines()[-1]


def test_the_overhead_floor_imports_what_a_run_imports(tmp_path):
    """benchmarks/overhead_floor.py times a process that imports RUN_LIBRARIES as the floor of
    the run's imports: a run's process (without figures, which its warm process draws) loads
    exactly the same third-party packages and SciPy sub-packages, no more and no fewer."""
    from railexu.runtime.warm_process import can_fork

    if not can_fork():
        pytest.skip("no warm process here: the run's process also imports the assessment's")
    floor = _overhead_floor()
    out = tmp_path / "out"
    run = _loaded_after(
        # the warm process is waited for however busy the test machine is (on a loaded machine
        # a starved warm process's work is done in the run's process, with its imports)
        "import railexu.runtime.helpers as helpers\n"
        "helpers.MIN_CPU_SHARE = 0.0\n"
        "helpers.free_core = lambda *args, **kwargs: True\n"
        "from railexu.cli import main\n"
        "main(['run', 'wheelset', '--distance', '2', '--no-plots', '--quiet', "
        f"'--out', {str(out)!r}])\n"
    )
    libraries = _loaded_after(floor.IMPORT_CODE)
    assert run == libraries
