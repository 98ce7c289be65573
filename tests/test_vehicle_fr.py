"""Model FR: the coach with flexible wheelsets (railvti.vehicle.flexible), first coupled step.

Checks against independent references: the rigid model RR (decoupled modes), the wheelset's
own modal statics (FlexibleWheelset.static_deflection under the coupled model's point
forces), and the Hertz potential (the rims' generalised forces are its gradient).
"""

from dataclasses import replace

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.flexible_points import (
    attachment_deflection,
    attachment_loads,
    point_forces,
    rim_camber_change,
    rim_deformation,
    rim_rail_angle_change,
)
from railvti.vehicle.model import CallSettings, ModalBlocks
from railvti.vehicle.params import Coach, speed_m_s
from railvti.vehicle.contact_models import contact_id
from railvti.vehicle.equilibrium import static_equilibrium
from railvti.vehicle.simulate import simulate
from railvti.wheelset import Wheelset
from railvti.wheelset.statics import static_fe_solve

V = speed_m_s(200.0)


@pytest.fixture(scope="module")
def body():
    return Wheelset().flexible_body(V)


@pytest.fixture(scope="module")
def rr():
    sy = scenarios.coach_system("RR", geometry="table")  # build_fr's geometry
    q, v, _ = static_equilibrium(sy, V, "hertz-kalker", return_velocity=True)
    return sy, q, v


@pytest.fixture(scope="module")
def fr(body):
    sy, lay = build_fr(Coach(), scenarios.wheel_table(), V, body=body)
    q, v, _ = static_equilibrium(sy, V, "hertz-kalker", return_velocity=True)
    return sy, lay, q, v


def test_zero_rows_reproduce_rr(body, rr):
    """All attachment rows zero: the modes decouple and the coach runs exactly as RR (the
    same wheelset body and gyroscopic moments, railvti.vehicle.wheelset_body)."""
    sy_rr, q_rr, v_rr = rr
    sy, _ = build_fr(Coach(), scenarios.wheel_table(), V, body=body, zero_rows=True)
    q0, v0, _ = static_equilibrium(sy, V, "hertz-kalker", return_velocity=True)
    assert np.max(np.abs(q0[: sy.n] - q_rr)) < 1e-8
    assert np.max(np.abs(q0[sy.n :])) == 0.0
    # a lateral kick, 50 ms at 0.5 ms steps, both models
    kick = np.zeros(sy.n_state)
    kick[sy.index("ws1_y")] = 0.05
    a = simulate(sy_rr, V, 0.05, h=5e-4, q0=q_rr, v0=v_rr + kick[: sy.n])
    b = simulate(sy, V, 0.05, h=5e-4, q0=q0, v0=v0 + kick)
    assert np.max(np.abs(b.q[:, : sy.n] - a.q)) < 1e-8
    assert np.max(np.abs(b.Q - a.Q)) < 1e-8 * sy.wheel_load


def test_static_deflection_matches_wheelset_statics(fr, body):
    """The coupled static rim deflection equals the wheelset's modal + residual statics
    under the coupled model's own rim and journal forces (the same modes and residual: only
    the spin's centrifugal terms differ, < 0.1 %), and the rim camber raises each tread's
    inner edge."""
    sy, lay, q, v = fr
    gp = point_forces(sy, V, q, v)
    for L in lay:
        f = attachment_loads(sy, L, gp)
        # loads: contact up near the static wheel load, journals down
        assert f[2] == pytest.approx(sy.wheel_load, rel=0.02)
        assert f[6] == pytest.approx(sy.wheel_load, rel=0.02)
        assert f[10] < 0 and f[13] < 0
        d = attachment_deflection(sy, L, q)
        ref = body.static_deflection(f, residual=True)
        for i in (1, 2, 3, 5, 6, 7, 10, 13):
            assert d[i] == pytest.approx(ref[i], rel=2e-3, abs=1e-9)
    ang = rim_rail_angle_change(sy, q)
    assert np.all(ang > 3e-4) and np.all(ang < 2e-3)
    np.testing.assert_allclose(ang[0], ang[1], rtol=1e-6)
    # rigid rail: the relative angle is the rim's camber, -drx on the left, +drx on the right
    drx = rim_deformation(sy, q)[2]
    np.testing.assert_array_equal(ang, rim_camber_change(sy, q))
    np.testing.assert_allclose(ang, drx * np.array([-1.0, 1.0])[:, None], rtol=1e-15)


