"""The standards' weighting filters (railvti.assessment.filters): their magnitudes against the
tabulated reference values and closed forms, analogue and digital.

Plots EN 12299's Wb, Wc, Wd, Wp, ISO 2631-4's Wb and ISO 2631-1's Wk (analogue chains,
solid; their digital forms at 500 Hz, dashed) with the ISO 8041 reference values (the value
at 100 rad/s of Wb (ISO 2631-4), Wc, Wd; Wk at 6.31 Hz, ISO 8041-1 Table B.8), and
Sperling's B(f) (vertical, lateral) with the weighting his piecewise frequency factor F(f)
implies, (0.896^10 F(f) / f)^(1/3). Prints each reference point's deviation in dB and the
largest digital-analogue deviation up to fs/20. Writes
validation/figures/assessment_filters.png.

    python validation/assessment_filters.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from railvti.assessment import sperling, weighting

ROOT = Path(__file__).resolve().parent.parent
FS = 500.0
REF = [
    ("Wb_iso2631_4", 100 / (2 * math.pi), 0.8126),
    ("Wc", 100 / (2 * math.pi), 0.5145),
    ("Wd", 100 / (2 * math.pi), 0.1261),
    ("Wk_iso2631_1", 10**0.8, 1.054),
]


def _piecewise_b(f: np.ndarray, direction: str) -> np.ndarray:
    """The weighting Sperling's piecewise F(f) implies: B^3 = 0.896^10 F(f) / f."""
    if direction == "vertical":
        fac = np.where(f < 5.9, 0.325 * f**2, np.where(f < 20.0, 400.0 / f**2, 1.0))
    else:
        fac = np.where(f < 5.4, 0.8 * f**2, np.where(f < 26.0, 650.0 / f**2, 1.0))
    return (0.896**10 * fac / f) ** (1.0 / 3.0)


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    f = np.logspace(-1, 2, 400)
    fd = f[f <= FS / 2.2]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.2))
    names = ["Wb", "Wb_iso2631_4", "Wc", "Wd", "Wp", "Wk_iso2631_1"]
    colors = dict(zip(names, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    for n in names:
        w = weighting(n)
        label = {
            "Wb": "Wb (EN 12299)",
            "Wb_iso2631_4": "Wb (ISO 2631-4)",
            "Wk_iso2631_1": "Wk (ISO 2631-1)",
        }.get(n, n + " (EN 12299)")
        ax1.loglog(f, np.abs(w.response(f)), color=colors[n], label=label)
        ax1.loglog(fd, np.abs(w.digital_response(fd, FS)), "--", color=colors[n], lw=0.8)
    print("reference point                 f (Hz)   tabulated   railvti    dB")
    for n, fr, v in REF:
        h = abs(weighting(n).response([fr])[0])
        ax1.plot(fr, v, "o", mfc="none", color=colors[n], ms=8)
        print(f"{n:<28} {fr:8.3f} {v:11.4f} {h:9.4f} {20 * math.log10(h / v):+6.3f}")
    ax1.plot([], [], "ko", mfc="none", label="ISO 8041 reference values")
    ax1.plot([], [], "k--", lw=0.8, label=f"digital, {FS:g} Hz")
    ax1.set(xlabel="frequency, Hz", ylabel="|W(f)|", title="comfort weightings", ylim=(1e-2, 2))
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=8, loc="lower center")
    print("\nSperling: continuous B(f) against the piecewise F(f) of his Wz = 0.896 (a^3 F/f)^0.1")
    for direction, c in (("vertical", "C0"), ("lateral", "C3")):
        s = sperling(direction)
        ax2.loglog(f, np.abs(s.response(f)), color=c, label=f"B(f) {direction}")
        ax2.loglog(fd, np.abs(s.digital_response(fd, FS)), "--", color=c, lw=0.8)
        fp = np.logspace(np.log10(0.5), np.log10(30.0), 16)
        bp = _piecewise_b(fp, direction)
        ax2.plot(fp, bp, "s", mfc="none", color=c, label=f"Sperling's piecewise F, {direction}")
        dev = 20 * np.log10(np.abs(s.response(fp)) / bp)
        wz = 100 * ((10 ** (np.abs(dev) / 20)) ** 0.3 - 1)
        for lo, hi in ((0.5, 20.0), (20.0, 30.0)):
            k = (fp >= lo) & (fp < hi)
            i = int(np.argmax(np.abs(dev[k])))
            print(
                f"  {direction:<9} {lo:g}-{hi:g} Hz: |dB| max {abs(dev[k][i]):.2f} at {fp[k][i]:.2f} Hz "
                f"(Wz, exponent 0.3: {wz[k][i]:.1f} %)"
            )
    ax2.set(xlabel="frequency, Hz", ylabel="|B(f)|", title="Sperling's weighting", ylim=(0.05, 2))
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=8, loc="lower center")
    worst = 0.0
    for n in names:
        w = weighting(n)
        fq = 10 ** (np.arange(-3, 20) / 10.0)
        fq = fq[fq <= FS / 20]
        worst = max(
            worst, float(np.max(np.abs(20 * np.log10(np.abs(w.digital_response(fq, FS) / w.response(fq))))))
        )
    print(
        f"\ndigital ({FS:g} Hz) against analogue, 1/3-octave points up to {FS / 20:g} Hz: max {worst:.3f} dB"
    )
    fig.tight_layout()
    out = ROOT / "validation" / "figures" / "assessment_filters.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
