"""The nested (coarse-grid) start of the normal CG on large grids (issue 33): coarse grids
of FFT-friendly size, the start trimmed where the coarse displacement predicts an open
gap, and the answer checked against an independent product and Hertz."""

import numpy as np
import pytest

from railvti import Material
from railvti.contact import Grid, convolve, hertz, hertz_gap, solve_normal
from railvti.contact import normal as normal_mod

MAT = Material(shear_modulus=82e9, poisson=0.28)
FN = 1.0e4


def prime_factors_are_235(m):
    for f in (2, 3, 5):
        while m % f == 0:
            m //= f
    return m == 1


@pytest.mark.parametrize("n", [7, 13, 225, 226, 257, 450, 500, 1000])
def test_coarse_grid_size_and_gap(n):
    """The coarse grid has at least half the elements per side, the smallest such size with
    prime factors 2, 3, 5; each coarse element averages the 2 x 2 fine ones it covers
    (loops here), and beyond the fine grid the last fine row and column are repeated."""
    ny = 9
    rng = np.random.default_rng(n)
    h = rng.random((n, ny))
    hc, coarse = normal_mod._coarsen(np.asfortranarray(h), Grid(n, ny, 1e-4, 2e-4))
    half = (n + 1) // 2
    assert coarse.nx >= half and prime_factors_are_235(coarse.nx)
    assert not any(prime_factors_are_235(m) for m in range(half, coarse.nx))
    assert coarse.ny == 5 and (coarse.dx, coarse.dy) == (2e-4, 4e-4)
    for i in range(coarse.nx):
        for j in range(coarse.ny):
            fine = [h[min(2 * i + a, n - 1), min(2 * j + b, ny - 1)] for a in (0, 1) for b in (0, 1)]
            assert hc[i, j] == pytest.approx(np.mean(fine), rel=1e-14)


@pytest.mark.parametrize("control", ["fn", "approach"])
def test_large_grid_meets_contact_conditions(control):
    """226 x 160 elements (coarse grids 120 x 80 rounded up from 113 x 80, then cold): the
    nested CG's answer satisfies the contact conditions on an independent FFT product
    (railvti.contact.convolve), equals the cold start's to the tolerance and Hertz's p0 to
    0.5 %; the CG needs few iterations (column corrections exact)."""
    A, B = 1.0, 0.6
    ref = hertz(A, B, FN, MAT)
    grid = Grid(226, 160, 2.4 * ref.a / 226, 2.4 * ref.b / 160, -1.2 * ref.a, -1.2 * ref.b)
    gap = hertz_gap(grid, A, B)
    kw = {"fn": FN} if control == "fn" else {"approach": ref.approach}
    warm = solve_normal(gap, grid, MAT, **kw)
    cold = solve_normal(gap, grid, MAT, nested=False, **kw)
    e = gap + convolve(warm.pressure, grid, MAT) - warm.approach
    scale = warm.approach - gap.min()
    assert (warm.pressure >= 0).all()
    assert e.min() >= -1e-6 * scale
    assert np.abs(e[warm.contact]).max() <= 1e-6 * scale
    assert np.abs(warm.pressure - cold.pressure).max() < 1e-5 * cold.pmax
    assert warm.fn == pytest.approx(cold.fn, rel=1e-6)
    assert warm.approach == pytest.approx(cold.approach, rel=1e-6)
    assert warm.pmax == pytest.approx(ref.p0, rel=5e-3)
    assert warm.coarse_fft_products > 0 and warm.iterations <= 12
    assert warm.fft_products < cold.fft_products


def test_trimmed_start_fewer_elements_outside_contact(monkeypatch):
    """Trimming the interpolated start where the coarse solution predicts an open gap puts
    fewer elements outside the final contact area into the start than plain bilinear
    interpolation (the untrimmed start, trim share infinite), misses almost none of it,
    and saves FFT products on the fine grid."""
    ref = hertz(1.0, 1.0, FN, MAT)
    grid = Grid(256, 256, 2.4 * ref.a / 256, 2.4 * ref.a / 256, -1.2 * ref.a, -1.2 * ref.a)
    gap = np.asfortranarray(hertz_gap(grid, 1.0, 1.0))
    final = solve_normal(gap, grid, MAT, fn=FN)
    trimmed, _ = normal_mod._nested_start(gap, grid, MAT, 1, FN, 0.0, 1, 2000)
    monkeypatch.setattr(normal_mod, "_NESTED_TRIM", np.inf)
    plain, _ = normal_mod._nested_start(gap, grid, MAT, 1, FN, 0.0, 1, 2000)
    untrimmed = solve_normal(gap, grid, MAT, fn=FN)
    outside = ~final.contact
    assert ((trimmed > 0) & outside).sum() < 0.5 * ((plain > 0) & outside).sum()
    assert ((trimmed == 0) & final.contact).sum() <= 0.002 * final.n_contact
    assert final.fft_products < untrimmed.fft_products
    assert np.abs(final.pressure - untrimmed.pressure).max() < 1e-5 * final.pmax
