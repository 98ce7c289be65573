"""Model RF: the coach's rigid wheelsets on the flexible ring track (railvti.vehicle.ring_coupling).

Checks against independent paths: the ring's own head shapes (RingTrack.head_shapes through the
vehicle-frame helper wheel_head_shapes), the ring's modal static solution under the same eight
loads, a moving constant load against the quasi-static deflection, and model RR on rigid
ground for a nearly rigid ring. Small rings (coarse section mesh), few modes.
"""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.track import RingTrack
from railvti.track.coupling import wheel_head_shapes
from railvti.vehicle.assembly import build_coach, build_rigid_system
from railvti.vehicle.model import ModalBlocks, PointElement
from railvti.vehicle.params import Coach
from railvti.vehicle.ring_coupling import RingSystem, build_rf, ring_rows
from railvti.vehicle.equilibrium import lateral_disturbance, static_equilibrium
from railvti.vehicle.simulate import simulate
from coarse_ring import COARSE

V = 200.0 / 3.6


@pytest.fixture(scope="module")
def ring():
    return RingTrack(40, **COARSE)


@pytest.fixture(scope="module")
def table():
    return scenarios.wheel_table()


def _crown_z(d: np.ndarray, half: float) -> np.ndarray:
    """Crown vertical displacement from the element pose (z - y_p roll with y_p = +-half)."""
    return d[..., 1, :, :] + np.array([half, -half])[:, None] * d[..., 2, :, :]


def test_rows_match_ring_head_shapes(ring):
    """The packed rows (numpy evaluation of the Fortran loop's sums) against the ring's own
    head shapes under each wheel (RingTrack.head_shapes, the vehicle's frame by the mirror
    helper), mapped onto the element pose; at two times, all modes."""
    xw = np.array([10.78, 8.22, -8.22, -10.78])
    rr = ring_rows(ring, xw, V, x_offset=0.3)
    half = 0.5 * ring.params["rail_distance"]
    for t in (0.0, 0.0137):
        rows = rr.rows(t)[0]
        for w in range(4):
            for k in range(2):
                h = wheel_head_shapes(ring, 0.3 + xw[w] + V * t, k)[:, rr.modes]
                yp = half if k == 0 else -half
                want = np.stack([h[1], h[2] - yp * h[3], h[3]])
                got = rows[:, 2 * w + k]
                assert np.allclose(got, want, rtol=0, atol=1e-9 * np.abs(want).max())


def test_displacement_in_blocks_matches_rows(ring):
    """RingRows.displacement (the history's rail motion without the rows, evaluated in blocks
    of DISPLACEMENT_BLOCK times to bound its memory) against rows(t) @ qm at each time, over
    2.5 blocks of random modal coordinates."""
    from railvti.vehicle.ring_coupling import DISPLACEMENT_BLOCK

    xw = np.array([10.78, 8.22, -8.22, -10.78])
    rr = ring_rows(ring, xw, V, x_offset=0.3, f_limit=300.0)
    nt = int(2.5 * DISPLACEMENT_BLOCK)
    t = np.linspace(0.0, 0.05, nt)
    qm = np.random.default_rng(3).standard_normal((nt, rr.n_modes))
    got = rr.displacement(t, qm)
    want = np.einsum("tipk,tk->tip", rr.rows(t), qm)
    assert np.allclose(got, want, rtol=0, atol=1e-10 * np.abs(want).max())


def test_static_deflection_against_ring_solution(ring, table):
    """RF's static equilibrium (all ring modes kept): the rail deflection under each wheel
    against the ring's modal static solution for the eight wheel loads (vertical and lateral
    forces from the contact outputs; the contact moment about the crown is left out: 0.3 %)."""
    sy = build_rf(Coach(), table, V, ring, f_limit=None)
    q, _ = static_equilibrium(sy, V)
    d = sy.rail_deflection(np.zeros(1), q[None])[0]
    half = 0.5 * ring.params["rail_distance"]
    uz = _crown_z(d, half)
    from railvti.vehicle.equilibrium import call_settings

    _, wo, info = sy.native.state_force(call_settings(V, "hertz-kalker", 8, None), q, np.zeros_like(q))
    assert info == 0
    qv, yv = wo[0], wo[1]
    hs = {(k, w): wheel_head_shapes(ring, sy.x_wheelsets[w], k) for w in range(4) for k in range(2)}
    fm = sum(-qv[k, w] * hs[k, w][2] - yv[k, w] * hs[k, w][1] for (k, w) in hs)
    qm = fm / ring.lam
    ref = np.array([[hs[k, w][2] @ qm for w in range(4)] for k in range(2)])
    assert np.all(uz < -1e-4)
    np.testing.assert_allclose(uz, ref, rtol=0.01)
    # the wheel loads carry the coach's weight
    assert abs(qv.sum() / (8 * sy.wheel_load) - 1) < 1e-3


