"""Interpolation between profile slices that keeps the surface smooth and its real edges.

Method (after CONTACT's variable profiles, E.A.H. Vollebregt, "Variable rail profiles for
switches and crossings", CONTACT user guide; the slices' *feature points* split each slice's
curve into *parts*):

1. Each slice's curve is parametrised by its arc length; within part ``p`` a point is named by
   its fraction ``t`` in [0, 1] of the part's length, so that ``t = 0`` and ``t = 1`` are the
   same feature (blade tip, nose start, ...) in every slice. Without features a slice is one
   part. Within a slice the curve is a monotone cubic (PCHIP) in arc length through the file's
   points: it passes through them, keeps their kinks and does not overshoot
   (``curve="spline"``: CONTACT's interpolating cubic spline instead, for comparisons with
   CONTACT; smooth curvature, overshoot beside real kinks).
2. Every slice's part ``p`` is resampled at the same ``M_p`` fractions (spacing at most
   ``spacing_m`` along the longest slice's part).
3. Between two neighbouring slices each resampled point moves linearly in ``s`` (a ruled
   surface between the slices): exact where the slices change linearly (a nose rising 1:10), no
   overshoot (a rising nose gets no false bump), and it cannot fold: a convex combination of two
   graphs ``z(y)`` sampled in the same order is again a graph. A cubic in ``s`` (CONTACT's
   ``U_INTPOL = 1`` spline) folds the steep flanks of ``cross+wing_extd.slcs``, whose points
   lie 0.03 mm apart laterally and move 2 mm per slice; its slope in ``s`` is continuous, the
   linear one's jumps at a slice where the rate of change does (the surface is continuous, its
   ``s``-slope piecewise constant). The features stay features: the surface has its edges
   exactly along the feature lines and nowhere else.

A part exists between two neighbouring slices only if both have it (a feature ``-1``/``null``
removes it): a rail that begins at a slice (the nose's start, an interrupted wing rail) begins
there with its edge. Outside the first and last slice the profile is constant (as CONTACT).
Every curve at every ``s`` is a graph ``z(y)``, checked halfway between each pair of slices
(a guard: the linear interpolation of checked slices cannot fail it).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import CubicSpline, PchipInterpolator

from railexu.profiles.core import ProfileError
from railexu.profiles.variable.slices import ProfileSlices, arc_length, check_slices

#: Largest distance along the curve between two resampled points [m].
DEFAULT_SPACING_M = 2.0e-4

#: The curves through a slice's points in arc length (``VariableProfile(curve=...)``).
SLICE_CURVES = {"pchip": PchipInterpolator, "spline": CubicSpline}


class VariableProfile:
    """A rail profile ``z(y; s)`` that varies along the track, from checked slices.

    Coordinates: ``y`` lateral and ``z`` downwards [m] (those of the slices' files), ``s`` the
    track position [m].
    """

    def __init__(
        self, slices: ProfileSlices, spacing_m: float = DEFAULT_SPACING_M, curve: str = "pchip"
    ):
        """``curve``: the curve through each slice's points in arc length, ``"pchip"`` (monotone
        cubic: keeps kinks, no overshoot; the default) or ``"spline"`` (the interpolating
        cubic spline, C2, not-a-knot: CONTACT's smooth surface through the same points, for
        comparisons with CONTACT; it overshoots beside a real kink)."""
        if curve not in SLICE_CURVES:
            raise ProfileError(
                f"slice curve {curve!r}: not one of {', '.join(sorted(SLICE_CURVES))}"
            )
        check_slices(slices)
        self.slices = slices
        self.positions_m = slices.positions_m
        self._bounds, self._present = _part_bounds(slices)
        n_parts = self._present.shape[1]
        lengths = np.where(self._present, np.diff(self._bounds, axis=1), 0.0)
        self._counts = [
            max(2, math.ceil(lengths[:, p].max() / spacing_m) + 1) for p in range(n_parts)
        ]
        self._offsets = np.concatenate(([0], np.cumsum(self._counts)))
        samples = np.full((slices.n_slices, self._offsets[-1], 2), np.nan)
        for k in range(slices.n_slices):
            _resample_slice(slices.points_m[k], self._bounds[k], self._present[k], self._counts,
                            self._offsets, samples[k], SLICE_CURVES[curve])  # fmt: skip
        self._samples = samples
        self._check_no_folds()

    @property
    def s_range_m(self) -> tuple[float, float]:
        """First and last slice position [m]."""
        return float(self.positions_m[0]), float(self.positions_m[-1])

    @property
    def n_parts(self) -> int:
        """Number of parts (one more than the features, or 1 without features)."""
        return int(self._present.shape[1])

    def _interval(self, s_m: float) -> tuple[int, float]:
        """The slice interval ``i`` (``s_i <= s <= s_i+1``) and ``s`` clamped to the slices."""
        s = min(max(float(s_m), self.positions_m[0]), self.positions_m[-1])
        i = int(np.searchsorted(self.positions_m, s, side="right")) - 1
        return min(max(i, 0), self.positions_m.size - 2), s

    def parts_at(self, s_m: float) -> list[tuple[int, np.ndarray]]:
        """The parts that exist at ``s`` with their points ``(M_p, 2)`` [m], in part order."""
        i, s = self._interval(s_m)
        out = []
        for p in range(self.n_parts):
            if not (self._present[i, p] and self._present[i + 1, p]):
                continue
            a = self._samples[i, self._offsets[p] : self._offsets[p + 1]]
            b = self._samples[i + 1, self._offsets[p] : self._offsets[p + 1]]
            w = (s - self.positions_m[i]) / (self.positions_m[i + 1] - self.positions_m[i])
            out.append((p, a + w * (b - a)))  # exact where the slices agree
        return out

    def curves_at(self, s_m: float) -> list[np.ndarray]:
        """The profile at ``s`` as continuous curves ``(m, 2)`` [m]: consecutive parts joined.

        Two curves are separate rails (or a rail interrupted): their points do not connect.
        """
        curves: list[np.ndarray] = []
        last = -2
        for p, pts in self.parts_at(s_m):
            if p == last + 1 and curves:
                curves[-1] = np.vstack((curves[-1], pts[1:]))
            else:
                curves.append(pts)
            last = p
        return curves

    def features_at(self, s_m: float) -> np.ndarray:
        """The feature points ``(y, z)`` [m] at ``s`` (ends of the parts that exist)."""
        pts = [pts[[0, -1]] for _, pts in self.parts_at(s_m)]
        return np.unique(np.vstack(pts), axis=0) if pts else np.empty((0, 2))

    def heights_on_grid(
        self, s_m: np.ndarray, y_m: np.ndarray, *, smooth: bool = False
    ) -> np.ndarray:
        """``z(y)`` [m] (downwards) of the top surface at each ``s``, ``(len(s), len(y))``.

        Where several curves lie above one ``y`` the topmost (smallest ``z``) counts; where none
        does the value is ``+inf`` (no rail: the flangeway of an interrupted crossing, beyond the
        rails). Between the resampled points the curve is straight (``smooth=False``: a
        polyline, kinks every ``spacing_m``) or a monotone cubic in ``y`` (``smooth=True``: no
        kinks, for the contact's pressure; :func:`top_surface_heights`).
        """
        return top_surface_heights(self.curves_at, s_m, y_m, smooth=smooth)

    def _check_no_folds(self) -> None:
        """Refuse neighbouring slices whose interpolated curve folds over halfway between."""
        s = self.positions_m
        for i in range(s.size - 1):
            for c in self.curves_at(0.5 * (s[i] + s[i + 1])):
                dy = np.diff(c[:, 0])
                if np.any(dy <= 0.0):
                    bad = int(np.argmax(dy <= 0.0))
                    raise ProfileError(
                        f"{self.slices.where(i + 1)}: cannot be interpolated with slice {i + 1}: "
                        f"halfway between them the curve folds over at y = "
                        f"{c[bad, 0] * 1e3:.3f} mm, z = {c[bad, 1] * 1e3:.3f} mm (the parts "
                        "do not correspond): add feature points at the edges or a slice between"
                    )


def pchip_heights(y_pts: np.ndarray, z_pts: np.ndarray, y_m: np.ndarray) -> np.ndarray:
    """The monotone cubic (PCHIP, Fritsch & Carlson, SIAM J. Numer. Anal. 17, 1980:
    :class:`scipy.interpolate.PchipInterpolator`) through the points ``(y, z)`` [m], ``y``
    non-decreasing (repeated ``y`` count once), evaluated at ``y_m`` inside them: continuous
    slope, so a curve given by points ``0.2 mm`` apart has no kinks between them (a kink is a
    wedge: it puts a logarithmic peak into the half-space pressure on grids finer than the
    points)."""
    keep = np.concatenate(([True], np.diff(y_pts) > 0.0))
    if np.count_nonzero(keep) < 2:
        return np.interp(y_m, y_pts, z_pts)
    return PchipInterpolator(y_pts[keep], z_pts[keep])(y_m)


def top_surface_heights(
    curves_at, s_m: np.ndarray, y_m: np.ndarray, *, smooth: bool = False
) -> np.ndarray:
    """``z(y)`` [m] (downwards) of the top surface at each ``s``, ``(len(s), len(y))``, from
    ``curves_at(s)`` (the rail curves ``(n, 2)`` at ``s``): where several curves lie above one
    ``y`` the topmost (smallest ``z``) counts; where none does the value is ``+inf``. Between
    a curve's points linear (``smooth=False``) or :func:`pchip_heights` (``smooth=True``)."""
    s_m = np.atleast_1d(np.asarray(s_m, dtype=float))
    y_m = np.asarray(y_m, dtype=float)
    out = np.full((s_m.size, y_m.size), np.inf)
    for j, s in enumerate(s_m):
        for c in curves_at(float(s)):
            inside = (y_m >= c[0, 0]) & (y_m <= c[-1, 0])
            if np.any(inside):
                if smooth and c.shape[0] > 2:
                    z = pchip_heights(c[:, 0], c[:, 1], y_m[inside])
                else:
                    z = np.interp(y_m[inside], c[:, 0], c[:, 1])
                out[j, inside] = np.minimum(out[j, inside], z)
    return out


def _part_bounds(slices: ProfileSlices) -> tuple[np.ndarray, np.ndarray]:
    """Arc-length bounds ``(n, parts + 1)`` [m] of each slice's parts and which parts exist."""
    n = slices.n_slices
    lengths = np.array([arc_length(p)[-1] for p in slices.points_m])
    if slices.features_m is None:
        return np.column_stack((np.zeros(n), lengths)), np.ones((n, 1), dtype=bool)
    f = slices.features_m.copy()
    f = np.where(np.isfinite(f), np.minimum(f, lengths[:, None]), f)  # beyond the end: the end
    present = np.isfinite(f[:, :-1]) & np.isfinite(f[:, 1:])
    return f, present


def _resample_slice(points, bounds, present, counts, offsets, out, make=PchipInterpolator):
    """Resample one slice's existing parts at the common fractions into ``out`` (in place);
    ``make(a, v)`` the curve through the points in arc length ``a``."""
    a = arc_length(points)
    fy = make(a, points[:, 0])
    fz = make(a, points[:, 1])
    for p, m in enumerate(counts):
        if present[p]:
            t = np.linspace(bounds[p], bounds[p + 1], m)
            out[offsets[p] : offsets[p + 1], 0] = fy(t)
            out[offsets[p] : offsets[p + 1], 1] = fz(t)
