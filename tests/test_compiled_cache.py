"""railexu.runtime.compiled_cache: numba's cache files are deleted when a compiled module's source
changes (numba itself checks only the loaded function's own file, so a caller could keep an
inlined callee's old code), and kept otherwise."""

from __future__ import annotations

import os

from railexu.runtime import compiled_cache


def _package(tmp_path):
    root = tmp_path / "pkg"
    (root / "sub" / "__pycache__").mkdir(parents=True)
    (root / "__pycache__").mkdir()
    (root / "a.py").write_text("x = 1\n")
    (root / "sub" / "b.py").write_text("y = 2\n")
    return root


def _cached(root):
    files = [root / "__pycache__" / "a.f-1.py311.nbi", root / "sub" / "__pycache__" / "b.nbc"]
    for f in files:
        f.write_bytes(b"cache")
    return files


def test_the_cache_is_cleared_when_a_source_changes_and_kept_otherwise(tmp_path, monkeypatch):
    monkeypatch.setattr(compiled_cache, "_refreshed", set())
    root = _package(tmp_path)
    sources = ("a.py", "sub/b.py")
    files = _cached(root)
    assert compiled_cache.refresh(root, sources)  # no stamp yet: cleared
    assert not any(f.exists() for f in files)
    files = _cached(root)
    monkeypatch.setattr(compiled_cache, "_refreshed", set())  # a new process
    assert not compiled_cache.refresh(root, sources)  # nothing changed
    assert all(f.exists() for f in files)
    # the callee's source changes (as an edit or a checkout would)
    b = root / "sub" / "b.py"
    b.write_text("y = 3\n")
    st = b.stat()
    os.utime(b, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000_000))
    monkeypatch.setattr(compiled_cache, "_refreshed", set())
    assert compiled_cache.refresh(root, sources)
    assert not any(f.exists() for f in files)
    assert (root / "a.py").exists() and b.exists()  # sources untouched


def test_every_module_with_cached_compiled_code_is_listed():
    root = compiled_cache.Path(compiled_cache.__file__).parents[1]  # the package
    found = {
        str(p.relative_to(root))
        for p in root.rglob("*.py")
        if p.name != "compiled_cache.py"  # this module names them in its text
        and ('"cache": True' in p.read_text() or "cache=True" in p.read_text())
    }
    assert found == set(compiled_cache.COMPILED_SOURCES)


def test_a_compilation_of_railexu_code_is_announced_once(capsys):
    """The first run compiles for about two minutes: one line says so before it starts (numba's
    compile event fires on a cache miss only), and only for railexu's own functions."""
    import numba

    compiled_cache.announce_compilation()
    compiled_cache._announcer.printed = False  # an earlier test may have compiled already
    outside = numba.njit(lambda x: x + 2)
    outside(1)
    assert compiled_cache.COMPILING_NOTE not in capsys.readouterr().err
    namespace = {"__name__": "railexu._compilation_probe"}
    exec("def probe(x):\n    return x + 1\n", namespace)
    probe = numba.njit(namespace["probe"])
    probe(1)
    probe(2.5)  # a second compilation in the same process: no second line
    assert capsys.readouterr().err.count(compiled_cache.COMPILING_NOTE) == 1
