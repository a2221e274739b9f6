"""Forces and torques of the track's vertical alignment on the vehicle's bodies.

The bodies' coordinates follow the track (``docs/curving.md``): their first coordinate is the
distance along the track, their third the height above the top of rail *normal to the local
track*, and their angles are relative to the local track direction. A gradient and a vertical
curve therefore appear as the inertial and gravity forces of a frame that pitches with the track
(``docs/curving.md``, "Vertical alignment"), evaluated at every body's own distance ``s`` and
applied as an Exudyn load on each body, set at the start of every step
(:meth:`railexu.model.assembly.VehicleModel.update_vertical_loads`):

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
in the Jacobian (a stiffness of m g / R_v, under 1e-4 of the suspension's), and their change
within a step (a body moves a few centimetres of a profile that changes over metres).
"""

from __future__ import annotations

import numpy as np

from railexu.track.vertical import VerticalAlignment


class VerticalForces:
    """The vertical alignment's loads on a vehicle's bodies and wheelsets.

    Args:
        vertical: the track's vertical profile.
        mass_kg: the bodies' masses [kg].
        pitch_inertia_kg_m2: their inertias about the lateral axis (a wheelset's spin inertia)
            [kg m^2].
        gravity_m_per_s2: gravity [m/s^2].
    """

    def __init__(
        self,
        vertical: VerticalAlignment,
        mass_kg: np.ndarray,
        pitch_inertia_kg_m2: np.ndarray,
        gravity_m_per_s2: float,
    ) -> None:
        self.v = vertical
        self.m = np.asarray(mass_kg, dtype=float)
        self.i_y = np.asarray(pitch_inertia_kg_m2, dtype=float)
        self.g = float(gravity_m_per_s2)

    def loads(
        self, s_m: np.ndarray, speed_m_per_s: np.ndarray, frame_roll_rad: float = 0.0
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(forces, torques)``, each ``(n, 3)`` [N, N m] in the vehicle frame's axes, on the
        bodies at distances ``s_m`` moving at ``speed_m_per_s`` along the track; the frame
        rolled by ``frame_roll_rad`` (curved track, 0 on straight track)."""
        v = self.v
        s = np.asarray(s_m, dtype=float)
        speed = np.asarray(speed_m_per_s, dtype=float)
        grad = np.interp(s, v.grid_m, v.gradient)
        kappa = np.interp(s, v.grid_m, v.curvature_1_per_m, left=0.0, right=0.0)
        dkappa = np.interp(s, v.grid_m, v.curvature_slope, left=0.0, right=0.0)
        cos_t = 1.0 / np.sqrt(1.0 + grad * grad)
        sin_t = grad * cos_t
        v2 = speed * speed
        normal = -self.m * (self.g * (cos_t - 1.0) + v2 * kappa)
        torque = self.i_y * v2 * dkappa
        cp, sp = np.cos(frame_roll_rad), np.sin(frame_roll_rad)
        # the normal (0, sin, cos) and the horizontal lateral axis (0, cos, -sin) of the track
        # in the axes of the frame rolled by phi
        forces = np.stack([-self.m * self.g * sin_t, sp * normal, cp * normal], axis=1)
        torques = np.stack([np.zeros_like(torque), cp * torque, -sp * torque], axis=1)
        return forces, torques
