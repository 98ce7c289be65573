"""The coach through a curve (issue 34, item 2): R = 1200 m, 150 mm cant, 100 m clothoids,
a 400 m arc, at 160 km/h (cant deficiency 102 mm), variants RR and RF, Hertz + FASTSIM.

Printed: the steady curving table of each variant (per wheel Q, Y, Y/Q, flange contact,
T gamma; per wheelset the angle of attack and sum Y) and the coach's lateral balance
sum Y = M a_unb. Plotted over the reference's position: the coach's sum Y against the
quasi-static M a_unb(s) of the curve (each body's own share at its own position), per
wheelset sum Y, the leading wheelsets' angle of attack and Y/Q of the outer wheels.

Run: .venv/bin/python validation/vehicle_curving.py
Writes validation/figures/vehicle_curving.png.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti._plotting import pyplot
from railvti.track import TrackCurve
from railvti.vehicle.params import Coach

HERE = Path(__file__).resolve().parent
CURVE = TrackCurve(radius=1200.0, cant=0.15, transition_in=100.0, arc_length=400.0, transition_out=100.0)
SPEED_KMH = 160.0


def quasi_static_sum_y(curve: TrackCurve, x: np.ndarray, v: float) -> np.ndarray:
    """The lateral balance each body would need at its own position: sum over the bodies of
    m (V^2 kappa cos theta_x + g sin theta_x) (carbody at x, bogies at +-9.5 m, wheelsets)."""
    p = Coach().params
    xb, a = p["half_bogie_distance"], p["half_wheelbase"]
    bodies = [(p["carbody_mass"], 0.0)]
    bodies += [(p["bogie_mass"], s * xb) for s in (1, -1)]
    bodies += [(p["wheelset_mass"], s * xb + t * a) for s in (1, -1) for t in (1, -1)]
    out = np.zeros_like(x)
    for m, dx in bodies:
        th = curve.roll(x + dx)
        out += m * (v * v * curve.curvature(x + dx) * np.cos(th) + p["gravity"] * np.sin(th))
    return out


def main() -> None:
    plt = pyplot()
    fig, ax = plt.subplots(2, 2, figsize=(13, 8), sharex=True)
    v = SPEED_KMH / 3.6
    for variant, ls in (("RR", "-"), ("RF", "--")):
        t0 = time.perf_counter()
        cr = scenarios.curving(SPEED_KMH, CURVE, variant, progress=False)
        wall = time.perf_counter() - t0
        st = cr.steady()
        print(f"--- {variant} ({wall:.1f} s wall for {cr.run.t[-1]:.1f} s simulated)")
        print(st.table())
        r, x = cr.run, cr.position()
        y = r.wheel_output("Y")
        if r.rail is not None:
            y = y - r.wheel_output("Q") * r.rail[:, 2]
        ax[0, 0].plot(x, y.sum(axis=(1, 2)) / 1e3, ls, label=f"{variant}: sum Y, all wheels")
        for w in range(4):
            ax[0, 1].plot(
                x, y[:, :, w].sum(axis=1) / 1e3, ls, color=f"C{w}", label=f"{variant} wheelset {w + 1}"
            )
        for w in (0, 2):
            ax[1, 0].plot(
                x, r.dof(f"ws{w + 1}_yaw") * 1e3, ls, color=f"C{w}", label=f"{variant} wheelset {w + 1}"
            )
        yq = r.wheel_output("Y")[:, 1] / r.wheel_output("Q")[:, 1]
        for w in (0, 2):
            ax[1, 1].plot(x, yq[:, w], ls, color=f"C{w}", label=f"{variant} wheelset {w + 1}, right (outer)")
    xs = np.linspace(x[0], x[-1], 2000)
    ax[0, 0].plot(xs, quasi_static_sum_y(CURVE, xs, v) / 1e3, "k:", label="quasi-static M a_unb")
    ax[0, 0].set_ylabel("lateral force, kN")
    ax[0, 0].set_title(f"coach's lateral balance, R 1200 m, cant 150 mm, {SPEED_KMH:.0f} km/h")
    ax[0, 1].set_ylabel("sum Y per wheelset, kN")
    ax[0, 1].set_title("track-shifting force per wheelset")
    ax[1, 0].set_ylabel("angle of attack, mrad (+ nose left)")
    ax[1, 0].set_title("leading wheelsets of each bogie")
    ax[1, 1].set_ylabel("Y/Q, outer wheel")
    ax[1, 1].set_title("outer (right) wheels of the leading wheelsets")
    for a in ax.flat:
        a.legend(fontsize=7)
        a.grid(alpha=0.3)
    for a in ax[1]:
        a.set_xlabel("position of the carbody's centre along the track, m (curve from 0 to 600 m)")
    fig.tight_layout()
    out = HERE / "figures" / "vehicle_curving.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
