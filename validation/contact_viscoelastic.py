"""Viscoelastic steady rolling (issue 35, Deliver 3) against Hunter's cylinder.

Hunter (1961, J. Appl. Mech. 28, 611-617): a rigid cylinder rolling on a standard-linear-solid
half-space, plane strain. The reference is Hunter's reduction of the problem (a finite
Hilbert transform of q = Jinf p - J0 L p', inverted in closed form, and a first-order
equation for p), computed by quadrature in railvti.contact.viscoelastic_hunter: independent
of the BEM (which filters the elastic strip kernel in closed form and solves the contact by
an active set). Printed: contact edges, pressure centroid e, mu_R = e / R against V tc / a
for J0/Jinf = 1/3 and 1/10; the 3-D strip emulation (two rows 2000 a long) against the line
solution; a rolling sphere on the 3-D grid; the Wang-Knothe polymer cylinders (CONTACT's
example visc_cylindr.inp: two PA6 rollers, normal part); times beside the elastic solve on
the same grid, with the machine's load.

Run: PYTHONPATH=_site .venv/bin/python validation/contact_viscoelastic.py
Writes validation/figures/contact_viscoelastic_pressure.png,
validation/figures/contact_viscoelastic_resistance.png and
validation/figures/contact_viscoelastic_creep.png.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from railvti import Material
from railvti.contact import Grid, solve_normal
from railvti.contact.viscoelastic import (
    ViscoelasticMaterial,
    line_hertz_half_width,
    solve_viscoelastic,
    solve_viscoelastic_line,
)
from railvti.contact.viscoelastic_hunter import hunter_cylinder
from railvti.contact.viscoelastic_rolling import solve_viscoelastic_rolling

HERE = Path(__file__).resolve().parent
R, FN = 0.05, 2.0e5  # m, N/m
RATIOS = [0.03, 0.1, 0.3, 0.6, 1.0, 2.0, 3.0, 10.0, 30.0, 100.0]


def _best(fun, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fun()
        best = min(best, time.perf_counter() - t0)
    return out, best


def hunter_table(mat: ViscoelasticMaterial, n: int = 800) -> dict:
    """BEM and Hunter at each V tc / a_inf; returns the arrays for the figure."""
    a = line_hertz_half_width(R, FN, mat.compliance_relaxed)
    rows = {"ratio": [], "bem": [], "hunter": [], "c1": [], "c2": [], "hc1": [], "hc2": []}
    print(
        f"\nHunter's cylinder, J0/Jinf = {mat.shear_modulus_relaxed / mat.shear_modulus:.3g}, "
        f"n = {n} strips over [-1.25, 1.25] a_inf (a_inf = relaxed Hertz half-width {a * 1e3:.4g} mm)"
    )
    print(" V tc/a | c1/a BEM  Hunter | c2/a BEM  Hunter |  e/a BEM    Hunter    rel.diff | mu_R BEM")
    for q in RATIOS:
        speed = q * a / mat.creep_time
        r = solve_viscoelastic_line(R, FN, speed, mat, n=n, half_length=1.25 * a)
        h = hunter_cylinder(R, FN, mat.compliance_instant, mat.compliance_relaxed, speed * mat.creep_time)
        print(
            f"{q:7.3g} | {r.x_trailing / a:7.4f} {h.x_trailing / a:7.4f} | {r.x_leading / a:7.4f} "
            f"{h.x_leading / a:7.4f} | {r.centroid / a:8.5f} {h.centroid / a:8.5f} "
            f"{r.centroid / h.centroid - 1:+9.2e} | {r.resistance_coefficient:.4e}"
        )
        for k, v in (
            ("ratio", q),
            ("bem", r.centroid / a),
            ("hunter", h.centroid / a),
            ("c1", r.x_trailing / a),
            ("c2", r.x_leading / a),
            ("hc1", h.x_trailing / a),
            ("hc2", h.x_leading / a),
        ):
            rows[k].append(v)
    dense = np.logspace(np.log10(RATIOS[0]), np.log10(RATIOS[-1]), 41)
    rows["dense"] = dense
    rows["hunter_dense"] = [
        hunter_cylinder(R, FN, mat.compliance_instant, mat.compliance_relaxed, q * a).centroid / a
        for q in dense
    ]
    k = int(np.argmax(rows["bem"]))
    print(
        f"largest e/a = {rows['bem'][k]:.4f} (mu_R = {rows['bem'][k] * a / R:.4g}) at V tc / a = {RATIOS[k]}"
    )
    return rows


def strip_check(mat: ViscoelasticMaterial) -> None:
    """The 3-D grid's filtered Boussinesq field on two rows of 2000 a: plane strain."""
    a = line_hertz_half_width(R, FN, mat.compliance_relaxed)
    print("\n3-D grid, two rows 2000 a long (plane strain emulated), n = 200 along x, vs the line solution")
    for q in (0.3, 1.0, 3.0):
        speed = q * a / mat.creep_time
        line = solve_viscoelastic_line(R, FN, speed, mat, n=200, half_length=1.25 * a)
        dy = 2000.0 * a
        grid = Grid(200, 2, 2.5 * a / 200, dy)
        x, _ = grid.mesh()
        r = solve_viscoelastic(x * x / (2 * R), grid, FN * 2 * dy, speed, mat, strip=True)
        dp = np.linalg.norm(r.pressure[:, 0] - line.pressure) / np.linalg.norm(line.pressure)
        print(
            f"  V tc/a = {q}: e/a {r.centroid / a:.6f} vs {line.centroid / a:.6f} ({r.centroid / line.centroid - 1:+.1e}),"
            f" pressure L2 diff {dp:.1e}, {r.iterations} active-set it, {r.fft_products} FFT products"
        )


