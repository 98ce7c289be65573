"""The loaded wheelset: load control per wheel, mirror symmetry, flange contact, bad input."""
import dataclasses

import numpy as np
import pytest

from railvti import STEEL, InputError, profiles
from railvti.contact.wheelset import solve_wheelset
from railvti.geometry import gap_field

WHEEL = profiles.s1002()
RAIL = profiles.uic60()
FZ = 1.0e4


def _vertical(patches):
    return sum(p.fn * p.contact.normal[2] for p in patches)


@pytest.mark.parametrize("y_mm", [0.0, 3.0, 8.0])
def test_load_control_per_wheel(y_mm):
    """Each wheel's vertical load (normal forces) equals the prescribed one within 0.1 %
    (the solver's tolerance is 1e-5), including flange contact at 8 mm."""
    s = solve_wheelset(WHEEL, RAIL, y_mm * 1e-3, 2.4e-3 * y_mm, (FZ, 0.8 * FZ), None, None, STEEL, 4e-4)
    assert abs(_vertical(s.left) / FZ - 1) < 1e-3
    assert abs(_vertical(s.right) / (0.8 * FZ) - 1) < 1e-3
    assert s.fz[0] == pytest.approx(_vertical(s.left), rel=1e-12)
    for p in s.patches:
        assert (p.pressure >= 0).all() and p.n_contact > 0
        # the contact area stays inside the patch's grid
        assert not p.pressure[[0, -1], :].any() and not p.pressure[:, [0, -1]].any()


def test_mirror_symmetry():
    """Shifts of +y and -y (no yaw) give the same patches with the wheels swapped."""
    a = solve_wheelset(WHEEL, RAIL, 4e-3, 0.0, FZ, None, None, STEEL, 4e-4)
    b = solve_wheelset(WHEEL, RAIL, -4e-3, 0.0, FZ, None, None, STEEL, 4e-4)
    for pa, pb in ((a.left[0], b.right[0]), (a.right[0], b.left[0])):
        assert pa.contact_angle == pytest.approx(pb.contact_angle, abs=1e-6)
        assert pa.fn == pytest.approx(pb.fn, rel=1e-4)
        assert pa.pmax == pytest.approx(pb.pmax, rel=1e-3)
        # lateral track force mirrors, vertical is the same
        assert pa.force_track[1] == pytest.approx(-pb.force_track[1], rel=1e-3, abs=1.0)
        assert pa.force_track[2] == pytest.approx(pb.force_track[2], rel=1e-4)
    assert a.roll == pytest.approx(-b.roll, rel=1e-2)


def test_flange_contact_pushes_wheel_back():
    """At 8 mm to the left the left wheel runs on its flange (contact angle near 1 rad):
    the normal force is much larger than the load and pushes the wheelset to the right."""
    s = solve_wheelset(WHEEL, RAIL, 8e-3, 0.0, FZ, None, None, STEEL, 4e-4)
    flange = s.left[0]
    assert flange.contact_angle > 0.8
    assert flange.fn > 1.3 * FZ
    assert flange.force_track[1] < -0.5 * FZ
    assert s.geometry.status[0] in ("ok", "flange climb")


