"""The vehicle's wheels on the ring's rails: rail index and the y -> -y map between the frames."""

import numpy as np
import pytest

from railvti.errors import InputError
from railvti.track import RingTrack
from railvti.track.coupling import rail_of_wheel, wheel_head_shapes
from coarse_ring import COARSE_SECTION as COARSE


@pytest.fixture(scope="module")
def ring8():
    return RingTrack(8, **COARSE)


def _compliance(track, x, side):
    h = wheel_head_shapes(track, x, side)
    return (h / track.lam) @ h.T


def test_left_wheel_runs_on_rail_1_with_y_reversed():
    for side in (0, "left"):
        m = rail_of_wheel(side)
        assert m.rail == 1 and m.lateral_sign == -1.0
    assert rail_of_wheel("right").rail == 2 and rail_of_wheel(1).rail == 2
    m = rail_of_wheel("left")
    v = np.array([1.0, 2.0, 3.0, 4.0])
    assert np.array_equal(m.to_ring(v), [1.0, -2.0, 3.0, -4.0])
    assert np.array_equal(m.to_vehicle(m.to_ring(v)), v)


def test_wheel_loads_move_their_rail_the_physical_way(ring8):
    """Independent of the code's conventions, from the physics of a rail on its pads, in the
    vehicle's frame (y to the left, roll about x from y towards z): a wheel pushing its rail
    outwards (left wheel +y, right wheel -y) moves the head outwards and tilts the rail
    outwards about its foot (the head moves further than the foot: left rail roll < 0, right
    rail roll > 0); a downward load moves the head down on either rail. The left wheel's
    head is at y = +d/2 in the vehicle's frame (rail 1 at y = -d/2 in the ring's)."""
    for side, out in (("left", 1.0), ("right", -1.0)):
        g = _compliance(ring8, 0.13, side)
        u = g @ np.array([0.0, out * 1e4, 0.0, 0.0])
        assert u[1] * out > 0
        assert u[3] * out < 0
        u = g @ np.array([0.0, 0.0, -1e5, 0.0])
        assert u[2] < 0
    y0 = ring8._geom[0]
    assert y0[rail_of_wheel("left").rail - 1] * rail_of_wheel("left").lateral_sign > 0


def test_wheels_mirror_each_other_in_the_vehicle_frame(ring8):
    """The vehicle's own mirror (y -> -y about its centre plane) maps the left wheel onto the
    right one: the left wheel's head compliance in the vehicle's frame is the right wheel's with
    the lateral and roll rows and columns flipped, every entry, at several x."""
    flip = np.diag([1.0, -1.0, 1.0, -1.0])
    for x in (0.0, 0.2, 0.45):
        gl, gr = _compliance(ring8, x, "left"), _compliance(ring8, x, 1)
        assert np.abs(gl - flip @ gr @ flip).max() < 1e-8 * np.abs(gl).max()
        # not symmetric without the flip: the lateral-vertical and lateral-roll couplings
        assert np.abs(gl - gr).max() > 1e-3 * np.abs(gl).max()


@pytest.mark.parametrize("side", [2, -1, "middle", True, None])
def test_bad_side(side):
    with pytest.raises(InputError, match="side"):
        rail_of_wheel(side)


def test_contact_point_off_the_crown_maps_with_the_lateral_sign(ring8):
    """A point s to the left of the rail's axis in the vehicle's frame is at -s in the ring's
    section frame; the vehicle's mirror maps the left wheel at s onto the right wheel at -s."""
    flip = np.diag([1.0, -1.0, 1.0, -1.0])
    for s in (0.0, 0.015, -0.03):
        hl = wheel_head_shapes(ring8, 0.2, "left", s)
        assert np.array_equal(hl, flip @ ring8.head_shapes(0.2, 1, -s))
        hr = wheel_head_shapes(ring8, 0.2, "right", -s)
        gl, gr = (hl / ring8.lam) @ hl.T, (hr / ring8.lam) @ hr.T
        assert np.abs(gl - flip @ gr @ flip).max() < 1e-8 * np.abs(gl).max()
