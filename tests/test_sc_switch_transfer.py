"""Quasi-static load transfer from the stock rail to the switch blade through the turnout's
generated switch panel (issue 29; docs/switches-and-crossings.md, "Rail-to-rail transfer").

The UK 56E1-R245-1:9.25 turnout's switch panel (``tracks/turnout_uk_r245_*_facing.yaml``, its
blade and stock rail generated from the track's rail by the design's planing rule) and the
wheelset vehicle's wheel (S1002, r0 = 625 mm, placed as the dynamics places it), pressed with
the static wheel load and moved along the panel at a fixed lateral position. Two transfers the
geometry gives at a fixed lateral position (the blade lies 10 mm below the stock rail at the toe
and rises 1:350 to full height at 3.5 m, while the stock rail moves to the field side):

- the through route, the centred wheel: its tread passes from the stock rail's head (y = 17-18
  mm, field side of its crown, the rail moved 22 mm) to the blade's top (y = -9 mm) where the
  rising blade overtakes the stock rail under the tread (3.33 m from the toe);
- the diverging route, the wheel 7 mm towards the panel's rail (towards the curve's outside):
  the flange root passes from the stock rail to the blade's gauge corner (y = -34 mm) at 2.7 m.

Checked against the rigid wheel's touch heights on each rail (the slices' geometry alone,
:func:`~railexu.contact.variable_rail.rail_touch_heights`): the rails' vertical forces sum to
the load; the blade's share rises monotonically and continuously; the wheel's height changes
per step as the rigid wheel's within the elastic approach; the 50 % point lies within
``0.63 delta / rate`` of where the rigid wheel touches both rails at once (``delta`` the
approach at the load, ``rate`` how fast the touch heights part along the track: Hertz's
approach at half the load is ``2^(-2/3) = 0.63`` of it, and the two rails' half-load
approaches differ by less than the larger), and within 10 % + 1 mm of where the two rails'
half-load approaches make up the touch heights' gap. Then the compiled kernel on the
dynamics' effective sections, the same sweep.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.variable_rail import (
    ContactSettings,
    WheelSection,
    press_wheel,
    rail_touch_heights,
)
from railexu.contact.variable_tables import section_rail_arrays
from railexu.model.assembly import wheelset_geometry
from railexu.profiles.variable.rails import rail_index
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

#: The wheelset vehicle's static wheel load (196.2 kN per axle) [N].
WHEEL_LOAD_N = 98.1e3
#: The quasi-static grid: CONTACT's DX, DS of the crossing's transfer test (0.4 mm; the force
#: at a given approach changes < 1 % from 0.4 to 0.2 mm, tests/test_sc_contact.py).
SETTINGS = ContactSettings(dx_m=4e-4, dy_m=4e-4, coarse_dx_m=2e-3, coarse_dy_m=5e-4)
#: Hertz: the approach at half the load is 2^(-2/3) of the approach at the load.
HALF_LOAD_APPROACH = 0.5 ** (2.0 / 3.0)

#: route, the wheel's lateral position in the panel's rail axes (field side positive) [m], a
#: bracket of the rigid transfer point [m from the toe], the sweep from it [m]
CASES = {
    "through, tread": ("through", 0.0, (3.2, 3.45), np.arange(-0.06, 0.0601, 0.01)),
    "diverging, flange root": ("diverging", 0.007, (2.5, 2.85), np.arange(-0.06, 0.2401, 0.02)),
}


class Panel:
    """The switch panel of a route (facing, the crossing panel left out), its side and the
    wheelset's geometry."""

    def __init__(self, route: str) -> None:
        track = load_track(f"turnout_uk_r245_{route}_facing", ["turnout.panels=switch"])
        self.rails = track.variable_rails
        self.side = 0 if self.rails.left is not None else 1
        self.zoned = self.rails.sides()[self.side]
        (panel,) = self.zoned.panels
        self.profile = panel.profile  # s from the toe (the slices begin 0.2 m ahead of it)
        self.toe_m = panel.s0_m  # the toe in the zoned profile's s
        geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
        self.geometry = geometry
        self.pair = geometry.pairs[self.side]
        self.wheel = WheelSection.from_pair(self.pair)


@pytest.fixture(scope="module", params=list(CASES))
def case(request):
    route, y, bracket, steps = CASES[request.param]
    return request.param, Panel(route), y, bracket, steps


