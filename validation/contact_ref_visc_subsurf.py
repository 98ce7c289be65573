"""railvti against CONTACT's own reference outputs (Vollebregt, eve70a/CONTACT at commit 424e4e60):
viscoelastic steady rolling (examples/visc_cylindr) and subsurface stresses (examples/subsurf).

Both cases are run on CONTACT's grids. visc_cylindr: one row of 99 elements of 0.16 mm x 1000 mm
(railvti's Grid needs two rows: the second one, 1000 mm aside, is taken out of contact by a large
gap, as CONTACT's planform would), FN = 600 kN, the PA6 rollers of Wang & Knothe (1993) with
CONTACT's MATER=1 inputs GG = 1143 N/mm^2 (glassy), FG = 1, TC (creep time) mapped to railvti's
standard linear solid as G0 = GG, Ginf = GG / (1 + FG), tau = TC / (1 + FG) (CONTACT's user guide,
table "visc_inputs"). subsurf: a uniform load on one 1 x 1 mm element, stresses at CONTACT's
points (z = 0 taken as 1e-7 mm: railvti refuses z <= 0).

Also railvti's own grid dependence on the elastic case 6 (0.16, 0.08, 0.04 mm elements), the
scale of the tangential difference. Prints the tables of docs/contact_viscoelastic.md and docs/contact_subsurface.md and the times on
this machine, and draws validation/figures/contact_ref_visc_cylindr.png.

    PYTHONPATH=_site python validation/contact_ref_visc_subsurf.py
"""

from __future__ import annotations

import csv
import os
import time
from pathlib import Path

import numpy as np

from railvti.contact import Grid, ViscoelasticMaterial
from railvti.contact.subsurface import subsurface_stress_fields
from railvti.contact.viscoelastic_rolling import solve_viscoelastic_rolling
from railvti.material import Material

HERE = Path(__file__).resolve().parent
DATA = HERE.parent / "tests" / "data"
MM = 1e-3
MU, FN, SPEED = 0.3, 6.0e5, 1.0
SUB_PTS = (-5.0, -3.0, -2.0, -1.0, -0.8, -0.6, -0.4, -0.3, -0.2, -0.1, 0.0)
SUB_PTS = np.array(SUB_PTS + tuple(-v for v in SUB_PTS[-2::-1]))
SUB_Z = np.array([0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.25, 1.667, 2.5, 5.0])


def rows(name: str) -> list[dict]:
    """The rows of one reference CSV (comment lines start with '#')."""
    with open(DATA / name) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def visc_grid() -> tuple[Grid, np.ndarray]:
    """CONTACT's 99 x 1 grid (XC1 = -7.92 mm, DX = 0.16 mm, DY = 1000 mm) plus a row out of contact."""
    grid = Grid(99, 2, 0.16 * MM, 1000.0 * MM, x0=-7.92 * MM, y0=0.0)
    x, _ = grid.mesh()
    gap = 0.01 / MM * x**2  # B1 = 0.01 /mm: h = 0.01 x^2 (mm)
    gap[:, 1] = 1.0  # the second row never touches
    return grid, np.asfortranarray(gap)


def visc_body(row: dict) -> ViscoelasticMaterial | Material:
    """CONTACT's (GG, FG, TC) as railvti's material; TC = 0 (instant creep) as a tiny tau."""
    gg = float(row["gg"]) * 1e6
    if row["material"] == "elastic":
        return Material(shear_modulus=gg, poisson=0.4)
    fg, tc = float(row["fg"]), float(row["tc"])
    return ViscoelasticMaterial(gg, gg / (1.0 + fg), max(tc, 1e-12) / (1.0 + fg), 0.4)


def visc_case(row: dict, xi: float | None = None):
    """railvti on the case's grid at CONTACT's creepage (or the one given)."""
    grid, gap = visc_grid()
    b = visc_body(row)
    cksi = float(row["cksi"]) if xi is None else xi
    return solve_viscoelastic_rolling(gap, grid, FN, SPEED, (cksi, 0.0, 0.0), MU, b, b, strip=True, tol=1e-9)


def visc_summary(r) -> dict:
    """The figures CONTACT prints, in its units."""
    p = r.normal.pressure[:, 0]
    on = np.nonzero(p > 0.0)[0]
    x = r.normal.grid.x / MM
    st = r.status[:, 0]
    return {
        "n_contact": on.size,
        "x_first": x[on[0]],
        "x_last": x[on[-1]],
        "n_adh": int((st == 1).sum()),
        "n_slip": int((st == 2).sum()),
        "pmax": p.max() / 1e6,
        "approach": r.normal.approach / MM,
        "fx_rel": r.fx / (MU * FN),
    }


