"""Animations of a finished run from its ``state.npz``: the contact view and the plan view.

- **Contact view**: the cross-section of one wheelset (seen from behind, in the direction of
  travel) on its rails, one panel per wheel: the wheel and rail profiles placed by the recorded
  pose and the rail irregularities, the contact points, the width ``2b`` of each contact
  ellipse drawn along the contact plane, the normal and tangential forces on the wheel as
  arrows (scale in kN stated), ``Y``, ``Q`` and ``Y/Q``, and time, distance and speed.
- **Plan view**: the vehicle from above on the track: wheelsets, bogie frames and the car body
  as rectangles, their lateral displacement and yaw exaggerated by a stated factor, wheels in
  flange contact in red. The track centre line is a polyline ``(x, y, heading)`` (straight
  along ``x`` by default), so curved track draws the same way.

Frames are drawn by reusing the artists (their data change, nothing is rebuilt) on an Agg
canvas with blitting: the static background (axes, profiles' frame, labels) is drawn once, each
frame restores it and draws only the moving artists. The frames go to a GIF through Pillow or,
when ``imageio-ffmpeg`` is installed (``pip install railexu[animation]``), to an MP4.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from railexu.errors import InputError
from railexu.report.state_file import CF, SIDES, STATE_FILE, RunState, load_state

VIEWS = ("contact", "plan")
FORMATS = ("gif", "mp4")
#: contact angle above which a point counts as a flange contact [rad] (about 17 deg: treads
#: of S1002-like profiles stay below 6 deg at the gauge corner's start, flanks reach 70 deg)
FLANGE_ANGLE_RAD = 0.30
MM = 1e3


@dataclass(frozen=True)
class AnimationSettings:
    """How to animate.

    Attributes:
        fps: frames per second of the animation.
        start_s, end_s: time window of the run to show [s] (None: from the start, to the end).
        playback: simulated seconds per second of animation (0.25: four times slower).
        wheelset: index of the wheelset for the contact view (0: the leading one).
        exaggeration: factor on lateral displacement and yaw in the plan view.
        force_scale_mm_per_kN: arrow length per force in the contact view [mm/kN]; None: the
            wheelset's largest normal force in 95 % of the output times is at most 45 mm long
            (1, 2 or 5 kN per mm times a power of ten; the rarer impact peaks run off the panel).
        trace: draw the contact positions of the frames shown so far on the profiles.
        dpi: resolution of the frames [dots per inch].
    """

    fps: float = 20.0
    start_s: float | None = None
    end_s: float | None = None
    playback: float = 1.0
    wheelset: int = 0
    exaggeration: float = 50.0
    force_scale_mm_per_kN: float | None = None
    trace: bool = False
    dpi: int = 80

    def __post_init__(self) -> None:
        if not 1.0 <= self.fps <= 60.0:
            raise InputError(f"frame rate {self.fps:g} fps: expected 1 .. 60", key="--fps")
        if not PLAYBACK_RANGE[0] <= self.playback <= PLAYBACK_RANGE[1]:
            raise InputError(f"playback {self.playback:g}: expected {PLAYBACK_RANGE[0]:g} .. "
                             f"{PLAYBACK_RANGE[1]:g} (a thousand times slower .. faster)",
                             key="--playback")  # fmt: skip
        if not 1.0 <= self.exaggeration <= MAX_EXAGGERATION:
            raise InputError(f"exaggeration {self.exaggeration:g}: expected 1 .. "
                             f"{MAX_EXAGGERATION:g} (1 mm shown as 1 m)",
                             key="--exaggeration")  # fmt: skip
        scale = self.force_scale_mm_per_kN
        if scale is not None and not FORCE_SCALE_RANGE[0] <= scale <= FORCE_SCALE_RANGE[1]:
            raise InputError(f"force scale {scale:g} mm/kN: expected {FORCE_SCALE_RANGE[0]:g} .. "
                             f"{FORCE_SCALE_RANGE[1]:g} mm/kN (a 100 kN wheel load 0.1 mm .. "
                             "100 m long)", key="--force-scale")  # fmt: skip
        if not DPI_RANGE[0] <= self.dpi <= DPI_RANGE[1]:
            raise InputError(f"resolution {self.dpi} dpi: expected {DPI_RANGE[0]} .. "
                             f"{DPI_RANGE[1]}", key="--dpi")  # fmt: skip
        for key, value in (("--start", self.start_s), ("--end", self.end_s)):
            if value is not None and not value >= 0.0:
                raise InputError(f"{value:g} s: a run's time starts at 0 s", key=key)


#: Allowed playback factors: a thousand times slower to a thousand times faster.
PLAYBACK_RANGE = (1.0e-3, 1.0e3)
#: Largest exaggeration of the plan view: 1 mm of lateral motion shown as 1 m.
MAX_EXAGGERATION = 1.0e3
#: Allowed arrow scales [mm/kN]: a 100 kN wheel load from 0.1 mm to 100 m long.
FORCE_SCALE_RANGE = (1.0e-3, 1.0e3)
#: Allowed frame resolutions [dpi]: 10 (a thumbnail) to 600 (print quality).
DPI_RANGE = (10, 600)
#: Most frames of one animation (50 min at 20 fps): more is a playback or window mistake.
MAX_FRAMES = 60_000


def frame_indices(time_s: np.ndarray, settings: AnimationSettings) -> np.ndarray:
    """Output rows to show: one per animation frame in the time window (nearest output time;
    a run with fewer outputs than frames shows each output once)."""
    t = np.asarray(time_s, dtype=float)
    if t.size == 0:
        raise InputError("the run has no output rows to animate")
    t0 = t[0] if settings.start_s is None else settings.start_s
    t1 = t[-1] if settings.end_s is None else settings.end_s
    if t1 < t0 or t0 > t[-1] or t1 < t[0]:
        raise InputError(
            f"time window {t0:g} .. {t1:g} s lies outside the run's {t[0]:g} .. {t[-1]:g} s",
            key="--start/--end",
        )
    step = settings.playback / settings.fps
    frames = (min(t1, t[-1]) - max(t0, t[0])) / step
    if frames > MAX_FRAMES:
        raise InputError(f"{frames:.3g} frames at playback {settings.playback:g} and "
                         f"{settings.fps:g} fps; at most {MAX_FRAMES}: a larger --playback or a "
                         "shorter --start/--end window", key="--playback")  # fmt: skip
    wanted = np.arange(max(t0, t[0]), min(t1, t[-1]) + 0.5 * step, step)
    idx = np.clip(np.searchsorted(t, wanted), 0, t.size - 1)
    prev = np.clip(idx - 1, 0, t.size - 1)
    idx = np.where(np.abs(t[prev] - wanted) < np.abs(t[idx] - wanted), prev, idx)
    return np.unique(idx) if t.size < wanted.size else idx


# ----------------------------------------------------------------------------------------------
# contact view
# ----------------------------------------------------------------------------------------------


class ContactView:
    """The cross-section of one wheelset on its rails (see the module text)."""

    def __init__(self, state: RunState, settings: AnimationSettings) -> None:
        if not 0 <= settings.wheelset < state.n_wheelsets:
            raise InputError(
                f"wheelset {settings.wheelset + 1}: the run has {state.n_wheelsets} "
                f"({', '.join(state.wheelset_names)})",
                key="--wheelset",
            )
        self.state = state
        self.settings = settings
        self.ws = settings.wheelset
        self.fig = Figure(figsize=(10, 5.0), dpi=settings.dpi)
        self.axes = self.fig.subplots(1, 2)
        self.fig.subplots_adjust(left=0.07, right=0.98, top=0.78, bottom=0.11, wspace=0.15)
        peak = state.contacts[:, self.ws, :, :, CF["N_N"]].max(axis=(1, 2))
        kN_per_mm = (
            1.0 / settings.force_scale_mm_per_kN
            if settings.force_scale_mm_per_kN
            else nice_kN_per_mm(float(np.percentile(peak, 95.0)))
        )
        self.mm_per_N = 1.0 / kN_per_mm / 1e3
        self.dynamic: list = []
        self.traces: list[list] = [[], []]
        self.prof = state.profiles[int(state.profile_index[self.ws])]
        # rails displaced by irregularities or an elastic track: their offsets as text too
        self.rails_move = bool(np.any(state.rail_offsets_m[:, self.ws] != 0.0))
        for k, ax in enumerate(self.axes):
            # seen from behind: the left rail (y > 0) on the left, so the axis shows -y
            centre = (1.0 if k == 0 else -1.0) * (self.prof.tape_circle_lateral_m - 0.015)
            ax.set_xlim(-(centre + 0.080) * MM, -(centre - 0.080) * MM)
            ax.set_ylim(-60.0, 60.0)
            ax.set_aspect("equal", adjustable="box")
            ax.set_xlabel("lateral position, seen in the direction of travel [mm]")
            ax.grid(True, alpha=0.3)
            ax.set_title(f"{SIDES[k]} wheel", fontsize=10, loc="right")
        self.axes[0].set_ylabel("height above top of rail [mm]")
        self._make_artists()
        name = state.wheelset_names[self.ws]
        source = (
            "points and forces as recorded"
            if state.contact_source in ("kernel", "recorded")
            else "points from the recorded pose, forces: recorded wheel totals Y, Q shared"
        )
        self.fig.suptitle(
            f"{state.meta.get('vehicle', '')}: wheelset {name} (ws{self.ws + 1}), seen from "
            f"behind. Force on the wheel {kN_per_mm:g} kN per mm: "
            f"blue normal, orange tangential;\ngreen: contact width 2b; {source}",
            fontsize=9,
        )
        self.overlay: list[Overlay] = []

    def _make_artists(self) -> None:
        for ax in self.axes:
            rail = Polygon(np.zeros((3, 2)), closed=True, fc="0.75", ec="0.3", lw=1.0)
            wheel = Polygon(np.zeros((3, 2)), closed=True, fc="#c8d8ea", ec="#1f4e79", lw=1.2)
            ax.add_patch(rail)
            ax.add_patch(wheel)
            (trace,) = ax.plot([], [], ".", color="#d62728", ms=2, alpha=0.5)
            (widths,) = ax.plot([], [], "-", color="#2ca02c", lw=5, solid_capstyle="butt")
            (normal,) = ax.plot([], [], "-", color="#1f77b4", lw=2)
            (tangential,) = ax.plot([], [], "-", color="#ff7f0e", lw=2)
            (points,) = ax.plot([], [], "o", ms=5, mfc="none", mec="k", mew=1.2)
            self.dynamic.append((rail, wheel, trace, widths, normal, tangential, points))

    @property
    def artists(self) -> list:
        return [a for group in self.dynamic for a in group]

    def update(self, f: int) -> None:
        st = self.state
        ws = self.ws
        texts = []
        for k, side in enumerate(SIDES):
            rail, wheel, trace, widths, normal, tangential, points = self.dynamic[k]
            ry, rz = st.rail_outline(f, ws, side)
            rail.set_xy(np.column_stack([-ry * MM, rz * MM]))
            wy, wz = st.wheel_outline(f, ws, side)
            top = st.wheelset_pose[f, ws, 1] - self.prof.nominal_radius_m + 0.080
            wheel.set_xy(
                np.column_stack([-np.r_[wy, wy[-1], wy[0]] * MM, np.r_[wz, top, top] * MM])
            )
            c = st.contacts[f, ws, k]
            on = c[:, CF["active"]] > 0
            y, z = c[on, CF["y_m"]] * MM, c[on, CF["z_m"]] * MM
            points.set_data(-y, z)
            gamma = c[on, CF["angle_rad"]]
            m = 1.0 if k == 0 else -1.0
            ty, tz = np.cos(gamma), m * np.sin(gamma)  # t_y = (0, cos g, m sin g)
            half = c[on, CF["b_m"]] * MM
            widths.set_data(*_segments(-y, z, -ty * half, tz * half, centred=True))
            n_len = c[on, CF["N_N"]] * self.mm_per_N
            ny, nz = -m * np.sin(gamma), np.cos(gamma)  # n = (0, -m sin g, cos g)
            normal.set_data(*_segments(-y, z, -ny * n_len, nz * n_len))
            t_len = np.nan_to_num(c[on, CF["Fy_N"]]) * self.mm_per_N
            tangential.set_data(*_segments(-y, z, -ty * t_len, tz * t_len))
            if self.settings.trace:
                self.traces[k].extend(zip(-y, z, strict=True))
                if self.traces[k]:
                    trace.set_data(*np.array(self.traces[k]).T)
            Y, Q = st.wheel_forces_N[f, ws, k]
            flange = bool(np.any(gamma > FLANGE_ANGLE_RAD))
            ratio = f"{Y / Q:+.2f}" if Q > 1.0 else "  -"
            lines = f"Y {Y / 1e3:+6.1f} kN\nQ {Q / 1e3:6.1f} kN\nY/Q {ratio}"
            if self.rails_move:
                dy, dz = st.rail_offsets_m[f, ws, 2 * k : 2 * k + 2] * MM
                lines += f"\nrail {dy:+5.2f} {dz:+5.2f} mm"
            x0 = self.axes[k].get_position().x0 + 0.01
            texts.append(Overlay(x0, 0.76, lines + ("\nFLANGE" if flange else ""), flange))
        lat, _, _, yaw = st.wheelset_pose[f, ws]
        header = (
            f"t {st.time_s[f]:6.2f} s   x {st.distance_m[f]:7.1f} m   v {st.speed_m_per_s[f]:5.1f}"
            f" m/s   lateral {lat * MM:+6.2f} mm   yaw {yaw * MM:+5.2f} mrad"
        )
        self.overlay = [Overlay(0.5, 0.86, header, False, centred=True), *texts]


@dataclass(frozen=True)
class Overlay:
    """A text drawn onto a frame with Pillow (much faster than matplotlib's text), at a
    position in figure fractions (``x``, ``y`` of the top left corner, or top centre)."""

    x: float
    y: float
    text: str
    alert: bool = False
    centred: bool = False


def nice_kN_per_mm(max_force_N: float, length_mm: float = 45.0) -> float:
    """A round force scale [kN/mm] (1, 2 or 5 times a power of ten) that draws ``max_force_N``
    at most ``length_mm`` long."""
    need = max(max_force_N, 1e3) / 1e3 / length_mm
    power = 10.0 ** math.floor(math.log10(need))
    return next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= need * (1 - 1e-12))


def _segments(x, y, dx, dy, centred: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Line segments from (x, y) along (dx, dy) as one polyline with NaN breaks."""
    x, y, dx, dy = (np.asarray(a, dtype=float) for a in (x, y, dx, dy))
    x0, y0 = (x - dx, y - dy) if centred else (x, y)
    nan = np.full_like(x, np.nan)
    return (np.column_stack([x0, x + dx, nan]).ravel(), np.column_stack([y0, y + dy, nan]).ravel())


# ----------------------------------------------------------------------------------------------
# plan view
# ----------------------------------------------------------------------------------------------


class TrackCentreLine:
    """The track centre line as a polyline ``x, y`` [m] with ``heading`` [rad], parametrised by
    the distance along it (straight along ``x`` when built with :meth:`straight`)."""

    def __init__(self, x_m, y_m, heading_rad) -> None:
        self.x = np.asarray(x_m, dtype=float)
        self.y = np.asarray(y_m, dtype=float)
        self.heading = np.unwrap(np.asarray(heading_rad, dtype=float))
        if self.x.size < 2 or not (self.x.shape == self.y.shape == self.heading.shape):
            raise ValueError("the track centre line needs >= 2 points of x, y and heading")
        seg = np.hypot(np.diff(self.x), np.diff(self.y))
        self.s = np.r_[0.0, np.cumsum(seg)]

    @classmethod
    def straight(cls, start_m: float, end_m: float) -> TrackCentreLine:
        return cls([start_m, end_m], [0.0, 0.0], [0.0, 0.0])

    def at(self, s_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x, y, heading`` at distances ``s_m`` along the line (extended straight beyond)."""
        s = np.asarray(s_m, dtype=float)
        x = np.interp(s, self.s, self.x)
        y = np.interp(s, self.s, self.y)
        h = np.interp(s, self.s, self.heading)
        beyond = np.clip(s - self.s[-1], 0.0, None) + np.clip(s - self.s[0], None, 0.0)
        hb = np.where(s > self.s[-1], self.heading[-1], self.heading[0])
        return x + beyond * np.cos(hb), y + beyond * np.sin(hb), h


def _rectangle(cx, cy, heading, length, width) -> np.ndarray:
    c, s = math.cos(heading), math.sin(heading)
    corners = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]]) * [0.5 * length, 0.5 * width]
    return np.column_stack(
        [cx + c * corners[:, 0] - s * corners[:, 1], cy + s * corners[:, 0] + c * corners[:, 1]]
    )


class PlanView:
    """The vehicle from above on the track (see the module text)."""

    def __init__(
        self,
        state: RunState,
        settings: AnimationSettings,
        centre_line: TrackCentreLine | None = None,
    ) -> None:
        self.state = state
        self.settings = settings
        self.k = settings.exaggeration
        if centre_line is None and state.track_x_m is not None:
            centre_line = TrackCentreLine(state.track_x_m, state.track_y_m,
                                          state.track_heading_rad)  # fmt: skip
        self.line = centre_line or TrackCentreLine.straight(-1e4, 1e5)
        # the centre line's distance 0 lies at track position s_line0; the vehicle's origin at
        # the start at track position s0 (both 0 unless the state file says otherwise)
        self.s0 = float(state.meta.get("track_s0_m", 0.0)) - float(
            state.meta.get("track_centre_s0_m", 0.0) if centre_line is None else 0.0
        )
        xs = np.r_[state.wheelset_x_m, state.body_x_m]
        self.half_span = 0.5 * float(np.ptp(xs)) + 3.0
        self.x_mid = 0.5 * (float(np.max(xs)) + float(np.min(xs)))
        self.fig = Figure(figsize=(10, 3.0), dpi=settings.dpi)
        self.ax = self.fig.subplots()
        self.fig.subplots_adjust(left=0.07, right=0.99, top=0.80, bottom=0.16)
        self.ax.set_xlim(-self.half_span, self.half_span)
        self.ax.set_ylim(-1.6, 1.6)
        self.ax.set_aspect("equal", adjustable="box")
        self.ax.set_xlabel("along the track, from the vehicle's centre [m]")
        self.ax.set_ylabel("lateral [m]")
        self.fig.suptitle(
            f"{state.meta.get('vehicle', '')} from above: lateral displacement and yaw "
            f"exaggerated x{self.k:g}; wheels in flange contact red",
            fontsize=10,
        )
        self.gauge = 1.5
        (self.rails,) = self.ax.plot([], [], "-", color="0.35", lw=1.5)
        (self.sleepers,) = self.ax.plot([], [], "-", color="0.8", lw=3, zorder=0)
        self.bodies = []
        for _ in state.body_names:
            p = Polygon(np.zeros((4, 2)), closed=True, fc="none", ec="#1f4e79", lw=1.5)
            self.ax.add_patch(p)
            self.bodies.append(p)
        self.axles, self.wheels = [], []
        for _ in state.wheelset_names:
            (axle,) = self.ax.plot([], [], "-", color="k", lw=2)
            self.axles.append(axle)
            pair = []
            for _side in SIDES:
                w = Polygon(np.zeros((4, 2)), closed=True, fc="0.3", ec="k", lw=0.5)
                self.ax.add_patch(w)
                pair.append(w)
            self.wheels.append(pair)
        self.overlay: list[Overlay] = []

    @property
    def artists(self) -> list:
        return [self.sleepers, self.rails, *self.bodies, *self.axles,
                *[w for pair in self.wheels for w in pair]]  # fmt: skip

    def _to_view(self, s_ref: float, x, y):
        """Global plane -> the view frame (origin on the centre line at ``s_ref``, axis along
        its heading there)."""
        x0, y0, h0 = self.line.at(s_ref)
        c, s = math.cos(float(h0)), math.sin(float(h0))
        dx, dy = np.asarray(x) - x0, np.asarray(y) - y0
        return c * dx + s * dy, -s * dx + c * dy

    def _place(self, s_ref: float, s_along, lateral, yaw, length, width):
        """A rectangle of a body at distance ``s_along`` on the track, displaced and turned
        (both exaggerated) from the centre line, in view coordinates."""
        x, y, h = self.line.at(s_along)
        nx, ny = -math.sin(float(h)), math.cos(float(h))
        cx, cy = x + self.k * lateral * nx, y + self.k * lateral * ny
        rect = _rectangle(float(cx), float(cy), float(h) + self.k * yaw, length, width)
        vx, vy = self._to_view(s_ref, rect[:, 0], rect[:, 1])
        return np.column_stack([vx, vy])

    def update(self, f: int) -> None:
        st = self.state
        s_ref = self.s0 + float(st.distance_m[f]) + self.x_mid
        s = s_ref + np.linspace(-self.half_span - 2, self.half_span + 2, 60)
        x, y, h = self.line.at(s)
        rails_x, rails_y = [], []
        for m in (1.0, -1.0):
            vx, vy = self._to_view(s_ref, x - m * 0.5 * self.gauge * np.sin(h),
                                   y + m * 0.5 * self.gauge * np.cos(h))  # fmt: skip
            rails_x += [*vx, np.nan]
            rails_y += [*vy, np.nan]
        self.rails.set_data(rails_x, rails_y)
        first = math.ceil((s[0]) / 0.6) * 0.6
        ss = np.arange(first, s[-1], 0.6)
        sx, sy, sh = self.line.at(ss)
        ends = []
        for m in (1.0, -1.0):
            ends.append(self._to_view(s_ref, sx - m * 1.3 * np.sin(sh), sy + m * 1.3 * np.cos(sh)))
        nan = np.full(ss.size, np.nan)
        self.sleepers.set_data(
            np.column_stack([ends[0][0], ends[1][0], nan]).ravel(),
            np.column_stack([ends[0][1], ends[1][1], nan]).ravel(),
        )
        for j, patch in enumerate(self.bodies):
            length, width = st.body_size_m[j]
            s_body = self.s0 + float(st.distance_m[f]) + st.body_x_m[j]
            lat, yaw = st.body_lateral_m[f, j], st.body_yaw_rad[f, j]
            patch.set_xy(self._place(s_ref, s_body, lat, yaw, length, width))
        for i in range(st.n_wheelsets):
            lat, _, _, yaw = st.wheelset_pose[f, i]
            s_ws = self.s0 + float(st.distance_m[f]) + st.wheelset_x_m[i]
            axle = self._place(s_ref, s_ws, lat, yaw, 0.05, 1.5)
            self.axles[i].set_data(
                [0.5 * (axle[0, 0] + axle[3, 0]), 0.5 * (axle[1, 0] + axle[2, 0])],
                [0.5 * (axle[0, 1] + axle[1, 1]), 0.5 * (axle[2, 1] + axle[3, 1])],
            )
            body = self._place(s_ref, s_ws, lat, yaw, 1.25, 1.5)
            for k, patch in enumerate(self.wheels[i]):
                corner = body[0] if k == 0 else body[3]
                other = body[1] if k == 0 else body[2]
                mid = 0.5 * (corner + other)
                inward = (body[3] - body[0]) if k == 0 else (body[0] - body[3])
                inward = inward / np.linalg.norm(inward) * 0.14
                along = (corner - other) * 0.5
                patch.set_xy(np.array([mid + along, mid - along, mid - along + inward,
                                       mid + along + inward]))  # fmt: skip
                c = st.contacts[f, i, k]
                flange = np.any(
                    (c[:, CF["active"]] > 0) & (c[:, CF["angle_rad"]] > FLANGE_ANGLE_RAD)
                )
                patch.set_facecolor("#d62728" if flange else "0.3")
        header = (
            f"t {st.time_s[f]:6.2f} s   x {st.distance_m[f]:7.1f} m   "
            f"v {st.speed_m_per_s[f]:5.1f} m/s"
        )
        self.overlay = [Overlay(0.5, 0.89, header, False, centred=True)]


# ----------------------------------------------------------------------------------------------
# rendering and writing
# ----------------------------------------------------------------------------------------------


class _Blitter:
    """Draws a view's frames on an Agg canvas, redrawing only its moving artists."""

    def __init__(self, view) -> None:
        self.view = view
        self.canvas = FigureCanvasAgg(view.fig)
        for a in view.artists:
            a.set_animated(True)
        self.canvas.draw()
        self.background = self.canvas.copy_from_bbox(view.fig.bbox)
        self._font = None

    def frame(self, f: int) -> np.ndarray:
        self.view.update(f)
        self.canvas.restore_region(self.background)
        renderer = self.canvas.get_renderer()
        for a in self.view.artists:
            a.draw(renderer)
        rgb = np.asarray(self.canvas.buffer_rgba())[..., :3].copy()
        return self._texts(rgb)

    def _texts(self, rgb: np.ndarray) -> np.ndarray:
        from PIL import Image, ImageDraw

        if not self.view.overlay:
            return rgb
        img = Image.fromarray(rgb)
        draw = ImageDraw.Draw(img)
        h, w = rgb.shape[:2]
        for o in self.view.overlay:
            colour = (214, 39, 40) if o.alert else (0, 0, 0)
            anchor = "ma" if o.centred else "la"
            draw.multiline_text((o.x * w, (1.0 - o.y) * h), o.text, fill=colour, font=self.font,
                                anchor=anchor, spacing=2)  # fmt: skip
        return np.asarray(img)

    @property
    def font(self):
        if self._font is None:
            from matplotlib import font_manager
            from PIL import ImageFont

            path = font_manager.findfont(font_manager.FontProperties(family="DejaVu Sans Mono"))
            self._font = ImageFont.truetype(path, size=round(11 * self.view.fig.dpi / 72))
        return self._font


def progress_line(label: str, stream=sys.stderr, unit: str = "frame") -> Callable[[int, int], None]:
    """A progress callback ``(done, total)`` writing one updating line."""
    t0 = time.perf_counter()
    state = {"last": -1.0}

    def report(done: int, total: int) -> None:
        now = time.perf_counter()
        if now - state["last"] < 0.3 and done < total:
            return
        state["last"] = now
        end = "\n" if done >= total else ""
        stream.write(f"\r  {label}: {unit} {done:4d} / {total}   {now - t0:5.1f} s{end}")
        stream.flush()

    return report


def render(view, frames: np.ndarray, path: str | Path, fps: float, progress=None) -> Path:
    """Draw ``frames`` (output rows) of ``view`` and write them to ``path`` (``.gif`` through
    Pillow, ``.mp4`` through imageio-ffmpeg)."""
    from railexu.report.folder import atomic_path

    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in FORMATS:
        raise InputError(f"{path}: animation format {fmt!r}, expected one of {FORMATS}")
    blit = _Blitter(view)
    total = len(frames)

    def images():
        for n, f in enumerate(frames):
            yield blit.frame(int(f))
            if progress is not None:
                progress(n + 1, total)

    with atomic_path(path) as tmp:
        if fmt == "gif":
            _write_gif(images(), tmp, fps)
        else:
            _write_mp4(images(), tmp, fps, blit.canvas.get_width_height())
    return path


def _write_gif(images, path: Path, fps: float) -> None:
    from PIL import Image

    # one palette for all frames (from the first): fast, and steady colours between frames
    first = None
    frames = []
    for rgb in images:
        img = Image.fromarray(rgb)
        if first is None:
            first = img.quantize(colors=64, method=Image.Quantize.MEDIANCUT)
            frames.append(first)
        else:
            frames.append(img.quantize(palette=first, dither=Image.Dither.NONE))
    frames[0].save(
        path, format="GIF", save_all=True, append_images=frames[1:],
        duration=max(20, round(1000.0 / fps)), loop=0, optimize=False,
    )  # fmt: skip


def mp4_available() -> bool:
    """True when imageio-ffmpeg (``pip install railexu[animation]``) is installed."""
    try:
        import imageio_ffmpeg  # noqa: F401
    except ImportError:
        return False
    return True


def _write_mp4(images, path: Path, fps: float, size: tuple[int, int]) -> None:
    if not mp4_available():
        raise InputError(
            "MP4 needs imageio-ffmpeg: pip install 'railexu[animation]' (or write a GIF)",
            key="--format",
        )
    import imageio_ffmpeg

    writer = imageio_ffmpeg.write_frames(
        str(path), size, fps=fps, codec="libx264", pix_fmt_out="yuv420p", macro_block_size=8,
        output_params=["-f", "mp4"],
    )  # fmt: skip
    writer.send(None)
    for rgb in images:
        writer.send(np.ascontiguousarray(rgb))
    writer.close()


def animate_run(
    folder: str | Path,
    views: tuple[str, ...] = VIEWS,
    fmt: str = "gif",
    settings: AnimationSettings | None = None,
    out_dir: str | Path | None = None,
    progress: bool = False,
    centre_line: TrackCentreLine | None = None,
) -> dict[str, Path]:
    """Animate a finished run from its folder's ``state.npz``; returns ``view -> file``.

    The files (``contact.gif``, ``plan.gif``, or ``.mp4``) go into ``out_dir`` (default: the
    run's folder, where they join the folder's list of written files so that the next run into
    the same folder removes them with the other outputs of this one).

    Raises:
        InputError: no state file, an unknown view or format, a bad time window.
    """
    settings = settings or AnimationSettings()
    folder = Path(folder)
    if fmt not in FORMATS:
        from railexu.errors import did_you_mean

        raise InputError(f"format {fmt!r}.{did_you_mean(fmt, FORMATS)}", key="--format")
    for view in views:
        if view not in VIEWS:
            from railexu.errors import did_you_mean

            raise InputError(f"view {view!r}.{did_you_mean(view, VIEWS)}", key="--view")
    from railexu.report.folder_check import check_output_folder

    check_output_folder(folder, "run", (STATE_FILE,))  # refuses an incomplete or damaged folder
    state = load_state(folder / STATE_FILE)
    frames = frame_indices(state.time_s, settings)
    out = Path(out_dir) if out_dir is not None else folder
    out.mkdir(parents=True, exist_ok=True)
    written: dict[str, Path] = {}
    for view in views:
        v = (
            ContactView(state, settings)
            if view == "contact"
            else PlanView(state, settings, centre_line)
        )
        report = progress_line(f"{view} view") if progress else None
        written[view] = render(v, frames, out / f"{view}.{fmt}", settings.fps, report)
    if out.resolve() == folder.resolve():
        from railexu.report.folder import add_to_manifest

        add_to_manifest(folder, [p.name for p in written.values()])
    return written


def save_frame_png(view, frame: int, path: str | Path) -> Path:
    """One frame of a view as a PNG (for documentation), as it appears in the animation."""
    from PIL import Image

    Image.fromarray(_Blitter(view).frame(int(frame))).save(path)
    return Path(path)
