"""Keep numba's on-disk cache of railexu's compiled functions consistent with their sources.

numba (``cache=True``) checks only the source file of the function it loads: a compiled function
in ``forces.py`` that inlines the contact kernel of ``contact/kernel.py`` would keep running the
kernel's old code from its cache after ``kernel.py`` changed, silently. :func:`refresh` keeps a
fingerprint of every source file that holds cached compiled code (paths, sizes, modification
times) and deletes numba's cache files under the package when it changes, so that everything
is compiled again from the current sources (a minute or two, once). A reinstalled package gets
new files and is refreshed the same way; a read-only installation is left alone.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

#: the modules with ``cache=True`` compiled functions, relative to the package
COMPILED_SOURCES = (
    "body_points.py",
    "contact/creep.py",
    "contact/fastsim.py",
    "contact/hertz.py",
    "contact/kalker.py",
    "contact/kernel.py",
    "contact/kik_piotrowski.py",
    "contact/polach.py",
    "forces.py",
    "record_row.py",
    "suspension_forces.py",
)
STAMP_NAME = "railexu-compiled-sources.stamp"

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
    root = Path(__file__).resolve().parent if root is None else Path(root)
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
