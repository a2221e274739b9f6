"""The switch panel's rails as profile slices: stock rail and switch blade from a plain rail.

No public slices of a switch blade were found (CONTACT's S&C test bank has the crossing only), so
the blade and the stock rail are generated from the plain rail's profile with a stated planing
rule. Every number of the rule is a parameter of :class:`SwitchPlaning`, each railexu's
assumption with its physical reason (docs/switches-and-crossings.md, "The turnout").

In the axes of the route's rail on the switch side (field side ``y`` positive, ``z`` down, ``s``
from the switch toe along the route), with ``y_g`` the plain rail head's gauge-side edge and
``W`` its width:

- the **other route's rail** (the stock rail for this route's closed blade) leaves this route's
  rail tangentially: its lateral divergence is ``d(s) = R (1 - cos(s / R))`` with ``R`` the
  radius of the curved one of the two rails (a tangential switch: both gauge lines touch at
  the toe);
- the **blade** is the plain rail's head on the gauge side of ``y_g + w(s)``, its width
  ``w(s) = min(w_tip + d(s), W)`` (its back lies against the stock rail's undercut web, its tip
  ``w_tip`` wide under the stock rail's head), lowered by
  ``drop(s) = drop_tip max(0, 1 - s / L_rise)`` (a tip below the wheels, rising to full height
  over ``L_rise``);
- the **stock rail** is the plain rail moved to the field side by ``d(s)``, its head intact
  (the undercut lies below it); it leaves the slices where ``d(s)`` exceeds ``stock_reach``
  (beyond any wheel's field face);
- the surface a wheel meets is the top of the two: the blade where it is higher (its gauge
  face emerges in front of the stock rail's as ``d`` grows, its top rises above the stock
  rail's head), the stock rail elsewhere. Near the toe the lowered blade does not show at all.

Each slice is one polyline ``z(y)``: the blade's visible part, then the stock rail's (1 um
apart where they meet). Feature points make them two separate rails whose edges stay edges
(:mod:`railexu.profiles.variable.interpolate`), so that no spline runs across the step where
they meet. The interpolation pairs the points of two slices by their fraction of a part's
length, so the features also tie the *same material points* of each rail together
(CONTACT's idea of features): both rails are the plain rail moved rigidly (the blade lowered
by ``drop``, the stock rail moved by ``d``), and only where one rail hides the other does a
part's end move along the rail. Feature columns (:data:`FEATURES`):

- ``blade start``: the blade's lowest point (the continued gauge face's end; material);
- ``blade head end``: where the rail's own head profile begins above the continued gauge face
  (material), or just before the blade's visible end while the blade shows less;
- ``blade end``: where the stock rail comes on top (moves along the blade);
- a column always absent (the joint is no part);
- ``stock start``: the stock rail's first visible point (moves along it);
- ``stock head end``: the stock rail's head end (material) while it shows, else just after its
  start;
- ``stock corner``: the stock rail's point ``tip_width + 1 mm`` field-side of its head's
  gauge-side edge (material): the blade (``tip_width + d`` wide, its back against the stock
  rail's web) never covers it, so the stock rail's head from there on, where wheels run, is
  one material part in every slice;
- ``stock end``.

NaN where a rail is absent (the blade where it does not show, the stock rail beyond
``stock_reach``). Without the material features the stock rail's part began at its visible
start, which jumps from its gauge face's foot to its head where the blade's gauge face takes
over (0.850-0.875 m from the toe at R 245 m): the fractions then paired points 27 mm apart
along the rail, an 84 um dip of the stock rail's top under a centred wheel and a 5.7 mm
(vertical) error on the gauge face between two slices that agree within 0.23 mm
(docs/switches-and-crossings.md, "The switch panel"). The rail's gauge face is continued
downwards (:func:`extended_gauge_face`). ``runout``: the zone begins that far ahead of the toe
(the plain rail there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railexu.profiles.core import ProfileError
from railexu.profiles.variable.slices import ProfileSlices, arc_length, check_slices

#: Narrowest blade that shows above the stock rail [m] (a narrower strip is left out).
MIN_VISIBLE_M = 2.0e-4
#: Width of the joint between the blade's back and the stock rail's cut face [m] (a graph
#: ``z(y)`` needs ``y`` to increase; 1 um is far below the kernel's 0.1 mm table step).
JOINT_WIDTH_M = 1.0e-6
#: Shortest part that ties a moving part end to a material feature [m] along the rail.
TIE_LENGTH_M = 1.0e-4
#: How far field-side of the blade's widest reach under the stock rail's head (``tip_width``
#: from its gauge-side edge) the stock rail's ``stock corner`` feature lies [m].
CORNER_MARGIN_M = 1.0e-3
#: The feature columns of a switch panel's slices (module docstring).
FEATURES = ("blade start", "blade head end", "blade end", "joint (absent)", "stock start",
            "stock head end", "stock corner", "stock end")  # fmt: skip


@dataclass(frozen=True)
class SwitchPlaning:
    """The planing rule of the switch blade and the stock rail (railexu's assumptions).

    Attributes:
        tip_width_m: the blade's head width at the toe [m] (a tip thinner than a few mm breaks;
            6 mm: railexu's assumption).
        tip_drop_m: how far the blade's top lies below the stock rail's at the toe [m] (so that
            no wheel strikes the thin tip; 10 mm: railexu's assumption).
        rise_length_m: length over which the blade rises linearly to full height [m] (3.5 m:
            the blade's head is then ~30 mm wide on an R 245 m switch, wide enough to carry a
            wheel; railexu's assumption).
        runout_m: how far ahead of the toe the slices begin (the plain rail there) [m] (0.2 m:
            railexu's assumption).
        stock_reach_m: divergence beyond which the other route's rail is dropped from the
            slices [m] (0.13 m: its cut edge then lies > 85 mm field-side of the rail's crown,
            beyond the field face of a wheel displaced 10 mm; railexu's assumption).
        slice_step_m: spacing of the generated slices [m] (25 mm: the visible parts of blade
            and stock rail change their extent from slice to slice; with the material feature
            points (:data:`FEATURES`) the surface at 25 mm lies within 59 um (normal distance)
            of the rule's own 12.5 mm slices on the running band at R 245 m, 2.5 um where the
            blade's gauge face takes over, 0.850-0.875 m from the toe; railexu's choice).
    """

    tip_width_m: float = 0.006
    tip_drop_m: float = 0.010
    rise_length_m: float = 3.5
    runout_m: float = 0.2
    stock_reach_m: float = 0.13
    slice_step_m: float = 0.025

    def __post_init__(self) -> None:
        limits = {
            "tip_width_m": (0.0005, 0.05),
            "tip_drop_m": (0.0, 0.05),
            "rise_length_m": (0.1, 30.0),
            "runout_m": (0.01, 5.0),
            "stock_reach_m": (0.02, 1.0),
            "slice_step_m": (0.01, 2.0),
        }
        for name, (lo, hi) in limits.items():
            value = getattr(self, name)
            if not (math.isfinite(value) and lo <= value <= hi):
                raise ProfileError(f"switch planing: {name} = {value}: expected {lo} .. {hi}")


def divergence_m(s_m: np.ndarray | float, radius_m: float) -> np.ndarray:
    """Lateral distance [m] between two rails that touch tangentially at ``s = 0``, one
    straight and one of radius ``radius_m``, at ``s`` along them (0 before the toe)."""
    s = np.maximum(np.asarray(s_m, dtype=float), 0.0)
    return radius_m * (1.0 - np.cos(np.minimum(s / radius_m, 0.5 * math.pi)))


#: Depth below the rail's top to which the gauge face is continued [m] (a flange reaches ~30 mm
#: below the tread; railexu's assumption, see :func:`extended_gauge_face`).
GAUGE_FACE_DEPTH_M = 0.045


def extended_gauge_face(points_m: np.ndarray, depth_m: float = GAUGE_FACE_DEPTH_M) -> np.ndarray:
    """The rail's points with its gauge face continued downwards at its end slope.

    Rail profiles end some 13 mm below the top (MBench_UIC60: 13.3 mm), and the kernel's table
    continues flat beyond a curve's end. A blade lowered by 10 mm would meet a flange there on
    that flat continuation (a false corner: forces of several hundred kN in the diverging route);
    the real blade's gauge face runs on down to its foot. The face is continued as a straight
    line with the slope of the profile's last 0.5 mm (at least 5:1, steeper than any flange
    flank) down to ``depth_m`` below the top, in 0.2 mm steps.
    """
    p = np.asarray(points_m, dtype=float)
    z_top = float(np.min(p[:, 1]))
    y0, z0 = float(p[0, 0]), float(p[0, 1])
    k = int(np.searchsorted(p[:, 0], y0 + 5.0e-4))
    slope = max((z0 - float(p[k, 1])) / max(float(p[k, 0]) - y0, 1e-9), 5.0)
    depth = z_top + depth_m - z0
    if depth <= 0.0:
        return p
    dz = np.arange(depth, 0.0, -2.0e-4)
    extra = np.column_stack([y0 - dz / slope, z0 + dz])
    return np.vstack((extra, p))


def switch_panel_slices(
    rail_points_m: np.ndarray, radius_m: float, planing: SwitchPlaning, source: str
) -> ProfileSlices:
    """Slices of one side's switch panel from the plain rail's points (see the module docstring).

    Args:
        rail_points_m: the plain rail's head ``(y, z)`` [m], ``y`` increasing, ``z`` down, in
            the rail's own axes (field side positive).
        radius_m: radius of the curved one of the blade and the stock rail [m].
        planing: the planing rule.
        source: a name for messages (the turnout file).

    Returns:
        slices from ``-runout`` before the toe to the first slice beyond ``stock_reach``, the
        last one the plain rail (the blade at full width and height, the stock rail gone).
    """
    p = np.asarray(rail_points_m, dtype=float)
    if p.ndim != 2 or p.shape[0] < 4 or not np.all(np.diff(p[:, 0]) > 0):
        raise ProfileError(f"{source}: the plain rail's points must be a graph z(y), y increasing")
    head = p
    y_head = float(p[0, 0])  # the head's gauge-side edge: the blade's width is measured from it
    p = extended_gauge_face(p)
    if not (math.isfinite(radius_m) and radius_m >= 50.0):
        raise ProfileError(f"{source}: switch radius {radius_m} m: expected >= 50 m")
    s_end = radius_m * math.acos(1.0 - planing.stock_reach_m / radius_m)
    n = int(math.ceil(s_end / planing.slice_step_m))
    regular = planing.slice_step_m * np.arange(n + 1)  # the last at or beyond s_end
    stations = [-planing.runout_m, *regular, regular[-1] + 0.01]  # then the plain rail
    points, features, names = [], [], []
    # the head's end on the rail with its gauge face continued: the continued face's length
    head_end_m = max(float(arc_length(p)[p.shape[0] - head.shape[0]]), TIE_LENGTH_M)
    nan = math.nan
    for k, s in enumerate(stations):
        if k == len(stations) - 1:  # the plain rail: the blade alone
            pts, feat = p.copy(), [0.0, head_end_m, math.inf, nan, nan, nan, nan, nan]
        else:
            pts, feat = _panel_section(p, y_head, float(s), radius_m, planing)
        points.append(pts)
        features.append(feat)
        names.append(f"switch panel s = {s:.3f} m")
    f = np.array(features)
    lengths = np.array([arc_length(q)[-1] for q in points])
    f = np.where(np.isinf(f), lengths[:, None], f)
    slices = ProfileSlices(source, np.array(stations, dtype=float), tuple(points), f,
                           (None,) * len(stations), tuple(names),
                           ("blade", "stock rail"))  # fmt: skip
    check_slices(slices)
    return slices


def _panel_section(
    p: np.ndarray, y_g: float, s: float, radius_m: float, planing: SwitchPlaning
) -> tuple[np.ndarray, list[float]]:
    """The top surface at ``s`` from the toe (``p``: the plain rail with its gauge face
    continued, ``y_g``: its head's gauge-side edge) as blade and stock rail, and the curve's
    features (:data:`FEATURES`; the blade's absent where it does not show)."""
    y_f = float(p[-1, 0])
    d = float(divergence_m(s, radius_m))
    w = min(planing.tip_width_m + d, y_f - y_g)
    drop = planing.tip_drop_m * max(0.0, 1.0 - max(s, 0.0) / planing.rise_length_m)
    blade = _cut(p, hi=y_g + w)
    blade[:, 1] += drop
    stock = p.copy()
    stock[:, 0] += d
    y_corner = min(y_g + planing.tip_width_m + CORNER_MARGIN_M, y_f - MIN_VISIBLE_M) + d
    y_s = _stock_on_top_from(blade, stock)
    nan = math.nan
    if y_s - blade[0, 0] < MIN_VISIBLE_M:  # the blade hidden under the stock rail's head
        a = arc_length(stock)
        head_end = max(float(np.interp(y_g + d, stock[:, 0], a)), TIE_LENGTH_M)
        corner = max(float(np.interp(y_corner, stock[:, 0], a)), head_end + TIE_LENGTH_M)
        return stock, [nan, nan, nan, nan, 0.0, head_end, corner, math.inf]
    blade = _cut(blade, hi=y_s)
    stock = _cut(stock, lo=min(y_s + JOINT_WIDTH_M, float(stock[-1, 0]) - MIN_VISIBLE_M))
    a_blade = arc_length(blade)
    blade_len = float(a_blade[-1])
    # the blade's head end (material) once it shows, else tied to the blade's visible end
    blade_head = float(np.interp(y_g, blade[:, 0], a_blade))
    blade_head = min(max(blade_head, TIE_LENGTH_M), blade_len - TIE_LENGTH_M)
    start = blade_len + float(np.hypot(*(stock[0] - blade[-1])))  # the joint: no part
    a_stock = start + arc_length(stock)
    stock_head = max(float(np.interp(y_g + d, stock[:, 0], a_stock)), start + TIE_LENGTH_M)
    corner = max(float(np.interp(y_corner, stock[:, 0], a_stock)), stock_head + TIE_LENGTH_M)
    features = [0.0, blade_head, blade_len, nan, start, stock_head, corner, math.inf]
    return np.vstack((blade, stock)), features


def _stock_on_top_from(blade: np.ndarray, stock: np.ndarray) -> float:
    """The lateral position from which the stock rail is the top surface (z down: smaller is
    higher): the first point of their common range where the stock rail is at least as high
    as the blade, or the blade's back if the blade is higher all across."""
    lo, hi = float(stock[0, 0]), float(blade[-1, 0])
    if hi <= lo:
        return hi
    y = np.linspace(lo, hi, max(2, int((hi - lo) / 1.0e-5) + 1))
    on_top = np.interp(y, stock[:, 0], stock[:, 1]) <= np.interp(y, blade[:, 0], blade[:, 1])
    return float(y[int(np.argmax(on_top))]) if np.any(on_top) else hi


def _cut(p: np.ndarray, lo: float | None = None, hi: float | None = None) -> np.ndarray:
    """The points of ``p`` within ``[lo, hi]`` in ``y``, with the cut ends interpolated."""
    y0 = p[0, 0] if lo is None else lo
    y1 = p[-1, 0] if hi is None else hi
    inside = p[(p[:, 0] > y0 + 1e-9) & (p[:, 0] < y1 - 1e-9)]  # no near-duplicate ends
    ends = np.array([[y0, np.interp(y0, p[:, 0], p[:, 1])], [y1, np.interp(y1, p[:, 0], p[:, 1])]])
    return np.vstack((ends[:1], inside, ends[1:]))


__all__ = ["SwitchPlaning", "divergence_m", "extended_gauge_face", "switch_panel_slices"]
