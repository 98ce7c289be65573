"""The loaded wheelset: load control per wheel, mirror symmetry, flange contact, bad input."""

import dataclasses

import numpy as np
import pytest

from railvti import STEEL, InputError, Material, profiles
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
    assert roll_share > 0.1  # a wrong roll lever arm would fail the check above


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(fz=-1.0), "fz"),
        (dict(y=float("nan")), "y"),
        (dict(dx=0.0), "dx"),
        (dict(mu=0.3), "speed"),
        (dict(fz=(1.0, 2.0, 3.0)), "fz"),
    ],
)
def test_bad_input(kwargs, word):
    args = dict(y=0.0, yaw=0.0, fz=FZ, mu=None, speed=None, dx=4e-4)
    args.update(kwargs)
    with pytest.raises(InputError, match=word):
        solve_wheelset(
            WHEEL, RAIL, args["y"], args["yaw"], args["fz"], args["mu"], args["speed"], STEEL, args["dx"]
        )


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
    assert ang[0, 0, 0] == pytest.approx(ang[0, 1, 0], abs=1e-6)  # centred: both wheels alike
    assert np.nanmax(ang[-1, 0]) > 0.8  # flange at 8 mm
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


# --- full kinematics: prescribed omega and roll, free rolling, vertical balance with tangential forces

MB_WHEEL = profiles.read(profiles.example_path("MBench_S1002_v3.prw"))
MB_RAIL = profiles.read(profiles.example_path("MBench_UIC60_v3.prr"))
MAT = Material(shear_modulus=82e9, poisson=0.28)
# Manchester benchmark A-2.2 (inputs/mbench_a22_*.inp), railvti's frame: y, yaw to the left
A22 = {  # CONTACT's y_ws (mm, to the right): (roll rad, pitch velocity rad/s)
    3.0: (-0.00018030, -4.34515030),
    8.0: (-0.00860600, -4.25348570),
}


def _a22(y_mm, dx=4e-4, **kw):
    roll, vpitch = A22[y_mm]
    args = dict(roll=roll, omega=-vpitch)
    args.update(kw)
    return solve_wheelset(MB_WHEEL, MB_RAIL, -y_mm * 1e-3, -2.4e-3 * y_mm, FZ, 0.3, 2.0, MAT, dx, **args)


def _vertical_from_angle(p, side):
    """Fn cos(d) + s Fy sin(d): the vertical force from the contact angle alone."""
    s = 1.0 if side == "left" else -1.0
    return p.fn * np.cos(p.contact_angle) + s * p.fy * np.sin(p.contact_angle)


def test_flange_vertical_balance_with_tangential_forces():
    """A-2.2 at 8 mm (deck kinematics): the right wheel runs on its flange (contact angle > 0.9
    rad). Its load, 10 kN, equals Fn cos(d) + Fs sin(d) of its patches to 1e-5; the normal
    force alone would carry 20 % more or less: the lateral creep force carries load."""
    s = _a22(8.0)
    flange = s.right[0]
    assert flange.contact_angle > 0.9
    for side in ("left", "right"):
        fz = sum(_vertical_from_angle(p, side) for p in s.wheel(side))
        assert fz == pytest.approx(FZ, rel=1e-5)
        assert s.fz[("left", "right").index(side)] == pytest.approx(FZ, rel=1e-5)
    normal_only = flange.fn * np.cos(flange.contact_angle)
    assert abs(normal_only / FZ - 1) > 0.2
    assert abs(flange.fy) > 0.25 * flange.fn  # near saturation: |F_t| -> mu Fn
    assert np.hypot(flange.fx, flange.fy) <= 0.3 * flange.fn * (1 + 1e-8)


def test_prescribed_omega_gives_the_rigid_creepages():
    """No yaw, roll 0: xi = (V - omega r) / V_ref with V_ref = (V + omega r) / 2 (r the rolling
    radius of the contact point), eta = 0, phi = -+ omega sin(d) / V_ref (left/right)."""
    omega = 2.0 / 0.4601
    s = solve_wheelset(MB_WHEEL, MB_RAIL, 0.0, 0.0, FZ, 0.3, 2.0, MAT, 4e-4, roll=0.0, omega=omega)
    for p in s.patches:
        r = p.contact.rolling_radius
        v_ref = 0.5 * (2.0 + omega * r)
        sg = 1.0 if p.side == "left" else -1.0
        assert p.reference_speed == pytest.approx(v_ref, rel=1e-8)
        # (the point and its rolling radius are interpolated separately: ~1e-8 m)
        assert p.creepage.xi == pytest.approx((2.0 - omega * r) / v_ref, abs=1e-9)
        assert p.creepage.eta == pytest.approx(0.0, abs=1e-12)
        assert p.creepage.phi == pytest.approx(-sg * omega * np.sin(p.contact_angle) / v_ref, rel=1e-9)
    assert s.omega == omega and not s.free_rolling


