"""The time loop keeps its condensed iteration matrix from step to step for the variants with
modal blocks (FR: the wheelsets' modes; FF: the wheelsets' and the ring's, whose contact rows
move with the time) as it does for RR with the strip contact (vehicle_newmark::keeps_matrix).
Checked against the run itself under other conditions that must not matter: the chunking of
the run into Fortran calls (bit for bit: a kept matrix crosses a call only when the call
continues from exactly its state), and a Newton tolerance 100 times tighter (the kept matrix
changes how Newton converges, not where to: the answers agree within the looser tolerance's
effect)."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle.equilibrium import lateral_disturbance, static_equilibrium
from railvti.vehicle.simulate import simulate
from coarse_ring import RING

V = 380.0 / 3.6


@pytest.fixture(scope="module", params=["FR", "FF"])
def system(request):
    if request.param == "FR":
        sy, _ = scenarios.fr_system(speed=V, k_max=1, f_max=300.0, geometry="strip")
    else:
        sy, _ = scenarios.ff_system(speed=V, k_max=1, f_max=300.0, geometry="strip", **RING)
    q0 = lateral_disturbance(sy, static_equilibrium(sy, V, "hertz-fastsim")[0], 0.006)
    return request.param, sy, q0


def _run(sy, q0, **kw):
    return simulate(sy, V, 0.06, q0=q0, h=5e-4, output_dt=0.002, contact="hertz-fastsim", **kw)


@pytest.mark.parametrize("modal_step", ["trapezoidal", "exact", "exact-moving", "exact-flange"])
def test_the_matrix_is_kept_and_the_chunking_does_not_matter(system, modal_step):
    """Also with the exact modal step (whose block matrices the model keeps across calls),
    the ring's moving rows (FF; their g_n recovered from the carried state) and the sub-steps
    in flange contact (decided from the carried state's wheel outputs: they are exercised).
    The flange impact renews the kept matrix after slow steps (vehicle_newmark refresh_due,
    issue 33: FF 14 and 16 tangents, FR 6 and 2): its age crosses the calls with it."""
    variant, sy, q0 = system
    runs = [_run(sy, q0, progress=True, chunk=c, modal_step=modal_step) for c in (0.004, 0.02, 0.06)]
    st = runs[-1].stats
    if modal_step == "exact-flange":  # each change between h and its sub-steps renews the matrix
        assert st["substepped_steps"] > 0 and st["tangents"] >= 2
    else:
        assert st["tangents"] < 0.2 * st["steps"], f"{variant}: {st['tangents']} tangents / {st['steps']}"
        assert st["tangents"] >= 2, f"{variant}: the renewal is not exercised"
    for r in runs[:-1]:
        np.testing.assert_array_equal(r.q, runs[-1].q)


def test_a_tighter_newton_tolerance_moves_the_run_by_less_than_the_tolerance_allows(system):
    """From 6 mm into a flange impact: the default tolerance (1e-9 m on the correction) and
    1e-11 m give the same history to 1e-7 m (the error of one correction left, times the
    steps' propagation over 120 steps)."""
    variant, sy, q0 = system
    a = _run(sy, q0, progress=False)
    b = _run(sy, q0, progress=False, tol=1e-11)
    rigid = slice(0, sy.n)
    assert np.abs(a.q[:, rigid] - b.q[:, rigid]).max() < 1e-7, variant
    assert np.abs(a.y_ws1).max() > 1e-3  # the motion is large: the check is not vacuous
