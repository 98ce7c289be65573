"""Kalker's creep coefficients: Table E.3 interpolation and the linear theory."""

import csv
from importlib import resources

import numpy as np
import pytest

from railvti.contact.kalker import KalkerRangeError, kalker_coefficients, kalker_table, linear_creep_forces
from railvti.errors import InputError
from railvti.material import Material


def _raw_table():
    text = resources.files("railvti").joinpath("data", "kalker_table_e3.csv").read_text()
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    rows = list(csv.reader(lines))
    return np.array(rows[1:], dtype=float)


def test_csv_keeps_its_source():
    text = resources.files("railvti").joinpath("data", "kalker_table_e3.csv").read_text()
    assert "Kalker" in text.splitlines()[0] and "Table E.3" in text.splitlines()[0]


@pytest.mark.parametrize("col, nu", [(0, 0.0), (1, 0.25), (2, 0.5)])
def test_nodes_reproduced_exactly(col, nu):
    raw = _raw_table()
    c11, c22, c23 = kalker_coefficients(raw[:, 0], nu)
    np.testing.assert_allclose(c11, raw[:, 1 + col], rtol=1e-12)
    np.testing.assert_allclose(c22, raw[:, 4 + col], rtol=1e-12)
    np.testing.assert_allclose(c23, raw[:, 7 + col], rtol=1e-12)


def test_scalar_in_scalar_out():
    c = kalker_coefficients(1.0, 0.25)
    assert c == pytest.approx((4.12, 3.67, 1.47), rel=1e-12)
    assert all(isinstance(v, float) for v in c)


def test_linear_in_nu_between_columns():
    ab = np.array([0.2, 0.77, 3.0])
    lo = np.array(kalker_coefficients(ab, 0.0))
    mid = np.array(kalker_coefficients(ab, 0.25))
    q = np.array(kalker_coefficients(ab, 0.125))
    np.testing.assert_allclose(q, 0.5 * (lo + mid), rtol=1e-12)


def test_monotone_and_smooth_between_nodes():
    """PCHIP: between two nodes the value stays within the nodes' bracket, and the
    curve has no kinks larger than the table's own (second differences small)."""
    ab, c = kalker_table()
    fine = np.exp(np.linspace(np.log(ab[0]), np.log(ab[-1]), 2001))
    for nu, m in ((0.0, 0), (0.25, 1), (0.5, 2)):
        vals = np.array(kalker_coefficients(fine, nu))  # (3, n)
        idx = np.clip(np.searchsorted(ab, fine, side="right") - 1, 0, len(ab) - 2)
        lo = np.minimum(c[:, idx, m], c[:, idx + 1, m])
        hi = np.maximum(c[:, idx, m], c[:, idx + 1, m])
        assert (vals >= lo - 1e-12).all() and (vals <= hi + 1e-12).all()
        # continuity: neighbouring samples differ by little
        jumps = np.abs(np.diff(vals, axis=1)) / vals[:, :-1]
        assert jumps.max() < 5e-3


def test_kalker_physics_trends():
    """C22 = C11 at nu = 0 (Kalker); all grow with a/b at nu = 0.25."""
    ab = np.linspace(0.1, 10, 50)
    c11, c22, _ = kalker_coefficients(ab, 0.0)
    np.testing.assert_allclose(c11, c22, rtol=1e-12)
    for v in kalker_coefficients(ab, 0.25)[1:]:
        assert (np.diff(v) > 0).all()


@pytest.mark.parametrize("ab", [0.05, 10.5, -1.0, 0.0])
def test_out_of_table_raises(ab):
    with pytest.raises(KalkerRangeError, match="a_over_b"):
        kalker_coefficients(ab, 0.25)


@pytest.mark.parametrize("nu", [-0.1, 0.6])
def test_bad_poisson_raises(nu):
    with pytest.raises(KalkerRangeError, match="poisson"):
        kalker_coefficients(1.0, nu)


@pytest.mark.parametrize(
    "ab, nu", [(float("nan"), 0.25), ([1.0, np.nan], 0.25), ("x", 0.25), (1.0, float("nan"))]
)
def test_nan_input_raises(ab, nu):
    with pytest.raises(InputError):
        kalker_coefficients(ab, nu)


def test_linear_forces_signs_and_values():
    mat = Material(shear_modulus=80e9, poisson=0.25)
    a, b = 5e-3, 5e-3
    fx, fy = linear_creep_forces(a, b, mat, (1e-3, 0.0, 0.0))
    assert fx == pytest.approx(-80e9 * a * b * 4.12e-3)
    assert fy == 0.0
    fx, fy = linear_creep_forces(a, b, mat, (0.0, 1e-3, 2.0))
    assert fy == pytest.approx(-80e9 * a * b * 3.67e-3 - 80e9 * (a * b) ** 1.5 * 1.47 * 2.0)


def _fortran_table():
    """The table in the Fortran layout: a/b (n,), columns (n, 9), read from the CSV here."""
    raw = _raw_table()
    return raw[:, 0].copy(), np.asfortranarray(raw[:, 1:])


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.25, 0.28, 0.5])
def test_fortran_kalker_interp_equals_python(nu):
    """The Fortran kalker_interp (FASTSIM's coefficients), given the CSV's table, gives the
    values of the independent Python implementation (scipy's PCHIP)."""
    from railvti._native import core
    from railvti._status import Status

    ab = np.exp(np.linspace(np.log(0.1), np.log(10.0), 401))
    c11, c22, c23, info, ibad = core.fastsim_kalker_c(ab, nu, *_fortran_table())
    assert info == Status.OK and ibad == 0
    for f, p in zip((c11, c22, c23), kalker_coefficients(ab, nu)):
        np.testing.assert_allclose(f, p, rtol=1e-13)


def test_fortran_kalker_interp_range():
    """a/b outside the table: BAD_ARGUMENT with the index of the first bad a/b; nu outside
    [0, 0.5]: BAD_ARGUMENT with no index."""
    from railvti._native import core
    from railvti._status import Status

    _, _, _, info, ibad = core.fastsim_kalker_c([1.0, 0.09, 11.0], 0.25, *_fortran_table())
    assert info == Status.BAD_ARGUMENT and ibad == 2
    _, _, _, info, ibad = core.fastsim_kalker_c([1.0], 0.51, *_fortran_table())
    assert info == Status.BAD_ARGUMENT and ibad == 0


def test_fastsim_uses_the_one_table():
    """FASTSIM's coefficients come from the packaged CSV: at a table node they are the
    published values (Kalker 1990, Table E.3, a/b = 0.5, nu = 0.25: C11 = 3.62, C22 = 3.01,
    C23 = 0.929); an ellipse outside the table is refused."""
    from railvti.contact import fastsim

    mat = Material(shear_modulus=80e9, poisson=0.25)
    r = fastsim(2e-3, 4e-3, 1e4, mat, 0.3, (1e-4, 0.0, 0.0), nx=4, ny=4)
    assert r.coefficients == pytest.approx((3.62, 3.01, 0.929), rel=1e-13)
    with pytest.raises(KalkerRangeError, match="a/b"):
        fastsim(2e-3, 4e-2, 1e4, mat, 0.3, (1e-4, 0.0, 0.0), nx=4, ny=4)
