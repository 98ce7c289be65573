"""Transient and shift tangential contact (railvti.contact.transient): the step kernel against
a dense solution, Cattaneo-Mindlin against Johnson (1985), transient rolling against the steady
solver, the load history, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railvti.contact import Grid, hertz, hertz_gap, influence_field, solve_rolling
from railvti.contact.transient import (
    STATUS_ADHESION,
    STATUS_SLIP,
    shift_problem,
    solve_step,
    solve_transient,
    transient_rolling,
)
from railvti.errors import GridTooSmallError, InputError
from railvti.material import STEEL

R = 0.05
A = 1.0 / (2.0 * R)
FN = 10e3
MU = 0.3


def _dense(grid: Grid) -> np.ndarray:
    """The (2N, 2N) tangential influence matrix [[Axx, Axy], [Axy, Ayy]] from the
    coefficient fields (numpy, independent of the FFT products)."""
    nx, ny = grid.shape
    c = {k: influence_field(grid, STEEL, k) for k in ("xx", "yy", "xy")}
    idx = [(i, j) for j in range(ny) for i in range(nx)]
    n = len(idx)
    m = np.zeros((2 * n, 2 * n))
    for a, (i, j) in enumerate(idx):
        for b, (k, l) in enumerate(idx):
            di, dj = (i - k) % (2 * nx), (j - l) % (2 * ny)
            m[a, b] = c["xx"][di, dj]
            m[n + a, n + b] = c["yy"][di, dj]
            m[a, n + b] = m[n + a, b] = c["xy"][di, dj]
    return m


def _reference_step(m, bound, s0x, s0y, sweeps=4000):
    """Point Gauss-Seidel with the exact solve on each Coulomb disc (block coordinate descent on
    the convex problem), in numpy, order of the fields' ravel('F')."""
    n = bound.size
    g = bound.ravel("F")
    s0 = np.concatenate([s0x.ravel("F"), s0y.ravel("F")])
    t = np.zeros(2 * n)
    for _ in range(sweeps):
        t_old = t.copy()
        for a in np.nonzero(g > 0)[0]:
            ia = [a, n + a]
            blk = m[np.ix_(ia, ia)]
            r = s0[ia] + m[ia] @ t - blk @ t[ia]
            ta = -np.linalg.solve(blk, r)
            if np.hypot(*ta) > g[a]:
                # slip: t = -g s/|s|, s = r + blk t; blk is diagonal (Axy(0) = 0): solve for lam
                lam = 1.0
                for _ in range(200):
                    e = r / (lam + g[a] * np.diag(blk))
                    f = e @ e - 1.0
                    fp = -2.0 * np.sum(e * e / (lam + g[a] * np.diag(blk)))
                    lam = max(lam - f / fp, 0.0)
                e = r / (lam + g[a] * np.diag(blk))
                ta = -g[a] * e / np.linalg.norm(e)
            t[ia] = ta
        if np.abs(t - t_old).max() <= 1e-13 * np.abs(t).max():
            break
    return t[:n].reshape(bound.shape, order="F"), t[n:].reshape(bound.shape, order="F")


def test_step_matches_dense_gauss_seidel():
    grid = Grid(9, 8, 1e-4, 1.2e-4)
    x, y = grid.mesh()
    p = 1e9 * np.sqrt(np.maximum(1.0 - (x / 3.5e-4) ** 2 - (y / 3.6e-4) ** 2, 0.0))
    bound = MU * p
    s0x = np.asfortranarray(-2e-7 + 3e-4 * y)  # a shift and a rotation: partial slip
    s0y = np.asfortranarray(1e-7 - 3e-4 * x)
    r = solve_step(grid, STEEL, bound, (s0x, s0y), tol=1e-10)
    rx, ry = _reference_step(_dense(grid), bound, s0x, s0y)
    scale = bound.max()
    assert np.abs(r.tx - rx).max() < 1e-6 * scale
    assert np.abs(r.ty - ry).max() < 1e-6 * scale
    assert (r.status == STATUS_SLIP).any() and (r.status == STATUS_ADHESION).any()
    # slip opposite the traction, at the bound
    sl = r.status == STATUS_SLIP
    cos = (r.tx * r.slip_x + r.ty * r.slip_y)[sl] / (np.hypot(r.tx, r.ty) * np.hypot(r.slip_x, r.slip_y))[sl]
    assert cos.max() < -1 + 1e-6
    assert np.hypot(r.tx, r.ty)[sl] == pytest.approx(bound[sl], rel=1e-9)


