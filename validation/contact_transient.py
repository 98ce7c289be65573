"""Transient and shift contact (issue 35, deliver 1) against theory and the steady solver.

1. Cattaneo-Mindlin: a Hertz sphere pressed by Fn, then shifted by Fx = 7/8 mu Fn, in one
   step and in 8 increments: the stick radius against c = a (1 - Fx/(mu Fn))^(1/3) and the
   shift against Johnson (1985), eq. 7.42 for two bodies of one material,
   delta = 3 mu Fn (2 - nu) / (8 G a) [1 - (1 - Fx/(mu Fn))^(2/3)], on three grids.
2. Rolling from rest at constant creepage on a Hertz patch: the force approaches the steady
   solver's on the same grid; the distance to 99 %.
3. Rolling from rest on a strip long in y under Hertz's 2-D pressure: the steady state against
   Carter (1926) at the strip's centre line.
4. A normal load Fn0 (1 + 0.1 sin(2 pi f t)) at 200 km/h on a wheel-rail Hertz patch
   (Fn0 = 80 kN): the transient Fx against the quasi-steady one (the steady solver at each
   instant), for f = 92.6 Hz (sleeper passing, wavelength 0.60 m) up to 2500 Hz.
5. A step of +10 % in that normal load: the distance over which Fx follows.
Each case prints the time per step beside one steady solve on the same grid.

Run: PYTHONPATH=_site python validation/contact_transient.py [--quick]
Writes validation/figures/contact_transient_{cattaneo,rolling,load}.png.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import numpy as np

from railvti.contact import Grid, hertz, hertz_gap, solve_rolling, solve_tangential
from railvti.contact.transient import shift_problem, solve_transient, transient_rolling
from railvti.material import STEEL

HERE = Path(__file__).resolve().parent
FIG = HERE / "figures"
MU = 0.3
A_SPHERE = 10.0  # 1/m: two spheres of radius 0.1 m, or a sphere of 0.05 m on a plane
FN_SPHERE = 10e3


def cattaneo(grids: tuple[int, ...]):
    """Stick radius and shift against Cattaneo-Mindlin on grids of n elements per semi-axis."""
    h = hertz(A_SPHERE, A_SPHERE, FN_SPHERE, STEEL)
    q = 7.0 / 8.0 * MU * FN_SPHERE
    c_th = h.a * (1 - 7 / 8) ** (1 / 3)
    d_th = (
        3
        * MU
        * FN_SPHERE
        * (2 - STEEL.poisson)
        / (8 * STEEL.shear_modulus * h.a)
        * (1 - (1 - 7 / 8) ** (2 / 3))
    )
    print("\n1. Cattaneo-Mindlin, Fx = 7/8 mu Fn (Johnson 1985, sect. 7.2)")
    print(f"   a = {h.a * 1e3:.4f} mm, c theory {c_th / h.a:.4f} a, shift theory {d_th * 1e6:.4f} um")
    print("   n/a  steps  c/a     err c %  shift um  err %   time s  (steady solve on the grid, s)")
    last = None
    for n in grids:
        g = Grid.covering(h.a, h.a, n, 1.15)
        gap = hertz_gap(g, A_SPHERE, A_SPHERE)
        for steps in (1, 8):
            t0 = time.perf_counter()
            r = shift_problem(gap, g, STEEL, MU, FN_SPHERE, (q, 0.0), steps=steps)
            el = time.perf_counter() - t0
            t0 = time.perf_counter()
            solve_rolling(gap, g, STEEL, MU, FN_SPHERE, (0.0005, 0, 0), 30.0)
            st = time.perf_counter() - t0
            c = math.sqrt(r.last.adhesion.sum() * g.element_area / math.pi)
            d = -r.shift_total[-1, 0]
            print(
                f"   {n:3d}  {steps:5d}  {c / h.a:.4f}  {100 * (c / c_th - 1):+6.2f}  {d * 1e6:8.4f}  "
                f"{100 * (d / d_th - 1):+6.3f}  {el:6.2f}  ({st:.3f})"
            )
            if steps == 1:
                last = (g, r, h)
    g, r, h = last
    x, y = g.mesh()
    j = g.ny // 2
    xs = np.linspace(-h.a, h.a, 401)
    cm = np.sqrt(np.clip(1 - (xs / h.a) ** 2, 0, None)) - (c_th / h.a) * np.sqrt(
        np.clip(1 - (xs / c_th) ** 2, 0, None)
    )
    return x[:, j], r.last.tx[:, j] / (MU * h.p0), r.last.status[:, j], xs, cm, h.a


def rolling_hertz(n: int):
    """Rolling from rest on a Hertz patch against the steady solver on the same grid."""
    h = hertz(A_SPHERE, A_SPHERE, FN_SPHERE, STEEL)
    g = Grid.covering(h.a, h.a, n, 1.2)
    g = Grid(g.nx + 4, g.ny, g.dx, g.dy, g.x0, g.y0)
    gap = hertz_gap(g, A_SPHERE, A_SPHERE)
    print("\n2. Rolling from rest on a Hertz patch (circle), theta = 1/3, against the steady solver")
    print("   creepage xi  Fx transient N  Fx steady N   rel.diff   99 % after (2a)   ms/step  ms/steady")
    out = []
    for xi in (-0.0005, -0.001, -0.002, -0.004):
        t0 = time.perf_counter()
        r = transient_rolling(g, STEEL, MU, FN_SPHERE, (xi, 0, 0), 30.0, 16 * h.a, gap=gap)
        el = (time.perf_counter() - t0) / r.fx.size
        t0 = time.perf_counter()
        s = solve_rolling(gap, g, STEEL, MU, FN_SPHERE, (xi, 0, 0), 30.0)
        st = time.perf_counter() - t0
        d99 = r.distance_to_fraction(0.99, s.fx)
        print(
            f"   {xi:+.4f}     {r.fx[-1]:12.3f}  {s.fx:11.3f}  {r.fx[-1] / s.fx - 1:+.2e}   {d99 / (2 * h.a):6.2f}"
            f"        {el * 1e3:6.2f}   {st * 1e3:6.2f}"
        )
        out.append((xi, r.distance / (2 * h.a), r.fx / s.fx, d99 / (2 * h.a)))
    return out


def carter_strip(n: int, lengths: float):
    """Rolling from rest on a strip 10 a long in y under Hertz's 2-D pressure, Carter at the centre line."""
    a, p0, nu, G = 5e-3, 800e6, STEEL.poisson, STEEL.shear_modulus
    ny, ly = 40, 10.0
    dx, dy = a / n, ly * a / ny
    nx = 2 * int(np.ceil(1.06 * n)) + 6
    g = Grid(nx, ny, dx, dy, -(int(np.ceil(1.06 * n)) + 1) * dx, None)
    x, _ = g.mesh()
    p = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    p[:, 0] = p[:, -1] = 0.0
    xi_sat = 2 * MU * p0 * (1 - nu) / G  # mu a / R with p0 = a E* / (2 R)
    kappa = 0.5
    xi = -kappa * xi_sat
    carter = 1 - (1 - kappa) ** 2
    jm = ny // 2
    q = p[:, jm].sum() * dx
    t0 = time.perf_counter()
    s = solve_tangential(p, g, STEEL, MU, (xi, 0, 0), 30.0)
    st = time.perf_counter() - t0
    t0 = time.perf_counter()
    r = transient_rolling(
        g, STEEL, MU, float(p.sum() * g.element_area), (xi, 0, 0), 30.0, lengths * 2 * a, pressure=p
    )
    el = time.perf_counter() - t0
    f_tr = r.last.tx[:, jm].sum() * dx / (MU * q)
    f_st = s.tx[:, jm].sum() * dx / (MU * q)
    d99 = r.distance_to_fraction(0.99, s.fx) / (2 * a)
    print(
        f"\n3. Strip {ly:g} a long in y, {2 * n} elements across 2a, kappa = {kappa}: Carter (1926) at the centre line"
    )
    print(
        f"   |Fx|/(mu Fn) Carter {carter:.4f}; steady solver {f_st:.4f} ({100 * (f_st / carter - 1):+.2f} %); "
        f"transient after {lengths:g} contact lengths {f_tr:.4f} ({100 * (f_tr / carter - 1):+.2f} %)"
    )
    print(
        f"   whole strip: transient / steady {r.fx[-1] / s.fx - 1:+.2e}; 99 % of the steady force after {d99:.2f} "
        f"contact lengths; {r.fx.size} steps in {el:.1f} s ({el / r.fx.size * 1e3:.1f} ms/step; steady solve "
        f"{st * 1e3:.1f} ms)"
    )
    xs = np.linspace(-a, a, 801)
    a1 = a * (1 - kappa)
    ct = np.sqrt(np.clip(1 - (xs / a) ** 2, 0, None)) - (a1 / a) * np.sqrt(
        np.clip(1 - ((xs - (a - a1)) / a1) ** 2, 0, None)
    )
    return x[:, jm] / a, r.last.tx[:, jm] / (MU * p0), xs / a, ct, r.distance / (2 * a), r.fx / s.fx


