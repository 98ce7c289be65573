"""Subsurface stresses below a circular Hertz contact (issue 35, Deliver 5).

The Hertz pressure p0 sqrt(1 - r^2/a^2) (nu = 0.3) on a grid of 40 elements per radius is
fed to railvti.contact.subsurface_stress_fields, without friction and in full sliding with
the traction mu p along +x (mu = 0.3). Printed and drawn:

- on the axis, sigma_z, sigma_r and the von Mises stress |sigma_z - sigma_r| against Hertz's
  closed form (Johnson 1985, eq. 3.45); the maximum 0.6200 p0 at z = 0.4809 a;
- the von Mises field in the x-z plane through the centre for mu = 0 and mu = 0.3
  (Hamilton 1983: the maximum grows and rises with mu and reaches the surface beyond it);
- the largest von Mises stress per depth and its overall maximum for mu = 0..0.5.

Run: PYTHONPATH=_site python validation/contact_subsurface.py
Writes validation/figures/contact_subsurface.png.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy import optimize

from railvti.contact import Grid
from railvti.contact.subsurface import hertz_axis_stresses, subsurface_stress_fields

HERE = Path(__file__).resolve().parent
NU = 0.3
A = 1.0e-3  # m
P0 = 1.0e9  # Pa
N_PER_A = 40


def _grid() -> tuple[Grid, np.ndarray]:
    g = Grid.covering(A, A, n_per_semiaxis=N_PER_A, margin=1.1)
    g = Grid(g.nx + 1, g.ny + 1, g.dx, g.dy)  # odd: an element on the axis
    x, y = g.mesh()
    return g, P0 * np.sqrt(np.maximum(1.0 - (x * x + y * y) / A**2, 0.0))


def main() -> None:
    import matplotlib.pyplot as plt

    g, p = _grid()
    f = lambda s: -abs(np.subtract(*hertz_axis_stresses(s, NU)))  # noqa: E731
    best = optimize.minimize_scalar(f, bounds=(0.2, 1.0), method="bounded", options={"xatol": 1e-12})
    print(f"Hertz closed form (nu = {NU}): max von Mises {-best.fun:.5f} p0 at z = {best.x:.5f} a")
    s = np.linspace(0.01, 3.0, 300)
    ax_r = subsurface_stress_fields(g, p, poisson=NU, z=s * A, x=[0.0], y=[0.0], method="direct")
    sr, sz = hertz_axis_stresses(s, NU)
    vm = ax_r.von_mises[0, 0] / P0
    print(
        f"axis, 300 depths 0.01-3 a: max |error| sigma_z {np.abs(ax_r.component('zz')[0, 0] / P0 - sz).max():.2e} p0,"
        f" sigma_r {np.abs(ax_r.component('xx')[0, 0] / P0 - sr).max():.2e} p0"
    )
    zf = np.linspace(0.46, 0.50, 81) * A
    fine = subsurface_stress_fields(g, p, poisson=NU, z=zf, x=[0.0], y=[0.0])
    print(
        f"BEM field ({N_PER_A} elements per radius): max von Mises {fine.max_von_mises / P0:.5f} p0 at"
        f" z = {fine.max_von_mises_at[2] / A:.4f} a ({(fine.max_von_mises / P0 / -best.fun - 1) * 100:+.3f} %,"
        f" {(fine.max_von_mises_at[2] / A / best.x - 1) * 100:+.2f} %)"
    )
    zs = np.concatenate(([0.002, 0.01], np.linspace(0.02, 1.5, 75))) * A
    jc = g.ny // 2
    planes, rows = {}, []
    for mu in (0.0, 0.1, 0.2, 0.3, 0.35, 0.4, 0.5):
        r = subsurface_stress_fields(g, p, mu * p, poisson=NU, z=zs, y=[g.y[jc]], method="fft")
        x_m, _, z_m = r.max_von_mises_at
        rows.append((mu, r.max_von_mises / P0, x_m / A, z_m / A))
        print(
            f"mu = {mu:4.2f}: max von Mises {r.max_von_mises / P0:.4f} p0 at x = {x_m / A:+.3f} a, z = {z_m / A:.3f} a"
        )
        if mu in (0.0, 0.3):
            planes[mu] = r
    fig, axs = plt.subplots(2, 2, figsize=(11.0, 8.0))
    ax = axs[0, 0]
    ax.plot(vm, s, "k-", lw=2.5, alpha=0.4, label="BEM von Mises")
    ax.plot(np.abs(sz - sr), s, "r--", label="Hertz |sigma_z - sigma_r| (Johnson eq. 3.45)")
    ax.plot(ax_r.component("zz")[0, 0] / P0, s, "b-", label="BEM sigma_z")
    ax.plot(sz, s, "c:", label="Hertz sigma_z")
    ax.plot(ax_r.component("xx")[0, 0] / P0, s, "g-", label="BEM sigma_r")
    ax.plot(sr, s, "y:", label="Hertz sigma_r")
    ax.invert_yaxis()
    ax.set_xlabel("stress / p0 (tension positive)")
    ax.set_ylabel("depth z / a")
    ax.set_title(f"On the axis, nu = {NU}: max {-best.fun:.4f} p0 at z = {best.x:.4f} a")
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    xa = g.x / A
    levels = np.linspace(0.0, 0.75, 16)
    for k, mu in enumerate((0.0, 0.3)):
        a2 = axs[0, 1] if k == 0 else axs[1, 0]
        r = planes[mu]
        cs = a2.contourf(xa, zs / A, r.von_mises[:, 0, :].T / P0, levels=levels, cmap="viridis", extend="max")
        x_m, _, z_m = r.max_von_mises_at
        a2.plot(x_m / A, z_m / A, "r+", ms=12, mew=2)
        a2.set_xlim(xa[0], xa[-1])
        a2.invert_yaxis()
        a2.set_xlabel("x / a (traction mu p along +x)")
        a2.set_ylabel("depth z / a")
        a2.set_title(
            f"von Mises / p0, y = 0, mu = {mu}: max {r.max_von_mises / P0:.3f} at z = {z_m / A:.2f} a"
        )
        fig.colorbar(cs, ax=a2, label="von Mises / p0")
    ax = axs[1, 1]
    for mu, r in planes.items():
        ax.plot(r.von_mises[:, 0, :].max(axis=0) / P0, zs / A, label=f"mu = {mu}: largest over x")
    ax.plot(np.abs(sz - sr), s, "r--", label="Hertz axis, mu = 0")
    ax.set_ylim(1.5, 0)
    ax.set_xlabel("von Mises / p0")
    ax.set_ylabel("depth z / a")
    ax.set_title("Largest von Mises per depth")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    out = HERE / "figures" / "contact_subsurface.png"
    fig.savefig(out, dpi=100)
    print(f"wrote {out.relative_to(HERE.parent)}")


if __name__ == "__main__":
    main()
