"""Steady rolling contact (railvti.contact.solve_rolling / solve_tangential):
Hertz smoke tests, consistency of the results, Kalker's linear theory, Carter
and saturation on coarse grids, a stability sweep and the error paths."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from railvti.contact import Grid, hertz, hertz_gap, solve_rolling, solve_tangential
from railvti.errors import ConvergenceError, GridTooSmallError, InputError
from railvti.material import Material

MAT = Material(shear_modulus=82e9, poisson=0.25)
FN = 10e3
A0 = 0.5 / 0.3


def _gap_for_ratio(a_over_b: float) -> tuple[float, float]:
    if a_over_b == 1.0:
        return A0, A0

    def f(lb: float) -> float:
        h = hertz(A0, A0 * math.exp(lb), FN, MAT)
        return math.log(h.a / h.b) - math.log(a_over_b)

    return A0, A0 * math.exp(brentq(f, -12.0, 12.0, xtol=1e-10))


def _case(a_over_b: float = 1.0, n: int = 8):
    A, B = _gap_for_ratio(a_over_b)
    h = hertz(A, B, FN, MAT)
    grid = Grid.covering(h.a, h.b, n, 1.5)
    return grid, hertz_gap(grid, A, B), h


@pytest.fixture(scope="module")
def spin_case():
    grid, gap, h = _case()
    r = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 5e-4, 0.5), 30.0, tol=1e-9)
    return grid, gap, h, r


@pytest.mark.parametrize("method", ["gs", "fftgs"])
def test_hertz_smoke_partial_slip(method):
    grid, gap, h = _case()
    r = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 2e-4, 0.3), 30.0, method=method)
    assert r.converged and r.residual <= 1e-7
    # creep force opposes the creepage and is bounded by friction
    assert r.fx < 0 and r.fy < 0
    assert np.hypot(r.fx, r.fy) < 0.3 * r.fn
    # adhesion at the leading edge (largest x) on the centre line, slip at the trailing edge
    row = r.status[:, grid.ny // 2]
    inside = np.nonzero(row)[0]
    assert row[inside[-1]] == 1 and row[inside[0]] == 2
    # the normal solution is the one of solve_normal
    assert r.normal is not None and r.fn == pytest.approx(FN, rel=1e-8)
    assert r.approach == r.normal.approach


def test_methods_agree():
    grid, gap, _ = _case()
    a = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 0.0, 0.5), 10.0, method="gs", tol=1e-10)
    b = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 0.0, 0.5), 10.0, method="fftgs", block=2, tol=1e-10)
    np.testing.assert_allclose(b.tx, a.tx, atol=1e-7 * a.pmax)
    np.testing.assert_allclose(b.ty, a.ty, atol=1e-7 * a.pmax)


def test_consistency(spin_case):
    grid, _, _, r = spin_case
    da = grid.element_area
    x, y = grid.mesh()
    assert r.fx == pytest.approx(r.tx.sum() * da, rel=1e-12)
    assert r.fy == pytest.approx(r.ty.sum() * da, rel=1e-12)
    assert r.mz == pytest.approx(((x * r.ty - y * r.tx).sum()) * da, rel=1e-12)
    tau = np.hypot(r.tx, r.ty)
    assert (tau <= r.mu * r.pressure * (1 + 1e-8)).all()
    assert r.power == pytest.approx((r.power_density * da).sum(), rel=1e-12)
    assert r.power > 0
    # status: exterior exactly where p = 0; zero traction and slip there
    assert ((r.status == 0) == (r.pressure <= 0)).all()
    assert (r.tx[r.status == 0] == 0).all() and (r.slip_velocity[r.status == 0] == 0).all()
    # adhesion: no slip; slip: on the bound, traction opposite to the slip velocity
    assert (r.slip_velocity[r.adhesion] == 0).all()
    s = r.slip
    assert s.sum() > 10 and r.adhesion.sum() > 10
    np.testing.assert_allclose(tau[s], r.mu * r.pressure[s], rtol=1e-6)
    cos = (r.tx * r.slip_velocity_x + r.ty * r.slip_velocity_y)[s] / (tau[s] * r.slip_velocity[s])
    assert (cos < -1 + 1e-6).all()
    assert np.isfinite(r.power_density).all()


def test_speed_scales_slip_only(spin_case):
    grid, gap, _, r = spin_case
    r2 = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 5e-4, 0.5), 60.0, tol=1e-9)
    np.testing.assert_allclose(r2.tx, r.tx, atol=1e-9 * r.pmax)
    np.testing.assert_allclose(r2.slip_velocity, 2 * r.slip_velocity, atol=1e-9 * r.slip_velocity.max())
    assert r2.power == pytest.approx(2 * r.power, rel=1e-6)


def test_warm_start(spin_case):
    grid, gap, _, r = spin_case
    again = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 5e-4, 0.5), 30.0, tol=1e-8, t0=(r.tx, r.ty))
    assert again.iterations == 0
    near = solve_rolling(gap, grid, MAT, 0.3, FN, (1.05e-3, 5e-4, 0.5), 30.0, tol=1e-8, t0=(r.tx, r.ty))
    cold = solve_rolling(gap, grid, MAT, 0.3, FN, (1.05e-3, 5e-4, 0.5), 30.0, tol=1e-8)
    assert near.iterations < cold.iterations
    assert near.fx == pytest.approx(cold.fx, rel=1e-6)


def test_kalker_linear_circle():
    """C11, C22, C23 of a circular patch (Hertz pressure, full adhesion), 16 elements per radius."""
    A, B = A0, A0
    h = hertz(A, B, FN, MAT)
    grid = Grid.covering(h.a, h.b, 16, 1.1)
    p = h.pressure(grid)
    G, ab = MAT.shear_modulus, h.a * h.b
    eps = 1e-6
    phi = eps / math.sqrt(ab)
    c11 = -solve_tangential(p, grid, MAT, 1e3, (eps, 0, 0), 1.0).fx / (G * ab * eps)
    c22 = -solve_tangential(p, grid, MAT, 1e3, (0, eps, 0), 1.0).fy / (G * ab * eps)
    c23 = -solve_tangential(p, grid, MAT, 1e3, (0, 0, phi), 1.0).fy / (G * ab**1.5 * phi)
    # Kalker 1990, Table E.3, a/b = 1, nu = 0.25: within 2 % (0.6-0.9 % measured)
    assert c11 == pytest.approx(4.12, rel=0.02)
    assert c22 == pytest.approx(3.67, rel=0.02)
    assert c23 == pytest.approx(1.47, rel=0.02)


def test_saturation():
    grid, gap, _ = _case(n=8)
    r = solve_rolling(gap, grid, MAT, 0.3, FN, (0.05, 0.0, 0.0), 1.0)
    assert abs(r.fx) == pytest.approx(0.3 * r.fn, rel=5e-3)
    assert r.slip[r.contact].all()


@pytest.mark.parametrize("kappa", [0.05, 0.3, 0.8])
def test_carter_plane_strain(kappa):
    """Two rows 2000 a long (plane strain), Hertz 2-D pressure: Carter's force within 1.5 % at 40 across."""
    a, p0, mu = 5e-3, 800e6, 0.3
    n = 40
    dx = 2 * a / n
    grid = Grid(nx=n + 6, ny=2, dx=dx, dy=2000 * a, x0=-0.5 * (n + 5) * dx)
    x, _ = grid.mesh()
    p = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    R = a * MAT.contact_modulus / (2 * p0)
    r = solve_tangential(p, grid, MAT, mu, (kappa * mu * a / R, 0, 0), 1.0, tol=1e-9)
    f = -r.fx / (mu * p.sum() * grid.element_area)
    assert f == pytest.approx(1 - (1 - kappa) ** 2, rel=0.015)
    # stick zone at the leading edge, of half-width a (1 - kappa)
    stick = x[:, 0][r.status[:, 0] == 1]
    assert stick.max() > a * (1 - 2 / n)
    assert (stick.max() - stick.min() + dx) / 2 == pytest.approx(a * (1 - kappa), abs=2 * dx)
    # traction profile within 3 % of mu p0 of Carter's element means (the
    # two-point upwind difference gave 5.8 % at kappa = 0.8)
    xs = x[:, 0][:, None] + dx * ((np.arange(20) + 0.5) / 20 - 0.5)[None, :]
    full = np.sqrt(np.clip(1 - (xs / a) ** 2, 0, None))
    a1 = a * (1 - kappa)
    exact = (full - (a1 / a) * np.sqrt(np.clip(1 - ((xs - (a - a1)) / a1) ** 2, 0, None))).mean(axis=1)
    assert np.abs(-r.tx[:, 0] / (mu * p0) - exact).max() < 0.03


