"""Profile readers: SIMPACK ``.prw``/``.prr`` files and plain two-column text files."""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline, make_smoothing_spline

from railexu.profiles.core import (
    MAX_SLOPE,
    MAX_SLOPE_DEG,
    PROFILE_KINDS,
    Profile,
    ProfileError,
    _CurveSegment,
    _make_profile,
)

_POINT_SMOOTHING = (
    "parametric C2 cubic interpolating spline (scipy CubicSpline, not-a-knot) through the points "
    "over their chord length; graph z(y) from it: C2 piecewise-quintic Hermite PPoly, nodes at "
    "the data and <= 0.1 mm apart, exact z, z', z'' of the parametric spline; cut where "
    f"|slope| > tan {MAX_SLOPE_DEG:g} deg"
)


def _err(path: str | os.PathLike, line: int | None, message: str) -> ProfileError:
    where = f"{path}" if line is None else f"{path}, line {line}"
    return ProfileError(f"{where}: {message}")


def _profile_from_points(
    y: np.ndarray,
    z: np.ndarray,
    lines: np.ndarray,
    *,
    kind: str,
    path: str | os.PathLike,
    name: str,
    source: str,
    flange_back_m: float | None,
    inclination_rad: float,
    smooth: float = 0.0,
    weights: np.ndarray | None = None,
) -> Profile:
    """A profile from points in conventions.md axes [m]; ``lines`` are the file lines."""
    if y.size < 4:
        raise _err(path, None, f"{y.size} profile points: expected at least 4")
    if not np.all(np.isfinite(y)) or not np.all(np.isfinite(z)):
        bad = int(np.flatnonzero(~(np.isfinite(y) & np.isfinite(z)))[0])
        raise _err(path, int(lines[bad]), "non-finite coordinate")
    # a profile given from the field side inwards is reversed (the geometry is the same)
    if y[-1] < y[0]:
        y, z, lines = y[::-1], z[::-1], lines[::-1]
        weights = None if weights is None else weights[::-1]
    # consecutive duplicate points carry no information
    keep = np.concatenate([[True], np.hypot(np.diff(y), np.diff(z)) > 0.0])
    y, z, lines = y[keep], z[keep], lines[keep]
    weights = None if weights is None else weights[keep]
    extent = float(np.max(y) - np.min(y))
    if not 0.005 <= extent <= 1.0:
        raise _err(
            path,
            None,
            f"lateral extent of the profile is {extent * 1e3:.4g} mm: expected 5 mm .. 1 m "
            "(check the length unit)",
        )
    _check_graph_points(y, z, lines, kind, path)
    u = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(y), np.diff(z)))])
    if smooth > 0.0:
        w = None if weights is None else np.asarray(weights, dtype=np.float64)
        fy = make_smoothing_spline(u, y, w=w, lam=smooth)
        fz = make_smoothing_spline(u, z, w=w, lam=smooth)
        segment = _CurveSegment(fy, fz, u)
        smoothing = _POINT_SMOOTHING.replace(
            "cubic interpolating spline (scipy CubicSpline, not-a-knot)",
            f"cubic smoothing spline (scipy make_smoothing_spline, lam = {smooth:g} m^3)",
        )
    else:
        segment = _CurveSegment(CubicSpline(u, y), CubicSpline(u, z), u)
        smoothing = _POINT_SMOOTHING
    if kind == "wheel" and flange_back_m is None:
        flange_back_m = float(np.min(y))
    return _make_profile(
        name=name,
        kind=kind,
        segments=(segment,),
        outline=np.column_stack([y, z]),
        flange_back_m=flange_back_m,
        inclination_rad=inclination_rad,
        source=source,
        smoothing=smoothing,
        what=str(path),
    )


