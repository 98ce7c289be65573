"""Dissimilar materials (railvti.contact.dissimilar, fortran/contact/contact_coupling.f90):
the combined constants against Kalker's and CONTACT's printed values, the cross influence
coefficients against quadrature and against the 2-D half-plane solution, the K = 0 limit
against today's solver (bit for bit), the extra-slip input leaving steady rolling unchanged,
and the bad input. The published benchmarks (Bentall-Johnson, Spence) are in
test_contact_dissimilar_benchmarks.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from railvti import STEEL, InputError, Material
from railvti._native import core
from railvti.contact import Grid, hertz_gap, solve_rolling
from railvti.contact.dissimilar import (
    BodyPair,
    coupling_displacements,
    cross_coefficients,
    solve_dissimilar_rolling,
    solve_progressive_compression,
)
from railvti.contact.workspace import workspace

ALU = Material(23.0e9, 0.31)


def test_combined_constants_match_kalker_eq_1_44_as_printed_by_contact():
    """Aluminium on steel: G = 35 924 N/mm^2, nu = 0.3034, K = 0.100 (CONTACT user guide,
    sect. 'The 2D Bentall-Johnson test-case', from Kalker 1990 eq. 1.44), kappa = 2 beta = 0.2877."""
    pair = BodyPair(ALU, Material(82.0e9, 0.28))
    assert pair.shear_modulus == pytest.approx(35.924e9, rel=2e-5)
    assert pair.poisson == pytest.approx(0.3034, abs=1e-4)
    assert pair.difference_parameter == pytest.approx(0.100, abs=5e-4)
    assert 2.0 * pair.beta == pytest.approx(0.2877, abs=1e-4)


def test_combined_modulus_is_hertz_e_star_and_beta_is_dundurs():
    """E* from Young's moduli (Johnson eq. 4.3) and beta from Johnson eq. 5.4 directly."""
    w, r = Material(30e9, -0.2), Material(200e9, 0.45)
    pair = BodyPair(w, r)
    e_star = 1.0 / ((1 - w.poisson**2) / w.young_modulus + (1 - r.poisson**2) / r.young_modulus)
    assert pair.contact_modulus == pytest.approx(e_star, rel=1e-12)
    beta = (
        0.5
        * ((1 - 2 * w.poisson) / w.shear_modulus - (1 - 2 * r.poisson) / r.shear_modulus)
        / ((1 - w.poisson) / w.shear_modulus + (1 - r.poisson) / r.shear_modulus)
    )
    assert pair.beta == pytest.approx(beta, rel=1e-12)
    same = BodyPair(STEEL, STEEL)
    assert same.difference_parameter == 0.0
    assert same.combined == STEEL


@pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")
@pytest.mark.parametrize("offset", [(1, 0), (2, 1), (-3, 2), (0, 3), (-1, -1), (4, -2)])
def test_cross_coefficients_match_quadrature(offset):
    g = Grid(5, 4, 1.0e-3, 2.0e-3)
    cx, cy = cross_coefficients(g, "x"), cross_coefficients(g, "y")
    k, m = offset
    X, Y = k * g.dx, m * g.dy
    hx, hy = g.dx / 2, g.dy / 2
    qx, _ = integrate.dblquad(
        lambda y, x: (X - x) / ((X - x) ** 2 + (Y - y) ** 2), -hx, hx, -hy, hy, epsabs=1e-14
    )
    qy, _ = integrate.dblquad(
        lambda y, x: (Y - y) / ((X - x) ** 2 + (Y - y) ** 2), -hx, hx, -hy, hy, epsabs=1e-14
    )
    assert cx[k + 4, m + 3] == pytest.approx(qx / math.pi, rel=1e-9, abs=1e-15)
    assert cy[k + 4, m + 3] == pytest.approx(qy / math.pi, rel=1e-9, abs=1e-15)
    assert cx[4, 3] == 0.0 and cy[4, 3] == 0.0  # the element's own: zero by symmetry


