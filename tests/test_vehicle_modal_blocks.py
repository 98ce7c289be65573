"""Modal blocks coupled through attachment points: the condensed Newton of vehicle_newmark.

Each test checks the condensed integrator against something it does not compute itself: the
same system assembled as dense M, C, K and run through the rigid (dense) path, the exact energy
balance of the trapezoidal rule on a conservative linear system, an adaptive Runge-Kutta
solution of the nonlinear equations written out in numpy, and the RR model without blocks.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from railvti import scenarios
from railvti._native import core
from railvti._status import Status, check
from railvti.errors import InputError
from railvti.vehicle import eigenvalues, lateral_disturbance, simulate, static_equilibrium
from railvti.vehicle.assembly import build_rigid_system
from railvti.vehicle.model import CallSettings, ModalBlocks, PointElement
from railvti.vehicle.equilibrium import force_and_tangent
from railvti.vehicle.simulate import MODAL_STEP_LIMIT


def _blocks(rng, sizes, zeta=0.02, gyro=5.0):
    """Random SPD stiffness blocks (omega about 100-250 rad/s), damping 2 zeta omega plus a
    skew (gyroscopic) part."""
    bb, kb = [], []
    for s in sizes:
        a = rng.normal(size=(s, s))
        k = a @ a.T * 1e4 + np.eye(s) * 2e4
        g = rng.normal(size=(s, s)) * gyro
        bb.append(2.0 * zeta * math.sqrt(np.trace(k) / s) * np.eye(s) + (g - g.T))
        kb.append(k)
    return tuple(bb), tuple(kb)


def _linear_system(damped=True, seed=1):
    """Two rigid masses and 9 modes in blocks of 1, 2, 3, 1, 2 with 3 attachment points: point
    0 on DOF 0 (spring, damper, preload), point 1 on DOF 1 (spring), point 2 on the ground."""
    rng = np.random.default_rng(seed)
    bb, kb = _blocks(rng, (1, 2, 3, 1, 2), zeta=0.02 if damped else 0.0)
    nm = sum(b.shape[0] for b in bb)
    phi = rng.normal(size=(3, nm)) * 0.3
    c = 20.0 if damped else 0.0
    els = (
        PointElement.linear(0, 0, 5e4, c, 10.0),
        PointElement.linear(1, 1, 3e4),
        PointElement.linear(2, None, 1e4, c),
    )
    m = np.diag([10.0, 20.0])
    k = np.array([[4e4, -1e4], [-1e4, 2e4]])
    cr = np.array([[30.0, 0.0], [0.0, 10.0]]) if damped else np.zeros((2, 2))
    return build_rigid_system(m, cr, k, f0=np.array([0.0, -50.0]), modal=ModalBlocks(bb, kb, phi, els))


def _start(sy):
    q0 = np.zeros(sy.n_state)
    q0[0] = 1e-3
    q0[3] = 2e-3
    return q0


def test_condensed_matches_dense_linear():
    """Condensed modal blocks and the same system as dense M, C, K: the same histories."""
    sy = _linear_system()
    de = sy.dense_equivalent()
    assert de.n == sy.n_state and de.modal is None
    q0 = _start(sy)
    r1 = simulate(sy, 1.0, 0.2, q0=q0, h=1e-3, output_dt=1e-3, tol=1e-12)
    r2 = simulate(de, 1.0, 0.2, q0=q0, h=1e-3, output_dt=1e-3, tol=1e-12)
    assert r1.dof_names == r2.dof_names
    assert np.max(np.abs(r1.q - r2.q)) <= 1e-8 * np.max(np.abs(r2.q))
    assert np.max(np.abs(r1.v - r2.v)) <= 1e-8 * np.max(np.abs(r2.v))
    assert np.max(np.abs(r2.q[:, sy.n :])) > 1e-4  # the modes did move


def test_condensed_matches_dense_hht_alpha():
    """Same with numerical damping (HHT alpha = -0.1) and a smaller step."""
    sy = _linear_system(seed=3)
    de = sy.dense_equivalent()
    q0 = _start(sy)
    kw = dict(q0=q0, h=5e-4, output_dt=5e-4, tol=1e-12, alpha=-0.1)
    r1 = simulate(sy, 1.0, 0.05, **kw)
    r2 = simulate(de, 1.0, 0.05, **kw)
    assert np.max(np.abs(r1.q - r2.q)) <= 1e-8 * np.max(np.abs(r2.q))


def _energy(sy, de, r):
    """E = v'Mv/2 + q'Kq/2 - f0'q of the dense equivalent along run r, and at the start
    (at rest)."""
    e = (
        0.5 * np.einsum("ti,ij,tj->t", r.v, de.m, r.v)
        + 0.5 * np.einsum("ti,ij,tj->t", r.q, de.k, r.q)
        - r.q @ de.f0
    )
    x0 = _start(sy)
    return e, 0.5 * x0 @ de.k @ x0 - x0 @ de.f0


def test_energy_conserved_trapezoidal():
    """Undamped, gyroscopic (skew B) and conservative: the trapezoidal rule keeps
    E = v'Mv/2 + q'Kq/2 - f0'q of the dense equivalent to 1e-8 over 2000 steps."""
    sy = _linear_system(damped=False)
    de = sy.dense_equivalent()
    r = simulate(sy, 1.0, 2.0, q0=_start(sy), h=1e-3, output_dt=1e-3, tol=1e-12)
    e, e0 = _energy(sy, de, r)
    assert np.max(np.abs(e - e0)) <= 1e-8 * abs(e0)
    assert np.abs(de.c[sy.n :, sy.n :] + de.c[sy.n :, sy.n :].T).max() == 0.0  # B skew: no damping
    assert np.abs(de.c[sy.n :, sy.n :]).max() > 0.0  # but gyroscopic