def _check_graph_points(
    y: np.ndarray, z: np.ndarray, lines: np.ndarray, kind: str, path: str | os.PathLike
) -> None:
    """Raise if the points fold back where the profile is not steep (cannot be a graph).

    From the anchor (rail: highest point; wheel: point nearest ``y = 0``) outwards in both
    directions the lateral coordinate must increase until the profile first gets steeper than
    the slope limit; beyond that (flange back, gauge face, underside of a head, ...) anything
    goes, it is only part of ``outline_m``.
    """
    anchor = int(np.argmax(z)) if kind == "rail" else int(np.argmin(np.abs(y)))
    dy, dz = np.diff(y), np.diff(z)
    steep = np.abs(dz) > MAX_SLOPE * np.abs(dy)
    for step in (1, -1):
        idx = range(anchor, y.size - 1) if step == 1 else range(anchor - 1, -1, -1)
        for i in idx:
            if steep[i]:
                break
            if dy[i] <= 0.0:
                j = i + 1 if step == 1 else i
                raise _err(
                    path,
                    int(lines[j]),
                    f"lateral coordinate goes back from {y[i] * 1e3:.6g} to "
                    f"{y[i + 1] * 1e3:.6g} mm where the profile is not steep "
                    f"(|slope| < tan {MAX_SLOPE_DEG:g} deg): expected increasing lateral "
                    "coordinates (a graph z(y)) except in steep parts",
                )


# ---------------------------------------------------------------------------------------------
# SIMPACK
# ---------------------------------------------------------------------------------------------

_SIMPACK_REAL_KEYS = (
    "approx.smooth",
    "point.dist.min",
    "shift.y",
    "shift.z",
    "rotate",
    "bound.y.min",
    "bound.y.max",
    "bound.z.min",
    "bound.z.max",
    "units.len.f",
    "units.ang.f",
)
_SIMPACK_INT_KEYS = ("mirror.y", "mirror.z", "inversion", "type", "version", "file.mtime")
_UNIT_FACTORS = {
    "m": 1.0,
    "mm": 1000.0,
    "cm": 100.0,
    "dm": 10.0,
    "rad": 1.0,
    "deg": 180.0 / math.pi,
}


def _strip_comment(text: str) -> str:
    """Text before the first ``!`` outside single or double quotes."""
    quote = None
    for i, ch in enumerate(text):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return text[:i]
    return text


def read_simpack_profile(
    path: str | os.PathLike,
    *,
    name: str | None = None,
    inclination_rad: float = 0.0,
    flange_back_m: float | None = None,
) -> Profile:
    """Read a SIMPACK rail-wheel profile (``.prw`` wheel, ``.prr`` rail).

    The header's ``type`` (0 rail, 1 wheel) decides the kind. The ``spline`` block's keys are
    applied to the point block (lines ``y z [weight]``, ``!`` starts a comment, so commented
    points are skipped) in SIMPACK's order, numbered 1-7 in the files themselves and followed
    by CONTACT's ``read_simpack.m``: 1 drop points closer than ``point.dist.min`` to the last
    kept one, 2 add ``shift.y``/``shift.z``, 3 rotate by ``rotate`` (angle unit
    ``units.ang.f`` per rad) about the x axis (``y' = y cos a - z sin a``,
    ``z' = y sin a + z cos a``), 4 drop points outside ``[bound.y.min, bound.y.max]`` and clip
    ``z`` to ``[bound.z.min, bound.z.max]`` (each only if min < max), 5 ``mirror.y``/``mirror.z``
    (negate), 6 ``inversion`` (reverse the order), 7 divide by ``units.len.f`` (length unit per
    metre; default 1000, mm). Shifts and bounds are in the file's length unit.

    After processing, SIMPACK's ``y`` points to the field side and ``z`` down; so the lateral
    coordinate is ``y``, a wheel's radius increase is ``z`` and a rail's height is ``-z``.

    ``approx.smooth = 0`` (the usual value): the curve interpolates the points. A positive value
    is used as the lambda of a penalised cubic smoothing spline (scipy
    ``make_smoothing_spline``, in the file's length unit cubed, weights from the third column);
    it is not guaranteed to reproduce SIMPACK's own smoothing numerically.

    Args:
        path: the file.
        name: profile name (default the file stem).
        inclination_rad: rail only, the cant already contained in the points [rad] (the file
            does not say; the Manchester benchmark rail has ``atan(1/40)``).
        flange_back_m: wheel only, lateral coordinate of the flange back [m]; default the
            smallest lateral coordinate of the points.

    Raises:
        ProfileError: naming the file, the line and what was expected.
    """
    path = Path(path)
    parsed = _parse_simpack(path)
    kind = _simpack_kind(path, parsed)
    data, line_no, len_f = _process_simpack_points(path, parsed)
    lateral = data[:, 0].copy()
    height = data[:, 1].copy() if kind == "wheel" else -data[:, 1]
    smooth = float(parsed.spline["approx.smooth"][0]) if "approx.smooth" in parsed.spline else 0.0
    return _profile_from_points(
        lateral,
        height,
        line_no,
        kind=kind,
        path=path,
        name=name or path.stem,
        source=f"SIMPACK file {path}",
        flange_back_m=flange_back_m,
        inclination_rad=float(inclination_rad),
        smooth=smooth / len_f**3 if smooth > 0.0 else 0.0,
        weights=data[:, 2],
    )


