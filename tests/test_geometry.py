"""Rigid wheel-rail geometry: geometry table, mirror symmetry, gap field vs Hertz curvatures, creepages."""

import numpy as np
import pytest

from railvti import InputError
from railvti import geometry as G
from railvti import profiles as P
from railvti.geometry.frames import axle_direction
from railvti.wheelset import WheelsetGeometry


@pytest.fixture(scope="module")
def pair():
    return P.s1002(), P.uic60(cant=1 / 40)


@pytest.fixture(scope="module")
def table(pair):
    return G.geometry_table(*pair, np.linspace(-0.01, 0.01, 81))


def test_layout_gauge(pair):
    lay = G.layout(*pair)
    # the gauge point, 14 mm below the rail top, is at half the gauge
    assert lay.rail_offset + lay.gauge_point == pytest.approx(0.7175, abs=1e-12)
    assert pair[1].height(lay.gauge_point) - lay.rail_top == pytest.approx(0.014, abs=1e-9)
    assert lay.max_flange_angle == pytest.approx(np.arctan(2.747477419), abs=2e-3)  # S1002 70 deg face


def test_wheelset_is_the_fe_wheelset(pair):
    """The contact geometry places each tread datum (wheel profile y = 0) on the FE wheelset's
    taping line: 1360 mm / 2 + 70 mm (EN 13715) from the centre."""
    lay = G.layout(*pair)
    assert lay.wheelset == WheelsetGeometry()
    c = G.contact_points(*pair, 0.0).left[0]
    assert c.position[1] - c.y_wheel == pytest.approx(0.68 + 0.07, abs=1e-9)
    assert c.rolling_radius - pair[0].height(c.y_wheel) == pytest.approx(0.46, abs=1e-12)
    wide = G.contact_points(*pair, 0.0, wheelset=WheelsetGeometry(back_to_back=1.37)).left[0]
    assert wide.position[1] - wide.y_wheel == pytest.approx(0.685 + 0.07, abs=1e-9)


def test_axle_direction_is_the_rotated_lateral_axis():
    roll, yaw = np.array([0.0, 0.02, -0.03]), np.array([0.0, 0.1, 0.05])
    for r, w, a in zip(roll, yaw, axle_direction(roll, yaw)):
        rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
        rz = np.array([[np.cos(w), -np.sin(w), 0], [np.sin(w), np.cos(w), 0], [0, 0, 1]])
        assert np.allclose(a, rz @ rx @ [0.0, 1.0, 0.0], atol=1e-15)


def test_centred_one_point_per_wheel_near_cant(pair):
    c = G.contact_points(*pair, 0.0)
    assert c.status == ("ok", "ok")
    for pts in (c.left, c.right):
        assert sum(p.in_contact for p in pts) == 1
        assert 0.024 < pts[0].contact_angle < 0.030
    assert c.pose.roll == pytest.approx(0.0, abs=1e-12)


def test_mirror_symmetry(table):
    i, j = np.arange(table.y.size), np.arange(table.y.size)[::-1]
    assert np.allclose(table.y[i], -table.y[j])
    for name in ("contact_angle", "rolling_radius", "y_wheel", "y_rail", "separation"):
        a = getattr(table, name)
        assert np.allclose(a[i, 0], a[j, 1], equal_nan=True, atol=1e-9), name
    assert np.allclose(table.y_track[i, 0], -table.y_track[j, 1], equal_nan=True, atol=1e-9)
    assert np.allclose(table.roll[i], -table.roll[j], atol=1e-10)
    assert np.allclose(table.delta_r[i], -table.delta_r[j], atol=1e-9)
    assert np.array_equal(table.status[i, 0], table.status[j, 1])


def test_mirror_with_yaw(pair):
    a = G.contact_points(*pair, 0.004, yaw=0.003)
    b = G.contact_points(*pair, -0.004, yaw=-0.003)
    pa, pb = a.left[0], b.right[0]
    assert pa.contact_angle == pytest.approx(pb.contact_angle, abs=1e-9)
    assert pa.position[0] == pytest.approx(pb.position[0], abs=1e-9)  # same lead
    ca, cb = G.creepages(pa, 2.0), G.creepages(pb, 2.0)
    assert ca.xi == pytest.approx(cb.xi, abs=1e-9)
    assert ca.eta == pytest.approx(-cb.eta, abs=1e-9)  # t_y points left on both wheels
    assert ca.phi == pytest.approx(-cb.phi, abs=1e-9)


