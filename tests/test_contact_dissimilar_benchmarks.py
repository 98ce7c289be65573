"""Published benchmarks of dissimilar materials (railvti.contact.dissimilar).

* Bentall and Johnson (1967), free rolling of an aluminium roller on a steel one (the
  CONTACT user guide's sect. 'The 2D Bentall-Johnson test-case' prints the data and the
  results): at vanishing friction the whole patch slips and the free-rolling creepage is
  xi = 0.457 kappa a / R, kappa = 2 beta (their theory); the slip changes direction where
  half of the Hertz load lies inside |x| < x0, x0 = 0.404 a (the same theory: t = -mu p sgn(s),
  s = xi + 2 K/G p). CONTACT reports xi = 5.260e-4 (mu = 1e-4), 4.29e-4 (mu = 0.05) and
  3.59e-4 (mu = 10), and the peak pressure 103.14 -> 103.81 MPa (+0.65 %) with the coupling.
* Spence (1975): a sphere pressed progressively onto a half-space of another material keeps a
  central stick zone of constant radius ratio c/a; beta = 0.5 (a sphere with nu = 0 on a
  rigid plane), mu = 0.2986 gives c/a = 0.5 (Spence
  1975, as used by Kalker 1990 sect. 5.3.1 and CONTACT's example spence35). With the full
  coupling c/a depends on beta besides beta/mu (the tractions feed back on the pressure):
  beta = 0.333, nu = 0.25 at the same beta/mu gives 0.57 here, so the one published point is
  the test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from railvti import Material
from railvti.contact import Grid, hertz_gap
from railvti.contact.dissimilar import BodyPair, solve_dissimilar_rolling, solve_progressive_compression

ALU, STEEL_BJ = Material(23.0e9, 0.31), Material(82.0e9, 0.28)
A_BJ, R_BJ = 1.0e-4, 0.025  # half-width and combined radius, m


def _bentall_johnson(mu: float, n: int = 100):
    """Free rolling (Fx = 0) of the 2-D case on a long strip (rows 1-2 of 4, dy = 1000 a)."""
    pair = BodyPair(ALU, STEEL_BJ)
    dx = 2.0 * A_BJ / n
    grid = Grid(int(round(2.16 * A_BJ / dx)), 4, dx, 1000.0 * A_BJ)
    gap = hertz_gap(grid, 1.0 / (2.0 * R_BJ), 0.0)
    gap[:, [0, 3]] = 1.0  # the strip: rows 1 and 2 only
    load = math.pi * A_BJ**2 * pair.contact_modulus / (4.0 * R_BJ)  # 2-D Hertz, N/m
    res = solve_dissimilar_rolling(
        gap, grid, pair, mu, 2.0 * grid.dy * load, (0, 0, 0), 10.0, free_rolling=True
    )
    return pair, grid, res


def test_bentall_johnson_complete_slip_creepage_and_reversal_points():
    pair, grid, res = _bentall_johnson(1e-4)
    xi_theory = 0.457 * 2.0 * pair.beta * A_BJ / R_BJ
    # the softer wheel (K > 0) needs a negative xi here (railvti's rolling direction -x)
    assert res.creepage[0] < 0
    assert abs(res.creepage[0]) == pytest.approx(xi_theory, rel=5e-3)
    assert abs(res.rolling.fx) <= 1e-6 * res.rolling.mu * res.rolling.fn
    tx = res.rolling.tx[:, 1]
    inside = res.rolling.pressure[:, 1] > 0
    # all slip but the elements where the slip changes sign
    assert np.count_nonzero(res.rolling.status[inside, 1] == 1) <= 2
    flips = grid.x[:-1][np.diff(np.sign(tx)) != 0] + grid.dx / 2
    flips = flips[np.abs(flips) < 0.9 * A_BJ]
    assert flips / A_BJ == pytest.approx([-0.404, 0.404], abs=grid.dx / A_BJ)


@pytest.mark.parametrize("mu, xi_contact", [(0.05, 4.29e-4), (10.0, 3.59e-4)])
def test_bentall_johnson_partial_slip_creepage_against_contact(mu, xi_contact):
    pair, grid, res = _bentall_johnson(mu)
    assert abs(res.creepage[0]) == pytest.approx(xi_contact, rel=0.015)
    assert res.outer_iterations >= 2


def test_bentall_johnson_peak_pressure_rises_by_the_coupling():
    """CONTACT: 103.14 MPa at mu = 1e-4 (Hertz's 103.14), 103.81 MPa at mu = 10 (+0.65 %)."""
    _, _, low = _bentall_johnson(1e-4)
    _, _, high = _bentall_johnson(10.0)
    assert low.rolling.pmax == pytest.approx(103.14e6, rel=2e-3)
    rise = high.rolling.pmax / low.rolling.pmax - 1.0
    assert rise == pytest.approx(0.0065, abs=0.0015)


def _spence(pair: BodyPair, mu: float, n: int = 31, steps: int = 25, normal_coupling: bool = True):
    R, dx = 0.1215, 2.0e-4
    grid = Grid(n, n, dx, dx)
    gap = hertz_gap(grid, 1.0 / (2.0 * R), 1.0 / (2.0 * R))
    a_end = dx * steps / 2.0  # the radius grows one element per step
    fns = [4.0 * (a_end * k / steps) ** 3 * pair.contact_modulus / (3.0 * R) for k in range(1, steps + 1)]
    return solve_progressive_compression(
        gap, grid, pair, mu, fns, outer_tol=1e-5, normal_coupling=normal_coupling
    )


def test_spence_stick_ratio_one_half():
    """beta = 0.5 (sphere G1, nu = 0 on a rigid plane), mu = 0.2986: c/a = 0.5 (Spence 1975)."""
    pair = BodyPair(Material(0.5e9, 0.0), Material(0.5e14, 0.0))
    assert pair.beta == pytest.approx(0.5, abs=1e-4)
    res = _spence(pair, 0.2986)
    ratio = res.stick_ratio[-5:].mean()  # the area estimate steps by elements: mean of the last 5
    assert ratio == pytest.approx(0.5, abs=0.03)
    # outward tractions on the sphere (body 1): they resist its inward (Boussinesq) displacement
    j = res.grid.ny // 2
    x = res.grid.x
    assert (res.tx[:, j] * x >= 0).all() and (res.tx[:, j] * x).max() > 0
    assert (res.outer_iterations[1:] >= 2).all()


def test_swapping_the_bodies_mirrors_free_rolling():
    """Steel wheel on an aluminium rail: K changes sign, so do xi and the tractions (the softer
    body rolls faster whichever it is); the pressure is the same."""
    a = _bentall_johnson(1e-4)[2]
    pair = BodyPair(STEEL_BJ, ALU)
    assert pair.difference_parameter == pytest.approx(-BodyPair(ALU, STEEL_BJ).difference_parameter)
    dx = 2.0 * A_BJ / 100
    grid = Grid(int(round(2.16 * A_BJ / dx)), 4, dx, 1000.0 * A_BJ)
    gap = hertz_gap(grid, 1.0 / (2.0 * R_BJ), 0.0)
    gap[:, [0, 3]] = 1.0
    load = math.pi * A_BJ**2 * pair.contact_modulus / (4.0 * R_BJ)
    b = solve_dissimilar_rolling(
        gap, grid, pair, 1e-4, 2.0 * grid.dy * load, (0, 0, 0), 10.0, free_rolling=True
    )
    assert b.creepage[0] == pytest.approx(-a.creepage[0], rel=1e-6)
    assert np.allclose(b.rolling.pressure, a.rolling.pressure, rtol=0, atol=1e-9 * a.rolling.pmax)
    assert np.allclose(b.rolling.tx, -a.rolling.tx, rtol=0, atol=1e-6 * 1e-4 * a.rolling.pmax)


def test_johnsons_process_makes_the_ratio_a_function_of_beta_over_mu():
    """Without the tractions' effect on the pressure (Johnson's process) the shift problem scales
    with beta/mu: the ratio is the same for a nu = 0 sphere (beta 0.5) and Al on steel (beta 0.144)
    at beta/mu = 1.6745; with the full coupling the stiffer pair's ratio is the larger, and Spence's
    0.5 belongs to the full coupling (Johnson's process gives 0.62 there)."""
    jp = []
    for pair in (BodyPair(Material(0.5e9, 0.0), Material(0.5e14, 0.0)), BodyPair(ALU, STEEL_BJ)):
        mu = pair.beta / (0.5 / 0.2986)
        jp.append(_spence(pair, mu, normal_coupling=False).stick_ratio[-5:].mean())
    full_alu = _spence(BodyPair(ALU, STEEL_BJ), BodyPair(ALU, STEEL_BJ).beta / (0.5 / 0.2986))
    assert jp[0] == pytest.approx(jp[1], abs=0.01)
    assert jp[0] > 0.55
    assert 0.55 < full_alu.stick_ratio[-5:].mean() < jp[1] + 0.01
