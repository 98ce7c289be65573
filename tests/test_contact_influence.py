"""Influence coefficients against quadrature of eqs 14-16, and FFT against direct sums."""

import numpy as np
import pytest
from scipy.integrate import dblquad

from railvti import Material
from railvti.contact import Grid, convolve, influence_field
from railvti.errors import InputError

MAT = Material(shear_modulus=80e9, poisson=0.3)
G, NU = MAT.shear_modulus, MAT.poisson


def integrand(kernel):
    """Point-load kernels of two quasi-identical half-spaces (Kalker 1990, sect. 1.5)."""

    def f(y, x):
        r = np.hypot(x, y)
        if kernel == "zz":
            return (1 - NU) / (np.pi * G) / r
        if kernel == "xx":
            return ((1 - NU) / r + NU * x * x / r**3) / (np.pi * G)
        if kernel == "yy":
            return ((1 - NU) / r + NU * y * y / r**3) / (np.pi * G)
        return NU * x * y / r**3 / (np.pi * G)

    return f


def quadrature(kernel, X, Y, dx, dy):
    """Integrate over the element centred at the origin seen from (X, Y); split at the
    point's own coordinates so that a singular corner lies on the subdivision lines."""
    f = integrand(kernel)
    xs = sorted({X - dx / 2, X + dx / 2} | ({0.0} if abs(X) < dx / 2 else set()))
    ys = sorted({Y - dy / 2, Y + dy / 2} | ({0.0} if abs(Y) < dy / 2 else set()))
    total = 0.0
    for x0, x1 in zip(xs[:-1], xs[1:]):
        for y0, y1 in zip(ys[:-1], ys[1:]):
            total += dblquad(f, x0, x1, y0, y1, epsabs=0, epsrel=1e-10)[0]
    return total


@pytest.mark.parametrize("kernel", ["zz", "xx", "yy", "xy"])
@pytest.mark.parametrize("k, l", [(0, 0), (1, 0), (0, 2), (3, -2), (-5, 4)])
def test_coefficients_match_quadrature(kernel, k, l):
    dx, dy = 1.0e-4, 0.6e-4
    grid = Grid(8, 8, dx, dy)
    c = influence_field(grid, MAT, kernel)
    coef = c[k % (2 * grid.nx), l % (2 * grid.ny)]
    ref = quadrature(kernel, k * dx, l * dy, dx, dy)
    if kernel == "xy" and (k == 0 or l == 0):
        assert abs(coef) < 1e-12 * abs(c).max()
    else:
        assert coef == pytest.approx(ref, rel=1e-7)


def test_far_field_is_point_load():
    grid = Grid(64, 64, 1e-4, 1e-4)
    c = influence_field(grid, MAT, "zz")
    r = np.hypot(50 * grid.dx, 30 * grid.dy)
    assert c[50, 30] == pytest.approx((1 - NU) / (np.pi * G) * grid.element_area / r, rel=1e-3)


def test_symmetries():
    grid = Grid(9, 7, 1e-4, 2e-4)
    zz = influence_field(grid, MAT, "zz")
    xy = influence_field(grid, MAT, "xy")
    for k, l in [(1, 2), (3, 5), (8, 6)]:
        assert zz[k, l] == pytest.approx(zz[-k, -l], rel=1e-13)
        assert zz[k, l] == pytest.approx(zz[-k, l], rel=1e-13)
        assert xy[k, l] == pytest.approx(-xy[-k, l], rel=1e-12)


@pytest.mark.parametrize("kernel", ["zz", "xx", "yy", "xy"])
def test_fft_equals_direct(kernel):
    rng = np.random.default_rng(1)
    grid = Grid(23, 17, 1.5e-4, 1.0e-4)
    q = rng.normal(size=grid.shape) * 1e8
    q[rng.random(grid.shape) < 0.3] = 0.0
    u_fft = convolve(q, grid, MAT, kernel, method="fft")
    u_dir = convolve(q, grid, MAT, kernel, method="direct")
    assert np.abs(u_fft - u_dir).max() <= 1e-12 * np.abs(u_dir).max()


def test_convolution_of_single_element_is_coefficient_column():
    grid = Grid(6, 5, 1e-4, 1e-4)
    q = np.zeros(grid.shape)
    q[2, 3] = 1.0
    u = convolve(q, grid, MAT, "zz")
    c = influence_field(grid, MAT, "zz")
    assert u[4, 1] == pytest.approx(c[2, -2], rel=1e-12)


def test_bad_kernel_and_traction():
    grid = Grid(4, 4, 1e-4, 1e-4)
    with pytest.raises(InputError, match="kernel"):
        influence_field(grid, MAT, "zx")
    q = np.zeros(grid.shape)
    q[1, 1] = np.nan
    with pytest.raises(InputError, match="traction"):
        convolve(q, grid, MAT)
    with pytest.raises(InputError, match="shape"):
        convolve(np.zeros((3, 4)), grid, MAT)


def test_kernel_codes_guarded_by_the_shims():
    """Bad kernel or method codes reaching the Fortran shims give BAD_ARGUMENT, not garbage."""
    from railvti._native import core
    from railvti._status import Status

    grid = Grid(4, 4, 1e-4, 1e-4)
    assert (
        core.influence_field_c(9, 4, 4, 1e-4, 1e-4, MAT.shear_modulus, MAT.poisson)[1] == Status.BAD_ARGUMENT
    )
    q = np.zeros(grid.shape, order="F")
    for kernel, method in ((0, 1), (5, 2), (1, 3)):
        assert (
            core.convolve_c(kernel, method, 1e-4, 1e-4, MAT.shear_modulus, MAT.poisson, q)[1]
            == Status.BAD_ARGUMENT
        )
