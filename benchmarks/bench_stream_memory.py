"""Peak memory of a long vehicle run with its history kept in memory against streamed to HDF5
(railvti.runner.stream): through the Python API (``simulate(..., stream_to=)``) and through
``railvti run`` (a deck case above / below ``RAILVTI_STREAM_ABOVE``).

Each run is a fresh process (peak RSS is per process: ``ru_maxrss`` of the child); the API
runs also report the tracemalloc peak (numpy's arrays are traced) and the growth of RSS
over the run. Hunting at 300 km/h, Hertz + Kalker, h = output_dt = 1 ms (1.9 kB per output).

Run: ``.venv/bin/python benchmarks/bench_stream_memory.py [DURATION_S]`` (default 60 s).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CHILD = r"""
import json, resource, sys, time, tracemalloc
from railvti import scenarios as sc
from railvti.runner.stream import HistoryStream
duration, stream = float(sys.argv[1]), sys.argv[2]
sc.hunting(300.0, duration=0.01, progress=False)          # contact table and imports first
rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
tracemalloc.start()
t0 = time.perf_counter()
sink = None if stream == "-" else HistoryStream(stream)
r = sc.hunting(300.0, duration=duration, output_dt=1e-3, progress=False, stream_to=sink)
if sink is not None:
    sink.close()
wall = time.perf_counter() - t0
peak = tracemalloc.get_traced_memory()[1]
print(json.dumps({"wall": wall, "traced_peak": peak, "rss_before": rss0 * 1024,
                  "outputs_in_memory": len(r.t)}))
"""

DECK = """&case
    name = 'long', type = 'vehicle', scenario = 'hunting', duration = {duration}, output_dt = 0.001
/
"""


def _child_rss(cmd: list[str], env: dict | None = None) -> tuple[float, str, float]:
    """Run ``cmd``; its peak RSS (bytes), stdout and wall time."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"{cmd} failed with status {proc.returncode}")
    return usage.ru_maxrss * 1024.0, out, time.perf_counter() - t0


def main() -> None:
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    mb = 1e6
    print(
        f"hunting 300 km/h, {duration:g} s simulated, h = output_dt = 1 ms ({duration / 1e-3:.0f} outputs)\n"
    )
    print("Python API (simulate):")
    print(
        f"{'history':>10} | {'peak RSS MB':>11} | {'RSS growth MB':>13} | {'traced peak MB':>14} | "
        f"{'outputs kept':>12} | {'wall s':>6}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        for mode in ("memory", "streamed"):
            target = "-" if mode == "memory" else str(Path(tmp) / "stream.h5")
            rss, out, _ = _child_rss([sys.executable, "-c", CHILD, str(duration), target])
            d = json.loads(out.strip().splitlines()[-1])
            print(
                f"{mode:>10} | {rss / mb:11.0f} | {(rss - d['rss_before']) / mb:13.0f} | "
                f"{d['traced_peak'] / mb:14.1f} | {d['outputs_in_memory']:12d} | {d['wall']:6.1f}"
            )
        print("\nrailvti run (one deck case):")
        print(f"{'history':>10} | {'peak RSS MB':>11} | {'file MB':>7} | {'wall s':>6}")
        deck = Path(tmp) / "long.nml"
        deck.write_text(DECK.format(duration=duration))
        for mode, threshold in (("memory", "none"), ("streamed", "0")):
            out_h5 = Path(tmp) / f"{mode}.h5"
            env = dict(os.environ, RAILVTI_STREAM_ABOVE=threshold)
            rss, _, wall = _child_rss(
                [sys.executable, "-m", "railvti.runner.cli", "run", str(deck), "-o", str(out_h5), "-q"], env
            )
            print(f"{mode:>10} | {rss / mb:11.0f} | {out_h5.stat().st_size / mb:7.1f} | {wall:6.1f}")


if __name__ == "__main__":
    main()
