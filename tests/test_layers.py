"""railexu's layers import only downward, and no modules import each other in a circle.

The layers, lowest first (the package docstring, ``railexu/__init__.py``, explains them):

    errors, units -> inputs -> profiles -> contact -> track, vehicle, run settings -> model
    -> simulation -> analysis (results, stability, assessment, curving) -> report (figures and
    file writers) -> study -> cli

A module may import its own layer and the layers below. Imports inside functions count too (a
lazy upward import is still an upward dependency); imports under ``if TYPE_CHECKING:`` do not
(they exist for type checkers only). The check reads the source with :mod:`ast`,
so it needs no import of the package and runs in a fraction of a second.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "railexu"

# module prefix -> layer (longest prefix wins); every module of the package must be covered
LAYERS: dict[str, int] = {
    "railexu.errors": 0,
    "railexu.units": 0,
    "railexu.version": 0,
    "railexu.jsonable": 0,
    "railexu.inputs": 1,
    "railexu.schema": 10,  # renders the docs of every input, the study's too: beside the cli
    "railexu.catalog": 1,
    "railexu.profiles": 2,
    "railexu.contact": 3,
    "railexu.track": 4,
    "railexu.irregularities": 4,
    "railexu.alignment": 4,
    "railexu.vehicle": 4,
    "railexu.vehicle_schema": 4,
    "railexu.vehicle_checks": 4,
    "railexu.track_schema": 4,
    "railexu.run_settings": 4,
    "railexu.speed_profile": 4,
    "railexu.traction": 4,
    "railexu.longitudinal": 6,
    "railexu.model": 5,
    "railexu.forces": 5,
    "railexu.body_points": 5,
    "railexu.statics": 5,
    "railexu.suspension_forces": 5,
    "railexu.track_model": 4,
    "railexu.timeseries": 6,
    "railexu.curving": 6,
    "railexu.simulation": 6,
    "railexu.recorder": 6,
    "railexu.compiled_cache": 0,
    "railexu.warm_process": 0,  # the standard library only: a process that runs calls
    "railexu.threads": 0,  # numba, imported when the first model is built
    "railexu.blas_threads": 0,  # sets OPENBLAS_NUM_THREADS before numpy loads
    "railexu.gc_pause": 0,  # the console script's start-up without cyclic collection
    "railexu.fork_server": 0,  # the standard library only: a study's workers' fork server
    "railexu.record_row": 5,
    "railexu.preflight": 6,
    "railexu.results": 7,
    "railexu.stability": 7,
    "railexu.assessment": 7,
    "railexu.runs": 7,
    "railexu.report": 8,
    "railexu.study": 9,
    "railexu.cli": 10,
    "railexu.console": 10,  # the console script: start-up settings, then railexu.cli
    "railexu": 11,  # the front door (railexu/__init__.py) re-exports from every layer
}
LAYER_NAMES = [
    "errors/units", "inputs", "profiles", "contact", "track/vehicle", "model", "simulation",
    "analysis", "report", "study", "cli", "front door",
]  # fmt: skip


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def layer_of(module: str) -> int:
    best = max((p for p in LAYERS if module == p or module.startswith(p + ".")), key=len)
    return LAYERS[best]


def imports_of(path: Path) -> set[str]:
    """Every railexu module that ``path`` imports (top level, in functions, type-only)."""
    module = module_name(path)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found: set[str] = set()
    tree = ast.parse(path.read_text(encoding="utf-8"))
    # imports under `if TYPE_CHECKING:` are for type checkers only: no run-time dependency
    type_only = {
        id(n)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
        for stmt in node.body
        for n in ast.walk(stmt)
    }
    for node in ast.walk(tree):
        if id(node) in type_only:
            continue
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("railexu"))
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("railexu"):
                continue
            # `from . import stability` imports a module, not the package's __init__
            modules = {f"{target}.{a.name}" for a in node.names if _exists(f"{target}.{a.name}")}
            found.update(modules)
            if len(modules) < len(node.names):
                found.add(target)
    found.discard(module)
    return found


def _exists(module: str) -> bool:
    rel = Path(*module.split(".")[1:])
    return (PACKAGE / rel).with_suffix(".py").is_file() or (PACKAGE / rel / "__init__.py").is_file()


def graph() -> dict[str, set[str]]:
    return {module_name(p): imports_of(p) for p in sorted(PACKAGE.rglob("*.py"))}


def test_every_module_has_a_layer():
    for module in graph():
        assert any(module == p or module.startswith(p + ".") for p in LAYERS), module


def test_imports_only_go_downward():
    upward = []
    for module, targets in graph().items():
        for target in sorted(targets):
            if layer_of(target) > layer_of(module):
                upward.append(
                    f"{module} ({LAYER_NAMES[layer_of(module)]}) imports {target} "
                    f"({LAYER_NAMES[layer_of(target)]})"
                )
    assert not upward, "upward imports:\n" + "\n".join(upward)


def test_no_import_cycles_between_modules():
    g = graph()
    # package __init__ files re-export their own modules: an edge from a module to its own
    # package's __init__ is what `from . import x` looks like, not a cycle of dependencies
    edges = {m: {t for t in ts if t in g and not m.startswith(t + ".")} for m, ts in g.items()}
    state: dict[str, int] = {}
    stack: list[str] = []
    cycles: list[list[str]] = []

    def visit(m: str) -> None:
        state[m] = 1
        stack.append(m)
        for t in sorted(edges[m]):
            if state.get(t) == 1:
                cycles.append(stack[stack.index(t) :] + [t])
            elif t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(edges):
        if m not in state:
            visit(m)
    assert not cycles, "import cycles:\n" + "\n".join(" -> ".join(c) for c in cycles)


@pytest.mark.parametrize(
    ("module", "forbidden"),
    [
        ("railexu.vehicle", "numba"),  # vehicle files must not pull in the compiled layer
        ("railexu.inputs", "numba"),
    ],
)
def test_input_layer_does_not_import_the_compiled_kernel(module, forbidden):
    import subprocess
    import sys

    code = f"import sys, {module}; print({forbidden!r} in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False", f"importing {module} imports {forbidden}"