def test_without_damping_is_conservative():
    """System.without_damping keeps the gyroscopic (skew) part of B and drops the modal and
    point dampers: the trapezoidal rule then conserves the energy as above."""
    sy = _linear_system().without_damping()
    assert all(np.array_equal(b, -b.T) for b in sy.modal.damping)
    assert all(np.abs(b).max() > 0 for b in sy.modal.damping if b.shape[0] > 1)
    assert all(e.params[1] == 0.0 for e in sy.modal.elements)
    de = sy.dense_equivalent()
    r = simulate(sy, 1.0, 0.5, q0=_start(sy), h=1e-3, output_dt=1e-3, tol=1e-12)
    e, e0 = _energy(sy, de, r)
    assert np.max(np.abs(e - e0)) <= 1e-8 * abs(e0)


def _hertz_system():
    """A 100 kg mass resting through a Hertz contact on point 0 of 12 modes (one 2 x 2 block
    with gyroscopic coupling), point 1 held by a spring to the ground."""
    rng = np.random.default_rng(7)
    om = np.linspace(60.0, 400.0, 10)
    bb = [np.array([[2 * 0.02 * w]]) for w in om] + [np.array([[1.0, 8.0], [-8.0, 1.0]])]
    kb = [np.array([[w * w]]) for w in om] + [np.diag([9e3, 1.6e4])]
    phi = np.abs(rng.normal(size=(2, 12))) * 0.2
    els = (PointElement.hertz(0, 0, 5e8), PointElement.linear(1, None, 2e4, 5.0))
    mb = ModalBlocks(tuple(bb), tuple(kb), phi, els)
    return build_rigid_system(
        np.array([[100.0]]), np.zeros((1, 1)), np.array([[0.0]]), f0=np.array([-981.0]), modal=mb
    )


def _hertz_rhs(sy):
    """x' = f(t, x) of the Hertz system written out in numpy (independent of the core)."""
    mb = sy.modal
    n, nm = sy.n, mb.n_modes
    bfull = np.zeros((nm, nm))
    kfull = np.zeros((nm, nm))
    j = 0
    for b, k in zip(mb.damping, mb.stiffness):
        s = b.shape[0]
        bfull[j : j + s, j : j + s] = b
        kfull[j : j + s, j : j + s] = k
        j += s
    (kh,), (kl, cl) = mb.elements[0].params[:1], mb.elements[1].params[:2]

    def rhs(t, y):
        q, qm, v, vm = y[:n], y[n : n + nm], y[n + nm : 2 * n + nm], y[2 * n + nm :]
        u, ud = mb.phi @ qm, mb.phi @ vm
        d = u[0] - q[0]
        fh = kh * max(d, 0.0) ** 1.5
        gp = np.array([-fh, -(kl * u[1] + cl * ud[1])])
        aq = (sy.f0 + np.array([fh])) / sy.m[0, 0]
        am = -bfull @ vm - kfull @ qm + mb.phi.T @ gp
        return np.concatenate([v, vm, aq, am])

    return rhs


