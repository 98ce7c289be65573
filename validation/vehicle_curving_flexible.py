"""Flexible wheelsets in curves (issue 34, item 2): variants FR and FF against RR and RF on
R = 1200 m, 150 mm cant, 160 km/h (cant deficiency 102 mm), Hertz + FASTSIM, the default mode
sets (FR and FF: k_max 2, f_max 800 Hz).

Printed:
1. steady arc (started in its static equilibrium at x = 500 m, 1 s): the coach's sum Y against
   M (V^2/R - g h/s) (the issue's reference) and M (V^2/R cos phi - g sin phi) (canted plane);
   per wheel Y and Q, per wheelset the angle of attack, for RR, FR, RF, FF (on the ring: Y in
   the vehicle's frame);
2. the stiff limit: FR with Young's modulus x 1e3 (k_max 1, f_max 300 Hz, exact modal step)
   against RR, per wheel;
3. the stiff primary (k_x 1e9 N/m): leading minus trailing wheelset yaw against -2 a / R, the
   journals' elastic x;
4. the mirror: FR in the right-hand curve against the left-hand one;
5. the passage through the curve (100 m clothoids, 400 m arc) of each variant: wall time.
Plotted over the carbody's position (the passage): the coach's sum Y against the quasi-static
M a_unb, the flexible wheelsets' change of the leading wheelset's Y (FR - RR, FF - RF), the leading wheelsets' angle of attack, Y/Q of the outer leading
wheels.

Run: .venv/bin/python validation/vehicle_curving_flexible.py
Writes validation/figures/vehicle_curving_flexible.png.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti._plotting import pyplot
from railvti.track import TrackCurve
from railvti.vehicle.flexible_points import attachment_deflection
from railvti.vehicle.params import Coach
from railvti.vehicle.simulate import simulate
from railvti.vehicle.systems import system_and_layouts, time_step

HERE = Path(__file__).resolve().parent
V = 160 / 3.6
ARC = TrackCurve(radius=1200.0, cant=0.15, transition_in=100.0, arc_length=1000.0, transition_out=100.0)
MIRROR = TrackCurve(radius=-1200.0, cant=0.15, transition_in=100.0, arc_length=1000.0, transition_out=100.0)
PASSAGE = TrackCurve(radius=1200.0, cant=0.15, transition_in=100.0, arc_length=400.0, transition_out=100.0)
SMALL = {"k_max": 1, "f_max": 300.0}
VARIANTS = ("RR", "FR", "RF", "FF")


def _y(r) -> np.ndarray:
    """Y per wheel in the vehicle's frame (on the ring the output is in the rolled rail's)."""
    y = r.wheel_output("Y")
    return y if r.rail is None else y - r.wheel_output("Q") * r.rail[:, 2]


def _arc(sy, curve=ARC, duration=1.0, coach=None, **kw):
    kw.setdefault("h", time_step(sy, None))
    return simulate(
        sy, V, duration, contact="hertz-fastsim", curve=curve, x_start=500.0, output_dt=0.005,
        progress=False, coach=coach, **kw,
    )  # fmt: skip


def steady() -> dict:
    """Part 1: the steady arc of each variant; returns the runs."""
    m = Coach().total_mass
    ref_std = m * (V * V / 1200.0 - 9.81 * 0.15 / 1.5)
    ref_cant = m * ARC.unbalanced_acceleration(V)
    print(
        f"1. steady arc, 1 s: M a_unb = {ref_std / 1e3:.3f} kN (V^2/R - g h/s), {ref_cant / 1e3:.3f} kN (canted)"
    )
    print(
        "| variant | wall, s | sum Y, kN | vs V^2/R - g h/s | vs canted plane | Y per wheel (l1 r1 l2 r2 ...), kN | Q, kN | AoA, mrad |"
    )
    print("|---|---|---|---|---|---|---|---|")
    runs = {}
    for v in VARIANTS:
        sy = scenarios.coach_system(v, speed=V)
        t0 = time.perf_counter()
        r = _arc(sy)
        wall = time.perf_counter() - t0
        y, q = _y(r).mean(axis=0), r.wheel_output("Q").mean(axis=0)
        s = _y(r).sum(axis=(1, 2)).mean()
        aoa = [r.dof(f"ws{w}_yaw").mean() * 1e3 for w in (1, 2, 3, 4)]
        print(
            f"| {v} | {wall:.1f} | {s / 1e3:.3f} | {100 * (s / ref_std - 1):+.2f} % | {100 * (s / ref_cant - 1):+.2f} % "
            f"| {' '.join(f'{x:.2f}' for x in y.T.ravel() / 1e3)} | {' '.join(f'{x:.2f}' for x in q.T.ravel() / 1e3)} "
            f"| {' '.join(f'{x:+.3f}' for x in aoa)} |"
        )
        runs[v] = r
    return runs


def stiff_limit(rr) -> None:
    """Part 2: FR x 1e3 against RR."""
    co = Coach(wheelset_stiffness_scale=1e3)
    sy = scenarios.coach_system("FR", coach=co, speed=V, **SMALL)
    r = _arc(sy, duration=0.1, coach=co, h=1e-3, modal_step="exact")
    ref = _arc(rr, duration=0.1)
    dy = np.abs(r.wheel_output("Y")[-1] - ref.wheel_output("Y")[-1]).max()
    dq = np.abs(r.wheel_output("Q")[-1] - ref.wheel_output("Q")[-1]).max()
    da = max(abs(r.dof(f"ws{w}_yaw")[-1] - ref.dof(f"ws{w}_yaw")[-1]) for w in (1, 2, 3, 4))
    print(f"2. stiff limit (E x 1e3) against RR: max |dY| {dy:.3f} N, |dQ| {dq:.3f} N, |dAoA| {da:.2e} rad")


def stiff_primary() -> None:
    """Part 3: primary stiff in yaw, the chord angle."""
    co = Coach().with_(primary_kx=1e9)
    sy, lays = system_and_layouts("FR", co, V, **SMALL)
    r = _arc(sy, duration=0.05, coach=co, h=1e-3, modal_step="exact")
    d = r.dof("ws1_yaw")[-1] - r.dof("ws2_yaw")[-1]
    ref = -2 * 1.28 / 1200.0
    u = attachment_deflection(sy, lays[0], r.q[-1])
    print(
        f"3. primary k_x 1e9 N/m: yaw ws1 - ws2 = {d * 1e3:.4f} mrad against -2 a / R = {ref * 1e3:.4f} mrad "
        f"({100 * (d / ref - 1):+.2f} %); journals' elastic x {u[8] * 1e3:+.4f}, {u[11] * 1e3:+.4f} mm"
    )


def mirror(fr_left) -> None:
    """Part 4: FR in the right-hand curve."""
    sy = scenarios.coach_system("FR", speed=V)
    right = _arc(sy, MIRROR)
    e_q = np.abs(right.wheel_output("Q") - fr_left.wheel_output("Q")[:, ::-1]).max()
    e_y = np.abs(right.wheel_output("Y") + fr_left.wheel_output("Y")[:, ::-1]).max()
    e_d = max(
        np.abs(right.dof(n) + fr_left.dof(n)).max() for n in ("ws1_y", "ws1_yaw", "carbody_y", "carbody_roll")
    )
    print(f"4. mirror (FR, right-hand curve): Q {e_q:.1e} N, Y {e_y:.1e} N, y/yaw/roll {e_d:.1e} m or rad")


def passage_plot() -> None:
    """Part 5: the passage of each variant, plotted."""
    from vehicle_curving import quasi_static_sum_y  # the script beside this one

    plt = pyplot()
    fig, ax = plt.subplots(2, 2, figsize=(13, 8), sharex=True)
    styles = {"RR": "-", "FR": "--", "RF": "-.", "FF": ":"}
    print("5. passage (100 m clothoids, 400 m arc):")
    runs = {}
    for v, ls in styles.items():
        t0 = time.perf_counter()
        cr = scenarios.curving(160, PASSAGE, v, progress=False)
        wall = time.perf_counter() - t0
        st = cr.steady()
        print(
            f"   {v}: {wall:.1f} s wall for {cr.run.t[-1]:.1f} s simulated; steady sum Y {st.sum_y_coach / 1e3:.3f} kN "
            f"= M a_unb {100 * (st.sum_y_coach / st.mass_times_a - 1):+.2f} %; AoA {np.round(np.asarray(st.angle_of_attack) * 1e3, 3)} mrad"
        )
        r, x = cr.run, cr.position()
        y = _y(r)
        ax[0, 0].plot(x, y.sum(axis=(1, 2)) / 1e3, ls, label=f"{v}: sum Y, all wheels")
        runs[v] = y[:, :, 0]
        for w in (0, 2):
            ax[1, 0].plot(x, r.dof(f"ws{w + 1}_yaw") * 1e3, ls, color=f"C{w}", label=f"{v} wheelset {w + 1}")
        yq = y[:, 1] / r.wheel_output("Q")[:, 1]
        ax[1, 1].plot(x, yq[:, 0], ls, color="C0", label=f"{v} wheelset 1, right (outer)")
    for (flex, rigid), ls in ((("FR", "RR"), "-"), (("FF", "RF"), "--")):
        for k, side in enumerate(("left (inner)", "right (outer)")):
            d = (runs[flex][:, k] - runs[rigid][:, k]) / 1e3
            ax[0, 1].plot(x, d, ls, color=f"C{k}", label=f"{flex} - {rigid}, wheelset 1 {side}")
    xs = np.linspace(x[0], x[-1], 2000)
    ax[0, 0].plot(xs, quasi_static_sum_y(PASSAGE, xs, V) / 1e3, "k", lw=0.8, label="quasi-static M a_unb")
    ax[0, 0].set_ylabel("lateral force, kN")
    ax[0, 0].set_title("coach's lateral balance, R 1200 m, cant 150 mm, 160 km/h")
    ax[0, 1].set_ylabel("difference in Y, kN")
    ax[0, 1].set_title("flexible minus rigid wheelsets: Y of the leading wheelset")
    ax[1, 0].set_ylabel("angle of attack, mrad (+ nose left)")
    ax[1, 0].set_title("leading wheelsets of each bogie")
    ax[1, 1].set_ylabel("Y/Q, outer wheel")
    ax[1, 1].set_title("outer (right) wheel of the leading wheelset")
    for a in ax.flat:
        a.legend(fontsize=7, ncol=2)
        a.grid(alpha=0.3)
    for a in ax[1]:
        a.set_xlabel("position of the carbody's centre along the track, m (curve from 0 to 600 m)")
    fig.suptitle("RR, FR (flexible wheelsets), RF (ring track), FF (both) in the curve")
    fig.tight_layout()
    out = HERE / "figures" / "vehicle_curving_flexible.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


def main() -> None:
    print(f"load {os.getloadavg()[0]:.2f}")
    runs = steady()
    stiff_limit(scenarios.coach_system("RR"))
    stiff_primary()
    mirror(runs["FR"])
    passage_plot()
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
