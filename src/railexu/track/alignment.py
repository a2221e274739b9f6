"""Track design geometry: the centre line's plan, heading, curvature and cant along the track.

A track's ``geometry:`` section (``docs/track-format.md``) is a sequence of sections::

    geometry:
      type: sections
      cant_base: 1.5 m                 # distance of the rail centres the cant is measured over
      sections:
        - {type: straight, length: 100 m}
        - {type: transition, length: 60 m}            # clothoid, linear cant ramp (default)
        - {type: curve, length: 300 m, radius: 600 m, cant: 100 mm, direction: left}
        - {type: transition, length: 60 m, shape: bloss}
        - {type: straight, length: 100 m}

or ``type: measured`` with a CSV file of distance [m], curvature [1/m] and cant [m], as track
recording cars give them, or ``type: straight`` (the default).

Conventions (``docs/conventions.md``, ``docs/curving.md``):

- distance ``s`` along the centre line from the start of the geometry, ``s < 0`` and beyond the
  end continue straight along the tangent;
- curvature ``kappa`` > 0 in a curve to the **left** (seen in the direction of travel);
- cant ``c`` is the height of the outer rail above the inner one, signed like the curvature it
  belongs to: ``c > 0`` raises the right rail (the outer rail of a left curve). The track frame is
  rolled about the centre line at the top of rail by the cant angle
  ``phi_c = -asin(c / cant_base)`` (positive ``phi_c`` raises the left rail, as the roll of a
  wheelset);
- transitions join the curvature and cant of the neighbouring sections. A clothoid has a
  curvature linear in ``s`` and a linear cant ramp; the Bloss transition uses
  ``f(u) = 3 u^2 - 2 u^3`` for both (Bloss 1936, after Lindahl 2001, "Track geometry for
  high-speed railways", KTH report TRITA-FKT 2001:54, ch. 3).

Heading is the exact integral of the curvature (a polynomial in each section); the plan position
``x + i y = integral of exp(i psi) ds`` is integrated by 32-point Gauss-Legendre quadrature in each
section, which is exact to rounding for the heading changes of railway sections (the tests compare
a clothoid with Fresnel's integrals, :func:`scipy.special.fresnel`). Position and heading are
therefore continuous everywhere; curvature and cant are continuous wherever the file joins
sections by transitions.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from railexu.errors import InputError
from railexu.inputs import Section

#: Default cant base: the distance of the rail centres of standard-gauge track [m].
CANT_BASE_M = 1.5
SHAPES = ("clothoid", "bloss")
SECTION_KEYS = {
    "straight": ("type", "length"),
    "transition": ("type", "length", "shape"),
    "curve": ("type", "length", "radius", "cant", "direction"),
}
GEOMETRY_KEYS = {
    "straight": ("type",),
    "sections": ("type", "sections", "cant_base"),
    "measured": ("type", "file", "cant_base"),
}
#: Smallest curve radius of a geometry, designed or measured [m]: below the tightest tram curves
#: (about 15-25 m) railexu's vehicles do not go, and mainline curves stay above 150 m; 50 m
#: (depots, sidings) is the lowest that the trajectory coordinates and the contact model cover.
MIN_RADIUS_M = 50.0
#: Largest cant as a fraction of the cant base (0.3 x 1.5 m = 450 mm, above the 180-200 mm
#: that EN 13803 allows): more is a unit mistake.
MAX_CANT_FRACTION = 0.3

_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(32)

#: Columns of :meth:`Alignment.table` (what the compiled kernel interpolates).
TAB_X, TAB_Y, TAB_PSI, TAB_KAPPA, TAB_CANT, TAB_DKAPPA, TAB_DCANT = range(7)
#: The vehicle frame's roll: the cant angle smoothed along the track, and its derivatives.
TAB_FROLL, TAB_DFROLL, TAB_DDFROLL = range(7, 10)
TAB_COLUMNS = 10
#: Smoothing length (Gaussian standard deviation) of the vehicle frame's roll [m].
FRAME_ROLL_SMOOTHING_M = 5.0
#: Rounding of the kinks of the cant under the wheels (Gaussian standard deviation) [m]: a rail
#: cannot follow a kink of its height over less than about its bending length (of the order of
#: a metre for a UIC60 rail on ballast; Knothe & Grassie 1993).
CANT_ROUNDING_M = 1.0


@dataclass(frozen=True)
class DesignSection:
    """One section of the design geometry as the file gives it (for figures and statistics)."""

    kind: str  # straight | transition | curve | measured
    start_m: float
    length_m: float
    curvature_1_per_m: float = 0.0  # at the end of the section (constant in a curve)
    cant_m: float = 0.0  # signed like the curvature, at the end of the section

    @property
    def end_m(self) -> float:
        return self.start_m + self.length_m

    @property
    def radius_m(self) -> float:
        k = self.curvature_1_per_m
        return math.inf if k == 0.0 else 1.0 / abs(k)


@dataclass
class Alignment:
    """Design geometry of a track's centre line (see the module docstring for conventions).

    The geometry is a list of pieces; in piece ``i`` (from ``start[i]``, length ``length[i]``)
    with ``u = (s - start) / length`` the curvature is ``k0 + dk f(u)`` and the cant
    ``c0 + dc f(u)``, ``f(u) = u`` (clothoid, constant pieces have ``dk = dc = 0``) or
    ``3 u^2 - 2 u^3`` (Bloss).
    """

    start: np.ndarray
    length: np.ndarray
    k0: np.ndarray
    dk: np.ndarray
    c0: np.ndarray
    dc: np.ndarray
    bloss: np.ndarray  # bool per piece
    cant_base_m: float = CANT_BASE_M
    sections: list[DesignSection] = field(default_factory=list)
    source: str = ""
    psi0: np.ndarray = field(init=False)
    x0: np.ndarray = field(init=False)
    y0: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        n = self.start.size
        self.psi0 = np.zeros(n + 1)
        self.x0 = np.zeros(n + 1)
        self.y0 = np.zeros(n + 1)
        for i in range(n):
            self.psi0[i + 1] = self.psi0[i] + self._heading_increment(i, 1.0)
            dx, dy = self._chord(i, 1.0)
            self.x0[i + 1] = self.x0[i] + dx
            self.y0[i + 1] = self.y0[i] + dy

    # -- construction helpers ---------------------------------------------------------------
    @property
    def end_m(self) -> float:
        return float(self.start[-1] + self.length[-1]) if self.start.size else 0.0

    @property
    def is_straight(self) -> bool:
        """True when the track has neither curvature nor cant anywhere."""
        return not (np.any(self.k0) or np.any(self.dk) or np.any(self.c0) or np.any(self.dc))

    def _shape(self, i, u):
        return np.where(self.bloss[i], u * u * (3.0 - 2.0 * u), u)

    def _shape_slope(self, i, u):
        return np.where(self.bloss[i], 6.0 * u * (1.0 - u), 1.0)

    def _shape_integral(self, i, u):
        return np.where(self.bloss[i], u**3 - 0.5 * u**4, 0.5 * u * u)

    def _heading_increment(self, i, u):
        """Heading change from the start of piece ``i`` to ``u`` [rad]."""
        return self.length[i] * (self.k0[i] * u + self.dk[i] * self._shape_integral(i, u))

    def _chord(self, i, u):
        """Plan offset from the start of piece ``i`` to ``u`` (Gauss-Legendre) [m]."""
        u = np.asarray(u, dtype=float)
        v = 0.5 * u[..., None] * (_GL_NODES + 1.0)  # nodes on [0, u]
        ii = np.asarray(i)[..., None]
        psi = self._heading_increment(ii, v)
        w = 0.5 * u[..., None] * _GL_WEIGHTS
        length = np.asarray(self.length[i])
        psi_start = np.asarray(self.psi0[i])
        c = np.cos(psi_start[..., None] + psi)
        s = np.sin(psi_start[..., None] + psi)
        return length * np.sum(w * c, axis=-1), length * np.sum(w * s, axis=-1)

    def _locate(self, s):
        """Piece index and ``u`` of every distance; ``u`` outside [0, 1] only before the first
        and after the last piece (straight continuation)."""
        s = np.asarray(s, dtype=float)
        i = np.clip(np.searchsorted(self.start, s, side="right") - 1, 0, self.start.size - 1)
        u = (s - self.start[i]) / self.length[i]
        return i, u

    # -- public geometry --------------------------------------------------------------------
    def curvature(self, s) -> np.ndarray:
        """Curvature [1/m], positive to the left; zero outside the geometry."""
        i, u = self._locate(s)
        inside = (u >= 0.0) & (u <= 1.0)
        uc = np.clip(u, 0.0, 1.0)
        return np.where(inside, self.k0[i] + self.dk[i] * self._shape(i, uc), 0.0)

    def curvature_slope(self, s) -> np.ndarray:
        """d(curvature)/ds [1/m^2]."""
        i, u = self._locate(s)
        inside = (u >= 0.0) & (u <= 1.0)
        uc = np.clip(u, 0.0, 1.0)
        return np.where(inside, self.dk[i] * self._shape_slope(i, uc) / self.length[i], 0.0)

    def cant(self, s) -> np.ndarray:
        """Cant [m], signed like the curvature (positive: right rail higher); zero outside."""
        i, u = self._locate(s)
        inside = (u >= 0.0) & (u <= 1.0)
        uc = np.clip(u, 0.0, 1.0)
        return np.where(inside, self.c0[i] + self.dc[i] * self._shape(i, uc), 0.0)

    def cant_slope(self, s) -> np.ndarray:
        """d(cant)/ds [m/m]."""
        i, u = self._locate(s)
        inside = (u >= 0.0) & (u <= 1.0)
        uc = np.clip(u, 0.0, 1.0)
        return np.where(inside, self.dc[i] * self._shape_slope(i, uc) / self.length[i], 0.0)

    def cant_angle(self, s) -> np.ndarray:
        """Roll of the track frame about its x axis [rad]: ``-asin(cant / cant_base)``."""
        return -np.arcsin(np.clip(self.cant(s) / self.cant_base_m, -1.0, 1.0))

    def cant_angle_slope(self, s) -> np.ndarray:
        """d(cant angle)/ds [rad/m]."""
        c = self.cant(s) / self.cant_base_m
        return -self.cant_slope(s) / self.cant_base_m / np.sqrt(1.0 - np.minimum(c * c, 0.99))

    def heading(self, s) -> np.ndarray:
        """Heading of the centre line [rad], counter-clockwise from the plan's x axis."""
        i, u = self._locate(s)
        uc = np.clip(u, 0.0, 1.0)
        psi = self.psi0[i] + self._heading_increment(i, uc)
        return np.asarray(psi, dtype=float)

    def position(self, s) -> tuple[np.ndarray, np.ndarray]:
        """Plan position (x, y) of the centre line [m]; the geometry starts at (0, 0) heading
        along x."""
        s = np.asarray(s, dtype=float)
        i, u = self._locate(s)
        uc = np.clip(u, 0.0, 1.0)
        dx, dy = self._chord(i, uc)
        x = self.x0[i] + dx
        y = self.y0[i] + dy
        # straight continuation before the start and after the end
        extra = (u - uc) * self.length[i]
        psi = self.psi0[i] + self._heading_increment(i, uc)
        return x + extra * np.cos(psi), y + extra * np.sin(psi)

    def table(
        self,
        s_min: float,
        s_max: float,
        step: float = 0.25,
        smoothing_m: float = FRAME_ROLL_SMOOTHING_M,
        rounding_m: float = CANT_ROUNDING_M,
    ):
        """Samples for the compiled kernel: ``(start, step, values)`` with ``values`` of shape
        ``(n, TAB_COLUMNS)`` (columns ``TAB_*``), from ``s_min`` to at least ``s_max``.

        The vehicle frame's roll (``TAB_FROLL`` and its first and second derivatives) is the
        cant angle smoothed by a Gaussian of ``smoothing_m``: the frame need not follow the cant
        exactly (the contact uses the local cant), and a smooth roll keeps the frame's angular
        acceleration finite where a linear cant ramp has a kink. The cant the wheels see is
        rounded at such kinks by a Gaussian of ``rounding_m`` (``TAB_CANT``, ``TAB_DCANT``)."""
        from scipy.ndimage import gaussian_filter1d

        n = int(math.ceil((s_max - s_min) / step)) + 2
        s = s_min + step * np.arange(n)
        values = np.zeros((n, TAB_COLUMNS))
        values[:, TAB_X], values[:, TAB_Y] = self.position(s)
        values[:, TAB_PSI] = self.heading(s)
        values[:, TAB_KAPPA] = self.curvature(s)
        values[:, TAB_CANT] = self.cant_angle(s)
        values[:, TAB_DKAPPA] = self.curvature_slope(s)
        values[:, TAB_DCANT] = self.cant_angle_slope(s)
        if rounding_m > 0.0:
            values[:, TAB_CANT] = gaussian_filter1d(
                values[:, TAB_CANT], rounding_m / step, mode="nearest"
            )
            values[:, TAB_DCANT] = np.gradient(values[:, TAB_CANT], step)
        roll = values[:, TAB_CANT]
        if smoothing_m > 0.0:
            roll = gaussian_filter1d(roll, smoothing_m / step, mode="nearest")
        values[:, TAB_FROLL] = roll
        values[:, TAB_DFROLL] = np.gradient(roll, step)
        values[:, TAB_DDFROLL] = np.gradient(values[:, TAB_DFROLL], step)
        return float(s_min), float(step), np.ascontiguousarray(values)

    def constant_curves(self) -> list[DesignSection]:
        """The constant-radius parts (``curve`` sections) of the geometry."""
        return [sec for sec in self.sections if sec.kind == "curve"]

    def to_dict(self) -> dict:
        """The geometry as plain lists (JSON), from which :func:`alignment_from_record` rebuilds
        it exactly: a run's ``summary.json`` keeps it so that ``railexu plot`` can redraw the
        track and curving figures without the track file."""
        return {
            "cant_base_m": float(self.cant_base_m),
            "pieces": {name: [float(v) for v in getattr(self, name)]
                       for name in ("start", "length", "k0", "dk", "c0", "dc")},
            "bloss": [bool(v) for v in self.bloss],
            "sections": [[sec.kind, sec.start_m, sec.length_m, sec.curvature_1_per_m, sec.cant_m]
                         for sec in self.sections],
            "source": self.source,
        }  # fmt: skip


