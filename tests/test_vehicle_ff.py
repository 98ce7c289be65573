"""Model FF: the coach's flexible rotating wheelsets on the flexible ring track.

FF is model FR's system on rigid ground with the ring's modal block appended
(railvti.vehicle.ring_coupling.build_rf(base=...)). Checks against independent paths: a nearly
rigid ring against FR on rigid ground (the same wheelsets, no ring); the rims' camber against
model FR's and the rail deflection against model RF's (each body's own response to nearly the
same wheel loads); the mirror symmetry of the centred static state.
"""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.vehicle.bifurcation import SweepSystems
from railvti.errors import InputError
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.flexible_points import rail_head_roll, rim_camber_change, rim_rail_angle_change
from railvti.vehicle.params import Coach
from railvti.vehicle.ring_coupling import build_rf
from railvti.vehicle.equilibrium import static_equilibrium
from railvti.vehicle.simulate import simulate
from coarse_ring import COARSE, RING

V = 200.0 / 3.6


@pytest.fixture(scope="module")
def fr_ground():
    """FR on rigid ground (no track elements), k_max 1, modes up to 300 Hz."""
    return build_fr(
        Coach(), scenarios.wheel_table(), V, wheelset=systems.fr_wheelset(), k_max=1, f_max=300.0, track=False
    )


def test_stiff_ring_reproduces_fr_on_rigid_ground(fr_ground):
    """A ring 1e6 times stiffer under FR's wheelsets: the static state of the coach and of the
    wheelsets' modes is FR's on rigid ground (the ring deflects by ~1e-10 m)."""
    base, _ = fr_ground
    ring = systems.ring_track(40, COARSE)
    ff = build_rf(Coach(), scenarios.wheel_table(), V, ring, f_limit=300.0, stiffness_scale=1e6, base=base)
    q_fr, _ = static_equilibrium(base, V, "hertz-kalker")
    q_ff, _ = static_equilibrium(ff, V, "hertz-kalker")
    n = base.n_state
    assert ff.n_state > n and ff.state_names[:n] == base.state_names
    scale = np.maximum(np.abs(q_fr), 1e-3 * np.abs(q_fr).max())
    assert np.max(np.abs(q_ff[:n] - q_fr) / scale) < 1e-3
    rail = ff.rail_deflection(np.zeros(1), q_ff[None])[0]
    assert np.max(np.abs(rail)) < 1e-8


def test_ff_static_state_against_fr_and_rf(fr_ground):
    """FF's centred static state: the rims' camber within 5 % of model FR's (on rigid ground:
    the wheelsets answer nearly the same loads), mirror-symmetric left/right; with the rims'
    rows set to zero (the wheelsets' modes decoupled) the ring's deflection is model RF's to
    round-off. (With the rims coupled the rail rolls about twice as much as in RF: the rims'
    lateral bending moves each wheel by ~0.2 mm, where the S1002/UIC60 contact point moves
    by millimetres across the rail head, and with it the rail's roll moment.)"""
    base, _ = fr_ground
    ff, _ = scenarios.ff_system(speed=V, k_max=1, f_max=300.0, geometry="table", **RING)
    q_ff, _ = static_equilibrium(ff, V, "hertz-kalker")
    q_fr, _ = static_equilibrium(base, V, "hertz-kalker")
    cam_ff = rim_camber_change(ff, q_ff)
    cam_fr = rim_camber_change(base, q_fr)
    assert np.all(cam_fr > 0)
    np.testing.assert_allclose(cam_ff, cam_fr, rtol=0.05)
    np.testing.assert_allclose(cam_ff[0], cam_ff[1], rtol=1e-5)
    tab = scenarios.wheel_table()
    off, _ = build_fr(
        Coach(), tab, V, wheelset=systems.fr_wheelset(), k_max=1, f_max=300.0, track=False, zero_rows=True
    )
    ring = systems.ring_track(40, COARSE)
    ff0 = build_rf(Coach(), tab, V, ring, f_limit=300.0, base=off)
    rf = scenarios.rf_system(speed=V, geometry="table", **RING)
    q0, _ = static_equilibrium(ff0, V, "hertz-kalker")
    q_rf, _ = static_equilibrium(rf, V, "hertz-kalker")
    d0 = ff0.rail_deflection(np.zeros(1), q0[None])[0]
    d_rf = rf.rail_deflection(np.zeros(1), q_rf[None])[0]
    assert np.all(d_rf[1] < 0)
    np.testing.assert_allclose(d0, d_rf, rtol=1e-6, atol=1e-6 * np.abs(d_rf).max())


def test_ff_centred_running():
    """A short centred run of FF at 200 km/h: Q within 3 % of the static wheel load, the
    rims' camber positive (the paper: +1 mrad from axle bending), the rails pressed down.
    The rim-rail relative angle is the camber minus the rail head's roll read from the ring
    (RingSystem.rail_deflection's roll under each wheel, -roll on the left rail, +roll on the
    right: the inner edge rising) to round-off, and left and right mirror each other."""
    c = scenarios.centred_running(200.0, "FF", "hertz-fastsim", duration=0.05, k_max=1, f_max=300.0, **RING)
    assert c.variant == "FF" and c.rim_angle is not None and c.rail is not None
    assert c.q_error < 0.03
    assert np.all(c.rim_camber > 0)
    assert np.all(c.rail[:, 1] < 0)
    roll = c.rail[-1, 2] * np.array([-1.0, 1.0])[:, None]
    assert np.max(np.abs(roll)) > 1e-5  # the head rolls: not the rigid-rail limit
    np.testing.assert_allclose(c.rail_roll, roll, rtol=0, atol=1e-15)
    np.testing.assert_allclose(c.rim_angle, c.rim_camber - roll, rtol=0, atol=1e-15)
    # mirror symmetry of centred running: the left wheel's angles are the right one's
    for a in (c.rim_camber, c.rail_roll, c.rim_angle):
        np.testing.assert_allclose(a[0], a[1], rtol=0, atol=1e-3 * np.abs(c.rim_camber).max())


