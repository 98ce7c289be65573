"""On the ring track (RF, FF) Newton's kept matrix contracts linearly, and a step also stops
when the error left after its last correction, estimated from the observed contraction
theta (theta / (1 - theta) |dq| <= tol, Hairer & Wanner's simplified-Newton test), is below
the tolerance (vehicle_newmark::newton_iterate, issue 33). Checked against the same run with a
tolerance 100 times tighter, whose state is converged to ~1e-11 m: the default run must stay
within a few tolerances of it (the estimate is an error bound, not a looser tolerance), and
its wheel loads within what the last correction's lag (at most 10 tol) gives against the
contact's stiffness."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle.equilibrium import lateral_disturbance, static_equilibrium
from railvti.vehicle.simulate import simulate
from coarse_ring import RING

V = 300.0 / 3.6
TOL = 1e-9


@pytest.fixture(scope="module")
def runs():
    sy = scenarios.rf_system(speed=V, geometry="strip", **RING)
    q0 = lateral_disturbance(sy, static_equilibrium(sy, V, "hertz-fastsim")[0], 0.006)
    kw = dict(q0=q0, h=5e-4, output_dt=0.001, contact="hertz-fastsim", progress=False)
    return sy, simulate(sy, V, 0.1, tol=TOL, **kw), simulate(sy, V, 0.1, tol=1e-11, **kw)


def test_the_contraction_test_is_taken(runs):
    """Some steps stop on the estimate: their last correction, added without a new force
    evaluation, exceeds tol (the plain test keeps it below tol), but never 10 tol."""
    _, a, _ = runs
    dq = a.stats["newton_correction_max"]
    assert TOL < dq <= 10 * TOL * (1 + 1e-12), dq


def test_the_state_stays_within_the_tolerance_of_a_converged_run(runs):
    """Hunting from 6 mm, 200 steps: the vehicle's DOFs (m, rad) within 2 tol of the run at tol
    1e-11 (each step's state within about tol of its solution, the error not growing over the
    run; measured 1.3 tol, the plain test 0.3 tol), the rail's pose under the wheels (m, rad;
    the sum of the ring's modes and residual coordinates, each within about tol) within 5 tol
    (measured 3.4 tol, the plain test 0.7 tol), the wheel loads within the outputs' lag (at
    most 10 tol) times the Hertz contact's stiffness (~1.5e9 N/m: 15 N, 0.03 % of the static
    wheel load; measured 8.5 N, the plain test 1.5 N)."""
    sy, a, b = runs
    rigid = slice(0, sy.n)
    assert np.abs(a.y_ws1).max() > 1e-3  # the motion is large: the check is not vacuous
    assert np.abs(a.q[:, rigid] - b.q[:, rigid]).max() < 2 * TOL
    assert np.abs(a.rail - b.rail).max() < 5 * TOL
    assert np.abs(a.Q - b.Q).max() < 15.0
