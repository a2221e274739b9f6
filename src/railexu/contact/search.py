"""General contact search on parametric surfaces: the seed's method, slow and independent.

The wheel surface is parametrised by its profile coordinate ``s_w`` and the angle ``theta_w``
around the axle, the rail surface by its profile coordinate ``y_r`` and the distance ``x_r``
along the track (the seed's ``s, u`` of eq. 1). A contact point satisfies four nonlinear
equations (Shabana, Zaazaa & Sugiyama, *Railroad Vehicle Dynamics*, 2008, ch. 5):

    t1_r . (P_w - P_r) = 0,   t2_r . (P_w - P_r) = 0,   t1_r . n_w = 0,   t2_r . n_w = 0,

where ``t1_r, t2_r`` are the rail's surface tangents and ``n_w`` the wheel normal: the distance
vector and the wheel normal are both along the rail normal. They are solved by
``scipy.optimize.root`` from seeds found by a brute-force scan of the wheel surface, and every
solution that is a local minimum of the distance is kept (tread and flange).

This module uses the profiles' splines directly, not the kernel's tables, and no closed form of
the contact locus: it is the reference against which the compiled kernel
(:mod:`railexu.contact.kernel`) and the contact tables are checked. It takes milliseconds per
wheel; never call it from the dynamics.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from railexu.contact.placement import WheelRailPair


@dataclass(frozen=True)
class SurfaceContact:
    """A contact point from the general search (left-type frame of its pair, SI units)."""

    wheel_s_m: float
    wheel_theta_rad: float
    rail_x_m: float
    rail_y_m: float
    wheel_point_m: tuple[float, float, float]
    rail_point_m: tuple[float, float, float]
    normal_distance_m: float  # signed distance along the rail normal, negative = overlap
    contact_angle_rad: float


class _Surfaces:
    """Wheel and rail surfaces of one pair in the left-type track frame."""

    def __init__(self, pair: WheelRailPair, cy: float, cz: float, phi: float, psi: float):
        self.pair = pair
        self.rail = pair.rail_canted
        self.y_shift, self.z_shift = pair.rail_origin_track_m
        self.r0 = pair.nominal_radius_m
        self.tape = pair.tape_circle_lateral_m
        self.c = np.array([0.0, cy, cz])
        cf, sf, cp, sp = np.cos(phi), np.sin(phi), np.cos(psi), np.sin(psi)
        rx = np.array([[1, 0, 0], [0, cf, -sf], [0, sf, cf]])
        rz = np.array([[cp, -sp, 0], [sp, cp, 0], [0, 0, 1]])
        self.R = rx @ rz

    def wheel(self, s: float, theta: float):
        w = self.pair.wheel
        r = self.r0 + float(w.height(s))
        dr = float(w.slope(s))
        local = np.array([r * np.sin(theta), self.tape + s, -r * np.cos(theta)])
        n_local = np.array([np.sin(theta), -dr, -np.cos(theta)]) / np.sqrt(1.0 + dr * dr)
        return self.c + self.R @ local, self.R @ n_local

    def rail_point(self, x: float, y: float):
        yo = y - self.y_shift
        z = float(self.rail.height(yo)) + self.z_shift
        dz = float(self.rail.slope(yo))
        t1 = np.array([1.0, 0.0, 0.0])
        t2 = np.array([0.0, 1.0, dz]) / np.sqrt(1.0 + dz * dz)
        return np.array([x, y, z]), t1, t2, dz

    def in_rail(self, y: float) -> bool:
        yo = y - self.y_shift
        return self.rail.y_min <= yo <= self.rail.y_max

    def in_wheel(self, s: float) -> bool:
        return self.pair.wheel.y_min <= s <= self.pair.wheel.y_max


def _residual(u: np.ndarray, surf: _Surfaces) -> np.ndarray:
    s, theta, x, y = u
    if not (surf.in_wheel(s) and surf.in_rail(y)):
        return np.full(4, 1.0)
    pw, nw = surf.wheel(s, theta)
    pr, t1, t2, _ = surf.rail_point(x, y)
    d = pw - pr
    return np.array([t1 @ d, t2 @ d, t1 @ nw, t2 @ nw])


def general_contact_search(
    pair: WheelRailPair,
    lateral_m: float,
    vertical_m: float,
    roll_rad: float,
    yaw_rad: float,
    *,
    seed_step_m: float = 5.0e-4,
    max_distance_m: float = 2.0e-3,
) -> list[SurfaceContact]:
    """All contact points of a left-type wheel on its rail by the general four-parameter method.

    Args:
        pair: the placed wheel and rail (left-type frame; mirror the pose for a right wheel).
        lateral_m, vertical_m: wheelset centre relative to the track [m].
        roll_rad, yaw_rad: wheelset roll and yaw [rad].
        seed_step_m: step of the brute-force seed scan along the wheel profile [m].
        max_distance_m: keep solutions whose normal distance is below this (overlap negative).

    Returns:
        the contact points sorted by wheel coordinate ``s``.
    """
    surf = _Surfaces(pair, lateral_m, vertical_m, roll_rad, yaw_rad)
    wheel = pair.wheel
    s_grid = np.arange(wheel.y_min + seed_step_m, wheel.y_max - seed_step_m, seed_step_m)
    # Seeds: for each wheel circle, the angle whose point lies lowest above the rail (brute force
    # over a fan of angles), vectorised over the whole grid.
    thetas = np.linspace(-0.2, 0.2, 161)
    S, TH = np.meshgrid(s_grid, thetas, indexing="ij")
    r = surf.r0 + wheel.height(S)
    local = np.stack([r * np.sin(TH), surf.tape + S, -r * np.cos(TH)], axis=-1)
    pts = surf.c + local @ surf.R.T
    y_own = pts[..., 1] - surf.y_shift
    inside = (y_own >= surf.rail.y_min) & (y_own <= surf.rail.y_max)
    gaps = pts[..., 2] - (surf.rail.height(y_own) + surf.z_shift)
    gaps = np.where(inside, gaps, np.inf)
    best = np.argmin(gaps, axis=1)
    dist = gaps[np.arange(s_grid.size), best]
    best_theta = thetas[best]
    seeds = [
        i
        for i in range(1, s_grid.size - 1)
        if np.isfinite(dist[i]) and dist[i] <= dist[i - 1] and dist[i] < dist[i + 1]
    ]
    found: list[SurfaceContact] = []
    for i in seeds:
        s0, th0 = s_grid[i], best_theta[i]
        pw, _ = surf.wheel(s0, th0)
        sol = root(_residual, np.array([s0, th0, pw[0], pw[1]]), args=(surf,), method="hybr",
                   options={"xtol": 1e-13})  # fmt: skip
        if not sol.success or np.max(np.abs(_residual(sol.x, surf))) > 1e-10:
            continue
        s, theta, x, y = sol.x
        pw, nw = surf.wheel(s, theta)
        pr, _, _, dz = surf.rail_point(x, y)
        n_r = np.array([0.0, -dz, 1.0]) / np.sqrt(1.0 + dz * dz)
        distance = float(n_r @ (pw - pr))
        if distance > max_distance_m:
            continue
        if any(abs(c.wheel_s_m - s) < 1e-7 for c in found):
            continue
        found.append(
            SurfaceContact(
                wheel_s_m=float(s),
                wheel_theta_rad=float(theta),
                rail_x_m=float(x),
                rail_y_m=float(y),
                wheel_point_m=tuple(float(v) for v in pw),
                rail_point_m=tuple(float(v) for v in pr),
                normal_distance_m=distance,
                contact_angle_rad=float(np.arctan(dz)),
            )
        )
    return sorted(found, key=lambda c: c.wheel_s_m)
