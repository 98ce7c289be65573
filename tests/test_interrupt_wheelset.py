"""Ctrl-C inside the wheelset's modes (issue 16 item 2). One harmonic of the default mesh
(10,000 equations) is one Fortran call of ~1 s (band Cholesky + ARPACK); it runs in a worker
thread with the GIL released while the main thread waits for signals
(``wheelset.fe._modes_call``), one call at a time (ARPACK is not reentrant): SIGINT stops the
process within about 0.05 s plus the exit (one blocking call: up to ~1.4 s,
benchmarks/bench_interrupt_latency.py)."""

from __future__ import annotations

import _thread
import signal
import threading

import numpy as np
import pytest

from interrupt_helper import sigint_after_ready
from railvti import _cache
from railvti.wheelset import Wheelset
from railvti.wheelset import fe

LONG_MODES = """
import os, signal
os.environ["RAILVTI_CACHE_DIR"] = ""   # solved, not replayed from the disk cache
signal.signal(signal.SIGINT, signal.default_int_handler)   # also when started with SIGINT ignored
from railvti.wheelset import Wheelset
ws = Wheelset()
print("ready", flush=True)
for k in range(7):
    ws.harmonic(k, 3000.0, "free")
print("finished", flush=True)
"""


def test_sigint_stops_the_wheelset_modes_within_a_second():
    stdout, stderr, latency, code = sigint_after_ready(LONG_MODES, 0.5)
    assert "finished" not in stdout and "KeyboardInterrupt" in stderr
    assert "_modes_call" in stderr  # stopped in the modes call's wait
    assert code != -signal.SIGSEGV
    assert latency < 1.0, f"stopped {latency:.2f} s after SIGINT"


def test_an_interrupted_modes_call_holds_arpack_until_its_end(monkeypatch):
    """In-process: interrupt_main 0.3 s into a harmonic. The abandoned call keeps the ARPACK
    lock until it ends; the next call waits for it and gives the frequencies of an
    uninterrupted call (to round-off) (computed first, on another Wheelset: no cache shared;
    the disk cache off, or the second call would replay the first's solve)."""
    monkeypatch.setenv(_cache.ENV, "")
    ref = Wheelset().harmonic(2, 3000.0, "free")
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            Wheelset().harmonic(2, 3000.0, "free")
        assert fe._ARPACK.locked()  # the abandoned call still runs
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    again = Wheelset().harmonic(2, 3000.0, "free")
    assert not fe._ARPACK.locked()
    assert again.freq_hz.size == ref.freq_hz.size > 3
    # not to the bit: ARPACK's random start vector moves on from call to call (two plain
    # successive calls differ by ~3e-12 Hz too)
    np.testing.assert_allclose(again.freq_hz, ref.freq_hz, rtol=1e-10)
