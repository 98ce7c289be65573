"""Steady rolling contact (railvti.contact.solve_rolling): Hertz smoke tests,
consistency of the results, Kalker's linear theory and saturation on coarse grids."""
from __future__ import annotations

import numpy as np
import pytest

from railvti.contact import Grid, hertz, hertz_gap, solve_rolling, solve_tangential
from railvti.errors import ConvergenceError, InputError
from railvti.material import Material

MAT = Material(shear_modulus=82e9, poisson=0.25)
FN = 10e3


def _case(a_over_b: float = 1.0, n: int = 8):
    A = 0.5 / 0.3
    B = A * a_over_b ** 2 if a_over_b <= 1 else A  # rough: the gap ratio sets a/b
    h = hertz(A, B, FN, MAT)
    grid = Grid.covering(h.a, h.b, n, 1.25)
    return grid, hertz_gap(grid, A, B), h


@pytest.mark.parametrize("method", ["gs", "fftgs"])
def test_hertz_smoke_partial_slip(method):
    grid, gap, h = _case()
    r = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 2e-4, 0.3), 30.0, method=method)
    assert r.converged and r.residual <= 1e-7
    # creep force opposes the creepage and is bounded by friction
    assert r.fx < 0 and r.fy < 0
    assert np.hypot(r.fx, r.fy) < 0.3 * r.fn
    # adhesion at the leading edge (largest x) on the centre line, slip at the trailing edge
    jc = grid.ny // 2
    row = r.status[:, jc]
    inside = np.nonzero(row)[0]
    assert row[inside[-1]] == 1 and row[inside[0]] == 2


def test_methods_agree():
    grid, gap, _ = _case()
    a = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 0.0, 0.5), 10.0, method="gs", tol=1e-9)
    b = solve_rolling(gap, grid, MAT, 0.3, FN, (1e-3, 0.0, 0.5), 10.0, method="fftgs", block=2, tol=1e-9)
    np.testing.assert_allclose(b.tx, a.tx, atol=1e-6 * a.pmax)
    np.testing.assert_allclose(b.ty, a.ty, atol=1e-6 * a.pmax)