def test_step_full_adhesion_is_the_linear_solve():
    grid = Grid(8, 8, 1e-4, 1e-4)
    inc = np.zeros(grid.shape, bool)
    inc[2:6, 2:6] = True
    bound = np.where(inc, 1e12, 0.0)
    s0x = np.full(grid.shape, 1e-7, order="F")
    s0y = np.full(grid.shape, -5e-8, order="F")
    r = solve_step(grid, STEEL, bound, (s0x, s0y), weight=4.0 / 3.0, tol=1e-11)
    m = _dense(grid)
    sel = np.concatenate([inc.ravel("F"), inc.ravel("F")])
    rhs = -np.concatenate([s0x.ravel("F"), s0y.ravel("F")])[sel]
    t = np.linalg.solve(4.0 / 3.0 * m[np.ix_(sel, sel)], rhs)
    n = inc.sum()
    assert r.tx.ravel("F")[inc.ravel("F")] == pytest.approx(t[:n], rel=1e-7)
    assert np.all(r.status[inc] == STATUS_ADHESION)
    # ux, uy is A t on the whole grid
    u = m @ np.concatenate([r.tx.ravel("F"), r.ty.ravel("F")])
    assert r.ux.ravel("F") == pytest.approx(u[: grid.nx * grid.ny], rel=1e-9, abs=1e-20)


def _sphere(n=10, margin=1.2, extra=0):
    h = hertz(A, A, FN, STEEL)
    g = Grid.covering(h.a, h.a, n, margin)
    g = Grid(g.nx + extra, g.ny, g.dx, g.dy, g.x0, g.y0)
    return h, g, hertz_gap(g, A, A)


def test_cattaneo_mindlin_sphere():
    """Johnson, Contact Mechanics (1985), eqs 7.38 and 7.42 for two bodies of one material:
    c = a (1 - Q/mu P)^(1/3), delta = 3 mu P (2 - nu) / (8 G a) [1 - (1 - Q/mu P)^(2/3)]."""
    h, g, gap = _sphere(20, margin=1.15)
    q = 7.0 / 8.0 * MU * FN
    r = shift_problem(gap, g, STEEL, MU, FN, (q, 0.0), steps=1)
    c = math.sqrt(r.last.adhesion.sum() * g.element_area / math.pi)
    assert c / h.a == pytest.approx(0.5, rel=0.02)
    delta = 3 * MU * FN * (2 - STEEL.poisson) / (8 * STEEL.shear_modulus * h.a) * (1 - (1 - 7 / 8) ** (2 / 3))
    assert -r.shift_total[-1, 0] == pytest.approx(delta, rel=0.01)
    assert r.fx[-1] == pytest.approx(q, rel=1e-5)
    assert abs(r.fy[-1]) < 1e-9 * q
    # monotonic loading: four increments give the same state up to the small lateral
    # tractions of the Poisson coupling (Mindlin neglects them), which follow the path:
    # measured 2e-4 mu p0 in tx, 3.1e-3 in ty on this grid
    r4 = shift_problem(gap, g, STEEL, MU, FN, (q, 0.0), steps=4)
    assert np.array_equal(r4.last.status, r.last.status)
    assert r4.shift_total[-1, 0] == pytest.approx(r.shift_total[-1, 0], rel=1e-4)
    assert np.abs(r4.last.tx - r.last.tx).max() < 1e-3 * MU * h.p0
    assert np.abs(r4.last.ty - r.last.ty).max() < 1e-2 * MU * h.p0
    # the force grows monotonically with the shift (a loading path)
    assert np.all(np.diff(r4.fx) > 0) and np.all(np.diff(-r4.shift_total[:, 0]) > 0)


