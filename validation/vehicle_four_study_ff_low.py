"""The lower side of FF's BEM fold (issue 30): the study's BEM path of FF keeps the flange cycle
down to its floor (280 km/h, 8.10 mm); this path starts at 280 km/h from the study's 6 mm
shift (8 mm puts the start's flange patch past the BEM grid) and walks down in 10 km/h steps
to 260 km/h, with the same settings as the study's FF BEM path (k_max 1 / 300 Hz, the ring's
residual inertia, 3 s per speed). A start that dies is no bound (a cycle may live there from
the carried state); one that lives and dies below brackets the fold.

    .venv/bin/python validation/vehicle_four_study_ff_low.py              # from 280 km/h
    .venv/bin/python validation/vehicle_four_study_ff_low.py --top 300    # ~20 min on 2 cores

Stores FF_bem_low_* into validation/figures/vehicle_four_study.npz (the study's store) and
prints the path.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from railvti.critical_search import nonlinear_critical_speed

import vehicle_four_study as study


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--top", type=float, default=280.0, help="the first speed, km/h")
    a = ap.parse_args(argv)
    t = time.perf_counter()
    c = nonlinear_critical_speed(
        "FF",
        "bem",
        k_max=1,
        f_max=300.0,
        speed_top_kmh=a.top,
        step_kmh=10.0,
        speed_floor_kmh=260.0,
        resolution_kmh=5.0,
        duration=3.0,
        y_large=0.006,
        decay=False,
        ring_residual_inertia=True,
    )
    wall = time.perf_counter() - t
    print(c.message)
    for s, a, ok in zip(c.path_speeds, c.path_amplitudes, c.path_alive):
        print(f"  {s * 3.6:.1f} km/h: {a * 1e3:.3f} mm, {'alive' if ok else 'died'}")
    out = study._load()
    study._store(
        out,
        "FF_bem_low",
        {
            "fold_lo": c.fold_bracket_kmh[0],
            "fold_hi": c.fold_bracket_kmh[1],
            "path_kmh": np.asarray(c.path_speeds) * 3.6,
            "path_amp": np.asarray(c.path_amplitudes),
            "path_alive": np.asarray(c.path_alive),
            "failure": c.failure,
        },
        wall,
    )
    print(f"[{wall:.0f} s]")


if __name__ == "__main__":
    main()
