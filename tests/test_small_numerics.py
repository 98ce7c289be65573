"""railvti's own small replacements of scipy functions that cost much to import at start-up:
a bracketed root (Brent's method) against closed-form roots, and the prominent-peak finder
of the contact tables against scipy.signal.find_peaks."""

import math

import numpy as np
import pytest
from scipy.signal import find_peaks

from railvti import ConvergenceError, InputError
from railvti._roots import brent_root
from railvti.geometry.table import prominent_peaks


@pytest.mark.parametrize(
    "f, a, b, root",
    [
        (lambda x: x * x - 2.0, 0.0, 2.0, math.sqrt(2.0)),
        (lambda x: math.cos(x) - x, 0.0, 1.0, 0.7390851332151607),  # the Dottie number
        (lambda x: math.exp(x) - 10.0, -5.0, 14.0, math.log(10.0)),
        (lambda x: x**3 - x - 2.0, 1.0, 2.0, 1.5213797068045676),  # the plastic-like cubic
        (lambda x: math.tanh(50.0 * (x - 0.3)), -1.0, 1.0, 0.3),  # a steep step
    ],
)
def test_brent_root_finds_closed_form_roots(f, a, b, root):
    x = brent_root(f, a, b, xtol=1e-14)
    assert abs(x - root) <= 1e-13 + 4 * np.finfo(float).eps * abs(root)


def test_brent_root_args_and_errors():
    assert brent_root(lambda x, c: x - c, -1.0, 1.0, args=(0.25,)) == pytest.approx(0.25, abs=1e-12)
    assert brent_root(lambda x: x, 0.0, 1.0) == 0.0
    with pytest.raises(InputError, match="same sign"):
        brent_root(lambda x: x * x + 1.0, -1.0, 1.0)
    with pytest.raises(ConvergenceError):
        brent_root(lambda x: math.exp(x) - 10.0, -5.0, 14.0, xtol=1e-15, maxiter=2)


def test_prominent_peaks_as_scipy_find_peaks():
    """Random walks rounded to 0.1 (plateaus and equal neighbours) at four prominences."""
    rng = np.random.default_rng(7)
    for _ in range(2000):
        x = np.round(rng.normal(size=int(rng.integers(3, 80))).cumsum(), 1)
        p = float(rng.choice([0.0, 0.1, 0.5, 2.0]))
        assert np.array_equal(prominent_peaks(x, p), find_peaks(x, prominence=p)[0]), (x, p)


def test_count_regions_as_scipy_ndimage_label():
    """The contact areas of a patch (4-neighbourhood) against scipy.ndimage.label."""
    from scipy import ndimage

    from railvti.contact.wheelset import count_regions

    rng = np.random.default_rng(11)
    for _ in range(1000):
        m = rng.random((int(rng.integers(1, 30)), int(rng.integers(1, 30)))) < rng.random()
        assert count_regions(m) == ndimage.label(m)[1]