def timing(mat: ViscoelasticMaterial) -> None:
    """Time per case beside the elastic solve on the same grid."""
    a = line_hertz_half_width(R, FN, mat.compliance_relaxed)
    print("\nTime per case (best of 3), load average", tuple(round(v, 2) for v in os.getloadavg()))
    for n in (200, 400, 800):
        _, te = _best(lambda: solve_viscoelastic_line(R, FN, 0.0, mat, n=n, half_length=1.25 * a))
        rv, tv = _best(
            lambda: solve_viscoelastic_line(R, FN, a / mat.creep_time, mat, n=n, half_length=1.25 * a)
        )
        print(
            f"  line, n = {n}: elastic (V = 0) {te * 1e3:.1f} ms, viscoelastic (V tc = a) {tv * 1e3:.1f} ms, "
            f"{rv.iterations} active-set it"
        )
    steel = Material(shear_modulus=82e9, poisson=0.28)
    rs, fn = 0.02, 50.0
    for nps in (8, 16, 24):
        j = mat.compliance_relaxed
        asp = (3 * fn * rs * j / 4) ** (1 / 3)
        grid = Grid.covering(asp, asp, n_per_semiaxis=nps, margin=1.3)
        x, y = grid.mesh()
        gap = np.asfortranarray((x * x + y * y) / (2 * rs))
        gel = Material(shear_modulus=mat.shear_modulus_relaxed, poisson=mat.poisson)
        # solve_normal's pair of two equal bodies has twice one body's compliance: halve G
        pair = Material(shear_modulus=gel.shear_modulus * 2.0, poisson=gel.poisson)
        _, tn = _best(lambda: solve_normal(gap, grid, pair, fn=fn, tol=1e-10))
        _, te = _best(lambda: solve_viscoelastic(gap, grid, fn, 0.0, mat, None))
        rv, tv = _best(lambda: solve_viscoelastic(gap, grid, fn, asp / mat.creep_time, mat, steel))
        print(
            f"  sphere, grid {grid.nx} x {grid.ny}: solve_normal (elastic, CG) {tn * 1e3:.1f} ms, "
            f"solve_viscoelastic V = 0 {te * 1e3:.1f} ms, V tc = a {tv * 1e3:.1f} ms "
            f"({rv.iterations} active-set it, {rv.fft_products} FFT products), mu_R = {rv.resistance_coefficient:.4g}"
        )


