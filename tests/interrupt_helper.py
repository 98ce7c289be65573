"""Shared by the interrupt tests: run a script in a child process, send SIGINT a given time
after it prints 'ready', and measure how long the child takes to exit."""

from __future__ import annotations

import signal
import subprocess
import sys
import time


def sigint_after_ready(script: str, delay: float) -> tuple[str, str, float, int]:
    """Run ``script`` (it prints 'ready' before its long call), send SIGINT ``delay`` s after
    that line, and return the child's stdout, stderr, the time from SIGINT to exit (s) and
    its return code.
    The child starts with SIGINT's default (a suite run in the background ignores it)."""
    proc = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    assert proc.stdout.readline().strip() == "ready"
    time.sleep(delay)
    assert proc.poll() is None, "the call ended before the signal"
    t0 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    return stdout, stderr, time.monotonic() - t0, proc.returncode
