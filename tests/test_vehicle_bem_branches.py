"""The BEM's contact forces stay continuous where a slot's contact point jumps to another
local minimum of the gap (vehicle_contact.table_at: the two branches share the slot's load
by the softmin of the pose table, each solved as its own BEM point).

A hard switch between the branches is a jump of the creepages and of the contact frame at
the point: 1.7 kN of longitudinal force on the tread jump of S1002 / UIC60 1:40, on which
the time loop's Newton iterations cannot converge at any step size (RR hunting at 420 km/h
stopped at the first such crossing). A continuous force changes by O(delta) over a shift
delta: ten times smaller for a ten times smaller shift, where a jump stays the same."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle.equilibrium import _force_and_tangent, bem_state, lateral_disturbance, static_equilibrium
from railvti.vehicle.table import IBRANCH

SPEED = 300.0 / 3.6


@pytest.fixture(scope="module")
def rr():
    sy = scenarios.coach_system("RR", speed_kmh=300.0, geometry=scenarios.resolve_geometry("bem", None))
    q0, _ = static_equilibrium(sy, SPEED, "hertz-kalker")
    return sy, q0


def _tread_jump(sy) -> tuple[float, float]:
    """The table interval (m) in which the tread slot's point jumps to another branch."""
    t = sy.table
    lab = t.data[IBRANCH, 0]
    i = [k for k in np.nonzero(np.diff(lab))[0] if lab[k] >= 0 and lab[k + 1] >= 0]
    assert i, "the S1002 / UIC60 table has a tread jump"
    return float(t.y[i[0]]), float(t.y[i[0] + 1])


def _wheelset_forces(sy, q0, st, ys) -> np.ndarray:
    """Generalised forces on wheelset 1 with it shifted to each lateral position ys (m)."""
    rows = sy.iws[:, 0] - 1
    v = np.zeros(sy.n)
    out = []
    for y in ys:
        q = lateral_disturbance(sy, q0, y, wheelsets=(0,))
        out.append(_force_and_tangent(sy, q, v, SPEED, "bem", 8, st)[0][rows])
    return np.array(out)


def test_forces_are_continuous_across_the_tread_jump(rr):
    sy, q0 = rr
    y1, y2 = _tread_jump(sy)
    with bem_state(sy) as st:
        ys = np.linspace(y1 - 2e-5, y2 + 2e-5, 46)
        f = _wheelset_forces(sy, q0, st, ys)
        # the steepest change of the longitudinal force (the branches' creepages differ)
        k = int(np.argmax(np.abs(np.diff(f[:, 4]))))
        a, b = ys[k], ys[k + 1]
        fa, fb = f[k, 4], f[k + 1, 4]
        # narrowed by bisection to the half with the larger change, down to 10 nm (a jump
        # is then inside the final interval; a continuous force at its steepest)
        while b - a > 1e-8:
            m = 0.5 * (a + b)
            fm = _wheelset_forces(sy, q0, st, [m])[0, 4]
            if abs(fm - fa) >= abs(fb - fm):
                b, fb = m, fm
            else:
                a, fa = m, fm
        yc = 0.5 * (a + b)
        jumps = []
        for delta in (1e-6, 1e-7):
            fa, fb = _wheelset_forces(sy, q0, st, [yc - delta / 2, yc + delta / 2])
            jumps.append(np.abs(fb - fa))
    # O(delta): a tenth of the shift, about a tenth of the change, in every component
    # larger than the solvers' noise (~1 N)
    big = jumps[0] > 20.0
    assert big.any()
    ratio = jumps[1][big] / jumps[0][big]
    assert np.all(ratio < 0.25), ratio