# ---------------------------------------------------------------------------------------------
def straight_alignment() -> Alignment:
    """Straight track without cant (the default geometry)."""
    one = np.ones(1)
    zero = np.zeros(1)
    return Alignment(
        np.zeros(1), one * 1000.0, zero, zero, zero, zero, np.zeros(1, bool),
        sections=[DesignSection("straight", 0.0, 1000.0)],
    )  # fmt: skip


def alignment_from_sections(
    sections: list[dict], cant_base_m: float = CANT_BASE_M, source: str = ""
) -> Alignment:
    """An :class:`Alignment` from already validated sections: dicts with ``type``,
    ``length_m`` and, for curves, ``curvature_1_per_m`` (signed) and ``cant_m`` (signed like
    the curvature), for transitions ``shape``."""
    n = len(sections)
    k_end = np.zeros(n)
    c_end = np.zeros(n)
    for j, sec in enumerate(sections):
        if sec["type"] == "curve":
            k_end[j] = sec["curvature_1_per_m"]
            c_end[j] = sec["cant_m"]
    # a transition runs from the previous section's end values to the next section's start
    fixed = [sec["type"] != "transition" for sec in sections]
    start, length, k0, dk, c0, dc, bloss, design = [], [], [], [], [], [], [], []
    s = 0.0
    for j, sec in enumerate(sections):
        if sec["type"] == "transition":
            prev = next((i for i in range(j - 1, -1, -1) if fixed[i]), None)
            nxt = next((i for i in range(j + 1, n) if fixed[i]), None)
            ka = k_end[prev] if prev is not None else 0.0
            ca = c_end[prev] if prev is not None else 0.0
            kb = k_end[nxt] if nxt is not None else 0.0
            cb = c_end[nxt] if nxt is not None else 0.0
            k0.append(ka), dk.append(kb - ka), c0.append(ca), dc.append(cb - ca)
            bloss.append(sec.get("shape", "clothoid") == "bloss")
            k_end[j], c_end[j] = kb, cb
        else:
            k0.append(k_end[j]), dk.append(0.0), c0.append(c_end[j]), dc.append(0.0)
            bloss.append(False)
        start.append(s)
        length.append(sec["length_m"])
        design.append(DesignSection(sec["type"], s, sec["length_m"], k_end[j], c_end[j]))
        s += sec["length_m"]
    return Alignment(
        np.array(start), np.array(length), np.array(k0), np.array(dk), np.array(c0),
        np.array(dc), np.array(bloss, dtype=bool), cant_base_m, design, source,
    )  # fmt: skip