@dataclass
class _SimpackFile:
    """The blocks of a SIMPACK profile file as read: header and spline keys (value, line), the
    point lines (y, z, weight) with their line numbers."""

    n_lines: int
    header: dict[str, tuple[object, int]] = field(default_factory=dict)
    spline: dict[str, tuple[object, int]] = field(default_factory=dict)
    points: list[tuple[float, float, float]] = field(default_factory=list)
    point_lines: list[int] = field(default_factory=list)
    seen_point_block: bool = False


def _parse_simpack(path: Path) -> _SimpackFile:
    """Read the blocks (``header``, ``spline``, ``point``) of a SIMPACK profile file."""
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ProfileError(f"{path}: cannot read the profile file ({exc.strerror})") from exc
    lines = text.splitlines()
    out = _SimpackFile(len(lines))
    section: list[tuple[str, int]] = []
    for lineno, raw in enumerate(lines, start=1):
        s = _strip_comment(raw).strip()
        if not s:
            continue
        m = re.fullmatch(r"([A-Za-z_][\w.]*)\.(begin|end)", s)
        if m:
            _simpack_block(path, lineno, s, m.group(1).lower(), m.group(2), section, out)
            continue
        current = section[-1][0] if section else None
        if current == "point":
            fields = s.replace(",", " ").split()
            try:
                values = [float(v) for v in fields]
            except ValueError:
                values = []
            if len(values) not in (2, 3):
                raise _err(path, lineno, f"'{s}': expected a point line 'y z [weight]'")
            out.points.append((values[0], values[1], values[2] if len(values) == 3 else 1.0))
            out.point_lines.append(lineno)
        elif "=" in s and current in ("header", "spline"):
            target = out.header if current == "header" else out.spline
            _simpack_key(path, lineno, s, target)
        elif current in ("header", "spline"):
            raise _err(path, lineno, f"'{s}': expected 'key = value'")
        elif current is None:
            raise _err(path, lineno, f"'{s}': expected 'header.begin' or 'spline.begin'")
    if section:
        block, start = section[-1]
        raise _err(
            path, len(lines), f"'{block}.begin' of line {start} is not closed by '{block}.end'"
        )
    return out


def _simpack_block(
    path: Path, lineno: int, s: str, block: str, what: str, section: list, out: _SimpackFile
) -> None:
    """A ``name.begin`` or ``name.end`` line: open or close a block."""
    if what == "begin":
        section.append((block, lineno))
        out.seen_point_block |= block == "point"
        return
    if not section or section[-1][0] != block:
        open_block = f"{section[-1][0]}.end" if section else "no '.end' here"
        raise _err(path, lineno, f"unexpected '{s}': expected {open_block}")
    section.pop()


def _simpack_key(path: Path, lineno: int, s: str, target: dict) -> None:
    """A ``key = value`` line of the header or spline block (numbers where SIMPACK has them)."""
    key, value = (p.strip() for p in s.split("=", 1))
    key = key.lower()
    if key not in _SIMPACK_REAL_KEYS and key not in _SIMPACK_INT_KEYS:
        target[key] = (value.strip("'\""), lineno)
        return
    try:
        number = float(value)
    except ValueError:
        raise _err(path, lineno, f"{key} = {value!r}: expected a number") from None
    if key in _SIMPACK_INT_KEYS:
        if number != round(number):
            raise _err(path, lineno, f"{key} = {value!r}: expected an integer")
        number = int(round(number))
    target[key] = (number, lineno)


