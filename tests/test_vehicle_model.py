"""Vehicle-track model RR: contact kernel, tangent, centred running, hunting, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.errors import ConvergenceError, InputError
from railvti.material import STEEL
from railvti.contact.hertz import hertz
from railvti.vehicle import (
    Coach,
    DivergenceError,
    build_single_wheelset,
    force_and_tangent,
    lateral_disturbance,
    simulate,
    static_equilibrium,
)
from railvti.vehicle.table import QUANTITIES


@pytest.fixture(scope="module")
def table():
    return scenarios.wheel_table()


@pytest.fixture(scope="module")
def coach_system():
    return scenarios.coach_system()


def test_table_hertz_constants_match_hertz(table):
    """a1, kH of the table reproduce railvti.contact.hertz from the profile curvatures."""
    from railvti.geometry import layout

    wheel, rail = systems.profiles()
    lay = layout(wheel, rail)
    i = int(np.argmin(np.abs(table.y + 0.002)))  # tread contact, ratio inside the clip
    s = table.s_wheel[0, i]
    a1, kh, dl, r, l = (table.data[QUANTITIES.index(n), 0, i] for n in ("a1", "kH", "delta", "r", "l"))
    yrail = table.y[i] + l - lay.rail_offset
    A = math.cos(dl) / (2 * r)
    B = 0.5 * (float(rail.curvature(yrail)) - float(wheel.curvature(s)))
    fn = 60e3
    h = hertz(A, B, fn, STEEL)
    assert h.a == pytest.approx(a1 * fn ** (1 / 3), rel=3e-3)
    assert h.approach == pytest.approx((fn / kh) ** (2 / 3), rel=3e-3)


def test_single_wheelset_static_load_and_approach(table):
    """Q equals the applied load; the wheelset sinks by the gap plus the Hertz approach."""
    sy = build_single_wheelset(
        table,
        mass=1800.0,
        roll_inertia=1100.0,
        yaw_inertia=1100.0,
        ky=1e6,
        kx=1e6,
        half_spacing=1.0,
        axle_load=100e3,
    )
    q, wout = static_equilibrium(sy, 30.0)
    load = 0.5 * (1800.0 * 9.81 + 100e3)
    assert wout[0, :, 0] == pytest.approx([load, load], rel=1e-9)
    i0 = int(np.argmin(np.abs(table.y)))
    g0, dl, kh = table.data[0, 0, i0], table.data[2, 0, i0], table.data[6, 0, i0]
    n = load / math.cos(dl)  # approximately: the spin creep force tilts it slightly
    dn = (n / kh) ** (2 / 3)
    assert q[1] == pytest.approx(-g0 - dn / math.cos(dl), rel=2e-3)
    assert abs(q[0]) < 1e-9 and abs(q[2]) < 1e-9


def test_tangent_matches_central_differences(coach_system):
    sy = coach_system
    q, _ = static_equilibrium(sy, 80.0)
    q = lateral_disturbance(sy, q, 0.00213)  # inside a table cell (linear interpolation)
    rng = np.random.default_rng(1)
    v = rng.normal(scale=0.01, size=sy.n)
    f, _, jq, jv = force_and_tangent(sy, q, v, 80.0)
    j = sy.index("ws1_y")
    e = 1e-7
    qp, qm = q.copy(), q.copy()
    qp[j] += e
    qm[j] -= e
    fd = (force_and_tangent(sy, qp, v, 80.0)[0] - force_and_tangent(sy, qm, v, 80.0)[0]) / (2 * e)
    assert np.allclose(jq[:, j], fd, rtol=1e-3, atol=1e-3 * np.abs(fd).max())
    j = sy.index("ws1_yaw")
    vp, vm = v.copy(), v.copy()
    vp[j] += 1e-6
    vm[j] -= 1e-6
    fd = (force_and_tangent(sy, q, vp, 80.0)[0] - force_and_tangent(sy, q, vm, 80.0)[0]) / 2e-6
    assert np.allclose(jv[:, j], fd, rtol=1e-3, atol=1e-3 * np.abs(fd).max())


@pytest.mark.parametrize("contact", ["hertz-kalker", "hertz-fastsim"])
def test_centred_running_200(contact):
    c = scenarios.centred_running(200.0, contact=contact, duration=0.2, progress=False)
    assert c.q_error < 1e-3  # acceptance: 0.1 %
    assert np.abs(c.Y.sum(axis=0)).max() < 1e-6 * c.static_wheel_load  # net lateral per axle
    assert np.allclose(c.Y[0], -c.Y[1], atol=1e-6 * c.static_wheel_load)
    assert np.abs(c.run.y_ws1).max() < 1e-9


def test_hunting_decays_at_low_speed_and_cycles_with_flange_at_high_speed():
    slow = scenarios.hunting(120.0, duration=2.0, y0=0.003, progress=False)
    assert scenarios.amplitude(slow, 0.5) < 0.05 * 0.003
    fast = scenarios.hunting(420.0, duration=2.5, y0=0.004, progress=False)
    amp = scenarios.amplitude(fast, 0.5)
    assert 5e-3 < amp < 10e-3  # of the order of the flange clearance
    assert fast.wheel_output("N_flange")[fast.t > 1.5].max() > 10e3
    assert np.isfinite(fast.q).all()


def test_linear_critical_speed_brackets_growth(table):
    v, f = scenarios.linear_critical_speed_kmh(tol_kmh=2.0)
    assert 150 < v < 600 and 2.0 < f < 12.0
    from railvti.vehicle import eigenvalues

    sy = scenarios.coach_system(linear_conicity=scenarios.equivalent_conicity(0.003))
    osc = lambda ev: ev[(np.abs(ev.imag) > 0.1) & (np.abs(ev.imag) < 2 * np.pi * 20)].real.max()  # noqa: E731
    assert osc(eigenvalues(sy, (v - 10) / 3.6)) < 0 < osc(eigenvalues(sy, (v + 10) / 3.6))


# --- bad input -------------------------------------------------------------------------
def test_unknown_parameter_suggests():
    with pytest.raises(InputError, match="did you mean 'carbody_mass'"):
        Coach(carbody_mas=1.0)


@pytest.mark.parametrize("name", ["carbody_mass", "wheelset_mass", "primary_kz"])
def test_negative_values_rejected(name):
    with pytest.raises(InputError, match=name):
        Coach(**{name: -1.0})


@pytest.mark.parametrize("speed", [0.0, -50.0, float("nan")])
def test_speed_must_be_positive(speed):
    with pytest.raises(InputError, match="speed"):
        scenarios.centred_running(speed)


@pytest.mark.parametrize("maxsub", [-1, 21, 2.5, True, "6"])
def test_maxsub_must_be_a_small_nonnegative_integer(maxsub):
    with pytest.raises(InputError, match="maxsub"):
        scenarios.hunting(300.0, duration=0.01, maxsub=maxsub, progress=False)


def test_unknown_contact_and_variant():
    with pytest.raises(InputError, match="unknown contact"):
        scenarios.hunting(300.0, contact="carter")
    with pytest.raises(InputError, match="unknown variant"):
        scenarios.hunting(300.0, variant="FX")


def test_model_is_sent_once_and_freed_with_its_system(table):
    """The System reaches Fortran through one handle, reused by every call and freed with
    the System; a closed or foreign handle is STAT_BAD_HANDLE -> InputError; a System whose
    DOF map points outside its matrices is refused when it is sent."""
    import gc
    import weakref
    from dataclasses import replace
    from railvti._status import Status, check
    from railvti.vehicle.model import CallSettings

    sy = build_single_wheelset(
        table,
        mass=1800.0,
        roll_inertia=1100.0,
        yaw_inertia=1100.0,
        ky=1e6,
        kx=1e6,
        half_spacing=1.0,
        axle_load=100e3,
    )
    model = sy.native
    q, _ = static_equilibrium(sy, 30.0)
    simulate(sy, 30.0, 0.01, q0=q, progress=False)
    assert sy.native is model  # one model for every call
    with pytest.raises(ValueError):
        sy.k[0, 0] = 1.0  # the sent arrays cannot change
    model.close()
    info = model.force(CallSettings(30.0, 1), q, np.zeros(sy.n))[-1]
    assert info == Status.BAD_HANDLE
    with pytest.raises(InputError, match="BAD_HANDLE"):
        check(info, "closed model")
    q2, _ = static_equilibrium(sy, 30.0)  # a new model on demand, same result
    assert np.array_equal(q, q2) and sy.native is not model
    ref = weakref.ref(sy.native)
    del sy
    gc.collect()
    assert ref() is None
    sy = build_single_wheelset(
        table,
        mass=1800.0,
        roll_inertia=1100.0,
        yaw_inertia=1100.0,
        ky=1e6,
        kx=1e6,
        half_spacing=1.0,
        axle_load=100e3,
    )
    with pytest.raises(InputError, match="BAD_ARGUMENT"):
        _ = replace(sy, iws=sy.iws + 10).native  # the property's check raises
    with pytest.raises(InputError, match="SIZE_MISMATCH"):
        check(sy.native.force(CallSettings(30.0, 1), np.zeros(3), np.zeros(3))[-1], "sizes")


def test_step_too_large_stops_with_clear_error(coach_system):
    sy = coach_system
    q, _ = static_equilibrium(sy, 400 / 3.6)
    q = lateral_disturbance(sy, q, 0.005)
    with pytest.raises(DivergenceError, match=r"t = .* s \(step \d+, h = 0.03 s\)") as exc:
        simulate(sy, 400 / 3.6, 3.0, h=0.03, q0=q, maxsub=0, progress=False)
    assert isinstance(exc.value, ConvergenceError)
    part = exc.value.result
    assert part is not None and np.isfinite(part.q).all()


def test_newton_stops_on_residual_as_well_as_correction(coach_system):
    """A step converges only with a small residual AND a small correction; both are reported.

    With the correction test switched off (tol = 1 m) the residual alone must hold every
    accepted step below rtol (checked from the reported maximum), and the trajectory must agree
    with the default (both tests) run to the size the residual bound allows; an rtol below the
    round-off of the residual cannot be met and the run must stop, not accept the step."""
    sy = coach_system
    v = 300 / 3.6
    q, _ = static_equilibrium(sy, v)
    q = lateral_disturbance(sy, q, 0.004)
    ref = simulate(sy, v, 0.2, q0=q, progress=False)
    st = ref.stats
    for k in ("newton_residual", "newton_residual_max", "newton_correction", "newton_correction_max"):
        assert np.isfinite(st[k]) and st[k] >= 0.0, k
    assert st["newton_correction_max"] <= st["newton_tol"]
    assert st["newton_residual_max"] <= st["newton_rtol"]
    assert st["load_scale"] == pytest.approx(sy.wheel_load)
    res_only = simulate(sy, v, 0.2, q0=q, tol=1.0, rtol=1e-7, progress=False)
    assert res_only.stats["newton_residual_max"] <= 1e-7
    assert np.max(np.abs(res_only.y_ws1 - ref.y_ws1)) < 1e-6  # 1 um of a 4 mm cycle
    with pytest.raises(DivergenceError, match="did not converge"):
        simulate(sy, v, 0.01, q0=q, rtol=1e-30, maxsub=0, progress=False)


def test_creepages_match_geometry_module(table):
    """Fortran creepages of a shifted, yawed, moving wheelset against railvti.geometry.creepages
    (full 3-D kinematics with yaw in the contact search)."""
    from railvti import geometry

    wheel, rail = systems.profiles()
    sy = build_single_wheelset(
        table,
        mass=1800.0,
        roll_inertia=1100.0,
        yaw_inertia=1100.0,
        ky=1e6,
        kx=1e6,
        half_spacing=1.0,
        axle_load=100e3,
    )
    speed, yaw = 50.0, 0.002
    q, _ = static_equilibrium(sy, speed)
    q = lateral_disturbance(sy, q, -0.002, (0,))
    q[3] = yaw
    v = np.array([0.05, 0.0, 0.01, 0.02])
    _, wout, _, _ = force_and_tangent(sy, q, v, speed)
    c = geometry.contact_points(wheel, rail, y=-0.002, yaw=yaw)
    assert q[2] == pytest.approx(c.pose.roll, rel=0.05)
    for side, w in (("left", 0), ("right", 1)):
        cr = geometry.creepages(
            c.wheel(side)[0],
            speed,
            lateral_velocity=0.05,
            yaw_rate=0.02,
            roll_rate=0.01,
            angular_velocity=speed / table.r0,
        )
        xi, eta, spin = wout[5:8, w, 0]
        assert abs(xi - cr.xi) < 2e-5
        assert eta == pytest.approx(cr.eta, rel=1e-2)
        assert spin == pytest.approx(cr.phi, rel=5e-2)


def test_flange_creepage_at_large_yaw_matches_geometry_module(table):
    """The yaw term of the lateral creepage at a flange contact, -psi / cos(delta) (the
    rolling about the yawed axle at a point that leads or lags the axle by r tan(delta) psi),
    against railvti.geometry.creepages (3-D contact search with yaw). At delta = 70 deg and
    psi = 10 mrad the term is -0.029; -psi cos(delta) would give -0.003.

    The same flange-flank point (delta 1.222 rad) is reached at y = 6.7 mm in the table (at
    nominal height and zero roll) and at 6.3 mm in the geometry module's rigid pose (the
    wheelset rolls as the flange takes the load): each model at its own y.
    """
    from railvti import geometry
    from railvti.vehicle.model import WHEEL_OUTPUTS as W

    wheel, rail = systems.profiles()
    sy = build_single_wheelset(
        table,
        mass=1800.0,
        roll_inertia=1100.0,
        yaw_inertia=1100.0,
        ky=1e6,
        kx=1e6,
        half_spacing=1.0,
        axle_load=100e3,
    )
    speed, v = 50.0, np.array([0.05, 0.0, 0.01, 0.02])
    qs, _ = static_equilibrium(sy, speed)
    eta_f, eta_g = [], []
    for yaw in (0.0, 0.01):
        q = lateral_disturbance(sy, qs, 0.0067, (0,))
        q[3] = yaw
        wout = force_and_tangent(sy, q, v, speed)[1][:, 0, 0]  # left wheel
        assert wout[W.index("N_flange")] > wout[W.index("N_tread")]  # reported: the flange
        c = geometry.contact_points(wheel, rail, y=0.0063, yaw=yaw)
        pt = max(c.wheel("left"), key=lambda p: p.contact_angle)
        assert wout[W.index("contact_angle")] == pytest.approx(pt.contact_angle, abs=5e-3)
        cr = geometry.creepages(
            pt, speed, lateral_velocity=0.05, yaw_rate=0.02, roll_rate=0.01, angular_velocity=speed / table.r0
        )
        eta_f.append(wout[W.index("eta")])
        eta_g.append(cr.eta)
        assert wout[W.index("spin")] == pytest.approx(cr.phi, rel=2e-2)
    assert eta_f[1] == pytest.approx(eta_g[1], rel=0.05)  # measured 3 %
    assert eta_f[1] - eta_f[0] == pytest.approx(eta_g[1] - eta_g[0], rel=0.05)


def test_friction_and_bumpstop_elements(coach_system):
    """Yaw friction torque T tanh(rate / w_eps) and the bump stop's force beyond its clearance."""
    sy = coach_system
    coach = Coach()
    q, _ = static_equilibrium(sy, 50.0)
    v = np.zeros(sy.n)
    ib, ic = sy.index("bolster1_yaw"), sy.index("carbody_yaw")
    v[ib] = 2e-3
    f0, _, _, _ = force_and_tangent(sy, q, np.zeros(sy.n), 50.0)
    f1, _, _, _ = force_and_tangent(sy, q, v, 50.0)
    t = coach["yaw_friction_torque"] * math.tanh(2e-3 / coach["yaw_friction_velocity"])
    assert f1[ib] - f0[ib] == pytest.approx(-t, rel=1e-9)
    assert f1[ic] - f0[ic] == pytest.approx(+t, rel=1e-9)
    # bogie 1 frame shifted laterally past the clearance: bump stop pushes it back
    jb = sy.index("bogie1_y")
    d = coach["bumpstop_clearance"] + 0.005
    qa, qb = q.copy(), q.copy()
    qa[jb] += 0.01
    qb[jb] += d
    fa = force_and_tangent(sy, qa, np.zeros(sy.n), 50.0)[0]
    fb = force_and_tangent(sy, qb, np.zeros(sy.n), 50.0)[0]
    lin = sy.k[jb, jb]
    extra = (fb[jb] - fa[jb]) + lin * (d - 0.01)
    assert extra == pytest.approx(-coach["bumpstop_stiffness"] * 0.005, rel=1e-6)


def test_every_default_names_its_source():
    """Each Coach default carries a source: a publication or 'assumption' (or the track fit,
    a standard constant, the regularisation, a model setting such as the stiff-limit
    scale); the Manchester values issue 13 quotes from
    Iwnicki 1998 (primary dampers 15 / 2 / 4 kN s/m, bump-stop clearance 25 mm) are the
    defaults."""
    from railvti.vehicle import DEFAULTS

    for name, (_value, unit, source) in DEFAULTS.items():
        assert unit and source, name
        assert (
            "Iwnicki 1998" in source
            or "assumption" in source
            or "TrackElement" in source
            or source in ("standard", "regularisation: torque = T tanh(rate / this)")
            or source.startswith("model setting:")
        ), name
    c = Coach()
    assert (c["primary_cx"], c["primary_cy"], c["primary_cz"]) == (15e3, 2e3, 4e3)
    assert c["bumpstop_clearance"] == 0.025
