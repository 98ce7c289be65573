"""The scipy-free replacements on the contact deck's path (issue 33: scipy's import cost a
quarter of a CONTACT deck's run) against scipy itself, and the import graph that keeps
scipy (and the areas a CONTACT deck does not use) out of a contact deck's run."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import CubicSpline
from scipy.special import ellipe as sp_ellipe
from scipy.special import ellipk as sp_ellipk

from railvti._elliptic import ellipe, ellipk
from railvti._spline import NotAKnotSpline
from railvti.errors import InputError


def test_elliptic_integrals_match_scipy():
    ms = np.concatenate([np.linspace(0.0, 0.999, 500), 1.0 - np.logspace(-3, -14, 60)])
    k = np.array([ellipk(m) for m in ms])
    e = np.array([ellipe(m) for m in ms])
    np.testing.assert_allclose(k, sp_ellipk(ms), rtol=2e-15)
    np.testing.assert_allclose(e, sp_ellipe(ms), rtol=1e-14)
    assert ellipk(0.0) == pytest.approx(np.pi / 2, rel=1e-16)
    assert ellipe(0.0) == pytest.approx(np.pi / 2, rel=1e-16)


@pytest.mark.parametrize("m", [-0.1, 1.0, float("nan")])
def test_elliptic_parameter_outside_range(m):
    with pytest.raises(InputError):
        ellipk(m)


@pytest.mark.parametrize("n", [4, 5, 9, 40, 500])
@pytest.mark.parametrize("uneven", [False, True])
def test_spline_matches_scipy_not_a_knot(n, uneven):
    rng = np.random.default_rng(n + 7 * uneven)
    x = np.cumsum(rng.uniform(0.01, 1.0, n)) if uneven else np.sort(rng.uniform(0.0, 1.0, n))
    y = rng.normal(size=n)
    ours = NotAKnotSpline(x, y)
    ref = CubicSpline(x, y, bc_type="not-a-knot", extrapolate=False)
    xv = np.concatenate([np.linspace(x[0], x[-1], 777), x])
    for nu in (0, 1, 2):
        scale = np.abs(ref(xv, nu)).max()
        np.testing.assert_allclose(ours(xv, nu), ref(xv, nu), rtol=0, atol=1e-13 * scale)
    assert np.isnan(ours(x[0] - 1e-3)) and np.isnan(ours(x[-1] + 1e-3))


def test_spline_reproduces_a_cubic():
    x = np.array([0.0, 0.3, 1.1, 1.5, 2.6])
    s = NotAKnotSpline(x, x**3 - 2 * x)
    xv = np.linspace(0.0, 2.6, 31)
    np.testing.assert_allclose(s(xv), xv**3 - 2 * xv, atol=1e-13)
    np.testing.assert_allclose(s(xv, 2), 6 * xv, atol=1e-12)


def test_spline_bad_input():
    with pytest.raises(InputError):
        NotAKnotSpline(np.array([0.0, 1.0, 1.0, 2.0]), np.zeros(4))
    with pytest.raises(InputError):
        NotAKnotSpline(np.arange(3.0), np.zeros(3))


def test_contact_deck_path_does_not_import_scipy():
    code = (
        "import sys, railvti.runner.batch, railvti.runner.deck, railvti.contact.wheel_rail_cases; "
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'scipy'))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd="/")
    assert out.stdout.strip() == "[]"


def test_contact_deck_run_imports_neither_scipy_nor_other_areas(tmp_path):
    # the whole `railvti run` of a CONTACT deck: scipy.signal (railvti.assessment, ~0.8 s) on
    # first use only; the vehicle, track and assessment areas not at all
    # (the deck's reader imports its own area only: railvti.runner.deck_registry)
    deck = Path(__file__).resolve().parent / "regression" / "decks" / "mbench_a22_small_left.inp"
    code = (
        "import sys\n"
        "from railvti.runner.cli import main\n"
        f"status = main(['run', {str(deck)!r}, '-o', {str(tmp_path / 'a22.h5')!r}, '-q'])\n"
        "top = {m.split('.')[0] for m in sys.modules} | {'.'.join(m.split('.')[:2]) for m in sys.modules}\n"
        "print(status, sorted(top & {'scipy', 'railvti.vehicle', 'railvti.track', "
        "'railvti.assessment'}))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd="/")
    assert out.stdout.strip().splitlines()[-1] == "0 []"