def _simpack_kind(path: Path, parsed: _SimpackFile) -> str:
    """``"wheel"`` or ``"rail"`` from the header's type, checked against the extension and the
    point block."""
    if "type" not in parsed.header:
        raise _err(path, None, "no 'type' in a header block: expected header.begin/type = 0|1")
    ptype, tline = parsed.header["type"]
    if ptype not in (0, 1):
        raise _err(path, tline, f"header type = {ptype}: expected 0 (rail) or 1 (wheel)")
    kind = "wheel" if ptype == 1 else "rail"
    ext = path.suffix.lower()
    if (ext == ".prw" and kind != "wheel") or (ext == ".prr" and kind != "rail"):
        raise _err(path, tline, f"header type = {ptype} ({kind}) contradicts the extension {ext}")
    if not parsed.seen_point_block:
        raise _err(path, parsed.n_lines, "no point block: expected 'point.begin' ... 'point.end'")
    if len(parsed.points) < 4:
        raise _err(
            path, parsed.n_lines, f"{len(parsed.points)} points in the point block: expected >= 4"
        )
    return kind


def _process_simpack_points(
    path: Path, parsed: _SimpackFile
) -> tuple[np.ndarray, np.ndarray, float]:
    """SIMPACK's seven processing steps on the points (see :func:`read_simpack_profile`);
    returns the points (y, z in m, weight), their line numbers and the length unit factor."""
    spline = parsed.spline

    def opt(key: str, default: float) -> float:
        return float(spline[key][0]) if key in spline else default

    data = np.asarray(parsed.points, dtype=np.float64)
    line_no = np.asarray(parsed.point_lines)
    # 1: minimum point distance
    dmin = opt("point.dist.min", 0.0)
    if dmin > 0.0:
        keep = [0]
        for i in range(1, data.shape[0]):
            if math.hypot(*(data[i, :2] - data[keep[-1], :2])) > dmin:
                keep.append(i)
        data, line_no = data[keep], line_no[keep]
    # 2: shift
    data[:, 0] += opt("shift.y", 0.0)
    data[:, 1] += opt("shift.z", 0.0)
    # 3: rotation about x
    a = opt("rotate", 0.0) / _unit_factor(spline, "units.ang", 1.0, path)
    if a != 0.0:
        c, s = math.cos(a), math.sin(a)
        y0, z0 = data[:, 0].copy(), data[:, 1].copy()
        data[:, 0], data[:, 1] = c * y0 - s * z0, s * y0 + c * z0
    # 4: bounds
    ymin, ymax = opt("bound.y.min", 1.0), opt("bound.y.max", 0.0)
    if ymin < ymax:
        keep = (data[:, 0] >= ymin) & (data[:, 0] <= ymax)
        data, line_no = data[keep], line_no[keep]
    zmin, zmax = opt("bound.z.min", 1.0), opt("bound.z.max", 0.0)
    if zmin < zmax:
        data[:, 1] = np.clip(data[:, 1], zmin, zmax)
    # 5: mirror
    if int(opt("mirror.y", 0)) == 1:
        data[:, 0] = -data[:, 0]
    if int(opt("mirror.z", 0)) == 1:
        data[:, 1] = -data[:, 1]
    # 6: inversion of the order
    if int(opt("inversion", 0)) == 1:
        data, line_no = data[::-1], line_no[::-1]
    # 7: length unit
    len_f = _unit_factor(spline, "units.len", 1000.0, path)
    data[:, :2] /= len_f
    return data, line_no, len_f


def _unit_factor(spline: dict, key: str, default: float, path: Path) -> float:
    """``units.len.f`` / ``units.ang.f`` (user unit per SI unit), else the unit name."""
    if f"{key}.f" in spline:
        value, line = spline[f"{key}.f"]
        if not value > 0.0:
            raise _err(path, line, f"{key}.f = {value}: expected a positive factor")
        return float(value)
    if key in spline:
        unit, line = spline[key]
        if unit not in _UNIT_FACTORS:
            raise _err(path, line, f"{key} = {unit!r}: expected one of {sorted(_UNIT_FACTORS)}")
        return _UNIT_FACTORS[unit]
    return default


# ---------------------------------------------------------------------------------------------
# Two-column text
# ---------------------------------------------------------------------------------------------


