"""Time from SIGINT to the end of the process inside long single Fortran calls, as the code
runs now ('sliced' / 'threaded') and as one blocking call ('one call', the code before).

* CG normal solver (preconditioned) on 1200 x 1200 and without preconditioner ('pk') on
  500 x 500: resumable slices of ~0.1 s (``normal_cg_slice_c``);
* steady rolling on 320 x 320, 40 iterations (~10 s): one call in a worker thread
  (``call_interruptibly``);
* the vehicle's static equilibrium with the BEM contact (coach, 0.75 mm grids, ~3.5 s): one
  Newton call in a worker thread (``equilibrium._static_call``);
* the wheelset's modes, k = 0..6 up to 3 kHz (default mesh, 10,000 equations): one Fortran
  call per harmonic (~1 s), each in a worker thread, one at a time (ARPACK is not reentrant;
  ``wheelset.fe._modes_call``).

Each run is a fresh process; SIGINT is sent 2 s into the call (1 s into the static solve).

Run: ``.venv/bin/python benchmarks/bench_interrupt_latency.py [case name ...]``
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time

SETUP = """
import sys
import signal
signal.signal(signal.SIGINT, signal.default_int_handler)   # also when started with SIGINT ignored
from railvti import STEEL
from railvti._native import core
from railvti.contact import Grid
from railvti.contact import normal as nm, rolling as rl
from railvti.contact.hertz import hertz_gap
mode = sys.argv[1]
if mode == "one call":
    nm._cg_in_slices = lambda hd, h, c, m, tol, mi, fn, ap, p, sub: core.normal_solve_c(hd, h, c, m, tol, mi, 1.0, fn, ap, p)
    rl.call_interruptibly = lambda hd, fn, *a: fn(hd, *a)
    import railvti.vehicle.equilibrium as vs
    vs._static_call = lambda system, cs, bem, q, tol, maxit: system.native.static(cs, q, tol, maxit)
    from railvti.wheelset import fe
    fe._modes_call = core.wheelset_modes_c
"""
CASES = {
    "CG 1200 x 1200, fn": """
n = 1200
g = Grid(n, n, 24e-3 / n, 24e-3 / n)
gap = hertz_gap(g, 1.0, 1.6)
print("ready", flush=True)
nm.solve_normal(gap, g, STEEL, fn=1e5, tol=1e-12, max_iter=100000)
""",
    "pk 500 x 500, fn": """
g = Grid(500, 500, 48e-6, 48e-6)
gap = hertz_gap(g, 1.0, 1.6)
print("ready", flush=True)
nm.solve_normal(gap, g, STEEL, method="pk", fn=1e5, tol=1e-12, max_iter=100000)
""",
    "rolling 320 x 320": """
g = Grid(320, 320, 75e-6, 75e-6, -12e-3, -12e-3)
gap = hertz_gap(g, 1.0, 1.6)
nm.solve_normal(gap, g, STEEL, fn=1e5)
print("ready", flush=True)
rl.solve_rolling(gap, g, STEEL, 0.3, 1e5, (1e-3, 5e-4, 0.5), 30.0, tol=1e-14, max_iter=40)
""",
    "vehicle static, BEM": """
from railvti import scenarios
from railvti.vehicle import bem_state, static_equilibrium
sy = scenarios.coach_system()
with bem_state(sy) as st:
    print("ready", flush=True)
    static_equilibrium(sy, 200 / 3.6, "bem", bem=st)
""",
    "wheelset modes": """
from railvti.wheelset import Wheelset
ws = Wheelset()
print("ready", flush=True)
for k in range(7):
    ws.harmonic(k, 3000.0, "free")
""",
}


def latency(code: str, mode: str, delay: float = 2.0) -> tuple[float, str]:
    """Seconds from SIGINT to the end of the process, and how it ended."""
    proc = subprocess.Popen(
        [sys.executable, "-c", SETUP + code, mode], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert proc.stdout.readline().strip() == "ready"
    time.sleep(delay)
    if proc.poll() is not None:
        return float("nan"), "finished before the signal"
    t0 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=900)
    dt = time.monotonic() - t0
    return dt, "KeyboardInterrupt" if "KeyboardInterrupt" in err else f"exit {proc.returncode}"


#: Seconds from 'ready' to SIGINT (default 2 s): the static solve lasts ~3.5 s in all.
DELAYS = {"vehicle static, BEM": 1.0}


def main() -> None:
    names = sys.argv[1:] or list(CASES)  # a subset by name, e.g. "vehicle static, BEM"
    print(f"{'call':<22} | {'mode':<9} | {'stop after SIGINT, s':>20} | how")
    for name in names:
        for mode in ("one call", "now"):
            dt, how = latency(CASES[name], mode, DELAYS.get(name, 2.0))
            print(f"{name:<22} | {mode:<9} | {dt:20.2f} | {how}")


if __name__ == "__main__":
    main()
