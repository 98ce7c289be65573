"""Manchester Contact Benchmark case A-2.2 (Shackleton & Iwnicki, Vehicle System Dynamics 46,
2008) from its CONTACT decks, inputs/mbench_a22_left.inp and inputs/mbench_a22_right.inp:
S1002 wheels on UIC60 rails inclined 1:40 (the benchmark's profile files), gauge 1435 mm,
flange-back distance 1360 mm, nominal radius 460 mm, 10 kN vertical force per wheel, the
wheelset shifted 0..10 mm to the right with the yaw rising 2.4 mrad/mm, roll and pitch
velocity prescribed per position, mu = 0.3, G = 82 GPa, nu = 0.28, V = 2 m/s, 0.2 mm grid.

Runs every case of both decks as `railvti run` does (the ``wheel_rail`` case type: each patch
at CONTACT's contact reference point, docs/contact_decks.md) and prints
per position and wheel, in railvti's frame (forces on the wheel, y to the left): contact
position on the rail, contact angle, creepages, Fn, Fx, Fy, Mz, pmax, elements in contact
(adhesion/slip). Checks: one patch per wheel; each wheel's vertical force (normal and
tangential forces) against its 10 kN; on the flange, what the normal force alone would
give. Then free rolling at the decks' roll (both wheels): the pitch velocity of zero torque
about the axle against the decks' own (found by CONTACT's author from the same balance).
Writes validation/figures/contact_a22_sweep.png and contact_a22_patches.png (0, 5, 7 mm).

    python validation/contact_a22.py [--dx 0.2] [--no-free]
"""

from __future__ import annotations

import argparse
import logging
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from railvti import Material
from railvti.contact.contact_deck import read_contact_deck
from railvti.contact.wheel_rail_cases import load_profile
from railvti.contact.wheelset import solve_wheelset
from railvti.contact.wheelset_cases import sweep_arrays
from railvti.contact.wheelset_plots import plot_fields, plot_sweep
from railvti.geometry import TrackLayout
from railvti.wheelset.geometry import WheelsetGeometry

ROOT = Path(__file__).resolve().parent.parent
FIG = Path(__file__).parent / "figures"