def read_xy_profile(
    path: str | os.PathLike,
    kind: str,
    unit: str = "mm",
    flip_lateral: bool = False,
    flip_height: bool = False,
    name: str | None = None,
    *,
    inclination_rad: float = 0.0,
    flange_back_m: float | None = None,
) -> Profile:
    """Read a plain two-column text profile ``lateral height``.

    Columns already in conventions.md axes: lateral coordinate outwards (towards the field
    side) positive, from the tape circle (wheel) or the rail's reference point; second column
    the wheel's radius increase (flange positive) or the rail height (up positive). One point
    a line, separated by whitespace or a comma; ``#`` starts a comment; blank lines are
    skipped. The points may run in either lateral direction.

    Args:
        path: the file.
        kind: ``"wheel"`` or ``"rail"``.
        unit: length unit of both columns, ``"mm"`` or ``"m"``.
        flip_lateral: negate the lateral column (file with the flange / gauge side at ``+y``).
        flip_height: negate the second column (file with z pointing down, e.g. SIMPACK-like).
        name: profile name (default the file stem).
        inclination_rad: rail only, cant already contained in the points [rad].
        flange_back_m: wheel only, flange back [m]; default the smallest lateral coordinate.

    Raises:
        ProfileError: naming the file, the line and what was expected.
    """
    if kind not in PROFILE_KINDS:
        raise ValueError(f"kind {kind!r}: expected 'wheel' or 'rail'")
    factors = {"mm": 1e-3, "m": 1.0}
    if unit not in factors:
        raise ValueError(f"unit {unit!r}: expected 'mm' or 'm'")
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ProfileError(f"{path}: cannot read the profile file ({exc.strerror})") from exc
    rows, line_no = [], []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        s = raw.split("#", 1)[0].strip()
        if not s:
            continue
        fields = [f for f in re.split(r"[\s,;]+", s) if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            values = []
        if len(values) != 2:
            raise _err(path, lineno, f"'{s}': expected two numbers 'lateral height' in {unit}")
        rows.append(values)
        line_no.append(lineno)
    if len(rows) < 4:
        raise _err(path, None, f"{len(rows)} points: expected at least 4 lines 'lateral height'")
    data = np.asarray(rows, dtype=np.float64) * factors[unit]
    lateral = -data[:, 0] if flip_lateral else data[:, 0]
    height = -data[:, 1] if flip_height else data[:, 1]
    if kind == "wheel":
        _check_wheel_orientation(lateral, height, np.asarray(line_no), path)
    return _profile_from_points(
        lateral,
        height,
        np.asarray(line_no),
        kind=kind,
        path=path,
        name=name or path.stem,
        source=f"two-column text file {path} ({unit})",
        flange_back_m=flange_back_m,
        inclination_rad=float(inclination_rad),
    )


#: A wheel profile whose largest radius increase reaches this is taken to have a flange [m].
FLANGE_MIN_HEIGHT_M = 0.010


def _check_wheel_orientation(
    lateral: np.ndarray, height: np.ndarray, lines: np.ndarray, path: str | os.PathLike
) -> None:
    """Refuse a wheel whose flange is on the field side or whose heights have the wrong sign.

    In railexu's axes (docs/conventions.md) the flange is a radius *increase* (positive, some
    25-35 mm) on the *inner* side (negative lateral coordinate). A profile without a flange of
    at least :data:`FLANGE_MIN_HEIGHT_M` (a cone, a worn-flat test shape) is not checked.
    """
    i_max, i_min = int(np.argmax(height)), int(np.argmin(height))
    if height[i_max] >= FLANGE_MIN_HEIGHT_M:
        if lateral[i_max] > 0.0:
            raise _err(
                path,
                int(lines[i_max]),
                f"the flange (largest radius increase, {height[i_max] * 1e3:.1f} mm) is at "
                f"lateral {lateral[i_max] * 1e3:+.1f} mm, on the field side: railexu expects the "
                "lateral coordinate to point outwards (flange at negative lateral); the file has "
                "the flange on the other side (read it with flip_lateral)",
            )
    elif height[i_min] <= -FLANGE_MIN_HEIGHT_M:
        raise _err(
            path,
            int(lines[i_min]),
            f"the heights have the wrong sign: the largest deviation is a radius decrease of "
            f"{-height[i_min] * 1e3:.1f} mm, where the flange (a radius increase) is expected; "
            "railexu expects the radius increase, flange positive (read it with flip_height)",
        )


#: Keys of a text profile's declaration line ``# railexu profile: wheel, unit = mm, ...``.
DECLARATION_KEYS = {
    "wheel": ("unit", "lateral", "height", "flange_back"),
    "rail": ("unit", "lateral", "height", "canted"),
}

_DECLARATION_HELP = (
    "a text profile must declare its conventions in a comment line, e.g. "
    "'# railexu profile: wheel, unit = mm, lateral = outwards, height = radius_increase, "
    "flange_back = -70' or '# railexu profile: rail, unit = mm, lateral = outwards, "
    "height = up, canted = none' (lateral: outwards|inwards; wheel height: "
    "radius_increase|radius_decrease; rail height: up|down; flange_back in the file's unit; "
    "canted: none, 1:40, 1:20 or an angle in rad)"
)


def read_declared_text_profile(path: str | os.PathLike, kind: str) -> Profile:
    """Read a two-column text profile that declares its conventions (the registry's reader).

    The file must hold one comment line ``# railexu profile: KIND, key = value, ...`` with
    ``unit`` (mm, m), ``lateral`` (outwards: positive towards the field side, railexu's axes;
    or inwards), ``height`` (wheel: ``radius_increase`` or ``radius_decrease``; rail: ``up`` or
    ``down``), and for a wheel ``flange_back`` (lateral coordinate of the flange back, in the
    file's unit and axes), for a rail ``canted`` (the cant already in the points: ``none``,
    ``1:40``, ``1:20`` or rad). A file without it, or with a missing or unknown key, is refused:
    a profile read with the wrong conventions gives plausible-looking nonsense (a mirrored wheel
    gave an equivalent conicity of 0.003).

    Raises:
        ProfileError: naming the file, the line and what was expected.
    """
    from fractions import Fraction

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ProfileError(f"{path}: cannot read the profile file ({exc.strerror})") from exc
    decl, decl_line = None, None
    for lineno, raw in enumerate(text.splitlines(), start=1):
        m = re.match(r"\s*#\s*railexu\s+profile\s*:(.*)$", raw, flags=re.IGNORECASE)
        if m:
            decl, decl_line = m.group(1), lineno
            break
    if decl is None:
        raise _err(path, None, f"no '# railexu profile:' line: {_DECLARATION_HELP}")
    fields = [f.strip() for f in decl.split(",") if f.strip()]
    if not fields or fields[0].lower() != kind:
        raise _err(path, decl_line, f"declares {fields[0] if fields else '?'!r}, expected {kind}")
    values: dict[str, str] = {}
    for f in fields[1:]:
        if "=" not in f:
            raise _err(path, decl_line, f"'{f}': expected 'key = value'. {_DECLARATION_HELP}")
        k, v = (x.strip().lower() for x in f.split("=", 1))
        if k not in DECLARATION_KEYS[kind]:
            raise _err(
                path, decl_line, f"unknown key {k!r}; a {kind} declares "
                f"{', '.join(DECLARATION_KEYS[kind])}",
            )  # fmt: skip
        values[k] = v
    missing = [k for k in DECLARATION_KEYS[kind] if k not in values]
    if missing:
        raise _err(path, decl_line, f"missing {', '.join(missing)}. {_DECLARATION_HELP}")

    def choice(key: str, options: tuple[str, ...]) -> str:
        if values[key] not in options:
            raise _err(path, decl_line, f"{key} = {values[key]!r}: expected {' or '.join(options)}")
        return values[key]

    unit = choice("unit", ("mm", "m"))
    flip_lateral = choice("lateral", ("outwards", "inwards")) == "inwards"
    if kind == "wheel":
        flip_height = choice("height", ("radius_increase", "radius_decrease")) == "radius_decrease"
        try:
            fb = float(values["flange_back"]) * (1e-3 if unit == "mm" else 1.0)
        except ValueError:
            raise _err(path, decl_line, "flange_back: expected a number") from None
        return read_xy_profile(
            path, "wheel", unit=unit, flip_lateral=flip_lateral, flip_height=flip_height,
            flange_back_m=-fb if flip_lateral else fb,
        )  # fmt: skip
    flip_height = choice("height", ("up", "down")) == "down"
    cant = values["canted"]
    try:
        if cant in ("none", "0"):
            angle = 0.0
        elif ":" in cant:
            num, den = cant.split(":", 1)
            angle = math.atan(float(Fraction(num.strip()) / Fraction(den.strip())))
        else:
            angle = float(cant)
    except (ValueError, ZeroDivisionError):
        raise _err(
            path, decl_line, f"canted = {cant!r}: expected none, 1:40, 1:20 or rad"
        ) from None
    return read_xy_profile(
        path, "rail", unit=unit, flip_lateral=flip_lateral, flip_height=flip_height,
        inclination_rad=angle,
    )  # fmt: skip