A_OVER_B = [0.1, 0.3, 1.0, 3.0, 10.0]


@pytest.mark.parametrize("a_over_b", A_OVER_B)
def test_stability_sweep(a_over_b):
    """Every case converges or raises ConvergenceError with a residual; never a silent wrong answer."""
    grid, gap, h = _case(a_over_b, n=4)
    rab = math.sqrt(h.a * h.b)
    for mu in (0.05, 0.6):
        for c in (1e-6, 1e-3, 0.1):
            for cr in ((c, 0, 0), (0, c, 0), (0, 0, c / rab), (c, c / 2, c / rab), (c / 10, 0, 10 * c / rab)):
                try:
                    r = solve_rolling(gap, grid, MAT, mu, FN, cr, 10.0, max_iter=500)
                except ConvergenceError as exc:
                    assert math.isfinite(exc.residual) and exc.residual > 1e-7
                    assert exc.result is not None
                    continue
                assert r.converged and r.residual <= 1e-7
                for f in (r.tx, r.ty, r.slip_velocity, r.power_density):
                    assert np.isfinite(f).all()
                assert math.hypot(r.fx, r.fy) <= mu * r.fn * (1 + 1e-8)
                assert (np.hypot(r.tx, r.ty) <= mu * r.pressure * (1 + 1e-8)).all()
                assert r.power >= 0


