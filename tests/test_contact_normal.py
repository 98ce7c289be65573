"""The normal contact solvers: Hertz validation, two patches, complementarity, errors."""

import numpy as np
import pytest
from scipy import ndimage

from railvti import ConvergenceError, GridTooSmallError, InputError, Material, NoContactError
from railvti.contact import Grid, SubPatches, convolve, hertz, hertz_gap, solve_normal

MAT = Material(shear_modulus=82e9, poisson=0.28)
FN = 1.0e4


def hertz_case(ratio, n_minor):
    """Gap with A/B = ratio (B = 1 1/m) and a grid with n_minor elements per minor semi-axis."""
    A, B = ratio, 1.0
    ref = hertz(A, B, FN, MAT)
    return ref, Grid.covering(ref.a, ref.b, n_per_semiaxis=n_minor, margin=1.2), A, B


def semi_axes(result):
    """Half the extent of the contact area along the x and y axes, element edges included."""
    x, y = result.grid.mesh()
    c = result.contact
    return np.abs(x[c]).max() + result.grid.dx / 2, np.abs(y[c]).max() + result.grid.dy / 2


@pytest.mark.parametrize("method", ["cg", "pk", "gs"])
@pytest.mark.parametrize("ratio", [1.0, 0.5, 0.2, 0.1])
def test_hertz_acceptance(method, ratio):
    """30 elements across the minor axis: Fn within 0.5 % (approach prescribed),
    p0 within 1.5 % and the semi-axes within one element (force prescribed)."""
    ref, grid, A, B = hertz_case(ratio, 15)
    gap = hertz_gap(grid, A, B)
    by_force = solve_normal(gap, grid, MAT, fn=FN, method=method)
    by_approach = solve_normal(gap, grid, MAT, approach=ref.approach, method=method)
    assert by_approach.fn == pytest.approx(FN, rel=5e-3)
    assert by_force.fn == pytest.approx(FN, rel=1e-8)
    assert by_force.pmax == pytest.approx(ref.p0, rel=1.5e-2)
    a, b = semi_axes(by_force)
    assert abs(a - ref.a) <= grid.dx
    assert abs(b - ref.b) <= grid.dy


def test_errors_shrink_with_refinement():
    errs = []
    for n in (5, 10, 20):
        ref, grid, A, B = hertz_case(0.5, n)
        r = solve_normal(hertz_gap(grid, A, B), grid, MAT, approach=ref.approach)
        errs.append(abs(r.fn / FN - 1))
    assert errs[0] > errs[1] > errs[2]


def test_cg_and_gs_agree():
    ref, grid, A, B = hertz_case(0.3, 8)
    x, y = grid.mesh()
    gap = hertz_gap(grid, A, B) + 2e-6 * np.sin(x / ref.a * 3) ** 2  # not Hertzian
    r1 = solve_normal(gap, grid, MAT, fn=FN, method="cg", tol=1e-10)
    r2 = solve_normal(gap, grid, MAT, fn=FN, method="gs", tol=1e-10)
    assert np.abs(r1.pressure - r2.pressure).max() < 1e-6 * r1.pmax
    assert r1.approach == pytest.approx(r2.approach, rel=1e-7)


def two_bump_gap(grid, sep):
    x, y = grid.mesh()
    return np.minimum(1.0 * x**2 + 1.0 * (y - sep) ** 2, 1.0 * x**2 + 0.5 * (y + sep) ** 2 + 1e-6)


@pytest.mark.parametrize("method", ["cg", "gs"])
def test_two_bumps_complementarity(method):
    grid = Grid(40, 80, 0.25e-3, 0.25e-3)
    gap = two_bump_gap(grid, sep=4.5e-3)
    r = solve_normal(gap, grid, MAT, fn=FN, method=method, tol=1e-10)
    labels, n = ndimage.label(r.contact)
    assert n == 2
    loads = [r.pressure[labels == k].sum() * grid.element_area for k in (1, 2)]
    assert sum(loads) == pytest.approx(FN, rel=1e-9)
    assert min(loads) > 0.1 * FN  # both bumps carry load
    assert (r.pressure >= 0).all()
    e = gap + convolve(r.pressure, grid, MAT) - r.approach
    scale = r.approach - gap.min()
    assert e.min() >= -1e-6 * scale
    assert np.abs(e[r.contact]).max() <= 1e-6 * scale
    assert np.abs(r.pressure * e).max() <= 1e-6 * r.pmax * scale


