"""Carter's exact 2-D rolling solution against the steady rolling BEM solver
(issue 3, validation a).

A long elliptical patch, a/b = 0.05 (a = 5 mm along x, b = 100 mm), carries
Hertz's pressure p0 sqrt(1 - x^2/a^2 - y^2/b^2) at the element centres, so the
comparison tests the tangential solver alone. Each row y is then a 2-D Hertz
strip of half-width a(y) = a sqrt(1 - y^2/b^2) and peak p0(y) with
p0(y)/a(y) = p0/a, i.e. the relative radius R = a E* / (2 p0),
1/E* = (1 - nu)/G. With kappa = |xi| R / (mu a), Carter (1926):
    Fx / (mu Fn) = -sign(xi) (1 - (1 - kappa)^2)   (kappa < 1; -sign(xi) beyond)
    tx(x) = -sign(xi) mu p0 [sqrt(1 - x^2/a^2) - (a'/a) sqrt(1 - (x - d)^2/a'^2) in stick]
with the stick zone of half-width a' = a (1 - kappa) at the leading edge,
centred at d = a - a'. The centre row (y = 0) is compared with Carter's strip
directly; the total force with Carter integrated over the rows (strip theory,
exact as a/b -> 0). A purely 2-D strip (two rows of length >> a) is not used:
on such rows the kernel is logarithmic and the row-wise Gauss-Seidel diverges
(see docs/rolling.md).

Elements: n across 2a in x, dy = 8 dx.

Run: .venv/bin/python validation/contact_carter.py [--quick]
Writes validation/figures/contact_rolling_carter.png.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from railvti.contact import Grid, solve_tangential
from railvti.material import Material

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
MAT = Material(shear_modulus=82.0e9, poisson=0.28)
MU = 0.3
A_HALF = 5.0e-3   # m
B_HALF = 20.0 * A_HALF
P0 = 800.0e6      # Pa
ASPECT = 8.0      # dy / dx


def carter_force(kappa: np.ndarray) -> np.ndarray:
    """|Fx| / (mu Fn) of Carter's solution."""
    k = np.minimum(np.abs(kappa), 1.0)
    return 1.0 - (1.0 - k) ** 2


def carter_traction(x: np.ndarray, a: float, kappa: float) -> np.ndarray:
    """|tx| / (mu p0) of Carter's solution at x (leading edge at +a)."""
    full = np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None))
    if kappa >= 1.0:
        return full
    a1 = a * (1.0 - kappa)
    d = a - a1
    stick = np.sqrt(np.clip(1.0 - ((x - d) / a1) ** 2, 0.0, None))
    return full - (a1 / a) * stick


def strip_case(n_across: int):
    """Grid over the long ellipse (n_across elements over 2a) and Hertz's pressure on it."""
    dx = 2.0 * A_HALF / n_across
    dy = ASPECT * dx
    nx = n_across + 6
    ny = 2 * int(np.ceil(1.05 * B_HALF / dy))
    grid = Grid(nx=nx, ny=ny, dx=dx, dy=dy)
    x, y = grid.mesh()
    p = P0 * np.sqrt(np.clip(1.0 - (x / A_HALF) ** 2 - (y / B_HALF) ** 2, 0.0, None))
    return grid, np.asfortranarray(p)


def strip_theory_force(kappa: float, n: int = 4001) -> float:
    """Carter integrated over the rows of the ellipse: |Fx| / (mu Fn)."""
    s = np.linspace(-1.0, 1.0, n)[1:-1]
    w = 1.0 - s ** 2                 # Fn per row ~ p0(y) a(y)
    return float(np.trapezoid(w * carter_force(kappa / np.sqrt(w)), s) / np.trapezoid(w, s))