def wang_knothe() -> list:
    """CONTACT's visc_cylindr.inp (after Wang and Knothe 1993): two PA6 rollers R = 100 mm,
    G = 1143 N/mm^2 (glassy), fg = 1 (relaxed G/2 = 571.5), nu = 0.4, 600 N/mm, V = 1 m/s,
    creep times tc = 0, 0.009, 0.045, 2 s (the relaxation time is tc / 2). Normal part."""
    print("\nWang-Knothe polymer cylinders (normal part of CONTACT's visc_cylindr.inp), V = 1 m/s")
    out = []
    for tc in (1e-9, 0.009, 0.045, 2.0):
        pa6 = ViscoelasticMaterial(1143e6, 571.5e6, tc / 2.0, 0.4)
        r = solve_viscoelastic_line(0.05, 6e5, 1.0, pa6, pa6, n=600, half_length=8e-3)
        print(
            f"  tc = {tc:g} s: contact [{r.x_trailing * 1e3:.3f}, {r.x_leading * 1e3:.3f}] mm, "
            f"pmax {r.pmax / 1e6:.2f} MPa, e = {r.centroid * 1e3:.4f} mm, mu_R = {r.resistance_coefficient:.4g}"
        )
        out.append((tc, r))
    for g in (571.5e6, 1143e6):
        el = Material(shear_modulus=g, poisson=0.4)
        r = solve_viscoelastic_line(0.05, 6e5, 1.0, el, el, n=600, half_length=8e-3)
        print(
            f"  elastic G = {g / 1e6:g} N/mm^2: half-width {(r.x_leading - r.x_trailing) / 2 * 1e3:.3f} mm "
            f"(Hertz {line_hertz_half_width(0.05, 6e5, 2 * 0.6 / (2 * g)) * 1e3:.3f}), pmax {r.pmax / 1e6:.2f} MPa"
        )
    return out


def carter(kappa: np.ndarray) -> np.ndarray:
    """Carter (1926): |Fx| / (mu Fn) = 1 - (1 - kappa)^2 for kappa < 1, else 1."""
    k = np.minimum(kappa, 1.0)
    return 1.0 - (1.0 - k) ** 2


def wang_knothe_tangential() -> dict:
    """Creep curves of the two PA6 rollers (plane strain emulated by two rows 2000 a long, 100
    elements of 0.16 mm along x as in CONTACT's visc_cylindr.inp), mu = 0.3, V = 1 m/s, against
    Carter's curve with the relaxed and with the glassy modulus (the limits tc = 0, tc -> inf)."""
    print("\nWang-Knothe rollers, tangential (plane strain emulated), mu = 0.3, V = 1 m/s: Fx / (mu Fn)")
    fn_line, rr, mu, n, dx = 6e5, 0.05, 0.3, 100, 0.16e-3
    a_rel = line_hertz_half_width(rr, fn_line, 2 * 0.6 / (2 * 571.5e6))
    a_gl = line_hertz_half_width(rr, fn_line, 2 * 0.6 / (2 * 1143e6))
    dy = 2000 * a_rel
    grid = Grid(n, 2, dx, dy)
    x, _ = grid.mesh()
    gap = np.asfortranarray(x * x / (2 * rr))
    xis = np.linspace(0.0, 0.05, 11)[1:]
    out = {"xi": xis}
    for tc in (1e-9, 0.009, 0.045, 2.0):
        pa6 = ViscoelasticMaterial(1143e6, 571.5e6, tc / 2.0, 0.4)
        f = []
        for xi in xis:
            r = solve_viscoelastic_rolling(
                gap, grid, fn_line * 2 * dy, 1.0, (-xi, 0, 0), mu, pa6, pa6, strip=True
            )
            f.append(r.fx / (mu * r.normal.fn))
        out[tc] = np.array(f)
        print(f"  tc = {tc:g} s: " + " ".join(f"{v:.3f}" for v in f))
    for name, a in (("relaxed", a_rel), ("glassy", a_gl)):
        out[name] = carter(xis * rr / (mu * a))
        print(f"  Carter {name} (a = {a * 1e3:.3f} mm): " + " ".join(f"{v:.3f}" for v in out[name]))
    d0 = np.abs(out[1e-9] - out["relaxed"]).max()
    d2 = np.abs(out[2.0] - out["glassy"]).max()
    print(f"  largest difference to Carter: tc = 0 {d0:.4f}, tc = 2 s {d2:.4f} (of mu Fn)")
    return out