def _solve(p: dict, side: str | None, free: bool = False):
    wheel = load_profile(p["wheel"], "wheel", bool(p["wheel_mirror_y"]), p["wheel_scale"])
    rail = load_profile(p["rail"], "rail", bool(p["rail_mirror_y"]), p["rail_scale"], p["cant_rad"])
    track = TrackLayout(gauge=p["gauge"], gauge_depth=p["gauge_depth"])
    ws = WheelsetGeometry(
        back_to_back=p["back_to_back"], wheel_radius=p["radius"], contact_offset=p["contact_offset"]
    )
    return solve_wheelset(
        wheel,
        rail,
        p["y"],
        p["yaw"],
        p["fz"],
        p["mu"],
        p["speed"],
        Material(shear_modulus=p["shear_modulus"], poisson=p["poisson"]),
        p["dx"],
        dy=p["dy"],
        roll=p["roll"],
        omega=None if free else p["omega"],
        side=side,
        track=track,
        wheelset=ws,
        reference=p["reference"],
    )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--dx", type=float, default=None, help="element size, mm (default: the decks' DX, DS)")
    ap.add_argument("--no-free", action="store_true", help="skip the free-rolling comparison")
    args = ap.parse_args()
    logging.disable(logging.WARNING)
    decks = {
        s: [c.params for c in read_contact_deck(ROOT / "inputs" / f"mbench_a22_{s}.inp")]
        for s in ("left", "right")
    }
    if args.dx:
        for cases in decks.values():
            for p in cases:
                p.update(dx=args.dx * 1e-3, dy=args.dx * 1e-3)
    n = len(decks["left"])
    y_mm = -np.array([p["y"] for p in decks["left"]]) * 1e3  # the benchmark's y: to the right
    sols, times = {}, np.zeros(n)
    for side, cases in decks.items():
        sols[side] = []
        for i, p in enumerate(cases):
            t0 = time.perf_counter()
            sols[side].append(_solve(p, side))
            times[i] += time.perf_counter() - t0
    both = []
    for sl, sr in zip(sols["left"], sols["right"]):  # the two half wheelsets as one solution
        both.append(replace(sl, right=sr.right, fz=(sl.fz[0], sr.fz[1])))
    arr = sweep_arrays(both)
    print(
        f"A-2.2 from the CONTACT decks at {decks['left'][0]['dx'] * 1e3:g} mm: {n} positions, "
        f"{times.mean() * 1e3:.0f} ms per position (both wheels, load control and rolling)"
    )
    print(
        f"{'y mm':>5s} {'wheel':5s} {'y_rail mm':>9s} {'angle':>6s} {'xi':>9s} {'eta':>9s} {'phi 1/m':>8s} "
        f"{'Fn kN':>7s} {'Fx kN':>7s} {'Fy kN':>7s} {'Mz Nm':>7s} {'pmax MPa':>8s} {'elements (adh/slip)':>20s}"
    )
    worst, patches_per_wheel, flange = 0.0, set(), []
    for i in range(n):
        for side in ("left", "right"):
            s = sols[side][i]
            w = ("left", "right").index(side)
            worst = max(worst, abs(s.fz[w] / 1e4 - 1))
            patches_per_wheel.add(len(s.wheel(side)))
            for p in s.wheel(side):
                c = p.creepage
                regions = f" {p.n_regions} areas" if p.n_regions > 1 else ""
                print(
                    f"{y_mm[i]:5.1f} {side:5s} {p.contact.y_rail * 1e3:9.2f} {p.contact_angle:6.3f} {c.xi:9.2e} "
                    f"{c.eta:9.2e} {c.phi:8.3f} {p.fn / 1e3:7.2f} {p.fx / 1e3:7.3f} {p.fy / 1e3:7.3f} "
                    f"{p.mz:7.2f} {p.pmax / 1e6:8.0f} {p.n_contact:8d} ({p.n_adhesion}/{p.n_slip}){regions}"
                )
                if p.contact_angle > 1.0:
                    flange.append((y_mm[i], p.fn * np.cos(p.contact_angle) / 1e4 - 1))
    print(f"patches per wheel: {sorted(patches_per_wheel)}")
    print(f"vertical balance with tangential forces: largest |Fz/10 kN - 1| = {worst:.2e}")
    if flange:
        dev = np.array([d for _, d in flange])
        print(
            f"flange (contact angle > 1 rad) from y = {min(y for y, _ in flange):.1f} mm: the normal force "
            f"alone carries {dev.min() * 100:+.0f} .. {dev.max() * 100:+.0f} % of the load"
        )
    if not args.no_free:
        print(
            f"{'y mm':>5s} {'omega deck':>11s} {'omega free':>11s} {'rel. diff':>9s} {'torque at deck omega':>21s}"
        )
        diffs = []
        for i in range(n):
            p = dict(decks["left"][i])
            free = _solve(p, None, free=True)
            prescribed = _solve(p, None)
            diffs.append(free.omega / p["omega"] - 1)
            print(
                f"{y_mm[i]:5.1f} {p['omega']:11.7f} {free.omega:11.7f} {diffs[-1]:+9.1e} "
                f"{prescribed.axle_torque:17.2f} N m"
            )
        print(
            f"free rolling against the decks' pitch velocity: largest |rel. diff| {np.max(np.abs(diffs)):.1e}"
        )
    FIG.mkdir(exist_ok=True)
    plot_sweep(
        y_mm * 1e-3,
        arr,
        FIG / "contact_a22_sweep.png",
        xlabel="wheelset shift to the right (the benchmark's y), mm",
        title="Manchester benchmark A-2.2: loaded wheelset, BEM at the decks' kinematics\n"
        "(S1002 / UIC60 1:40, 10 kN per wheel, mu 0.3, 0.2 mm elements)",
    )
    fields = {}
    for y_show in (0.0, 5.0, 7.0):
        i = int(np.argmin(np.abs(y_mm - y_show)))
        for side in ("left", "right"):
            for k, p in enumerate(sols[side][i].wheel(side)):
                fields[f"y = {y_show:g} mm, {side} wheel, patch {k + 1}"] = dict(
                    pressure=p.pressure, x=p.grid.x, y=p.grid.y, tx=p.tx, ty=p.ty
                )
    plot_fields(
        fields,
        FIG / "contact_a22_patches.png",
        title="Manchester benchmark A-2.2: pressure and tractions (BEM)",
    )
    print(f"wrote {FIG / 'contact_a22_sweep.png'} and {FIG / 'contact_a22_patches.png'}")


if __name__ == "__main__":
    main()
