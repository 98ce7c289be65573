"""Manchester Contact Benchmark case A-2.2 (Shackleton & Iwnicki, Vehicle System Dynamics 46,
2008): S1002 wheels on UIC60 rails canted 1:40, gauge 1435 mm, back-to-back 1360 mm, wheel
radius 460 mm, 10 kN vertical load per wheel, lateral shift 0..10 mm in 0.5 mm steps with the
yaw rising at 2.4 mrad per mm, mu = 0.3, G = 82 GPa, nu = 0.28, V = 2 m/s, 0.2 mm grid.

Prints per shift and wheel: contact position, contact angle, creepages, Fn, Fx, Fy, pmax and
the number of elements in contact; checks the load control; writes
validation/figures/contact_a22_sweep.png and contact_a22_patches.png (patches at 0, 5, 7 mm).

    python validation/contact_a22.py [--dx 0.2]
"""
from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

import numpy as np

from railvti import Material, profiles
from railvti.contact.wheelset import solve_wheelset
from railvti.contact.wheelset_cases import sweep_arrays
from railvti.contact.wheelset_plots import plot_fields, plot_sweep

FIG = Path(__file__).parent / "figures"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--dx", type=float, default=0.2, help="element size, mm")
    args = ap.parse_args()
    logging.disable(logging.WARNING)
    wheel, rail = profiles.s1002(), profiles.uic60(cant=1 / 40)
    mat = Material(shear_modulus=82e9, poisson=0.28)
    y_mm = np.arange(0.0, 10.01, 0.5)
    sols, times = [], []
    for y in y_mm:
        t0 = time.perf_counter()
        sols.append(solve_wheelset(wheel, rail, y * 1e-3, 2.4e-3 * y, 1.0e4, 0.3, 2.0, mat, args.dx * 1e-3))
        times.append(time.perf_counter() - t0)
    arr = sweep_arrays(sols)
    print(f"A-2.2 at {args.dx} mm: {len(y_mm)} shifts, {np.mean(times) * 1e3:.0f} ms per shift (mean, "
          f"both wheels with load control and rolling)")
    print(f"{'y mm':>5s} {'wheel':5s} {'#':>1s} {'y_rail mm':>9s} {'angle':>6s} {'xi':>9s} {'eta':>9s} "
          f"{'phi 1/m':>8s} {'Fn kN':>7s} {'Fx kN':>7s} {'Fy kN':>7s} {'pmax MPa':>8s} {'n el':>5s} {'status':>12s}")
    worst = 0.0
    for i, s in enumerate(sols):
        for w, side in enumerate(("left", "right")):
            fz = sum(p.fn * p.contact.normal[2] for p in s.wheel(side))
            worst = max(worst, abs(fz / 1e4 - 1))
            for k, p in enumerate(s.wheel(side)):
                c = p.creepage
                print(f"{y_mm[i]:5.1f} {side:5s} {k:1d} {p.contact.y_rail * 1e3:9.2f} {p.contact_angle:6.3f} "
                      f"{c.xi:9.2e} {c.eta:9.2e} {c.phi:8.3f} {p.fn / 1e3:7.2f} {p.fx / 1e3:7.3f} "
                      f"{p.fy / 1e3:7.3f} {p.pmax / 1e6:8.0f} {p.n_contact:5d} {s.geometry.status[w]:>12s}")
    print(f"load control: largest |Fz/10 kN - 1| over all wheels and shifts = {worst:.2e}")
    flange = y_mm[np.nanmax(arr["contact_angle"][:, 0, :], axis=1) > 1.0]
    if flange.size:
        print(f"flange contact (angle > 1 rad) on the left wheel from y = {flange.min():.1f} mm")
    FIG.mkdir(exist_ok=True)
    plot_sweep(y_mm * 1e-3, arr, FIG / "contact_a22_sweep.png")
    fields = {}
    for y_show in (0.0, 5.0, 7.0):
        s = sols[int(np.argmin(np.abs(y_mm - y_show)))]
        for side in ("left", "right"):
            for k, p in enumerate(s.wheel(side)):
                fields[f"y = {y_show:g} mm, {side} wheel, patch {k}"] = dict(
                    pressure=p.pressure, x=p.grid.x, y=p.grid.y, tx=p.tx, ty=p.ty)
    plot_fields(fields, FIG / "contact_a22_patches.png")
    print(f"wrote {FIG / 'contact_a22_sweep.png'} and {FIG / 'contact_a22_patches.png'}")


if __name__ == "__main__":
    main()