def test_rail_head_roll_needs_the_time(fr_ground):
    """On the ring track the rail head's roll needs the states' times (the contact points
    move along the ring): a clear error naming the key; FR's rigid rail does not roll."""
    base, _ = fr_ground
    ff, _ = scenarios.ff_system(speed=V, k_max=1, f_max=300.0, geometry="table", **RING)
    x = np.zeros(ff.n_state)
    with pytest.raises(InputError, match="'t'"):
        rail_head_roll(ff, x)
    with pytest.raises(InputError, match="'t'"):
        rim_rail_angle_change(ff, np.zeros((3, ff.n_state)), np.zeros(2))
    assert not np.any(rail_head_roll(base, np.ones(base.n_state)))


@pytest.mark.filterwarnings("ignore:bifurcation")
def test_ring_bifurcation_below_the_critical_speed():
    """A ring-track sweep (model RF, continuation down from 200 km/h): centred running is
    stable there (RR's linear critical speed is far above), so the disturbance decays along
    the carried branch (each speed's amplitude below the one above it, all below y_large) and
    the small one too; the step of every speed is reported."""
    b = scenarios.bifurcation(
        [200.0, 180.0],
        variant="RF",
        contact="hertz-kalker",
        duration=0.6,
        y_large=0.003,
        y_small=0.0005,
        progress=False,
        v_min_kmh=180.0,
        **RING,
    )
    up = b.upper[::-1]  # from 200 km/h down
    assert np.all(up < 0.003) and np.all(np.diff(up) < 0)
    assert np.all(b.decay < 0.0005)
    assert b.details["h"].size == b.speeds_kmh.size


def test_ring_continuation_carries_the_rail_under_the_wheels():
    """The upper branch's next run starts its contact points where the previous run's
    ended (``SweepSystems.upper_at``, speeds in m/s): the rail deflection under every wheel at
    the start of the run at 180 km/h, from the carried state, equals the one at the end of the run at
    200 km/h (an independent path: the same ring state read through the other speed's rows
    at its own time), to 1e-9 of the static deflection; the restart from x_offset, as the
    continuation did before, misses it by the sleeper-passing fluctuation."""
    sw = SweepSystems(
        "RF", None, "hertz-kalker", None, scenarios.FR_K_MAX, scenarios.FR_F_MAX, "table", dict(RING)
    )
    v200, v180 = 200.0 / 3.6, 180.0 / 3.6
    a, _, h = sw.at(v200)
    qs, _ = static_equilibrium(a, v200, "hertz-kalker")
    r = simulate(a, v200, 0.05, h=h, q0=qs, output_dt=0.05, progress=False)
    end = a.rail_deflection(r.t[-1:], r.q[-1:])[0]
    travel = v200 * float(r.t[-1])
    q, _, _ = sw.carry(r.q[-1], r.v[-1], v200, v180, lambda: None)
    b = sw.upper_at(v180, travel)[0]
    start = b.rail_deflection(np.zeros(1), q[None])[0]
    scale = np.abs(end[1]).max()  # vertical, m
    assert scale > 1e-5
    np.testing.assert_allclose(start, end, rtol=0, atol=1e-9 * scale)
    c = sw.at(v180)[0]  # the contact points back at x_offset
    assert np.abs(c.rail_deflection(np.zeros(1), q[None])[0] - end).max() > 1e-3 * scale


def test_ff_and_ring_bad_input():
    with pytest.raises(InputError, match="too short"):
        scenarios.coach_system("FF", speed_kmh=200.0, n_sleepers=30)
    with pytest.raises(InputError, match="k_max"):
        scenarios.coach_system("RF", speed_kmh=200.0, k_max=1)
    with pytest.raises(InputError, match="ring track"):
        scenarios.bifurcation([300.0, 280.0], variant="FR", n_sleepers=40, progress=False)
    with pytest.raises(InputError, match="unknown keyword"):
        scenarios.bifurcation([300.0, 280.0], variant="RF", sleepers=40, progress=False)
    with pytest.raises(InputError, match="f_limit"):
        scenarios.critical_speed("FF", method="linear", f_limit=-1.0)


def test_massive_residual_keeps_the_static_deflection():
    """The ring's residual coordinates with a mass (residual_hz) keep the massless residual's
    static compliance: the rail deflection under every wheel in the static state is the same
    to 1e-6, and the blocks' natural frequency is residual_hz (what the default step then
    resolves)."""
    a = scenarios.rf_system(speed=V, **RING)
    b = scenarios.rf_system(speed=V, ring_residual_hz=1500.0, **RING)
    assert a.modal.massless is not None and b.modal.massless is None
    np.testing.assert_allclose(b.modal.max_frequency() / (2 * np.pi), 1500.0, rtol=1e-12)
    qa, _ = static_equilibrium(a, V, "hertz-kalker")
    qb, _ = static_equilibrium(b, V, "hertz-kalker")
    da = a.rail_deflection(np.zeros(1), qa[None])[0]
    db = b.rail_deflection(np.zeros(1), qb[None])[0]
    np.testing.assert_allclose(db, da, rtol=0, atol=1e-6 * np.abs(da).max())
    with pytest.raises(InputError, match="residual_hz"):
        scenarios.rf_system(speed=V, ring_residual_hz=-1.0, **RING)