@pytest.mark.parametrize("k_max, f_max", [(2, 800.0), (1, 300.0)])
def test_static_acceptance_against_fe(k_max, f_max):
    """Issue 14's static acceptance: under the static load the coupled model's rim rotation
    and contact-point displacement agree with a direct static FE solve of the wheelset
    (harmonics 0..6, point constraints, rigid parts removed; the unbalanced weight as the
    d'Alembert body force) under the same contact and journal forces within 2 %, at the
    default truncation and a smaller one; without the residual flexibility they do not."""
    ws = Wheelset()
    body = ws.flexible_body(V, k_max=k_max, f_max=f_max)
    errs = {}
    for res in (True, False):
        sy, lay = build_fr(Coach(), scenarios.wheel_table(), V, body=body, residual=res, flexible=(0,))
        q, v, _ = static_equilibrium(sy, V, "hertz-kalker", return_velocity=True)
        f = attachment_loads(sy, lay[0], point_forces(sy, V, q, v))
        d = attachment_deflection(sy, lay[0], q)
        ref = static_fe_solve(ws, f, inertia_relief=True)
        assert abs(ref[3]) > 3e-4 and abs(ref[2]) > 1e-5  # a real deflection
        errs[res] = max(abs(d[i] / ref[i] - 1.0) for i in (1, 2, 3, 5, 6, 7))
    assert errs[True] < 0.02
    assert errs[False] > 0.1  # the truncated modes alone miss it


def test_rows_at_the_static_contact_point(body):
    """Rows, Eulerian rows, residual and arms at the static contact point (s = +3 mm, not
    the taping line): the coupled statics still match the FE solve with the loads at that
    point (2 %), and the contact point sits lower than at s = 0 (the tread's local
    deflection grows outwards), while the camber (the tread's slope) barely moves."""
    ws = Wheelset()
    out = {}
    for s_c in (0.0, 3e-3):
        sy, lay = build_fr(
            Coach(), scenarios.wheel_table(), V, body=body, wheelset=ws, flexible=(0,), s_contact=s_c
        )
        q, v, _ = static_equilibrium(sy, V, "hertz-kalker", return_velocity=True)
        f = attachment_loads(sy, lay[0], point_forces(sy, V, q, v))
        d = attachment_deflection(sy, lay[0], q)
        ref = static_fe_solve(ws, f, s_pair=(s_c, s_c), inertia_relief=True)
        for i in (1, 2, 3, 5, 6, 7):
            assert d[i] == pytest.approx(ref[i], rel=0.02)
        out[s_c] = d
    assert out[3e-3][2] < out[0.0][2] * 1.03  # z more negative by > 3 %
    assert out[3e-3][3] == pytest.approx(out[0.0][3], rel=2e-3)


@pytest.mark.slow
def test_frf_peaks_match_wheelset_model():
    """Issue 14's dynamic acceptance at 300 km/h: the flexible wheelset in the coach (contact
    removed, the same wheelset's mass and inertias, primary springs without dampers as in the
    reference) has the lateral receptance peaks of railvti.wheelset's gyroscopic axle-fixed
    model (modes on the primary springs to a fixed bogie, k <= 6) within 1 %: the k = 1 and
    k = 2 forward/backward pairs and the k = 0 modes (validation/wheelset_fr_frf.py)."""
    from scipy.signal import find_peaks
    from railvti.vehicle.flexible_linear import contact_receptance
    from railvti.wheelset import analytic

    ws = Wheelset()
    v = 300 / 3.6
    f = np.arange(60.0, 600.0, 0.05)
    h_ref = ws.frf(f, v, "lateral", "lateral")
    idx, _ = find_peaks(np.log(np.abs(h_ref)), prominence=0.5)
    p_ref = f[idx]
    assert p_ref.size >= 8
    mp = analytic.wheelset_mass_properties(ws.geometry)
    coach = Coach(
        wheelset_mass=mp["mass"],
        wheelset_roll_inertia=mp["roll_inertia"],
        wheelset_yaw_inertia=mp["roll_inertia"],
        wheelset_pitch_inertia=mp["spin_inertia"],
        primary_cx=0.0,
        primary_cy=0.0,
        primary_cz=0.0,
    )
    sy, lay = build_fr(coach, scenarios.wheel_table(), v, flexible=(0,), wheelset=ws)
    for fp in p_ref:
        fw = np.arange(0.985 * fp, 1.015 * fp, 0.05)
        h = np.abs(contact_receptance(sy, lay[0], fw))
        j = int(np.argmax(h))
        assert 0 < j < fw.size - 1, f"no coupled peak within 1.5 % of {fp:.2f} Hz"
        assert fw[j] == pytest.approx(fp, rel=0.01)


