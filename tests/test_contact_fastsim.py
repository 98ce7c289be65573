"""FASTSIM: linear limit against Kalker's linear theory, saturation, the Coulomb
bound, symmetry, consistency, the strip-wise form, and bad input."""

import numpy as np
import pytest

from railvti._native import core
from railvti.contact.fastsim import fastsim, fastsim_forces, fastsim_grid, equivalent_ellipse
from railvti.contact.grid import Grid
from railvti.contact.kalker import KalkerRangeError, kalker_coefficients, linear_creep_forces
from railvti.errors import InputError
from railvti.material import Material

MAT = Material(shear_modulus=82e9, poisson=0.28)
FN = 80e3
MU = 0.3


@pytest.mark.parametrize("a, b", [(6e-3, 4e-3), (2e-3, 10e-3), (10e-3, 2e-3), (5e-3, 5e-3)])
@pytest.mark.parametrize("k", [0, 1, 2])
def test_linear_limit_matches_kalker(a, b, k):
    """Tiny creepage, tractions far from the bound: FASTSIM with L from C_ij gives
    Kalker's linear forces (exact up to the strips' midpoint rule in y)."""
    cr = [0.0, 0.0, 0.0]
    cr[k] = 1e-7 if k < 2 else 1e-4
    r = fastsim(a, b, FN, MAT, 100.0, cr, nx=40, ny=60)
    fx_lin, fy_lin = linear_creep_forces(a, b, MAT, cr)
    assert not r.slip.any()
    if k == 0:
        assert r.fx == pytest.approx(fx_lin, rel=2e-3)
        assert abs(r.fy) < 1e-9 * abs(fx_lin)
    else:
        assert r.fy == pytest.approx(fy_lin, rel=2e-3)
        assert abs(r.fx) < 1e-9 * abs(fy_lin)


def test_forces_only_routine_equals_fields_routine():
    cr = (2e-3, -1e-3, 0.4)
    r = fastsim(6e-3, 4e-3, FN, MAT, MU, cr, nx=25, ny=17)
    fx, fy, mz = fastsim_forces(6e-3, 4e-3, FN, MAT, MU, *cr, nx=25, ny=17)
    assert (fx, fy, mz) == pytest.approx((r.fx, r.fy, r.mz), rel=1e-13, abs=1e-9)


def test_vectorised_forces_shape_and_zero_fn_kernel():
    fx, fy, mz = fastsim_forces(6e-3, 4e-3, [FN, FN], MAT, MU, [1e-3, 2e-3], 0.0, 0.0)
    assert fx.shape == (2,) and abs(fx[1]) > abs(fx[0])
    # the Fortran routine itself returns zero forces for fn <= 0 (the vehicle code relies on it)
    c = kalker_coefficients(1.5, 0.28)
    out = core.fastsim_ellipse_c(
        6e-3, 4e-3, 82e9, *c, MU, [0.0, -1.0], [1e-3] * 2, [0.0] * 2, [0.0] * 2, 10, 10
    )
    assert all((v == 0.0).all() for v in out)


@pytest.mark.parametrize("cr", [(0.05, 0, 0), (0, 0.05, 0), (0.03, 0.04, 0), (-0.1, 0, 0)])
def test_saturation(cr):
    """Large creepage: the whole patch slides, |F| -> mu Fn (the pressure is scaled to
    sum to Fn)."""
    r = fastsim(6e-3, 4e-3, FN, MAT, MU, cr, nx=50, ny=50)
    f = np.hypot(r.fx, r.fy)
    assert f == pytest.approx(MU * FN, rel=5e-3)
    assert f <= MU * FN * (1 + 1e-12)
    # the force points against the creepage
    assert np.dot([r.fx, r.fy], cr[:2]) < 0


@pytest.mark.parametrize("pressure", ["parabolic", "hertz"])
@pytest.mark.parametrize("cr", [(2e-3, 1e-3, 0.0), (0.0, 0.0, 3.0), (1e-3, -2e-3, -1.5)])
def test_coulomb_bound_and_consistency(pressure, cr):
    r = fastsim(6e-3, 4e-3, FN, MAT, MU, cr, nx=30, ny=30, speed=20.0, pressure=pressure)
    tau = np.hypot(r.tx, r.ty)
    bound = MU * r.pressure
    assert (tau <= bound * (1 + 1e-12) + 1e-9).all()
    # elements marked slipping sit on the bound; others are below it
    np.testing.assert_allclose(tau[r.slip], bound[r.slip], rtol=1e-12)
    # forces are the sums of the tractions, the pressure sums to Fn
    assert r.fx == pytest.approx((r.tx * r.element_area).sum(), rel=1e-12, abs=1e-9)
    assert r.fy == pytest.approx((r.ty * r.element_area).sum(), rel=1e-12, abs=1e-9)
    mz = ((r.x * r.ty - r.y * r.tx) * r.element_area).sum()
    assert r.mz == pytest.approx(mz, rel=1e-10, abs=1e-12)
    assert (r.pressure * r.element_area).sum() == pytest.approx(FN, rel=1e-12)
    # power = sum of density; no slip velocity in adhesion
    assert r.power == pytest.approx((r.power_density * r.element_area).sum(), rel=1e-12)
    assert (r.slip_velocity[~r.slip] == 0).all()
    assert r.slip.any() and r.power > 0


