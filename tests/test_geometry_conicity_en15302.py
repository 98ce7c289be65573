"""The equivalent-conicity formula against EN 15302's benchmark: reference case E1 (wheel
profile UIC 519-A on rail A, 920 mm wheels, gauge 1435.16 mm), its Delta-r function and its
reference equivalent conicities (EN 15302:2008+A1, Annex E; the numbers as transcribed in
github.com/criogenox/B_ECC-Equivalent-Conicity-Calculation, data/dr_ce_E1.dat and
data/ben_E1.dat, column 2). The standard's reference results come from the integration of the
nonlinear equation of motion (its Annex B); railvti's regression / harmonic-linearisation
formula meets them within 0.003 at 1-5 mm, inside the standard's tolerance
+-min(0.05, 0.5 tan(gamma_e)) (Annex F) by a factor of 17 or more."""

from __future__ import annotations

import numpy as np
import pytest

from railvti.errors import InputError
from railvti.geometry import conicity_of_delta_r

#: Delta-r (mm) of case E1 at y = -6.8 .. 0 mm in 0.1 mm steps (odd in y: the rest mirrors it).
_DR_E1_HALF = [
    -10.954, -9.010, -7.597, -6.521, -5.692, -5.064, -4.636, -4.494, -4.328, -4.166,
    -4.008, -3.879, -3.729, -3.582, -3.440, -3.324, -3.189, -3.058, -2.931, -2.808,
    -2.709, -2.593, -2.481, -2.373, -2.286, -2.185, -2.088, -1.995, -1.906, -1.834,
    -1.752, -1.673, -1.598, -1.539, -1.471, -1.407, -1.346, -1.299, -1.236, -1.177,
    -1.111, -1.055, -0.992, -0.931, -0.879, -0.822, -0.766, -0.719, -0.667, -0.616,
    -0.574, -0.527, -0.481, -0.443, -0.402, -0.361, -0.328, -0.292, -0.257, -0.227,
    -0.197, -0.167, -0.142, -0.116, -0.092, -0.071, -0.051, -0.032, 0.0,
]  # fmt: skip
#: The reference tan(gamma_e) of case E1 at amplitudes 1, 2, 3, 4, 5 mm.
_REF_E1 = {1.0: 0.125, 2.0: 0.155, 3.0: 0.188, 4.0: 0.216, 5.0: 0.254}


def test_en15302_case_e1() -> None:
    dr = np.array(_DR_E1_HALF)
    dr = np.concatenate([dr, -dr[-2::-1]])
    y = np.round(np.arange(dr.size) * 0.1 - 6.8, 10)
    amps = np.array(list(_REF_E1))
    got = conicity_of_delta_r(y, dr, amps)
    ref = np.array(list(_REF_E1.values()))
    assert np.abs(got - ref).max() < 0.003
    assert np.all(np.abs(got - ref) < np.minimum(0.05, 0.5 * ref) / 17)


def test_a_cone_is_its_own_conicity() -> None:
    """A coned wheelset, Delta-r = 2 lambda y: tan(gamma_e) = lambda at every amplitude."""
    y = np.linspace(-8.0, 8.0, 161)
    assert conicity_of_delta_r(y, 2 * 0.05 * y, np.array([1.0, 3.0, 7.0])) == pytest.approx(0.05, rel=1e-6)


def test_bad_input() -> None:
    y = np.linspace(-2.0, 2.0, 41)
    with pytest.raises(InputError, match="cover"):
        conicity_of_delta_r(y, y, 3.0)
    with pytest.raises(InputError, match="one length"):
        conicity_of_delta_r(y, y[:-1], 1.0)
    with pytest.raises(InputError, match="amplitude"):
        conicity_of_delta_r(y, y, -1.0)