def test_flange_contact_appears_at_6_to_7_mm(table):
    big = table.contact_angle[:, 0, 0] > 1.0  # left wheel carrying point on the flange
    first = table.y[np.argmax(big)]
    assert 0.006 <= first <= 0.007
    assert not big[table.y < 0.006].any()
    # delta-r grows with y and jumps at flange contact
    ok = (table.y > 0) & (table.y < 0.006)
    assert np.all(np.diff(table.delta_r[ok]) > 0)


def test_flange_climb_status(table):
    # far beyond flange contact the rigid wheel rides past the 70 deg face: explicit status
    assert table.status[-1, 0] == G.FLANGE_CLIMB
    assert table.status[0, 1] == G.FLANGE_CLIMB
    assert np.all(table.status[np.abs(table.y) < 0.006] == G.OK)


def test_no_contact_status(pair):
    # a wheelset so narrow that the wheels miss the rails' heads
    t = G.geometry_table(*pair, [0.0], wheelset=WheelsetGeometry(back_to_back=1.2))
    assert np.all(t.status[0] == G.NO_CONTACT)
    assert np.isnan(t.roll[0])


def test_gap_field_matches_hertz_curvatures(pair):
    wheel, rail = pair
    for y, yaw in [(0.0, 0.0), (0.003, 0.0), (0.003, 0.004)]:
        c = G.contact_points(wheel, rail, y, yaw).left[0]
        h = 2e-4
        f = G.gap_field(wheel, rail, c, h, h, 5, 5)
        g = f.gap
        assert f.gap.shape == (5, 5) and f.gap.flags.f_contiguous
        assert g[2, 2] == pytest.approx(0.0, abs=1e-10)
        assert g.min() > -1e-10
        gxx = (g[3, 2] - 2 * g[2, 2] + g[1, 2]) / h**2
        gyy = (g[2, 3] - 2 * g[2, 2] + g[2, 1]) / h**2
        pose = c.pose
        a = pose.axle
        rel = c.position - pose.centre
        rad = rel - (rel @ a) * a
        # circumferential normal curvature of a surface of revolution: cos / rolling radius
        a_hertz = abs(rad @ c.normal) / np.linalg.norm(rad) / c.rolling_radius
        b_hertz = rail.curvature(c.y_rail) - wheel.curvature(c.y_wheel)
        assert gxx == pytest.approx(a_hertz, rel=2e-3)
        assert gyy == pytest.approx(b_hertz, rel=2e-3, abs=2e-3)


def test_gap_field_cylinder_on_arc():
    """Cylinder wheel (r = 0.46) on a R300 rail: gap = x^2/(2 r) + y^2/(2 R) + higher order."""
    ys = np.linspace(-0.075, 0.06, 271)
    wheel = P.Profile(ys, 0.028 * np.clip(-(ys + 0.045) / 0.025, 0, None) ** 2, kind="wheel")
    yr = np.linspace(-0.03, 0.03, 601)
    rail = P.Profile(yr, 0.3 - np.sqrt(0.09 - yr**2), kind="rail")
    c = G.contact_points(wheel, rail, 0.0, track=G.TrackLayout(gauge_depth=0.001)).left[0]
    assert c.contact_angle == pytest.approx(0.0, abs=1e-9)
    f = G.gap_field(wheel, rail, c, 5e-4, 5e-4, 11, 11)
    X, Y = np.meshgrid(f.x, f.y, indexing="ij")
    exact_x = 0.46 - np.sqrt(0.46**2 - X**2)
    exact_y = 0.3 - np.sqrt(0.09 - Y**2)
    assert np.allclose(f.gap, exact_x + exact_y, atol=1e-10)


def test_creepages_small_angle(pair):
    c = G.contact_points(*pair, 0.002, yaw=0.004).left[0]
    r0, v, d = 0.46, 2.0, c.contact_angle
    # pure yaw: the slip lies in the tangent plane: eta = -yaw / cos(delta)
    cr = G.creepages(c, v)
    assert cr.xi == pytest.approx(1 - c.rolling_radius / r0, abs=2e-5)
    assert cr.eta == pytest.approx(-0.004 / np.cos(d), abs=2e-5)
    assert cr.phi == pytest.approx(-np.sin(d) / r0, rel=2e-3)
    # lateral velocity adds its tangential part; yaw rate adds -yaw_rate * arm longitudinally and spin
    cr2 = G.creepages(c, v, lateral_velocity=0.01, yaw_rate=0.1)
    arm = c.position[1] - c.pose.y
    lead = c.position[0] - c.pose.centre[0]
    assert cr2.xi - cr.xi == pytest.approx(-0.1 * arm / v, rel=1e-6)
    assert cr2.eta - cr.eta == pytest.approx((0.01 + 0.1 * lead) * np.cos(d) / v, rel=1e-6)
    assert cr2.phi - cr.phi == pytest.approx(0.1 * np.cos(d) / v, rel=1e-6)
    pure = G.creepages(c, v, angular_velocity=v / c.rolling_radius)
    assert pure.xi == pytest.approx(0.0, abs=2e-5)


