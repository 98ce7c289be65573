"""Sweeps on dask.distributed: the same bifurcation sweep serial, on a LocalCluster of 2
workers, and through a scheduler address with 2 worker processes; speed-up and overhead.

The sweep: model RR, Hertz + FASTSIM, 24 speeds from 440 down to 210 km/h by 10, each run
twice (from a 6 mm and a 0.5 mm lateral shift, 2 s each): 48 independent runs
(``scenarios.bifurcation(..., independent=True)`` serial, ``client=...`` on a cluster). Each
new worker process first gets the contact table, the strip geometry and the profiles'
conicity (as the serial process does once; built, or since issue 33 loaded from the disk
cache, railvti._cache, which the serial process filled): the timings are given with that
warm-up and without it. The run uses a new, empty cache folder (``RAILVTI_CACHE_DIR``,
removed at the end), so the serial process builds the tables as on a first run. The
results are checked to be the same bit for bit. With the cache, the time to get the contact
table into each worker is measured both ways: pickled from this process (``client.run``)
and loaded from the disk cache. The overhead per task is also measured directly with 200 empty tasks, and the
CPU time the workers spent on the sweep is compared with the serial process's: on a machine
shared with other jobs the wall-clock speed-up depends on their load, the CPU ratio does not.

    python benchmarks/bench_sweeps.py [--speeds 24] [--duration 2.0] [--no-scheduler]

Old and new builds in one run, alternately (issue 33)::

    for p in OLD NEW OLD NEW; do PYTHONPATH=$p python benchmarks/bench_sweeps.py --speeds 8; done

Other processes on the machine slow the parallel runs more than the serial one: the load
(``os.getloadavg``) is printed before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np


def _noop(i: int) -> int:
    return i


def _warm(_: int) -> float:
    """This worker's contact table, system and the profiles' conicity (what every sweep point
    needs first)."""
    from railvti import scenarios
    from railvti.vehicle import systems

    t0 = time.perf_counter()
    scenarios.coach_system("RR")
    systems.hunting_conicity()
    return time.perf_counter() - t0


def _receive(table) -> int:
    """A contact table sent pickled (its size, to use it)."""
    return int(table.data_roll.size)


def _load_table() -> float:
    """Seconds to get the scenarios' contact table from the disk cache (the in-memory one
    emptied)."""
    from railvti.vehicle import systems, table

    table._CACHE.clear()
    t0 = time.perf_counter()
    systems.wheel_table()
    return time.perf_counter() - t0


def _delivery(client) -> str:
    """The contact table into each worker, pickled from here and from the disk cache."""
    import importlib.util

    if importlib.util.find_spec("railvti._cache") is None:
        return "no disk cache in this build"
    from railvti.vehicle import systems

    tab = systems.wheel_table()
    t0 = time.perf_counter()
    client.run(_receive, tab)
    pickled = time.perf_counter() - t0
    t0 = time.perf_counter()
    inside = max(client.run(_load_table).values())
    disk = time.perf_counter() - t0
    return (
        f"contact table ({tab.data_roll.nbytes / 1e6:.1f} MB) into every worker: pickled from "
        f"this process {pickled * 1e3:.0f} ms, from the disk cache {disk * 1e3:.0f} ms "
        f"({inside * 1e3:.0f} ms in the slowest worker)"
    )


def _cpu(client) -> float:
    """CPU seconds used so far: this process (client None) or the sum over the workers."""
    if client is None:
        return time.process_time()
    return float(sum(client.run(time.process_time).values()))


def _sweep(client, speeds, duration):
    """(Bifurcation, wall time, CPU time) of the sweep."""
    from railvti import scenarios

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # 'no decay found' at the bottom
        c0, t0 = _cpu(client), time.perf_counter()
        b = scenarios.bifurcation(
            speeds,
            contact="hertz-fastsim",
            duration=duration,
            v_min_kmh=float(min(speeds)),
            progress=False,
            independent=True,
            client=client,
        )
        return b, time.perf_counter() - t0, _cpu(client) - c0


def _overhead(client, n: int = 200) -> float:
    """Seconds per empty task, submitted together and gathered."""
    t0 = time.perf_counter()
    client.gather(client.map(_noop, range(n), pure=False))
    return (time.perf_counter() - t0) / n


def _measure(client, n_workers, speeds, duration):
    t0 = time.perf_counter()
    client.gather(client.map(_warm, range(n_workers), pure=False))
    warm = time.perf_counter() - t0
    b, t, cpu = _sweep(client, speeds, duration)
    return b, t, cpu, warm, _overhead(client), _delivery(client)


def _scheduler(folder: Path):
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", TQDM_DISABLE="1")
    sfile = folder / "scheduler.json"
    procs = [
        subprocess.Popen(
            [
                sys.executable,
                "-m",
                "dask",
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                "0",
                "--no-dashboard",
                "--scheduler-file",
                str(sfile),
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
        )
    ]
    t0 = time.monotonic()
    while not sfile.exists() and time.monotonic() - t0 < 60:
        time.sleep(0.1)
    address = json.loads(sfile.read_text())["address"]
    procs.append(
        subprocess.Popen(
            [
                sys.executable,
                "-m",
                "dask",
                "worker",
                address,
                "--nworkers",
                "2",
                "--nthreads",
                "1",
                "--no-dashboard",
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
            cwd=folder,
        )
    )
    return address, procs


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", type=int, default=24, help="speeds in the sweep (2 runs each)")
    ap.add_argument("--duration", type=float, default=2.0, help="simulated time per run, s")
    ap.add_argument("--no-scheduler", action="store_true", help="only the LocalCluster")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="railvti-bench-cache-") as cache:
        os.environ["RAILVTI_CACHE_DIR"] = cache  # empty: the serial process builds and stores
        return _main(args)


def _main(args) -> int:
    import logging

    logging.getLogger("railvti").setLevel(logging.ERROR)  # the 'no decay found' warning
    from distributed import Client
    from railvti.runner import sweeps

    speeds = [440.0 - 10.0 * i for i in range(args.speeds)]
    n_tasks = 2 * len(speeds)
    import railvti

    print(f"railvti from {Path(railvti.__file__).parent}")
    print(f"load before: {os.getloadavg()[0]:.2f} (1 min), {os.cpu_count()} cores")
    print(
        f"sweep: {len(speeds)} speeds {speeds[0]:.0f}..{speeds[-1]:.0f} km/h x 2 starts = "
        f"{n_tasks} runs of {args.duration:g} s (RR, Hertz + FASTSIM)"
    )
    t0 = time.perf_counter()
    _warm(0)
    warm_serial = time.perf_counter() - t0
    ref, t_serial, cpu_serial = _sweep(None, speeds, args.duration)
    print(
        f"serial: sweep {t_serial:.1f} s, CPU {cpu_serial:.1f} s (+ {warm_serial:.1f} s contact table and "
        "conicity, once)"
    )
    rows = {}
    t0 = time.perf_counter()
    with sweeps.local_client(2) as client:
        start = time.perf_counter() - t0
        rows["LocalCluster"] = (start,) + _measure(client, 2, speeds, args.duration)
    with tempfile.TemporaryDirectory() as tmp:
        if args.no_scheduler:
            return _report(rows, ref, t_serial, cpu_serial, warm_serial, n_tasks)
        t0 = time.perf_counter()
        address, procs = _scheduler(Path(tmp))
        try:
            with Client(address, timeout=30) as client:
                client.wait_for_workers(2, timeout=60)
                start = time.perf_counter() - t0
                rows[f"scheduler {address}"] = (start,) + _measure(client, 2, speeds, args.duration)
        finally:
            for p in reversed(procs):
                p.terminate()
            for p in reversed(procs):
                p.wait(timeout=30)
    return _report(rows, ref, t_serial, cpu_serial, warm_serial, n_tasks)


def _report(rows, ref, t_serial, cpu_serial, warm_serial, n_tasks) -> int:
    same = True
    for name, (start, b, t, cpu, warm, over, delivery) in rows.items():
        ident = all(np.array_equal(getattr(ref, k), getattr(b, k)) for k in ("speeds_kmh", "upper", "decay"))
        same &= ident
        ideal = t_serial / 2
        per_task = (t - ideal) * 2 / n_tasks
        print(
            f"{name}: start {start:.1f} s, worker warm-up {warm:.1f} s, sweep {t:.1f} s: "
            f"speed-up {t_serial / t:.2f} (with start and warm-up "
            f"{(t_serial + warm_serial) / (t + start + warm):.2f}); time over the ideal "
            f"{per_task * 1e3:.0f} ms per task; empty task {over * 1e3:.2f} ms; workers' "
            f"CPU {cpu:.1f} s ({cpu / cpu_serial:.2f} x serial: speed-up on an idle machine "
            f"at most {2 * cpu_serial / cpu:.2f}); results "
            f"{'bit-identical' if ident else 'DIFFER'} to serial; {delivery}"
        )
    print(f"load after: {os.getloadavg()[0]:.2f} (1 min)")
    print(f"critical speed (serial): {ref.message}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
