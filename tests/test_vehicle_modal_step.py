"""The exact modal step (vehicle_modal_step, simulate(modal_step='exact')): a block with mass
integrated exactly over the step for the point forces linear in time, against closed-form
and independently integrated solutions (docs/vehicle_integrator.md, "Exact modal step")."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from railvti.errors import InputError
from railvti.vehicle import simulate
from railvti.vehicle.assembly import build_rigid_system
from railvti.vehicle.model import ModalBlocks, PointElement
from railvti.vehicle.simulate import exact_modal

W1, W2 = 400.0, 900.0  # rad/s: the block's modes
ZETA = 0.01
GYRO = 60.0  # rad/s: skew (gyroscopic) coupling of the 2 x 2 block


def _system(k_point: float = 0.0, f_point: float = 50.0):
    """A rigid DOF (decoupled) and one 2 x 2 block (damped, gyroscopic) with a point on the
    ground: a preload f_point (a constant force -f_point on the point) and a spring k_point."""
    k = np.diag([W1**2, W2**2])
    b = np.diag([2 * ZETA * W1, 2 * ZETA * W2]) + np.array([[0.0, GYRO], [-GYRO, 0.0]])
    phi = np.array([[0.8, -0.5]])
    els = (PointElement.linear(0, None, k_point, 0.0, f_point),)
    modal = ModalBlocks((b,), (k,), phi, els)
    return build_rigid_system(np.eye(1), np.zeros((1, 1)), np.eye(1) * 1e4, modal=modal), b, k, phi


def _closed_form(b, k, force, z0, t):
    """Q, V of Q'' + B Q' + K Q = force (constant) from z0 at times t (matrix exponential)."""
    n = k.shape[0]
    f = np.block([[np.zeros((n, n)), np.eye(n)], [-k, -b]])
    zs = np.concatenate([np.linalg.solve(k, force), np.zeros(n)])  # the static solution
    return np.array([zs + expm(f * ti) @ (z0 - zs) for ti in t])


def _start(sy):
    q0 = np.zeros(sy.n_state)
    q0[1] = 2e-3
    q0[2] = -1e-3
    return q0


def test_constant_force_exact_at_large_step():
    """A constant point force: the exact step reproduces the closed form at h omega = 5 (both
    modes beyond the trapezoidal rule's MODAL_STEP_LIMIT), to the Newton tolerance."""
    sy, b, k, phi = _system()
    h = 5.0 / W2
    q0 = _start(sy)
    r = simulate(sy, 1.0, 60 * h, q0=q0, h=h, output_dt=h, tol=1e-13, modal_step="exact")
    z = _closed_form(b, k, phi.T @ np.array([-50.0]), np.concatenate([q0[1:], np.zeros(2)]), r.t)
    amp = np.abs(z[:, :2]).max()
    assert np.abs(r.q[:, 1:] - z[:, :2]).max() <= 1e-9 * amp
    assert np.abs(r.v[:, 1:] - z[:, 2:]).max() <= 1e-9 * np.abs(z[:, 2:]).max()
    # the trapezoidal rule refuses this step, and at a step it takes is far less exact
    with pytest.raises(InputError, match="too large for the highest mode"):
        simulate(sy, 1.0, 10 * h, q0=q0, h=h, modal_step="trapezoidal")
    ht = h / 3.0
    rt = simulate(sy, 1.0, 60 * h, q0=q0, h=ht, output_dt=h, tol=1e-13, modal_step="trapezoidal")
    assert np.abs(rt.q[:, 1:] - z[:, :2]).max() > 1e-2 * amp


def test_point_spring_second_order():
    """A spring on the point (a force that depends on the block's motion, linear in time over
    the step): second-order convergence to an independent integration (solve_ivp)."""
    kp = 3e5
    sy, b, k, phi = _system(k_point=kp)
    q0 = _start(sy)
    kk = k + kp * phi.T @ phi
    force = phi.T @ np.array([-50.0])

    def rhs(_t, z):
        return np.concatenate([z[2:], force - b @ z[2:] - kk @ z[:2]])

    dur = 0.05
    ref = solve_ivp(rhs, (0, dur), np.concatenate([q0[1:], np.zeros(2)]), rtol=1e-12, atol=1e-15)
    errs = []
    for h in (5e-4, 2.5e-4, 1.25e-4):
        r = simulate(sy, 1.0, dur, q0=q0, h=h, output_dt=dur, tol=1e-13, modal_step="exact")
        errs.append(np.abs(r.q[-1, 1:] - ref.y[:2, -1]).max())
    amp = np.abs(ref.y[:2]).max()
    assert errs[-1] < 2e-3 * amp, errs
    assert 3.0 < errs[0] / errs[1] < 5.0 and 3.0 < errs[1] / errs[2] < 5.0


def test_point_spring_within_the_stability_limit():
    """A point spring stiff against the step (sqrt(k_p |phi|^2) h = 3, below the linear force's
    limit sqrt(12)) over 2000 steps: the energy of the coupled block stays bounded."""
    kp = (3.0 / 1e-3) ** 2 / (0.8**2 + 0.5**2)
    sy, b, k, phi = _system(k_point=kp, f_point=0.0)
    r = simulate(sy, 1.0, 2.0, q0=_start(sy), h=1e-3, output_dt=1e-3, modal_step="exact")
    kk = k + kp * phi.T @ phi
    e = 0.5 * np.einsum("ti,ij,tj->t", r.q[:, 1:], kk, r.q[:, 1:]) + 0.5 * np.sum(r.v[:, 1:] ** 2, axis=1)
    assert np.all(np.isfinite(e)) and e.max() <= 2.0 * e[0]


def test_modal_step_settings():
    """'trapezoidal' by default, 'exact' on request (hht, alpha 0 only); bad names refused."""
    sy, _, _, _ = _system()
    assert exact_modal(sy, modal_step="exact") and not exact_modal(sy)
    assert not exact_modal(sy, alpha=-0.1)
    assert not exact_modal(sy, integrator="energy")
    assert not exact_modal(sy, modal_step="trapezoidal")
    with pytest.raises(InputError, match="modal_step"):
        exact_modal(sy, modal_step="exponential")
    with pytest.raises(InputError, match="alpha"):
        simulate(sy, 1.0, 0.01, q0=_start(sy), h=1e-3, alpha=-0.1, modal_step="exact")
    # the default: the trapezoidal modal step, with its step-size limit
    with pytest.raises(InputError, match="too large"):
        simulate(sy, 1.0, 0.01, q0=_start(sy), h=5.0 / W2)


def test_cached_step_matrices_change_nothing():
    """The model keeps the blocks' step matrices across calls (a few step sizes): a run after
    runs at other steps (the cache full and cycled) equals the first run bit for bit, and a
    run split into calls (chunks) equals one call."""
    sy, _, _, _ = _system(k_point=2e5)
    q0 = _start(sy)
    kw = dict(q0=q0, output_dt=1e-3, modal_step="exact")
    first = simulate(sy, 1.0, 0.05, h=1e-3, **kw)
    for h in (5e-4, 2.5e-4, 2e-3, 4e-4, 8e-4):
        simulate(sy, 1.0, 0.01, h=h, **kw)
    again = simulate(sy, 1.0, 0.05, h=1e-3, **kw)
    np.testing.assert_array_equal(first.q, again.q)
    chunked = simulate(sy, 1.0, 0.05, h=1e-3, progress=True, chunk=0.004, **kw)
    np.testing.assert_array_equal(first.q, chunked.q)