def test_residual_flexibility_restores_static_deflection(ring, table):
    """Modes up to 300 Hz (184 of 2260): without the residual flexibility the static crown
    deflection under the wheels is a third short; with it (the truncated modes' compliance at
    each contact point, tabulated over a bay) within 1 % of the all-mode state."""
    half = 0.5 * ring.params["rail_distance"]
    uz = {}
    for key, fl, res in (("all", None, False), ("cut", 300.0, False), ("res", 300.0, True)):
        sy = build_rf(Coach(), table, V, ring, f_limit=fl, residual=res, x_offset=0.11)
        q, _ = static_equilibrium(sy, V)
        uz[key] = _crown_z(sy.rail_deflection(np.zeros(1), q[None])[0], half)
    assert np.all(np.abs(uz["cut"] / uz["all"] - 1) > 0.2)
    np.testing.assert_allclose(uz["res"], uz["all"], rtol=0.01)


def test_mirror_symmetric_static_state(ring, table):
    """Left wheels on rail 1, right on rail 2 with y -> -y: the centred static state is a
    mirror image (Q and the vertical deflection equal, lateral and roll opposite)."""
    sy = build_rf(Coach(), table, V, ring, f_limit=300.0, x_offset=0.17)
    q, _ = static_equilibrium(sy, V)
    d = sy.rail_deflection(np.zeros(1), q[None])[0]
    np.testing.assert_allclose(d[1, 0], d[1, 1], rtol=1e-6)
    np.testing.assert_allclose(d[0, 0], -d[0, 1], rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(d[2, 0], -d[2, 1], rtol=1e-6, atol=1e-12)
    assert np.all(d[1] < 0)
    for w in range(4):  # rigid wheelsets centred: no lateral shift or roll
        assert abs(q[sy.iws[0, w] - 1]) < 1e-7 and abs(q[sy.iws[2, w] - 1]) < 1e-7


def test_stiff_ring_reproduces_rigid_ground(ring, table):
    """A ring 10^6 times stiffer: RF's static state is RR's on rigid ground; a ring 100 times
    stiffer: the leading wheelset's lateral transient after a 3 mm shift follows RR's on rigid
    ground."""
    rr_sy = build_coach(Coach(), table, track=False)
    q_rr, _ = static_equilibrium(rr_sy, V)
    sy = build_rf(Coach(), table, V, ring, f_limit=300.0, stiffness_scale=1e6)
    q_rf, _ = static_equilibrium(sy, V)
    assert np.max(np.abs(q_rf[: rr_sy.n] - q_rr)) < 1e-8
    sy = build_rf(Coach(), table, V, ring, f_limit=300.0, stiffness_scale=100.0)
    q_rf, _ = static_equilibrium(sy, V)
    h = 1e-4
    a = simulate(
        rr_sy,
        V,
        0.15,
        h=h,
        q0=lateral_disturbance(rr_sy, q_rr, 0.003, wheelsets=(0,)),
        output_dt=1e-3,
        progress=False,
    )
    b = simulate(
        sy,
        V,
        0.15,
        h=h,
        q0=lateral_disturbance(sy, q_rf, 0.003, wheelsets=(0,)),
        output_dt=1e-3,
        progress=False,
    )
    assert abs(a.y_ws1).max() > 1e-3
    print(
        "y err",
        np.max(np.abs(a.y_ws1 - b.y_ws1)) / np.abs(a.y_ws1).max(),
        "Q mean err",
        np.max(np.abs(b.Q.mean(0) / a.Q.mean(0) - 1)),
        "Y mean err",
        np.max(np.abs(b.Y.mean(0) - a.Y.mean(0))) / np.abs(a.Y).max(),
    )
    assert np.max(np.abs(a.y_ws1 - b.y_ws1)) < 0.01 * np.abs(a.y_ws1).max()
    # the wheel forces averaged over the transient (the wheels' vertical vibration on the
    # contact spring differs: the stiff ring still has its mass)
    np.testing.assert_allclose(b.Q.mean(0), a.Q.mean(0), rtol=0.005)
    assert np.max(np.abs(b.Y.mean(0) - a.Y.mean(0))) < 0.02 * np.abs(a.Y).max()


def _moving_load_system(track, speed, load):
    """One constant vertical force on rail 1's crown moving at speed (point elements with a
    preload on the pose of the element under wheel 0: z gets the force, roll its arm)."""
    rr = ring_rows(track, np.zeros(1), speed, f_limit=500.0, residual=False)
    om = np.sqrt(track.lam[rr.modes])
    half = 0.5 * track.params["rail_distance"]
    phi = rr.rows(0.0)[0].reshape(-1, rr.n_modes, order="F")
    mb = ModalBlocks.diagonal(om, track.cmod[rr.modes] / (2 * om), phi)
    mb = ModalBlocks(
        mb.damping,
        mb.stiffness,
        mb.phi,
        elements=(
            PointElement("linear", 1, None, (0.0, 0.0, load)),
            PointElement("linear", 2, None, (0.0, 0.0, half * load)),
        ),
    )
    base = build_rigid_system(np.eye(1), np.zeros((1, 1)), np.eye(1), modal=mb)
    return RingSystem(**{f: getattr(base, f) for f in base.__dataclass_fields__}, ring=rr), rr


@pytest.mark.parametrize("kmh, bays, rtol", [(5.0, 1, 1e-3), (200.0, 3, 0.03)])
def test_moving_load_follows_quasi_static_deflection(kmh, bays, rtol):
    """A constant 60 kN load moving over an 8-sleeper ring: the crown deflection under it
    against the ring's static solution at the load's position (RingTrack.head_shapes, the kept
    modes), which varies between sleeper and midspan. 5 km/h: quasi-static (< 0.1 %); 200
    km/h: within 3 %, and the fluctuation repeats at the sleeper-passing period a / v0."""
    track = RingTrack(8, **COARSE)
    v, load = kmh / 3.6, 60e3
    sy, rr = _moving_load_system(track, v, load)
    q0 = static_equilibrium(sy, v, return_velocity=True)[0]
    a = track.params["sleeper_spacing"]
    h = 5e-4 if kmh < 100 else 2.5e-4
    run = simulate(sy, v, bays * a / v, h=h, q0=q0, output_dt=h, progress=False)
    half = 0.5 * track.params["rail_distance"]
    d = sy.rail_deflection(run.t, run.q)
    uz = d[:, 1, 0, 0] + half * d[:, 2, 0, 0]
    ref = np.array(
        [-load * np.sum(track.head_shapes(v * t, 1)[2][rr.modes] ** 2 / track.lam[rr.modes]) for t in run.t]
    )
    assert ref.max() - ref.min() > 0.005 * abs(ref).max()  # sleeper vs midspan
    np.testing.assert_allclose(uz, ref, rtol=rtol)
    if kmh > 100:  # the last bay repeats the one before (period a / v0)
        n = int(round(a / v / h))
        np.testing.assert_allclose(uz[-n:], uz[-2 * n : -n], rtol=0.01)


def _all_mode_crown_z(track, sy, t, wheel):
    """The ring's static solution over all its modes under the eight wheel loads of a run
    output (Q, Y of the rail on each wheel: the rail carries -Q, -Y): the crown's vertical
    displacement under each wheel (2, nw), m."""
    nw = sy.x_wheelsets.size
    hs = {
        (k, w): wheel_head_shapes(track, sy.ring.cx0[2 * w + k] + sy.ring.speed * t, k)
        for w in range(nw)
        for k in range(2)
    }
    fm = sum(-wheel[0, k, w] * hs[k, w][2] - wheel[1, k, w] * hs[k, w][1] for (k, w) in hs)
    qm = fm / track.lam
    return np.array([[hs[k, w][2] @ qm for w in range(nw)] for k in range(2)])


def test_moving_coach_at_5_kmh_matches_ring_static_solution(ring, table):
    """Model RF as the scenarios build it (ring modes up to 300 Hz of 2260, residual
    flexibility at the contact points), the coach moving at 5 km/h over a bay and a half:
    the crown deflection under every wheel within 1 % of the ring's static solution over all
    its modes under the same wheel loads (the loads from the run), which differs by more than
    that between sleeper and midspan."""
    v = 5.0 / 3.6
    sy = build_rf(Coach(), table, v, ring, f_limit=300.0, x_offset=0.05)
    assert sy.ring.n_modes < 0.1 * ring.n_modes and sy.ring.n_residual == 24
    q0, v0, _ = static_equilibrium(sy, v, return_velocity=True)
    run = simulate(sy, v, 0.65, q0=q0, v0=v0, output_dt=0.02, progress=False)
    half = 0.5 * ring.params["rail_distance"]
    uz = _crown_z(sy.rail_deflection(run.t, run.q), half)  # (nt, 2, 4)
    ref = np.array([_all_mode_crown_z(ring, sy, t, run.wheel[i]) for i, t in enumerate(run.t)])
    assert np.all(ref < -1e-4)
    print(
        f"5 km/h: max |u_z / static - 1| = {np.max(np.abs(uz / ref - 1)):.2e}, "
        f"sleeper-midspan variation {np.ptp(ref[:, 0, 0]) / abs(ref[:, 0, 0]).mean():.3f}"
    )
    assert np.ptp(ref[:, 0, 0]) > 0.01 * abs(ref[:, 0, 0]).mean()  # sleeper against midspan
    np.testing.assert_allclose(uz, ref, rtol=0.01)


def test_deflection_under_wheel_at_sleeper_passing_frequency(ring, table):
    """Model RF at 200 km/h (modes up to 300 Hz and the residual flexibility): the crown
    deflection under the leading wheel oscillates at the sleeper-passing frequency v0 / a
    = 92.6 Hz: the peak of its spectrum (Hann window, zero-padded) within 1 %."""
    sy = build_rf(Coach(), table, V, ring, f_limit=300.0)
    q0, v0, _ = static_equilibrium(sy, V, return_velocity=True)
    h = 5e-4
    run = simulate(sy, V, 0.3, h=h, q0=q0, v0=v0, output_dt=h, progress=False)
    half = 0.5 * ring.params["rail_distance"]
    z = _crown_z(sy.rail_deflection(run.t, run.q), half)[run.t > 0.05, 0, 0]
    s = (z - z.mean()) * np.hanning(z.size)
    n = 16 * z.size
    f = np.fft.rfftfreq(n, h)
    a = np.abs(np.fft.rfft(s, n))
    band = (f > 20.0) & (f < 1000.0)
    peak = f[band][a[band].argmax()]
    f_sl = V / ring.params["sleeper_spacing"]
    print(
        f"deflection spectrum peak {peak:.2f} Hz, sleeper passing {f_sl:.2f} Hz, "
        f"peak-to-peak {np.ptp(z) * 1e6:.1f} um"
    )
    assert abs(peak / f_sl - 1) < 0.01
    assert np.ptp(z) > 0.01 * abs(z.mean())


def test_centred_running_rf(ring):
    """scenarios.centred_running(model='RF') on a small ring: wheel loads about the static
    load, the rail deflected under every wheel, mirror-symmetric."""
    tp = {k: v for k, v in COARSE.items()}
    c = scenarios.centred_running(
        200.0, variant="RF", duration=0.05, n_sleepers=40, f_limit=300.0, track_params=tp, progress=False
    )
    assert c.variant == "RF" and c.rail is not None
    assert np.max(np.abs(c.Q / c.static_wheel_load - 1)) < 0.03
    assert np.all(c.rail[:, 1] < 0)
    np.testing.assert_allclose(c.Q[0], c.Q[1], rtol=1e-6)


def test_rf_bad_input():
    with pytest.raises(InputError, match="too short"):
        scenarios.coach_system("RF", speed_kmh=200.0, n_sleepers=30)
    with pytest.raises(InputError, match="speed"):
        scenarios.coach_system("RF")
    with pytest.raises(InputError, match="RF"):
        scenarios.centred_running(200.0, variant="RR", n_sleepers=40)
    with pytest.raises(InputError, match="no ring mode"):
        ring_rows(RingTrack(8, **COARSE), np.zeros(1), V, f_limit=1.0)
    with pytest.raises(InputError, match="ring track"):
        scenarios.linear_critical_speed_kmh("RR", n_sleepers=40)
