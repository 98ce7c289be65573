"""The wheelsets' longitudinal (x) and spin-perturbation (beta) DOFs: layout, free rolling,
the spin-rate decay against the creep law, the longitudinal oscillation on the primary kx."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from railvti import scenarios
from railvti.errors import InputError
from railvti.vehicle import (
    Coach,
    build_coach,
    build_single_wheelset,
    linearised_table,
    simulate,
    static_equilibrium,
)
from railvti.vehicle.model import WHEEL_OUTPUTS as W
from railvti.vehicle.table import QUANTITIES

V = 200 / 3.6
WS = dict(mass=1813.0, roll_inertia=1120.0, yaw_inertia=1120.0)
IWY = 112.0  # Manchester benchmark wheelset pitch inertia (Iwnicki 1998)


def test_dof_layout_53_and_the_old_45():
    tab = scenarios.wheel_table()
    sy = build_coach(Coach(), tab)
    assert sy.n == 53
    assert sy.dof_names[17:23] == ("ws1_x", "ws1_y", "ws1_z", "ws1_roll", "ws1_yaw", "ws1_beta")
    assert sy.dof_names[41] == "track1_y" and sy.dof_names[-1] == "track4_roll"
    # iws rows (y, z, roll, yaw, x, beta), 1-based
    assert list(sy.iws[:, 0]) == [19, 20, 21, 22, 18, 23]
    assert sy.m[sy.index("ws2_beta"), sy.index("ws2_beta")] == Coach().params["wheelset_pitch_inertia"]
    assert sy.m[sy.index("ws2_x"), sy.index("ws2_x")] == Coach().params["wheelset_mass"]
    # x on the primary longitudinal springs: 2 kx (two axleboxes); beta has no stiffness
    kx = Coach().params["primary_kx"]
    assert sy.k[sy.index("ws3_x"), sy.index("ws3_x")] == pytest.approx(2 * kx)
    assert not sy.k[sy.index("ws3_beta")].any() and not sy.k[:, sy.index("ws3_beta")].any()
    # the bogie's pitch moves the axlebox along x: coupling ws x - bogie pitch
    assert sy.k[sy.index("ws1_x"), sy.index("bogie1_pitch")] != 0.0
    s4 = build_coach(Coach(), tab, wheelset_dofs=4)
    assert s4.n == 45 and "ws1_x" not in s4.dof_names
    assert list(s4.iws[:, 0]) == [18, 19, 20, 21, 0, 0]
    with pytest.raises(InputError, match="wheelset_dofs"):
        build_coach(Coach(), tab, wheelset_dofs=5)


@pytest.mark.parametrize("contact", ["hertz-kalker", "hertz-fastsim"])
def test_centred_running_free_rolling(contact):
    c = scenarios.centred_running(200.0, contact=contact, duration=0.2, progress=False)
    assert c.q_error < 1e-3
    r0 = scenarios.wheel_table().r0
    fx = c.run.wheel_output("Fx")[-1]
    # free rolling: the moments about the axle balance, r Fx against the axle components
    # -sg sin(delta) Mz of the spin moments (FASTSIM's, applied since issue 13)
    ms = c.run.wheel_output("M_spin")[-1]
    dl = c.run.wheel_output("contact_angle")[-1]
    axle = -(np.array([[1.0], [-1.0]]) * np.sin(dl) * ms).sum(axis=0)
    assert np.abs(fx.sum(axis=0) * r0 - axle).max() < 1e-6 * c.static_wheel_load * r0
    assert np.abs(c.Y.sum(axis=0)).max() < 1e-6 * c.static_wheel_load


def test_bem_centred_running_relaxes_the_spin_loaded_fx():
    """The non-elliptic spin-loaded BEM patch gives Fx ~ 2 kN per wheel (same sign) with the
    rolling speed imposed (4 DOF wheelsets); with beta free the wheelset's rolling speed
    adjusts until sum r Fx = 0: Fx ~ 0 on both wheels (measured < 0.2 N after 0.02 s)."""
    tab = scenarios.wheel_table()
    s4 = build_coach(Coach(), tab, wheelset_dofs=4)
    _, w4 = static_equilibrium(s4, V, "bem")
    assert np.abs(w4[W.index("Fx")]).min() > 1000.0  # measured 1978 N
    c = scenarios.centred_running(200.0, contact="bem", duration=0.02, progress=False)
    fx = c.run.wheel_output("Fx")[-1]
    assert np.abs(fx).max() < 5.0
    assert np.abs(fx.sum(axis=0) * tab.r0).max() < 1.0
    assert c.q_error < 1e-3
    # the spin rate that frees the rolling: xi = -betadot r / v0 ~ 1.6e-4 (the patch's own)
    jb = c.run.dof_names.index("ws1_beta")
    assert c.run.v[-1, jb] < -1e-3


def _single(v0, *, longitudinal, spin, kx=2e6):
    tab = linearised_table(scenarios.wheel_table(), 0.2, gravitational=False, spin=False)
    sy = build_single_wheelset(
        tab,
        ky=1e6,
        kx=kx,
        half_spacing=1.0,
        axle_load=100e3,
        longitudinal=longitudinal,
        spin_inertia=IWY if spin else None,
        **WS,
    )
    q, v, wout = static_equilibrium(sy, v0, return_velocity=True)
    i0 = int(np.argmin(np.abs(tab.y)))
    a, b = wout[W.index("a"), 0, 0], wout[W.index("b"), 0, 0]
    f11 = tab.material.shear_modulus * a * b * tab.data[QUANTITIES.index("c11"), 0, i0]
    r = tab.data[QUANTITIES.index("r"), 0, i0]
    return sy, q, v, f11, r


def test_spin_rate_decays_at_the_creep_law_rate():
    """Imposed betadot on a wheelset held in x: I betadot' = -2 r^2 f11 betadot / v0 (two
    wheels, Kalker's linear law, small creepage): exponential decay at 2 r^2 f11 / (I v0)."""
    v0 = 30.0
    sy, q, v, f11, r = _single(v0, longitudinal=False, spin=True)
    rate = 2 * r * r * f11 / (IWY * v0)
    jb = sy.index("ws1_beta")
    v[jb] = 2e-3  # xi = 3e-5: far from saturation
    h = 0.02 / rate
    res = simulate(sy, v0, 3.0 / rate, q0=q, v0=v, h=h, output_dt=h, tol=1e-13, progress=False)
    bd = res.v[:, jb]
    fit = -np.polyfit(res.t, np.log(bd), 1)[0]
    assert fit == pytest.approx(rate, rel=0.01)
    assert rate > 1000.0  # the stiff mode: ~1/ms at 108 km/h


