"""Carter's exact 2-D rolling solution against the steady rolling BEM solver
(issue 3, validation a).

Plane strain is emulated by two element rows of length dy = 2000 a: uniform
in y over such a strip, the Cerruti kernel's x-dependence differs from the
2-D one by O(x^2/dy^2). The pressure is Hertz's 2-D distribution
p0 sqrt(1 - x^2/a^2) at the element centres, so the comparison tests the
tangential solver alone. With the relative radius R (p0 = a E* / (2 R),
1/E* = (1 - nu)/G) and kappa = |xi| R / (mu a), Carter (1926):
    Fx / (mu Fn) = -sign(xi) (1 - (1 - kappa)^2)   (kappa < 1; -sign(xi) beyond)
    tx(x) = -sign(xi) mu p0 [sqrt(1 - x^2/a^2) - (a'/a) sqrt(1 - (x - d)^2/a'^2) in stick]
with the stick zone of half-width a' = a (1 - kappa) at the leading edge,
centred at d = a - a'. The BEM traction is uniform on each element; it is
compared with Carter's element means (and point values), on the 13 creepages
of the table and on a dense sweep kappa = 0.02, 0.03, ..., 0.99 (the stick/slip
boundary then falls anywhere inside an element).

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
A_HALF = 5.0e-3  # m
P0 = 800.0e6  # Pa


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
    """Two long rows with n_across elements over 2a, and Hertz's 2-D pressure."""
    dx = 2.0 * A_HALF / n_across
    nx = n_across + 6
    grid = Grid(nx=nx, ny=2, dx=dx, dy=2000.0 * A_HALF, x0=-0.5 * (nx - 1) * dx)
    x, _ = grid.mesh()
    p = P0 * np.sqrt(np.clip(1.0 - (x / A_HALF) ** 2, 0.0, None))
    return grid, np.asfortranarray(p)


def solve(grid: Grid, p: np.ndarray, xi: float, method: str = "fftgs"):
    return solve_tangential(p, grid, MAT, MU, (xi, 0.0, 0.0), 1.0, method=method, tol=1e-10)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    grids = (40, 80) if args.quick else (40, 80, 160)
    es = MAT.contact_modulus
    R = A_HALF * es / (2.0 * P0)
    xi_sat = MU * A_HALF / R
    kappas = np.array([0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.2])
    rows = []
    print(
        f"Carter 2-D, mu = {MU}, a = {A_HALF * 1e3} mm, p0 = {P0 / 1e6:.0f} MPa, R = {R:.4f} m, "
        f"saturation creepage mu a / R = {xi_sat:.3e}"
    )
    for n in grids:
        grid, p = strip_case(n)
        fn = p.sum() * grid.element_area
        print(f"\n{n} elements across the strip (dx = {grid.dx * 1e6:.1f} um)")
        print(
            f"{'kappa':>6} {'xi':>10} {'Fx/muFn BEM':>12} {'Carter':>8} {'err %':>7} "
            f"{'dt mean %':>10} {'dt pt %':>8} {'sweeps':>6}"
        )
        for k in kappas:
            r = solve(grid, p, k * xi_sat)
            f_bem = -r.fx / (MU * fn)
            f_ref = float(carter_force(k))
            sub = grid.x[:, None] + grid.dx * ((np.arange(20) + 0.5) / 20 - 0.5)[None, :]
            t_mean = carter_traction(sub, A_HALF, k).mean(axis=1)
            t_pt = carter_traction(grid.x, A_HALF, k)
            t_bem = -r.tx[:, 0] / (MU * P0)
            dtm = float(np.max(np.abs(t_bem - t_mean)))
            dtp = float(np.max(np.abs(t_bem - t_pt)))
            rows.append((n, k, f_bem, f_ref, dtm, dtp))
            print(
                f"{k:6.2f} {k * xi_sat:10.3e} {f_bem:12.5f} {f_ref:8.5f} {100 * (f_bem / f_ref - 1):7.3f} "
                f"{100 * dtm:10.2f} {100 * dtp:8.2f} {r.iterations:6d}"
            )
    dense = {}
    for n in grids:
        grid, p = strip_case(n)
        fn = p.sum() * grid.element_area
        sub = grid.x[:, None] + grid.dx * ((np.arange(20) + 0.5) / 20 - 0.5)[None, :]
        worst = [0.0, 0.0, 0.0]
        for k in np.arange(0.02, 0.995, 0.01):
            r = solve(grid, p, k * xi_sat)
            t_bem = -r.tx[:, 0] / (MU * P0)
            worst[0] = max(worst[0], abs(-r.fx / (MU * fn) / float(carter_force(k)) - 1))
            worst[1] = max(
                worst[1], float(np.max(np.abs(t_bem - carter_traction(sub, A_HALF, k).mean(axis=1))))
            )
            worst[2] = max(worst[2], float(np.max(np.abs(t_bem - carter_traction(grid.x, A_HALF, k)))))
        dense[n] = worst
    for n in grids:
        sel = [r for r in rows if r[0] == n]
        print(
            f"{n:4d} across, dense sweep kappa = 0.02..0.99: largest force error {100 * dense[n][0]:.3f} %, "
            f"traction error {100 * dense[n][1]:.2f} % (element means) / {100 * dense[n][2]:.2f} % (point values)"
        )
        print(
            f"{n:4d} across: largest force error {100 * max(abs(r[2] / r[3] - 1) for r in sel):.3f} % "
            f"(acceptance 1 %), largest traction error {100 * max(r[4] for r in sel):.2f} % of mu p0 "
            f"against element means, {100 * max(r[5] for r in sel):.2f} % against point values (acceptance 3 %)"
        )

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    kk = np.linspace(0, 1.3, 300)
    ax1.plot(kk, carter_force(kk), "k-", lw=1.2, label="Carter (exact)")
    for n, mk in zip(grids, ("s", "o", "^")):
        sel = [r for r in rows if r[0] == n]
        ax1.plot([r[1] for r in sel], [r[2] for r in sel], mk, mfc="none", label=f"BEM, {n} across")
    ax1.set_xlabel(r"$\kappa = |\xi| R / (\mu a)$")
    ax1.set_ylabel(r"$|F_x| / (\mu F_n)$")
    ax1.set_title("Creep force vs creepage")
    ax1.legend()
    ax1.grid(alpha=0.3)
    n = grids[1]
    grid, p = strip_case(n)
    xf = np.linspace(-A_HALF, A_HALF, 400)
    for k, col in ((0.2, "C0"), (0.5, "C1"), (0.8, "C2")):
        r = solve(grid, p, k * xi_sat)
        ax2.plot(
            xf / A_HALF, carter_traction(xf, A_HALF, k), "-", color=col, lw=1, label=f"Carter, kappa={k}"
        )
        ax2.plot(grid.x / A_HALF, -r.tx[:, 0] / (MU * P0), ".", color=col, ms=4, label=f"BEM {n} across")
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
