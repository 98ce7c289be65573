"""The 11 x 11 creep-force case (issue 18 item 4): the fast path of the steady rolling solver
(u = A t by direct sums over the contact box, chosen by product='auto' on small patches)
against the reference path (zero-padded FFT products, product='fft'), on the table of
cases of benchmarks/bench_contact_small_grid.py, and both against Kalker's linear theory in
the small-creepage limit; the normal solution (dense products) against numpy sums."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import STEEL
from railvti.contact import Grid, hertz, hertz_gap, influence_field, solve_normal, solve_tangential
from railvti.contact.kalker import kalker_coefficients
from railvti.errors import InputError

FN, MU, V, MARGIN, N = 10e3, 0.3, 30.0, 1.57, 11
# a/b = 0.5, 1.0, 1.33, 2.0 (benchmarks/bench_contact_small_grid.py)
SHAPES = [(2.8, 1.0), (1.0, 1.0), (0.5 / 0.46, 0.5 / 0.30), (0.35, 1.0)]
CREEP = [(xi, eta, phi) for xi in (0.0, 5e-4, 2e-3) for eta in (0.0, 1e-3) for phi in (0.0, 0.5, 2.0)]


def _problem(A: float, B: float):
    h = hertz(A, B, FN, STEEL)
    g = Grid(N, N, 2 * MARGIN * h.a / N, 2 * MARGIN * h.b / N)
    return h, g, solve_normal(hertz_gap(g, A, B), g, STEEL, fn=FN)


@pytest.mark.parametrize("shape", SHAPES, ids=["a/b=0.5", "a/b=1", "a/b=1.33", "a/b=2"])
def test_direct_products_give_the_fft_answer(shape):
    """The small contact set's path ('auto' and 'direct': the dense slip operator, finished by
    Newton's method once the statuses have settled) against the grid path with FFT products
    (Anderson-mixed sweeps to the end): the same statuses, and both within 1e-6 of the largest
    traction bound of the converged solution (the FFT path to tolerance 1e-13; 4e-7 measured
    for either: both stop at the residual 1e-7), in fewer sweeps (about half). 'auto' and
    'direct' take the same path: the same tractions to rounding."""
    _, g, nr = _problem(*shape)
    worst = 0.0
    for c in CREEP:
        ref = solve_tangential(nr.pressure, g, STEEL, MU, c, V, product="fft")
        conv = solve_tangential(nr.pressure, g, STEEL, MU, c, V, product="fft", tol=1e-13, max_iter=500)
        fast = solve_tangential(nr.pressure, g, STEEL, MU, c, V, product="auto")
        direct = solve_tangential(nr.pressure, g, STEEL, MU, c, V, product="direct")
        assert ref.converged and fast.converged and conv.converged
        assert fast.iterations <= ref.iterations and (fast.iterations < ref.iterations or ref.iterations == 0)
        scale = MU * nr.pressure.max()
        for r in (fast, ref):
            worst = max(worst, np.abs(r.tx - conv.tx).max() / scale, np.abs(r.ty - conv.ty).max() / scale)
            np.testing.assert_array_equal(r.status, conv.status)
        assert np.abs(direct.tx - fast.tx).max() <= 1e-10 * scale
        assert np.abs(direct.ty - fast.ty).max() <= 1e-10 * scale
        fscale = MU * FN
        assert abs(fast.fx - conv.fx) <= 1e-6 * fscale and abs(fast.fy - conv.fy) <= 1e-6 * fscale
        assert abs(fast.mz - conv.mz) <= 1e-6 * fscale * g.dx * g.nx
    assert worst < 1e-6


@pytest.mark.parametrize("law", ["exponential", "rational"])
def test_small_path_with_a_friction_law_gives_the_fft_answer(law):
    """The small contact set's packed iteration (product 'direct', 41 elements) with a falling
    friction law (element problems by contact_friction) against the grid iteration with FFT
    products: the same sweeps, status and tractions to 1e-10 of mu_s p0 (the two differ by
    rounding)."""
    from railvti.contact.friction import FrictionLaw, solve_tangential_friction

    _, g, nr = _problem(0.5 / 0.46, 0.5 / 0.30)
    fl = FrictionLaw(law, 0.4, 0.25, 0.5, root_rule="smallest")
    scale = 0.4 * nr.pressure.max()
    for c in ((2e-3, 0.0, 0.0), (5e-4, 1e-3, 2.0)):
        ref = solve_tangential_friction(nr.pressure, g, STEEL, fl, c, V, product="fft")
        fast = solve_tangential_friction(nr.pressure, g, STEEL, fl, c, V, product="direct")
        assert fast.rolling.iterations == ref.rolling.iterations
        np.testing.assert_array_equal(fast.rolling.status, ref.rolling.status)
        assert np.abs(fast.rolling.tx - ref.rolling.tx).max() < 1e-10 * scale
        assert np.abs(fast.rolling.ty - ref.rolling.ty).max() < 1e-10 * scale
        assert np.abs(ref.rolling.tx).max() > 0.1 * scale


def test_direct_products_on_a_larger_patch():
    """On a 24 x 24 grid ('auto' takes the FFT there) forced direct products agree too."""
    h = hertz(0.5 / 0.46, 0.5 / 0.30, FN, STEEL)
    g = Grid(24, 24, 2 * 1.3 * h.a / 24, 2 * 1.3 * h.b / 24)
    nr = solve_normal(hertz_gap(g, 0.5 / 0.46, 0.5 / 0.30), g, STEEL, fn=FN)
    ref = solve_tangential(nr.pressure, g, STEEL, MU, (1e-3, 5e-4, 0.5), V, product="fft")
    direct = solve_tangential(nr.pressure, g, STEEL, MU, (1e-3, 5e-4, 0.5), V, product="direct")
    assert direct.iterations == ref.iterations
    assert np.abs(direct.tx - ref.tx).max() < 1e-10 * MU * nr.pressure.max()
    assert np.abs(direct.ty - ref.ty).max() < 1e-10 * MU * nr.pressure.max()


@pytest.mark.parametrize("shape", SHAPES, ids=["a/b=0.5", "a/b=1", "a/b=1.33", "a/b=2"])
def test_small_grid_small_creepage_follows_kalker(shape):
    """Independent check of the fast path: at small creepage the 11 x 11 grid's Fx, Fy lie
    within 6 % of Kalker's linear theory (Fx = -G a b C11 xi; 1-5 % measured, the coarse
    grid's discretisation error, not the solver's)."""
    h, g, nr = _problem(*shape)
    xi = eta = 2e-5
    r = solve_tangential(nr.pressure, g, STEEL, MU, (xi, eta, 0.0), V)
    c11, c22, _ = kalker_coefficients(h.a / h.b, STEEL.poisson)
    gc2 = STEEL.shear_modulus * h.a * h.b
    assert r.fx == pytest.approx(-gc2 * c11 * xi, rel=0.06)
    assert r.fy == pytest.approx(-gc2 * c22 * eta, rel=0.06)


def test_bad_product_is_named():
    _, g, nr = _problem(1.0, 1.0)
    with pytest.raises(InputError, match="product"):
        solve_tangential(nr.pressure, g, STEEL, MU, (1e-3, 0.0, 0.0), V, product="dense")


@pytest.mark.parametrize("shape", SHAPES, ids=["a/b=0.5", "a/b=1", "a/b=1.33", "a/b=2"])
def test_small_grid_normal_solution_is_complementary(shape):
    """The 11 x 11 normal solve (products by the kernel's dense matrix) checked against an
    independent product (numpy sums of influence_field's coefficients): the deformed gap
    e = h + A p - approach vanishes where p > 0 and is >= 0 elsewhere, to 1e-6 of the
    approach, and the pressures carry Fn."""
    h, g, nr = _problem(*shape)
    gap = hertz_gap(g, *shape)
    c = influence_field(g, STEEL, "zz")  # circular layout on the (2 nx, 2 ny) grid
    ii = np.arange(g.nx)
    jj = np.arange(g.ny)
    a = c[np.subtract.outer(ii, ii) % (2 * g.nx)][:, :, np.subtract.outer(jj, jj) % (2 * g.ny)]
    u = np.einsum("ikjl,kl->ij", a, nr.pressure)  # u_ij = sum_kl C(i - k, j - l) p_kl
    e = gap + u - nr.approach
    tol = 1e-6 * nr.approach
    assert np.abs(e[nr.pressure > 0]).max() < tol
    assert e[nr.pressure == 0].min() > -tol
    assert nr.pressure.sum() * g.element_area == pytest.approx(FN, rel=1e-12)


def test_direct_products_on_a_contact_set_beyond_the_dense_operator():
    """A contact set of more than 100 elements (36 x 36 grid) takes the direct sums over the
    box instead of the dense slip operator (11 x 11 grids): they agree with the FFT products too."""
    g0 = hertz(1.0, 1.0, FN, STEEL)
    g = Grid(36, 36, 2 * 1.3 * g0.a / 36, 2 * 1.3 * g0.b / 36)
    nr = solve_normal(hertz_gap(g, 1.0, 1.0), g, STEEL, fn=FN)
    assert nr.n_contact > 100
    ref = solve_tangential(nr.pressure, g, STEEL, MU, (1e-3, 5e-4, 0.5), V, product="fft")
    direct = solve_tangential(nr.pressure, g, STEEL, MU, (1e-3, 5e-4, 0.5), V, product="direct")
    assert direct.iterations == ref.iterations
    assert np.abs(direct.tx - ref.tx).max() < 1e-10 * MU * nr.pressure.max()
    assert np.abs(direct.ty - ref.ty).max() < 1e-10 * MU * nr.pressure.max()