def _hertz_start(sy):
    """Near the static state (found in numpy), the mass pushed down by 20 % of its approach."""
    mb = sy.modal
    kh = mb.elements[0].params[0]
    w = -sy.f0[0]
    d0 = (w / kh) ** (2.0 / 3.0)
    # static: K_m Q = Phi^T g_p with g_p = (-w, -kl u1): solve the linear modal equations
    kl = mb.elements[1].params[0]
    kfull = np.zeros((12, 12))
    kfull[:10, :10] = np.diag([k[0, 0] for k in mb.stiffness[:10]])
    kfull[10:, 10:] = mb.stiffness[10]
    a = kfull + kl * np.outer(mb.phi[1], mb.phi[1])
    qm = np.linalg.solve(a, -w * mb.phi[0])
    u0 = mb.phi[0] @ qm
    x0 = np.concatenate([[u0 - d0 * 1.2], qm])
    return x0


def test_hertz_point_second_order_and_newton():
    """A nonlinear (d^1.5) point contact: errors against a DOP853 solution fall as h^2, and
    Newton with the analytic point tangent needs few iterations per step."""
    sy = _hertz_system()
    x0 = _hertz_start(sy)
    T = 0.05
    ref = solve_ivp(
        _hertz_rhs(sy),
        (0.0, T),
        np.concatenate([x0, np.zeros_like(x0)]),
        method="DOP853",
        rtol=1e-12,
        atol=1e-15,
    ).y[: sy.n_state, -1]
    errs = []
    for h in (2.5e-4, 1.25e-4, 6.25e-5):  # the contact mode: ~1800 rad/s
        r = simulate(sy, 1.0, T, q0=x0, h=h, output_dt=T, tol=1e-13, maxsub=0)
        assert r.t[-1] == pytest.approx(T)
        errs.append(np.max(np.abs(r.q[-1] - ref)))
        # one tangent per step, and Newton quadratic: <= 3 iterations from the predictor to
        # the rounding floor at 1e-13 m (a wrong point tangent would need many more)
        assert r.stats["tangents"] == r.stats["steps"]
        assert r.stats["newton_iterations"] <= 3 * r.stats["steps"]
    order = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(order > 1.8) and np.all(order < 2.3), (errs, order)
    assert errs[-1] < 1e-3 * np.max(np.abs(ref))


def _coach_with_modes(coupled: bool):
    """The RR coach with 6 modes (two 2 x 2 gyroscopic blocks and two single modes) on the
    leading wheelset's z and y by springs preloaded to the static state, or with zero
    stiffness (decoupled). The table geometry: with the strips, the rigid model keeps its
    Newton matrix from step to step and the modal one does not, so the two would agree to
    the Newton tolerance only, not to round-off."""
    sy = scenarios.coach_system(geometry="table")
    v = 300 / 3.6
    q, vs, _ = static_equilibrium(sy, v, return_velocity=True)
    iz, iy = sy.index("ws1_z"), sy.index("ws1_y")
    rng = np.random.default_rng(11)
    bb, kb = _blocks(rng, (2, 2, 1, 1), gyro=20.0)
    kb = tuple(k * 30.0 for k in kb)
    phi = rng.normal(size=(2, 6)) * 0.05
    ks = (5e6, 2e6) if coupled else (0.0, 0.0)
    # f = k d + p with d = u - q = -q at the start: p = k q keeps the start in equilibrium
    els = (
        PointElement.linear(0, iz, ks[0], 1e3 if coupled else 0.0, ks[0] * q[iz]),
        PointElement.linear(1, iy, ks[1], 0.0, ks[1] * q[iy]),
    )
    fr = sy.with_modal(ModalBlocks(bb, kb, phi, els))
    q1 = lateral_disturbance(sy, q, 0.003)
    x0 = np.concatenate([q1, np.zeros(6)])
    v0 = np.concatenate([vs, np.zeros(6)])
    return sy, fr, q1, vs, x0, v0, v