def test_transient_rolling_reaches_the_steady_solver():
    h, g, gap = _sphere(8, extra=4)
    creep = (-0.002, 0.0, 0.5)
    r = transient_rolling(g, STEEL, MU, FN, creep, 30.0, 16 * h.a, gap=gap)
    s = solve_rolling(gap, g, STEEL, MU, FN, creep, 30.0)
    assert r.fx[-1] == pytest.approx(s.fx, rel=1e-5)
    assert r.fy[-1] == pytest.approx(s.fy, rel=1e-4, abs=1e-5 * abs(s.fx))
    assert np.abs(r.last.tx - s.tx).max() < 1e-4 * MU * h.p0
    # from rest: |Fx| grows to the steady value within a few contact lengths
    d99 = r.distance_to_fraction(0.99, s.fx)
    assert 1.0 < d99 / (2 * h.a) < 4.0
    assert abs(r.fx[0]) < 0.2 * abs(s.fx)


def test_first_order_scheme_is_first_order_close():
    """theta = 0 (Kalker's two-point form) settles within a few per cent of the steady solver."""
    h, g, gap = _sphere(8, extra=4)
    r = transient_rolling(g, STEEL, MU, FN, (-0.002, 0, 0), 30.0, 16 * h.a, gap=gap, theta=0.0)
    s = solve_rolling(gap, g, STEEL, MU, FN, (-0.002, 0, 0), 30.0)
    assert r.fx[-1] == pytest.approx(s.fx, rel=0.05)
    assert r.fx[-1] != pytest.approx(s.fx, rel=1e-4)