def test_equivalent_conicity(pair):
    # a pure cone wheel on a knife-edge-like rail: Delta-r = 2 * 0.05 * y -> conicity 0.05
    ys = np.linspace(-0.075, 0.06, 271)
    cone = P.Profile(ys, -0.05 * ys + 0.028 * np.clip(-(ys + 0.045) / 0.025, 0, None) ** 2, kind="wheel")
    # a sharp rail head (R5 crown, 1:1.3 flanks) so that the contact stays near its crown
    yr = np.linspace(-0.015, 0.015, 601)
    ye = np.clip(yr, -0.003, 0.003)
    zr = 0.005 - np.sqrt(0.005**2 - ye**2) + (np.abs(yr) - np.abs(ye)) * 0.003 / np.sqrt(0.005**2 - 0.003**2)
    rail = P.Profile(yr, zr, kind="rail")
    t = G.geometry_table(cone, rail, np.linspace(-0.004, 0.004, 41), track=G.TrackLayout(gauge_depth=0.001))
    # rigid kinematics: the roll moves the wheel's contact point by r0 * roll, so
    # Delta-r = 2 lambda y (1 + r0 lambda / b)
    assert G.equivalent_conicity(t, 0.003) == pytest.approx(0.05 * (1 + 0.46 * 0.05 / 0.75), rel=5e-3)
    assert G.klingel_wavelength(0.05) == pytest.approx(2 * np.pi * np.sqrt(0.46 * 0.75 / 0.05))
    with pytest.raises(InputError, match="cover"):
        G.equivalent_conicity(t, 0.005)


@pytest.mark.parametrize(
    "kw, word",
    [
        (dict(y=np.nan), "y"),
        (dict(y=0.1), "50 mm"),
        (dict(y=0.0, yaw=0.5), "yaw"),
        (dict(y=[0.0, 0.001], yaw=[0.0, 0.0, 0.0]), "yaw"),
    ],
)
def test_bad_positions(pair, kw, word):
    with pytest.raises(InputError, match=word):
        G.geometry_table(*pair, **kw)


def test_bad_profiles_and_grid(pair):
    wheel, rail = pair
    with pytest.raises(InputError, match="rail profile"):
        G.geometry_table(rail, rail, [0.0])
    c = G.contact_points(wheel, rail, 0.0).left[0]
    with pytest.raises(InputError, match="dx"):
        G.gap_field(wheel, rail, c, 0.0, 1e-4, 10, 10)
    with pytest.raises(InputError, match="same wheel"):
        G.gap_field(P.s1002(), rail, c, 1e-4, 1e-4, 10, 10)
    with pytest.raises(InputError, match="speed"):
        G.creepages(c, -1.0)


def test_deck_case_runs():
    from railvti.casetypes import REGISTRY
    import railvti.geometry.cases  # noqa: F401

    ct = REGISTRY["geometry_table"]
    params = dict(ct.defaults)
    params.update(n=41)
    out = ct.run(params)
    assert out.datasets["delta_r"][0].shape == (41,)
    assert 0.1 < out.scalars["equivalent_conicity"][0] < 0.3
    with pytest.raises(InputError):
        ct.run({**params, "wheel": "nonexistent.txt"})


def test_deck_layout_defaults_are_the_class_defaults():
    """One back-to-back (and gauge, radius) default: the decks' mm keys repeat the classes'."""
    from railvti.casetypes import REGISTRY
    from railvti.runner.deck_registry import case_types
    from railvti.geometry.cases import deck_layout

    case_types()
    for name in ("geometry_table", "loaded_wheelset"):
        track, ws = deck_layout(REGISTRY[name].defaults)
        assert track == G.TrackLayout() and ws == WheelsetGeometry(), name
