"""Generalized forces of the track's vertical alignment on the vehicle's bodies.

The bodies' coordinates follow the track (``docs/curving.md``): their first coordinate is the
distance along the track, their third the height above the top of rail *normal to the local
track*, and their angles are relative to the local track direction. A gradient and a vertical
curve therefore appear as the inertial and gravity forces of a frame that pitches with the track
(``docs/curving.md``, "Vertical alignment"), evaluated at every body's own distance ``s``:

- gravity turned by the pitch ``theta(s) = atan(dz/ds)``: along the track ``-m g sin(theta)``,
  normal to it ``-m g cos(theta)`` (Exudyn already applies ``-m g``: the difference
  ``-m g (cos(theta) - 1)`` is added);
- the centripetal acceleration of a path of vertical curvature ``kappa_v = d theta/ds``:
  ``-m V^2 kappa_v`` normal to the track (a sag, ``kappa_v > 0``, presses the wheels down; a
  crest unloads them);
- the pitch acceleration of the local track direction: a body that follows the track turns
  with ``d^2 theta / dt^2 = V^2 d kappa_v/ds``, so about the lateral axis the torque
  ``+I_y V^2 d kappa_v/ds`` acts in the track-relative coordinates (the wheelsets' spin too).

On canted track (curved mode) the normal and the lateral axis are those of the vehicle frame
rolled by its cant roll ``phi``: the normal force splits into ``sin(phi)`` (lateral) and
``cos(phi)`` (vertical) parts. Neglected: terms of order height/R_v (the lever of a body's centre
above the rail in the vertical curve, < 0.4 % at R_v >= 250 m and 1 m height), ``dV/dt kappa_v``
in the pitch torque, the chord effect a^2/(2 R_v) of a vehicle's ends on a vertical curve (the
bodies' coordinates are each relative to the track under them; it changes no load of a
vehicle on two bogies or two wheelsets), and the dependence of these forces on the coordinates
in the Jacobian (a stiffness of m g / R_v, under 1e-4 of the suspension's).
"""

from __future__ import annotations

import math

import numpy as np

from railexu.track.vertical import VerticalAlignment


class VerticalForces:
    """The vertical alignment's generalized forces on the bodies at given node slots.

    Args:
        vertical: the track's vertical profile.
        slots: node slot (6 coordinates each) of every body in the contact object's coordinates.
        reference_s_m: the first reference coordinate of each body (distance along the track of
            its nominal position) [m].
        mass_kg: masses [kg].
        pitch_inertia_kg_m2: inertia about the lateral axis (a wheelset's spin inertia) [kg m^2].
        gravity_m_per_s2: gravity [m/s^2].
        frame_roll: callable returning the vehicle frame's cant roll [rad] now (None: level
            frame, straight track).
    """

    def __init__(
        self,
        vertical: VerticalAlignment,
        slots: np.ndarray,
        reference_s_m: np.ndarray,
        reference_angles: np.ndarray,
        mass_kg: np.ndarray,
        pitch_inertia_kg_m2: np.ndarray,
        gravity_m_per_s2: float,
        frame_roll=None,
    ) -> None:
        self.v = vertical
        self.o = 6 * np.asarray(slots, dtype=np.int64)
        self.s_ref = np.asarray(reference_s_m, dtype=float)
        self.a_ref = np.asarray(reference_angles, dtype=float).reshape(-1, 3)
        self.m = np.asarray(mass_kg, dtype=float)
        self.i_y = np.asarray(pitch_inertia_kg_m2, dtype=float)
        self.g = float(gravity_m_per_s2)
        self.frame_roll = frame_roll

    def add(self, q: np.ndarray, qt: np.ndarray, out: np.ndarray) -> None:
        """Add the forces at the state ``(q, qt)`` (the object's coordinates) to ``out``."""
        o = self.o
        s = self.s_ref + q[o]
        speed = qt[o]
        v = self.v
        grad = np.interp(s, v.grid_m, v.gradient)
        kappa = np.interp(s, v.grid_m, v.curvature_1_per_m, left=0.0, right=0.0)
        dkappa = np.interp(s, v.grid_m, v.curvature_slope, left=0.0, right=0.0)
        cos_t = 1.0 / np.sqrt(1.0 + grad * grad)
        sin_t = grad * cos_t
        v2 = speed * speed
        normal = -self.m * (self.g * (cos_t - 1.0) + v2 * kappa)
        torque = self.i_y * v2 * dkappa
        phi = 0.0 if self.frame_roll is None else self.frame_roll()
        cp, sp = math.cos(phi), math.sin(phi)
        out[o] -= self.m * self.g * sin_t
        out[o + 1] += sp * normal
        out[o + 2] += cp * normal
        # torque (0, T cos(phi), -T sin(phi)) in frame axes on the Tait-Bryan angles: G^T M
        a0 = self.a_ref[:, 0] + q[o + 3]
        a1 = self.a_ref[:, 1] + q[o + 4]
        my, mz = torque * cp, -torque * sp
        c0, s0, c1 = np.cos(a0), np.sin(a0), np.cos(a1)
        out[o + 4] += c0 * my + s0 * mz
        out[o + 5] += -s0 * c1 * my + c0 * c1 * mz
