"""Creep-force curves with falling friction: the Eurosprinter test case (Polach 2005).

Polach, "Creep forces in simulations of traction vehicles running on adhesion limit",
Wear 258 (2005) 992-1000, fitted his model to traction measurements of the Eurosprinter
locomotive (SBB 460 / Siemens ES64) on dry and wet rails. His friction law
``mu = mu0 ((1 - A) exp(-B w) + A)`` (w the slip velocity) and reduction factors
k_A, k_S of the creep stiffness (dry: mu0 0.55, A 0.40, B 0.60 s/m, k_A 1.00, k_S 0.40;
wet: mu0 0.30, A 0.40, B 0.20 s/m, k_A 0.30, k_S 0.10: his Table 2 as recalled; the
paper's text could not be opened here to check them) are used with:

* the BEM steady rolling solver with the falling law (``railvti.contact.friction``),
  without slope reduction (the elastic half-space has none);
* the FASTSIM variant with the falling law and the slope reduction (k_A + k_S) / 2;
* Polach's closed-form creep force with k_A, k_S (the independent reference).

Contact: wheel radius 0.625 m (ES64: 1250 mm wheels), rail crown radius 0.3 m, wheel
load 100 kN, steel G = 82 GPa, nu = 0.28, V = 40 km/h, pure longitudinal creepage (the
contact geometry and speed are this script's choices; Polach's measured points are not
reproduced: the paper's figures are not available here, so the check is model against
model). The script prints the curves' maxima, the creepage at the maximum, F/Q at 10 %,
the convergence and the count of elements with several solutions at every creepage, and
draws validation/figures/contact_friction_eurosprinter.png; then, for three steep laws whose
element problems have several solutions, the BEM curves with both rules (smallest slip,
continuous with the iterate) and where they converge: validation/figures/contact_friction_rules.png.

Run: ``PYTHONPATH=_site python validation/contact_friction.py [--n 40]``
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from railvti.contact import Grid, hertz, hertz_gap
from railvti.contact.friction import FrictionLaw, creep_curve_friction, fastsim_friction, polach_creep_force
from railvti.material import Material

MAT = Material(shear_modulus=82e9, poisson=0.28)
GAP_A, GAP_B, FN, SPEED = 0.5 / 0.625, 0.5 / 0.3, 100e3, 40.0 / 3.6
#: Polach 2005, Table 2 (Eurosprinter): mu0, A, B (s/m), k_A, k_S
CASES = {"dry": (0.55, 0.40, 0.60, 1.00, 0.40), "wet": (0.30, 0.40, 0.20, 0.30, 0.10)}
FIG = Path(__file__).resolve().parent / "figures" / "contact_friction_eurosprinter.png"
FIG_STEEP = FIG.with_name("contact_friction_rules.png")
#: Laws whose element problems have several solutions (k p V max|mu'| >> 1) and the speed, m/s
STEEP = {
    "jump law mu_s 0.5, mu_k 0.3": (FrictionLaw("coulomb", 0.5, 0.3), 30.0),
    "exponential 0.5 -> 0.1, v_h 0.5 mm/s": (FrictionLaw("exponential", 0.5, 0.1, 5e-4), 50.0),
    "rational 0.5 -> 0.2, v_h 10 mm/s": (FrictionLaw("rational", 0.5, 0.2, 1e-2), 30.0),
}


def curves(n: int) -> dict:
    h = hertz(GAP_A, GAP_B, FN, MAT)
    dx, dy = 2.4 * h.a / n, 2.4 * h.b / n
    grid = Grid(n, n, dx, dy, -1.15 * h.a, -1.2 * h.b + dy / 2)
    gap = hertz_gap(grid, GAP_A, GAP_B)
    xi = np.concatenate([np.geomspace(2e-4, 5e-3, 12), np.linspace(6e-3, 0.1, 20)])
    out = {"xi": xi, "a": h.a, "b": h.b}
    for name, (mu0, a, b, ka, ks) in CASES.items():
        law = FrictionLaw.polach(mu0, a, b)
        t = time.perf_counter()
        c = creep_curve_friction(gap, grid, MAT, law, FN, xi, SPEED)
        t_bem = (time.perf_counter() - t) / len(xi)
        fs, *_, nm_fs = fastsim_friction(
            h.a, h.b, MAT, law, FN, (xi, 0, 0), SPEED, slope_reduction=0.5 * (ka + ks)
        )
        pol = polach_creep_force(FN, h.a, h.b, MAT, mu0, a, b, ka, ks, SPEED, xi)
        out[name] = dict(bem=-c.fx / FN, conv=c.converged, nmult=c.n_multiple, it=c.iterations, t_bem=t_bem,
                         fastsim=-fs / FN, nm_fs=nm_fs, polach=pol / FN)  # fmt: skip
    return out


def report(out: dict) -> None:
    xi = out["xi"]
    print(
        f"Hertz a = {out['a'] * 1e3:.2f} mm, b = {out['b'] * 1e3:.2f} mm, Q = {FN / 1e3:g} kN, V = {SPEED:.2f} m/s"
    )
    print(f"{'case':5s} {'model':22s} {'max F/Q':>8s} {'at xi %':>8s} {'F/Q @10%':>9s}")
    for name in CASES:
        r = out[name]
        for key, label in (("bem", "BEM falling friction"), ("fastsim", "FASTSIM falling+slope"),
                           ("polach", "Polach formula")):  # fmt: skip
            f = r[key]
            k = int(np.argmax(f))
            print(f"{name:5s} {label:22s} {f[k]:8.4f} {xi[k] * 100:8.3f} {f[-1]:9.4f}")
        print(
            f"      BEM: converged at {int(r['conv'].sum())}/{len(xi)} creepages, sweeps {r['it'].min()}-"
            f"{r['it'].max()}, elements with several solutions: max {int(r['nmult'].max())}; "
            f"{r['t_bem'] * 1e3:.1f} ms per creepage; FASTSIM several solutions: max {int(r['nm_fs'].max())}"
        )
        d = np.abs(r["fastsim"] - r["polach"]).max()
        print(
            f"      |FASTSIM variant - Polach| max {d:.4f} Q; |BEM - Polach| max {np.abs(r['bem'] - r['polach']).max():.4f} Q"
        )


def chart(out: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xi = out["xi"] * 100
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), sharex=True)
    for ax, name in zip(axes, CASES):
        mu0, a, b, ka, ks = CASES[name]
        r = out[name]
        ax.plot(xi, r["bem"], "o-", ms=3, label="BEM, falling friction (no slope reduction)")
        ax.plot(
            xi, r["fastsim"], "s--", ms=3, label=f"FASTSIM, falling friction, slope x {0.5 * (ka + ks):.2f}"
        )
        ax.plot(xi, r["polach"], "k-", lw=1.5, label=f"Polach's formula, k_A = {ka}, k_S = {ks}")
        ax.set_title(f"Eurosprinter {name}: mu0 = {mu0}, A = {a}, B = {b} s/m", fontsize=10)
        ax.set_xlabel("longitudinal creepage (%)")
        ax.set_ylabel("creep force / wheel load  F/Q (1)")
        ax.set_ylim(0, 1.1 * mu0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    fig.suptitle(
        "Creep-force curves with slip-velocity-dependent friction (Polach 2005 parameters), "
        f"Q = {FN / 1e3:g} kN, V = {SPEED * 3.6:.0f} km/h",
        fontsize=11,
    )
    fig.tight_layout()
    FIG.parent.mkdir(exist_ok=True)
    fig.savefig(FIG, dpi=110)
    print(f"wrote {FIG}")


def steep(n: int) -> None:
    """Both rules on laws with several element solutions: convergence and the count."""
    import dataclasses

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = hertz(GAP_A, GAP_B, FN, MAT)
    dx, dy = 2.4 * h.a / n, 2.4 * h.b / n
    grid = Grid(n, n, dx, dy, -1.15 * h.a, -1.2 * h.b + dy / 2)
    gap = hertz_gap(grid, GAP_A, GAP_B)
    xi = np.concatenate([np.geomspace(2e-4, 5e-3, 10), np.linspace(7e-3, 0.05, 8)])
    fig, axes = plt.subplots(1, len(STEEP), figsize=(14, 4.2))
    print("\nlaws with several element solutions (both rules, warm-started along the curve):")
    for ax, (name, (law, v)) in zip(axes, STEEP.items()):
        for rule, style in (("smallest", "o--"), ("continuous", "s-")):
            c = creep_curve_friction(gap, grid, MAT, dataclasses.replace(law, root_rule=rule), FN, xi, v)
            f = -c.fx / FN
            (line,) = ax.plot(xi * 100, f, style, ms=3, label=f"rule '{rule}'")
            bad = ~c.converged
            ax.plot(xi[bad] * 100, f[bad], "x", color=line.get_color(), ms=9, mew=2)
            print(
                f"  {name:38s} {rule:10s}: converged {int(c.converged.sum())}/{len(xi)}, "
                f"several solutions at up to {int(c.n_multiple.max())} elements"
            )
        ax.set_title(f"{name}, V = {v:g} m/s", fontsize=9)
        ax.set_xlabel("longitudinal creepage (%)")
        ax.set_ylabel("F/Q (1)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, title="x: not converged (2000 sweeps)", title_fontsize=8)
    fig.suptitle(
        f"BEM creep curves for steep friction laws: the two rules for several element solutions (Q = {FN / 1e3:g} kN)"
    )
    fig.tight_layout()
    fig.savefig(FIG_STEEP, dpi=110)
    print(f"wrote {FIG_STEEP}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=40, help="BEM elements along each axis of the grid")
    args = ap.parse_args()
    out = curves(args.n)
    report(out)
    chart(out)
    steep(args.n)


if __name__ == "__main__":
    main()
