"""The pruned FFT product (issue 33) against direct summation in numpy and the plain FFT product.

The pruned product transforms along x only the ny loaded columns of the zero-padded grid, and
along y blocks of x frequencies (16 per block: sizes below give one block, several, and a
remainder); a point-symmetric coefficient field is multiplied by a real spectrum, any other by
the complex one.
"""

import numpy as np
import pytest

from railvti import Material
from railvti.contact import Grid, convolve, convolve_field, influence_field
from railvti.errors import InputError

MAT = Material(shear_modulus=80e9, poisson=0.3)


def numpy_direct(c, q):
    """u[i, j] = sum_kl c[(i - k) mod 2nx, (j - l) mod 2ny] q[k, l], summed in numpy."""
    nx, ny = q.shape
    i = np.arange(nx)
    j = np.arange(ny)
    di = (i[:, None] - i[None, :]) % (2 * nx)  # [i, k]
    dj = (j[:, None] - j[None, :]) % (2 * ny)  # [j, l]
    a = c[di[:, None, :, None], dj[None, :, None, :]]  # [i, j, k, l]
    return np.einsum("ijkl,kl->ij", a, q)


SIZES = [(2, 2), (15, 9), (31, 4), (47, 13), (20, 20), (9, 33)]


@pytest.mark.parametrize("nx, ny", SIZES)
@pytest.mark.parametrize("kernel", ["zz", "xx", "xy"])
def test_pruned_equals_direct_and_plain(nx, ny, kernel):
    rng = np.random.default_rng(nx * 100 + ny)
    grid = Grid(nx, ny, 1.5e-4, 1.0e-4)
    c = influence_field(grid, MAT, kernel)
    q = rng.normal(size=grid.shape) * 1e8
    q[rng.random(grid.shape) < 0.3] = 0.0
    ref = numpy_direct(c, q)
    scale = np.abs(c).max() * np.abs(q).sum()  # bounds every |u|; rounding is relative to it
    u, real = convolve_field(c, q)
    plain, _ = convolve_field(c, q, "fft_plain")
    assert real  # influence fields are point-symmetric: the real spectrum is used
    assert np.abs(u - ref).max() <= 1e-14 * scale
    assert np.abs(plain - ref).max() <= 1e-14 * scale
    assert np.abs(u - ref).max() <= 1e-12 * np.abs(ref).max()
    # the solvers' product (convolve's 'fft') is the pruned one
    assert np.array_equal(convolve(q, grid, MAT, kernel), u)


@pytest.mark.parametrize("nx, ny", SIZES)
def test_pruned_complex_spectrum_for_an_asymmetric_field(nx, ny):
    """A field without point symmetry (as viscoelastic rolling's filtered ones) takes the
    complex spectrum, and is still the linear convolution."""
    rng = np.random.default_rng(7 + nx)
    c = rng.normal(size=(2 * nx, 2 * ny))
    q = rng.normal(size=(nx, ny))
    ref = numpy_direct(c, q)
    u, real = convolve_field(c, q)
    assert not real
    assert np.abs(u - ref).max() <= 1e-13 * np.abs(c).max() * np.abs(q).sum()
    d, _ = convolve_field(c, q, "direct")
    assert np.abs(d - ref).max() <= 1e-13 * np.abs(c).max() * np.abs(q).sum()


def test_symmetric_random_field_takes_the_real_spectrum():
    rng = np.random.default_rng(3)
    nx, ny = 20, 11
    c = rng.normal(size=(2 * nx, 2 * ny))
    c = 0.5 * (c + np.roll(c[::-1, ::-1], (1, 1), axis=(0, 1)))  # c[-i, -j] = c[i, j]
    q = rng.normal(size=(nx, ny))
    u, real = convolve_field(c, q)
    assert real
    assert np.abs(u - numpy_direct(c, q)).max() <= 1e-13 * np.abs(c).max() * np.abs(q).sum()


@pytest.mark.parametrize("nx, ny", SIZES)
@pytest.mark.parametrize("symmetric", [True, False])
def test_pruned_pair_product_equals_direct(nx, ny, symmetric):
    """The tangential pair product (rolling, transient contact), pruned, against numpy sums:
    with the Cerruti fields (point-symmetric: real spectra) and with random fields (complex)."""
    from railvti._native import core
    from railvti._status import Status

    rng = np.random.default_rng(11 + nx + ny)
    grid = Grid(nx, ny, 1.2e-4, 1.0e-4)
    if symmetric:
        cxx, cxy, cyy = (influence_field(grid, MAT, k) for k in ("xx", "xy", "yy"))
    else:
        cxx, cxy, cyy = (rng.normal(size=(2 * nx, 2 * ny)) for _ in range(3))
    qx = rng.normal(size=grid.shape) * 1e8
    qy = rng.normal(size=grid.shape) * 1e8
    c = np.asfortranarray(np.stack([cxx, cxy, cyy], axis=2))
    ux, uy, info = core.convolve_pair_c(c, np.asfortranarray(qx), np.asfortranarray(qy))
    assert info == Status.OK
    ref_x = numpy_direct(cxx, qx) + numpy_direct(cxy, qy)
    ref_y = numpy_direct(cxy, qx) + numpy_direct(cyy, qy)
    scale = np.abs(c).max() * (np.abs(qx).sum() + np.abs(qy).sum())
    assert np.abs(ux - ref_x).max() <= 1e-14 * scale
    assert np.abs(uy - ref_y).max() <= 1e-14 * scale


def test_single_source_gives_the_coefficient_column():
    grid = Grid(40, 17, 1e-4, 1e-4)
    c = influence_field(grid, MAT, "zz")
    q = np.zeros(grid.shape)
    q[31, 2] = 1.0
    u, _ = convolve_field(c, q)
    assert u[3, 16] == pytest.approx(c[3 - 31, 16 - 2], rel=1e-11)
    assert u[39, 0] == pytest.approx(c[8, -2], rel=1e-11)


def test_bad_input_names_the_argument():
    c = np.zeros((8, 6))
    with pytest.raises(InputError, match="method"):
        convolve_field(c, np.zeros((4, 3)), "spectral")
    with pytest.raises(InputError, match="coefficients"):
        convolve_field(c, np.zeros((4, 4)))
    with pytest.raises(InputError, match="values"):
        convolve_field(c, np.zeros(12))
    q = np.zeros((4, 3))
    q[0, 0] = np.inf
    with pytest.raises(InputError, match="values"):
        convolve_field(c, q)
