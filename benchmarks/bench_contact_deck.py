"""Whole-program time of CONTACT's A-2.2 decks against the solver's own time, per position.

Runs ``railvti run inputs/mbench_a22_{left,right}.inp -o TMP.h5`` as a user does (a fresh
process: Python start-up, imports, deck reading, the cases, HDF5) and reads the time each case
took (the wheel_rail case's own solve, geometry to forces): the ``wall_time`` attribute of its
group in the results file, to the microsecond (the ``[0.07 s]`` of its summary line, rounded
to 10 ms, for a file without it).
Prints per deck the wall time per position, the reported solve time per position and their
ratio (issue 29 item 5, issue 33 item 4: below 2). ``--railvti`` adds other installations
(e.g. a checkout of the previous commit) to compare in the same run: they run without the
caller's PYTHONPATH (so ``PYTHONPATH=NEW python bench_contact_deck.py --railvti
OLD/bin/railvti`` compares the two even when OLD is this interpreter's own installation);
each executable runs ``--repeat`` times, interleaved, and the median is printed, with the
machine's load (os.getloadavg) before and after.

    PYTHONPATH=NEW python benchmarks/bench_contact_deck.py [--railvti OLD/bin/railvti] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DECKS = [ROOT / "inputs" / "mbench_a22_left.inp", ROOT / "inputs" / "mbench_a22_right.inp"]
_CASE_TIME = re.compile(r"\[(\d+(?:\.\d+)?) s\]")


def run_once(exe: str, deck: Path, tmp: Path, env: dict | None = None) -> tuple[float, list[float]]:
    """Wall time of one `railvti run` of a deck and the times its cases report (``env``: the
    process's environment, default this one's)."""
    out = tmp / f"{deck.stem}_{time.monotonic_ns()}.h5"
    t0 = time.perf_counter()
    proc = subprocess.run(
        [exe, "run", str(deck), "-o", str(out), "-q"],
        capture_output=True,
        text=True,
        cwd=deck.parent,
        env=env,
    )
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"{exe} run {deck.name} failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    with h5py.File(out, "r") as f:
        times = [float(g.attrs["wall_time"]) for g in f.values() if "wall_time" in g.attrs]
    return wall, times or [float(t) for t in _CASE_TIME.findall(proc.stdout)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--railvti",
        action="append",
        default=[],
        metavar="EXE",
        help="another railvti executable to time in the same run (repeatable)",
    )
    ap.add_argument("--repeat", type=int, default=3, help="runs per executable and deck (median printed)")
    args = ap.parse_args()
    own = str(Path(sys.executable).with_name("railvti"))
    bare = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    path = os.environ.get("PYTHONPATH", "")
    exes = [(f"{own} (PYTHONPATH={path})" if path else own, own, None)]
    exes += [(f"{exe} (no PYTHONPATH)", exe, bare) for exe in args.railvti]
    results: dict[tuple[str, str], list[tuple[float, float, int]]] = {}
    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(args.repeat):
            for deck in DECKS:
                for label, exe, env in exes:
                    wall, cases = run_once(exe, deck, Path(tmp), env)
                    results.setdefault((label, deck.name), []).append((wall, sum(cases), len(cases)))
    print(f"load (1, 5, 15 min) before {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}, after", end=" ")
    print(" ".join(f"{x:.2f}" for x in os.getloadavg()))
    print(f"{'railvti':72s} {'deck':22s} {'whole s/pos':>11s} {'solve s/pos':>11s} {'ratio':>6s}")
    for (exe, deck), runs in results.items():
        wall = float(np.median([r[0] for r in runs]))
        solve = float(np.median([r[1] for r in runs]))
        n = runs[0][2]
        print(f"{exe[-72:]:72s} {deck:22s} {wall / n:11.3f} {solve / n:11.3f} {wall / solve:6.2f}")


if __name__ == "__main__":
    main()
