"""Keep numba's on-disk cache of railexu's compiled functions consistent with their sources.

numba (``cache=True``) checks only the source file of the function it loads: a compiled function
in ``model/forces.py`` that inlines the contact kernel of ``contact/kernel.py`` would keep running
the kernel's old code from its cache after ``kernel.py`` changed, silently. :func:`refresh` keeps a
fingerprint of every source file that holds cached compiled code (paths, sizes, modification
times) and deletes numba's cache files under the package when it changes, so that everything
is compiled again from the current sources (a minute or two, once). A reinstalled package gets
new files and is refreshed the same way; a read-only installation is left alone.

That first compilation takes about two minutes on a 2-core machine: :func:`announce_compilation`
prints one line when numba starts compiling a railexu function (a cache miss, not a load from
the cache), so that the wait does not look like a hang.
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

#: the modules with ``cache=True`` compiled functions, relative to the package
COMPILED_SOURCES = (
    "contact/creep.py",
    "contact/fastsim.py",
    "contact/halfspace_tangential.py",
    "contact/hertz.py",
    "contact/kalker.py",
    "contact/kernel.py",
    "contact/kik_piotrowski.py",
    "contact/polach.py",
    "contact/wear/patch.py",
    "model/body_points.py",
    "model/forces.py",
    "model/record_row.py",
    "model/suspension_forces.py",
)
STAMP_NAME = "railexu-compiled-sources.stamp"
#: the line printed (to standard error) when numba starts compiling railexu's functions
COMPILING_NOTE = (
    "railexu: compiling the contact kernel and the force functions (numba): about 2 minutes on "
    "a 2-core machine, once; later runs load them from numba's cache"
)

_refreshed: set[Path] = set()


def fingerprint(root: Path, sources: tuple[str, ...] = COMPILED_SOURCES) -> str:
    """A digest of the sources' paths, sizes and modification times (missing files count)."""
    digest = hashlib.sha256()
    for name in sources:
        path = root / name
        try:
            st = path.stat()
            digest.update(f"{name}:{st.st_size}:{st.st_mtime_ns};".encode())
        except OSError:
            digest.update(f"{name}:missing;".encode())
    return digest.hexdigest()


def refresh(root: Path | None = None, sources: tuple[str, ...] = COMPILED_SOURCES) -> bool:
    """Delete numba's cache files (``*.nbi``, ``*.nbc``) under ``root`` (the package) when the
    fingerprint of ``sources`` differs from the one stored at the last refresh; once per
    process and root. Returns True when the cache was cleared."""
    if "numba" in sys.modules:  # never import numba here: the input layer must not load it
        announce_compilation()
    root = Path(__file__).resolve().parents[1] if root is None else Path(root)
    if root in _refreshed:
        return False
    _refreshed.add(root)
    stamp = root / "__pycache__" / STAMP_NAME
    current = fingerprint(root, sources)
    try:
        if stamp.read_text(encoding="ascii") == current:
            return False
    except OSError:
        pass
    try:
        for pattern in ("*.nbi", "*.nbc"):
            for cached in root.rglob(pattern):
                if cached.parent.name == "__pycache__":
                    cached.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(current, encoding="ascii")
    except OSError:  # a read-only installation: numba keeps its own cache elsewhere
        return False
    return True


_announcer: object | None = None


def announce_compilation(stream=None) -> None:
    """Print :data:`COMPILING_NOTE` once in this process when numba starts compiling a railexu
    function (numba's ``"numba:compile"`` event fires on a cache miss only). Installed once per
    process; ``stream`` defaults to standard error at the time of printing."""
    global _announcer
    if _announcer is not None:
        return
    from numba.core import event

    class _FirstCompilation(event.Listener):
        printed = False

        def on_start(self, ev) -> None:
            dispatcher = (ev.data or {}).get("dispatcher")
            module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
            if self.printed or not module.startswith("railexu"):
                return
            self.printed = True
            print(COMPILING_NOTE, file=stream or sys.stderr, flush=True)

        def on_end(self, ev) -> None:
            pass

    _announcer = _FirstCompilation()
    event.register("numba:compile", _announcer)
