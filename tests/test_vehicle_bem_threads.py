"""contact='bem' with the wheels' patches solved in parallel (OpenMP, simulate(threads=)): the
threaded run must give the serial run's states and forces (vehicle_bem.f90, "Threads")."""

from __future__ import annotations

import os

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.vehicle import BemOptions, bem_state, lateral_disturbance, simulate, static_equilibrium
from railvti.vehicle.model import WHEEL_OUTPUTS
from railvti.vehicle.simulate import bem_threads

V = 300 / 3.6
#: A coarse grid keeps the runs short (two 0.05 s runs, 8 wheels, about 5 s each).
OPTIONS = BemOptions(dx=1.5e-3)


@pytest.fixture(scope="module")
def coach_system():
    return scenarios.coach_system()


@pytest.fixture(scope="module")
def openmp(coach_system):
    """Skip where the build has no OpenMP (the state then takes one thread only)."""
    with bem_state(coach_system, OPTIONS) as st:
        if bem_threads(st, 2) < 2:
            pytest.skip("railvti was built without OpenMP")


def _hunting(sy, q0, threads):
    # one output interval per Fortran call: the chunking, otherwise sized by the wall clock,
    # is then the same in both runs (each call starts a fresh Newton tangent)
    return simulate(
        sy,
        V,
        0.05,
        contact="bem",
        q0=q0,
        output_dt=0.002,
        bem_options=OPTIONS,
        threads=threads,
        progress=True,
        chunk=0.002,
    )


def test_threads_give_the_serial_run(coach_system, openmp):
    """Hunting at 300 km/h from 6 mm (tread and flange contact on the leading wheelsets, so
    up to three patches per wheelset): two threads give the one-thread run's displacements,
    velocities and wheel forces to 1e-10 relative (the patches are independent and summed
    in a fixed order, so the runs agree to the bit in practice)."""
    sy = coach_system
    qs, _ = static_equilibrium(sy, V)
    q0 = lateral_disturbance(sy, qs, 0.006, wheelsets=(0, 1))
    r1 = _hunting(sy, q0, 1)
    r2 = _hunting(sy, q0, 2)
    assert r1.stats["bem_threads"] == 1 and r2.stats["bem_threads"] == 2
    # the runs solve patches, several per evaluation, some in flange contact
    assert r1.stats["bem_normal_solves"] > 6 * r1.stats["steps"]
    assert (r1.wheel[:, WHEEL_OUTPUTS.index("N_flange")] > 1e3).any()
    for name in ("q", "v", "wheel"):
        a, b = getattr(r1, name), getattr(r2, name)
        assert a.shape == b.shape
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-10 * np.abs(a).max(), err_msg=name)
    for key in (
        "newton_iterations",
        "bem_normal_solves",
        "bem_rolling_solves",
        "bem_cg_iterations",
        "bem_rolling_sweeps",
        "bem_open_points",
    ):
        assert r2.stats[key] == r1.stats[key], key


def test_thread_count_settings(coach_system, openmp, monkeypatch):
    """threads=None takes RAILVTI_THREADS, else all cores; a bad value is an InputError."""
    with bem_state(coach_system, OPTIONS) as st:
        assert bem_threads(st, 3) == 3
        monkeypatch.setenv("RAILVTI_THREADS", "2")
        assert bem_threads(st) == 2
        monkeypatch.delenv("RAILVTI_THREADS")
        if "OMP_NUM_THREADS" not in os.environ:
            assert bem_threads(st) == min(len(os.sched_getaffinity(0)), 64)
        for bad in (0, -1, 1.5):
            with pytest.raises(InputError):
                bem_threads(st, bad)
        monkeypatch.setenv("RAILVTI_THREADS", "many")
        with pytest.raises(InputError):
            bem_threads(st)