def test_rr_with_decoupled_blocks_reproduces_rr():
    """RR with modal blocks attached by zero-stiffness elements: rigid histories as RR's."""
    sy, fr, q1, vs, x0, v0, v = _coach_with_modes(coupled=False)
    r0 = simulate(sy, v, 0.1, q0=q1, v0=vs, output_dt=1e-3)
    r1 = simulate(fr, v, 0.1, q0=x0, v0=v0, output_dt=1e-3)
    assert r1.q.shape[1] == sy.n + 6 and r1.dof_names[-1] == "mode6"
    assert np.max(np.abs(r1.q[:, : sy.n] - r0.q)) <= 1e-12 * np.max(np.abs(r0.q))
    assert np.allclose(r1.wheel, r0.wheel, rtol=1e-10, atol=1e-10 * sy.wheel_load)  # round-off
    assert np.max(np.abs(r1.q[:, sy.n :])) == 0.0


def test_coach_with_coupled_blocks_matches_dense():
    """The coach with contact and modes sprung to the leading wheelset: condensed and dense
    paths agree (both with the finite-difference contact tangent)."""
    sy, fr, q1, vs, x0, v0, v = _coach_with_modes(coupled=True)
    de = fr.dense_equivalent()
    kw = dict(q0=x0, v0=v0, output_dt=1e-3, h=5e-4, tol=1e-12)
    r1 = simulate(fr, v, 0.05, **kw)
    r2 = simulate(de, v, 0.05, **kw)
    assert np.max(np.abs(r1.q - r2.q)) <= 1e-8 * np.max(np.abs(r2.q))
    assert np.max(np.abs(r1.q[:, sy.n :])) > 1e-6  # the modes are excited
    assert np.allclose(r1.wheel, r2.wheel, rtol=1e-7, atol=1e-6 * sy.wheel_load)


# --- bad input --------------------------------------------------------------------------


def test_bad_blocks_and_rows():
    phi = np.ones((2, 3))
    with pytest.raises(InputError, match="same size"):
        ModalBlocks((np.eye(2), np.eye(1)), (np.eye(2), np.eye(2)), phi)
    with pytest.raises(InputError, match="same, non-zero number"):
        ModalBlocks((np.eye(2),), (np.eye(2), np.eye(1)), phi)
    with pytest.raises(InputError, match="square"):
        ModalBlocks((np.ones((2, 3)),), (np.ones((2, 3)),), phi)
    with pytest.raises(InputError, match="phi must have shape"):
        ModalBlocks((np.eye(2), np.eye(1)), (np.eye(2), np.eye(1)), np.ones((2, 4)))
    with pytest.raises(InputError, match="non-finite"):
        ModalBlocks((np.eye(2), np.eye(1)), (np.eye(2), np.array([[np.nan]])), phi)
    with pytest.raises(InputError, match="non-finite"):
        ModalBlocks((np.eye(3),), (np.eye(3),), np.full((2, 3), np.inf))
    with pytest.raises(InputError, match="point element on point 2"):
        ModalBlocks((np.eye(3),), (np.eye(3),), phi, (PointElement.linear(2, None, 1.0),))
    with pytest.raises(InputError, match="unknown point element kind"):
        PointElement("spring", 0, None, (1.0,))
    with pytest.raises(InputError, match="stiffness >= 0"):
        PointElement.hertz(0, None, -1.0)
    mb = ModalBlocks((np.eye(3),), (np.eye(3),), phi, (PointElement.linear(0, 5, 1.0),))
    with pytest.raises(InputError, match="point element on DOF 5"):
        build_rigid_system(np.eye(2), np.zeros((2, 2)), np.eye(2), modal=mb)