def _probe(sy):
    """The FR system with its points as coordinates (phi = I, B = K = 0): its modal forces
    are the point forces g_p, its modal coordinates the rim and journal displacements."""
    mb = sy.modal
    npt = mb.n_points
    probe = ModalBlocks(
        damping=(np.zeros((npt, npt)),),
        stiffness=(np.zeros((npt, npt)),),
        phi=np.eye(npt),
        couplings=mb.couplings,
    )
    return replace(sy, modal=probe)


def test_rim_motion_equals_rigid_motion(fr):
    """Moving both rims as the rigid wheelset moves gives the same wheel poses: a lateral
    shift (dy = d on both wheels) and a roll (dy = r0 a, dz = +-l0 a, drx = a) give the
    contact forces on the rims of the rigidly moved wheelset (independent bookkeeping: the
    rigid path has no rim terms); the rim and wheel forces agree with the wheel outputs."""
    sy, _, q, v = fr
    ps = _probe(sy)
    mb = sy.modal
    cs = CallSettings(V, contact_id("hertz-kalker"))
    n = sy.n
    x0 = np.concatenate([q[:n], mb.phi @ q[n:]])
    xd0 = np.concatenate([v[:n], mb.phi @ v[n:]])
    rp = mb.couplings.rim_points[:, :, 0]  # (y, z, rx) x (left, right), wheelset 1
    l0, r0 = mb.couplings.rim_arms[:, 0]

    def gp(x, xd=xd0):
        f, wout, info = ps.native.state_force(cs, x, xd)
        assert info == 0
        return f[n:][rp], wout

    g0, w0 = gp(x0)
    # rim forces are this wheel's forces: vertical = Q, lateral = Y (track roll ~ 0)
    np.testing.assert_allclose(g0[1], w0[0, :, 0], rtol=1e-9)
    np.testing.assert_allclose(g0[0], w0[1, :, 0], rtol=1e-6, atol=1e-3)
    for dof, rim in (("ws1_y", [[1, 1], [0, 0], [0, 0]]), ("ws1_roll", [[r0, r0], [l0, -l0], [1, 1]])):
        d = 2e-4 if dof == "ws1_y" else 4e-4
        xa = x0.copy()
        xa[sy.index(dof)] += d
        xb = x0.copy()
        xb[n + rp] += d * np.array(rim)
        ga, _ = gp(xa)
        gb, _ = gp(xb)
        assert np.max(np.abs(ga - g0)) > 10.0  # the motion changes the forces
        np.testing.assert_allclose(gb, ga, rtol=1e-7, atol=1e-5)
        # the same for rates: the creepages see the rim rates as the rigid rates
        d = 1e-3
        va = xd0.copy()
        va[sy.index(dof)] += d
        vb = xd0.copy()
        vb[n + rp] += d * np.array(rim)
        ga, _ = gp(x0, va)
        gb, _ = gp(x0, vb)
        assert np.max(np.abs(ga - g0)) > 10.0
        np.testing.assert_allclose(gb, ga, rtol=1e-9, atol=1e-6)


def _frozen_rates(body, qm):
    """Rates of the axle-fixed modal coordinates of a deformation frozen in the spinning
    material: the cylindrical components move as w(theta - Omega t), and d/dtheta maps the
    (A, B) pair of harmonic k to (k Q_B, -k Q_A) (A: cos k theta, B: sin k theta)."""
    qd = np.zeros_like(qm)
    for k in set(body.k[body.k > 0]):
        ia = np.flatnonzero((body.k == k) & (body.family == "A"))
        ib = np.flatnonzero((body.k == k) & (body.family == "B"))
        qd[ia] = -body.omega * k * qm[ib]
        qd[ib] = body.omega * k * qm[ia]
    return qd