@pytest.mark.parametrize(
    "a_over_b, creepage",
    [
        (0.2, (0.2 * 0.5 * 1.6523e-3, 0.2 * 0.5 * 2.2227e-3, 0.2 * 0.3 * 1.8651)),  # combined, 0.1 mu Fn
        (5.0, (0.0, 0.0, 2.0 * 0.17265)),  # pure spin, 1 mu Fn
    ],
)
def test_strong_spin_cases_converge(a_over_b, creepage):
    """The two cases of validation/contact_fastsim_vs_bem.py (sqrt(ab) = 5 mm, 80 kN, n = 40 per
    semi-axis) on which an earlier point Gauss-Seidel kernel raised ConvergenceError."""
    A, B = _gap_for_ratio(a_over_b)
    h = hertz(A, B, 80e3, MAT)
    s = (math.sqrt(h.a * h.b) / 5e-3) ** 3
    A, B = s * A, s * B
    h = hertz(A, B, 80e3, MAT)
    n = 40
    grid = Grid(nx=96, ny=96, dx=h.a / n, dy=h.b / n)
    r = solve_rolling(hertz_gap(grid, A, B), grid, MAT, 0.3, 80e3, creepage, 20.0)
    assert r.converged and r.residual <= 1e-7 and r.iterations < 100
    assert math.hypot(r.fx, r.fy) < 0.3 * r.fn


def test_not_converged_raises_with_result():
    grid, gap, _ = _case()
    with pytest.raises(ConvergenceError) as info:
        solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 0, 0.5), 1.0, max_iter=1, tol=1e-12)
    assert info.value.residual > 1e-12 and info.value.iterations == 1
    assert info.value.result is not None and not info.value.result.converged


def test_no_contact_pressure_gives_zero():
    grid, _, _ = _case()
    r = solve_tangential(np.zeros(grid.shape), grid, MAT, 0.3, (1e-3, 0, 0), 1.0)
    assert r.fx == 0 and r.fy == 0 and r.n_contact == 0 and r.converged