def test_core_rejects_inconsistent_blocks():
    """The Fortran core checks the packed blocks itself (SIZE_MISMATCH -> InputError)."""
    sy = build_rigid_system(np.eye(1), np.zeros((1, 1)), np.eye(1))
    h = sy.native.handle
    one = np.ones(1, dtype=np.int32)
    par = np.zeros((4, 1), order="F")
    # blocks 1..2 and 3..3 need 4 + 1 packed entries, not 4
    info = core.vehicle_modal_attach_c(
        h,
        np.array([1, 3, 4], dtype=np.int32),
        np.ones(4),
        np.ones(4),
        np.ones((1, 3), order="F"),
        one,
        0 * one,
        one,
        par,
    )
    with pytest.raises(InputError):
        check(info, "modal blocks")
    # block starts beyond the modes
    info = core.vehicle_modal_attach_c(
        h,
        np.array([1, 5], dtype=np.int32),
        np.ones(16),
        np.ones(16),
        np.ones((1, 3), order="F"),
        one,
        0 * one,
        one,
        par,
    )
    with pytest.raises(InputError):
        check(info, "modal blocks")
    # a point element on a DOF the model does not have
    info = core.vehicle_modal_attach_c(
        h,
        np.array([1, 4], dtype=np.int32),
        np.ones(9),
        np.ones(9),
        np.ones((1, 3), order="F"),
        one,
        2 * one,
        one,
        par,
    )
    with pytest.raises(InputError):
        check(info, "modal blocks")
    # a non-finite stiffness entry
    kb = np.ones(9)
    kb[4] = np.nan
    info = core.vehicle_modal_attach_c(
        h,
        np.array([1, 4], dtype=np.int32),
        np.ones(9),
        kb,
        np.ones((1, 3), order="F"),
        one,
        0 * one,
        one,
        par,
    )
    with pytest.raises(InputError):
        check(info, "modal blocks")
    # the failed attachments left the model without blocks: the rigid force shim (which
    # refuses models with blocks) still works on it
    _, _, _, _, info = sy.native.force(CallSettings(1.0, 1), np.array([1e-3]), np.zeros(1))
    assert info == Status.OK


def test_step_too_large_for_highest_mode():
    sy = _linear_system()
    wmax = sy.modal.max_frequency()
    k_all = np.concatenate([np.linalg.eigvalsh(k) for k in sy.modal.stiffness])
    assert wmax == pytest.approx(math.sqrt(k_all.max()), rel=1e-12)
    h_ok = 0.99 * MODAL_STEP_LIMIT / wmax
    simulate(sy, 1.0, 2 * h_ok, q0=_start(sy), h=h_ok)
    with pytest.raises(InputError, match="too large for the highest mode"):
        simulate(sy, 1.0, 0.1, q0=_start(sy), h=1.01 * MODAL_STEP_LIMIT / wmax)


def test_rigid_only_functions_refuse_modal_systems():
    sy = _linear_system()
    with pytest.raises(InputError, match="modal blocks"):
        force_and_tangent(sy, np.zeros(sy.n), np.zeros(sy.n), 1.0)
    with pytest.raises(InputError, match="modal blocks"):
        eigenvalues(sy, 1.0, q=np.zeros(sy.n))
    with pytest.raises(InputError, match="q0 must have shape"):
        simulate(sy, 1.0, 0.01, q0=np.zeros(sy.n))
    with pytest.raises(InputError, match="q0 must have shape"):
        static_equilibrium(sy, 1.0, q0=np.zeros(sy.n))


# --- static equilibrium with modal blocks -------------------------------------------------


def test_static_linear_matches_dense_solve():
    """The condensed static Newton against numpy's solve of the dense K x = f0."""
    sy = _linear_system()
    de = sy.dense_equivalent()
    q, _ = static_equilibrium(sy, 1.0)
    x = np.linalg.solve(de.k, de.f0)
    assert np.max(np.abs(q - x)) <= 1e-12 * np.max(np.abs(x))
    r = simulate(sy, 1.0, 0.05, h=1e-3)  # the default start is that state: at rest
    assert np.max(np.abs(r.q - x)) <= 1e-10 * np.max(np.abs(x))


def test_static_hertz_point_contact():
    """Mass on a Hertz point: approach (W / k_H)^(2/3) below the point, whose static
    deflection solves the linear modal equations under the load W (numpy)."""
    sy = _hertz_system()
    x0 = _hertz_start(sy)  # the static modal state, the mass 20 % too low
    d0 = (981.0 / 5e8) ** (2.0 / 3.0)
    q, _ = static_equilibrium(sy, 1.0, q0=x0)
    assert q[0] == pytest.approx(x0[0] + 0.2 * d0, abs=1e-12 * d0 + 1e-15)
    assert np.max(np.abs(q[1:] - x0[1:])) <= 1e-12 * np.max(np.abs(x0[1:]))


