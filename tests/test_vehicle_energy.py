"""The energy-conserving integrator (simulate(integrator='energy')): an undamped frictionless FR
run keeps its energy where the default trapezoidal rule drifts, and bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.errors import InputError
from railvti.vehicle import simulate, static_equilibrium
from railvti.vehicle.model import CallSettings
from railvti.vehicle.simulate import consistent_massless

SPEED = 200.0 / 3.6
KICK = 5e-4


@pytest.fixture(scope="module")
def fr():
    """Model FR at the scenario defaults (k_max 2, f_max 800 Hz, residual flexibility) on the
    strip geometry, every damper and the modal damping removed, frictionless."""
    sy, _ = scenarios.fr_system(speed=SPEED, geometry="strip")
    return dataclasses.replace(sy.without_damping(), friction=0.0)


def fr_energy(sy):
    """E(q, v, W) over the whole state, J: kinetic + elastic (the dense M, K of
    flexible_linear.linear_matrices: coach, modal blocks with the residual flexibility (its mass,
    none if massless), the journal couplings) - the work of the constant loads (gravity and
    spring preloads, the
    journal couplings' preloads through Phi) + the contacts' potential W. The gyroscopic
    terms (modal G, the 'gyro' couplings: skew) do no work."""
    from railvti.vehicle.flexible_linear import linear_matrices

    m, _, k = linear_matrices(sy)
    assert np.abs(k - k.T).max() < 1e-9 * np.abs(k).max()  # conservative: K symmetric
    k = 0.5 * (k + k.T)
    n, mb = sy.n, sy.modal
    f0 = np.zeros(sy.n_state)
    f0[:n] = sy.f0
    for e, kind in enumerate(mb.couplings.kinds):
        if kind == "split":
            f0[n:] += mb.couplings.params[2, e] * mb.phi[mb.couplings.points[e]]

    def energy(q, v, w):
        return 0.5 * np.einsum("ti,ij,tj->t", v, m, v) + 0.5 * np.einsum("ti,ij,tj->t", q, k, q) - q @ f0 + w

    return energy


def energy_error(sy, integrator: str, duration: float, h: float, tol: float = 1e-9, **kw) -> float:
    """max |E - E0| over a run from the static state with ws1 kicked 0.5 mm to the left (the
    massless coordinates, if any, consistent with it, as integrator='energy' starts),
    relative to the kick's energy (the start against the static state). kw: to simulate."""
    energy = fr_energy(sy)
    x, _ = static_equilibrium(sy, SPEED)
    x1 = x.copy()
    x1[sy.index("ws1_y")] += KICK
    x1 = consistent_massless(sy, SPEED, x1)  # the residual flexibility at the kick
    r = simulate(
        sy, SPEED, duration, q0=x1, h=h, output_dt=h, progress=False, tol=tol, integrator=integrator, **kw
    )
    e = energy(r.q, r.v, r.wheel_output("energy").sum(axis=(1, 2)))
    w0 = sy.native.state_force(CallSettings(SPEED, 1), x, np.zeros_like(x))[1][8].sum()
    e_static = energy(x[None], np.zeros((1, x.size)), np.array([w0]))[0]
    e_start = energy(
        x1[None],
        np.zeros((1, x.size)),
        np.array([sy.native.state_force(CallSettings(SPEED, 1), x1, np.zeros_like(x1))[1][8].sum()]),
    )[0]
    return float(np.abs(np.concatenate([[e_start], e]) - e_start).max() / abs(e_start - e_static))


def test_undamped_frictionless_fr_conserves_energy(fr):
    """0.1 s after a 0.5 mm lateral kick of the leading wheelset (200 km/h, h = 0.5 ms, every
    step compared): the energy-conserving scheme keeps the energy to 1e-5 of the kick's
    (measured 9.5e-9, the share of the Newton tolerance 1e-9), where the default trapezoidal
    rule is off by its O(h^2) error of the nonlinear contact force (measured 7.4e-4: 8e4
    times more; asserted 1e3). The trapezoidal modal step's default step (FR's default, the
    exact modal step at 1 ms, is not the energy scheme's counterpart)."""
    h = systems.default_step(fr, exact=False)
    e_energy = energy_error(fr, "energy", 0.1, h)
    e_hht = energy_error(fr, "hht", 0.1, h, modal_step="trapezoidal")
    assert e_energy < 1e-5
    assert e_hht > 1e-4
    assert e_hht > 1000.0 * e_energy


def test_energy_scheme_bad_input(fr):
    with pytest.raises(InputError, match="integrator"):
        simulate(fr, SPEED, 0.01, h=5e-4, integrator="verlet", progress=False)
    with pytest.raises(InputError, match="alpha"):
        simulate(fr, SPEED, 0.01, h=5e-4, integrator="energy", alpha=-0.05, progress=False)
    rr = scenarios.coach_system(geometry="table")  # no potential
    with pytest.raises(InputError, match="strip"):
        simulate(rr, SPEED, 0.01, integrator="energy", progress=False)