def test_tread_forces_are_the_rolling_solution_at_the_prescribed_omega():
    """A-2.2 at 3 mm: each tread patch's forces equal an independent steady-rolling solve of
    its gap at its Fn with the creepages of the prescribed omega."""
    from railvti.contact import solve_rolling

    s = _a22(3.0)
    for p in s.patches:
        c = p.creepage
        ref = solve_rolling(p.gap, p.grid, MAT, 0.3, p.fn, (c.xi, c.eta, c.phi), p.reference_speed)
        assert p.fx == pytest.approx(ref.fx, rel=1e-5, abs=1e-3)
        assert p.fy == pytest.approx(ref.fy, rel=1e-5, abs=1e-3)
        assert p.n_contact == ref.n_contact


@pytest.mark.parametrize("y_mm", [3.0])
def test_free_rolling_matches_the_benchmark_pitch_velocity(y_mm):
    """Free rolling (no torque about the axle) at the benchmark's roll gives the pitch velocity
    that the A-2.2 decks prescribe (CONTACT's author found it from the same torque balance)
    to 1e-5, and the axle torque of the contact forces and moments vanishes."""
    roll, vpitch = A22[y_mm]
    s = solve_wheelset(MB_WHEEL, MB_RAIL, -y_mm * 1e-3, -2.4e-3 * y_mm, FZ, 0.3, 2.0, MAT, 2e-4, roll=roll)
    assert s.free_rolling
    assert s.omega == pytest.approx(-vpitch, rel=1e-5)
    scale = 0.3 * sum(p.fn * p.contact.rolling_radius for p in s.patches)
    assert abs(s.axle_torque) <= 1e-5 * scale
    # the torque recomputed from the patches' forces and moments (about their reference points)
    yaw = -2.4e-3 * y_mm
    a = np.array(
        [-np.sin(yaw) * np.cos(roll), np.cos(yaw) * np.cos(roll), np.sin(roll)]
    )  # Rz(yaw) Rx(roll) e_y
    t = 0.0
    for p in s.patches:
        c = p.contact.pose.centre - np.array([0.0, 0.0, s.sinks[("left", "right").index(p.side)]])
        t += a @ (np.cross(p.contact.position - c, p.force_track) + p.moment_track)
    assert abs(t) <= 1e-5 * scale


def test_half_wheelset_is_its_wheel_of_the_whole():
    """With the roll prescribed the wheels are independent half wheelsets: solving one side
    gives the same patch as solving both."""
    both = _a22(3.0, dx=5e-4)
    left = _a22(3.0, dx=5e-4, side="left")
    assert left.right == [] and np.isnan(left.fz[1])
    a, b = both.left[0], left.left[0]
    assert b.fn == pytest.approx(a.fn, rel=1e-9)
    assert b.fx == pytest.approx(a.fx, rel=1e-6)
    assert b.fy == pytest.approx(a.fy, rel=1e-6)


def test_grid_size_does_not_move_results(monkeypatch):
    """Element centres are anchored to the reference point: a larger grid (more margin
    around the contact area) gives the same forces to the solvers' tolerance."""
    import railvti.contact.wheelset as ws_mod
    import railvti.contact.wheelset_patch as patch_mod

    a = _a22(8.0, dx=5e-4)
    monkeypatch.setattr(patch_mod, "GROW", 2.0)
    monkeypatch.setattr(ws_mod, "GROW", 2.0)
    b = _a22(8.0, dx=5e-4)
    for pa, pb in zip(a.patches, b.patches):
        assert pb.grid.nx * pb.grid.ny > pa.grid.nx * pa.grid.ny
        assert pb.n_contact == pa.n_contact
        for q in ("fn", "fx", "fy"):
            assert getattr(pb, q) == pytest.approx(getattr(pa, q), rel=1e-6, abs=1e-3)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(omega=0.0), "omega"),
        (dict(omega=-4.3), "omega"),
        (dict(roll=float("nan")), "roll"),
        (dict(roll=0.2), "roll"),
        (dict(side="left"), "roll"),
        (dict(side="middle", roll=0.0), "side"),
        (dict(side="left", roll=0.0, omega=None), "free rolling"),
    ],
)
def test_bad_kinematics(kwargs, word):
    args = dict(omega=4.3)
    args.update(kwargs)
    with pytest.raises(InputError, match=word):
        solve_wheelset(WHEEL, RAIL, 0.0, 0.0, FZ, 0.3, 2.0, STEEL, 5e-4, **args)


def test_kinematics_without_rolling_is_refused():
    with pytest.raises(InputError, match="mu and speed"):
        solve_wheelset(WHEEL, RAIL, 0.0, 0.0, FZ, None, None, STEEL, 5e-4, omega=4.3)
