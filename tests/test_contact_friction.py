"""Friction laws (railvti.contact.friction): the laws against their formulas, the element
problem against a brute-force root search, steady rolling with a law against today's
solver, full-slip theory and the law itself in the slip area, the falling creep curve of
Polach's Eurosprinter parameters (converged at every creepage), the FASTSIM variant against
FASTSIM and Kalker's linear theory, Polach's formula against its limits, and bad input."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from railvti._native import core
from railvti.contact import Grid, hertz, hertz_gap, solve_tangential, solve_normal
from railvti.contact.fastsim import fastsim_forces
from railvti.contact.friction import (
    FrictionLaw,
    creep_curve_friction,
    fastsim_friction,
    polach_creep_force,
    solve_tangential_friction,
)
from railvti.contact.kalker import linear_creep_forces
from railvti.errors import InputError
from railvti.material import Material

MAT = Material(shear_modulus=82e9, poisson=0.28)
# Eurosprinter-like contact: wheel radius 0.625 m, rail crown 0.3 m, wheel load 100 kN
GAP_A, GAP_B, FN, SPEED = 0.8, 1.0 / 0.6, 100e3, 40.0 / 3.6
# Polach 2005 (Wear 258, Table 2, as recalled: not checked against the paper here), Eurosprinter dry:
# mu0, A, B (s/m), kA, kS
DRY = (0.55, 0.40, 0.60, 1.00, 0.40)


@pytest.fixture(scope="module")
def patch():
    h = hertz(GAP_A, GAP_B, FN, MAT)
    nx = ny = 30
    dx, dy = 2.4 * h.a / nx, 2.4 * h.b / ny
    grid = Grid(nx, ny, dx, dy, -1.15 * h.a, -1.2 * h.b + dy / 2)
    gap = hertz_gap(grid, GAP_A, GAP_B)
    normal = solve_normal(gap, grid, MAT, fn=FN)
    return grid, gap, normal, h


def _mu_numpy(kind: str, mus: float, muk: float, vh: float, v: np.ndarray) -> np.ndarray:
    d = mus - muk
    if kind == "linear":
        return muk + d * np.maximum(0.0, 1.0 - v / (2.0 * vh))
    if kind == "rational":
        return muk + d / (1.0 + v / vh)
    if kind == "exponential":
        return muk + d * 0.5 ** (v / vh)
    return np.where(v > 0, muk, mus)


@pytest.mark.parametrize("kind", ["coulomb", "linear", "rational", "exponential"])
def test_law_matches_its_formula(kind):
    law = FrictionLaw(kind, 0.5, 0.2, 0.3)
    v = np.array([0.0, 1e-3, 0.1, 0.3, 0.6, 2.0, 50.0])
    np.testing.assert_allclose(law.mu(v), _mu_numpy(kind, 0.5, 0.2, 0.3, v), rtol=1e-14, atol=0)


def test_polach_law_is_polach_formula():
    mu0, a, b = 0.55, 0.4, 0.6
    v = np.linspace(0.0, 10.0, 11)
    np.testing.assert_allclose(
        FrictionLaw.polach(mu0, a, b).mu(v), mu0 * ((1 - a) * np.exp(-b * v) + a), rtol=1e-13
    )


def _brute_roots(law, speed, s0, k, bound0):
    """All solutions of the element problem by a dense scan (numpy): adhesion if
    admissible, and every sign change of F(lam) = (|s0| / (lam + k g(lam)))^2 - 1."""
    p = bound0 / law.mu_static
    smag = float(np.hypot(*s0))
    lam = np.linspace(1e-12, smag, 400_001)
    g = p * law.mu(speed * lam)
    f = (smag / (lam + k * g)) ** 2 - 1.0
    idx = np.nonzero(np.sign(f[:-1]) != np.sign(f[1:]))[0]
    roots = [float(lam[i]) for i in idx]
    adhesion = smag / k <= bound0
    return adhesion, roots


@pytest.mark.parametrize(
    ("s0", "rule"),
    [((3e-3, 1e-3), 0), ((5e-3, -2e-3), 0), ((1.2e-2, 0.0), 0), ((1.7e-2, 4e-3), 0), ((5e-3, -2e-3), 1)],
)
def test_element_problem_against_brute_force(s0, rule):
    # a steep rational law: k p V max|mu'| = 1e-11 * 1e9 * 30 * 30 = 9 >> 1, several roots
    law = FrictionLaw("rational", 0.5, 0.1, 0.01)
    k, bound0, speed = 1e-11, 0.5e9, 30.0
    adhesion, roots = _brute_roots(law, speed, s0, k, bound0)
    nsol_ref = len(roots) + int(adhesion)
    lam_prev = np.array([0.9 * roots[-1] if roots else 0.0])
    tx, ty, stat, lam, nsol = core.friction_element_c(
        *law._args(), rule, speed, np.array([s0[0]]), np.array([s0[1]]), k, k, np.array([bound0]), lam_prev
    )
    assert nsol[0] == nsol_ref
    if rule == 0:
        if adhesion:
            assert stat[0] == 1 and lam[0] == 0.0
        else:
            assert stat[0] == 2 and lam[0] == pytest.approx(roots[0], rel=1e-4)
    else:
        cands = ([0.0] if adhesion else []) + roots
        assert lam[0] == pytest.approx(min(cands, key=lambda r: abs(r - lam_prev[0])), rel=1e-4, abs=1e-12)
    if stat[0] == 2:
        # the equations themselves: s = s0 + k t = lam e, t = -g(lam) e
        g = bound0 / law.mu_static * law.mu(speed * lam[0])[0]
        assert math.hypot(tx[0], ty[0]) == pytest.approx(g, rel=1e-9)
        sx, sy = s0[0] + k * tx[0], s0[1] + k * ty[0]
        assert math.hypot(sx, sy) == pytest.approx(lam[0], rel=1e-8)
        assert sx * tx[0] + sy * ty[0] == pytest.approx(-lam[0] * g, rel=1e-8)


def test_monotone_element_problem_has_one_solution():
    law = FrictionLaw.polach(*DRY[:3])
    s0 = np.array([2e-3, 5e-3, 1e-2])
    tx, ty, stat, lam, nsol = core.friction_element_c(
        *law._args(), 0, SPEED, s0, 0 * s0, 1.2e-11, 1.1e-11, np.full(3, 0.55e9), 0 * s0
    )
    assert np.all(nsol == 1)
    adhesion, roots = _brute_roots(law, SPEED, (s0[2], 0.0), 1.2e-11, 0.55e9)
    assert stat[2] == 2 and lam[2] == pytest.approx(roots[0], rel=1e-4)


def test_nearly_constant_law_gives_the_coulomb_solver(patch):
    # the friction path (friction_element_solve) against today's element_solve
    grid, _, normal, _ = patch
    ref = solve_tangential(normal.pressure, grid, MAT, 0.3, (2e-3, 1e-3, 0.5), SPEED, tol=1e-10)
    law = FrictionLaw("exponential", 0.3, 0.3 * (1 - 1e-12), 1.0)
    r = solve_tangential_friction(normal.pressure, grid, MAT, law, (2e-3, 1e-3, 0.5), SPEED, tol=1e-10)
    assert r.rolling.fx == pytest.approx(ref.fx, rel=1e-7)
    assert r.rolling.fy == pytest.approx(ref.fy, rel=1e-7)
    np.testing.assert_array_equal(r.rolling.status, ref.status)


def test_constant_law_is_todays_solver_bit_for_bit(patch):
    grid, _, normal, _ = patch
    ref = solve_tangential(normal.pressure, grid, MAT, 0.3, (2e-3, 0.0, 0.0), SPEED)
    r = solve_tangential_friction(
        normal.pressure, grid, MAT, FrictionLaw.constant(0.3), (2e-3, 0.0, 0.0), SPEED
    )
    np.testing.assert_array_equal(r.rolling.tx, ref.tx)
    np.testing.assert_array_equal(r.rolling.ty, ref.ty)


@pytest.mark.parametrize("rule", ["smallest", "continuous"])
def test_jump_law_full_slip_and_bounds(patch, rule):
    grid, _, normal, _ = patch
    law = FrictionLaw("coulomb", 0.5, 0.3, root_rule=rule)
    # full slip: F = mu_k Fn (Coulomb's law over the whole patch)
    r = solve_tangential_friction(normal.pressure, grid, MAT, law, (0.05, 0.0, 0.0), SPEED)
    assert -r.fx / normal.fn == pytest.approx(0.3, rel=2e-3)
    # partial slip (continuous rule converges): slip elements on mu_k p, adhesion ones within mu_s p
    if rule == "continuous":
        r = solve_tangential_friction(normal.pressure, grid, MAT, law, (2e-3, 0.0, 0.0), SPEED)
        rr = r.rolling
        t = np.hypot(rr.tx, rr.ty)
        np.testing.assert_allclose(t[rr.slip], 0.3 * rr.pressure[rr.slip], rtol=1e-5)
        assert np.all(t[rr.adhesion] <= 0.5 * rr.pressure[rr.adhesion] * (1 + 1e-9))
        assert r.n_multiple > 0  # adhesion beside kinetic slip: stated


def test_eurosprinter_curve_falls_after_its_peak_and_converges(patch):
    grid, gap, _, _ = patch
    law = FrictionLaw.polach(*DRY[:3])
    xi = np.array([5e-4, 1e-3, 2e-3, 4e-3, 7e-3, 1e-2, 2e-2, 4e-2, 0.1])
    c = creep_curve_friction(gap, grid, MAT, law, FN, xi, SPEED)
    assert c.converged.all()
    f = -c.fx / c.fn
    k = int(np.argmax(f))
    assert 0 < k < len(xi) - 1
    assert np.all(np.diff(f[: k + 1]) > 0) and np.all(np.diff(f[k:]) < 0)
    # full slip at xi = 0.1: the rigid slip dominates, F/Fn -> mu(V xi) (the law)
    assert f[-1] == pytest.approx(float(law.mu(SPEED * 0.1)[0]), rel=5e-3)
    assert f[-1] < 0.8 * f[k]


def test_slip_area_follows_the_law(patch):
    grid, _, normal, _ = patch
    law = FrictionLaw.polach(*DRY[:3])
    r = solve_tangential_friction(normal.pressure, grid, MAT, law, (4e-3, 0.0, 0.0), SPEED, tol=1e-9)
    rr = r.rolling
    mu_local = r.mu_local[rr.slip]
    np.testing.assert_allclose(mu_local, law.mu(rr.slip_velocity[rr.slip]), rtol=1e-6)
    assert rr.slip.any() and rr.adhesion.any() and r.n_multiple == 0


def test_fastsim_variant_reduces_to_fastsim_and_kalker():
    h = hertz(GAP_A, GAP_B, FN, MAT)
    xi = np.array([1e-4, 1e-3, 5e-3])
    ref = fastsim_forces(h.a, h.b, FN, MAT, 0.4, xi, 0.0 * xi, 0.0 * xi, nx=40, ny=40)
    fx, fy, mz, nm = fastsim_friction(
        h.a, h.b, MAT, FrictionLaw.constant(0.4), FN, (xi, 0, 0), SPEED, nx=40, ny=40
    )
    np.testing.assert_allclose(fx, ref[0], rtol=1e-12)
    # slope reduction: linear limit scaled by kred (Kalker's linear theory times kred)
    fx_lin, _ = linear_creep_forces(h.a, h.b, MAT, (1e-7, 0.0, 0.0))
    law = FrictionLaw.polach(*DRY[:3])
    kred = 0.5 * (DRY[3] + DRY[4])
    fx2, *_ = fastsim_friction(
        h.a, h.b, MAT, law, FN, (1e-7, 0, 0), SPEED, slope_reduction=kred, nx=40, ny=40
    )
    assert fx2[0] == pytest.approx(kred * fx_lin, rel=1e-3)


def test_polach_formula_limits():
    h = hertz(GAP_A, GAP_B, FN, MAT)
    mu0, a, b, ka, ks = DRY
    f_small = polach_creep_force(FN, h.a, h.b, MAT, mu0, a, b, ka, ks, SPEED, 1e-7)[0]
    fx_lin, _ = linear_creep_forces(h.a, h.b, MAT, (1e-7, 0.0, 0.0))
    assert f_small == pytest.approx(0.5 * (ka + ks) * abs(fx_lin), rel=1e-4)
    f_big = polach_creep_force(FN, h.a, h.b, MAT, mu0, a, b, ka, ks, SPEED, 1.0)[0]
    mu = mu0 * ((1 - a) * math.exp(-b * SPEED) + a)
    assert f_big == pytest.approx(mu * FN, rel=2e-2)


def test_bem_fastsim_and_polach_agree_on_the_falling_curve(patch):
    # three independent models, constant-slope Polach (kA = kS = 1) and FASTSIM without
    # reduction, against the BEM with falling friction: within 0.05 mu0 Fn everywhere
    grid, gap, _, h = patch
    mu0, a, b = DRY[:3]
    law = FrictionLaw.polach(mu0, a, b)
    xi = np.array([1e-3, 3e-3, 1e-2, 3e-2, 0.1])
    c = creep_curve_friction(gap, grid, MAT, law, FN, xi, SPEED)
    fs, *_ = fastsim_friction(h.a, h.b, MAT, law, FN, (xi, 0, 0), SPEED)
    pol = polach_creep_force(FN, h.a, h.b, MAT, mu0, a, b, 1.0, 1.0, SPEED, xi)
    np.testing.assert_allclose(-c.fx, -fs, atol=0.05 * mu0 * FN)
    np.testing.assert_allclose(-c.fx, pol, atol=0.05 * mu0 * FN)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        (dict(law="linear", mu_static=0.3, mu_kinetic=0.4, halving_speed_m_s=1.0), "mu_kinetic"),
        (dict(law="linear", mu_static=-0.1, mu_kinetic=0.0), "mu_static"),
        (dict(law="linear", mu_static=0.3, mu_kinetic=-0.1), "mu_kinetic"),
        (
            dict(law="rational", mu_static=0.3, mu_kinetic=0.1, halving_speed_m_s=0.0),
            "friction_halving_speed_m_s",
        ),
        (dict(law="cubic", mu_static=0.3, mu_kinetic=0.1), "friction_law"),
        (dict(law="linear", mu_static=0.3, mu_kinetic=0.1, root_rule="any"), "friction_root_rule"),
        (dict(law="linear", mu_static=float("nan"), mu_kinetic=0.1), "mu_static"),
    ],
)
def test_bad_law_names_the_key(kwargs, key):
    with pytest.raises(InputError, match=key):
        FrictionLaw(**kwargs)


@pytest.mark.parametrize(
    ("keys", "name"),
    [
        (
            {"friction_law": "polach", "mu_static": 0.5, "polach_a": 1.5, "friction_decay_s_m": 0.6},
            "polach_a",
        ),
        (
            {"friction_law": "polach", "mu_static": 0.5, "polach_a": -0.1, "friction_decay_s_m": 0.6},
            "polach_a",
        ),
        (
            {"friction_law": "polach", "mu_static": 0.5, "polach_a": 0.4, "friction_decay_s_m": -1},
            "friction_decay_s_m",
        ),
        ({"friction_law": "polach", "mu_static": 0.5, "polach_a": 0.4}, "friction_decay_s_m"),
        ({"friction_law": "linear", "mu_static": 0.5, "mu_kinetic": 0.2}, "friction_halving_speed_m_s"),
        ({"friction_law": "coulomb", "mu_static": 0.5, "polach_a": 0.2}, "polach_a"),
        ({"friction_law": "coulomb", "mu_static": 0.3, "mu_kinetic": 0.5}, "mu_kinetic"),
        ({"friction_law": "coulomb", "mu_kinetic": 0.2}, "mu_static"),
        ({"friction_law": "coulomb", "mu_static": 0.3, "mu_statc": 0.2}, "mu_statc"),
    ],
)
def test_bad_keys_name_the_key(keys, name):
    with pytest.raises(InputError, match=name):
        FrictionLaw.from_keys(keys)


def test_keys_build_the_laws():
    law = FrictionLaw.from_keys(
        {"friction_law": "polach", "mu_static": 0.55, "polach_a": 0.4, "friction_decay_s_m": 0.6}
    )
    assert law.law == "exponential" and law.mu_kinetic == pytest.approx(0.22)
    assert law.halving_speed_m_s == pytest.approx(math.log(2) / 0.6)
    law = FrictionLaw.from_keys({"mu_static": 0.4})
    assert law.is_constant and law.mu_kinetic == 0.4
    assert dataclasses.replace(law, root_rule="smallest").root_rule == "smallest"


def test_polach_bad_reduction_factors():
    h = hertz(GAP_A, GAP_B, FN, MAT)
    with pytest.raises(InputError, match="k_s"):
        polach_creep_force(FN, h.a, h.b, MAT, 0.55, 0.4, 0.6, 0.3, 0.4, SPEED, 0.01)
    with pytest.raises(InputError, match="k_a"):
        polach_creep_force(FN, h.a, h.b, MAT, 0.55, 0.4, 0.6, 1.3, 0.4, SPEED, 0.01)
    with pytest.raises(InputError, match="slope_reduction"):
        fastsim_friction(
            h.a, h.b, MAT, FrictionLaw.constant(0.3), FN, (0.01, 0, 0), SPEED, slope_reduction=0.0
        )


@pytest.mark.parametrize(
    ("law", "speed"),
    [
        (FrictionLaw("coulomb", 0.5, 0.3), 30.0),
        (FrictionLaw("exponential", 0.5, 0.1, 5e-4), 50.0),
        (FrictionLaw("rational", 0.5, 0.2, 1e-2), 30.0),
    ],
)
def test_every_creepage_converges_or_states_several_solutions(patch, law, speed):
    # acceptance: steady rolling at every creepage converges, or the result states that
    # element problems had several solutions (steep laws: k p V max|mu'| >> 1)
    grid, gap, _, _ = patch
    xi = np.concatenate([np.geomspace(2e-4, 5e-3, 8), [1e-2, 3e-2]])
    c = creep_curve_friction(gap, grid, MAT, law, FN, xi, speed, max_iter=800)
    assert np.all(c.converged | (c.n_multiple > 0))
    assert c.converged[-2:].all()  # full slip converges
    assert -c.fx[-1] / c.fn == pytest.approx(law.mu_kinetic, rel=2e-2)
