"""Ctrl-C inside the steady rolling solver (issue 16 item 2). Its Fortran call cannot run in
slices (Anderson history and patch set-up), so it runs in a worker thread with the GIL
released (``!f2py threadsafe``) while the main thread waits for signals
(``contact.workspace.call_interruptibly``): SIGINT stops the process within about 0.05 s
plus the exit, and the abandoned call's workspace is neither reused nor freed under it."""

from __future__ import annotations

import signal
import time

import numpy as np

from interrupt_helper import sigint_after_ready
from railvti import STEEL
from railvti.contact import Grid
from railvti.contact import workspace as ws_mod
from railvti.contact.hertz import hertz_gap
from railvti.contact.rolling import solve_rolling

LONG_ROLLING = """
import time
import signal
signal.signal(signal.SIGINT, signal.default_int_handler)   # also when started with SIGINT ignored
from railvti import STEEL
from railvti.contact import Grid
from railvti.contact.hertz import hertz_gap
from railvti.contact.rolling import solve_rolling
from railvti.contact.normal import solve_normal
g = Grid(320, 320, 75e-6, 75e-6, -12e-3, -12e-3)
gap = hertz_gap(g, 1.0, 1.6)
solve_normal(gap, g, STEEL, fn=1e5)           # the normal part's workspace and imports first
print("ready", flush=True)
solve_rolling(gap, g, STEEL, 0.3, 1e5, (1e-3, 5e-4, 0.5), 30.0, tol=1e-14, max_iter=100000)
print("finished", flush=True)
"""


def test_sigint_stops_a_long_rolling_solve_within_a_second():
    # 2.5 s: the normal solve (< 1 s), then inside the rolling call
    stdout, stderr, latency, code = sigint_after_ready(LONG_ROLLING, 2.5)
    assert "finished" not in stdout and "KeyboardInterrupt" in stderr
    assert "call_interruptibly" in stderr  # stopped in the rolling call's wait
    assert code != -signal.SIGSEGV
    assert latency < 1.0, f"stopped {latency:.2f} s after SIGINT"


def test_the_threaded_call_gives_the_numbers_of_a_direct_call(monkeypatch):
    g = Grid(40, 40, 0.5e-3, 0.5e-3, -10e-3, -10e-3)
    gap = hertz_gap(g, 1.0, 1.6)
    args = (gap, g, STEEL, 0.3, 1e5, (1e-3, 5e-4, 0.5), 30.0)
    threaded = solve_rolling(*args)
    monkeypatch.setattr("railvti.contact.rolling.call_interruptibly", lambda handle, fn, *a: fn(handle, *a))
    direct = solve_rolling(*args)
    assert threaded.iterations == direct.iterations > 3
    assert np.array_equal(threaded.tx, direct.tx) and np.array_equal(threaded.ty, direct.ty)


def test_a_workspace_still_in_use_waits_and_is_not_freed(monkeypatch):
    """A call on a busy workspace (an interrupted call still running on it) waits for it;
    freeing skips it."""
    freed = []
    monkeypatch.setattr(ws_mod.core, "contact_ws_free_c", freed.append)
    monkeypatch.setattr(ws_mod, "_live", ws_mod._live | {-7})  # a made workspace, busy
    ws_mod._busy.add(-7)
    try:
        ws_mod._free(-7)
        assert freed == []
        import threading

        threading.Timer(0.2, ws_mod._busy.discard, args=(-7,)).start()
        t0 = time.monotonic()
        assert ws_mod.call_interruptibly(-7, lambda h, x: (h, x), 3) == (-7, 3)
        assert time.monotonic() - t0 >= 0.15
    finally:
        ws_mod._busy.discard(-7)