def test_eulerian_term_frozen_pattern(body):
    """A deformation frozen in the rolling material (an out-of-round wheel, k = 0..2): the
    rim material under the fixed contact point moves at dW/dt + Omega dW/dtheta = Omega x u
    (the rigid rotation of the displacement: no y or camber rate, a vertical rate -Omega u_x).
    The contact forces with the Eulerian rows equal those of the same displaced rims with
    exactly these rates, and differ without the Eulerian term (dW/dt alone)."""
    sy, lay = build_fr(Coach(), scenarios.wheel_table(), V, body=body, flexible=(0,), residual=False)
    q, v, _ = static_equilibrium(sy, V, "hertz-kalker", return_velocity=True)
    n, mb = sy.n, sy.modal
    cp = mb.couplings
    rp, ep = cp.rim_points[:, :, 0], cp.rim_euler[:, :, 0]
    rng = np.random.default_rng(3)
    qm = q[n:] + 2e-3 * rng.normal(size=body.n)  # rim motions of some um
    qd = _frozen_rates(body, qm)
    assert np.max(np.abs(mb.phi[rp] @ qd)) > 1e-3  # dW/dt alone is not small
    ps = _probe(sy)
    cs = CallSettings(V, contact_id("hertz-kalker"))

    def forces(x, xd):
        f, _, info = ps.native.state_force(cs, x, xd)
        assert info == 0
        return np.concatenate([f[:n], f[n:][rp].ravel()])

    x = np.concatenate([q[:n], mb.phi @ qm])
    xd = np.concatenate([v[:n], mb.phi @ qd])
    with_euler = forces(x, xd)
    # the same rims at rest against the contact point except Omega x u
    xb, xdb = x.copy(), xd.copy()
    xb[n + ep] = 0.0
    for w, side in enumerate((1, 0)):
        ux = body.rows(side, 0.0)[0] @ qm
        xdb[n + rp[:, w]] = [0.0, -body.omega * ux, 0.0]
    np.testing.assert_allclose(with_euler, forces(xb, xdb), rtol=1e-9, atol=1e-6)
    without = forces(xb, xd)
    assert np.max(np.abs(without - with_euler)) > 100.0  # N: the term matters


def test_centred_running_fr(fr):
    """centred_running(model='FR') runs and gives the static loads and the rim angle."""
    c = scenarios.centred_running(200, variant="FR", duration=0.05, geometry="table")
    assert c.variant == "FR"
    assert c.q_error < 0.01
    assert c.rim_angle.shape == (2, 4)
    sy, _, q, _ = fr
    np.testing.assert_allclose(c.rim_angle, rim_rail_angle_change(sy, q), rtol=1e-3)
    assert not np.any(c.rail_roll)
    np.testing.assert_array_equal(c.rim_angle, c.rim_camber)


def test_fr_errors(body):
    with pytest.raises(InputError, match="f_max"):  # bifurcation takes FR (issue 14 item 5)
        scenarios.bifurcation([300.0, 280.0], variant="FR", duration=0.1, progress=False, f_max=-1.0)
    with pytest.raises(InputError, match="speed_kmh"):
        scenarios.coach_system("FR")
    with pytest.raises(InputError):
        scenarios.coach_system("XX")
    with pytest.raises(InputError, match="subset"):
        build_fr(Coach(), scenarios.wheel_table(), V, flexible=(5,))
    with pytest.raises(InputError, match="tread"):
        build_fr(Coach(), scenarios.wheel_table(), V, body=body, s_contact=-0.05)


def test_hunting_fr_starts_from_the_disturbed_fr_equilibrium():
    """hunting(model='FR') builds the FR system at the speed, releases the leading bogie's
    wheelsets by y0 from the FR static equilibrium (modes deflected, not from RR's), and
    integrates the modal state with a step that resolves the kept modes."""
    y0 = 0.004
    fr = scenarios.hunting(350.0, variant="FR", duration=0.02, y0=y0, output_dt=0.002, progress=False)
    sy = scenarios.coach_system("FR", speed_kmh=350.0)
    qs, _ = static_equilibrium(sy, speed_m_s(350.0), "hertz-kalker")
    assert fr.q.shape[1] == sy.n_state and np.all(np.isfinite(fr.q))
    assert np.max(np.abs(qs[sy.n :])) > 0.0  # the static modal deflection
    # after one output interval the leading wheelset is still near y_static + y0, the
    # trailing bogie's wheelsets near their static position
    i1, i3 = sy.index("ws1_y"), sy.index("ws3_y")
    assert abs(fr.q[0, i1] - (qs[i1] + y0)) < 0.05 * y0
    assert abs(fr.q[0, i3] - qs[i3]) < 0.05 * y0
