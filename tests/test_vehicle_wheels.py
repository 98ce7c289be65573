"""All eight wheels in the results: Nadal's limit, Y/Q per wheel and the worst wheel."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.vehicle.analytic import nadal_limit


@pytest.mark.parametrize("deg, mu", [(60.0, 0.3), (70.0, 0.3), (70.0, 0.0), (75.0, 0.5)])
def test_nadal_limit_from_the_flange_force_balance(deg, mu):
    """At the limit the wheel slides down the flange: the normal force N and the friction
    mu N (up the flange) balance Q and Y. Solve that 2 x 2 balance for (Y, N) at Q = 1."""
    g = math.radians(deg)
    # unknowns (Y, N): vertical N cos g + mu N sin g = Q, lateral N sin g - mu N cos g = Y
    a = np.array([[0.0, math.cos(g) + mu * math.sin(g)], [-1.0, math.sin(g) - mu * math.cos(g)]])
    y, _ = np.linalg.solve(a, [1.0, 0.0])
    assert nadal_limit(g, mu) == pytest.approx(y, rel=1e-12)
    if mu == 0.0:
        assert nadal_limit(g, mu) == pytest.approx(math.tan(g), rel=1e-12)


def test_nadal_bad_input():
    with pytest.raises(InputError):
        nadal_limit(math.radians(95.0), 0.3)
    with pytest.raises(InputError):
        nadal_limit(math.radians(70.0), -0.1)


def test_all_wheels_and_the_worst_wheel_in_flange_hunting():
    """Flange hunting at 420 km/h: the worst wheel (Y/Q against Nadal) and the largest Q are
    recomputed here from the stored histories; the worst wheel must be in flange contact
    (its flange point carrying load) when its Y/Q peaks, and above Nadal's limit."""
    r = scenarios.hunting(420, duration=2.0, y0=0.004, progress=False)
    ws = r.wheels(window=1.0)
    k = r.t >= r.t[-1] - 1.0
    Q, Y = r.Q[k], r.Y[k]
    yq = np.where(Q > 0.01 * Q.max(), np.stack([-Y[:, 0], Y[:, 1]], 1) / np.maximum(Q, 1e-9), 0.0)
    worst = np.unravel_index(np.argmax(yq.max(axis=0)), (2, 4))
    assert ws.worst_yq == tuple(int(i) for i in worst)
    assert ws.worst_q == tuple(int(i) for i in np.unravel_index(np.argmax(Q.max(axis=0)), (2, 4)))
    assert ws.YQ_max[worst] == pytest.approx(yq.max(), rel=1e-12)
    s, w = worst
    it = int(np.argmax(yq[:, s, w]))
    assert r.wheel_output("N_flange")[k][it, s, w] > 0.1 * Q[it, s, w]
    assert ws.exceeds_nadal and ws.YQ_max[worst] > ws.nadal
    assert math.degrees(r.flange_angle) == pytest.approx(70.0, abs=0.5)
    assert ws.nadal == pytest.approx(nadal_limit(r.flange_angle, 0.3))
    for j in range(4):  # amplitudes per wheelset from the DOF histories
        assert ws.amplitude[j] == pytest.approx(0.5 * np.ptp(r.dof(f"ws{j + 1}_y")[k]))
    side = ("left", "right")[s]
    assert f"wheelset {w + 1} {side}" in ws.line() and "ABOVE" in ws.line()


def test_centred_running_no_wheel_near_nadal():
    c = scenarios.centred_running(200, duration=0.3)
    ws = c.run.wheels(window=0.2)
    assert not ws.exceeds_nadal and ws.YQ_max.max() < 0.2
    assert np.allclose(ws.Q_max, c.static_wheel_load, rtol=1e-3)
