"""Write railexu's YAML slices of the whole UK crossing 56E1-R245-1:9.25 and its check rail.

Run once (``python tracks/uk_crossing/make_full_slices.py``); it writes, beside itself,

* ``uk_crossing_full.yaml``: the crossing side (wing rail and nose) from the plain rail before
  the crossing (slice 4, s = -0.995 m) to the plain rail after it (slice 145, s = +2.258 m),
  slices 4-145 of CONTACT's ``uk_crossing.slcs`` (slices 1-4 are the same plain rail from
  s = -75 m, slices 145-148 the same plain rail to +50 m), with **feature points** derived here;
* ``check_rail_thr.yaml`` and ``check_rail_thr/*.txt``: the other side, the check rail beside the
  opposite stock rail, 31 slices at the positions of ``SectionPositionCheckRail_Thr.txt``.

Source data: CONTACT (E.A.H. Vollebregt, eve70a/CONTACT, Apache-2.0), ``testbank/profiles/
uk_crossing/`` (copied unchanged into ``uk_crossing/``; README.md beside this script).

Feature points (CONTACT's and railexu's meaning: arc-length positions along each slice's curve
that name the same physical point in every slice; railexu interpolates each *part* between two
features by its arc-length fraction, docs/switches-and-crossings.md). ``uk_crossing.slcs`` has
none, so each slice is split here into its rails and each rail gets the same kind of points:

1. **Rails.** A slice whose curve dips deeper than ``FLANGEWAY_DEPTH_M`` between its ends holds
   two rails, the nose (gauge side) and the wing rail (field side), parted at the flangeway's
   deepest point; slices before the first such slice hold the wing rail only (the plain rail
   becoming the wing rail), slices after the last one the nose only (the nose becoming the
   plain rail). The script checks this order (wing; nose + wing; nose) holds.
2. Per rail (all positions as ``y`` or depth, turned into arc lengths): its **start**; its
   **foot**, the first point from the start at ``FOOT_DEPTH_M`` below the rail's own top (the
   lower end of the gauge face: slices end at different depths); its **gauge corner**, the
   first point from the start at ``CORNER_DEPTH_M`` below its top (it moves with the rail: the
   wing rail's gauge face leaving at ~1:11, the rising nose's tip); its **crown edge** and
   **field corner**, the first points after the gauge corner where the rail falls steeper than
   ``CROWN_SLOPE`` and ``FIELD_SLOPE`` (the rounding of the top's field edge; the field corner
   at most ``FIELD_WINDOW_M`` beyond the crown edge); before the crown
   edge the **band end**, ``BAND_WIDTH_M`` beyond the gauge corner (on a wide nose or wing rail
   the running band between the gauge corner and the band end has a constant width, so that its
   points correspond by their lateral distance from the gauge corner; on a narrow one the band
   end follows the crown edge); the **flank**, ``FLANK_WIDTH_M`` beyond the field corner; its
   **end**. Each is kept at least 0.5 mm before the next (parts of positive length).
3. Features (15 per slice, -1 / null where absent): ``[nose start, foot, gauge corner, band
   end, crown edge, field corner, flank, flangeway bottom (nose end, wing start), wing foot,
   gauge corner, band end, crown edge, field corner, flank, wing end]``. Wing-only slices: the
   first seven absent and the eighth the curve's start; nose-only slices: the last seven absent
   and the eighth the curve's end. The nose's start is therefore an edge (its parts begin at the
   first two-rail slice, with the edge of its tip) and the wing rail ends with its own edge
   after the last.

Check rail (``CheckRail_Thr_k.txt``, ``y`` from -172 to -75 mm) and opposite stock rail
(``OppositeStockRail_k.txt``, identical to the plain rail ``Crossing_1.txt`` at all 6 positions):
assumed in the opposite rail's own axes (field side positive, the same origin as the crossing's
slices, mirrored onto the right rail by railexu as every right rail), at track positions from
``SectionPositionCheckRail_Thr.txt`` (second column, metres, the crossing slices' ``s``: the
check rail's middle lies opposite the nose's start). Each slice's curve is the check rail, a
flangeway continuing both flanks straight down to ``CHECK_FLANGEWAY_DEPTH_M`` (the files stop
33 mm and 19.5 mm below the top; below that no wheel reaches), and the opposite stock rail;
features ``[0, check rail end, flangeway end, curve end]``, the same in every slice.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE / "uk_crossing"
#: A dip below this depth between a curve's ends is the flangeway between nose and wing rail [m].
FLANGEWAY_DEPTH_M = 0.045
#: Depth below a rail's own top that marks its corners [m].
CORNER_DEPTH_M = 0.006
#: Depth below a rail's own top of its foot, the lower end of its gauge face [m].
FOOT_DEPTH_M = 0.018
#: Slope (dz/dy, z down) beyond which the rail's top has turned into its field flank [-].
FIELD_SLOPE = 0.5
#: Slope beyond which the top has turned into the rounding of its field edge [-].
CROWN_SLOPE = 0.1
#: Largest lateral distance from the crown edge to the field corner (a field edge that flattens
#: out along the track keeps its corner near the crown edge) [m].
FIELD_WINDOW_M = 0.005
#: Lateral width of the field flank below the field corner, kept as one part [m].
FLANK_WIDTH_M = 0.003
#: Largest lateral width of the part between the corners (the running band) [m].
BAND_WIDTH_M = 0.055
#: Depth to which the check rail's and the stock rail's flanks are continued [m].
CHECK_FLANGEWAY_DEPTH_M = 0.060
#: The crossing's slices used: the plain rail before (slice 4) to the plain rail after (145).
FIRST_SLICE, LAST_SLICE = 4, 145


def arc_mm(points_m: np.ndarray) -> np.ndarray:
    """Cumulative arc length [mm] along the polyline (as railexu measures features)."""
    p = points_m * 1000.0
    return np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))))


def _rise(z: np.ndarray, level: float) -> int:
    """Index of the first point at or above (``z <=``) ``level`` (z down)."""
    hits = np.flatnonzero(z <= level)
    if hits.size == 0:
        raise ValueError("the rail never rises to its corner level")
    return int(hits[0])


def rail_features(y, z, a, i0, i1) -> list[float]:
    """Foot, gauge corner, band end, crown edge, field corner, flank [mm along the curve] of
    the rail between points ``i0..i1``."""
    top = z[i0 : i1 + 1].min()
    foot = max(i0 + _rise(z[i0 : i1 + 1], top + FOOT_DEPTH_M), i0 + 1)
    g = i0 + _rise(z[i0 : i1 + 1], top + CORNER_DEPTH_M)
    slope = np.diff(z[g : i1 + 1]) / np.diff(y[g : i1 + 1])
    y_end = y[i1] - 0.001
    y_crown = min(_first_beyond(slope, CROWN_SLOPE, y, g, y[i1]), y_end - 0.0025)
    y_field = _first_beyond(slope, FIELD_SLOPE, y, g, y[i1])
    y_field = min(y_field, y_crown + FIELD_WINDOW_M, y_end - 0.002)
    y_crown = min(y_crown, y_field - 0.0005)
    y_band = min(y[g] + BAND_WIDTH_M, y_crown - 0.0005)
    y_flank = min(y_field + FLANK_WIDTH_M, y_end)
    at = np.interp([y_band, y_crown, y_field, y_flank], y[i0 : i1 + 1], a[i0 : i1 + 1])
    return [float(a[foot]), float(a[g]), *(float(v) for v in at)]


def _first_beyond(slope, limit, y, g, default) -> float:
    """``y`` of the first point after ``g`` where the slope exceeds ``limit`` (else default)."""
    hits = np.flatnonzero(slope > limit)
    return float(y[g + hits[0]]) if hits.size else float(default)


def crossing_slice_features(points_m: np.ndarray, kind: str) -> list[float | None]:
    """The 15 features [mm] of one crossing slice of ``kind`` 'wing', 'both' or 'nose'."""
    y, z = points_m[:, 0], points_m[:, 1]
    a = arc_mm(points_m)
    n = y.size - 1
    end = round(float(a[-1]), 4)
    if kind == "wing":
        return [None] * 7 + [0.0, *rail_features(y, z, a, 0, n), end]
    if kind == "nose":
        return [0.0, *rail_features(y, z, a, 0, n), end] + [None] * 7
    b = 1 + int(np.argmax(z[1:-1]))
    nose = rail_features(y, z, a, 0, b)
    wing = rail_features(y, z, a, b, n)
    return [0.0, *nose, float(a[b]), *wing, end]


def crossing_kinds(profiles: list[np.ndarray]) -> list[str]:
    """'wing' / 'both' / 'nose' per slice, checked to come in that order."""
    two = [p[1:-1, 1].max() > FLANGEWAY_DEPTH_M for p in profiles]
    first, last = two.index(True), len(two) - 1 - two[::-1].index(True)
    if not all(two[first : last + 1]):
        raise ValueError("the two-rail slices are not contiguous")
    return ["wing"] * first + ["both"] * (last - first + 1) + ["nose"] * (len(two) - last - 1)


def _positions(name: str) -> np.ndarray:
    return np.loadtxt(DATA / name)[:, 1]


def _fmt(values) -> str:
    return "[" + ", ".join("null" if v is None else f"{v:.4f}" for v in values) + "]"


def write_crossing(path: Path) -> None:
    """``uk_crossing_full.yaml``: slices FIRST_SLICE..LAST_SLICE with their features."""
    s = _positions("SectionPositionCrossing.txt")
    ks = range(FIRST_SLICE, LAST_SLICE + 1)
    profiles = [np.loadtxt(DATA / f"Crossing_{k}.txt") for k in ks]
    kinds = crossing_kinds(profiles)
    lines = [
        "# The whole UK crossing 56E1-R245-1:9.25 (S&C benchmark), crossing side: slices",
        f"# {FIRST_SLICE}-{LAST_SLICE} of CONTACT's uk_crossing.slcs (Apache-2.0, README.md),",
        "# plain rail to plain rail. Written by make_full_slices.py (feature points derived there:",
        "# 15 per slice in mm along its curve, nose then wing rail: see the script).",
        "# Do not edit.",
        "text_unit: m",
        "rails: [nose, wing rail]",
        "slices:",
    ]
    for k, p, kind in zip(ks, profiles, kinds, strict=True):
        feats = crossing_slice_features(p, kind)
        lines.append(f"  - s_m: {s[k - 1]:.5f}   # slice {k}: {kind}")
        lines.append(f"    profile: uk_crossing/Crossing_{k}.txt")
        lines.append(f"    features_mm: {_fmt(feats)}")
    path.write_text("\n".join(lines) + "\n")


def _continued_down(p0: np.ndarray, p1: np.ndarray, depth: float) -> np.ndarray:
    """The point where the line from ``p1`` through ``p0`` reaches ``z = depth`` (z down)."""
    t = (depth - p0[1]) / (p0[1] - p1[1])
    return p0 + t * (p0 - p1)


def check_rail_curve(check: np.ndarray, stock: np.ndarray) -> tuple[np.ndarray, list[float]]:
    """One slice of the check-rail side: check rail, deep flangeway, stock rail, features [mm]."""
    c_end = _continued_down(check[-1], check[-2], CHECK_FLANGEWAY_DEPTH_M)
    s_start = _continued_down(stock[0], stock[1], CHECK_FLANGEWAY_DEPTH_M)
    pts = np.vstack((check, c_end, s_start, stock))
    if np.any(np.diff(pts[:, 0]) <= 0.0):
        raise ValueError("the check-rail side's curve is not a graph z(y)")
    a = arc_mm(pts)
    n_c = check.shape[0]
    return pts, [0.0, float(a[n_c]), float(a[n_c + 1]), round(float(a[-1]), 4)]


def write_check_rail(path: Path, folder: Path) -> None:
    """``check_rail_thr.yaml`` and its slice files: check rail beside the opposite stock rail."""
    s = _positions("SectionPositionCheckRail_Thr.txt")
    stock = np.loadtxt(DATA / "OppositeStockRail_1.txt")
    for k in range(2, 7):  # the six stock-rail slices are one plain rail: checked, not assumed
        if not np.array_equal(np.loadtxt(DATA / f"OppositeStockRail_{k}.txt"), stock):
            raise ValueError(f"OppositeStockRail_{k}.txt differs from OppositeStockRail_1.txt")
    folder.mkdir(exist_ok=True)
    lines = [
        "# The check rail beside the opposite stock rail of the UK crossing 56E1-R245-1:9.25",
        "# (S&C benchmark, through route): CONTACT's CheckRail_Thr_k.txt at the positions of",
        "# SectionPositionCheckRail_Thr.txt and OppositeStockRail_1.txt (Apache-2.0, README.md),",
        "# joined by a flangeway 60 mm deep. Written by make_full_slices.py (features: [check",
        "# rail start, check rail end, flangeway end, stock rail end] in mm). Do not edit.",
        "text_unit: m",
        "rails: [check rail, stock rail]",
        "slices:",
    ]
    for k in range(1, s.size + 1):
        pts, feats = check_rail_curve(np.loadtxt(DATA / f"CheckRail_Thr_{k}.txt"), stock)
        name = f"check_rail_thr/slice_{k}.txt"
        np.savetxt(HERE / name, pts, fmt="%.10e")
        lines.append(f"  - s_m: {s[k - 1]:.5f}")
        lines.append(f"    profile: {name}")
        lines.append(f"    features_mm: {_fmt(feats)}")
    path.write_text("\n".join(lines) + "\n")


def write_plain_rail(path: Path) -> None:
    """The crossing's plain rail (``Crossing_1.txt``, the same points as slices 2-4, 145-148
    and every ``OppositeStockRail``) as a railexu rail profile: the track's rail outside the
    zone, so that the zone begins and ends on the rail the track carries (no step)."""
    points = np.loadtxt(DATA / "Crossing_1.txt")
    for k in (4, 145):
        if not np.array_equal(np.loadtxt(DATA / f"Crossing_{k}.txt"), points):
            raise ValueError(f"Crossing_{k}.txt differs from the plain rail Crossing_1.txt")
    header = (
        "railexu profile: rail, unit = m, lateral = outwards, height = down, canted = none\n"
        "The plain rail 56E1 of the UK crossing 56E1-R245-1:9.25 (S&C benchmark): CONTACT's\n"
        "testbank/profiles/uk_crossing/Crossing_1.txt (E.A.H. Vollebregt, eve70a/CONTACT,\n"
        "Apache-2.0), y field side positive, z down [m]; vertical (not inclined) as UK 56E1 S&C.\n"
        "Written by make_full_slices.py."
    )
    np.savetxt(path, points, fmt="%.10e", header=header)


if __name__ == "__main__":
    write_plain_rail(HERE / "uk_56e1_plain.txt")
    write_crossing(HERE / "uk_crossing_full.yaml")
    write_check_rail(HERE / "check_rail_thr.yaml", HERE / "check_rail_thr")
