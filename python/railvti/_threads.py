"""Thread pools around the Fortran time loop.

The time loop factorises and solves small dense systems (the rigid DOFs plus the condensed
modal points: tens to a few hundred unknowns) thousands of times per simulated second. A
threaded BLAS gains nothing on them and its idle threads spin (sched_yield) between calls,
taking a core from the loop: on the shared 2-core machine variant FR's 2 s of hunting took
31-38 s of wall time with OpenBLAS's two threads and 11-15 s with one (benchmarks/
bench_vehicle_fr.py).
"""

from __future__ import annotations

from contextlib import AbstractContextManager, nullcontext


def serial_blas() -> AbstractContextManager:
    """A context in which the BLAS libraries loaded in the process (numpy's and the Fortran
    core's) run on one thread; they get their thread counts back on exit. Without
    threadpoolctl: nothing changes."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - a declared dependency
        return nullcontext()
    return threadpool_limits(limits=1, user_api="blas")
