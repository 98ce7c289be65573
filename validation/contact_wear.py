"""Wear and RCF indices of a contact patch (issue 34, item 4): railvti.contact.wear.

(a) T gamma V against the BEM's frictional power sum |tau| |s| dA, which it equals in the
    continuum for steady rolling without spin (the elastic part of the slip does no net work
    on the half-space's symmetric kernel): the relative difference over the element count,
    three creepages. The BEM's upwind slip converges at first order.
(b) Archard wear with Jendel's map: the depth one passage wears across the patch for three
    creepages (S1002/UIC60-like Hertz patch, Fn = 80 kN, mu = 0.3, V = 30 m/s, H = 2.4 GPa).
(c) Ekberg's surface fatigue index FI_surf = f - k / p0 over the traction coefficient f for
    three wheel loads (k = 300 MPa): zero on Johnson's shakedown limit f = k / p0.

Run: .venv/bin/python validation/contact_wear.py
Writes validation/figures/contact_wear.png and prints the figures.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railvti._plotting import pyplot
from railvti.contact import Grid, hertz, hertz_gap, solve_rolling
from railvti.contact.wear import archard_wear, surface_fatigue_index, t_gamma
from railvti.material import Material

HERE = Path(__file__).resolve().parent
MAT = Material(shear_modulus=82e9, poisson=0.28)
FN, MU, V, HARD, K_SHEAR = 80e3, 0.3, 30.0, 2.4e9, 300e6
A_GAP, B_GAP = 0.5 / 0.46, 0.5 / 0.3
CREEPAGES = [(1e-3, 0.0, 0.0), (0.0, 1.5e-3, 0.0), (2e-3, -1e-3, 0.0)]


def _rolling(creepage, n: int, fn: float = FN):
    h = hertz(A_GAP, B_GAP, fn, MAT)
    grid = Grid.covering(h.a, h.b, n, 1.3)
    return solve_rolling(hertz_gap(grid, A_GAP, B_GAP), grid, MAT, MU, fn, creepage, V, tol=1e-9)


def main() -> None:
    plt = pyplot()
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    ns = [15, 20, 30, 40, 60]
    for c in CREEPAGES:
        err = []
        for n in ns:
            r = _rolling(c, n)
            err.append(100 * (t_gamma(r.fx, r.fy, c[0], c[1]) * V / r.power - 1.0))
        print(f"creepage {c}: T gamma V / power - 1 = " + ", ".join(f"{e:.2f} %" for e in err), f"(n = {ns})")
        ax[0].loglog(ns, err, "o-", label=f"xi = {c[0]:g}, eta = {c[1]:g}")
    ax[0].loglog(ns, 0.66 * np.array(ns[0]) / np.array(ns), "k--", label="first order")
    ax[0].set_xlabel("elements per semi-axis (Grid.covering)")
    ax[0].set_ylabel("T gamma V / frictional power - 1, %")
    ax[0].set_title("(a) T gamma V against the BEM's friction power")
    ax[0].legend(fontsize=8)
    for c in [(5e-4, 0.0, 0.0), (2e-3, 0.0, 0.0), (5e-3, 2e-3, 0.0)]:
        r = _rolling(c, 40)
        w = archard_wear(r, HARD)
        y = r.grid.y
        print(
            f"creepage {c}: worn volume {w.volume_per_distance * 1e9:.3f} mm^3 per m rolled, "
            f"max depth per pass {w.depth_per_pass.max() * 1e9:.4f} nm"
        )
        ax[1].plot(y * 1e3, w.depth_per_pass * 1e9, label=f"xi = {c[0]:g}, eta = {c[1]:g}")
    ax[1].set_xlabel("lateral position y, mm")
    ax[1].set_ylabel("depth worn per passage, nm")
    ax[1].set_title("(b) Archard wear, Jendel's map, H = 2.4 GPa")
    ax[1].legend(fontsize=8)
    f = np.linspace(0.0, 0.6, 121)
    for fn in (40e3, 80e3, 120e3):
        h = hertz(A_GAP, B_GAP, fn, MAT)
        ax[2].plot(f, surface_fatigue_index(f * fn, fn, h.a, h.b, K_SHEAR), label=f"Fn = {fn / 1e3:.0f} kN")
        print(f"Fn {fn / 1e3:.0f} kN: p0 {h.p0 / 1e6:.0f} MPa, FI_surf > 0 beyond f = {K_SHEAR / h.p0:.3f}")
    ax[2].axhline(0.0, color="k", lw=0.8)
    ax[2].set_xlabel("traction coefficient |F_t| / Fn")
    ax[2].set_ylabel("FI_surf")
    ax[2].set_title("(c) surface fatigue index, k = 300 MPa")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    out = HERE / "figures" / "contact_wear.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