@pytest.mark.parametrize("y_mm, fz_right", [(3.0, 0.6 * FZ), (8.0, FZ)])
def test_patch_approach_follows_shared_motion(y_mm, fz_right):
    """Each patch's approach is the closure of the rigid gap that the solved sink and roll
    produce, computed independently: the wheel surface of the moved pose (height - sink,
    roll + roll) intersected along the contact normal by the geometry module (exact 3-D
    surface of revolution, no linearisation). Unequal loads and flange contact (8 mm,
    contact angle ~1 rad) make the roll part of the motion large in some patch."""
    s = solve_wheelset(WHEEL, RAIL, y_mm * 1e-3, 0.0, (FZ, fz_right), None, None, STEEL, 4e-4)
    pose = s.geometry.pose
    moved = dataclasses.replace(pose, z=pose.z - s.sink, roll=pose.roll + s.roll)

    def gap_at_point(cp):
        return gap_field(WHEEL, RAIL, cp, 1e-4, 1e-4, 1, 1, x0=0.0, y0=0.0).gap[0, 0]

    roll_share = 0.0
    for p in s.patches:
        closure = gap_at_point(p.contact) - gap_at_point(dataclasses.replace(p.contact, pose=moved))
        # second-order terms of the finite motion: 1e-4 on the tread, 1e-2 on the steep flange
        rel = 1e-4 if p.contact_angle < 0.5 else 1e-2
        assert p.approach == pytest.approx(closure, rel=rel)
        # the roll's own share of the closure (sink alone: n_z * sink)
        roll_share = max(roll_share, abs(closure - p.contact.normal[2] * s.sink) / p.approach)
    assert roll_share > 0.1   # a wrong roll lever arm would fail the check above


@pytest.mark.parametrize("kwargs, word", [
    (dict(fz=-1.0), "fz"), (dict(y=float("nan")), "y"), (dict(dx=0.0), "dx"),
    (dict(mu=0.3), "speed"), (dict(fz=(1.0, 2.0, 3.0)), "fz"),
])
def test_bad_input(kwargs, word):
    args = dict(y=0.0, yaw=0.0, fz=FZ, mu=None, speed=None, dx=4e-4)
    args.update(kwargs)
    with pytest.raises(InputError, match=word):
        solve_wheelset(WHEEL, RAIL, args["y"], args["yaw"], args["fz"], args["mu"], args["speed"], STEEL,
                       args["dx"])


def test_deck_case_normal_sweep(tmp_path):
    """The loaded_wheelset deck type: arrays per position/wheel/patch, flange contact found,
    fields stored and plotted."""
    from railvti.casetypes import REGISTRY
    import railvti.contact.wheelset_cases  # noqa: F401
    ct = REGISTRY["loaded_wheelset"]
    params = dict(ct.defaults)
    params.update(n=3, y_max_mm=8.0, mu=0.0, dx_mm=0.5, field_at_mm=8.0)
    out = ct.run(params)
    fn = out.datasets["fn"][0]
    assert fn.shape == (3, 2, 2)
    ang = out.datasets["contact_angle"][0]
    assert ang[0, 0, 0] == pytest.approx(ang[0, 1, 0], abs=1e-6)   # centred: both wheels alike
    assert np.nanmax(ang[-1, 0]) > 0.8                               # flange at 8 mm
    assert "field_left0_pressure" in out.datasets
    with pytest.raises(InputError):
        ct.run({**params, "dx_mm": -1.0})


def test_rolling_patches_bounded_and_consistent():
    """With friction and speed every loaded patch gets tractions: its creep force is at most
    mu Fn, equals the sum of the tractions, and the track-frame force projects back on the
    contact frame."""
    mu = 0.3
    s = solve_wheelset(WHEEL, RAIL, 3e-3, 7.2e-3, FZ, mu, 2.0, STEEL, 4e-4)
    for p in s.patches:
        area = p.grid.dx * p.grid.dy
        assert np.hypot(p.fx, p.fy) <= mu * p.fn * (1 + 1e-8)
        assert p.fx == pytest.approx(p.tx.sum() * area, rel=1e-9, abs=1e-6)
        assert p.fy == pytest.approx(p.ty.sum() * area, rel=1e-9, abs=1e-6)
        f = p.force_track
        assert f @ p.contact.normal == pytest.approx(p.fn, rel=1e-12)
        assert f @ p.contact.t_y == pytest.approx(p.fy, rel=1e-9, abs=1e-6)
        assert p.rolling.converged
    # yaw 7.2 mrad: lateral creepage eta ~ -yaw on both wheels, lateral creep forces push left
    assert all(p.creepage.eta < 0 and p.fy > 0 for p in s.patches)
