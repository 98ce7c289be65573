"""The normal CG stops on its recurrence's u = A p (issue 33): the residual it reports, and
its convergence, hold for the exact product of the pressure it returns.

The CG updates u = A p by the recurrence u - tau A t plus the columns of A of the elements
the projection changed, and above ``CONFIRM_TOL`` no longer confirms the last iterate on an
exact product. Here the complementarity residual of each returned pressure is recomputed
from an independent product (direct summation on the small grid, the library's
zero-padded FFT product on a plan of its own on the large ones) and the returned approach."""

import numpy as np
import pytest

from railvti import Material
from railvti.contact import Grid, convolve, hertz, hertz_gap, solve_normal

MAT = Material(shear_modulus=82e9, poisson=0.28)
FN = 1.0e4


def independent_residual(h, p, u, approach):
    """||v|| / ||delta - h|| with v = e where p > 0 and min(e, 0) where p = 0, e = h + u -
    delta, both norms over the elements in contact or interpenetrating (normal_residual)."""
    e = h + u - approach
    on = (p > 0.0) | (e < 0.0)
    v = np.where(p > 0.0, e, np.minimum(e, 0.0))
    return np.sqrt(np.sum(v[on] ** 2) / np.sum((approach - h)[on] ** 2))


@pytest.mark.parametrize(
    "side, ab, control",
    [(40, 1.0, "fn"), (100, 3.3, "approach"), (300, 1.0, "fn"), (450, 3.3, "fn"), (450, 1.0, "approach")],
)
def test_reported_residual_holds_for_the_exact_product(side, ab, control):
    ref = hertz(1.0, ab, FN, MAT)
    grid = Grid(side, side, 2.4 * ref.a / side, 2.4 * ref.b / side)
    h = hertz_gap(grid, 1.0, ab)
    kw = {"fn": FN} if control == "fn" else {"approach": ref.approach}
    tol = 1e-8
    r = solve_normal(h, grid, MAT, method="cg", tol=tol, **kw)
    assert r.converged
    p = r.pressure
    u = convolve(p, grid, MAT, method="direct" if side <= 40 else "fft")
    res = independent_residual(h, p, u, r.approach)
    assert res <= tol
    assert abs(res - r.residual) <= 1e-12