def test_pressure_on_a_long_strip_gives_the_half_plane_displacement():
    """2-D limit: a line load P moves a half-plane's surface by -(1 - 2 nu) P sgn(x) / (4 G)
    (Johnson 1985, eq. 2.19b), so the displacement difference of the pair is -K/G P sgn(x):
    for a uniform pressure on a strip of width w, u_x(x) = -K/G p (2x) inside, -K/G p w sgn(x) outside."""
    pair = BodyPair(ALU, STEEL)
    kg = pair.difference_parameter / pair.shear_modulus
    dx, nx = 1e-5, 40
    g = Grid(nx, 3, dx, 1.0e3 * nx * dx)
    p = np.zeros(g.shape, order="F")
    p[10:30, 1] = 1.0e8
    zero = np.zeros(g.shape, order="F")
    un, ux, uy = coupling_displacements(g, pair, p, zero, zero)
    x = g.x - 0.5 * (g.x[9] + g.x[10]) - 10 * dx  # from the strip's centre
    w = 20 * dx
    expected = -kg * 1.0e8 * np.where(np.abs(x) < w / 2, 2.0 * x, w * np.sign(x))
    assert np.allclose(ux[:, 1], expected, rtol=0, atol=2e-3 * kg * 1.0e8 * w)
    assert np.abs(uy[:, 1]).max() < 1e-6 * np.abs(ux).max()  # the strip's centre line
    assert not un.any()


def test_cross_terms_are_reciprocal():
    """Betti: the gap's increase at A from a traction at B equals the tangential
    displacement difference at B from the same pressure at A (symmetric operator)."""
    pair = BodyPair(ALU, STEEL)
    g = Grid(8, 7, 1e-4, 1.5e-4)
    a, b = (2, 3), (6, 1)
    zero = np.zeros(g.shape, order="F")
    pa = zero.copy()
    pa[a] = 1.0
    tb = zero.copy()
    tb[b] = 1.0
    _, ux, uy = coupling_displacements(g, pair, pa, zero, zero)
    un_x, _, _ = coupling_displacements(g, pair, zero, tb, zero)
    un_y, _, _ = coupling_displacements(g, pair, zero, zero, tb)
    assert un_x[a] == pytest.approx(ux[b], rel=1e-13)
    assert un_y[a] == pytest.approx(uy[b], rel=1e-13)
    assert ux[b] != 0.0 and uy[b] != 0.0


def _ellipse_case():
    g = Grid(40, 36, 2.5e-4, 2.5e-4)
    return g, hertz_gap(g, 1 / (2 * 0.46), 1 / (2 * 0.3))


@pytest.mark.parametrize("creepage", [(1e-3, 0.0, 0.0), (5e-4, 2e-4, 0.5), (-3e-3, 0.0, 0.0)])
def test_identical_materials_equal_todays_solver_bit_for_bit(creepage):
    """beta = 0: the richer model reduces to the decoupled solver exactly (one outer iteration)."""
    g, gap = _ellipse_case()
    ref = solve_rolling(gap, g, STEEL, 0.3, 1e4, creepage, 10.0)
    res = solve_dissimilar_rolling(gap, g, BodyPair(STEEL, STEEL), 0.3, 1e4, creepage, 10.0)
    assert res.outer_iterations == 1
    for name in ("pressure", "tx", "ty", "slip_velocity_x", "slip_velocity_y"):
        assert np.array_equal(getattr(res.rolling, name), getattr(ref, name)), name
    assert res.rolling.fx == ref.fx and res.rolling.fy == ref.fy


def test_zero_extra_slip_leaves_the_steady_solver_unchanged():
    """The shim with the extra-slip input (kg = 0: a zero field) against rolling_solve_c, the
    unchanged path, on the same workspace: identical tractions and slip."""
    g, gap = _ellipse_case()
    ref = solve_rolling(gap, g, STEEL, 0.3, 1e4, (1e-3, 1e-4, 0.3), 10.0)
    p = ref.pressure
    h = workspace(g, STEEL, tangential=True)
    out = []
    for fn, extra in ((core.rolling_solve_c, ()), (core.dissimilar_rolling_c, (0.0,))):
        tx, ty = np.zeros(g.shape, order="F"), np.zeros(g.shape, order="F")
        args = (p, g.x0, g.y0, 1e-3, 1e-4, 0.3, 0.3, 10.0, 2, 16, 1, 1e-7, 2000, 0, *extra, tx, ty)
        status, sx, sy, iters, resid, info = fn(h, *args)
        out.append((tx, ty, sx, sy, status, iters))
    for x, y in zip(*out):
        assert np.array_equal(x, y)
    assert np.array_equal(out[0][0], ref.tx)


