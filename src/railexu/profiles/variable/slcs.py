"""CONTACT's variable-profile file ``.slcs`` (E.A.H. Vollebregt, CONTACT user guide, "Variable
profiles for switches and crossings"; the format of ``testbank/profiles/*.slcs``).

Layout (``%`` starts a comment; each value line begins with its numbers, the rest is a label)::

    U_OFFSET  U_SCALE           offset [usr] and scale [mm/usr] of the slice positions
    NSLC                        number of slices
    NFEAT  NKINK  NACCEL        feature points per slice, kinks, accelerations
    U_INTPOL                    1 interpolate, 2 approximate (railexu: interpolates)
    u_1  'file_1'               NSLC lines: slice position [usr] and its profile file
    ...
    P_KINK(1..NKINK)            only if NKINK > 0 (parts with a kink to the next part)
    P_ACCEL(1..NACCEL)          only if NACCEL > 0
    u_1  S_F(1..NFEAT)          NSLC lines if NFEAT > 0: feature positions [mm] along the curve
    ...

The track position of a slice is ``s = (u + U_OFFSET) * U_SCALE`` [mm]. Profile files are
SIMPACK ``.prr`` (their own length unit) or two-column text ``y z`` scaled by ``scale_to_mm``
(CONTACT's ``SCALE`` of the ``RFNAME`` line); their paths are relative to the ``.slcs`` file. A
feature ``-1`` is absent in that slice (the part it bounds does not exist there); ``999`` is the
end of the curve. Kinks and accelerations are read and not used: railexu interpolates every part
with the same monotone cubic in ``s`` (:mod:`railexu.profiles.variable.interpolate`).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from railexu.profiles.core import ProfileError
from railexu.profiles.readers import _parse_simpack, _process_simpack_points
from railexu.profiles.variable.slices import ProfileSlices, check_slices

_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?$")


def _value_lines(path: Path) -> list[tuple[int, str]]:
    """The non-comment, non-blank lines with their line numbers."""
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ProfileError(f"{path}: cannot read the slices file ({exc.strerror})") from exc
    out = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        s = raw.split("%", 1)[0].strip()
        if s:
            out.append((lineno, s))
    return out


def _numbers(path: Path, lineno: int, s: str, count: int, what: str) -> list[float]:
    """The first ``count`` numbers of a line (``what`` names them for the message)."""
    fields = s.split()
    values = []
    for f in fields[:count]:
        if not _NUMBER.match(f):
            break
        values.append(float(f.replace("d", "e").replace("D", "e")))
    if len(values) < count:
        raise ProfileError(f"{path}, line {lineno}: '{s}': expected {count} number(s): {what}")
    return values


def _read_profile_points(path: Path, lineno: int, name: str, scale_to_mm: float) -> np.ndarray:
    """One slice's profile file as points ``(y, z)`` [m], z downwards."""
    file = (path.parent / name).resolve() if not Path(name).is_absolute() else Path(name)
    if not file.is_file():
        raise ProfileError(f"{path}, line {lineno}: profile file '{name}' not found ({file})")
    if file.suffix.lower() in (".prr", ".prw"):
        data, _, _ = _process_simpack_points(file, _parse_simpack(file))
        return np.ascontiguousarray(data[:, :2])
    try:
        data = np.loadtxt(file, comments=("%", "#", "!"), ndmin=2)
    except ValueError as exc:
        raise ProfileError(f"{file}: not a two-column text profile 'y z' ({exc})") from None
    if data.shape[1] < 2:
        raise ProfileError(f"{file}: {data.shape[1]} column(s): expected 'y z'")
    return np.ascontiguousarray(data[:, :2] * scale_to_mm * 1.0e-3)


def read_slcs(path: str | os.PathLike, *, scale_to_mm: float = 1.0) -> ProfileSlices:
    """Read and check a CONTACT ``.slcs`` file (see the module docstring).

    Args:
        path: the ``.slcs`` file.
        scale_to_mm: factor from a text profile's unit to mm (CONTACT's ``SCALE``; 1000 for
            profiles in metres).

    Raises:
        ProfileError: the file, the line or slice and what was expected.
    """
    path = Path(path)
    if not (scale_to_mm > 0.0 and np.isfinite(scale_to_mm)):
        raise ProfileError(f"{path}: scale_to_mm = {scale_to_mm}: expected a positive number")
    lines = _value_lines(path)
    if len(lines) < 4:
        raise ProfileError(f"{path}: {len(lines)} value lines: expected the 4 header lines")
    u_offset, u_scale = _numbers(path, *lines[0], 2, "U_OFFSET U_SCALE")
    nslc = int(_numbers(path, *lines[1], 1, "NSLC")[0])
    nfeat, nkink, naccel = (int(v) for v in _numbers(path, *lines[2], 3, "NFEAT NKINK NACCEL"))
    _numbers(path, *lines[3], 1, "U_INTPOL")
    if nslc < 2 or nfeat < 0 or nkink < 0 or naccel < 0 or not u_scale > 0.0:
        raise ProfileError(
            f"{path}, lines {lines[1][0]}-{lines[2][0]}: NSLC = {nslc}, NFEAT = {nfeat}, "
            f"U_SCALE = {u_scale}: expected NSLC >= 2, NFEAT >= 0, U_SCALE > 0"
        )
    rest = lines[4:]
    need = nslc + (nkink > 0) + (naccel > 0) + (nslc if nfeat > 0 else 0)
    if len(rest) < need:
        raise ProfileError(
            f"{path}: {len(rest)} lines after the header: expected {need} (NSLC = {nslc} slice "
            f"lines{', the kink and acceleration lines' if nkink or naccel else ''}"
            f"{', NSLC feature lines' if nfeat else ''})"
        )
    positions, points, slice_lines, names = [], [], [], []
    for lineno, s in rest[:nslc]:
        u = _numbers(path, lineno, s, 1, "the slice position u and its profile file")[0]
        m = re.search(r"['\"]([^'\"]+)['\"]", s)
        if not m:
            raise ProfileError(f"{path}, line {lineno}: '{s}': expected u 'profile file'")
        positions.append((u + u_offset) * u_scale * 1.0e-3)
        points.append(_read_profile_points(path, lineno, m.group(1), scale_to_mm))
        slice_lines.append(lineno)
        names.append(m.group(1))
    features = None
    if nfeat > 0:
        feat_rows = rest[nslc + (nkink > 0) + (naccel > 0) : need]
        features = np.empty((nslc, nfeat))
        for k, (lineno, s) in enumerate(feat_rows):
            row = _numbers(path, lineno, s, nfeat + 1, f"u and NFEAT = {nfeat} feature positions")
            s_mm = (row[0] + u_offset) * u_scale
            if abs(s_mm * 1.0e-3 - positions[k]) > 1.0e-6 * max(1.0, abs(positions[k])):
                raise ProfileError(
                    f"{path}, line {lineno}: features given for u = {row[0]:g}: expected those "
                    f"of slice {k + 1} at u = {positions[k] * 1e3 / u_scale - u_offset:g}"
                )
            f = np.asarray(row[1:], dtype=float)
            features[k] = np.where(f < 0.0, np.nan, f * 1.0e-3)
    slices = ProfileSlices(
        source=str(path),
        positions_m=np.asarray(positions, dtype=float),
        points_m=tuple(points),
        features_m=features,
        lines=tuple(slice_lines),
        names=tuple(names),
    )
    check_slices(slices)
    return slices