def visc_table() -> list:
    print("visc_cylindr (CONTACT / railvti), V = 1 m/s, FN = 600 N/mm, mu = 0.3")
    print(
        " case  TC s  contact elements [x_first, x_last] mm   adh/slip   pmax N/mm^2   approach mm   Fx/(mu Fn) at CKSI"
    )
    out = []
    for row in rows("contact_ref_visc_cylindr.csv"):
        r = visc_case(row)
        s = visc_summary(r)
        out.append((row, r, s))
        print(
            f" {row['case']:>4} {row['tc']:>5}  {row['n_contact']}/{s['n_contact']} [{row['x_first']}, {row['x_last']}]/"
            f"[{s['x_first']:.2f}, {s['x_last']:.2f}]  {row['n_adh']}/{row['n_slip']} | {s['n_adh']}/{s['n_slip']}"
            f"  {row['pmax']}/{s['pmax']:.3f}  {row['approach']}/{s['approach']:.4f}  {row['fx_rel']}/{s['fx_rel']:.4f}"
        )
    return out


def visc_creep() -> dict:
    """Fx at each of CONTACT's Newton-Raphson creepages; largest relative difference per case."""
    print("visc_cylindr creep force at CONTACT's iterates: Fx/(mu Fn) CONTACT / railvti")
    bycase = {r["case"]: r for r in rows("contact_ref_visc_cylindr.csv")}
    out: dict = {}
    for row in rows("contact_ref_visc_cylindr_creep.csv"):
        xi, ref = float(row["cksi"]), float(row["fx_rel"])
        got = visc_case(bycase[row["case"]], xi).fx / (MU * FN)
        out.setdefault(row["case"], []).append((xi, ref, got))
    for case, pts in out.items():
        d = max(abs(g / f - 1.0) for _, f, g in pts)
        print(
            f"  case {case}: "
            + " ".join(f"{f:.4g}/{g:.4g}" for _, f, g in pts)
            + f"  largest {d * 100:.2f} %"
        )
    return out


def visc_wrong_mapping() -> None:
    """The same case 2 with tau = TC (the creep time taken as the relaxation time): must not match."""
    grid, gap = visc_grid()
    b = ViscoelasticMaterial(1143e6, 571.5e6, 0.009, 0.4)
    r = solve_viscoelastic_rolling(gap, grid, FN, SPEED, (1.365e-2, 0, 0), MU, b, b, strip=True)
    s = visc_summary(r)
    print(
        f"case 2 with tau = TC instead of TC/(1+FG): {s['n_contact']} elements [{s['x_first']:.2f}, {s['x_last']:.2f}] mm, "
        f"pmax {s['pmax']:.2f} (CONTACT 62 [-3.92, 5.84], 78.74)"
    )


def visc_grid_dependence() -> None:
    """railvti's own grid dependence on the elastic case 6: 0.16, 0.08, 0.04 mm elements."""
    from scipy.optimize import brentq

    b = Material(shear_modulus=1143e6, poisson=0.4)
    print("case 6 (elastic G = 1143) on finer grids: CKSI for Fx = -0.6 mu Fn, slope dFx/dCKSI / (mu Fn)")
    for k in (1, 2, 4):
        grid = Grid(100 * k - 1, 2, 0.16 * MM / k, 1000.0 * MM, x0=-7.92 * MM, y0=0.0)
        x, _ = grid.mesh()
        gap = 0.01 / MM * x**2
        gap[:, 1] = 1.0
        gap = np.asfortranarray(gap)

        def fx(xi: float) -> float:
            r = solve_viscoelastic_rolling(
                gap, grid, FN, SPEED, (xi, 0.0, 0.0), MU, b, b, strip=True, tol=1e-9
            )
            return r.fx / (MU * FN)

        xs = brentq(lambda v: fx(v) + 0.6, 5e-3, 2e-2, xtol=1e-10)
        print(
            f"  dx = {0.16 / k:.2f} mm: {xs:.4g}, {fx(1e-6) / 1e-6:.2f} (CONTACT on 0.16 mm: 9.792e-3, -74.68)"
        )


def subsurf_fields(case: int, block: int) -> dict:
    """railvti's extremes over CONTACT's points of one block (N/mm^2, mm)."""
    grid = Grid(2, 2, MM, MM, x0=1e-4 * MM, y0=2e-4 * MM)
    p = np.zeros((2, 2))
    p[0, 0] = 1e6
    q = np.where(p > 0, 0.999e6, 0.0) if case == 2 else None
    pts = np.array([1e-5]) if block == 1 else SUB_PTS
    z = np.where(SUB_Z == 0.0, 1e-7, SUB_Z) * MM
    r = subsurface_stress_fields(grid, p, q, None, poisson=0.28, z=z, x=pts * MM, y=pts * MM, method="direct")
    s, pr = r.stress / 1e6, r.principal / 1e6
    fields = {
        "sighyd": (s[..., :3].sum(-1) / 3, "abs"),
        "sigvm": (r.von_mises / 1e6, "max"),
        "sigtr": (r.tresca / 1e6, "max"),
        "sigma1": (pr[..., 0], "max"),
        "sigma3": (pr[..., 2], "min"),
        "sigxx": (s[..., 0], "abs"),
        "sigyy": (s[..., 1], "abs"),
        "sigzz": (s[..., 2], "abs"),
    }
    out = {}
    for name, (f, how) in fields.items():
        g = {"max": f, "min": -f, "abs": np.abs(f)}[how]
        i, j, k = np.unravel_index(int(np.argmax(g)), g.shape)
        out[name] = (float(f[i, j, k]), pts[i], pts[j], SUB_Z[k])
    return out