def test_dissimilar_rolling_reports_outer_iterations_and_converges():
    g, gap = _ellipse_case()
    res = solve_dissimilar_rolling(gap, g, BodyPair(ALU, STEEL), 0.3, 1e4, (1e-3, 0.0, 0.0), 10.0)
    assert 2 <= res.outer_iterations <= 30
    assert res.outer_change <= 1e-6
    ref = solve_rolling(gap, g, BodyPair(ALU, STEEL).combined, 0.3, 1e4, (1e-3, 0.0, 0.0), 10.0)
    # the coupling moves the force (here by a few per cent), it does not change its sign
    assert res.rolling.fx != ref.fx and res.rolling.fx * ref.fx > 0


def test_identical_materials_compress_without_tangential_traction():
    """K = 0: a pure normal load causes no tangential displacement difference, hence no traction."""
    g = Grid(15, 15, 2e-4, 2e-4)
    gap = hertz_gap(g, 4.0, 4.0)
    res = solve_progressive_compression(gap, g, BodyPair(STEEL, STEEL), 0.3, [1e2, 5e2, 1e3])
    assert not res.tx.any() and not res.ty.any()
    assert (res.outer_iterations == 1).all()
    assert (res.n_adhesion == res.n_contact).all()


@pytest.mark.parametrize(
    "args, word",
    [
        ((0.0, 0.3, 82e9, 0.28), "wheel_shear_modulus"),
        ((23e9, 0.3, -1.0, 0.28), "rail_shear_modulus"),
        ((23e9, 0.5, 82e9, 0.28), "wheel_poisson"),
        ((23e9, 0.3, 82e9, -1.0), "rail_poisson"),
        ((23e9, math.nan, 82e9, 0.28), "wheel_poisson"),
    ],
)
def test_bad_material_names_the_key(args, word):
    with pytest.raises(InputError, match=word):
        BodyPair.from_constants(*args)


def test_bad_arguments():
    g, gap = _ellipse_case()
    pair = BodyPair(ALU, STEEL)
    with pytest.raises(InputError, match="pair"):
        solve_dissimilar_rolling(gap, g, STEEL, 0.3, 1e4, (0, 0, 0), 1.0)
    with pytest.raises(InputError, match="wheel"):
        BodyPair(82e9, STEEL)
    with pytest.raises(InputError, match="fn_steps"):
        solve_progressive_compression(gap, g, pair, 0.3, [2e3, 1e3])
    with pytest.raises(InputError, match="mu"):
        solve_progressive_compression(gap, g, pair, 0.0, [1e3])
    with pytest.raises(InputError, match="kernel"):
        cross_coefficients(g, "z")


def test_shift_step_reproduces_cattaneo_mindlin():
    """The incremental tangential solver (coupling_shift_step) on its own, K = 0: a sphere under
    Hertz pressure shifted rigidly by delta = 3 mu P (2 - nu)/(8 G a) (1 - (c/a)^2) (Mindlin; Johnson
    1985 eq. 7.42 for two equal bodies) has the stick radius c and Q = mu P (1 - (c/a)^3)."""
    from railvti.contact import hertz, solve_normal

    g = Grid(41, 41, 1.5e-4, 1.5e-4)
    gap = hertz_gap(g, 4.0, 4.0)
    fn, mu = 2.0e3, 0.3
    normal = solve_normal(gap, g, STEEL, fn=fn, tol=1e-10)
    a = hertz(4.0, 4.0, fn, STEEL).a
    G, nu = STEEL.shear_modulus, STEEL.poisson
    delta = 3 * mu * fn * (2 - nu) / (8 * G * a) * (1 - 0.5**2)  # c/a = 1/2
    zero = np.zeros(g.shape, order="F")
    tx, ty = np.zeros(g.shape, order="F"), np.zeros(g.shape, order="F")
    status, ux, uy, iters, change, info = core.coupling_shift_c(
        g.dx, g.dy, G, nu, 0.0, mu, normal.pressure, zero, zero, delta, 0.0, 1e-10, 20000, tx, ty
    )
    assert info == 0
    q = -tx.sum() * g.element_area  # the rail pulls the shifted wheel back
    assert q / (mu * fn) == pytest.approx(7.0 / 8.0, abs=0.02)
    stick = np.sqrt(np.count_nonzero(status == 1) / np.count_nonzero(normal.pressure))
    assert stick == pytest.approx(0.5, abs=0.04)
    # in the stick zone the displacement difference cancels the shift
    assert np.abs(ux[status == 1] + delta).max() <= 1e-8 * delta
