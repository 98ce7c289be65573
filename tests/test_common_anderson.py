"""fortran/common: Anderson mixing (common_anderson) and the small dense solves
(common_dense), checked against numpy through the shims of api_common.f90."""

import numpy as np
import pytest

from railvti._native import core
from railvti._status import Status


def _affine(n: int, radius: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """G with eigenvalues spread over [-radius, 0.9] (plus a small non-symmetric part), b."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    g = q @ np.diag(np.linspace(-radius, 0.9, n)) @ q.T + 0.05 * rng.standard_normal((n, n))
    return np.asfortranarray(g), rng.standard_normal(n)


def test_anderson_solves_an_affine_map_that_plain_iteration_cannot():
    """x = G x + b with spectral radius ~1.7 (plain iteration diverges): Anderson with
    depth n is GMRES in disguise and reaches numpy.linalg.solve's x in about n steps."""
    n = 8
    g, b = _affine(n, 1.6, 3)
    assert max(abs(np.linalg.eigvals(g))) > 1.5
    exact = np.linalg.solve(np.eye(n) - g, b)
    x, _, iters, resid, info = core.anderson_affine_c(g, b, np.zeros(n), n, 40, 1e-13, 0)
    assert info == Status.OK
    assert iters <= n + 3
    np.testing.assert_allclose(x, exact, rtol=1e-10, atol=1e-12 * np.abs(exact).max())
    # the plain iteration from the same start runs away
    _, _, _, resid0, info0 = core.anderson_affine_c(g, b, np.zeros(n), 0, 40, 1e-13, 0)
    assert info0 == Status.NOT_CONVERGED and resid0 > 1e-2


def test_depth_zero_is_the_plain_iteration():
    """With memory 0 every iterate is G x + b of the previous one (numpy recurrence)."""
    n, steps = 6, 25
    g, b = _affine(n, 0.8, 5)
    x0 = np.linspace(-1.0, 1.0, n)
    _, hist, iters, _, info = core.anderson_affine_c(g, b, x0, 0, steps, 0.0, 0)
    assert info == Status.NOT_CONVERGED and iters == steps
    x = x0.copy()
    for k in range(steps + 1):
        np.testing.assert_allclose(hist[:, k], x, rtol=1e-12, atol=1e-14)
        x = g @ x + b


def test_small_depth_beats_plain_iteration_on_a_slow_contraction():
    """A symmetric contraction with spectral radius 0.98 (plain iteration needs ~1,100 steps
    to 1e-12): depth 5 converges to numpy's solution at least four times faster."""
    rng = np.random.default_rng(11)
    n = 60
    q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    g = np.asfortranarray(q @ np.diag(np.linspace(-0.5, 0.98, n)) @ q.T)
    b = rng.standard_normal(n)
    exact = np.linalg.solve(np.eye(n) - g, b)
    x, _, it_aa, _, info = core.anderson_affine_c(g, b, np.zeros(n), 5, 3000, 1e-12, 0)
    assert info == Status.OK
    np.testing.assert_allclose(x, exact, rtol=1e-9, atol=1e-10 * np.abs(exact).max())
    _, _, it_plain, _, info0 = core.anderson_affine_c(g, b, np.zeros(n), 0, 3000, 1e-12, 0)
    assert info0 == Status.OK
    assert 4 * it_aa < it_plain


def test_restart_takes_the_last_plain_step():
    """anderson_restart: the iterate becomes G(x) of the previous iterate; the method still
    converges afterwards."""
    n = 8
    g, b = _affine(n, 1.6, 3)
    x, hist, iters, _, info = core.anderson_affine_c(g, b, np.zeros(n), n, 60, 1e-13, 4)
    assert info == Status.OK and iters > 4
    np.testing.assert_allclose(hist[:, 4], g @ hist[:, 3] + b, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(x, np.linalg.solve(np.eye(n) - g, b), rtol=1e-10)


@pytest.mark.parametrize("n", [1, 3, 17])
def test_dense_inverse_matches_numpy(n):
    rng = np.random.default_rng(n)
    a = rng.standard_normal((n, n)) + n * np.eye(n)
    ainv, info = core.dense_inverse_c(np.asfortranarray(a))
    assert info == Status.OK
    np.testing.assert_allclose(ainv, np.linalg.inv(a), rtol=1e-12, atol=1e-14)


def test_dense_inverse_reports_a_singular_matrix():
    a = np.asfortranarray([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]])
    _, info = core.dense_inverse_c(a)
    assert info == Status.SINGULAR


@pytest.mark.parametrize("n", [1, 2, 5])
def test_spd_solve_matches_numpy(n):
    rng = np.random.default_rng(10 + n)
    m = rng.standard_normal((n, n))
    h = m @ m.T + 0.1 * np.eye(n)
    rhs = rng.standard_normal(n)
    x, info = core.spd_solve_small_c(np.asfortranarray(h), rhs)
    assert info == Status.OK
    np.testing.assert_allclose(x, np.linalg.solve(h, rhs), rtol=1e-11)


def test_spd_solve_refuses_an_indefinite_matrix():
    h = np.asfortranarray([[1.0, 2.0], [2.0, 1.0]])  # eigenvalues 3 and -1
    _, info = core.spd_solve_small_c(h, np.ones(2))
    assert info == Status.NOT_POSITIVE_DEFINITE
