"""Contact geometry: placement, symmetry, the compiled search against the general method,
conicity of a cone, flange contact onset. Physics checks, not snapshots."""

from __future__ import annotations

import numpy as np
import pytest

from railexu.contact import kernel as K
from railexu.contact.conicity import equivalent_conicity, equivalent_conicity_from_delta_r
from railexu.contact.evaluation import ContactParameters, WheelsetContactModel
from railexu.contact.placement import (
    PlacementError,
    WheelsetGeometry,
    parse_inclination,
    place_wheel_rail,
    symmetric_wheelset,
)
from railexu.contact.quasistatic import press_wheelset, rigid_contact
from railexu.contact.search import general_contact_search
from railexu.profiles import cone_wheel, round_rail


@pytest.fixture(scope="module")
def s1002_uic60():
    geometry = symmetric_wheelset("S1002", "UIC60", nominal_radius_m=0.46, inclination="1:40")
    return WheelsetContactModel(geometry, ContactParameters(), speed_m_per_s=2.0)


def test_parse_inclination():
    assert parse_inclination("1:40") == pytest.approx(np.arctan(1 / 40), rel=1e-15)
    assert parse_inclination("1/20") == pytest.approx(np.arctan(1 / 20), rel=1e-15)
    assert parse_inclination("none") == 0.0
    assert parse_inclination(0.025) == 0.025
    with pytest.raises(PlacementError, match="1:40"):
        parse_inclination("one in forty")


def test_placement_gauge_top_and_tape_circle(s1002_uic60):
    pair = s1002_uic60.geometry.left
    # top of the canted rail at z = 0
    assert np.max(pair.rail_table.z) == pytest.approx(0.0, abs=1e-9)
    # gauge: the gauge face 14 mm below the top sits at gauge / 2 (60E1 widens downwards, so
    # the innermost point of the top 14 mm is at the bottom of the band)
    outline = pair.rail_outline_track_m
    face = outline[(outline[:, 0] < 0.73) & (outline[:, 1] < -0.008) & (outline[:, 1] > -0.02)]
    order = np.argsort(face[:, 1])
    y_at_14mm = np.interp(-0.014, face[order, 1], face[order, 0])
    assert y_at_14mm == pytest.approx(0.7175, abs=1e-7)
    # tape circle 70 mm outboard of the flange back at half the flange-back distance
    assert pair.tape_circle_lateral_m == pytest.approx(0.680 + 0.070, abs=1e-12)
    # the canted 60E1's highest point lies R300 * sin(1/40) = 7.5 mm outwards of the rail axis
    y_top = pair.rail_table.y0_m + pair.rail_table.step_m * np.argmax(pair.rail_table.z)
    y_axis, _ = pair.rail_origin_track_m
    assert y_top - y_axis == pytest.approx(0.300 * np.sin(np.arctan(1 / 40)), abs=5e-5)


def test_placement_rejects_swapped_profiles():
    from railexu.profiles import rail_profile

    with pytest.raises(PlacementError, match="not a wheel"):
        place_wheel_rail(rail_profile("UIC60"), "UIC60", nominal_radius_m=0.46)
    with pytest.raises(ValueError, match="unknown wheel profile 'UIC60'"):
        place_wheel_rail("UIC60", "UIC60", nominal_radius_m=0.46)


def test_centred_wheelset_is_symmetric(s1002_uic60):
    rc = rigid_contact(s1002_uic60, 0.0)
    assert rc.roll_rad == pytest.approx(0.0, abs=1e-12)
    res = press_wheelset(s1002_uic60, 0.0, 0.0, 10000.0)
    left, right = res.result.wheel("left"), res.result.wheel("right")
    assert len(left) == len(right)
    for pl, pr in zip(left, right, strict=True):
        # 1e-8 m, 1e-6: the load centroid sums the gap over the patch, whose last digits differ
        # between the mirrored tables (a nanometre, 0.1 mN, 0.01 mN laterally: no consequence)
        assert pl.wheel_lateral_m == pytest.approx(pr.wheel_lateral_m, abs=1e-8)
        assert pl.normal_force_N == pytest.approx(pr.normal_force_N, rel=1e-6)
        assert pl.position_m[1] == pytest.approx(-pr.position_m[1], abs=1e-8)
        assert pl.force_lat_N == pytest.approx(-pr.force_lat_N, abs=1e-4)
    assert res.result.force_N[1] == pytest.approx(0.0, abs=1e-4)


