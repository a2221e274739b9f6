"""Where the bodies of a vehicle stand at the start of a run inside a curve (issue 29).

A wheelset is placed on its local rails, tangent to the track. A body carried by wheelsets (a
bogie frame, a two-axle wagon's car body) or by other bodies (a car body on its bogies) stands,
in a vehicle that has come into the curve from straight track, on the **chord** of what carries
it: its suspension then carries no lateral deflection from the curve's geometry. Placed instead
on the track's centre line under its own centre, it is off that chord by the versine
``a^2 / (2 R)`` of its supports' half distance ``a`` (51 mm for the Hbbins' 10 m wheelbase in
R 245 m): its lateral suspension starts deflected by that much, and the loaded Hbbins' links
and axle-guard stops pushed each wheelset sideways with 364 kN at t = 0, unloaded one wheel of
each to a third of its static load and derailed the wagon in its first metre.

The rule (railexu's): each body, in the order of its distance from the wheelsets in the
suspension's graph (bogie frames before the car body), is given the lateral offset ``dy`` and
yaw ``dpsi`` in its local track frame that fit, by least squares, the line
``v = dy + dpsi u`` through the points where its stiff suspension elements (springs, links,
air springs, stick-slip friction; not dampers, bump stops or torsion springs) meet the bodies
already placed, in the body's local track frame ``(u, v)`` (one point per element). For a body
whose supports are symmetric about its centre (every shipped vehicle) this is the chord: the
suspension's lateral deflection from the curve is zero. On straight track the placement is the
nominal one (nothing changes).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from railexu.vehicle.parts import (
    AirSpring,
    Friction,
    NonlinearSpring,
    SpringDamper,
    SuspensionElement,
    UICLink,
)

#: Offsets [m] and yaws [rad] below this are round-off (a body on straight track): 0.
ROUND_OFF = 1.0e-12
#: ``pose(x) -> (origin, rotation)``: the local track frame at distance ``x`` in the vehicle
#: frame at the start (origin [m], 3 x 3 rotation).
Pose = Callable[[float], tuple[np.ndarray, np.ndarray]]


@dataclass(frozen=True)
class Support:
    """A suspension element's link between two bodies at the vehicle's x ``x_m`` [m]."""

    bodies: tuple[str, str]
    x_m: float


def carries_statically(el: SuspensionElement) -> bool:
    """Whether an element is stiff (a spring, a link, an air spring, stick-slip friction):
    dampers carry no static force, bump stops none within their play, torsion springs and
    anti-roll bars no lateral one."""
    if isinstance(el, SpringDamper):
        return any(k > 0.0 for k in el.stiffness_N_per_m)
    if isinstance(el, Friction):
        return el.stick_stiffness_N_per_m is not None
    return isinstance(el, NonlinearSpring | UICLink | AirSpring)


def rz(angle_rad: float) -> np.ndarray:
    """Rotation about z by ``angle_rad``."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def chord_placements(
    wheelsets: dict[str, tuple[float, float]],
    bodies: dict[str, float],
    supports: Sequence[Support],
    pose: Pose,
) -> dict[str, tuple[float, float]]:
    """``{body: (dy [m], dpsi [rad])}``: each body's lateral offset and yaw in its local track
    frame that put it on the chord of what carries it (module docstring).

    Args:
        wheelsets: ``{name: (x [m], lateral offset on its rails [m])}`` (x: distance along the
            track at the start).
        bodies: ``{name: x of its centre [m]}``, the bodies to place.
        supports: the stiff suspension elements, with the x of each along the track [m].
        pose: the local track frame at a distance.
    """
    placed: dict[str, tuple[float, np.ndarray, np.ndarray]] = {}
    for name, (x, lateral) in wheelsets.items():
        origin, rot = pose(x)
        placed[name] = (x, origin + rot @ np.array([0.0, lateral, 0.0]), rot)
    out: dict[str, tuple[float, float]] = {}
    remaining = dict(bodies)
    while remaining:
        level = {}
        for name, x_c in remaining.items():
            points = [
                _support_point(placed[other], s.x_m)
                for s in supports
                if name in s.bodies
                for other in s.bodies
                if other != name and other in placed
            ]
            if points:
                level[name] = (x_c, points)
        if not level:  # bodies carried by nothing placed: the nominal placement
            out.update({name: (0.0, 0.0) for name in remaining})
            break
        for name, (x_c, points) in level.items():
            origin, rot = pose(x_c)
            local = np.array([rot.T @ (p - origin) for p in points])
            dy, dpsi = _line_fit(local[:, 0], local[:, 1])
            # on straight track the chord is the centre line: exactly the nominal placement
            dy = 0.0 if abs(dy) < ROUND_OFF else dy
            dpsi = 0.0 if abs(dpsi) < ROUND_OFF else dpsi
            out[name] = (dy, dpsi)
            turn = rot @ rz(dpsi)
            placed[name] = (x_c, origin + rot @ np.array([0.0, dy, 0.0]), turn)
            del remaining[name]
    return out


def _support_point(body: tuple[float, np.ndarray, np.ndarray], x_m: float) -> np.ndarray:
    """The point of a placed body ``(x of its centre, centre, rotation)`` on its own axis at
    the vehicle's ``x_m``."""
    x_c, centre, rot = body
    return centre + rot @ np.array([x_m - x_c, 0.0, 0.0])


def _line_fit(u: np.ndarray, v: np.ndarray) -> tuple[float, float]:
    """``(dy, dpsi)`` of ``v = dy + dpsi u`` by least squares; one abscissa only: ``dpsi = 0``
    and ``dy`` the mean."""
    if np.ptp(u) < 1e-9:
        return float(np.mean(v)), 0.0
    a = np.column_stack([np.ones_like(u), u])
    (dy, slope), *_ = np.linalg.lstsq(a, v, rcond=None)
    return float(dy), math.atan(float(slope))
