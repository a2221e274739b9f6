"""The slices of a variable rail profile as read, and the checks that make them interpolable.

:class:`ProfileSlices` holds what a ``.slcs`` or YAML file says: per slice its track position,
its profile points and (optionally) its feature points. :func:`check_slices` refuses, naming
the file, the slice (its number, line and position) and why, slices that are out of order or
overlap (two slices at one position), profiles that are not a graph ``z(y)`` or hold NaN or
infinite values, and feature points that do not split the profiles into matching parts.
Whether two neighbouring slices can be interpolated at all (the surface between them must not
fold over) is checked by :class:`railexu.profiles.variable.interpolate.VariableProfile`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railexu.profiles.core import ProfileError

#: Fewest points of one slice's profile.
MIN_SLICE_POINTS = 4
#: Largest ratio of the curve lengths of neighbouring slices without feature points: beyond
#: it a rail appears or disappears between them and arc-length fractions would morph one rail
#: into another (CONTACT's ``uk_crossing.slcs`` between its slices 47 and 48).
MAX_LENGTH_RATIO = 1.5
#: Tolerance on a feature beyond the profile's length [m] (the files round to 1 um).
FEATURE_TOL_M = 1.0e-5


@dataclass(frozen=True, eq=False)
class ProfileSlices:
    """Profile slices of one rail (or of the rails of one side given as one curve per slice).

    Attributes:
        source: the file read (for messages).
        positions_m: track position ``s`` of each slice [m], ``(n,)``.
        points_m: per slice the profile points ``(y, z)`` [m], ``z`` downwards, ``(m_i, 2)``.
        features_m: arc-length positions of the feature points along each slice's curve
            [m], ``(n, nfeat)``; NaN where a feature is absent in a slice (CONTACT's -1: the
            part it bounds does not exist there, e.g. before the nose starts); ``None``: no
            features (each slice is one part).
        lines: the file's line of each slice (``None`` where not known).
        names: the profile file (or name) of each slice.
        rail_names: the names of the side's two rails, gauge side first (``("nose", "wing
            rail")``, ``("blade", "stock rail")``, ``("check rail", "stock rail")``): the
            outputs' labels (:mod:`railexu.simulation.sc_outputs`); ``None``: not named.
    """

    source: str
    positions_m: np.ndarray
    points_m: tuple[np.ndarray, ...]
    features_m: np.ndarray | None
    lines: tuple[int | None, ...]
    names: tuple[str, ...]
    rail_names: tuple[str, str] | None = None

    @property
    def n_slices(self) -> int:
        """Number of slices."""
        return int(self.positions_m.size)

    def where(self, k: int) -> str:
        """``"FILE, line L, slice K (s = ... m)"`` for messages about slice ``k`` (0-based)."""
        line = self.lines[k]
        at = f", line {line}" if line is not None else ""
        return (
            f"{self.source}{at}, slice {k + 1} (s = {self.positions_m[k]:.5g} m, {self.names[k]})"
        )


def arc_length(points_m: np.ndarray) -> np.ndarray:
    """Cumulative arc length [m] along a polyline of points ``(m, 2)``."""
    seg = np.hypot(np.diff(points_m[:, 0]), np.diff(points_m[:, 1]))
    return np.concatenate(([0.0], np.cumsum(seg)))


def check_slices(slices: ProfileSlices) -> None:
    """Refuse slices that cannot make a variable profile (see the module docstring).

    Raises:
        ProfileError: naming the file, the slice and why.
    """
    s = slices.positions_m
    if s.size < 2:
        raise ProfileError(f"{slices.source}: {s.size} slice(s): a variable profile needs >= 2")
    for k in range(s.size):
        if not math.isfinite(float(s[k])):
            raise ProfileError(f"{slices.where(k)}: the position is not a finite number")
        if k > 0 and s[k] == s[k - 1]:
            raise ProfileError(
                f"{slices.where(k)}: overlaps slice {k} at the same position s = {s[k]:.6g} m: "
                "expected one profile per position"
            )
        if k > 0 and s[k] < s[k - 1]:
            raise ProfileError(
                f"{slices.where(k)}: out of order, before slice {k} at s = {s[k - 1]:.6g} m: "
                "expected increasing positions"
            )
        _check_points(slices, k)
    if slices.features_m is not None:
        for k in range(s.size):
            _check_features(slices, k)
    else:
        _check_lengths(slices)


def _check_lengths(slices: ProfileSlices) -> None:
    """Without feature points, neighbouring curves must be alike in length (one rail does not
    turn into two)."""
    lengths = [float(arc_length(p)[-1]) for p in slices.points_m]
    for k in range(1, len(lengths)):
        ratio = max(lengths[k], lengths[k - 1]) / min(lengths[k], lengths[k - 1])
        if ratio > MAX_LENGTH_RATIO:
            raise ProfileError(
                f"{slices.where(k)}: cannot be interpolated with slice {k}: its curve is "
                f"{lengths[k] * 1e3:.1f} mm long against {lengths[k - 1] * 1e3:.1f} mm (a rail "
                "appears or disappears between them): give feature points, -1 (null) for the "
                "parts absent in a slice, as CONTACT's uk_interrupt_v2.slcs does"
            )


def _check_points(slices: ProfileSlices, k: int) -> None:
    """One slice's profile: enough points, finite, a graph ``z(y)`` (``y`` increasing)."""
    p = slices.points_m[k]
    if p.ndim != 2 or p.shape[0] < MIN_SLICE_POINTS or p.shape[1] != 2:
        raise ProfileError(
            f"{slices.where(k)}: {p.shape[0] if p.ndim == 2 else 0} profile points: expected "
            f">= {MIN_SLICE_POINTS} points (y, z)"
        )
    if not np.all(np.isfinite(p)):
        bad = int(np.argmax(~np.all(np.isfinite(p), axis=1)))
        raise ProfileError(f"{slices.where(k)}: point {bad + 1} is not finite: {p[bad].tolist()}")
    dy = np.diff(p[:, 0])
    if np.any(dy <= 0.0):
        bad = int(np.argmax(dy <= 0.0))
        raise ProfileError(
            f"{slices.where(k)}: the lateral coordinate does not increase at point {bad + 2} "
            f"(y = {p[bad + 1, 0] * 1e3:.4f} mm after {p[bad, 0] * 1e3:.4f} mm): expected a "
            "profile z(y) with increasing y (several rails of a side: one curve through the "
            "flangeway, or one slices file per rail)"
        )


def _check_features(slices: ProfileSlices, k: int) -> None:
    """One slice's feature points: increasing along the curve, bounding parts of positive
    length. A feature beyond the curve's end is its end (CONTACT writes 299 or 999 mm)."""
    f = slices.features_m[k]
    present = np.isfinite(f)
    length = float(arc_length(slices.points_m[k])[-1])
    values = f[present]
    if values.size == 1:
        raise ProfileError(
            f"{slices.where(k)}: a single feature point present: expected none or >= 2 "
            "(a part lies between two)"
        )
    if np.any(values < -FEATURE_TOL_M):
        raise ProfileError(f"{slices.where(k)}: negative feature position {values.min():.6g} m")
    if np.any(np.diff(np.minimum(values, length)) <= 0.0):
        raise ProfileError(
            f"{slices.where(k)}: feature positions {np.round(values * 1e3, 3).tolist()} mm do "
            "not increase: expected the features in order along the curve, each part of "
            "positive length"
        )
