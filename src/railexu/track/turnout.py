"""A turnout as a track: the route's centre line and which side holds the switch and crossing.

Geometry of a tangential turnout (Network Rail's terms, e.g. the PWI's "Turnout geometry" data
sheet: toe, lead, intersection of the gauge lines, crossing rate 1:N), in the plan of the turnout
seen from the toe with the diverging route leaving to the ``hand`` side:

- the **through route** is straight;
- the **diverging route**'s centre line leaves the through route's tangentially at the switch
  toe on a circle of radius ``R`` (no transition, cant 0: as built), until its heading reaches
  the crossing angle ``theta = atan(1 / N)``, and runs straight (the crossing's leg) beyond;
- the **crossing** lies where the diverging route's outer rail (gauge line of radius
  ``R + g/2``, from ``-g/2`` at the toe) meets the through route's rail on the hand side
  (``+g/2``): the intersection of the gauge lines (IP), on the circle or on the straight leg.

For the UK 56E1-R245-1:9.25 design the circle reaches 1:9.25 at 26.38 m from the toe and the
IP lies 0.107 m further on the straight leg: 26.49 m from the toe along the diverging route,
26.52 m along the through route. The circle of R 245 m and the 1:9.25 crossing fit each other
(a tangential circle through the IP would cross at 1:9.21).

Sides: in a facing move the switch and the crossing that a route runs over lie on the hand side
for the through route (its straight blade against the curved stock rail, then the crossing's
wing rail and nose) and on the other side for the diverging route (its curved blade against the
straight stock rail, the crossing's mirror image); a trailing move meets them in reverse, with
left and right exchanged. Each side's rail profile is in its own axes (field side positive),
so the crossing's slices serve both sides unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

_ROUTES = ("through", "diverging")
_DIRECTIONS = ("facing", "trailing")


@dataclass(frozen=True)
class TurnoutGeometry:
    """The plan geometry of a tangential turnout (module docstring).

    Attributes:
        radius_m: radius of the diverging route's centre line [m].
        crossing_n: the crossing rate ``N`` (angle ``atan(1 / N)``).
        gauge_m: track gauge between the gauge lines [m].
    """

    radius_m: float
    crossing_n: float
    gauge_m: float = 1.435

    @property
    def crossing_angle_rad(self) -> float:
        return math.atan(1.0 / self.crossing_n)

    @property
    def curve_length_m(self) -> float:
        """Length of the diverging centre line's circle, toe to heading ``theta`` [m]."""
        return self.radius_m * self.crossing_angle_rad

    def intersection(self) -> tuple[float, float, float]:
        """The IP: its distance from the toe along the through and along the diverging route's
        centre line [m], and the angle between the two gauge lines there [rad]."""
        r, half, theta = self.radius_m, 0.5 * self.gauge_m, self.crossing_angle_rad
        r_outer = r + half
        y_end = r - r_outer * math.cos(theta)  # the outer gauge line's offset at the curve's end
        if y_end >= half:  # the IP on the circle
            phi = math.acos((r - half) / r_outer)
            return r_outer * math.sin(phi), r * phi, phi
        t = (half - y_end) / math.sin(theta)  # along the straight leg
        return r_outer * math.sin(theta) + t * math.cos(theta), r * theta + t, theta

    def ip_distance_m(self, route: str) -> float:
        """Distance of the IP from the toe along the route's centre line [m]."""
        x_through, s_div, _ = self.intersection()
        return x_through if route == "through" else s_div

    def switch_rail_radius_m(self, route: str) -> float:
        """Radius of the curved one of the blade and the stock rail the route runs over [m]:
        the diverging route's inner rail (the through route's curved stock rail) or its outer
        rail (the diverging route's curved blade)."""
        half = 0.5 * self.gauge_m
        return self.radius_m - half if route == "through" else self.radius_m + half


def turnout_side(route: str, direction: str, hand: str) -> str:
    """The side (``left``/``right`` in the direction of travel) of the switch blade and the
    crossing that the route runs over (module docstring)."""
    other = {"left": "right", "right": "left"}
    facing_side = hand if route == "through" else other[hand]
    return facing_side if direction == "facing" else other[facing_side]


