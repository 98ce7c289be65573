"""Continuity of the BEM contact force across the contact table's branch changes.

The vehicle's contact table tracks each slot's point as a branch (a local minimum of the
wheel-rail gap followed continuously in the lateral shift y); the look-up never blends gap
fields or points of two branches (vehicle_contact.table_at). This script runs the BEM
contact of the left wheel of one wheelset (zero roll and yaw, no creepage) at a fixed
vertical approach d0 below the exact minimum gap (computed here from the profiles, not from
the table) through every branch change of the S1002 / UIC60 1:40 table (0.05 mm steps), and
compares with the exact fields: a table whose nodes lie on the evaluation points (12.5 um).

    .venv/bin/python validation/vehicle_branches.py   # ~2-4 min; writes
                                                      # validation/figures/vehicle_branches.png
"""

from __future__ import annotations

import dataclasses
import logging
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti._status import Status, describe
from railvti.geometry import layout
from railvti.vehicle import BemOptions, bem_state, build_single_wheelset
from railvti.vehicle.bem import grid_for
from railvti.vehicle.equilibrium import call_settings
from railvti.vehicle.model import WHEEL_OUTPUTS
from railvti.vehicle.table import QUANTITIES, wheel_table

W = WHEEL_OUTPUTS
log = logging.getLogger("vehicle_branches")
FIG = Path(__file__).resolve().parent / "figures"
V = 200 / 3.6
D0 = 60e-6  # vertical approach below the minimum gap, m
BANDS = [(0.15e-3, 0.30e-3), (4.05e-3, 5.25e-3), (5.25e-3, 6.15e-3), (6.50e-3, 6.75e-3)]


def exact_min_gap(table, y: np.ndarray) -> np.ndarray:
    """Minimum vertical gap of the left wheel at nominal height, straight from the profiles."""
    lay = layout(table.wheel, table.rail)
    yr = y[:, None] + lay.wheelset.contact_y + lay.ws[None, :] - lay.rail_offset
    zr = np.interp(yr, lay.ry, lay.rz, left=np.nan, right=np.nan)
    return np.nanmin(zr - lay.rail_top - lay.wz[None, :], axis=1)


def left_fn(table, y: np.ndarray, grid: tuple[int, int]) -> np.ndarray:
    """Normal forces (N, tread + flange slot) of the left wheel at y with the approach D0."""
    sy = build_single_wheelset(
        table,
        mass=1500.0,
        roll_inertia=700.0,
        yaw_inertia=700.0,
        ky=0.0,
        kx=0.0,
        half_spacing=1.0,
        axle_load=1e5,
    )
    g = exact_min_gap(table, y)
    out = np.empty((y.size, 2))
    with bem_state(sy, BemOptions(nx=grid[0], ny=grid[1])) as st:
        cs = call_settings(V, "bem", 8, st)
        for i, (yi, gi) in enumerate(zip(y, g)):
            q = np.array([yi, -gi - D0, 0.0, 0.0])
            _, wout, _, _, info = sy.native.force(cs, q, np.zeros(4))
            if info != Status.OK:
                log.warning("y = %.4f mm: %s", yi * 1e3, describe(info)[0])
                out[i] = np.nan
                continue
            out[i] = wout[W.index("N_tread"), 0, 0], wout[W.index("N_flange"), 0, 0]
    return out


def main() -> None:
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t0 = time.perf_counter()
    coarse = scenarios.wheel_table()
    w, r = coarse.wheel, coarse.rail
    fine = wheel_table(w, r, y_max=0.007, step=coarse.dy / 4)  # nodes every 12.5 um
    # the look-up as it was: one label for every node, i.e. linear blending across the jumps
    data = np.array(coarse.data, order="F", copy=True)
    data[QUANTITIES.index("branch")] = 0.0
    blended = dataclasses.replace(coarse, data=data)
    g = grid_for(coarse, 6e4, BemOptions())
    grid = (g.nx, g.ny)
    print(f"BEM grid {g.nx} x {g.ny} of {g.dx * 1e3:.2f} mm")
    fig, axes = plt.subplots(1, len(BANDS), figsize=(16, 4.2))
    worst = 0.0
    for ax, (a, b) in zip(axes, BANDS):
        y = np.arange(round(a / fine.dy), round(b / fine.dy) + 1) * fine.dy
        fc = left_fn(coarse, y, grid)
        fe = left_fn(fine, y, grid)
        fb = left_fn(blended, y, grid).sum(axis=1)
        nc, ne = fc.sum(axis=1), fe.sum(axis=1)
        dev = np.nanmax(np.abs(nc - ne))
        jump = np.nanmax(np.abs(np.diff(nc)))
        jump_e = np.nanmax(np.abs(np.diff(ne)))
        bad = int(np.isnan(nc).sum() + np.isnan(ne).sum())
        worst = max(worst, dev / np.nanmax(ne))
        print(
            f"y {a * 1e3:.2f}-{b * 1e3:.2f} mm: max |Fn table - Fn exact| = {dev / 1e3:.2f} kN "
            f"({dev / np.nanmax(ne):.1%} of max {np.nanmax(ne) / 1e3:.1f} kN); largest step between "
            f"neighbours {jump / 1e3:.2f} kN (exact {jump_e / 1e3:.2f} kN); {bad} failed solves; "
            f"blended across jumps: max deviation {np.nanmax(np.abs(fb - ne)) / 1e3:.2f} kN"
        )
        nodes = coarse.y[(coarse.y >= a - 1e-12) & (coarse.y <= b + 1e-12)]
        ax.plot(y * 1e3, ne / 1e3, "k-", lw=2.5, alpha=0.35, label="exact field (node at y)")
        ax.plot(y * 1e3, nc / 1e3, "C0.-", ms=3, label="table, 0.05 mm nodes (branches)")
        ax.plot(y * 1e3, fb / 1e3, "C1:", lw=1.5, label="table blended across jumps (before)")
        ax.plot(y * 1e3, fc[:, 1] / 1e3, "C3--", lw=1, label="table, flange slot")
        for yn in nodes:
            ax.axvline(yn * 1e3, color="0.85", lw=0.6, zorder=0)
        ax.set_xlabel("lateral shift y of the wheelset, mm")
        ax.set_ylabel("normal force Fn of the left wheel, kN")
        ax.set_title(f"y = {a * 1e3:.2f} - {b * 1e3:.2f} mm", fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle(
        f"BEM normal force at a fixed vertical approach of {D0 * 1e6:.0f} um below the "
        "minimum gap, through the table's branch changes (grey: table nodes)"
    )
    fig.tight_layout()
    FIG.mkdir(exist_ok=True)
    out = FIG / "vehicle_branches.png"
    fig.savefig(out, dpi=110)
    print(f"worst deviation table vs exact: {worst:.2%}; wrote {out} ({time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