@pytest.mark.parametrize("kmh", [50.0, 400.0])
def test_spin_mode_stable_and_accurate_at_the_default_step(kmh):
    """A 0.05 rad/s spin kick on the coach's second wheelset at h = 1 ms (spin decay rate * h
    up to ~3 at 50 km/h: beyond the trapezoidal rule's accuracy, inside its A-stability):
    the run stays bounded, and the wheelset's x (the kick goes into its rolling oscillation on
    the primary kx) follows a h = 0.25 ms reference within 10 % of its peak (measured 4.4 %
    at 50 km/h, 1.9 % at 400 km/h)."""
    sy = scenarios.coach_system()
    q, v, _ = static_equilibrium(sy, kmh / 3.6, return_velocity=True)
    jb, jx = sy.index("ws2_beta"), sy.index("ws2_x")
    v[jb] += 0.05
    runs = [
        simulate(sy, kmh / 3.6, 0.05, q0=q, v0=v, h=h, output_dt=1e-3, progress=False) for h in (1e-3, 2.5e-4)
    ]
    assert np.isfinite(runs[0].q).all()
    # the kick decays about the static spin (the strips' rolling radius differs from r0)
    assert np.abs(runs[0].v[:, jb] - (v[jb] - 0.05)).max() < 0.05
    peak = np.abs(runs[1].q[:, jx]).max()
    assert peak > 1e-5
    assert np.abs(runs[0].q[:, jx] - runs[1].q[:, jx]).max() < 0.1 * peak


def test_longitudinal_offset_oscillates_against_kx_as_linear_theory():
    """Wheelset released 5 um off its x position on springs 2 kx, free to spin: the linear
    model  m x'' = -2 kx x - 2 f11 (x' - r beta') / v0,  I beta'' = 2 r f11 (x' - r beta') / v0
    (Fx = -f11 xi per wheel, torque -r Fx) against the nonlinear simulation."""
    v0 = 30.0
    kx = 2e7
    sy, q, v, f11, r = _single(v0, longitudinal=True, spin=True, kx=kx)
    m = WS["mass"]
    c = 2 * f11 / v0
    # state (x, beta, xdot, betadot)
    a = np.array(
        [
            [0, 0, 1, 0],
            [0, 0, 0, 1],
            [-2 * kx / m, 0, -c / m, c * r / m],
            [0, 0, c * r / IWY, -c * r * r / IWY],
        ]
    )
    jx = sy.index("ws1_x")
    x0 = 5e-6
    qs = q[jx]
    q[jx] = qs + x0
    res = simulate(sy, v0, 0.15, q0=q, v0=v, h=1e-4, output_dt=1e-3, tol=1e-14, progress=False)
    ref = np.array([(expm(a * t) @ [x0, 0, 0, 0])[0] for t in res.t])
    x = res.q[:, jx] - qs
    assert np.abs(x - ref).max() < 0.02 * x0
    # it rolls to and fro on the creep (effective mass m + I / r^2), lightly damped by the
    # small sliding part: the period of the rolling oscillator within 3 %
    up = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    period = np.mean(np.diff(res.t[up]))
    assert period == pytest.approx(2 * np.pi / np.sqrt(2 * kx / (m + IWY / r**2)), rel=0.03)
    assert x.min() < -0.5 * x0