def subsurf_table() -> float:
    print("subsurf (CONTACT / railvti), N/mm^2 at (x, y, z) mm")
    got = {(c, b): subsurf_fields(c, b) for c in (1, 2) for b in (1, 2)}
    worst = 0.0
    for row in rows("contact_ref_subsurf.csv"):
        v, x, y, z = got[(int(row["case"]), int(row["block"]))][row["quantity"]]
        worst = max(worst, abs(v - float(row["value"])))
        same = all(abs(a - float(row[k])) < 5e-4 for a, k in ((x, "x"), (y, "y"), (z, "z")))
        where = "same" if same else f"railvti ({x:.3f}, {y:.3f}, {z:.3f})"
        if row["unique_at"] == "0":
            where += " (a tie: the location says nothing)"
        print(
            f"  case {row['case']} block {row['block']} {row['quantity']:>6}: {row['value']:>6} / {v:8.4f}"
            f"  at ({row['x']}, {row['y']}, {row['z']}) {where}"
        )
    print(f"  largest difference {worst:.2e} N/mm^2 (CONTACT prints 3 decimals)")
    return worst


def timing() -> None:
    grid, gap = visc_grid()
    b = ViscoelasticMaterial(1143e6, 571.5e6, 0.0045, 0.4)
    best = []
    for body in (b, Material(shear_modulus=1143e6, poisson=0.4)):
        ts = []
        for _ in range(5):
            t = time.perf_counter()
            solve_viscoelastic_rolling(gap, grid, FN, SPEED, (1.365e-2, 0, 0), MU, body, body, strip=True)
            ts.append(time.perf_counter() - t)
        best.append(min(ts))
    t = time.perf_counter()
    for c in (1, 2):
        for blk in (1, 2):
            subsurf_fields(c, blk)
    ts = time.perf_counter() - t
    print(
        f"times here (best of 5, load {os.getloadavg()[0]:.1f} on 2 shared cores): visc_cylindr case 2 "
        f"{best[0] * 1e3:.1f} ms (normal + tangential at one creepage), elastic case 6 {best[1] * 1e3:.1f} ms; "
        f"subsurf both cases, both blocks {ts * 1e3:.1f} ms"
    )


def figure(table: list, creep: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12.0, 4.6))
    ax = axes[0]
    for (row, r, _), col in zip(table[:4], ("C0", "C1", "C2", "C3")):
        x = r.normal.grid.x / MM
        ax.step(
            x, r.normal.pressure[:, 0] / 1e6, where="mid", color=col, label=f"railvti, TC = {row['tc']} s"
        )
        ax.plot([float(row["x_first"]), float(row["x_last"])], [0, 0], "|", ms=14, color=col)
        xp = x[int(np.argmax(r.normal.pressure[:, 0]))]
        ax.plot(
            xp,
            float(row["pmax"]),
            "o",
            mfc="none",
            color=col,
            label=f"CONTACT pmax, edges (|), TC = {row['tc']} s",
        )
    ax.set_xlabel("x (mm), rolling direction: leading edge at the right")
    ax.set_ylabel("pressure (N/mm^2)")
    ax.set_title("visc_cylindr: two PA6 rollers, 600 N/mm, V = 1 m/s")
    ax.legend(fontsize=6, loc="upper left")
    ax = axes[1]
    for (case, pts), col in zip(creep.items(), ("C0", "C1", "C2", "C3", "k")):
        xi = np.array([p[0] for p in pts[1:]])
        ax.plot(xi, [-p[1] for p in pts[1:]], "o", mfc="none", color=col, label=f"CONTACT, case {case}")
        ax.plot(xi, [-p[2] for p in pts[1:]], "x", color=col, label=f"railvti, case {case}")
    ax.set_xlabel("longitudinal creepage CKSI")
    ax.set_ylabel("-Fx / (mu Fn)")
    ax.set_title("Creep force at CONTACT's Newton iterates (case 6 elastic G = 1143)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    path = HERE / "figures" / "contact_ref_visc_cylindr.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print("wrote", path)


def main() -> None:
    table = visc_table()
    creep = visc_creep()
    visc_wrong_mapping()
    visc_grid_dependence()
    subsurf_table()
    timing()
    figure(table, creep)


if __name__ == "__main__":
    main()