def alignment_from_samples(
    distance_m: np.ndarray,
    curvature_1_per_m: np.ndarray,
    cant_m: np.ndarray,
    cant_base_m: float = CANT_BASE_M,
    source: str = "",
) -> Alignment:
    """An :class:`Alignment` from measured samples (curvature and cant linear between samples,
    i.e. short clothoids); the distances are shifted to start at 0."""
    d = np.asarray(distance_m, float)
    k = np.asarray(curvature_1_per_m, float)
    c = np.asarray(cant_m, float)
    start = d[:-1] - d[0]
    length = np.diff(d)
    return Alignment(
        start, length, k[:-1], np.diff(k), c[:-1], np.diff(c), np.zeros(start.size, bool),
        cant_base_m, [DesignSection("measured", 0.0, float(d[-1] - d[0]), 0.0, 0.0)], source,
    )  # fmt: skip


def alignment_from_record(record: dict) -> Alignment:
    """Rebuild an :class:`Alignment` from :meth:`Alignment.to_dict`'s output.

    Raises:
        InputError: the record lacks a field or has pieces of different lengths.
    """
    try:
        pieces = {k: np.asarray(record["pieces"][k], dtype=float)
                  for k in ("start", "length", "k0", "dk", "c0", "dc")}  # fmt: skip
        bloss = np.asarray(record["bloss"], dtype=bool)
        sections = [DesignSection(str(k), float(a), float(b), float(c), float(d))
                    for k, a, b, c, d in record["sections"]]  # fmt: skip
        base = float(record["cant_base_m"])
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"track geometry record: missing or bad field ({exc})") from None
    if len({v.size for v in pieces.values()} | {bloss.size}) != 1 or bloss.size == 0:
        raise InputError("track geometry record: pieces of different lengths")
    return Alignment(
        pieces["start"], pieces["length"], pieces["k0"], pieces["dk"], pieces["c0"],
        pieces["dc"], bloss, base, sections, str(record.get("source", "")),
    )  # fmt: skip


