"""Look up wheel and rail profiles by built-in name or file path."""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Callable
from importlib import resources
from pathlib import Path

from railexu.errors import did_you_mean
from railexu.profiles.builtin import cone_wheel, flat_rail, rail_60e1, round_rail, s1002
from railexu.profiles.core import Profile, ProfileError
from railexu.profiles.readers import read_declared_text_profile, read_simpack_profile

#: Cant of the Manchester benchmark rail file (already contained in its points) [rad].
MBENCH_RAIL_INCLINATION_RAD = math.atan(1.0 / 40.0)


def _read_packaged(filename: str, **kwargs) -> Profile:
    """Read a SIMPACK file packaged in ``src/railexu/data/profiles`` (importlib.resources)."""
    ref = resources.files("railexu").joinpath("data", "profiles", filename)
    with resources.as_file(ref) as path:
        return read_simpack_profile(path, **kwargs)


@functools.cache
def mbench_s1002() -> Profile:
    """The Manchester benchmark S1002 wheel (``MBench_S1002_v3.prw``, packaged).

    The file's flange-back point (-70 mm) is commented out, so the data start at -69.61 mm;
    the flange back is set to the S1002 value -0.070 m.
    """
    return _read_packaged("MBench_S1002_v3.prw", name="MBench_S1002", flange_back_m=-0.070)


@functools.cache
def mbench_uic60() -> Profile:
    """The Manchester benchmark UIC60 rail (``MBench_UIC60_v3.prr``, packaged).

    Already canted 1:40 (``inclination_rad = atan(1/40)``); origin at the highest point of the
    canted head; gauge side at negative lateral coordinates (field side positive), as
    conventions.md wants.
    """
    return _read_packaged(
        "MBench_UIC60_v3.prr", name="MBench_UIC60", inclination_rad=MBENCH_RAIL_INCLINATION_RAD
    )


_WHEELS: dict[str, Callable[[], Profile]] = {"S1002": s1002, "MBench_S1002": mbench_s1002}
_RAILS: dict[str, Callable[[], Profile]] = {
    "UIC60": rail_60e1,
    "60E1": rail_60e1,
    "MBench_UIC60": mbench_uic60,
}

#: Built-in wheel profile names (case-insensitive).
BUILTIN_WHEELS = tuple(_WHEELS)
#: Built-in rail profile names (case-insensitive).
BUILTIN_RAILS = tuple(_RAILS)


#: Parametric test shapes, ``name:value``: ``cone:0.05`` (wheel, cone slope), ``round:0.3``
#: (rail, head radius in m), ``flat`` (rail).
PARAMETRIC_WHEELS = ("cone:<conicity>",)
PARAMETRIC_RAILS = ("round:<radius_m>", "flat")


def _parametric(text: str, kind: str) -> Profile | None:
    name, sep, value = text.strip().lower().partition(":")
    try:
        if kind == "wheel" and name == "cone" and sep:
            return cone_wheel(_number(value))
        if kind == "rail" and name == "round" and sep:
            return round_rail(_number(value), width_m=min(0.072, 1.9 * _number(value)))
        if kind == "rail" and name == "flat" and not sep:
            return flat_rail()
    except ValueError as exc:
        raise ProfileError(f"{kind} profile {text!r}: {exc}") from exc
    return None


def _number(text: str) -> float:
    if "/" in text:
        num, den = text.split("/", 1)
        return float(num) / float(den)
    return float(text)


def _lookup(name_or_path: str | os.PathLike, kind: str) -> Profile:
    table = _WHEELS if kind == "wheel" else _RAILS
    if isinstance(name_or_path, str):
        shape = _parametric(name_or_path, kind)
        if shape is not None:
            return shape
        key = name_or_path.strip().lower()
        for name, builder in table.items():
            if name.lower() == key:
                return builder()
    elif not isinstance(name_or_path, os.PathLike):
        raise TypeError(
            f"{kind} profile: expected a name or a path, got {type(name_or_path).__name__}"
        )
    text = os.fspath(name_or_path)
    path = Path(text)
    looks_like_path = (
        isinstance(name_or_path, os.PathLike)
        or path.suffix != ""
        or "/" in text
        or os.sep in text
        or path.exists()
    )
    if not looks_like_path:
        names = list(table)
        suggestion = did_you_mean(text.strip(), names, cutoff=0.5, n=3, known=False)
        ext = ".prw" if kind == "wheel" else ".prr"
        shapes = PARAMETRIC_WHEELS if kind == "wheel" else PARAMETRIC_RAILS
        raise ProfileError(
            f"unknown {kind} profile {text!r}.{suggestion} Built-in {kind} profiles: "
            f"{', '.join(names)}, test shapes {', '.join(shapes)}; or give a file path ({ext} "
            "SIMPACK, anything else two-column text 'lateral height' with a "
            "'# railexu profile:' line declaring its conventions)."
        )
    if not path.is_file():
        raise ProfileError(f"{kind} profile file {text!r} does not exist")
    if path.suffix.lower() in (".prw", ".prr"):
        profile = read_simpack_profile(path)
    else:
        profile = read_declared_text_profile(path, kind)
    if profile.kind != kind:
        raise ProfileError(f"{path}: this is a {profile.kind} profile, expected a {kind} profile")
    return profile


def wheel_profile(name_or_path: str | os.PathLike) -> Profile:
    """A wheel profile by built-in name (case-insensitive: ``"S1002"``, ``"MBench_S1002"``, the
    test cone ``"cone:0.05"``) or by path (``.prw``: SIMPACK; anything else: two-column text
    that declares its conventions, :func:`~railexu.profiles.readers.read_declared_text_profile`).
    """
    return _lookup(name_or_path, "wheel")


def rail_profile(name_or_path: str | os.PathLike) -> Profile:
    """A rail profile by built-in name (case-insensitive: ``"UIC60"``, ``"60E1"`` - the analytic
    upright head - and ``"MBench_UIC60"``, canted 1:40; test shapes ``"round:0.3"`` (circular
    head of 0.3 m radius) and ``"flat"``) or by path (``.prr``: SIMPACK;
    anything else: two-column text declaring its conventions and cant,
    :func:`~railexu.profiles.readers.read_declared_text_profile`)."""
    return _lookup(name_or_path, "rail")