@pytest.mark.parametrize("method", ["cg", "pk", "gs"])
def test_subpatches_interaction_factor(method):
    """Two bumps cut apart at y = 0 (CONTACT's reduced interaction between sub-patches):
    factor 1 is the plain half-space; factor 0 makes each bump the contact problem of its
    own gap alone (the other bump lifted away), solved separately; in between, the
    reduced operator f A + (1 - f) diag(A_aa) is checked by complementarity."""
    grid = Grid(40, 80, 0.25e-3, 0.25e-3)
    gap = two_bump_gap(grid, sep=4.5e-3)
    _, y = grid.mesh()
    approach = 2e-5
    kw = dict(approach=approach, method=method, tol=1e-10)
    plain = solve_normal(gap, grid, MAT, **kw)
    one = solve_normal(gap, grid, MAT, subpatches=SubPatches((0.0,), (1.0,)), **kw)
    assert np.abs(one.pressure - plain.pressure).max() <= 1e-8 * plain.pmax
    zero = solve_normal(gap, grid, MAT, subpatches=SubPatches((0.0,), (0.0,)), **kw)
    alone = sum(solve_normal(np.where(side, gap, 1.0), grid, MAT, **kw).pressure for side in (y <= 0, y > 0))
    assert np.abs(zero.pressure - alone).max() <= 1e-7 * plain.pmax
    assert zero.fn > plain.fn  # less interaction, stiffer: more force at the same approach
    f = 0.46
    half = solve_normal(gap, grid, MAT, subpatches=SubPatches((0.0,), (f,)), **kw)
    assert plain.fn < half.fn < zero.fn
    lo = y <= 0
    u = np.zeros(grid.shape)
    for src in (lo, ~lo):
        part = convolve(np.where(src, half.pressure, 0.0), grid, MAT)
        u += np.where(src, part, f * part)  # full within the source's sub-patch
    e = gap + u - approach
    scale = approach - gap.min()
    assert e.min() >= -1e-6 * scale and np.abs(e[half.contact]).max() <= 1e-6 * scale


@pytest.mark.parametrize(
    "args, word",
    [
        (((0.0, 1e-3), (0.5,)), "2 cuts need as many factors"),
        (((1e-3, 0.0), (0.5, 0.5)), "ascending"),
        (((0.0,), (1.5,)), r"\[0, 1\]"),
        (((np.nan,), (0.5,)), "finite"),
    ],
)
def test_subpatches_bad_arguments(args, word):
    with pytest.raises(InputError, match=word):
        SubPatches(*args)
    with pytest.raises(InputError, match="SubPatches"):
        solve_normal(np.ones((4, 4)), Grid(4, 4, 1e-4, 1e-4), MAT, fn=1.0, subpatches=(0.0, 0.5))


@pytest.mark.parametrize("control", ["fn", "approach"])
def test_nested_start_same_answer_fewer_products(control):
    """The nested (coarse-grid) start of CG gives the cold start's pressure to the
    tolerance and saves FFT products on the fine grid."""
    ref = hertz(1.0, 0.5, FN, MAT)
    grid = Grid.covering(ref.a, ref.b, n_per_semiaxis=60, margin=1.2)
    assert min(grid.shape) >= 128
    gap = hertz_gap(grid, 1.0, 0.5)
    kw = {"fn": FN} if control == "fn" else {"approach": ref.approach}
    cold = solve_normal(gap, grid, MAT, nested=False, **kw)
    warm = solve_normal(gap, grid, MAT, **kw)
    assert cold.coarse_fft_products == 0 and warm.coarse_fft_products > 0
    assert warm.fft_products < cold.fft_products
    assert np.abs(warm.pressure - cold.pressure).max() < 1e-5 * cold.pmax
    assert abs(warm.fn / cold.fn - 1) < 1e-6