def test_static_coach_with_modes_matches_dense():
    """The coach with contact and sprung modes: condensed and dense static states agree."""
    _, fr, _, _, _, _, v = _coach_with_modes(coupled=True)
    q, vv, w = static_equilibrium(fr, v, return_velocity=True)
    qd, vd, wd = static_equilibrium(fr.dense_equivalent(), v, return_velocity=True)
    assert np.max(np.abs(q - qd)) <= 1e-10 * np.max(np.abs(qd))
    assert np.max(np.abs(vv - vd)) <= 1e-10  # spin rates, rad/s (zero: centred)
    assert np.max(np.abs(w - wd)) <= 1e-9 * np.max(np.abs(wd))


def _series_system(kp: float, comp: np.ndarray):
    """A 100 kg mass under gravity on a spring kp to point 0, whose compliance comp is a
    massless block (compliance_block)."""
    from railvti.vehicle.model import compliance_block

    phi_r, k_r = compliance_block(comp)
    mb = ModalBlocks((np.zeros_like(k_r),), (k_r,), phi_r, (PointElement.linear(0, 0, kp),), massless=(True,))
    return build_rigid_system(
        np.array([[100.0]]), np.zeros((1, 1)), np.array([[0.0]]), f0=np.array([-981.0]), modal=mb
    )


def test_massless_block_is_a_series_compliance():
    """A point compliance R (massless block) in series with a spring kp: the static
    deflection is W (1/kp + R) and the free vibration runs at the trapezoidal rule's discrete
    frequency of sqrt(k_eff / m), k_eff = 1 / (1/kp + R) (exact for the linear oscillator:
    2 atan(omega h / 2) / h), to rounding; the condensed and the static Newton agree."""
    kp, R, m, h = 1e6, 1e-6, 100.0, 1e-3
    sy = _series_system(kp, np.array([[R]]))
    assert sy.modal.max_frequency() == 0.0  # no mass: no step limit from it
    x_s = static_equilibrium(sy, 1.0)[0]
    keff = 1.0 / (1.0 / kp + R)
    assert x_s[0] == pytest.approx(-981.0 / keff, rel=1e-12)
    assert sy.modal.phi[0] @ x_s[1:] == pytest.approx(-981.0 * R, rel=1e-12)
    a0 = 1e-3
    x0 = x_s.copy()
    x0[0] += a0
    # a consistent start: the massless coordinate at u = R g (it is algebraic)
    u0 = R * kp * x0[0] / (1.0 + R * kp)
    x0[1] = u0 / sy.modal.phi[0, 0]
    r = simulate(sy, 1.0, 0.5, q0=x0, h=h, output_dt=h, tol=1e-13)
    om = math.sqrt(keff / m)
    omd = 2.0 * math.atan(om * h / 2.0) / h
    # the trapezoidal rule's oscillator: amplitude a0 / cos(phase of the initial half step)
    ref = x_s[0] + a0 * np.cos(omd * r.t)
    np.testing.assert_allclose(r.q[:, 0], ref, atol=1e-9 * a0 / 1e-3)
    # the massless coordinate follows the spring force at every output step: u = R g
    g = -kp * (sy.modal.phi[0] @ r.q[:, 1:].T - r.q[:, 0])
    np.testing.assert_allclose(sy.modal.phi[0] @ r.q[:, 1:].T, R * g, rtol=1e-9, atol=1e-15)
    # HHT-alpha: the algebraic equation still holds at every step, and the motion decays
    r = simulate(sy, 1.0, 0.5, q0=x0, h=h, output_dt=h, tol=1e-13, alpha=-0.1)
    g = -kp * (sy.modal.phi[0] @ r.q[:, 1:].T - r.q[:, 0])
    np.testing.assert_allclose(sy.modal.phi[0] @ r.q[:, 1:].T, R * g, rtol=1e-9, atol=1e-15)
    assert 0.5 * a0 < np.abs(r.q[-50:, 0] - x_s[0]).max() < a0


def test_compliance_block_errors():
    from railvti.vehicle.model import compliance_block

    with pytest.raises(InputError, match="semi-definite"):
        compliance_block(np.array([[1.0, 0.0], [0.0, -1.0]]))
    with pytest.raises(InputError, match="square"):
        compliance_block(np.ones((2, 3)))
    with pytest.raises(InputError, match="massless"):
        _series_system(1e6, np.array([[1e-6]])).dense_equivalent()
    with pytest.raises(InputError, match="flags"):
        ModalBlocks((np.zeros((1, 1)),), (np.eye(1),), np.ones((1, 1)), massless=(True, False))
