"""Contact geometry for the actual pose: the vehicle's contact table over the lateral position
and the relative roll of wheel against rail, against the exact geometry; speed against
accuracy; continuity through branch changes; what the yaw does.

Run:  .venv/bin/python validation/contact_pose_table.py
Writes validation/figures/contact_pose_table.png and prints the figures quoted in
docs/vehicle.md.

Models compared (S1002 on UIC60 1:40, left wheel; the right wheel is the mirror):
  before  the zero-roll table read at the wheelset's lateral shift y, roll entering as the
          vertical lift l roll only (the look-up before issue 13: the wheel's lowest point
          does not move sideways with the roll, the profile does not tilt);
  1st     the zero-roll table read at u = y + r_nom roll with the point rotated about the
          centre to first order (the BEM path's geometry: the gap field itself is tilted);
  2-D     the table over (u, roll) read by the time loop's look-up (vehicle_contact%pose_at)
          with roll steps 5, 2.5 and 1.25 mrad (the default).
Reference: the exact gap of the rolled wheel (table.rolled_gap) minimised over the wheel
samples of each slot, and, independently, the 3-D contact search of railvti.geometry
(contact_points: the wheelset's roll from the constraint that both wheels touch).
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from railvti.vehicle import systems  # noqa: E402
from railvti.geometry import contact_points, layout  # noqa: E402
from railvti.vehicle.table import pose_values, rolled_gap, wheel_table  # noqa: E402

OUT = Path(__file__).with_name("figures") / "contact_pose_table.png"


def exact(lay, split: float, u: np.ndarray, roll: np.ndarray):
    """Exact lowest point of the tread-side slot: gap, contact angle and rolling radius."""
    g = np.empty(u.size)
    d = np.empty(u.size)
    r = np.empty(u.size)
    rail, wheel = lay.rail, lay.wheel
    for i, (ui, pi) in enumerate(zip(u, roll)):
        y = ui - lay.wheelset.wheel_radius * pi
        gap, ay, _ = rolled_gap(lay, np.array([y]), float(pi))
        m = lay.ws > split
        k = int(np.argmin(gap[0, m]))
        s = lay.ws[m][k]
        g[i] = gap[0, m][k]
        yr = np.clip(y + ay[m][k] - lay.rail_offset, rail.y_min, rail.y_max)
        d[i] = -np.arctan(rail.slope(yr))
        r[i] = lay.wheelset.wheel_radius + wheel.height(s)
    return g, d, r


def model_before(t0, u, roll):
    """Zero-roll table at y = u - r_nom roll, gap + l roll (the look-up before issue 13)."""
    y = u - t0.r_nominal * roll
    v = pose_values(t0, y, np.zeros_like(y))
    return v[0, 0] + v[1, 0] * roll, v[2, 0], v[3, 0]


def model_first(t0, u, roll):
    """Zero-roll table at u, the point rotated about the centre to first order."""
    v = pose_values(t0, u, roll)  # nr = 1: the look-up's first-order roll
    return v[0, 0], v[2, 0], v[3, 0]


def main() -> None:
    w, r = systems.profiles()
    lay = layout(w, r)
    rng = np.random.default_rng(1)
    n = 400
    u = rng.uniform(-0.005, 0.005, n)  # tread region (flange from ~6.5 mm)
    roll = rng.uniform(-0.012, 0.012, n)
    t0 = time.perf_counter()
    ge, de, re = exact(lay, -0.022, u, roll)
    t_exact = (time.perf_counter() - t0) / n
    keep = np.isfinite(ge)
    rows = []
    t_single = wheel_table(w, r, roll_max=0.0)
    tables = {"before (y only)": None, "1st order": t_single}
    for step in (0.005, 0.0025, 0.00125):
        tables[f"2-D, {step * 1e3:g} mrad"] = None if step is None else step
    print(
        f"{'model':22s} {'gap um (95%/max)':>20s} {'delta mrad (95%/max)':>22s} "
        f"{'r um (95%/max)':>18s} {'build s':>8s} {'MB':>6s} {'look-up us':>11s}"
    )
    for name in tables:
        tb0 = time.perf_counter()
        if name.startswith("before"):
            tab = t_single
            g, d, rr = model_before(tab, u, roll)
        elif name.startswith("1st"):
            tab = t_single
            g, d, rr = model_first(tab, u, roll)
        else:
            tab = wheel_table(w, r, roll_step=tables[name])
            v = pose_values(tab, u, roll)
            g, d, rr = v[0, 0], v[2, 0], v[3, 0]
        tb = time.perf_counter() - tb0
        big = np.repeat(u, 250), np.repeat(roll, 250)
        tl0 = time.perf_counter()
        pose_values(tab, *big)
        tl = (time.perf_counter() - tl0) / big[0].size * 1e6
        ok = keep & (g < 0.5)  # the model has a tread point there
        eg = np.abs(g - ge)[ok] * 1e6
        ed = np.abs(d - de)[ok] * 1e3
        er = np.abs(rr - re)[ok] * 1e6
        mb = tab.data_roll.nbytes / 2**20
        rows.append((name, eg, ed, er, tl, mb))
        small = (np.abs(roll) <= 0.003)[ok]
        if name.startswith("1st"):
            print(
                f"  (1st order with |roll| <= 3 mrad: contact angle {np.percentile(ed[small], 95):.2f} / "
                f"{ed[small].max():.2f} mrad, gap {np.percentile(eg[small], 95):.2f} um)"
            )
        print(
            f"{name:22s} {np.percentile(eg, 95):9.2f} / {eg.max():8.2f} "
            f"{np.percentile(ed, 95):10.2f} / {ed.max():9.2f} {np.percentile(er, 95):8.2f} / "
            f"{er.max():7.2f} {tb:8.2f} {mb:6.1f} {tl:11.3f}"
        )
    print(f"exact search (Python, vectorised over the wheel samples): {t_exact * 1e6:.0f} us per pose")

    # independent 3-D check: the wheelset's own roll from the two-wheel constraint, yaw 0
    ys = np.linspace(-0.006, 0.006, 25)
    tab = wheel_table(w, r)
    dd, dr = [], []
    for y in ys:
        c = contact_points(w, r, float(y))
        pt = min(c.left, key=lambda p: p.separation)
        uu = y + tab.r_nominal * c.pose.roll
        v = pose_values(tab, [uu], [c.pose.roll])[:, :, 0]
        k = int(np.argmin(v[0]))
        dd.append(abs(v[2, k] - pt.contact_angle))
        dr.append(abs(v[3, k] - pt.rolling_radius))
    print(
        f"3-D contact search, |y| <= 6 mm, left wheel at its constraint roll: contact angle "
        f"within {max(dd) * 1e3:.2f} mrad, rolling radius within {max(dr) * 1e6:.1f} um "
        f"(median {np.median(dd) * 1e3:.3f} mrad, {np.median(dr) * 1e6:.2f} um)"
    )

    # yaw: what the table leaves out
    print(
        "yaw (3-D search) at y = 0 / 3 / 6 mm: change of the left wheel's contact angle "
        "(mrad), rolling radius (um) and lead x (mm) against yaw 0"
    )
    for yaw in (0.002, 0.005, 0.010):
        cells = []
        for y in (0.0, 0.003, 0.006):
            a = min(contact_points(w, r, y).left, key=lambda p: p.separation)
            b = min(contact_points(w, r, y, yaw).left, key=lambda p: p.separation)
            cells.append(
                f"{(b.contact_angle - a.contact_angle) * 1e3:+7.3f} "
                f"{(b.rolling_radius - a.rolling_radius) * 1e6:+7.1f} {b.position[0] * 1e3:+6.2f}"
            )
        print(f"  yaw {yaw * 1e3:4.1f} mrad: " + " | ".join(cells))

    # continuity of the Hertz normal force at a fixed approach through branch changes
    uu = np.linspace(-0.001, 0.0075, 8501)
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.6))
    for name, _eg, ed, _er, tl, _mb in rows:
        ax[0].scatter(tl, np.percentile(ed, 95), s=40, label=name)
    ax[0].set_xscale("log")
    ax[0].set_yscale("log")
    ax[0].set_xlabel("look-up time per pose (Fortran), us")
    ax[0].set_ylabel("95th percentile contact-angle error, mrad")
    ax[0].set_title(
        "Tread contact for |y| <= 5 mm, |roll| <= 12 mrad\nagainst the exact rolled-wheel geometry"
    )
    ax[0].axvline(t_exact * 1e6, color="grey", ls=":")
    ax[0].text(t_exact * 1e6, ax[0].get_ylim()[1], " exact search\n (Python)", va="top", fontsize=8)
    ax[0].grid(True, which="both", alpha=0.3)
    ax[0].legend(fontsize=8)
    for phi in (0.0, 0.003, -0.003):
        vals, wt, _ = pose_values(tab, uu, np.full(uu.size, phi), members=True)
        d0 = 8e-5  # the wheel 0.08 mm below its first touch
        fn = np.zeros(uu.size)
        live = np.where(wt > 0, vals[0], np.inf)
        g_low = live.min(axis=(0, 1))
        for k in range(2):
            for m in range(2):
                dn = (d0 + g_low - vals[0, m, k]) * np.cos(vals[2, m, k])
                fn += wt[m, k] * vals[6, m, k] * np.clip(dn, 0, None) ** 1.5 * (vals[0, m, k] < 0.5)
        ax[1].plot(uu * 1e3, fn / 1e3, lw=1, label=f"roll {phi * 1e3:+.0f} mrad")
    ax[1].set_xlabel("u = y + r_nom roll, mm")
    ax[1].set_ylabel("Hertz normal force, kN")
    ax[1].set_title(
        "Left wheel 0.08 mm below its first touch (fixed approach):\n"
        "continuous through the branch changes (0.2 mm, 6.6 mm)"
    )
    ax[1].grid(True, alpha=0.3)
    ax[1].legend(fontsize=8)
    fig.suptitle(
        "S1002 on UIC60 1:40: the vehicle's contact table over lateral position and relative roll",
        fontsize=11,
    )
    fig.tight_layout()
    OUT.parent.mkdir(exist_ok=True)
    fig.savefig(OUT, dpi=120)
    jumps = np.abs(np.diff(fn))
    print(
        f"Hertz force at fixed approach, roll -3 mrad, 1 um steps in u: largest step "
        f"{jumps.max():.0f} N (median {np.median(jumps):.1f} N)"
    )
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
