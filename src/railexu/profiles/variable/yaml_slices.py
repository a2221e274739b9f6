"""railexu's own variable-profile file (YAML): the slices of a rail along the track.

Example (``tests/data/switches_crossings/cross_nose.yaml``)::

    text_unit: mm                 # unit of two-column text profiles: mm (default) or m
    rails: [nose, wing rail]      # optional: the two rails' names, gauge side first
    slices:
      - s_m: -0.100               # track position of the slice [m]
        profile: cross_nose/nose_1.prr   # .prr (SIMPACK/CONTACT) or text 'y z', z downwards
        features_mm: [0.0, 33.0541, 50.9076, 87.0158, 299.0]   # optional, see below
      - s_m: -0.090
        ...

``features_mm`` are positions along each slice's curve [mm] that tie corresponding points of
neighbouring slices together (blade tip, nose start): every slice gives the same number, or no
slice gives any; ``null`` marks a feature absent in that slice (the part it bounds does not
exist there), 999 the end of the curve. Paths are relative to the YAML file. The same checks as
for ``.slcs`` files apply (:func:`railexu.profiles.variable.slices.check_slices`).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from railexu.inputs.reader import load_yaml
from railexu.profiles.core import ProfileError
from railexu.profiles.variable.slcs import _read_profile_points
from railexu.profiles.variable.slices import ProfileSlices, check_slices

_UNITS_TO_MM = {"mm": 1.0, "m": 1000.0}
_SLICE_KEYS = {"s_m", "profile", "features_mm"}


def _line(lines: dict, *key) -> int | None:
    return lines.get(tuple(key))


def read_yaml_slices(path: str | os.PathLike) -> ProfileSlices:
    """Read and check a YAML variable profile (see the module docstring).

    Raises:
        ProfileError: the file, the line, the key and what was expected.
    """
    path = Path(path)
    data, lines = load_yaml(path)
    if not isinstance(data, dict) or "slices" not in data:
        raise ProfileError(f"{path}: expected a mapping with the key 'slices'")
    unknown = set(data) - {"slices", "text_unit", "rails"}
    if unknown:
        key = sorted(unknown)[0]
        raise ProfileError(
            f"{path}, line {_line(lines, key)}: unknown key '{key}': expected slices, text_unit, "
            "rails"
        )
    rails = data.get("rails")
    if rails is not None and not (
        isinstance(rails, list) and len(rails) == 2 and all(isinstance(r, str) and r for r in rails)
    ):
        raise ProfileError(
            f"{path}, line {_line(lines, 'rails')}: rails = {rails!r}: expected the two rails' "
            "names, gauge side first (e.g. [nose, wing rail])"
        )
    unit = data.get("text_unit", "mm")
    if unit not in _UNITS_TO_MM:
        raise ProfileError(
            f"{path}, line {_line(lines, 'text_unit')}: text_unit = {unit!r}: expected mm or m"
        )
    items = data["slices"]
    if not isinstance(items, list) or len(items) < 2:
        raise ProfileError(
            f"{path}, line {_line(lines, 'slices')}: slices: expected a list of >= 2"
        )
    positions, points, slice_lines, names, feats = [], [], [], [], []
    for k, item in enumerate(items):
        where = f"{path}, line {_line(lines, 'slices', k)}, slices.{k}"
        if not isinstance(item, dict):
            raise ProfileError(f"{where}: expected a mapping with s_m and profile")
        extra = set(item) - _SLICE_KEYS
        if extra or "s_m" not in item or "profile" not in item:
            raise ProfileError(
                f"{where}: keys {sorted(item)}: expected s_m, profile and optionally features_mm"
            )
        s_m = item["s_m"]
        if isinstance(s_m, bool) or not isinstance(s_m, (int, float)) or not math.isfinite(s_m):
            raise ProfileError(f"{where}.s_m = {s_m!r}: expected a finite number [m]")
        positions.append(float(s_m))
        points.append(_read_profile_points(path, _line(lines, "slices", k, "profile"),
                                           str(item["profile"]), _UNITS_TO_MM[unit]))  # fmt: skip
        slice_lines.append(_line(lines, "slices", k))
        names.append(str(item["profile"]))
        feats.append(_features(where, item.get("features_mm")))
    given = [f is not None for f in feats]
    if any(given) and not all(given):
        k = given.index(not given[0])
        raise ProfileError(
            f"{path}, line {slice_lines[k]}, slices.{k}: features_mm "
            f"{'given' if given[k] else 'missing'}: expected features in every slice or in none"
        )
    features = None
    if all(given):
        counts = {len(f) for f in feats}
        if len(counts) > 1:
            k = next(i for i, f in enumerate(feats) if len(f) != len(feats[0]))
            raise ProfileError(
                f"{path}, line {slice_lines[k]}, slices.{k}.features_mm: {len(feats[k])} values: "
                f"expected {len(feats[0])} as in slice 0"
            )
        features = np.asarray(feats, dtype=float)
    slices = ProfileSlices(str(path), np.asarray(positions), tuple(points), features,
                           tuple(slice_lines), tuple(names),
                           None if rails is None else (rails[0], rails[1]))  # fmt: skip
    check_slices(slices)
    return slices


def _features(where: str, value) -> list[float] | None:
    """``features_mm`` of one slice in metres, NaN for ``null`` (absent)."""
    if value is None:
        return None
    if not isinstance(value, list) or len(value) < 2:
        raise ProfileError(f"{where}.features_mm: expected a list of >= 2 positions [mm]")
    out = []
    for v in value:
        if v is None:
            out.append(math.nan)
        elif isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ProfileError(f"{where}.features_mm: {v!r}: expected a finite number or null")
        else:
            out.append(float(v) * 1.0e-3)
    return out
