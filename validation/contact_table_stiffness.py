"""Vertical stiffness of the table contact against the BEM through the branch changes.

The time loop's table contact (railvti.vehicle.table, Hertz, Kalker and FASTSIM paths) puts
one Hertz point at each slot's lowest local minimum of the gap; the wheel's vertical
interference under a vertical load Fz is P = (Fz / kv)^(2/3) with kv = kH cos(delta)^2.5 of
that point. Where the point jumps to another minimum (S1002 / UIC60 1:40 near y = 0.2 mm),
kH and delta jump with it. The half-space BEM (railvti.contact.solve_wheelset: normal
contact, one half wheelset at zero roll, the same profiles) resolves the whole patch and
is the independent reference here: its sink under the same load is what a rigid wheel
really moves.

A third curve is the strip contact (railvti.vehicle.strip, ``geometry='strip'`` in the time
loop, Fortran vehicle_strip): a semi-Hertzian strip potential over the whole rigid
interpenetration of wheel and rail, V = sum_j c_j cos(delta_j) w_j P_j^2 over the wheel
profile's samples (P_j the sample's vertical interference, w_j its lateral width), with
c = 3/8 kH(1, B/A) sqrt(B/A) from the local curvatures, so that a parabolic gap gives Hertz's
N = kH d^1.5 exactly; the vertical force is -dV/dz. It needs no contact points, branches or
jumps.

Prints P from all three over y and the largest jumps; writes
validation/figures/contact_table_stiffness.png.

Run: python validation/contact_table_stiffness.py [step_mm]   (default 0.05 mm, ~1 min)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from railvti.vehicle import systems
from railvti.contact.wheelset import solve_wheelset
from railvti.errors import GridTooSmallError
from railvti.material import STEEL
from railvti.vehicle.params import Coach
from railvti.vehicle.strip import STRIP_OUTPUTS, strip_geometry, strip_wheel
from railvti.vehicle.table import wheel_table

FIG = Path(__file__).resolve().parent / "figures" / "contact_table_stiffness.png"


def strip_interference(wheel, rail, ys: np.ndarray, fz: float) -> np.ndarray:
    """Vertical interference (m, from first touch) of the left wheel under the vertical load
    fz at each lateral shift ys (zero roll) from the strip contact (module docstring)."""
    geo = strip_geometry(wheel, rail)
    dz, pmax = STRIP_OUTPUTS.index("dV_dz"), STRIP_OUTPUTS.index("P_max")
    lo, hi = np.full(ys.size, -0.02), np.full(ys.size, 0.02)
    for _ in range(55):  # bisection on the centre height: the load falls as it rises
        zc = 0.5 * (lo + hi)
        out, _ = strip_wheel(geo, ys, zc, np.zeros(ys.size))
        up = -out[:, :, dz].sum(axis=1) > fz
        lo, hi = np.where(up, zc, lo), np.where(up, hi, zc)
    out, _ = strip_wheel(geo, ys, 0.5 * (lo + hi), np.zeros(ys.size))
    return out[:, :, pmax].max(axis=1)


def main() -> None:
    step = float(sys.argv[1]) * 1e-3 if len(sys.argv) > 1 else 0.05e-3
    wheel, rail = systems.profiles()
    fz = Coach().static_wheel_load
    table = wheel_table(wheel, rail, roll_max=0.0)
    ys = np.arange(-3e-3, 7.5e-3 + 1e-12, step)
    p_bem = np.empty(ys.size)
    p_tab = np.empty(ys.size)
    delta = np.empty(ys.size)
    for n, y in enumerate(ys):
        try:
            s = solve_wheelset(
                wheel, rail, float(y), 0.0, fz, None, None, STEEL, 0.5e-3, roll=0.0, side="left"
            )
            p_bem[n] = s.sinks[0]
        except GridTooSmallError as e:  # a conformal patch wider than the grid
            print(f"y = {y * 1e3:.3f} mm: BEM left out ({e})")
            p_bem[n] = np.nan
        # the table's lowest point at the node (the look-up never blends across a jump)
        i = int(np.argmin(np.abs(table.y - y)))
        g = table.data[0, :, i]
        k = int(np.argmin(g))
        delta[n] = table.data[2, k, i]
        kv = table.data[6, k, i] * np.cos(delta[n]) ** 2.5
        # the lower of the two slots carries the load; P measured from its first touch
        p_tab[n] = (fz / kv) ** (2.0 / 3.0)
    p_strip = strip_interference(wheel, rail, ys, fz)
    print(f"wheel load {fz / 1e3:.1f} kN, BEM dx = dy = 0.5 mm, step {step * 1e3:.3f} mm")
    print("   y mm   P table um   P BEM um   P strip um   contact angle rad")
    for n in range(0, ys.size, max(1, int(round(0.5e-3 / step)))):
        print(
            f"{ys[n] * 1e3:7.3f} {p_tab[n] * 1e6:11.1f} {p_bem[n] * 1e6:10.1f} "
            f"{p_strip[n] * 1e6:11.1f} {delta[n]:10.4f}"
        )
    ok = np.isfinite(p_bem)
    for name, p in (("table", p_tab), ("strip", p_strip)):
        d = np.abs(p - p_bem)[ok] / p_bem[ok]
        tread = ys[ok] <= 5e-3
        print(
            f"{name} against the BEM: max {d[tread].max() * 100:.1f} % for y <= 5 mm, "
            f"max {d.max() * 100:.1f} % over the table"
        )
    for name, p in (("table", p_tab), ("BEM", p_bem), ("strip", p_strip)):
        j = int(np.nanargmax(np.abs(np.diff(p))))
        print(
            f"largest step of P between neighbouring y, {name}: {np.diff(p)[j] * 1e6:+.1f} um "
            f"at y = {ys[j] * 1e3:.3f} -> {ys[j + 1] * 1e3:.3f} mm"
        )
    _plot(ys, p_tab, p_bem, p_strip, fz)


def _plot(ys: np.ndarray, p_tab: np.ndarray, p_bem: np.ndarray, p_strip: np.ndarray, fz: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axs = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [1.6, 1]})
    for ax, (lo, hi) in zip(axs, ((-3e-3, 5e-3), (ys[0], ys[-1]))):
        m = (ys >= lo - 1e-12) & (ys <= hi + 1e-12)
        ax.plot(ys[m] * 1e3, p_tab[m] * 1e6, label="table: Hertz at the lowest point, (Fz / kv)^(2/3)")
        ax.plot(ys[m] * 1e3, p_bem[m] * 1e6, label="BEM, whole patch (gaps: patch wider than its grid)")
        ax.plot(ys[m] * 1e3, p_strip[m] * 1e6, "--", label="strip contact (geometry='strip': no points)")
        ax.set_xlabel("lateral shift of the wheelset y, mm")
        ax.set_ylabel("vertical interference P under the load, um")
        ax.grid(alpha=0.3)
    axs[0].set_title("tread: the point jumps at y = 0.2 mm")
    axs[1].set_title("whole table: flange contact from y = 6.6 mm")
    axs[0].legend(fontsize=8)
    fig.suptitle(f"Left wheel, S1002 / UIC60 1:40, zero roll, vertical load {fz / 1e3:.1f} kN, frictionless")
    fig.tight_layout()
    FIG.parent.mkdir(exist_ok=True)
    fig.savefig(FIG, dpi=130)
    print(f"wrote {FIG}")


if __name__ == "__main__":
    main()
