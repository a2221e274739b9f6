"""railexu's layers import only downward, and no modules import each other in a circle.

The folders of ``src/railexu`` are the layers, lowest first (``docs/architecture.md``):

    errors, units, runtime -> inputs -> profiles -> contact -> track, vehicle, operation -> model
    -> simulation -> analysis (results, assessment, stability) -> report (figures and file
    writers) -> study -> cli

A module may import its own layer and the layers below. Every import counts: those inside
functions (a lazy upward import is still an upward dependency) and those under
``if TYPE_CHECKING:`` (a type that two modules need from each other lives in the wrong module).
The check reads the source with :mod:`ast`, so it needs no import of the package and runs in a
fraction of a second.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "railexu"

# module prefix -> layer (longest prefix wins); every module of the package must be covered.
# The folders are the layers: a module's folder says where it stands.
LAYERS: dict[str, int] = {
    "railexu.errors": 0,
    "railexu.units": 0,
    "railexu.version": 0,
    "railexu.jsonable": 0,
    # the process: the standard library only (threads imports numba when the first model is
    # built), so that these can run before numpy loads
    "railexu.runtime": 0,
    "railexu.inputs": 1,
    "railexu.profiles": 2,
    "railexu.contact": 3,
    "railexu.track": 4,
    "railexu.vehicle": 4,
    "railexu.operation": 4,
    "railexu.model": 5,
    "railexu.simulation": 6,
    "railexu.results": 7,
    "railexu.stability": 7,
    "railexu.assessment": 7,
    "railexu.report": 8,
    "railexu.study": 9,
    "railexu.cli": 10,
    "railexu.schema": 10,  # renders the docs of every input, the study's too: beside the cli
    "railexu.console": 10,  # the console script: start-up settings, then railexu.cli
    "railexu": 11,  # the front door (src/railexu/__init__.py) re-exports from every layer
}
LAYER_NAMES = [
    "base/runtime", "inputs", "profiles", "contact", "track/vehicle/operation", "model",
    "simulation", "analysis", "report", "study", "cli", "front door",
]  # fmt: skip
#: at most this many modules at the package's top level (the front door, errors, units, ...)
MAX_TOP_LEVEL_MODULES = 10


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def layer_of(module: str) -> int:
    best = max((p for p in LAYERS if module == p or module.startswith(p + ".")), key=len)
    return LAYERS[best]


def imports_of(path: Path, type_only_too: bool = False) -> set[str]:
    """Every railexu module that ``path`` imports at run time (top level and in functions), and
    with ``type_only_too`` also those under ``if TYPE_CHECKING:``."""
    module = module_name(path)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found: set[str] = set()
    tree = ast.parse(path.read_text(encoding="utf-8"))
    # imports under `if TYPE_CHECKING:` are for type checkers only: no run-time dependency
    type_only = {
        id(n)
        for node in ast.walk(tree)
        if not type_only_too
        and isinstance(node, ast.If)
        and "TYPE_CHECKING" in ast.unparse(node.test)
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


def package_files() -> list[Path]:
    """The package's modules (not the shipped inputs linked into it)."""
    linked = {"vehicles", "tracks", "studies", "programmes"}
    return [
        p for p in sorted(PACKAGE.rglob("*.py")) if not linked & set(p.relative_to(PACKAGE).parts)
    ]


def graph(type_only_too: bool = False) -> dict[str, set[str]]:
    return {module_name(p): imports_of(p, type_only_too) for p in package_files()}


def test_the_package_top_level_holds_few_modules():
    """The folders are the layers; the top level keeps only the front door and its like."""
    top = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert len(top) <= MAX_TOP_LEVEL_MODULES, top


def test_every_module_has_a_layer():
    for module in graph():
        assert any(module == p or module.startswith(p + ".") for p in LAYERS), module


def test_imports_only_go_downward():
    upward = []
    for module, targets in graph(type_only_too=True).items():
        for target in sorted(targets):
            if layer_of(target) > layer_of(module):
                upward.append(
                    f"{module} ({LAYER_NAMES[layer_of(module)]}) imports {target} "
                    f"({LAYER_NAMES[layer_of(target)]})"
                )
    assert not upward, "upward imports:\n" + "\n".join(upward)


def test_no_import_cycles_between_modules():
    """No module imports another that imports it back, directly or through a chain, counting
    imports inside functions and those for type hints only (a type used by both sides of such a
    pair lives in the wrong module)."""
    g = graph(type_only_too=True)
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
        ("railexu.vehicle.vehicle", "numba"),  # vehicle files must not pull in the compiled layer
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