def read_measured_geometry(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a CSV of distance [m], curvature [1/m, positive left] and cant [m, positive: right
    rail higher]; lines starting with ``#`` and a header line are skipped.

    Raises:
        InputError: unreadable numbers, fewer than 2 rows or distances not increasing.
    """
    rows = []
    with open(path, newline="") as fh:
        for lineno, row in enumerate(csv.reader(fh), start=1):
            if not row or row[0].lstrip().startswith("#"):
                continue
            try:
                values = [float(v) for v in row[:3]]
            except ValueError:
                if rows:
                    raise InputError(
                        f"expected three numbers (distance, curvature, cant), got {row!r}",
                        source=str(path), line=lineno,
                    ) from None  # fmt: skip
                continue  # header
            if len(values) != 3:
                raise InputError(
                    "expected three columns: distance [m], curvature [1/m], cant [m]",
                    source=str(path), line=lineno,
                )  # fmt: skip
            _check_measured_row(values, str(path), lineno)
            rows.append(values)
    data = np.array(rows)
    if data.shape[0] < 2 or np.any(np.diff(data[:, 0]) <= 0.0):
        raise InputError("needs at least two rows with increasing distance", source=str(path))
    return data[:, 0], data[:, 1], data[:, 2]


def _check_measured_row(values: list[float], source: str, line: int) -> None:
    """A measured geometry row: finite, curvature within 1 / :data:`MIN_RADIUS_M` (the designed
    sections' limit), cant at most 0.3 m (the cant base is checked by the caller)."""
    distance, curvature, cant = values
    if not all(math.isfinite(v) for v in values):
        raise InputError(f"expected finite numbers, got {values}", source=source, line=line)
    if abs(curvature) > 1.0 / MIN_RADIUS_M:
        raise InputError(
            f"curvature {curvature:g} 1/m is a radius of {1.0 / abs(curvature):.3g} m, below the "
            f"{MIN_RADIUS_M:g} m of railexu's geometries (docs/track-format.md)",
            source=source, line=line,
        )  # fmt: skip
    if abs(distance) > 1.0e6 or abs(cant) > 0.5:
        raise InputError(
            f"distance {distance:g} m or cant {cant:g} m out of range (|distance| <= 1000 km, "
            "|cant| <= 0.5 m): is a unit wrong?",
            source=source, line=line,
        )  # fmt: skip


def alignment_from_dict(
    data: dict | None, source: str = "<track>", lines: dict | None = None, path=None
) -> Alignment:
    """Validate a track file's ``geometry:`` section into an :class:`Alignment`.

    Args:
        data: the section's mapping (``None``: straight track).
        source, lines: file name and line numbers for messages (:func:`railexu.inputs.load_yaml`).
        path: folder that a measured geometry's file name is relative to.

    Raises:
        InputError: naming file, line and key.
    """
    if data is None:
        return straight_alignment()
    top = Section(data, source, lines, ("geometry",))
    kind = top.string("type", default="straight", choices=tuple(GEOMETRY_KEYS))
    top = Section(data, source, lines, ("geometry",), GEOMETRY_KEYS[kind])
    if kind == "straight":
        return straight_alignment()
    base = top.quantity("cant_base", "m", default=CANT_BASE_M, minimum=0.5, maximum=3.0)
    if kind == "measured":
        file = Path(top.string("file"))
        if not file.is_absolute() and path is not None:
            file = Path(path) / file
        if not file.exists():
            top.fail(f"geometry file {str(file)!r} not found", key="file")
        try:
            d, k, c = read_measured_geometry(file)
        except InputError as exc:  # the track file's line too, then the data file's
            top.fail(str(exc), key="file")
        if np.any(np.abs(c) >= base):
            top.fail("a cant in the file is not smaller than the cant base", key="file")
        return alignment_from_samples(d, k, c, base, source)
    raw = top.data.get("sections")
    if not isinstance(raw, list) or not raw:
        top.fail("expected a list of sections ({type: straight|transition|curve, ...})",
                 key="sections")  # fmt: skip
    sections = [_section(item, j, source, lines, base) for j, item in enumerate(raw)]
    for j, sec in enumerate(sections):
        if sec["type"] == "transition" and j > 0 and sections[j - 1]["type"] == "transition":
            Section(raw[j], source, lines, ("geometry", "sections", j)).fail(
                "two transitions in a row: put a straight or a curve between them"
            )
    return alignment_from_sections(sections, base, source)


def _section(item, j: int, source: str, lines: dict | None, base: float) -> dict:
    where = ("geometry", "sections", j)
    sec = Section(item, source, lines, where)
    kind = sec.string("type", choices=tuple(SECTION_KEYS))
    sec = Section(item, source, lines, where, SECTION_KEYS[kind])
    out = {"type": kind, "length_m": sec.quantity("length", "m", positive=True)}
    if kind == "transition":
        out["shape"] = sec.string("shape", default="clothoid", choices=SHAPES)
    elif kind == "curve":
        radius = sec.quantity("radius", "m", minimum=MIN_RADIUS_M)
        cant = sec.quantity("cant", "m", default=0.0, minimum=0.0, maximum=MAX_CANT_FRACTION * base)
        direction = sec.string("direction", choices=("left", "right"))
        sign = 1.0 if direction == "left" else -1.0
        out["curvature_1_per_m"] = sign / radius
        out["cant_m"] = sign * cant
    return out