def load_history(n: int, freqs: tuple[float, ...]):
    """Fn0 (1 + 0.1 sin(2 pi f t)) at 200 km/h: transient against quasi-steady Fx."""
    A, B, fn0, V = 1.087, 1.6667, 80e3, 200 / 3.6
    h = hertz(A, B, fn0, STEEL)
    dx = h.a / n
    g = Grid(2 * int(1.3 * n) + 6, 2 * int(1.3 * n * h.b / h.a) + 4, dx, dx, -int(1.3 * n) * dx, None)
    gap = hertz_gap(g, A, B)
    creep = (-0.001, 0.0, 0.0)
    t_start = 8 * 2 * h.a / V
    print(
        f"\n4. Normal load Fn0 (1 + 0.1 sin(2 pi f t)) at 200 km/h, Fn0 = 80 kN, 2a = {2e3 * h.a:.2f} mm, xi = -0.001"
    )
    print(
        "   f Hz    V/f m   V/(f 2a)  |Fx| amplitude tr/qs  max|Fx - Fx_qs| / amplitude  / mean  ms/step  ms/steady"
    )
    curves = []
    for f in freqs:
        lam = V / f
        # 2.25 periods after the start; compared over the last two (and after one contact length)
        steps = int(round((8 * 2 * h.a + 2.25 * lam + 2 * h.a) / dx))
        dt = dx / V
        t = dt * np.arange(1, steps + 1)
        fn = fn0 * (1 + 0.1 * np.sin(2 * np.pi * f * np.maximum(t - t_start, 0.0)))
        t0 = time.perf_counter()
        r = solve_transient(g, STEEL, MU, fn, steps, dt, gap=gap, speed=V, creepage=creep, theta=1 / 3)
        el = (time.perf_counter() - t0) / steps
        sel = np.nonzero(t > t_start + max(2 * h.a / V, 0.25 / f))[0]
        sel = sel[:: max(1, sel.size // 150)]
        t0 = time.perf_counter()
        qs = np.array([solve_rolling(gap, g, STEEL, MU, fn[i], creep, V).fx for i in sel])
        st = (time.perf_counter() - t0) / sel.size
        amp_q = (qs.max() - qs.min()) / 2
        amp_t = (r.fx[sel].max() - r.fx[sel].min()) / 2
        diff = np.abs(r.fx[sel] - qs).max()
        print(
            f"   {f:7.1f}  {lam:6.3f}  {lam / (2 * h.a):7.2f}   {amp_t / amp_q:8.3f}            {diff / amp_q:8.3f}"
            f"               {diff / abs(qs.mean()):.4f}  {el * 1e3:6.2f}  {st * 1e3:6.2f}"
        )
        curves.append((f, lam / (2 * h.a), t[sel] - t_start, r.fx[sel], qs))
    return curves


def load_step(n: int):
    """A step of +10 % in the normal load at 200 km/h: how far the creep force lags."""
    A, B, fn0, V = 1.087, 1.6667, 80e3, 200 / 3.6
    h = hertz(A, B, fn0, STEEL)
    dx = h.a / n
    g = Grid(2 * int(1.3 * n) + 6, 2 * int(1.4 * n * h.b / h.a) + 4, dx, dx, -int(1.3 * n) * dx, None)
    gap = hertz_gap(g, A, B)
    creep = (-0.001, 0.0, 0.0)
    n0 = int(round(8 * 2 * h.a / dx))
    steps = n0 + int(round(6 * 2 * h.a / dx))
    fn = np.where(np.arange(steps) < n0, fn0, 1.1 * fn0)
    r = solve_transient(g, STEEL, MU, fn, steps, dx / V, gap=gap, speed=V, creepage=creep, theta=1 / 3)
    s0 = solve_rolling(gap, g, STEEL, MU, fn0, creep, V).fx
    s1 = solve_rolling(gap, g, STEEL, MU, 1.1 * fn0, creep, V).fx
    after = (r.fx[n0:] - s0) / (s1 - s0)
    d = (np.arange(after.size) + 1) * dx / (2 * h.a)
    reach = [float(d[np.nonzero(np.abs(after - 1) <= tol)[0][0]]) for tol in (0.1, 0.01)]
    print(
        f"\n5. Normal load step +10 % at 200 km/h (Fn0 = 80 kN, xi = -0.001): the change of Fx reaches 90 % of "
        f"the quasi-steady change after {reach[0]:.2f} and 99 % after {reach[1]:.2f} contact lengths "
        f"(quasi-steady: at once); Fx before {r.fx[n0 - 1]:.1f} N (steady {s0:.1f}), end {r.fx[-1]:.1f} N (steady {s1:.1f})"
    )


def plots(cm, roll, strip, load) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    FIG.mkdir(exist_ok=True)
    x, tx, st, xs, th, a = cm
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.plot(xs / a, th, "k-", label="Cattaneo-Mindlin (Johnson 1985, 7.2)")
    ax.plot(x[st > 0] / a, tx[st > 0], "o", ms=4, label="BEM shift, adhesion/slip elements")
    ax.set_xlabel("x / a (y = 0)")
    ax.set_ylabel("tx / (mu p0)")
    ax.set_title("Sphere shifted by Fx = 7/8 mu Fn: traction along x")
    ax.legend()
    fig.tight_layout()
    fig.savefig(FIG / "contact_transient_cattaneo.png", dpi=110)
    plt.close(fig)

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for xi, d, ratio, d99 in roll:
        ax1.plot(d, ratio, label=f"xi = {xi:g} (99 % at {d99:.2f})")
    ax1.axhline(0.99, color="grey", lw=0.6, ls=":")
    ax1.set_xlabel("distance rolled / contact length 2a")
    ax1.set_ylabel("Fx / Fx steady (same grid)")
    ax1.set_title("Hertz patch, rolling from rest")
    ax1.legend(fontsize=8)
    xb, tb, xc, ct, ds, rs = strip
    ax2.plot(xc, ct, "k-", label="Carter (1926)")
    ax2.plot(xb, tb, "o", ms=3, label="transient BEM, steady state")
    ax2.set_xlabel("x / a (rolling direction; leading edge at +1)")
    ax2.set_ylabel("tx / (mu p0) at the centre line")
    ax2.set_title("Strip long in y, kappa = 0.5")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "contact_transient_rolling.png", dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, len(load), figsize=(4.2 * len(load), 3.8), squeeze=False)
    for ax, (f, ratio, t, fx, qs) in zip(axes[0], load):
        ax.plot(t * 1e3, fx / 1e3, label="transient")
        ax.plot(t * 1e3, qs / 1e3, "--", label="quasi-steady (steady solver per step)")
        ax.set_xlabel("time after the load starts (ms)")
        ax.set_ylabel("Fx (kN)")
        ax.set_title(f"{f:g} Hz, V/f = {ratio:.1f} x 2a", fontsize=10)
        ax.legend(fontsize=8)
    fig.suptitle("Fn0 (1 + 0.1 sin 2 pi f t) at 200 km/h, xi = -0.001")
    fig.tight_layout()
    fig.savefig(FIG / "contact_transient_load.png", dpi=110)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    print(f"load average {os.getloadavg()}")
    cm = cattaneo((10, 20) if args.quick else (10, 20, 40))
    roll = rolling_hertz(8 if args.quick else 12)
    strip = carter_strip(25 if args.quick else 50, 6.0 if args.quick else 8.0)
    load = load_history(8, (92.6, 1000.0) if args.quick else (92.6, 300.0, 1000.0, 2500.0))
    load_step(8)
    plots(cm, roll, strip, load)
    print(f"\nfigures in {FIG}; load average {os.getloadavg()}")


if __name__ == "__main__":
    main()