def test_slip_opposes_traction():
    r = fastsim(6e-3, 4e-3, FN, MAT, MU, (2e-3, 1e-3, 2.0), nx=30, ny=30)
    # the kernel's slip vector is antiparallel to the traction on sliding elements
    c = r.coefficients
    out = core.fastsim_fields_c(6e-3, 4e-3, 82e9, *c, MU, FN, 2e-3, 1e-3, 2.0, 30, 30, 1)
    tx, ty, sx, sy, slip = out[3], out[4], out[5], out[6], out[7].astype(bool)
    cosang = (tx * sx + ty * sy)[slip] / (np.hypot(tx, ty) * np.hypot(sx, sy))[slip]
    np.testing.assert_allclose(cosang, -1.0, atol=1e-9)


def test_symmetry():
    a, b = 6e-3, 4e-3
    r1 = fastsim(a, b, FN, MAT, MU, (1e-3, 2e-3, 0.0))
    r2 = fastsim(a, b, FN, MAT, MU, (1e-3, -2e-3, 0.0))
    r3 = fastsim(a, b, FN, MAT, MU, (-1e-3, 2e-3, 0.0))
    assert r2.fy == pytest.approx(-r1.fy, rel=1e-12)
    assert r2.fx == pytest.approx(r1.fx, rel=1e-12)
    assert r3.fx == pytest.approx(-r1.fx, rel=1e-12)
    # spin sign flips the lateral force and the moment
    s1 = fastsim(a, b, FN, MAT, MU, (0.0, 0.0, 2.0))
    s2 = fastsim(a, b, FN, MAT, MU, (0.0, 0.0, -2.0))
    assert s2.fy == pytest.approx(-s1.fy, rel=1e-12) and s2.mz == pytest.approx(-s1.mz, rel=1e-12)
    assert s1.fy < 0  # Kalker's sign: Fy = -G (ab)^1.5 C23 phi


def test_monotone_creep_curve():
    xi = np.linspace(0.0, 0.01, 21)
    fx, _, _ = fastsim_forces(6e-3, 4e-3, FN, MAT, MU, xi, 0.0, 0.0)
    assert (np.diff(-fx) >= -1e-9).all()


def _hertz_grid(a, b, n):
    g = Grid.covering(a, b, n)
    x, y = g.mesh()
    p = np.sqrt(np.maximum(0.0, 1.0 - (x / a) ** 2 - (y / b) ** 2))
    return g, np.asfortranarray(p * FN / (p.sum() * g.element_area))


@pytest.mark.parametrize("cr", [(1e-3, 0, 0), (0, 1e-3, 0), (0, 0, 0.5), (2e-3, 1e-3, 0.3)])
def test_strip_form_on_hertz_pressure_matches_elliptic_form(cr):
    a, b = 6e-3, 4e-3
    g, p = _hertz_grid(a, b, 40)
    ref = fastsim(a, b, FN, MAT, MU, cr, nx=60, ny=60, pressure="hertz")
    for kw in ({"ellipse": (a, b)}, {}):
        r = fastsim_grid(p, g, MAT, MU, cr, **kw)
        fref = np.hypot(ref.fx, ref.fy)
        assert abs(r.fx - ref.fx) < 5e-3 * fref
        assert abs(r.fy - ref.fy) < 5e-3 * fref
        assert (np.hypot(r.tx, r.ty) <= MU * p * (1 + 1e-12)).all()
        assert r.fx == pytest.approx((r.tx * g.element_area).sum(), rel=1e-12, abs=1e-9)


def test_equivalent_ellipse_of_hertz_patch():
    g, p = _hertz_grid(6e-3, 4e-3, 40)
    ae, be = equivalent_ellipse(p, g)
    assert ae == pytest.approx(6e-3, rel=1e-2) and be == pytest.approx(4e-3, rel=1e-2)


