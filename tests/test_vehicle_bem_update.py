"""Linear updates of the BEM patches in the time loop (issue 33, ``BemOptions.update_band``):
a patch whose inputs moved little since its last solve takes its forces from its linear model
instead of a solve (vehicle_bem.f90, bem_update). Checked against full solves of the same
problems (BemState.probe) and against the run that solves every patch."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.vehicle import BemOptions, bem_state, lateral_disturbance, simulate, static_equilibrium
from railvti.vehicle.equilibrium import _force_and_tangent

V = 300 / 3.6
#: A coarse grid keeps the runs short.
COARSE = BemOptions(dx=1.5e-3)


@pytest.fixture(scope="module")
def coach_system():
    return scenarios.coach_system(geometry="table")


def _band_steps(st, wheel: int, band: float):
    """The leading wheelset's linear model at ``wheel`` (inputs x0, forces y0, Jacobian) and
    each input's step at the band's limit: its largest term of the model = band x Fn (the
    last three outputs' limit 0.01 of that)."""
    lm = st.linear_model(0, wheel, 0)
    x0, y0, jac = lm["x"], lm["y"], lm["jac"]
    lim = band * y0[0] * np.array([1, 1, 1, 0.01, 0.01, 0.01])
    step = np.array([np.min(lim / np.maximum(np.abs(jac[:, i]), 1e-300)) for i in range(6)])
    return x0, y0, jac, step


def test_linear_model_inside_the_band_matches_the_solves(coach_system):
    """At the edge of the default band (each input's own first-order force change = band x
    Fn, all six inputs moved at once, in both directions) the linear model's forces agree
    with full solves of the moved problem (BemState.probe) within 10 % of the band's force
    change, band Fn (the model's error is second order in the moves, plus the solvers' own
    tolerances: measured up to 6 % of it, in Fx), at the leading wheelset's tread points
    3 mm off centre with a lateral velocity."""
    sy = coach_system
    qs, _ = static_equilibrium(sy, V)
    q = lateral_disturbance(sy, qs, 0.003, wheelsets=(0,))
    v = np.zeros(sy.n)
    v[sy.dof_names.index("ws1_y")] = 1e-4 * V
    o = BemOptions(jacobian_age=1)
    band = BemOptions().update_band
    with bem_state(sy, o) as st:
        _force_and_tangent(sy, q, v, V, "bem", 8, st)
        for wheel in (0, 1):
            x0, y0, jac, step = _band_steps(st, wheel, band)
            fn = y0[0]
            step[5] = min(step[5], 1.0)  # within one table node
            worst = 0.0
            for sign in (1.0, -1.0):
                e = sign * step
                lin = y0 + jac @ e
                full = st.probe(0, wheel, 0, x0 + e)
                worst = max(worst, float(np.max(np.abs(full[:3] - lin[:3]))))
                assert np.all(np.abs(full[:3] - lin[:3]) <= 0.1 * band * fn), (wheel, sign, full, lin)
            # the test can fail: the moves change the forces well beyond the error allowed
            assert np.max(np.abs((jac @ step)[:3])) > 0.5 * band * fn
            assert worst > 0.0


def _run(sy, q0, duration, band, reach=0.0):
    o = BemOptions(dx=1.5e-3, update_band=band, update_reach=reach)
    return simulate(sy, V, duration, contact="bem", q0=q0, bem_options=o, threads=1)


def test_centred_run_with_linear_updates_follows_the_solved_run(coach_system):
    """Centred running at 300 km/h from the static equilibrium, 0.4 s, 1.5 mm grid: once the
    start's transient has passed, most patch evaluations are linear updates (the run solves
    fewer patches than the one that solves every patch, update_band=0, Jacobians included),
    and the leading wheelset's lateral displacement and the wheel forces follow that run
    within 1e-8 m, 5 N (Q) and 2 N (Y) (measured: 2e-9 m, 0.4 N, 0.3 N); the model's force
    error measured at the solves within twice the band stays below 0.1 % of the wheel load
    (measured 3.4 N)."""
    sy = coach_system
    q0, _ = static_equilibrium(sy, V)
    ref = _run(sy, q0, 0.4, 0.0)
    upd = _run(sy, q0, 0.4, COARSE.update_band)  # the band alone (update_reach=0)
    assert ref.stats["bem_linear_updates"] == 0
    assert upd.stats["bem_linear_updates"] > 0.3 * ref.stats["bem_normal_solves"]
    assert upd.stats["bem_normal_solves"] < 0.7 * ref.stats["bem_normal_solves"]
    assert 0.0 < upd.stats["bem_max_linear_error"] < 1e-3 * sy.wheel_load
    np.testing.assert_allclose(upd.y_ws1, ref.y_ws1, rtol=0, atol=1e-8)
    np.testing.assert_allclose(upd.Q, ref.Q, rtol=0, atol=5.0)
    np.testing.assert_allclose(upd.Y, ref.Y, rtol=0, atol=2.0)
    # the loads move (the start's vertical transient): the comparison is not of two constants
    assert np.ptp(ref.Q) > 1e3
    # with the reach (the default): fewer solves still, within Newton's tolerance of 1e-8 m
    # (the lateral motion is of that size: 1.4e-9 m), 5 N and 2 N (measured: 1.06e-8 m,
    # 1.0 N, 0.26 N; 1692 normal solves against 2804 with the band alone, 5088 without)
    rch = _run(sy, q0, 0.4, COARSE.update_band, COARSE.update_reach)
    assert rch.stats["bem_normal_solves"] < 0.8 * upd.stats["bem_normal_solves"]
    np.testing.assert_allclose(rch.y_ws1, ref.y_ws1, rtol=0, atol=3e-8)
    np.testing.assert_allclose(rch.Q, ref.Q, rtol=0, atol=5.0)
    np.testing.assert_allclose(rch.Y, ref.Y, rtol=0, atol=2.0)


def test_released_run_with_linear_updates_follows_the_solved_run(coach_system):
    """Hunting at 300 km/h released from 4 mm, 0.05 s (fast motion: few updates), 1.5 mm grid:
    y_ws1 within 1e-8 m and Q within 25 N of the run that solves every patch (measured:
    3e-10 m, 0.01 N; Newton's tolerance of 1e-8 m alone moves Q by ~12 N: 1e-9 against 1e-8
    on the 0.75 mm grid, 3 s)."""
    sy = coach_system
    qs, _ = static_equilibrium(sy, V)
    q0 = lateral_disturbance(sy, qs, 0.004, wheelsets=(0, 1))
    ref = _run(sy, q0, 0.05, 0.0)
    for reach in (0.0, COARSE.update_reach):
        upd = _run(sy, q0, 0.05, COARSE.update_band, reach)
        assert upd.stats["bem_linear_updates"] > 0
        np.testing.assert_allclose(upd.y_ws1, ref.y_ws1, rtol=0, atol=1e-8)
        np.testing.assert_allclose(upd.Q, ref.Q, rtol=0, atol=25.0)
    assert np.ptp(ref.y_ws1) > 1e-4


def test_static_equilibrium_solves_every_patch(coach_system):
    """The static equilibrium takes no linear updates (band switched off during it, and
    restored): the same state to the bit as with update_band=0."""
    sy = coach_system
    with bem_state(sy, COARSE) as st:
        qa, _ = static_equilibrium(sy, V, "bem", bem=st)
        assert st.counts()["linear_updates"] == 0
        assert st.update_band == COARSE.update_band
    qb, _ = static_equilibrium(sy, V, "bem", bem_options=BemOptions(dx=1.5e-3, update_band=0.0))
    np.testing.assert_array_equal(qa, qb)


def test_update_band_is_checked():
    for bad in (-1e-3, 1.0, float("nan"), "2e-3"):
        with pytest.raises(InputError, match="update_band"):
            BemOptions(update_band=bad)


def test_linear_model_within_the_reach_matches_the_solves(coach_system):
    """Updates in motion (``update_reach``): at the reach's edge for the gap's inputs
    (approach, roll, lateral position within the node: each input's own first-order force
    change = reach x band x Fn, moved at once, both directions; creepages within the band),
    with a Jacobian made at the base, the linear model's forces agree with full solves of the
    moved problem (BemState.probe) within 2 band x Fn (40-42 N at these 40-42 kN patches,
    where the moves change Fn by 360-460 N; measured up to 22.6 N, in Fx, 1.1 band x Fn:
    the error the reach admits is ~20 times the band's)."""
    sy = coach_system
    qs, _ = static_equilibrium(sy, V)
    q = lateral_disturbance(sy, qs, 0.003, wheelsets=(0,))
    v = np.zeros(sy.n)
    v[sy.dof_names.index("ws1_y")] = 1e-4 * V
    o = BemOptions(jacobian_age=1)
    band, reach = o.update_band, o.update_reach
    with bem_state(sy, o) as st:
        _force_and_tangent(sy, q, v, V, "bem", 8, st)
        for wheel in (0, 1):
            x0, y0, jac, step = _band_steps(st, wheel, band)
            fn = y0[0]
            step[[0, 1, 5]] *= reach
            # the lateral position stays in its table cell (the updates' condition)
            s0 = x0[5] - np.floor(x0[5])
            worst = 0.0
            for sign in (1.0, -1.0):
                e = sign * step
                e[5] = np.clip(e[5], -0.99 * s0, 0.99 * (1.0 - s0))
                lin = y0 + jac @ e
                full = st.probe(0, wheel, 0, x0 + e)
                err = float(np.max(np.abs(full[:3] - lin[:3])))
                worst = max(worst, err)
                assert err <= 2.0 * band * fn, (wheel, sign, full, lin)
                # the test can fail: the gap's moves change Fn by far more than the error allowed
                assert abs(full[0] - y0[0]) > 0.3 * reach * band * fn
            assert worst > 0.0


def test_ring_run_with_updates_in_motion_follows_the_solved_run():
    """On the ring track (model RF, 40 sleepers, coarse rail mesh, 1.5 mm grid), released from
    1 mm at 300 km/h, 0.1 s: the sleeper passing moves the patches' approach beyond the band
    every step; with the reach (the default) more patches are updates and fewer solved than
    with the band alone, and y_ws1, Q and Y follow the run that solves every patch within
    1e-8 m, 5 N and 5 N (measured: 2.6e-9 m, 0.42 N, 1.8 N; the band alone 2.2e-9 m, 0.12 N,
    0.33 N)."""
    from railvti.vehicle import systems
    from railvti.vehicle.params import Coach
    from railvti.vehicle.ring_coupling import build_rf

    track = dict(kappa_max=30.0, mesh_max_area=4e-4, arc_step=12e-3, f_max=500.0)
    sy = build_rf(Coach(), scenarios.wheel_table(), V, systems.ring_track(40, track), f_limit=300.0)
    qs, _ = static_equilibrium(sy, V, "bem", bem_options=COARSE)
    q0 = lateral_disturbance(sy, qs, 0.001, wheelsets=(0, 1))
    ref = _run(sy, q0, 0.1, 0.0)
    band = _run(sy, q0, 0.1, COARSE.update_band)
    rch = _run(sy, q0, 0.1, COARSE.update_band, COARSE.update_reach)
    assert rch.stats["bem_linear_updates"] > 3 * band.stats["bem_linear_updates"]
    assert rch.stats["bem_normal_solves"] < 0.95 * band.stats["bem_normal_solves"]
    np.testing.assert_allclose(rch.y_ws1, ref.y_ws1, rtol=0, atol=1e-8)
    np.testing.assert_allclose(rch.Q, ref.Q, rtol=0, atol=5.0)
    np.testing.assert_allclose(rch.Y, ref.Y, rtol=0, atol=5.0)
    assert np.ptp(ref.Q) > 1e3 and np.ptp(ref.y_ws1) > 1e-4


def test_update_reach_is_checked():
    for bad in (-1.0, float("inf"), float("nan"), "20", True):
        with pytest.raises(InputError, match="update_reach"):
            BemOptions(update_reach=bad)
