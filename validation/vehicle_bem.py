"""BEM contact in the time simulation: centred running at 200 km/h with contact='bem'.

Prints Q per wheel against the static load, the lateral forces, and the leading wheelset's
right contact patch (BEM fields straight from the run: the paper's Figs 11-14) beside the
Hertz + FASTSIM patch of the same state; writes validation/figures/vehicle_patch_bem.png.

    .venv/bin/python validation/vehicle_bem.py             # centred running, patch chart
    .venv/bin/python validation/vehicle_bem.py --hunting 1 # + hunting at 300 km/h over 1 s,
                                                           #   BEM vs Hertz models (~2 min)
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.vehicle import Coach, build_coach, static_equilibrium
from railvti.vehicle.plots import plot_patch

FIG = Path(__file__).resolve().parent / "figures"


def main() -> None:
    t0 = time.perf_counter()
    c = scenarios.centred_running(200.0, contact="bem", duration=0.05, progress=False)
    wall = time.perf_counter() - t0
    f = scenarios.centred_running(200.0, contact="hertz-fastsim", duration=0.05, progress=False)
    print(f"centred running 200 km/h, contact='bem' (0.05 s, wall {wall:.1f} s incl. static solve)")
    print(f"  max |Q/Q0 - 1| = {c.q_error:.2e} (Q0 = {c.static_wheel_load:.1f} N)")
    print(
        f"  Y left/right, leading wheelset: {c.Y[0, 0]:.1f} / {c.Y[1, 0]:.1f} N "
        f"(Hertz+FASTSIM {f.Y[0, 0]:.1f} / {f.Y[1, 0]:.1f} N); net per axle "
        f"{np.abs(c.Y.sum(axis=0)).max():.2e} N"
    )
    fx = c.run.wheel_output("Fx")[-1]
    r0 = scenarios.wheel_table().r0
    jb = [c.run.dof_names.index(f"ws{i}_beta") for i in (1, 2, 3, 4)]
    print(
        "  free rolling (wheelset spin DOF beta): Fx left/right per wheelset "
        + ", ".join(f"{fx[0, w]:+.2f}/{fx[1, w]:+.2f}" for w in range(4))
        + " N; "
        f"max |sum r Fx| {np.abs(fx.sum(axis=0) * r0).max():.2e} N m; spin rate "
        f"{c.run.v[-1, jb[0]]:+.4f} rad/s (xi = {-c.run.v[-1, jb[0]] * r0 / c.run.speed:+.2e})"
    )
    s4 = build_coach(Coach(), scenarios.wheel_table(), wheelset_dofs=4)
    _, w4 = static_equilibrium(s4, 200 / 3.6, "bem")
    print(
        f"  the same with the rolling speed imposed (4-DOF wheelsets): Fx left/right "
        f"{w4[2, 0, 0]:+.1f}/{w4[2, 1, 0]:+.1f} N on the leading wheelset"
    )
    pb, pf = c.patch, f.patch
    print(f"{'leading ws, right wheel':>26s} {'BEM':>10s} {'Hertz+FASTSIM':>14s}")
    for name, vb, vf, scale, unit in (
        ("normal force", pb.fn, c.run.wheel_output("N_tread")[-1, 1, 0], 1e3, "kN"),
        ("p max", pb.pressure.max(), pf.pressure.max(), 1e6, "MPa"),
        ("half length a", pb.a, pf.a, 1e-3, "mm"),
        ("half width b", pb.b, pf.b, 1e-3, "mm"),
        ("Fx", pb.fx, pf.fx, 1.0, "N"),
        ("Fy", pb.fy, pf.fy, 1.0, "N"),
        ("friction power", pb.power, pf.power, 1.0, "W"),
    ):
        print(f"{name + ', ' + unit:>26s} {vb / scale:10.2f} {vf / scale:14.2f}")
    st = c.run.stats
    print(
        f"  BEM grid {st['bem_grid'][0]} x {st['bem_grid'][1]} of 0.75 mm, "
        f"{st['bem_solves_per_step']:.1f} solve pairs per step, RTF {st['real_time_factor']:.0f}"
    )
    FIG.mkdir(exist_ok=True)
    k = pb.pressure.sum(axis=0) > 0
    j = np.nonzero(k)[0]
    sl = slice(max(j[0] - 2, 0), j[-1] + 3)
    path = plot_patch(
        pb.x[:, sl],
        pb.y[:, sl],
        pb.pressure[:, sl],
        pb.tx[:, sl],
        pb.ty[:, sl],
        pb.power_density[:, sl],
        FIG / "vehicle_patch_bem.png",
        "BEM 0.75 mm, centred running 200 km/h: leading wheelset, right wheel",
    )
    print(f"wrote {path}")


def hunting_comparison(duration: float) -> None:
    """Leading-wheelset amplitude and frequency over the last half of a run at 300 km/h."""
    print(f"hunting 300 km/h from 4 mm, {duration:g} s: last half of the run")
    for c in ("hertz-kalker", "hertz-fastsim", "bem"):
        r = scenarios.hunting(300.0, contact=c, duration=duration, y0=0.004, progress=False)
        k = r.t >= 0.5 * duration
        y, t = r.y_ws1[k], r.t[k]
        ym = y - y.mean()
        zc = t[1:][(ym[:-1] < 0) & (ym[1:] >= 0)]
        f = (zc.size - 1) / (zc[-1] - zc[0]) if zc.size > 1 else float("nan")
        print(
            f"  {c:>14s}: amplitude {0.5 * np.ptp(y) * 1e3:6.3f} mm, frequency {f:5.2f} Hz, "
            f"RTF {r.stats['real_time_factor']:.3g}"
        )


if __name__ == "__main__":
    main()
    if "--hunting" in sys.argv:
        i = sys.argv.index("--hunting")
        hunting_comparison(float(sys.argv[i + 1]) if len(sys.argv) > i + 1 else 1.0)