def test_warm_start_converges_at_once():
    ref, grid, A, B = hertz_case(1.0, 10)
    gap = hertz_gap(grid, A, B)
    cold = solve_normal(gap, grid, MAT, fn=FN)
    warm = solve_normal(gap, grid, MAT, fn=FN, p0=cold.pressure)
    assert warm.iterations <= 1
    assert np.allclose(warm.pressure, cold.pressure, rtol=0, atol=1e-6 * cold.pmax)
    warm_gs = solve_normal(gap, grid, MAT, approach=cold.approach, method="gs", p0=cold.pressure)
    assert warm_gs.iterations < 5


GRID = Grid(20, 20, 0.4e-3, 0.4e-3)
GAP = hertz_gap(GRID, 1.0, 1.0)


@pytest.mark.parametrize(
    "kwargs, error, word",
    [
        (dict(fn=-1.0), InputError, "fn"),
        (dict(fn=0.0), InputError, "fn"),
        (dict(fn=np.nan), InputError, "fn"),
        (dict(), InputError, "exactly one"),
        (dict(fn=1e4, approach=1e-5), InputError, "exactly one"),
        (dict(approach=-1e-6), NoContactError, "no contact"),
        (dict(fn=1e4, method="newton"), InputError, "method"),
        (dict(fn=1e4, tol=0.0), InputError, "tol"),
        (dict(fn=1e4, omega=2.5), InputError, "omega"),
        (dict(fn=1e4, p0=-np.ones((20, 20))), InputError, "p0"),
    ],
)
def test_bad_arguments(kwargs, error, word):
    with pytest.raises(error, match=word):
        solve_normal(GAP, GRID, MAT, **kwargs)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_gap(bad):
    gap = GAP.copy()
    gap[3, 4] = bad
    with pytest.raises(InputError, match="gap .*non-finite.*index \\(3, 4\\)"):
        solve_normal(gap, GRID, MAT, fn=1e4)


def test_gap_of_wrong_shape():
    with pytest.raises(InputError, match="gap must have shape"):
        solve_normal(GAP[:, :10], GRID, MAT, fn=1e4)


def test_grid_too_small():
    # 10 kN on this gap gives a ~3.2 mm radius; the grid reaches only 2 mm
    grid = Grid(20, 20, 0.2e-3, 0.2e-3)
    with pytest.raises(GridTooSmallError, match="grid edge"):
        solve_normal(hertz_gap(grid, 0.5, 0.5), grid, MAT, fn=1e4)


@pytest.mark.parametrize("method", ["cg", "pk", "gs"])
def test_not_converged_raises_with_residual(method):
    with pytest.raises(ConvergenceError, match="did not converge") as info:
        solve_normal(GAP, GRID, MAT, fn=1e4, method=method, max_iter=2, tol=1e-12)
    assert info.value.residual > 1e-12
    assert info.value.result is not None and np.isfinite(info.value.result.pressure).all()


def test_shim_reports_bad_handle_and_codes():
    """normal_solve_c: an unknown workspace handle, or one of another grid size, gives
    BAD_HANDLE; an unknown control or method code BAD_ARGUMENT."""
    from railvti._native import core
    from railvti._status import Status
    from railvti.contact.workspace import workspace

    grid = Grid(8, 8, 1e-4, 1e-4)
    h = np.zeros(grid.shape, order="F")

    def info(handle, control=1, method=1):
        p = np.zeros(grid.shape, order="F")
        return core.normal_solve_c(handle, h, control, method, 1e-8, 10, 1.0, 1.0, 0.0, p)[-1]

    mat = Material(shear_modulus=80e9, poisson=0.3)
    assert info(999) == Status.BAD_HANDLE
    assert info(workspace(Grid(10, 8, 1e-4, 1e-4), mat)) == Status.BAD_HANDLE
    assert info(workspace(grid, mat), control=3) == Status.BAD_ARGUMENT
    assert info(workspace(grid, mat), method=4) == Status.BAD_ARGUMENT
