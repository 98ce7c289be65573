"""Creep-force tables in one Fortran call (railvti.contact.creep_force_table, issue 18 item 4):
each case the same as solve_rolling's, the table's exact normal solve (the dense active set
on small grids, issue 33) against projected CG and Hertz, the table against Kalker's linear
theory and the symmetry of a Hertz patch, and the error paths."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import STEEL
from railvti.contact import Grid, creep_force_table, hertz, hertz_gap, solve_normal, solve_rolling
from railvti.contact.kalker import kalker_coefficients
from railvti.errors import GridTooSmallError, InputError

FN, MU, V, MARGIN, N = 10e3, 0.3, 30.0, 1.57, 11
# a/b = 0.5, 1.33 (a wheel-rail patch) of benchmarks/bench_contact_small_grid.py
SHAPES = [(2.8, 1.0), (0.5 / 0.46, 0.5 / 0.30)]
CREEP = np.array(
    [(xi, eta, phi) for xi in (0.0, 5e-4, 2e-3) for eta in (0.0, 1e-3) for phi in (0.0, 0.5, 2.0)]
)


def _problem(A: float, B: float, n: int = N, margin: float = MARGIN):
    h = hertz(A, B, FN, STEEL)
    g = Grid(n, n, 2 * margin * h.a / n, 2 * margin * h.b / n)
    return h, g, hertz_gap(g, A, B)


@pytest.mark.parametrize("shape", SHAPES, ids=["a/b=0.5", "a/b=1.33"])
def test_table_gives_the_cases_of_solve_rolling(shape):
    """Every case of the table equals solve_rolling's (same sweeps, forces to 1e-7 of mu Fn: the
    table's normal solve on this grid is the exact active set, solve_rolling's projected CG stops
    at its tolerance 1e-8; 8e-9 measured), whether the normal problem is shared (one gap) or
    solved per case (a gap per case)."""
    _, g, gap = _problem(*shape)
    shared = creep_force_table(gap, g, STEEL, MU, FN, CREEP, V)
    each = creep_force_table(np.repeat(gap[None], len(CREEP), axis=0), g, STEEL, MU, FN, CREEP, V)
    assert shared.normal_solves == 1 and each.normal_solves == len(CREEP)
    scale = MU * FN
    for k, c in enumerate(CREEP):
        r = solve_rolling(gap, g, STEEL, MU, FN, tuple(c), V)
        for t in (shared, each):
            assert t.iterations[k] == r.iterations
            assert t.n_contact[k] == r.n_contact
            assert abs(t.fx[k] - r.fx) <= 1e-7 * scale and abs(t.fy[k] - r.fy) <= 1e-7 * scale
            assert abs(t.mz[k] - r.mz) <= 1e-7 * scale * g.nx * g.dx
            assert t.power[k] == pytest.approx(r.power, rel=1e-7, abs=1e-7 * scale * V)
            assert t.approach[k] == pytest.approx(r.approach, rel=1e-7)
    # the shared and the per-case normal solves are the same computation
    np.testing.assert_array_equal(shared.fx, each.fx)
    np.testing.assert_array_equal(shared.fy, each.fy)


def test_mixed_table_equals_separate_tables():
    """Cases of two geometries and two loads in one table give the forces of separate tables."""
    (_, g, gap1), (_, _, gap2) = _problem(1.0, 1.0), _problem(1.0, 1.0)
    gap2 = gap2 * 1.2  # another curvature on the same grid
    creep = CREEP[::3]
    gaps = np.array([gap1] * len(creep) + [gap2] * len(creep))
    fns = np.array([FN] * len(creep) + [0.8 * FN] * len(creep))
    mixed = creep_force_table(gaps, g, STEEL, MU, fns, np.vstack([creep, creep]), V)
    t1 = creep_force_table(gap1, g, STEEL, MU, FN, creep, V)
    t2 = creep_force_table(gap2, g, STEEL, MU, 0.8 * FN, creep, V)
    np.testing.assert_allclose(mixed.fx, np.concatenate([t1.fx, t2.fx]), rtol=0, atol=1e-10 * MU * FN)
    np.testing.assert_allclose(mixed.fy, np.concatenate([t1.fy, t2.fy]), rtol=0, atol=1e-10 * MU * FN)
    assert t1.normal_solves == t2.normal_solves == 1


def test_kept_normal_factor_gives_the_fresh_solves():
    """Cases with different gaps on one contact set (a table over the curvature: the active set
    keeps the previous case's Cholesky factor when its trial set is the same) give the bits of
    each case solved in its own table (a fresh factor), with a change of contact set inside the
    table (the kept factor then replaced)."""
    _, g, gap = _problem(1.0, 1.0)
    scales = [1.0, 1.001, 1.002, 1.004, 1.3, 1.5]  # 1.3: a smaller contact area (37 elements, not 45)
    gaps = np.array([gap * s for s in scales])
    creep = CREEP[[4, 10, 13, 16, 17, 7]]
    t = creep_force_table(gaps, g, STEEL, MU, FN, creep, V)
    assert t.normal_solves == len(scales)
    assert t.n_contact[0] == t.n_contact[3] != t.n_contact[4] == t.n_contact[5]
    assert (t.normal_iterations[1:4] == 1).all() and t.normal_iterations[5] == 1  # the kept set
    for k in range(len(scales)):
        one = creep_force_table(gaps[k], g, STEEL, MU, FN, creep[k : k + 1], V)
        for name in ("fx", "fy", "mz", "approach", "n_contact", "iterations"):
            assert getattr(one, name)[0] == getattr(t, name)[k], (k, name)


@pytest.mark.parametrize(
    "case",
    [(1.0, 1.0, 1.57, 1.0), (2.8, 1.0, 1.57, 0.3), (0.5 / 0.46, 0.5 / 0.30, 3.0, 1.0), (1.0, 1.0, 2.0, 2.5)],
    ids=["circle", "a/b=0.5 light", "wide grid", "heavy"],
)
def test_exact_normal_solve_against_cg_and_hertz(case):
    """The table's normal solve (the dense active set on grids of at most 1024 elements) against
    projected CG (solve_normal, tolerance 1e-10): the same contact set and approach to 1e-8, and
    Hertz's approach within the 11 x 11 grid's discretisation error (3 %; 0.6 % measured), also
    where the start set (h below a quarter of its range) is far from the contact area (a grid
    of 3 semi-axes each side: 4 trial sets) and at 0.3 and 2.5 times the load."""
    A, B, margin, load = case
    h = hertz(A, B, load * FN, STEEL)
    g = Grid(N, N, 2 * margin * h.a / N, 2 * margin * h.b / N)
    gap = hertz_gap(g, A, B)
    t = creep_force_table(gap, g, STEEL, MU, load * FN, CREEP[:1], V)
    cg = solve_normal(gap, g, STEEL, fn=load * FN, tol=1e-10)
    assert t.n_contact[0] == cg.n_contact
    assert t.approach[0] == pytest.approx(cg.approach, rel=1e-8)
    assert t.approach[0] == pytest.approx(h.approach, rel=0.03)


@pytest.mark.parametrize("per_slice", [1, 4, 7])
def test_table_in_slices_equals_one_call(monkeypatch, per_slice):
    """A table run in slices (Ctrl-C acts between them; each continues the previous slice's
    normal solution) gives exactly the forces, approaches and iterations of one call, with
    slice boundaries inside a run of one gap and load and at a change of load."""
    import railvti.contact.creep_table as ct

    _, g, gaps = _problem(1.0, 1.0)
    fns = np.array([FN] * 9 + [0.8 * FN] * 9)
    creep = np.vstack([CREEP[::2], CREEP[1::2]])
    monkeypatch.setattr(ct, "DIRECT_CALL_WORK", 10**12)  # one call
    whole = creep_force_table(gaps, g, STEEL, MU, fns, creep, V)
    monkeypatch.setattr(ct, "DIRECT_CALL_WORK", per_slice * g.nx * g.ny * 2000)
    sliced = creep_force_table(gaps, g, STEEL, MU, fns, creep, V)
    for name in ("fx", "fy", "mz", "power", "approach", "n_contact", "iterations", "normal_iterations"):
        np.testing.assert_array_equal(getattr(sliced, name), getattr(whole, name))
    assert sliced.normal_solves == whole.normal_solves == 2
    assert abs(whole.fx).max() > 0.1 * MU * FN


def test_table_is_odd_in_the_creepages():
    """A Hertz patch is symmetric: reversing all creepages reverses Fx, Fy and Mz (to the
    solver's tolerance; the grid is symmetric about the patch's centre)."""
    _, g, gap = _problem(0.5 / 0.46, 0.5 / 0.30)
    creep = CREEP[1:]
    plus = creep_force_table(gap, g, STEEL, MU, FN, creep, V)
    minus = creep_force_table(gap, g, STEEL, MU, FN, -creep, V)
    np.testing.assert_allclose(minus.fx, -plus.fx, rtol=0, atol=1e-5 * MU * FN)
    np.testing.assert_allclose(minus.fy, -plus.fy, rtol=0, atol=1e-5 * MU * FN)


def test_table_follows_kalker_at_small_creepage():
    """At small creepage the table's Fx, Fy lie within 6 % of Kalker's linear theory (the
    11 x 11 grid's discretisation error; as tests/test_contact_small_grid.py)."""
    h, g, gap = _problem(0.5 / 0.46, 0.5 / 0.30)
    s = 2e-5
    t = creep_force_table(gap, g, STEEL, MU, FN, np.array([[s, 0.0, 0.0], [0.0, s, 0.0]]), V)
    c11, c22, _ = kalker_coefficients(h.a / h.b, STEEL.poisson)
    gc2 = STEEL.shear_modulus * h.a * h.b
    assert t.fx[0] == pytest.approx(-gc2 * c11 * s, rel=0.06)
    assert t.fy[1] == pytest.approx(-gc2 * c22 * s, rel=0.06)


def test_bad_input_is_named():
    _, g, gap = _problem(1.0, 1.0)
    with pytest.raises(InputError, match="creepages"):
        creep_force_table(gap, g, STEEL, MU, FN, np.zeros((4, 2)), V)
    with pytest.raises(InputError, match="gap"):
        creep_force_table(gap[:, :5], g, STEEL, MU, FN, CREEP, V)
    with pytest.raises(InputError, match="fn"):
        creep_force_table(gap, g, STEEL, MU, np.array([FN, FN]), CREEP, V)
    with pytest.raises(InputError, match="fn"):
        creep_force_table(gap, g, STEEL, MU, -FN, CREEP, V)
    with pytest.raises(InputError, match="creepages"):
        creep_force_table(gap, g, STEEL, MU, FN, np.array([[np.nan, 0.0, 0.0]]), V)


def test_patch_cut_by_the_grid_is_refused():
    """A grid of 1.1 semi-axes each side leaves the contact area on its last rows."""
    _, g, gap = _problem(1.0, 1.0, margin=1.1)
    with pytest.raises(GridTooSmallError, match="case 0"):
        creep_force_table(gap, g, STEEL, MU, FN, CREEP[:2], V)
