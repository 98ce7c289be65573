"""BEM patches solved on windows around the interpenetration (BemOptions.window) against the
same solves on the whole grid: the contact area lies inside the rigid interpenetration, so
the window must give the full grid's forces and fields to the solvers' tolerances."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import BemOptions, bem_state, lateral_disturbance, static_equilibrium
from railvti.vehicle.equilibrium import _force_and_tangent
from railvti.vehicle.model import WHEEL_OUTPUTS

W = WHEEL_OUTPUTS
V = 300 / 3.6


@pytest.fixture(scope="module")
def coach_system():
    return scenarios.coach_system()


def _evaluate(sy, q, v, window):
    """F, wheel outputs and the leading wheelset's patches with windows on or off."""
    with bem_state(sy, BemOptions(window=window, tol_normal=1e-8, tol_rolling=1e-6)) as st:
        f, wout, _, _ = _force_and_tangent(sy, q, v, V, "bem", 8, st)
        patches = [st.patch(0, w, k, V) for w in (0, 1) for k in (0, 1)]
    return f, wout, patches


@pytest.mark.parametrize("y0", [0.003, 0.006])
def test_windowed_bem_equals_the_full_grid(coach_system, y0):
    """Tread contact (3 mm) and tread + flange contact (6 mm) with creepages from a
    lateral velocity and a yaw rate: generalised forces and wheel outputs within 1e-6 of the
    largest, pressures within 1e-6 of the peak (solver tolerances 1e-8 and 1e-6)."""
    sy = coach_system
    qs, _ = static_equilibrium(sy, V)
    q = lateral_disturbance(sy, qs, y0, wheelsets=(0,))
    v = np.zeros(sy.n)
    v[sy.dof_names.index("ws1_y")] = 2e-4 * V
    v[sy.dof_names.index("ws1_yaw")] = 3e-4 * V / 0.75
    fw, ww, pw = _evaluate(sy, q, v, True)
    ff, wf, pf = _evaluate(sy, q, v, False)
    assert np.abs(ff).max() > 1e4
    np.testing.assert_allclose(fw, ff, rtol=0, atol=1e-6 * np.abs(ff).max())
    for name in ("N_tread", "N_flange", "Y", "Fx"):
        i = W.index(name)
        np.testing.assert_allclose(ww[i], wf[i], rtol=0, atol=1e-6 * np.abs(wf[i]).max() + 1e-9)
    if y0 > 0.005:
        assert (wf[W.index("N_flange")] > 1e3).any()  # the flange point is in contact
    for a, b in zip(pw, pf):
        assert (a is None) == (b is None)
        if a is None:
            continue
        peak = b.pressure.max()
        np.testing.assert_allclose(a.pressure, b.pressure, rtol=0, atol=1e-6 * peak)
        np.testing.assert_allclose(a.tx, b.tx, rtol=0, atol=1e-5 * peak)
        np.testing.assert_allclose(a.ty, b.ty, rtol=0, atol=1e-5 * peak)