def solve(grid: Grid, p: np.ndarray, xi: float, method: str = "fftgs"):
    return solve_tangential(p, grid, MAT, MU, (xi, 0.0, 0.0), 1.0, method=method, tol=1e-9)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n_across = 40 if args.quick else 80
    es = MAT.contact_modulus
    R = A_HALF * es / (2.0 * P0)
    xi_sat = MU * A_HALF / R
    kappas = np.array([0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.2])
    rows = []
    print(f"Carter 2-D, mu = {MU}, a = {A_HALF * 1e3} mm, p0 = {P0 / 1e6:.0f} MPa, R = {R:.4f} m, "
          f"saturation creepage mu a / R = {xi_sat:.3e}")
    for n in sorted({40, n_across}):
        grid, p = strip_case(n)
        fn = p.sum() * grid.element_area
        print(f"\n{n} elements across the strip (dx = {grid.dx * 1e6:.1f} um)")
        print(f"{'kappa':>6} {'xi':>10} {'Fx/muFn BEM':>12} {'strips':>8} {'err %':>7} {'row0 BEM':>9} "
              f"{'Carter':>8} {'err %':>7} {'dt mean %':>11} {'dt pt %':>9} {'sweeps':>6}")
        for k in kappas:
            xi = k * xi_sat
            r = solve(grid, p, xi)
            f_bem = -r.fx / (MU * fn)
            f_ref = strip_theory_force(k)
            j0 = grid.ny // 2          # rows j0 - 1 and j0 straddle y = 0
            y0 = abs(grid.y[j0])
            s0 = np.sqrt(1.0 - (y0 / B_HALF) ** 2)
            row = 0.5 * (r.tx[:, j0] + r.tx[:, j0 - 1])
            prow = 0.5 * (p[:, j0] + p[:, j0 - 1])
            f_row = -row.sum() / (MU * prow.sum())
            f_row_ref = carter_force(k / s0)
            # the BEM traction is uniform on each element: compare with the
            # element mean of Carter's profile (20-point midpoint rule)
            sub = grid.x[:, None] + grid.dx * ((np.arange(20) + 0.5) / 20 - 0.5)[None, :]
            t_ref = s0 * carter_traction(sub, A_HALF * s0, k / s0).mean(axis=1)
            t_pt = s0 * carter_traction(grid.x, A_HALF * s0, k / s0)
            t_bem = -row / (MU * P0)
            dt = np.max(np.abs(t_bem - t_ref))
            dtp = np.max(np.abs(t_bem - t_pt))
            rows.append((n, k, f_bem, f_ref, dt, f_row, f_row_ref, dtp))
            print(f"{k:6.2f} {xi:10.3e} {f_bem:12.5f} {f_ref:8.5f} {100 * (f_bem / f_ref - 1):7.3f} "
                  f"{f_row:9.5f} {f_row_ref:8.5f} {100 * (f_row / f_row_ref - 1):7.3f} "
                  f"{100 * dt:11.2f} {100 * dtp:9.2f} {r.iterations:6d}")
    fine = [r for r in rows if r[0] == n_across]
    worst_f = max(abs(r[2] / r[3] - 1) for r in fine)
    worst_r = max(abs(r[5] / r[6] - 1) for r in fine)
    worst_t = max(r[4] for r in fine)
    worst_tp = max(r[7] for r in fine)
    print(f"\n{n_across} across: largest force error {100 * worst_f:.3f} % (patch vs strip theory), "
          f"{100 * worst_r:.3f} % (centre row vs Carter) (acceptance 1 %), "
          f"largest traction error {100 * worst_t:.2f} % of mu p0 against Carter's element means, "
          f"{100 * worst_tp:.2f} % against point values (acceptance 3 %)")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    kk = np.linspace(0, 1.3, 300)
    ax1.plot(kk, carter_force(kk), "k-", lw=1.2, label="Carter (exact, 2-D)")
    ax1.plot(kk, [strip_theory_force(k) for k in kk], "k--", lw=0.8, label="Carter over the rows")
    for n, mk in ((40, "s"), (n_across, "o")):
        sel = [r for r in rows if r[0] == n]
        ax1.plot([r[1] for r in sel], [r[2] for r in sel], mk, mfc="none", label=f"BEM patch, {n} across")
        ax1.plot([r[1] for r in sel], [r[5] for r in sel], "+", label=f"BEM centre row, {n} across")
    ax1.set_xlabel(r"$\kappa = |\xi| R / (\mu a)$")
    ax1.set_ylabel(r"$|F_x| / (\mu F_n)$")
    ax1.set_title("Creep force vs creepage")
    ax1.legend()
    ax1.grid(alpha=0.3)
    grid, p = strip_case(n_across)
    xf = np.linspace(-A_HALF, A_HALF, 400)
    for k, col in ((0.2, "C0"), (0.5, "C1"), (0.8, "C2")):
        r = solve(grid, p, k * xi_sat)
        j0 = grid.ny // 2
        s0 = np.sqrt(1.0 - (grid.y[j0] / B_HALF) ** 2)
        ax2.plot(xf / A_HALF, s0 * carter_traction(xf, A_HALF * s0, k / s0), "-", color=col, lw=1,
                 label=f"Carter, kappa={k}")
        ax2.plot(grid.x / A_HALF, -0.5 * (r.tx[:, j0] + r.tx[:, j0 - 1]) / (MU * P0), ".", color=col, ms=4,
                 label=f"BEM {n_across} across, y = 0")
    ax2.plot(xf / A_HALF, np.sqrt(1 - (xf / A_HALF) ** 2), "k:", lw=0.8, label=r"$\mu p$")
    ax2.set_xlim(-1.05, 1.05)
    ax2.set_xlabel("x / a  (leading edge at +1)")
    ax2.set_ylabel(r"$-t_x / (\mu p_0)$")
    ax2.set_title("Traction profile")
    ax2.legend(fontsize=7)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    out = HERE / "figures" / "contact_rolling_carter.png"
    fig.savefig(out, dpi=90)
    print(f"wrote {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
