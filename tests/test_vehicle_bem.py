"""contact='bem' in the time simulation: BEM normal + steady rolling at every wheel."""
from __future__ import annotations

import sys

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import GridTooSmallError, InputError
from railvti.vehicle import (BemOptions, BemPatch, force_and_tangent, lateral_disturbance,
                             simulate, static_equilibrium)

S = sys.modules["railvti.vehicle.simulate"]
W = S.WHEEL_OUTPUTS
V = 200 / 3.6


@pytest.fixture(scope="module")
def coach_system():
    return scenarios.coach_system()


def _creep_increments(sy, q, contact):
    """Wheel outputs of the leading wheelset at rest and the changes from a lateral velocity
    (eta ~ 1e-4) and a yaw rate (xi ~ -+1.4e-4 on the two wheels)."""
    v = np.zeros(sy.n)
    _, w0, _, _ = force_and_tangent(sy, q, v, V, contact)
    v[sy.dof_names.index("ws1_y")] = 1e-4 * V
    _, w1, _, _ = force_and_tangent(sy, q, v, V, contact)
    v[:] = 0.0
    v[sy.dof_names.index("ws1_yaw")] = 2e-4 * V / 0.75
    _, w2, _, _ = force_and_tangent(sy, q, v, V, contact)
    return w0[:, :, 0], (w1 - w0)[:, :, 0], (w2 - w0)[:, :, 0]


def test_bem_matches_hertz_kalker_where_the_contact_is_hertzian(coach_system):
    """Leading wheelset 3 mm off centre (single tread contacts, close to elliptic): the BEM
    normal forces at the Hertz path's approach agree with Hertz within 2 %, and the creep
    forces from small extra creepages (~1e-4) with Kalker's linear theory within 12 %.
    The 12 % covers the 0.75 mm discretisation (about 12 elements along the rolling
    direction, ~2-3 % on Kalker's coefficients), the non-elliptic patch the real gap gives,
    and the static spin (~0.1 1/m) present in both models, which makes the increments
    partly nonlinear (SHE saturation vs. the exact Coulomb law)."""
    sy = coach_system
    qs, _ = static_equilibrium(sy, V)
    q = lateral_disturbance(sy, qs, 0.003, wheelsets=(0,))
    k0, ke, kx = _creep_increments(sy, q, "hertz-kalker")
    b0, be, bx = _creep_increments(sy, q, "bem")
    n = W.index("N_tread")
    np.testing.assert_allclose(b0[n], k0[n], rtol=0.02)
    assert (b0[W.index("N_flange")] == 0).all()
    np.testing.assert_allclose(be[W.index("Y")], ke[W.index("Y")], rtol=0.12)
    np.testing.assert_allclose(bx[W.index("Fx")], kx[W.index("Fx")], rtol=0.12)
    assert np.abs(bx[W.index("Fx")]).min() > 300.0               # the increments are not noise


def test_bem_centred_running_static_load_and_patch():
    c = scenarios.centred_running(200.0, contact="bem", duration=0.02, progress=False)
    assert c.contact == "bem" and c.run.contact == "bem"
    assert c.q_error < 1e-3                                      # acceptance: 0.1 %
    assert np.abs(c.Y.sum(axis=0)).max() < 1e-3 * c.static_wheel_load
    assert np.allclose(c.Y[0], -c.Y[1], atol=1e-3 * c.static_wheel_load)
    assert np.abs(c.run.y_ws1).max() < 1e-7
    pt = c.patch
    assert isinstance(pt, BemPatch) and pt.point == 0
    n_right = c.run.wheel_output("N_tread")[-1, 1, 0]
    assert pt.fn == pytest.approx(n_right, rel=1e-9)             # the fields are the run's
    assert pt.pressure.max() > 3e8 and pt.power > 0
    assert (pt.pressure[0] == 0).all() and (pt.pressure[:, -1] == 0).all()   # inside the grid
    st = c.run.stats
    assert st["bem_normal_solves"] >= 8 * st["steps"]            # every wheel, every step
    assert st["bem_solves_per_step"] == pytest.approx(st["bem_normal_solves"] / st["steps"])
    assert st["bem_max_normal_residual"] <= 1e-8


def test_bem_hunting_follows_fastsim_over_a_short_run(coach_system):
    """0.06 s after a 4 mm release at 300 km/h: the leading wheelset's lateral motion with
    the BEM within 15 % of its FASTSIM counterpart (the contact models differ, the
    kinematics dominate over so short a time)."""
    rb = scenarios.hunting(300.0, contact="bem", duration=0.06, y0=0.004, progress=False)
    rf = scenarios.hunting(300.0, contact="hertz-fastsim", duration=0.06, y0=0.004, progress=False)
    assert np.isfinite(rb.q).all()
    dy_b = rb.y_ws1[-1] - 0.004
    dy_f = rf.y_ws1[-1] - 0.004
    assert abs(dy_b) > 1e-4
    assert dy_b == pytest.approx(dy_f, rel=0.15)


def test_bem_grid_too_small_is_a_clean_error(coach_system):
    with pytest.raises(GridTooSmallError, match="edge"):
        static_equilibrium(coach_system, V, "bem", bem_options=BemOptions(nx=8, ny=8))


def test_bem_rejects_linearised_table_and_bad_options():
    sy = scenarios.coach_system(linear_conicity=0.2)
    with pytest.raises(InputError, match="profiles"):
        static_equilibrium(sy, V, "bem")
    with pytest.raises(InputError, match="dx"):
        BemOptions(dx=-1e-3)
    with pytest.raises(InputError, match="nx"):
        BemOptions(nx=4)
    with pytest.raises(InputError, match="bem_options"):
        simulate(scenarios.coach_system(), V, 0.01, contact="bem", bem_options="fine")
