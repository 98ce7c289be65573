"""The rims' rows follow the contact point (Kaiser eq. 3, issue 30 item 3) in models FR and FF:
the option reaches FF and the scenarios, and the result does not depend on how the time loop
is chunked (the followed point is carried from chunk to chunk, not restarted at the taping
line). The rows themselves are checked against direct FE solves in
tests/test_wheelset_flexible.py."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.errors import InputError
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.params import Coach
from railvti.vehicle.equilibrium import lateral_disturbance, static_equilibrium
from railvti.vehicle.model import WHEEL_OUTPUTS
from railvti.vehicle.simulate import simulate
from railvti.wheelset.residual import residual_table

SMALL = {"k_max": 1, "f_max": 300.0}
V = 420.0 / 3.6
RUN = dict(h=1e-3, output_dt=1e-3, progress=False)


@pytest.fixture(scope="module")
def runs():
    """0.2 s from 6 mm at 420 km/h, into the first flange impact: followed (default chunks and
    one step per chunk) and not followed (the taping line's rows), the 10 mm residual grid."""
    ws = systems.fr_wheelset()
    body = ws.flexible_body(V, **SMALL)
    table = scenarios.wheel_table()
    grid = residual_table(ws, body, ds=0.01)
    # the scenarios' cache of the grid at this speed and selection: ff_system below reuses it
    systems._PROFILES[("residual_grid", float(V), SMALL["k_max"], SMALL["f_max"], 1.0)] = grid
    sy, _ = build_fr(Coach(), table, V, wheelset=ws, body=body, follow_contact=True, residual_grid=grid)
    s0, _ = build_fr(Coach(), table, V, wheelset=ws, body=body)
    sy, s0 = (systems.with_geometry(s, "strip") for s in (sy, s0))
    qs, _ = static_equilibrium(sy, V, "hertz-kalker")
    q0 = lateral_disturbance(sy, qs, 0.006, wheelsets=(0, 1))
    return (
        sy,
        simulate(sy, V, 0.2, q0=q0, **RUN),
        simulate(sy, V, 0.2, q0=q0, chunk=1e-3, **RUN),
        simulate(s0, V, 0.2, q0=q0, **RUN),
    )


def test_chunking_does_not_change_a_followed_run(runs):
    sy, a, b, _ = runs
    assert a.wheel[:, WHEEL_OUTPUTS.index("N_flange")].max() > 0.1 * sy.wheel_load
    assert np.max(np.abs(a.q - b.q)) <= 1e-9 * np.max(np.abs(a.q))
    assert np.max(np.abs(a.Q - b.Q)) <= 1e-6 * sy.wheel_load


def test_following_moves_the_flange_forces(runs):
    """Without following the flange impact differs (the flange points are about 20 % stiffer
    vertically than the taping line), the hunting motion barely."""
    sy, a, _, c = runs
    assert np.max(np.abs(a.y_ws1 - c.y_ws1)) < 0.05 * np.max(np.abs(c.y_ws1))
    assert np.max(np.abs(a.Q - c.Q)) > 1e-3 * sy.wheel_load


def test_ff_takes_the_option_and_rigid_models_refuse_it(runs):
    with pytest.raises(InputError, match="follow_contact"):
        scenarios.coach_system("RR", follow_contact=True)
    with pytest.raises(InputError, match="follow_contact"):
        scenarios.hunting(300.0, "RF", follow_contact=True, duration=0.01)
    sy, _ = scenarios.ff_system(speed=V, follow_contact=True, **SMALL)
    assert sy.modal.couplings.rim_follow is not None