@dataclass(frozen=True)
class RouteLayout:
    """The route as a track: sections and where the turnout's parts lie (track distances).

    Attributes:
        sections: the geometry's sections (``{type, length[, radius, direction, cant]}``, SI).
        toe_m: the switch toe [m].
        ip_m: the intersection of the gauge lines [m].
        crossing_s0_m: the crossing slices' ``s = 0`` [m].
        end_m: the geometry's end [m].
        side: the side of the switch and the crossing run over.
        reversed: trailing: panels' slices run with ``s -> -s``.
        curve_m: ``(start, end)`` of the constant-radius part [m] (None: through route).
    """

    sections: tuple[dict, ...]
    toe_m: float
    ip_m: float
    crossing_s0_m: float
    end_m: float
    side: str
    reversed: bool
    curve_m: tuple[float, float] | None


def route_layout(
    geometry: TurnoutGeometry,
    route: str,
    direction: str,
    hand: str,
    *,
    approach_m: float,
    run_out_m: float,
    s0_from_ip_m: float,
    crossing_range_m: tuple[float, float],
) -> RouteLayout:
    """The route's sections and positions (facing: toe first; trailing: crossing first).

    Args:
        geometry: the turnout's plan geometry.
        route, direction, hand: ``through``/``diverging``, ``facing``/``trailing``,
            ``left``/``right``.
        approach_m: straight track before the first part met (the toe facing; the crossing's
            last slice trailing) [m].
        run_out_m: straight track beyond the last part met [m].
        s0_from_ip_m: the crossing slices' ``s = 0`` beyond the IP [m].
        crossing_range_m: the crossing slices' first and last ``s`` [m].
    """
    if route not in _ROUTES or direction not in _DIRECTIONS or hand not in ("left", "right"):
        raise ValueError(f"route {route!r}, direction {direction!r}, hand {hand!r}")
    s_ip = geometry.ip_distance_m(route)
    c_hi = s_ip + s0_from_ip_m + crossing_range_m[1]  # the crossing's last slice from the toe
    lead = geometry.curve_length_m if route == "diverging" else 0.0
    facing = direction == "facing"
    before, after = (approach_m, run_out_m) if facing else (run_out_m, approach_m)
    # the facing route: straight, circle (diverging), straight to the crossing's end and beyond
    parts = [{"type": "straight", "length": before}]
    if lead > 0.0:
        turn = hand if facing else {"left": "right", "right": "left"}[hand]
        parts.append({"type": "curve", "length": lead, "radius": geometry.radius_m,
                      "cant": 0.0, "direction": turn})  # fmt: skip
    parts.append({"type": "straight", "length": c_hi - lead + after})
    end = before + c_hi + after
    toe, ip = before, before + s_ip
    curve = (before, before + lead) if lead > 0.0 else None
    if not facing:  # the same track run from its other end
        parts = parts[::-1]
        toe, ip = end - toe, end - ip
        curve = None if curve is None else (end - curve[1], end - curve[0])
    if len(parts) == 2:  # through: one straight
        parts = [{"type": "straight", "length": end}]
    crossing_s0 = ip + s0_from_ip_m if facing else ip - s0_from_ip_m
    return RouteLayout(
        sections=tuple(parts), toe_m=toe, ip_m=ip, crossing_s0_m=crossing_s0, end_m=end,
        side=turnout_side(route, direction, hand), reversed=not facing, curve_m=curve,
    )  # fmt: skip


def parse_crossing_rate(text: str) -> float:
    """``N`` of a crossing rate written ``"1:N"`` (or ``"1 in N"``); ValueError otherwise."""
    t = str(text).replace(" in ", ":").replace(" ", "")
    one, _, n = t.partition(":")
    value = float(n) if one == "1" and n else math.nan
    if not (math.isfinite(value) and 3.0 <= value <= 50.0):
        raise ValueError(f"crossing rate {text!r}: expected '1:N' with N from 3 to 50")
    return value


__all__ = [
    "RouteLayout",
    "TurnoutGeometry",
    "parse_crossing_rate",
    "route_layout",
    "turnout_side",
]