def test_strip_flexibility_keeps_linear_fx_and_handles_two_runs():
    """'strip' flexibility: the linear Fx of the equivalent ellipse is kept; a patch
    with two separate runs per strip (non-convex) is marched run by run."""
    g = Grid(nx=40, ny=10, dx=0.5e-3, dy=0.5e-3)
    x, y = g.mesh()
    p = np.where((np.abs(np.abs(x) - 5e-3) < 3e-3) & (np.abs(y) < 2e-3), 1e9, 0.0)
    lin = fastsim_grid(p, g, MAT, 100.0, (1e-7, 0, 0), flexibility="ellipse")
    strip = fastsim_grid(p, g, MAT, 100.0, (1e-7, 0, 0), flexibility="strip")
    assert strip.fx == pytest.approx(lin.fx, rel=1e-10)
    # both runs start at zero traction at their leading edges: the traction
    # just behind each leading edge is the same
    j = 5
    rows = np.flatnonzero(p[:, j] > 0)
    lead2, lead1 = rows[-1], rows[np.flatnonzero(np.diff(rows) > 1)[0]]
    assert lin.tx[lead2, j] == pytest.approx(lin.tx[lead1, j], rel=1e-12)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"mu": -0.1}, "mu"),
        ({"fn": 0.0}, "fn"),
        ({"fn": -5.0}, "fn"),
        ({"a": 0.0}, "a"),
        ({"b": -1e-3}, "b"),
        ({"creepage": (float("nan"), 0, 0)}, "xi"),
        ({"creepage": (0, 0, float("inf"))}, "phi"),
        ({"creepage": (0, 0)}, "creepage"),
        ({"nx": 0}, "nx"),
        ({"speed": 0.0}, "speed"),
        ({"pressure": "flat"}, "pressure"),
        ({"material": "steel"}, "material"),
    ],
)
def test_bad_input_elliptic(kwargs, match):
    args = {"a": 6e-3, "b": 4e-3, "fn": FN, "material": MAT, "mu": MU, "creepage": (1e-3, 0, 0)}
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        fastsim(**args)


def test_bad_aspect_ratio():
    with pytest.raises(KalkerRangeError):
        fastsim(20e-3, 1e-3, FN, MAT, MU, (1e-3, 0, 0))


def test_bad_input_grid():
    g, p = _hertz_grid(6e-3, 4e-3, 10)
    with pytest.raises(InputError, match="no contact"):
        fastsim_grid(np.zeros(g.shape), g, MAT, MU, (1e-3, 0, 0))
    with pytest.raises(InputError, match="p must be >= 0"):
        fastsim_grid(-p, g, MAT, MU, (1e-3, 0, 0))
    with pytest.raises(InputError, match="shape"):
        fastsim_grid(p[:-1], g, MAT, MU, (1e-3, 0, 0))
    with pytest.raises(InputError, match="mu"):
        fastsim_grid(p, g, MAT, -1.0, (1e-3, 0, 0))
    with pytest.raises(InputError, match="eta"):
        fastsim_grid(p, g, MAT, MU, (1e-3, float("nan"), 0))
    with pytest.raises(InputError, match="flexibility"):
        fastsim_grid(p, g, MAT, MU, (1e-3, 0, 0), flexibility="x")
    with pytest.raises(InputError, match="grid"):
        fastsim_grid(p, None, MAT, MU, (1e-3, 0, 0))


def test_sweep_finite_and_bounded():
    """a/b over Kalker's whole table, mu 0.05-0.6, creepages 1e-6-0.1, spin-dominated
    cases: forces finite, |F| <= mu Fn, opposing the creepage in xi."""
    rng = np.random.default_rng(3)
    for ratio in (0.1, 0.3, 1.0, 3.0, 10.0):
        a, b = 5e-3 * np.sqrt(ratio), 5e-3 / np.sqrt(ratio)
        for mu in (0.0, 0.05, 0.6):
            xi = 10.0 ** rng.uniform(-6, -1, 40) * rng.choice([-1, 1], 40)
            eta = 10.0 ** rng.uniform(-6, -1, 40) * rng.choice([-1, 1], 40)
            phi = 10.0 ** rng.uniform(-3, 2, 40) * rng.choice([-1, 1], 40)
            fx, fy, mz = fastsim_forces(a, b, FN, MAT, mu, xi, eta, phi, nx=12, ny=12)
            assert np.isfinite(fx).all() and np.isfinite(fy).all() and np.isfinite(mz).all()
            assert (np.hypot(fx, fy) <= mu * FN * (1 + 1e-12) + 1e-9).all()
            fx0, _, _ = fastsim_forces(a, b, FN, MAT, mu, xi, 0.0, 0.0, nx=12, ny=12)
            assert (fx0 * xi <= 0).all()
