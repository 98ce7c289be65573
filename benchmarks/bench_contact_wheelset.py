"""Benchmark of the loaded wheelset on the Manchester benchmark's case A-2.2 (21 positions,
0.2 mm grid, both wheels, normal + steady rolling, vertical balance with tangential forces):

* the decks' kinematics (inputs/mbench_a22_*.inp: roll and pitch velocity prescribed per
  position, the benchmark's profile files): the acceptance case;
* load-controlled roll with omega = V / r0 (what solve_wheelset did before it balanced the
  tangential forces), on the generated S1002 / UIC60 1:40 profiles, the wheelset shifted
  to the left (the mirror image);
* load-controlled roll with free rolling (omega from the torque balance, the default);
* normal contact only; and the 201-position contact table (geometry only).

    python benchmarks/bench_contact_wheelset.py [--only decks]
"""

from __future__ import annotations

import argparse
import logging
import resource
import time

import numpy as np

from railvti import Material, geometry, profiles
from railvti.contact.contact_deck import read_contact_deck
from railvti.contact.wheelset import solve_wheelset

Y_MM = np.arange(0.0, 10.01, 0.5)


def _deck_cases() -> list[dict]:
    from pathlib import Path

    deck = Path(__file__).resolve().parent.parent / "inputs" / "mbench_a22_left.inp"
    return [c.params for c in read_contact_deck(deck)]


def _time(label: str, calls, repeat: int = 2) -> None:
    """Wall-clock time per position (first sweep: workspaces made) and the process's CPU time
    (less sensitive to other jobs on a shared machine)."""
    for run in range(repeat):
        t = []
        c0 = time.process_time()
        for call in calls:
            t0 = time.perf_counter()
            call()
            t.append(time.perf_counter() - t0)
        cpu = (time.process_time() - c0) / len(calls) * 1e3
        t = np.array(t) * 1e3
        print(
            f"A-2.2 {label:44s} {'first' if run == 0 else 'repeat':6s}: {t.mean():6.1f} ms per position "
            f"(median {np.median(t):.1f}, max {t.max():.1f}; CPU {cpu:.1f} ms), sweep {t.sum() / 1e3:.2f} s"
        )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", choices=["decks", "old"], help="run one variant only")
    args = ap.parse_args()
    logging.disable(logging.WARNING)
    mat = Material(shear_modulus=82e9, poisson=0.28)
    if args.only in (None, "decks"):
        wheel = profiles.read(profiles.example_path("MBench_S1002_v3.prw"))
        rail = profiles.read(profiles.example_path("MBench_UIC60_v3.prr"))
        calls = [
            lambda p=p: solve_wheelset(
                wheel,
                rail,
                p["y"],
                p["yaw"],
                p["fz"],
                p["mu"],
                p["speed"],
                mat,
                p["dx"],
                omega=p["omega"],
                roll=p["roll"],
            )
            for p in _deck_cases()
        ]
        _time("decks' kinematics (roll, omega prescribed)", calls)
    wheel, rail = profiles.s1002(), profiles.uic60()
    if args.only in (None, "old"):
        calls = [
            lambda y=y: solve_wheelset(
                wheel, rail, y * 1e-3, 2.4e-3 * y, 1.0e4, 0.3, 2.0, mat, 2e-4, omega=2.0 / 0.46
            )
            for y in Y_MM
        ]
        _time("load-controlled roll, omega = V / r0", calls)
    if args.only is None:
        calls = [
            lambda y=y: solve_wheelset(wheel, rail, y * 1e-3, 2.4e-3 * y, 1.0e4, 0.3, 2.0, mat, 2e-4)
            for y in Y_MM
        ]
        _time("load-controlled roll, free rolling", calls)
        calls = [
            lambda y=y: solve_wheelset(wheel, rail, y * 1e-3, 2.4e-3 * y, 1.0e4, None, None, mat, 2e-4)
            for y in Y_MM
        ]
        _time("normal only", calls)
        y = np.linspace(-10e-3, 10e-3, 201)
        geometry.geometry_table(wheel, rail, y[:3])
        t0 = time.perf_counter()
        geometry.geometry_table(wheel, rail, y)
        print(f"contact table, 201 positions: {time.perf_counter() - t0:.3f} s")
    print(f"peak memory {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main()
