"""Ctrl-C inside the CG normal solver (issue 16 item 2): the solver runs in resumable slices
(``normal_cg_slice_c``) whose numbers are those of one call, and SIGINT stops a long solve
within about a slice (0.1 s) instead of at the end of the Fortran call."""

from __future__ import annotations

import numpy as np
import pytest

from interrupt_helper import sigint_after_ready
from railvti import STEEL
from railvti._native import core
from railvti.contact import Grid
from railvti.contact import normal as normal_mod
from railvti.contact.hertz import hertz_gap


@pytest.mark.parametrize("method", ["cg", "pk"])
@pytest.mark.parametrize("control", ["fn", "approach"])
def test_cg_in_slices_equals_one_call(monkeypatch, method, control):
    """Slices of one iteration give the pressures, force, approach, iteration and product
    counts of one normal_solve_c call, to the bit (nested start included: 160 x 160)."""
    g = Grid(160, 160, 0.15e-3, 0.15e-3)
    gap = hertz_gap(g, 1.0, 1.6)
    kw = {"fn": 1e4} if control == "fn" else {"approach": 2e-5}
    monkeypatch.setattr(normal_mod, "CG_SLICE_SECONDS", 1e-9)  # one iteration per slice
    sliced = normal_mod.solve_normal(gap, g, STEEL, method=method, **kw)

    def one_call(handle, h, ctrl, meth, tol, max_iter, fn_in, app_in, p, sub, u=None):
        out = core.normal_solve_c(handle, h, ctrl, meth, tol, max_iter, 1.0, fn_in, app_in, p)
        if u is not None:  # the converged solve ends on an exact product: u = A p
            u[...] = core.convolve_repeat_c(handle, 1, p)[0]
        return out

    monkeypatch.setattr(normal_mod, "_cg_in_slices", one_call)
    whole = normal_mod.solve_normal(gap, g, STEEL, method=method, **kw)
    assert np.array_equal(sliced.pressure, whole.pressure)
    assert (sliced.fn, sliced.approach, sliced.residual) == (whole.fn, whole.approach, whole.residual)
    assert (sliced.iterations, sliced.fft_products, sliced.coarse_fft_products) == (
        whole.iterations,
        whole.fft_products,
        whole.coarse_fft_products,
    )
    assert sliced.iterations > 5


LONG_SOLVE = """
import sys
import signal
signal.signal(signal.SIGINT, signal.default_int_handler)   # also when started with SIGINT ignored
from railvti import STEEL
from railvti.contact import Grid
from railvti.contact.hertz import hertz_gap
from railvti.contact.normal import solve_normal
g = Grid(1000, 1000, 24e-6, 24e-6)
gap = hertz_gap(g, 1.0, 1.6)
print("ready", flush=True)
solve_normal(gap, g, STEEL, method="pk", fn=1e5, tol=1e-12, max_iter=100000, nested=False)
print("finished", flush=True)
"""


def test_sigint_stops_a_long_cg_solve_within_a_second():
    """CG on 1000 x 1000 to 1e-12 without the nested start (~10 s unloaded; 500 x 500 took
    only ~2 s since the faster CG, and could end before the signal): SIGINT 1.5 s into it."""
    stdout, stderr, latency, _ = sigint_after_ready(LONG_SOLVE, 1.5)
    assert "finished" not in stdout and "KeyboardInterrupt" in stderr
    assert latency < 1.0, f"stopped {latency:.2f} s after SIGINT"