def test_load_step_settles_to_the_new_steady_state():
    h, g, gap = _sphere(8, margin=1.35, extra=4)
    steps = int(round(16 * h.a / g.dx))
    fn = np.where(np.arange(steps) < steps // 2, FN, 1.2 * FN)
    dt = g.dx / 30.0
    r = solve_transient(
        g, STEEL, MU, fn, steps, dt, gap=gap, speed=30.0, creepage=(-0.002, 0, 0), theta=1 / 3
    )
    s1 = solve_rolling(gap, g, STEEL, MU, FN, (-0.002, 0, 0), 30.0)
    s2 = solve_rolling(gap, g, STEEL, MU, 1.2 * FN, (-0.002, 0, 0), 30.0)
    assert r.fx[steps // 2 - 1] == pytest.approx(s1.fx, rel=1e-3)
    assert r.fx[-1] == pytest.approx(s2.fx, rel=1e-3)
    assert r.fn[-1] == pytest.approx(1.2 * FN, rel=1e-8)
    # the force lags the load: just after the step it is below the new steady value
    assert abs(r.fx[steps // 2]) < abs(s2.fx) - 0.3 * abs(s2.fx - s1.fx)


def test_repeat_is_bit_identical():
    h, g, gap = _sphere(8, extra=4)
    a = transient_rolling(g, STEEL, MU, FN, (-0.002, 0, 0), 30.0, 2 * h.a, gap=gap)
    b = transient_rolling(g, STEEL, MU, FN, (-0.002, 0, 0), 30.0, 2 * h.a, gap=gap)
    assert np.array_equal(a.fx, b.fx) and np.array_equal(a.last.tx, b.last.tx)


@pytest.mark.parametrize(
    "kw, key",
    [
        (dict(dt=1.5), "dt"),  # not a whole number of elements
        (dict(dt=30.0), "dt"),  # skips the patch
        (dict(dt=7.0), "dt"),  # history beyond the grid's leading edge
        (dict(theta=1.5), "theta"),
    ],
)
def test_bad_time_step_names_the_key(kw, key):
    h, g, gap = _sphere(8)
    dt = kw.pop("dt", 1.0) * g.dx / 30.0
    with pytest.raises(InputError, match=key):
        solve_transient(g, STEEL, MU, FN, 4, dt, gap=gap, speed=30.0, **kw)


def test_bad_inputs():
    h, g, gap = _sphere(8)
    with pytest.raises(InputError, match="force"):
        shift_problem(gap, g, STEEL, MU, FN, (MU * FN, 0.0))
    with pytest.raises(InputError, match="theta"):
        solve_transient(g, STEEL, MU, FN, 2, 1.0, gap=gap, theta=1 / 3)
    with pytest.raises(InputError, match="gap"):
        solve_transient(g, STEEL, MU, FN, 2, 1.0)
    with pytest.raises(InputError, match="fn"):
        solve_transient(g, STEEL, MU, [FN, -1.0], 2, 1.0, gap=gap)
    with pytest.raises(InputError, match="mu"):
        solve_transient(g, STEEL, 0.0, FN, 2, 1.0, gap=gap)
    with pytest.raises(InputError, match="bound"):
        solve_step(g, STEEL, -np.ones(g.shape), (np.zeros(g.shape), np.zeros(g.shape)))


def test_patch_on_the_grid_edge():
    h = hertz(A, A, FN, STEEL)
    g = Grid(10, 10, h.a / 5, h.a / 5)
    with pytest.raises((GridTooSmallError, InputError)):
        shift_problem(hertz_gap(g, A, A), g, STEEL, MU, FN, (0.5 * MU * FN, 0.0))


_CHILD = """
import sys, numpy as np
from railvti.contact import hertz, hertz_gap, Grid, transient_rolling
from railvti.material import STEEL
h = hertz(10.0, 10.0, 1e4, STEEL)
g = Grid.covering(h.a, h.a, 8, 1.2)
g = Grid(g.nx + 4, g.ny, g.dx, g.dy, g.x0, g.y0)
r = transient_rolling(g, STEEL, 0.3, 1e4, (-0.002, 0, 0), 30.0, 2 * h.a, gap=hertz_gap(g, 10.0, 10.0))
np.save(sys.argv[1], np.concatenate([r.fx, r.last.tx.ravel()]))
"""


@pytest.mark.parametrize("threads", ["1", "2"])
def test_independent_of_threads_and_workspace_cache(tmp_path, threads):
    """The same march in a fresh process with 1 or 2 OpenMP/BLAS threads (cold workspace
    cache), and here after clearing the cache: bit-identical."""
    import os
    import subprocess
    import sys

    from railvti.contact import workspace

    h, g, gap = _sphere(8, extra=4)
    workspace.clear()
    r = transient_rolling(g, STEEL, MU, FN, (-0.002, 0, 0), 30.0, 2 * h.a, gap=gap)
    env = dict(os.environ, OMP_NUM_THREADS=threads, OPENBLAS_NUM_THREADS=threads)
    out = tmp_path / "child.npy"
    subprocess.run([sys.executable, "-c", _CHILD, str(out)], check=True, env=env, timeout=300)
    assert np.array_equal(np.load(out), np.concatenate([r.fx, r.last.tx.ravel()]))


def test_mindlin_deresiewicz_unloading():
    """Unloading from Q* along the load path (Johnson 1985, sect. 7.2, after Mindlin and
    Deresiewicz 1953): delta(Q) = delta_l(Q*) - 2 delta_l((Q* - Q) / 2), delta_l the loading
    curve, proportional to 1 - (1 - Q/(mu P))^(2/3); a force cycle closes symmetrically."""
    h, g, gap = _sphere(10)
    qs = 0.75 * MU * FN
    f = np.array([[qs, 0], [qs / 2, 0], [0, 0], [-qs / 2, 0], [-qs, 0]])
    r = solve_transient(g, STEEL, MU, FN, len(f), 1.0, gap=gap, force=f)
    d = -r.shift_total[:, 0]

    def load(q):
        return 1.0 - (1.0 - q / (MU * FN)) ** (2.0 / 3.0)

    for k, q in enumerate(f[1:, 0], start=1):
        expected = (load(qs) - 2.0 * load((qs - q) / 2.0)) / load(qs)
        assert d[k] / d[0] == pytest.approx(expected, abs=0.01)
    assert d[-1] == pytest.approx(-d[0], rel=1e-3)
    assert r.fx == pytest.approx(f[:, 0], abs=1e-6 * qs)