def figures(mat: ViscoelasticMaterial, tables: list, wk: list, wkt: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a = line_hertz_half_width(R, FN, mat.compliance_relaxed)
    p0 = 2 * FN / (np.pi * a)
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 4.6))
    ax = axes[0]
    for q, col in zip((0.0, 0.1, 1.0, 10.0, 1e6), ("k", "C0", "C1", "C2", "C3")):
        r = solve_viscoelastic_line(R, FN, q * a / mat.creep_time, mat, n=800, half_length=1.25 * a)
        label = {0.0: "V = 0 (relaxed Hertz)", 1e6: "V tc/a = 1e6 (glassy Hertz)"}.get(q, f"V tc/a = {q:g}")
        ax.plot(r.x / a, r.pressure / p0, color=col, label=label + " BEM")
        if 0 < q < 1e6:
            h = hunter_cylinder(R, FN, mat.compliance_instant, mat.compliance_relaxed, q * a)
            ax.plot(
                h.x[::40] / a,
                h.pressure[::40] / p0,
                "o",
                ms=3,
                color=col,
                mfc="none",
                label="Hunter (reduction)",
            )
    ax.set_xlabel("x / a_inf (rolling direction; leading edge at the right)")
    ax.set_ylabel("p / p0_inf")
    ax.set_title("Rigid cylinder on a standard linear solid, J0/Jinf = 1/3")
    ax.legend(fontsize=7)
    ax = axes[1]
    for tc, r in wk:
        ax.plot(r.x * 1e3, r.pressure / 1e6, label=f"tc = {tc:g} s" if tc > 1e-6 else "tc = 0")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("pressure (MPa)")
    ax.set_title("Two PA6 rollers (Wang-Knothe / CONTACT visc_cylindr), V = 1 m/s")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = HERE / "figures" / "contact_viscoelastic_pressure.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print("wrote", path)

    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for (ratio_label, rows), col in zip(tables, ("C0", "C1")):
        ax.semilogx(
            rows["dense"], rows["hunter_dense"], "-", color=col, label=f"Hunter (reduction), {ratio_label}"
        )
        ax.semilogx(rows["ratio"], rows["bem"], "o", color=col, mfc="none", label=f"BEM, {ratio_label}")
    ax.set_xlabel("V tc / a_inf (tc creep time, a_inf relaxed Hertz half-width)")
    ax.set_ylabel("e / a_inf = mu_R R / a_inf")
    ax.set_title("Rolling resistance of a rigid cylinder (Hunter 1961)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = HERE / "figures" / "contact_viscoelastic_resistance.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print("wrote", path)

    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for tc, col in zip((1e-9, 0.009, 0.045, 2.0), ("C0", "C1", "C2", "C3")):
        ax.plot(
            wkt["xi"], wkt[tc], "o-", color=col, label=f"BEM, tc = {tc:g} s" if tc > 1e-6 else "BEM, tc = 0"
        )
    ax.plot(wkt["xi"], wkt["relaxed"], "k--", label="Carter, relaxed G = 571.5 MPa")
    ax.plot(wkt["xi"], wkt["glassy"], "k:", label="Carter, glassy G = 1143 MPa")
    ax.set_xlabel("longitudinal creepage |xi|")
    ax.set_ylabel("|Fx| / (mu Fn)")
    ax.set_title("Two PA6 rollers (Wang-Knothe), V = 1 m/s, mu = 0.3")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = HERE / "figures" / "contact_viscoelastic_creep.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print("wrote", path)


def main() -> None:
    poly3 = ViscoelasticMaterial(3.0e9, 1.0e9, 0.01, 0.4)
    poly10 = ViscoelasticMaterial(10.0e9, 1.0e9, 0.01, 0.4)
    tables = [("J0/Jinf = 1/3", hunter_table(poly3)), ("J0/Jinf = 1/10", hunter_table(poly10))]
    strip_check(poly3)
    wk = wang_knothe()
    wkt = wang_knothe_tangential()
    timing(poly3)
    figures(poly3, tables, wk, wkt)


if __name__ == "__main__":
    main()