def rigid_touch_heights(panel: Panel, s_m: float, y_m: float) -> np.ndarray:
    """The rigid wheel's touch heights on the blade (0) and the stock rail (1) [m, down]."""
    return rail_touch_heights(panel.profile, panel.wheel, s_m, y_m)


@pytest.fixture(scope="module")
def sweep(case):
    """The rigid transfer point, then the wheel pressed at 10 mm steps within +-60 mm of it."""
    name, panel, y, bracket, steps = case
    gap = lambda s: np.subtract(*rigid_touch_heights(panel, s, y))  # noqa: E731
    s_star = brentq(gap, *bracket, xtol=1e-6)
    s_grid = s_star + steps
    forces, heights, rigid = [], [], []
    for s in s_grid:
        touch = rigid_touch_heights(panel, s, y)
        z, patches = press_wheel(panel.profile, panel.wheel, s, y, WHEEL_LOAD_N, SETTINGS)
        fz = np.zeros(2)
        for p in patches:
            fz[p.rail_index] += p.vertical_force_n
        forces.append(fz)
        heights.append(z)
        rigid.append(touch)
    rigid = np.array(rigid)
    rate = np.polyfit(s_grid, rigid[:, 0] - rigid[:, 1], 1)[0]
    return {"name": name, "panel": panel, "y": y, "s_star": s_star, "s": s_grid,
            "forces": np.array(forces), "z": np.array(heights), "rigid": rigid,
            "rate": rate}  # fmt: skip


def test_quasi_static_stock_rail_to_blade(sweep):
    """The rails' vertical forces sum to the load (0.1 %: the pressing's tolerance); the
    blade's share rises monotonically (1e-3: the pressing's tolerance) from < 2 % to > 98 %,
    and continuously: over the ~2 delta / rate the two rails share the load (~70 mm here)
    at least four 10 mm steps lie strictly between, none changing the share by more than 0.3;
    the wheel's height changes per step as the rigid wheel's within the elastic approach (a
    jump between rails would show as a step of the surface); the 50 % point lies within
    0.63 delta / rate of the rigid transfer point (measured: +0.64 mm of 3.3322 m, tread;
    +91.2 mm of 2.6586 m, flange root, whose blade corner patch needs 0.55 mm of approach
    against the stock rail's 0.10 mm)."""
    f, s, z, rigid = sweep["forces"], sweep["s"], sweep["z"], sweep["rigid"]
    np.testing.assert_allclose(f.sum(axis=1), WHEEL_LOAD_N, rtol=1e-3)
    share = f[:, 0] / f.sum(axis=1)
    assert share[0] < 0.02 and share[-1] > 0.98, share
    assert np.all(np.diff(share) >= -1e-3), share
    between = (share > 0.02) & (share < 0.98)
    assert np.count_nonzero(between) >= 4 and np.max(np.diff(share)) < 0.3, share
    # the elastic approach at the load: the pressed wheel below the rigid one where one rail
    # carries all (the sweep's ends)
    on_top = np.nanmin(rigid, axis=1)
    approach = z - on_top
    delta = float(max(approach[0], approach[-1]))
    # 0.1 mm at 98 kN on the heads' tops, 0.55 mm on the blade's gauge corner (its small
    # radius against the flange root)
    assert 5e-5 < delta < 1e-3
    assert np.max(np.abs(np.diff(z) - np.diff(on_top))) < delta
    rate = abs(sweep["rate"])
    assert 2.5e-3 < rate < 4e-3  # the blade's rise, 10 mm over 3.5 m, and the stock's fall
    s_half = float(np.interp(0.5, share, s))
    assert abs(s_half - sweep["s_star"]) < HALF_LOAD_APPROACH * delta / rate
    # sharper: the 50 % point where the two rails' half-load approaches (Hertz: 0.63 of each
    # rail's approach at the load, measured at the sweep's ends) make up the touch heights'
    # gap; within 10 % of that offset (Hertz's exponent for these non-elliptic patches) and
    # 1 mm (the share interpolated between 10-20 mm steps)
    offset = HALF_LOAD_APPROACH * (approach[-1] - approach[0]) / rate
    assert abs(s_half - sweep["s_star"] - offset) < 0.1 * abs(offset) + 1e-3


