"""Speed against accuracy: FASTSIM and the BEM steady-rolling solver.

For Hertzian patches with a/b = 0.2, 1 and 5 and four creepage cases (pure xi,
pure eta, pure spin phi, combined), the BEM (``railvti.contact.solve_rolling``)
is run with n = 5 ... 60 elements per semi-axis (dx = a/n, dy = b/n) and
FASTSIM (elliptic, parabolic pressure, nx = ny = n; and strip-wise on the
BEM's own normal pressure). The error is the norm of the creep-force error
``|F - F_ref| / |F_ref|``, F = (Fx, Fy), against the finest BEM solution;
it is charted against the time per case (log-log), and a markdown table
lists where FASTSIM's error exceeds 10%.

Creepages are chosen so that the linear theory would give half of mu Fn
(partial slip, where the methods differ most).

Run: ``.venv/bin/python validation/contact_fastsim_vs_bem.py [--quick]``
(--quick: n up to 30 and the finest BEM at 40, for a smoke test).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from railvti.contact.fastsim import fastsim_forces, fastsim_grid
from railvti.contact.grid import Grid
from railvti.contact.hertz import hertz, hertz_gap
from railvti.contact.kalker import kalker_coefficients
from railvti.errors import RailvtiError
from railvti.material import STEEL

try:
    from railvti.contact import solve_rolling
except ImportError:  # the BEM lives on branch 'rolling' until merged
    solve_rolling = None

FIG = Path(__file__).resolve().parent / "figures"
FN, MU, SPEED = 80e3, 0.3, 20.0
SQRT_AB = 5e-3  # geometric mean of the semi-axes, m
RATIOS = (0.2, 1.0, 5.0)
CASES = ("xi", "eta", "phi", "combined")


def gap_coefficients(ratio: float) -> tuple[float, float, float, float]:
    """Gap coefficients (A, B) giving a Hertz ellipse with a/b = ratio and sqrt(ab) = SQRT_AB."""

    def res(logq: float) -> float:
        h = hertz(1.0, float(np.exp(logq)), FN, STEEL)
        return np.log(h.a / h.b) - np.log(ratio)

    if abs(ratio - 1.0) < 1e-12:
        q = 1.0
    else:
        q = float(np.exp(brentq(res, -12.0, 12.0, xtol=1e-13)))
    h = hertz(1.0, q, FN, STEEL)
    s = (np.sqrt(h.a * h.b) / SQRT_AB) ** 3  # a ~ A^(-1/3)
    h = hertz(s, s * q, FN, STEEL)
    return s, s * q, h.a, h.b


def creepages(case: str, a: float, b: float) -> tuple[float, float, float]:
    """Creepages for which the linear theory gives 0.5 mu Fn (combined: shared)."""
    c11, c22, c23 = kalker_coefficients(a / b, STEEL.poisson)
    g = STEEL.shear_modulus
    target = 0.5 * MU * FN
    xi = target / (g * a * b * c11)
    eta = target / (g * a * b * c22)
    phi = target / (g * (a * b) ** 1.5 * c23)
    return {
        "xi": (xi, 0.0, 0.0),
        "eta": (0.0, eta, 0.0),
        "phi": (0.0, 0.0, phi),
        "combined": (0.5 * xi, 0.5 * eta, 0.3 * phi),
    }[case]


def grid_for(a: float, b: float, n: int) -> Grid:
    # 20 % margin, and at least two free elements upstream of the patch (the
    # rolling solver's upwind difference reaches two elements upstream)
    m = max(int(np.ceil(1.2 * n)), n + 2)
    return Grid(nx=2 * m, ny=2 * m, dx=a / n, dy=b / n)


def timed(fn, min_time: float = 0.05):
    """Result of fn() and its time per call, s (repeated for fast calls)."""
    t0 = time.perf_counter()
    out = fn()
    t = time.perf_counter() - t0
    if t < min_time:
        k = max(1, int(min_time / max(t, 1e-7)))
        t0 = time.perf_counter()
        for _ in range(k):
            fn()
        t = (time.perf_counter() - t0) / k
    return out, t


def fastsim_alone() -> None:
    """FASTSIM against Kalker's linear theory (tiny creepage) and saturation, and
    the traction / slip maps of a combined case (figure contact_fastsim_maps.png)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from railvti.contact.fastsim import fastsim
    from railvti.contact.kalker import linear_creep_forces

    print("FASTSIM in the linear limit (mu = 1e3) against Kalker's linear theory, nu = 0.28")
    print("| a/b | n = nx = ny | Fx/Fx_lin - 1 (xi) | Fy/Fy_lin - 1 (eta) | Fy/Fy_lin - 1 (phi) |")
    print("|---|---|---|---|---|")
    for ratio in (0.2, 0.5, 1.0, 2.0, 5.0):
        a, b = SQRT_AB * np.sqrt(ratio), SQRT_AB / np.sqrt(ratio)
        for n in (10, 20, 50):
            errs = []
            for k, cr in enumerate(((1e-7, 0, 0), (0, 1e-7, 0), (0, 0, 1e-5))):
                fx, fy, _ = fastsim_forces(a, b, FN, STEEL, 1e3, *cr, nx=n, ny=n)
                lin = linear_creep_forces(a, b, STEEL, cr)
                errs.append(fx[()] / lin[0] - 1 if k == 0 else fy[()] / lin[1] - 1)
            print(f"| {ratio:g} | {n} | {errs[0]:+.2e} | {errs[1]:+.2e} | {errs[2]:+.2e} |")
    print("\nSaturation, a/b = 1, n = 50: |F| / (mu Fn) for xi = 0.05, eta = 0.05 and both")
    a = b = SQRT_AB
    for cr in ((0.05, 0, 0), (0, 0.05, 0), (0.03, 0.04, 0)):
        fx, fy, _ = fastsim_forces(a, b, FN, STEEL, MU, *cr, nx=50, ny=50)
        print(f"  creepage {cr}: {np.hypot(fx[()], fy[()]) / (MU * FN):.5f}")

    a, b = 6e-3, 4e-3
    cr = (1e-3, 5e-4, 0.8)
    r = fastsim(a, b, FN, STEEL, MU, cr, nx=30, ny=30, speed=SPEED)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    # i = 0 is the leading edge (largest x): flip so that x increases
    X, Y = 1e3 * r.x[::-1], 1e3 * r.y[::-1]
    tx, ty, slip, dens = r.tx[::-1], r.ty[::-1], r.slip[::-1], r.power_density[::-1]
    tau = np.hypot(tx, ty)
    m0 = axes[0].pcolormesh(X, Y, tau / 1e6, shading="gouraud", cmap="viridis")
    axes[0].quiver(X[::2, ::2], Y[::2, ::2], tx[::2, ::2], ty[::2, ::2], color="w", scale=None, width=0.004)
    fig.colorbar(m0, ax=axes[0], label="|tau|, MPa")
    axes[0].set_title("traction")
    axes[1].pcolormesh(X, Y, slip.astype(float), shading="gouraud", cmap="coolwarm", vmin=0, vmax=1)
    axes[1].set_title("stick (blue) / slip (red)")
    m2 = axes[2].pcolormesh(X, Y, dens / 1e6, shading="gouraud", cmap="inferno")
    fig.colorbar(m2, ax=axes[2], label="W/mm^2")
    axes[2].set_title(f"power density, total {r.power:.0f} W")
    for ax in axes:
        ax.set_xlabel("x (rolling), mm")
        ax.set_aspect("equal")
    axes[0].set_ylabel("y, mm")
    fig.suptitle(
        f"FASTSIM, a = 6 mm, b = 4 mm, Fn = 80 kN, mu = 0.3, xi = 1e-3, eta = 5e-4, phi = 0.8/m, "
        f"V = {SPEED:g} m/s: Fx = {r.fx / 1e3:.2f} kN, Fy = {r.fy / 1e3:.2f} kN",
        fontsize=9,
    )
    fig.tight_layout()
    FIG.mkdir(exist_ok=True)
    fig.savefig(FIG / "contact_fastsim_maps.png", dpi=70)
    print(f"wrote {FIG / 'contact_fastsim_maps.png'}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarser meshes (smoke test)")
    args = ap.parse_args()
    fastsim_alone()
    if solve_rolling is None:
        print(
            "railvti.contact.solve_rolling is not available (BEM steady rolling, branch 'rolling'): "
            "no BEM comparison"
        )
        return 0
    ns_bem = (5, 10, 15, 20, 30) if args.quick else (5, 10, 15, 20, 30, 40)
    n_ref = 40 if args.quick else 60
    ns_fs = (5, 10, 20, 30, 50) if args.quick else (5, 10, 20, 30, 50, 80)
    rows = []  # (ratio, case, method, n, time, error)
    table = []  # (ratio, case, fastsim err at finest, strip err, fx_ref, fy_ref)
    for ratio in RATIOS:
        A, B, a, b = gap_coefficients(ratio)
        for case in CASES:
            cr = creepages(case, a, b)
            g = grid_for(a, b, n_ref)
            ref = solve_rolling(hertz_gap(g, A, B), g, STEEL, MU, FN, creepage=cr, speed=SPEED)
            fref = np.array([ref.fx, ref.fy])
            nref = np.linalg.norm(fref)
            for n in ns_bem:
                g = grid_for(a, b, n)
                gap = hertz_gap(g, A, B)
                try:
                    r, t = timed(lambda: solve_rolling(gap, g, STEEL, MU, FN, creepage=cr, speed=SPEED))
                except RailvtiError as exc:
                    print(f"  BEM n={n} a/b={ratio:g} {case}: {type(exc).__name__}: {exc}")
                    continue
                rows.append(
                    (ratio, case, "BEM", n, t, np.linalg.norm([r.fx - fref[0], r.fy - fref[1]]) / nref)
                )
                fsg, ts = timed(lambda: fastsim_grid(r.pressure, g, STEEL, MU, cr, SPEED))
                rows.append(
                    (
                        ratio,
                        case,
                        "FASTSIM strip-wise (BEM p)",
                        n,
                        ts,
                        np.linalg.norm([fsg.fx - fref[0], fsg.fy - fref[1]]) / nref,
                    )
                )
            for n in ns_fs:
                (fx, fy, _), t = timed(lambda: fastsim_forces(a, b, FN, STEEL, MU, *cr, nx=n, ny=n))
                rows.append(
                    (
                        ratio,
                        case,
                        "FASTSIM ellipse",
                        n,
                        t,
                        np.linalg.norm([fx[()] - fref[0], fy[()] - fref[1]]) / nref,
                    )
                )
            e_fs = rows[-1][5]
            e_strip = [r for r in rows if r[:3] == (ratio, case, "FASTSIM strip-wise (BEM p)")][-1][5]
            # strip-wise with per-strip flexibility on the finest BEM pressure
            fl = fastsim_grid(ref.pressure, grid_for(a, b, n_ref), STEEL, MU, cr, SPEED, flexibility="strip")
            e_fl = np.linalg.norm([fl.fx - fref[0], fl.fy - fref[1]]) / nref
            table.append((ratio, case, e_fs, e_strip, e_fl, ref.fx, ref.fy, cr))
            print(
                f"a/b={ratio:4.1f} {case:9s} ref Fx={ref.fx:10.1f} Fy={ref.fy:10.1f} N  "
                f"FASTSIM err {100 * e_fs:5.1f}%  strip-wise err {100 * e_strip:5.1f}%",
                flush=True,
            )

    print("\n| method | a/b | case | n | time (ms) | force error (%) |")
    print("|---|---|---|---|---|---|")
    for ratio, case, method, n, t, e in rows:
        print(f"| {method} | {ratio:g} | {case} | {n} | {1e3 * t:.3g} | {100 * e:.3g} |")
    print(f"\nFASTSIM against the finest BEM (n = {n_ref}); error > 10% in bold:\n")
    print(
        "| a/b | case | creepage (xi, eta, phi 1/m) | BEM Fx, Fy (kN) | FASTSIM ellipse err "
        "| strip-wise err | strip-wise, flexibility='strip' err |"
    )
    print("|---|---|---|---|---|---|---|")
    for ratio, case, e1, e2, e3, fx, fy, cr in table:
        f = lambda e: f"**{100 * e:.1f}%**" if e > 0.1 else f"{100 * e:.1f}%"  # noqa: E731
        print(
            f"| {ratio:g} | {case} | {cr[0]:.2e}, {cr[1]:.2e}, {cr[2]:.3g} | {fx / 1e3:.2f}, {fy / 1e3:.2f} "
            f"| {f(e1)} | {f(e2)} | {f(e3)} |"
        )

    levels = (0.1, 0.3, 1.0, 3.0)
    n_lev = 30 if args.quick else 40
    print(
        f"\nFASTSIM (ellipse, n = 50 | strip-wise on the BEM pressure) against the BEM (n = {n_lev}) "
        "at creepages scaled so that the linear theory gives the multiple of mu Fn in the header; "
        "error > 10% in bold:\n"
    )
    print("| a/b | case | " + " | ".join(f"{lv:g} mu Fn" for lv in levels) + " |")
    print("|---|---|" + "---|" * len(levels))
    for ratio in RATIOS:
        A, B, a, b = gap_coefficients(ratio)
        g = grid_for(a, b, n_lev)
        gap = hertz_gap(g, A, B)
        for case in CASES:
            cells = []
            for lv in levels:
                cr = tuple(c * lv / 0.5 for c in creepages(case, a, b))
                try:
                    ref = solve_rolling(gap, g, STEEL, MU, FN, creepage=cr, speed=SPEED)
                except RailvtiError as exc:
                    cells.append(f"BEM failed ({type(exc).__name__})")
                    continue
                nref = np.hypot(ref.fx, ref.fy)
                fx, fy, _ = fastsim_forces(a, b, FN, STEEL, MU, *cr, nx=50, ny=50)
                e1 = np.hypot(fx[()] - ref.fx, fy[()] - ref.fy) / nref
                fsg = fastsim_grid(ref.pressure, g, STEEL, MU, cr, SPEED)
                e2 = np.hypot(fsg.fx - ref.fx, fsg.fy - ref.fy) / nref
                f = lambda e: f"**{100 * e:.1f}%**" if e > 0.1 else f"{100 * e:.1f}%"  # noqa: E731
                cells.append(f"{f(e1)} \\| {f(e2)}")
            print(f"| {ratio:g} | {case} | " + " | ".join(cells) + " |", flush=True)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(RATIOS), figsize=(12, 4), sharey=True)
    markers = {"BEM": "o", "FASTSIM ellipse": "s", "FASTSIM strip-wise (BEM p)": "^"}
    colors = dict(zip(CASES, ("C0", "C1", "C2", "C3")))
    for ax, ratio in zip(axes, RATIOS):
        for method, mk in markers.items():
            for case in CASES:
                pts = [
                    (t, max(e, 1e-5))
                    for r_, c_, m_, n, t, e in rows
                    if r_ == ratio and c_ == case and m_ == method
                ]
                if pts:
                    t, e = np.array(pts).T
                    ax.loglog(
                        t, e, marker=mk, color=colors[case], ls="-" if method == "BEM" else ":", ms=4, lw=0.8
                    )
        ax.axhline(0.1, color="k", lw=0.5, ls="--")
        ax.set_title(f"a/b = {ratio:g}")
        ax.set_xlabel("time per case, s")
        ax.grid(True, which="major", lw=0.3)
    axes[0].set_ylabel(f"|F - F_BEM,n={n_ref}| / |F_BEM,n={n_ref}|")
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], marker=mk, color="k", ls="", label=m) for m, mk in markers.items()]
    handles += [Line2D([], [], color=c, label=k) for k, c in colors.items()]
    axes[-1].legend(handles=handles, fontsize=7, loc="upper right")
    fig.suptitle(
        "Creep force error against time: BEM (n = 5..%d per semi-axis) and FASTSIM" % max(ns_bem), fontsize=10
    )
    fig.tight_layout()
    FIG.mkdir(exist_ok=True)
    out = FIG / "contact_fastsim_vs_bem.png"
    fig.savefig(out, dpi=80)
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
