"""contact='bem' in the time simulation: BEM normal + steady rolling at every wheel."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import GridTooSmallError, InputError
from railvti.vehicle import (
    BemOptions,
    BemPatch,
    bem_state,
    build_single_wheelset,
    force_and_tangent,
    lateral_disturbance,
    simulate,
    static_equilibrium,
)
from railvti.vehicle import time_loop
from railvti.vehicle.equilibrium import _force_and_tangent
from railvti.vehicle.model import WHEEL_OUTPUTS
from railvti.vehicle.table import QUANTITIES

W = WHEEL_OUTPUTS
V = 200 / 3.6


@pytest.fixture(scope="module")
def coach_system():
    # the table geometry: the Hertz points of the gap fields the BEM reads (like for like)
    return scenarios.coach_system(geometry="table")


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
    assert np.abs(bx[W.index("Fx")]).min() > 300.0  # the increments are not noise


def test_bem_centred_running_static_load_and_patch():
    c = scenarios.centred_running(200.0, contact="bem", duration=0.02, progress=False)
    assert c.contact == "bem" and c.run.contact == "bem"
    assert c.q_error < 1e-3  # acceptance: 0.1 %
    assert np.abs(c.Y.sum(axis=0)).max() < 1e-3 * c.static_wheel_load
    assert np.allclose(c.Y[0], -c.Y[1], atol=1e-3 * c.static_wheel_load)
    assert np.abs(c.run.y_ws1).max() < 1e-7
    pt = c.patch
    assert isinstance(pt, BemPatch) and pt.point == 0
    n_right = c.run.wheel_output("N_tread")[-1, 1, 0]
    # the fields are the point's last solve's: with linear updates (BemOptions.update_band)
    # the run's last force is that solve's plus its model's change, within the band
    assert pt.fn == pytest.approx(n_right, rel=BemOptions().update_band)
    assert pt.pressure.max() > 3e8 and pt.power > 0
    assert (pt.pressure[0] == 0).all() and (pt.pressure[:, -1] == 0).all()  # inside the grid
    st = c.run.stats
    # every wheel, every step: a solve or a linear update
    assert st["bem_normal_solves"] + st["bem_linear_updates"] >= 8 * st["steps"]
    assert st["bem_solves_per_step"] == pytest.approx(st["bem_normal_solves"] / st["steps"])
    assert st["bem_max_normal_residual"] <= BemOptions().tol_normal  # every solve converged


def test_bem_spin_rate_decay_follows_the_bem_creep_stiffness_and_kalker():
    """A wheelset spinning 2e-3 rad/s faster than free rolling (xi ~ 3e-5 per wheel), held in
    x, with the BEM in the time loop. Linear theory: the excess spin rate decays
    exponentially at 2 r^2 k / (I v0), k = -dFx/dxi per wheel (two wheels, torque -r Fx).

    - With k from quasi-static BEM solves at the steady state (force_and_tangent, a cold BEM
      state): the time loop (warm starts, the modified Newton with the calibrated tangent)
      reproduces the rate within 2 % (measured 0.1 %).
    - k against Kalker's f11 = G a b C11 of the Hertz ellipse at the wheel load: within 12 %
      (measured 7 % below: the centred S1002 / UIC60 1:40 gap is not quite Hertzian, the
      static spin of the contact angle makes part of the patch slip under the exact Coulomb
      law, and 0.75 mm elements resolve a ~ 6 mm).
    """
    tab = scenarios.wheel_table()
    inertia = 112.0
    sy = build_single_wheelset(
        tab,
        mass=1813.0,
        roll_inertia=1120.0,
        yaw_inertia=1120.0,
        ky=1e6,
        kx=2e6,
        half_spacing=1.0,
        axle_load=100e3,
        spin_inertia=inertia,
    )
    v0, jb = 30.0, sy.index("ws1_beta")
    i0 = int(np.argmin(np.abs(tab.y)))
    a1, b1, c11, r = (tab.data[QUANTITIES.index(k), 0, i0] for k in ("a1", "b1", "c11", "r"))
    with bem_state(sy) as st:
        q, v, w = static_equilibrium(sy, v0, "bem", bem=st, return_velocity=True)
        kick = v.copy()
        kick[jb] += 2e-3
        dfx = (force_and_tangent(sy, q, kick, v0, "bem")[1] - w)[W.index("Fx"), :, 0]
        k_bem = -dfx / (-2e-3 * r / v0)  # dxi = -dbetadot r / v0
        rate = 2 * r * r * k_bem.mean() / (inertia * v0)
        h = 0.1 / rate
        res = simulate(
            sy,
            v0,
            2.0 / rate,
            contact="bem",
            bem=st,
            q0=q,
            v0=kick,
            h=h,
            output_dt=h,
            tol=1e-12,
            progress=False,
        )
    # the BEM did the work: solves, or linear updates from its patch Jacobians
    assert res.stats["bem_normal_solves"] + res.stats["bem_linear_updates"] >= 2 * res.stats["steps"]
    assert res.stats["bem_normal_solves"] > 0
    excess = res.v[:, jb] - v[jb]
    assert 0 < excess[-1] < 0.2 * excess[0]
    assert -np.polyfit(res.t, np.log(excess), 1)[0] == pytest.approx(rate, rel=0.02)
    n = w[W.index("N_tread"), :, 0]
    f11 = tab.material.shear_modulus * a1 * b1 * n ** (2 / 3) * c11
    np.testing.assert_allclose(k_bem, f11, rtol=0.12)


@pytest.mark.parametrize("offset", [0.0, 0.003])
def test_bem_patch_jacobian_matches_central_differences_of_the_solves(coach_system, offset):
    """The Newton tangent's linear model of a BEM patch (issue 18): its Jacobian over
    (approach, relative roll, xi, eta, spin, lateral position), forward differences of the
    point's own solves on its window warm-started from the solution, against central
    differences of independent full-grid solves (BemState.probe) with twice the steps, at
    the leading wheelset's tread points, centred (the wide non-Hertzian patch) and 3 mm off
    centre, with a lateral velocity (eta ~ 1e-4). Each column's predicted change over a step
    agrees within 3 % plus the solvers' noise (tol_normal, tol_rolling of the traction bound
    mu Fn, 10x; a lever arm of 1 cm for the moments); the probe at the base reproduces the
    time loop's solve within tol_normal."""
    sy = coach_system
    qs, _ = static_equilibrium(sy, V)
    q = lateral_disturbance(sy, qs, offset, wheelsets=(0,))
    v = np.zeros(sy.n)
    v[sy.dof_names.index("ws1_y")] = 1e-4 * V
    o = BemOptions(jacobian_age=1)  # a Jacobian at every solve: at the base
    with bem_state(sy, o) as st:
        _force_and_tangent(sy, q, v, V, "bem", 8, st)
        for wheel in (0, 1):
            lm = st.linear_model(0, wheel, 0)
            x0, jac = lm["x"], lm["jac"]
            fn = lm["y"][0]
            assert st.probe(0, wheel, 0, x0)[0] == pytest.approx(fn, rel=o.tol_normal)
            steps = np.array([4e-3 * x0[0], 4e-5, 4e-5, 4e-5, 1e-2, 0.2])
            cd = np.empty((6, 6))
            for j, d in enumerate(steps):
                e = np.zeros(6)
                e[j] = d
                cd[:, j] = (st.probe(0, wheel, 0, x0 + e) - st.probe(0, wheel, 0, x0 - e)) / (2 * d)
            ft = 10 * o.tol_rolling * 0.3 * fn
            noise = np.array([10 * o.tol_normal * fn, ft, ft, 0.01 * ft, 1e-7 * fn, 1e-7 * fn])
            err = np.abs(jac - cd) * steps
            assert (err <= 0.03 * np.abs(cd) * steps + noise[:, None]).all(), (wheel, jac, cd)
            # the columns are not noise: each input moves its own force well above it
            for i, j in [(0, 0), (1, 2), (2, 3), (2, 4), (5, 1), (0, 5)]:
                assert abs(cd[i, j]) * steps[j] > 10 * noise[i]
        assert st.counts()["normal_solves"] > 0
    with bem_state(sy, BemOptions(jacobian_age=0)) as st:
        _force_and_tangent(sy, q, v, V, "bem", 8, st)
        assert st.linear_model(0, 0, 0) is None


