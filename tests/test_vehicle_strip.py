"""The strip contact (railvti.vehicle.strip): against the half-space BEM, conservative, smooth,
mirror-symmetric, and bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.contact.wheelset import solve_wheelset
from railvti.errors import InputError
from railvti.material import STEEL
from railvti.vehicle import simulate, static_equilibrium
from railvti.vehicle.model import CallSettings
from railvti.vehicle.params import Coach
from railvti.vehicle.strip import STRIP_OUTPUTS, strip_geometry, strip_linearise, strip_wheel

N, DZ, P_MAX = (STRIP_OUTPUTS.index(k) for k in ("N", "dV_dz", "P_max"))


@pytest.fixture(scope="module")
def geo():
    w, r = systems.profiles()
    return strip_geometry(w, r)


def _height(geo, y: float, roll: float, fz: float) -> float:
    """The centre height at which the left wheel at shift y and roll carries fz."""
    lo, hi = -0.02, 0.02
    for _ in range(55):  # bisection: the load falls as the centre rises
        zc = 0.5 * (lo + hi)
        out, _ = strip_wheel(geo, y, zc, roll)
        lo, hi = (zc, hi) if -out[:, DZ].sum() > fz else (lo, zc)
    return zc


def _sink(geo, y: float, fz: float) -> float:
    """Vertical interference (from first touch) of the left wheel carrying fz at shift y."""
    out, _ = strip_wheel(geo, y, _height(geo, y, 0.0, fz), 0.0)
    return float(out[:, P_MAX].max())


def test_sink_matches_the_bem_on_the_tread(geo):
    """The wheel's sink under its static load within 6 % of the half-space BEM (0.5 mm grid,
    the whole patch) on the tread, across the band where the table's point jumps (y = 0.2 mm)
    and the table is up to 50 % off (validation/contact_table_stiffness.py)."""
    wheel, rail = systems.profiles()
    fz = Coach().static_wheel_load
    for y in (-3e-3, 0.0, 0.5e-3, 1.0e-3, 2.0e-3, 3.0e-3):
        bem = solve_wheelset(wheel, rail, y, 0.0, fz, None, None, STEEL, 0.5e-3, roll=0.0, side="left").sinks[
            0
        ]
        assert _sink(geo, y, fz) == pytest.approx(bem, rel=0.06), y


def test_forces_are_the_gradient_of_the_potential(geo):
    """The returned forces are -grad V (central differences of V), flange contact included:
    the contact is conservative."""
    for y, roll, fz in ((0.21e-3, 0.003, 5e4), (3e-3, -0.004, 7e4), (7e-3, 0.002, 9e4)):
        zc = _height(geo, y, roll, fz)
        out, _ = strip_wheel(geo, y, zc, roll)
        grad = out[:, 2:5].sum(axis=0)
        fd = []
        for k, h in enumerate((1e-7, 1e-8, 1e-7)):
            d = np.zeros(3)
            d[k] = h
            vp = strip_wheel(geo, y + d[0], zc + d[1], roll + d[2])[0][:, 1].sum()
            vm = strip_wheel(geo, y - d[0], zc - d[1], roll - d[2])[0][:, 1].sum()
            fd.append((vp - vm) / (2 * h))
        assert out[:, N].sum() > 1e3
        np.testing.assert_allclose(grad, fd, rtol=1e-5, atol=1e-5 * np.abs(grad).max())


def test_linearisation_is_the_derivative_of_the_outputs(geo):
    """The Newton tangent's linearisation (strip_linearise, forward mode) equals central
    differences of strip_wheel at steps small enough to stay between the rail spline's knots
    (the potential's Hessian varies on the 0.05 mm grid), for every output the contact reads,
    tread and flange; the Hessian of V is symmetric."""
    cols = [
        STRIP_OUTPUTS.index(k)
        for k in ("N", "V", "dV_dy", "dV_dz", "dV_droll", "l", "zarm", "delta", "r", "x", "A")
    ]
    for y, roll, fz in ((0.21e-3, 0.003, 5e4), (3e-3, -0.004, 7e4), (7e-3, 0.002, 9e4)):
        zc = _height(geo, y, roll, fz)
        out, d = strip_linearise(geo, y, zc, roll)
        # two code paths: equal to round-off (one element differs by 1 ulp under OpenBLAS's
        # SkylakeX kernels), not bit for bit
        ref = strip_wheel(geo, y, zc, roll)[0]
        assert np.all(np.abs(out - ref) <= 1e-12 * (np.abs(ref) + np.abs(ref).max(axis=0)))
        for k, h in enumerate((2e-10, 2e-10, 2e-10)):
            e = np.zeros(3)
            e[k] = h
            fd = (
                strip_wheel(geo, y + e[0], zc + e[1], roll + e[2])[0]
                - strip_wheel(geo, y - e[0], zc - e[1], roll - e[2])[0]
            ) / (2 * h)
            for i in cols:
                a, b = d[:, i, k], fd[:, i]
                scale = max(np.abs(d[:, i, :]).max(), 1e-12)
                np.testing.assert_allclose(
                    a, b, rtol=0, atol=2e-4 * scale, err_msg=f"{STRIP_OUTPUTS[i]} over pose {k} at y={y}"
                )
        hess = d[:, 2:5, :3].sum(axis=0)
        np.testing.assert_allclose(hess, hess.T, rtol=1e-12, atol=1e-12 * np.abs(hess).max())


def test_coarse_scan_misses_no_interference(geo):
    """The coarse scan (segments of 8 samples with a curvature bound) finds the deepest strip
    at random poses, tread to flange and rolled: the largest interference the strips report
    equals numpy's over every wheel sample (SciPy's spline of the rail through the same
    nodes, each sample's pose by its own rotation)."""
    from scipy.interpolate import CubicSpline

    ry = geo.rail_y0 + geo.rail_dy * np.arange(geo.rail_z.size)
    rail = CubicSpline(ry, geo.rail_z, bc_type=((2, geo.rail_m[0]), (2, geo.rail_m[-1])))
    rng = np.random.default_rng(3)
    y = rng.uniform(-0.012, 0.012, 300)
    zc = rng.uniform(-6e-4, 1e-4, 300)
    roll = rng.uniform(-0.02, 0.02, 300)
    out, _ = strip_wheel(geo, y, zc, roll)
    y0, z0 = geo.ws[0], geo.ws[1]
    c, s = np.cos(roll)[:, None], np.sin(roll)[:, None]
    yr = y[:, None] + c * y0 - s * z0 - geo.offset
    p = np.where(
        (yr >= ry[0]) & (yr <= ry[-1]),
        geo.top - rail(np.clip(yr, ry[0], ry[-1])) - (geo.r_nominal + zc[:, None] + s * y0 + c * z0),
        -np.inf,
    ).max(axis=1)
    touching = p > 0
    assert 50 < touching.sum() < 300
    np.testing.assert_allclose(out[touching][:, :, P_MAX].max(axis=1), p[touching], rtol=0, atol=1e-12)
    assert np.all(out[~touching][:, :, N] == 0.0)


def test_no_force_jump_where_the_table_point_jumps(geo):
    """Along y through the table's point jump (0.2 mm) at a fixed centre height the strip's
    vertical force has no jump: its change per micrometre changes by less than 5 % between
    neighbouring steps (a jump of 1 % of the load would be ten times the change itself)."""
    ys = np.arange(0.0, 0.5e-3, 1e-6)
    zc = _height(geo, 0.2e-3, 0.0, Coach().static_wheel_load)
    out, _ = strip_wheel(geo, ys, np.full(ys.size, zc), np.zeros(ys.size))
    fz = -out[..., DZ].sum(axis=-1)
    assert fz.min() > 2e4
    d = np.diff(fz)
    assert np.abs(np.diff(d)).max() < 0.05 * np.median(np.abs(d))


def test_the_right_wheel_mirrors_the_left():
    """A wheelset shifted and rolled one way gives the other wheel's forces mirrored when it
    is shifted and rolled the other way (vehicle y to the left)."""
    sy = scenarios.coach_system(geometry="strip")
    q, _ = static_equilibrium(sy, 50.0, "hertz-kalker")
    iy, ir = sy.index("ws1_y"), sy.index("ws1_roll")
    outs = []
    for s in (1.0, -1.0):
        x = q.copy()
        x[iy] += s * 2e-3
        x[ir] += s * 1e-3
        outs.append(sy.native.force(CallSettings(50.0, 1), x, np.zeros_like(x))[1])
    (a, b) = outs
    np.testing.assert_allclose(a[0, :, 0], b[0, ::-1, 0], rtol=1e-9)  # Q
    np.testing.assert_allclose(a[1, :, 0], -b[1, ::-1, 0], rtol=1e-9)  # Y


def test_undamped_frictionless_energy_is_conserved():
    """The undamped frictionless coach with the leading wheelset kicked 0.5 mm sideways keeps
    its energy within 1 % of the kick's, and halving the step more than halves what remains
    (the trapezoidal rule's oscillation of the stiff contact modes, not a drift; measured
    0.54 % and 0.21 %, the gyroscopic moments doing no work), where the table contact gains
    more than the kick's energy itself (it is not the gradient of a potential)."""
    rr_t = dataclasses.replace(scenarios.coach_system(geometry="table").without_damping(), friction=0.0)
    rr_s = dataclasses.replace(scenarios.coach_system(geometry="strip").without_damping(), friction=0.0)
    e_h = energy_drift(rr_s, 5e-4, 0.4)
    assert e_h < 1e-2
    assert energy_drift(rr_s, 2.5e-4, 0.4) < 0.5 * e_h
    assert energy_drift(rr_t, 5e-4, 0.4) > 1.0


def _energy(sy, q, v, wheel_energy) -> np.ndarray:
    """Kinetic + linear springs with their preload + the contacts' potential, J."""
    return (
        0.5 * np.einsum("ti,ij,tj->t", v, sy.m, v)
        + 0.5 * np.einsum("ti,ij,tj->t", q, sy.k, q)
        - q @ sy.f0
        + wheel_energy
    )


def energy_drift(sy, h: float, duration: float) -> float:
    """max |E - E0| over a run from the static state with ws1 kicked 0.5 mm to the left,
    relative to the kick's energy (the start against the static state)."""
    x, _ = static_equilibrium(sy, 50.0)
    x1 = x.copy()
    x1[sy.index("ws1_y")] += 5e-4
    r = simulate(sy, 50.0, duration, q0=x1, h=h, output_dt=0.005, progress=False)
    e = _energy(sy, r.q, r.v, r.wheel_output("energy").sum(axis=(1, 2)))
    w0 = sy.native.force(CallSettings(50.0, 1), x, np.zeros_like(x))[1][8].sum()
    e_static = _energy(sy, x[None], np.zeros((1, x.size)), np.array([w0]))[0]
    return float(np.abs(e - e[0]).max() / abs(e[0] - e_static))


def test_run_does_not_depend_on_the_chunking_or_an_earlier_run():
    """With the strip contact the time loop keeps its iteration matrix from step to step and,
    in the model, from one Fortran call (a chunk sized by wall time) to the next; a call reads
    it only when it continues from exactly the state and settings the last one ended at. So a
    run split into other chunks gives the same numbers bit for bit, and so does the same run
    repeated on the model after another one (whose kept matrix it must not read)."""
    from railvti.vehicle.equilibrium import lateral_disturbance

    sy = scenarios.coach_system(geometry="strip")
    v = 300.0 / 3.6
    qs, _ = static_equilibrium(sy, v)
    q0 = lateral_disturbance(sy, qs, 0.004, wheelsets=(0, 1))
    runs = [
        simulate(sy, v, 0.08, q0=q0, h=1e-3, output_dt=0.002, progress=True, chunk=c)
        for c in (0.004, 0.02, 0.08)
    ]
    simulate(sy, v, 0.03, q0=qs, h=1e-3, progress=False)
    runs.append(simulate(sy, v, 0.08, q0=q0, h=1e-3, output_dt=0.002, progress=False))
    assert runs[0].stats["tangents"] < 0.5 * runs[0].stats["steps"]  # the matrix was kept
    for r in runs[1:]:
        np.testing.assert_array_equal(r.q, runs[0].q)


def test_bad_input(geo):
    with pytest.raises(InputError, match="finite"):
        strip_wheel(geo, np.nan, 0.0, 0.0)
    with pytest.raises(InputError, match="geometry"):
        scenarios.coach_system(geometry="points")
    with pytest.raises(InputError, match="strip"):
        scenarios.coach_system(linear_conicity=0.2, geometry="strip")
    w, r = systems.profiles()
    with pytest.raises(InputError, match="step"):
        strip_geometry(w, r, step=-1.0)


def test_deck_case_runs_the_strip_geometry():
    """A 'vehicle' deck case with geometry = 'strip' runs it (the stored geometry says so and
    the static wheel loads balance the coach's weight), and the BEM with it is refused."""
    from railvti.casetypes import REGISTRY
    import railvti.vehicle.cases  # noqa: F401  (registers the case type)

    p = dict(REGISTRY["vehicle"].defaults)
    p.update(scenario="centred_running", speed_kmh=200.0, duration=0.05, geometry="strip")
    out = REGISTRY["vehicle"].run(p)
    assert out.scalars["geometry"][0] == "strip"
    assert out.scalars["max_Q_error"][0] < 1e-3
    p.update(contact="bem")
    with pytest.raises(InputError, match="strip"):
        REGISTRY["vehicle"].run(p)
    with pytest.raises(InputError, match="geometry"):
        scenarios.hunting(300, contact="bem", geometry="strip", duration=0.1)