def test_mirror_symmetry_of_a_moving_wheelset(s1002_uic60):
    """A pose and its mirror image (y -> -y) give mirrored contacts on the other wheel."""
    m = s1002_uic60
    pose = dict(lateral_m=0.0032, vertical_m=0.4598, roll_rad=2.1e-4, yaw_rad=-3.0e-3)
    vel = (2.0, 0.013, -0.002)
    omega = (0.02, 2.0 / 0.46, -0.05)
    a = m.evaluate(**pose, velocity_m_per_s=vel, angular_velocity_rad_per_s=omega)
    mirrored = dict(lateral_m=-0.0032, vertical_m=0.4598, roll_rad=-2.1e-4, yaw_rad=3.0e-3)
    b = m.evaluate(
        **mirrored,
        velocity_m_per_s=(vel[0], -vel[1], vel[2]),
        angular_velocity_rad_per_s=(-omega[0], omega[1], -omega[2]),
    )
    assert a.points and len(a.wheel("left")) == len(b.wheel("right"))
    for pa, pb in zip(a.wheel("left"), b.wheel("right"), strict=True):
        assert pa.wheel_lateral_m == pytest.approx(pb.wheel_lateral_m, abs=1e-10)
        assert pa.normal_force_N == pytest.approx(pb.normal_force_N, rel=1e-9)
        assert pa.creep_long == pytest.approx(pb.creep_long, abs=1e-12)
        assert pa.creep_lat == pytest.approx(-pb.creep_lat, abs=1e-12)
        assert pa.spin_per_m == pytest.approx(-pb.spin_per_m, abs=1e-12)
    # polar vector: F_y flips; pseudo-vector torque: M_x, M_z flip
    np.testing.assert_allclose(a.force_N * [1, -1, 1], b.force_N, rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(a.torque_Nm * [-1, 1, -1], b.torque_Nm, rtol=1e-9, atol=1e-6)


POSES = [
    # (y [m], roll [rad], yaw [rad]) with the height chosen to give ~0.05 mm overlap
    (0.0, 0.0, 0.0),
    (0.0025, 1.4e-4, 0.004),
    (-0.004, -2.5e-4, -0.008),
    (0.0066, 4.4e-3, 0.0156),  # flange contact, large yaw: contact point leads the axle
    (0.0052, 5.0e-4, 0.0),  # tread and flange root together
]


@pytest.mark.parametrize("y, roll, yaw", POSES)
def test_kernel_agrees_with_general_parametric_search(s1002_uic60, y, roll, yaw):
    """The compiled locus search on the sampled tables finds the same contact points as the
    general four-parameter surface method on the profiles' splines.

    (a) Touching (rigid contact): both methods must give the same point: position on the wheel,
    flange lead and contact angle. (b) With overlap the kernel's virtual penetration
    ``-g cos(gamma)`` (vertical gap) and the general method's normal distance agree to second
    order in the overlap. (The points themselves then differ slightly: equal slopes at one
    lateral position versus parallel normals across the overlap, a difference of order
    delta gamma kappa / (kappa_w + kappa_r) that is large only in near-conformal contact.)
    """
    m = s1002_uic60
    rc = rigid_contact(m, y, yaw)
    roll = rc.roll_rad
    for z, touching in ((rc.vertical_m, True), (rc.vertical_m - 5e-5, False)):
        res = m.evaluate(y, z, roll, yaw)
        for side, mirror in (("left", 1.0), ("right", -1.0)):
            pair = m.geometry.left if side == "left" else m.geometry.right
            general = general_contact_search(pair, mirror * y, z, mirror * roll, mirror * yaw)
            if touching:
                kernel_pts = [p for p in res.wheel(side) if abs(p.gap_m) < 1e-10]
                general_pts = [c for c in general if abs(c.normal_distance_m) < 1e-9]
            else:
                kernel_pts = [p for p in res.wheel(side) if p.penetration_m > 0.0]
                general_pts = [c for c in general if c.normal_distance_m < 0.0]
            assert len(kernel_pts) == len(general_pts)
            for kp in kernel_pts:
                gp = min(general_pts, key=lambda c, kp=kp: abs(c.wheel_s_m - kp.wheel_lateral_m))
                if touching:
                    # 0.05 mm tables reproduce the spline's stationary point
                    assert kp.wheel_lateral_m == pytest.approx(gp.wheel_s_m, abs=2e-6)
                    assert kp.position_m[0] == pytest.approx(gp.wheel_point_m[0], abs=2e-6)
                    assert kp.contact_angle_rad == pytest.approx(gp.contact_angle_rad, abs=2e-5)
                else:
                    # the minimum's vertical gap along the general method's normal (the kernel's
                    # force acts at the patch's load centroid since issue 28, so its reported
                    # angle and approach are the centroid's: docs/contact-model.md)
                    # (paired by depth: the centroid of a patch may lie nearer another minimum)
                    gp = min(
                        general_pts,
                        key=lambda c, kp=kp: abs(
                            kp.gap_m * np.cos(c.contact_angle_rad) - c.normal_distance_m
                        ),
                    )
                    depth = -kp.gap_m * np.cos(gp.contact_angle_rad)
                    assert depth == pytest.approx(-gp.normal_distance_m, rel=2e-3, abs=1e-8)
                    # the centroid and the minimum both lie inside the patch, so closer than
                    # its width: 2 sqrt(eps d / B) for a parabolic gap, and at least the 15.5 mm
                    # of the nearly conformal centred tread (Kik-Piotrowski, docs/validation.md)
                    b_lat = 0.5 * (kp.wheel_curvature_lat_per_m + kp.rail_curvature_lat_per_m)
                    width = max(2.0 * np.sqrt(0.55 * depth / max(b_lat, 1.0)), 0.0155)
                    assert abs(kp.wheel_lateral_m - gp.wheel_s_m) < width
    # at least one touching point per wheel was compared
    assert rc.vertical_m > 0.45


def test_flange_contact_point_leads_the_axle_with_yaw(s1002_uic60):
    """A yawed wheelset in flange contact: the flange point moves ahead of or behind the axle,
    relative to the wheel's own centre, by r tan(gamma_w) psi (the classic flange lead, gamma_w the
    flank angle in the wheelset frame); a tread point hardly moves."""
    m = s1002_uic60
    y, yaw = 0.0068, -0.010
    st = press_wheelset(m, y, yaw, 10000.0)
    e = m.geometry.left.tape_circle_lateral_m

    def lead(p, side_sign):
        # wheel centre of this wheel circle sits at x = -sin(psi) * (lateral axle coordinate)
        axle_y = side_sign * (e + p.wheel_lateral_m)
        return p.position_m[0] + np.sin(yaw) * axle_y

    flange = max(st.result.wheel("left"), key=lambda p: p.contact_angle_rad)
    assert flange.contact_angle_rad > np.radians(45)
    gamma_w = flange.contact_angle_rad - st.roll_rad
    expected = flange.rolling_radius_m * np.tan(gamma_w) * yaw
    assert lead(flange, 1.0) == pytest.approx(expected, rel=0.02)
    assert abs(expected) > 0.008  # about 10 mm behind the axle for psi = -10 mrad
    tread = st.result.wheel("right")[0]
    assert abs(lead(tread, -1.0)) < 0.05 * abs(expected)


def test_cone_on_round_rail_gives_cone_slope_as_conicity():
    """A cone of slope lambda on a round rail head of radius R.

    Shifting the wheelset by y moves both contacts along the cones: Delta r = 2 lambda y. The
    wheelset then rolls by phi = Delta r / (2 e_c) (e_c: half the distance between the contact
    points); the roll tilts each cone by phi, which moves the contact across the rail head by
    R phi and, through the wheel's radius, along the wheel by r0 phi. To first order
    Delta r = 2 lambda y + 2 lambda (R + r0) phi, so the equivalent conicity is the same for all
    amplitudes (linear Delta r) and equals gamma_e = lambda / (1 - lambda (R + r0) / e_c), which
    tends to the cone slope lambda for a small wheel on a knife edge.
    """
    lam, radius, r0 = 0.05, 0.05, 0.625
    wheel = cone_wheel(lam, half_width_m=0.07)
    rail = round_rail(radius, width_m=0.06)
    geometry = symmetric_wheelset(wheel, rail, nominal_radius_m=r0, inclination="none")
    m = WheelsetContactModel(geometry, ContactParameters(), 10.0)
    centred = press_wheelset(m, 0.0, 0.0, 10000.0).result.wheel("left")[0]
    e_c = centred.position_m[1]
    amps = np.array([0.001, 0.003, 0.006])
    gamma, y, dr = equivalent_conicity(m, amps, step_m=2.5e-4)
    expected = lam / (1.0 - lam * (radius + r0) / e_c)
    # second-order terms are of order lambda * phi ~ 1e-4 relative
    np.testing.assert_allclose(gamma, expected, rtol=1e-3)
    # and Delta r is linear (no jumps) on a cone
    assert np.max(np.abs(dr - 2.0 * expected * y)) < 1e-6
    # a cone on a (nearly) knife-edge rail with a small wheel: gamma_e -> lambda
    assert lam / (1.0 - lam * (0.001 + 0.05) / e_c) == pytest.approx(lam, rel=5e-3)


def test_harmonic_linearisation_of_a_cubic():
    """For Delta r = 2 (g y + c y^3) the first harmonic gives g + (3/4) c A^2."""
    y = np.linspace(-0.01, 0.01, 4001)
    g, c = 0.1, 500.0
    amps = np.array([0.002, 0.005, 0.009])
    gamma = equivalent_conicity_from_delta_r(y, 2.0 * (g * y + c * y**3), amps, method="harmonic")
    np.testing.assert_allclose(gamma, g + 0.75 * c * amps**2, rtol=1e-6)


def test_flange_contact_appears_near_the_flangeway_clearance(s1002_uic60):
    """New S1002 on 60E1 1:40, gauge 1435, flange back 1360: flangeway clearance
    (1435 - 1360 - 2 x 32.5) / 2 = 5.0 mm. Below it only tread contact; the flange root is met
    just above it and the flank (~70 deg) about 1.5 mm later; a second (flange) point carries load
    together with the tread only in that transition. (Near y = 0 this pair touches at two tread
    points, 11 mm apart, which is a known feature of new S1002 on 1:40 rails.)"""
    m = s1002_uic60
    ys = np.round(np.arange(0.0, 0.0091, 0.0005), 6)
    first_flank = None
    for y in ys:
        st = press_wheelset(m, float(y), 0.0, 10000.0)
        loaded = [p for p in st.result.wheel("left") if p.loaded]
        angles = [np.degrees(p.contact_angle_rad) for p in loaded]
        if y < 0.0045:
            assert max(angles) < 10.0, f"flange contact already at y = {y * 1e3} mm"
        flange_pts = [a for a in angles if a > 10.0]
        if flange_pts and len(loaded) >= 2:  # tread and flange carry load together
            assert 0.0045 <= y <= 0.0070, f"tread + flange contact at y = {y * 1e3} mm"
        if max(angles) > 55.0 and first_flank is None:
            first_flank = y
        # the other wheel stays on its tread
        assert all(np.degrees(p.contact_angle_rad) < 10.0 for p in st.result.wheel("right"))
    assert first_flank is not None and 0.0050 <= first_flank <= 0.0070


def test_contact_forces_oppose_creepage(s1002_uic60):
    """Force on the wheel opposes the creepage (conventions.md): a wheelset sliding sideways to
    the left (positive lateral creepage) gets pushed to the right."""
    m = s1002_uic60
    rc = rigid_contact(m, 0.0)
    res = m.evaluate(0.0, rc.vertical_m - 2e-5, 0.0, 0.0, velocity_m_per_s=(2.0, 0.004, 0.0))
    for p in res.points:
        if p.loaded:
            assert np.sign(p.force_lat_N) == -np.sign(p.creep_lat)
    assert res.force_N[1] < 0.0


def test_damped_normal_force_never_pulls(s1002_uic60):
    """N = K delta^1.5 + D delta_dot is clipped at zero when the wheel lifts fast."""
    m = s1002_uic60
    rc = rigid_contact(m, 0.0)
    res = m.evaluate(0.0, rc.vertical_m - 1e-6, 0.0, 0.0, velocity_m_per_s=(2.0, 0.0, 5.0))
    assert all(p.normal_force_N == 0.0 for p in res.points)
    assert any(p.penetration_m > 0.0 for p in res.points)


def test_different_wheels_left_and_right():
    """Left and right pairs are independent: a cone on one side, S1002 on the other."""
    left = place_wheel_rail("S1002", "UIC60", nominal_radius_m=0.46)
    right = place_wheel_rail(cone_wheel(0.05, flange_back_m=-0.07), "UIC60", nominal_radius_m=0.46)
    m = WheelsetContactModel(WheelsetGeometry(left=left, right=right), ContactParameters(), 2.0)
    res = press_wheelset(m, 0.0, 0.0, 10000.0)
    assert res.result.wheel_force_N("left")[2] == pytest.approx(10000.0, abs=1e-2)
    assert res.result.wheel_force_N("right")[2] == pytest.approx(10000.0, abs=1e-2)


def test_kernel_output_layout():
    assert K.N_POINT_FIELDS == K.PF_WEIGHT + 1
    assert K.N_PARAMS == K.P_TANGENTIAL + 1
