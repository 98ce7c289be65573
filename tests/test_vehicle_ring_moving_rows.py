"""The ring's moving rows (simulate(modal_step='exact-moving'), vehicle_ring_step): the ring
track's modes integrated exactly over their rows at m + 1 nodes a step (docs/vehicle_integrator.md,
"The ring's moving rows"). Checked against the plain exact step, which it is for m = 1 (rows at
the step's ends only), against a converged reference (the trapezoidal step at 1/8 ms), and
against the conditions that must not matter (chunking, threads, OpenBLAS kernels)."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.vehicle.equilibrium import static_equilibrium
from railvti.vehicle.simulate import simulate

from coarse_ring import RING

_SIM = importlib.import_module("railvti.vehicle.simulate")

V = 300.0 / 3.6


@pytest.fixture(scope="module")
def rf():
    sy = scenarios.rf_system(speed=V, geometry="strip", **RING)
    return sy, static_equilibrium(sy, V, "hertz-fastsim")[0]


def _run(sy, q0, h, modal_step, nodes=4, duration=0.3, **kw):
    old = _SIM.RING_NODES
    _SIM.RING_NODES = nodes
    try:
        return simulate(
            sy, V, duration, q0=q0, h=h, output_dt=1e-3, contact="hertz-fastsim", modal_step=modal_step, **kw
        )
    finally:
        _SIM.RING_NODES = old


def test_one_node_interval_is_the_plain_exact_step(rf):
    """m = 1: the rows at the step's ends and the force linear in time, the plain exact step
    (its f_n from the carried acceleration; here from g_n recovered by least squares):
    the same history to the Newton tolerance's propagation."""
    sy, q0 = rf
    a = _run(sy, q0, 1e-3, "exact", duration=0.1)
    b = _run(sy, q0, 1e-3, "exact-moving", nodes=1, duration=0.1)
    assert np.abs(a.q[:, : sy.n] - b.q[:, : sy.n]).max() < 1e-8  # m, rad: 10 Newton tolerances
    # the modal coordinates: the plain step carries the force its end position implies, this
    # one the force evaluated there; they differ by Newton's residual (5.5e-6 of the largest)
    assert np.abs(a.q[:, sy.n :] - b.q[:, sy.n :]).max() < 2e-5 * np.abs(a.q[:, sy.n :]).max()
    assert np.abs(a.Q - b.Q).max() < 1e-4 * a.Q.max()  # 0.9 N of 55 kN


def test_moving_rows_converge_towards_the_reference(rf):
    """Centred running at 300 km/h (the sleeper passing moves the wheel load): the largest
    wheel load over the last 0.1 s at 1 ms against the trapezoidal step at 1/8 ms. The plain
    exact step is off by ~140 N; the moving rows bring it to ~110 N at m = 4 and 8 (what is
    left is the 1 ms step's, not the rows': at 0.5 ms, m = 4, ~20 N)."""
    sy, q0 = rf

    def qmax(r):
        return r.Q[r.t >= r.t[-1] - 0.1].max()

    ref = qmax(_run(sy, q0, 1.25e-4, "trapezoidal"))
    exact = abs(qmax(_run(sy, q0, 1e-3, "exact")) - ref)
    moving = [abs(qmax(_run(sy, q0, 1e-3, "exact-moving", nodes=m)) - ref) for m in (2, 8)]
    half = abs(qmax(_run(sy, q0, 5e-4, "exact-moving", nodes=4)) - ref)
    assert exact > 100.0, exact
    assert moving[1] < moving[0] < exact and moving[1] < 0.85 * exact, (moving, exact)
    assert half < 0.3 * moving[1], (half, moving)


def test_the_chunking_does_not_matter(rf):
    sy, q0 = rf
    a = _run(sy, q0, 1e-3, "exact-moving", duration=0.04)
    b = _run(sy, q0, 1e-3, "exact-moving", duration=0.04, chunk=0.004)
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.v, b.v)


def test_exact_moving_needs_the_trapezoidal_rule(rf):
    sy, q0 = rf
    with pytest.raises(InputError, match="exact-moving"):
        simulate(sy, V, 0.01, q0=q0, h=1e-3, contact="hertz-fastsim", modal_step="exact-moving", alpha=-0.05)


_SCRIPT = """
import sys, numpy as np
from railvti import scenarios
from railvti.vehicle.equilibrium import static_equilibrium
from railvti.vehicle.simulate import simulate
V = 300.0 / 3.6
sy = scenarios.rf_system(speed=V, geometry="strip", n_sleepers=40, f_limit=300.0,
    track_params=dict(kappa_max=30.0, mesh_max_area=4e-4, arc_step=12e-3, f_max=500.0))
q0 = static_equilibrium(sy, V, "hertz-fastsim")[0]
r = simulate(sy, V, 0.03, q0=q0, h=1e-3, output_dt=1e-3, contact="hertz-fastsim", modal_step="exact-moving")
np.savez(sys.argv[1], q=r.q, Q=r.Q, n=sy.n)
"""


def test_independent_of_threads_and_openblas_coretype(tmp_path):
    """One thread and the default kernels against two threads and Haswell's: the rigid DOFs
    to 1e-10 m, the wheel loads to 2 N (the ring's degenerate mode pairs come out of its
    eigensolver rotated by the kernels; the rail's motion, and so the contact, does not see
    it)."""
    out = []
    for env_extra in ({"OMP_NUM_THREADS": "1"}, {"OMP_NUM_THREADS": "2", "OPENBLAS_CORETYPE": "Haswell"}):
        path = tmp_path / f"run{len(out)}.npz"
        env = dict(os.environ, **env_extra)
        subprocess.run([sys.executable, "-c", _SCRIPT, str(path)], env=env, timeout=600, check=True)
        out.append(np.load(path))
    a, b = out
    n = int(a["n"])
    assert np.abs(a["q"][:, :n] - b["q"][:, :n]).max() < 1e-10
    # the wheel load to Newton's tolerance (1e-9 m on the correction) times the contact's
    # stiffness (~1e9 N/m): an iteration more or fewer somewhere moves it by ~1 N (0.59 N here)
    assert np.abs(a["Q"] - b["Q"]).max() < 2.0