@pytest.mark.parametrize("row", [-1, -2])
def test_contact_at_leading_edge(row):
    """The slip needs the displacement two elements upstream."""
    grid, _, _ = _case()
    p = np.zeros(grid.shape)
    p[row, grid.ny // 2] = 1e6
    with pytest.raises(GridTooSmallError):
        solve_tangential(p, grid, MAT, 0.3, (1e-3, 0, 0), 1.0)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"mu": -0.1}, "mu"),
        ({"speed": 0.0}, "speed"),
        ({"speed": -3.0}, "speed"),
        ({"creepage": (float("nan"), 0, 0)}, "xi"),
        ({"creepage": (0, float("nan"), 0)}, "eta"),
        ({"creepage": (0, 0, float("inf"))}, "phi"),
        ({"creepage": (0, 0)}, "creepage"),
        ({"fn": 0.0}, "fn"),
        ({"fn": -1.0}, "fn"),
        ({"method": "cg"}, "method"),
        ({"tol": 0.0}, "tol"),
        ({"max_iter": 0}, "max_iter"),
        ({"t0": (np.zeros((3, 3)), np.zeros((3, 3)))}, "t0"),
    ],
)
def test_bad_input(kwargs, name):
    grid, gap, _ = _case(n=4)
    args = {"mu": 0.3, "fn": FN, "creepage": (1e-3, 0, 0), "speed": 1.0}
    args.update(kwargs)
    with pytest.raises(InputError, match=name):
        solve_rolling(gap, grid, MAT, **args)


def test_inner_passes_same_solution(spin_case):
    grid, gap, _, r = spin_case
    r2 = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 5e-4, 0.5), 30.0, tol=1e-9, inner=2, block=3)
    np.testing.assert_allclose(r2.tx, r.tx, atol=1e-6 * r.pmax)
    np.testing.assert_allclose(r2.ty, r.ty, atol=1e-6 * r.pmax)


def test_frictionless_gives_zero_traction():
    grid, gap, _ = _case()
    r = solve_rolling(gap, grid, MAT, 0.0, FN, (1e-3, 0, 0.5), 1.0)
    assert r.fx == 0 and r.fy == 0 and r.power == 0
    assert r.slip[r.contact].all()


def test_kernel_reports_named_status_codes():
    """The Fortran kernel's error paths (which the Python checks screen) give the named codes
    of common_status: no contact, contact at the leading grid edge, a bad method, a bad handle
    and a workspace made without the tangential kernels."""
    from railvti._native import core
    from railvti._status import Status
    from railvti.contact.workspace import workspace

    grid, _, _ = _case(n=4)
    tang = workspace(grid, MAT, tangential=True)

    def call(handle, p, method=2):
        tx, ty = np.zeros(grid.shape, order="F"), np.zeros(grid.shape, order="F")
        return core.rolling_solve_c(
            handle, p, grid.x0, grid.y0, 1e-3, 0.0, 0.0, 0.3, 1.0, method, 4, 1, 1e-7, 50, 0, tx, ty
        )[-1]

    p = np.zeros(grid.shape, order="F")
    assert call(tang, p) == Status.NO_CONTACT
    p[grid.nx // 2, grid.ny // 2] = 1e6
    assert call(tang, p) == Status.OK
    assert call(tang, p, method=7) == Status.BAD_ARGUMENT
    assert call(999, p) == Status.BAD_HANDLE
    other = Grid(grid.nx + 2, grid.ny, grid.dx, grid.dy, grid.x0, grid.y0)
    assert call(workspace(other, MAT), p) == Status.BAD_HANDLE  # another grid size
    normal_only = workspace(grid, Material(80e9, 0.3))  # not cached with tangential kernels
    assert call(normal_only, p) == Status.BAD_HANDLE
    p[-2, grid.ny // 2] = 1e6
    assert call(tang, p) == Status.GRID_EDGE