def _kernel(panel: Panel, s_m: float):
    """The compiled kernel with the panel's effective section at ``s`` from the toe on the
    panel's side (the dynamics' table: :func:`section_rail_arrays` of the zoned profile)."""
    model = WheelsetContactModel(panel.geometry)
    tab = section_rail_arrays(panel.zoned, panel.toe_m + s_m, panel.pair,
                              x_max_m=panel.rails.x_max_m)  # fmt: skip
    if panel.side == 0:
        model.rtab_l, model.rinfo_l = tab
    else:
        model.rtab_r, model.rinfo_r = tab
    return model


def kernel_rail_forces(panel: Panel, model, s_m: float, y_m: float, height_m) -> np.ndarray:
    """Vertical forces [N] of blade (0) and stock rail (1) on the panel's wheel, the wheel at
    ``y`` towards the panel rail's field side and its centre at ``height_m`` (z up)."""
    lateral = y_m if panel.side == 0 else -y_m  # the right wheel's field side: -y of the track
    y0 = panel.pair.rail_origin_track_m[0]
    out = np.zeros((np.size(height_m), 2))
    for i, h in enumerate(np.atleast_1d(height_m)):
        for p in model.evaluate(lateral, float(h)).raw[panel.side]:
            if p[K.PF_ACTIVE] > 0 and p[K.PF_N] > 0:
                y = np.array([p[K.PF_YRAIL] - y0])
                out[i, rail_index(panel.zoned, panel.toe_m + s_m, y)[0]] += p[K.PF_FTZ]
    return out if np.ndim(height_m) else out[0]


@pytest.fixture(scope="module")
def kernel_sweep(sweep):
    panel, y = sweep["panel"], sweep["y"]
    r0 = panel.pair.nominal_radius_m
    forces, heights, monotone = [], [], []
    for s in sweep["s"]:
        model = _kernel(panel, s)

        def excess(h, model=model, s=s):
            return kernel_rail_forces(panel, model, s, y, h).sum() - WHEEL_LOAD_N

        h = brentq(excess, r0 - 0.005, r0 + 0.005, xtol=1e-11)
        heights.append(h)
        forces.append(kernel_rail_forces(panel, model, s, y, h))
        grid = h + np.linspace(-2e-4, 6e-4, 161)  # from below the pressed height to clear
        f = kernel_rail_forces(panel, model, s, y, grid)
        monotone.append(float(np.max(np.diff(f, axis=0))))  # a rail's force rising with h
    return {"forces": np.array(forces), "h": np.array(heights), "rise": np.array(monotone)}


def test_kernel_stock_rail_to_blade(sweep, kernel_sweep):
    """The compiled kernel on the dynamics' effective sections, the same wheel and positions:
    each rail's force does not rise as the wheel is lifted (1 N: the rails' overlaps all shrink
    together); the blade's share rises monotonically and continuously as in the quasi-static
    solution; its 50 % point within 0.63 delta / rate of the rigid transfer point (measured
    +0.9 and +91.5 mm, the quasi-static +0.64 and +91.2 mm); the pressed wheel's height
    changes per step as the rigid wheel's within the approach (measured: as the quasi-static
    one's within 0.73 um on the tread, 19 um on the blade's corner, Hertz against the
    half-space)."""
    f, h = kernel_sweep["forces"], kernel_sweep["h"]
    assert np.all(kernel_sweep["rise"] < 1.0), kernel_sweep["rise"]
    share = f[:, 0] / f.sum(axis=1)
    assert share[0] < 0.02 and share[-1] > 0.98, share
    assert np.all(np.diff(share) >= -1e-3), share
    between = (share > 0.02) & (share < 0.98)
    assert np.count_nonzero(between) >= 4 and np.max(np.diff(share)) < 0.3, share
    on_top = np.nanmin(sweep["rigid"], axis=1)
    delta = float(max(sweep["z"][0] - on_top[0], sweep["z"][-1] - on_top[-1]))
    s_half = float(np.interp(0.5, share, sweep["s"]))
    assert abs(s_half - sweep["s_star"]) < HALF_LOAD_APPROACH * delta / abs(sweep["rate"])
    # the kernel's pressed wheel (its centre up) changes height per step as the rigid wheel
    # (z down) within the approach: its sum of the two rails' forces is continuous
    assert np.max(np.abs(np.diff(-h) - np.diff(on_top))) < delta