def test_bem_run_does_not_depend_on_the_chunking(coach_system, monkeypatch):
    """The time loop runs in calls sized by wall time; a BEM run cut into 3-step calls gives
    the same numbers, bit for bit, as one call (each call used to re-evaluate the force at
    its start, whose BEM solves moved the warm starts: results then differed by the solvers'
    tolerance and depended on the machine's load)."""
    sy = coach_system
    opts = BemOptions(dx=1.5e-3)
    with bem_state(sy, opts) as st:
        qs, _ = static_equilibrium(sy, V, "bem", bem=st)
    q0 = lateral_disturbance(sy, qs, 0.004, wheelsets=(0, 1))
    runs = []
    for size in (3, 10_000):
        monkeypatch.setattr(
            time_loop, "_next_chunk", lambda ns, wall, plan, size=size: min(size, plan.per_chunk)
        )
        monkeypatch.setattr(time_loop, "CHUNK_SECONDS", 0.0)
        with bem_state(sy, opts) as st:
            runs.append(
                simulate(
                    sy,
                    V,
                    0.012,
                    contact="bem",
                    bem=st,
                    q0=q0,
                    h=1e-3,
                    output_dt=1e-3,
                    progress=size == 3,
                    chunk=0.003,
                    threads=1,
                )
            )
    assert runs[0].stats["newton_iterations"] > 0
    np.testing.assert_array_equal(runs[0].q, runs[1].q)
    np.testing.assert_array_equal(runs[0].wheel, runs[1].wheel)


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
    with pytest.raises(InputError, match="jacobian_age"):
        BemOptions(jacobian_age=-1)
    with pytest.raises(InputError, match="bem_options"):
        simulate(scenarios.coach_system(), V, 0.01, contact="bem", bem_options="fine")
