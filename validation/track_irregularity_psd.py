"""Generated track irregularities against their target spectra (issue 34, item 1).

For ERRI B176 low and high and FRA classes 4 and 6: 10 tracks of 4096 m (seeds 0-9, band
3-70 m, dx 0.25 m), each channel's Welch PSD (Hann, 2048 m segments, half overlap) averaged
over the seeds, against the target PSD. Prints, per spectrum and channel, the deviation in dB
of the band-averaged sample PSD from the band-averaged target in each octave band from 3 to
70 m, the rms from the PSD's integral and the sample rms. Writes the chart
validation/figures/track_irregularity_psd.png (log-log against wavelength; below: 200 m of
one ERRI low track).

    python validation/track_irregularity_psd.py
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.signal import welch  # noqa: E402

from railvti.track import CHANNELS  # noqa: E402
from railvti.track import irregularity_spectra as irs  # noqa: E402

FIG = Path(__file__).parent / "figures"
SPECTRA = ("erri-b176-low", "erri-b176-high", "fra-4", "fra-6")
COLORS = dict(zip(SPECTRA, ("tab:blue", "tab:red", "tab:green", "tab:purple"), strict=True))
LENGTH, DX, SEEDS, BAND = 4096.0, 0.25, range(10), (3.0, 70.0)
OCTAVES = [(3.0, 6.0), (6.0, 12.0), (12.0, 24.0), (24.0, 48.0), (48.0, 70.0)]
NPERSEG = 8192  # 2048 m
TICKS = (1, 3, 10, 30, 70, 300)


def sample_psd(spectrum: str) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, float]]:
    """Omega (rad/m) and, per channel, the seed-averaged Welch PSD (m^2/(rad/m)) and variance."""
    psd = {c: 0.0 for c in CHANNELS}
    var = {c: 0.0 for c in CHANNELS}
    for seed in SEEDS:
        tr = irs.generate(spectrum, LENGTH, seed=seed, band=BAND, dx=DX)
        for c in CHANNELS:
            f, p = welch(getattr(tr, c), fs=1.0 / DX, window="hann", nperseg=NPERSEG, detrend=False)
            psd[c] = psd[c] + p / (2.0 * math.pi) / len(SEEDS)
            var[c] += getattr(tr, c).var() / len(SEEDS)
    return 2.0 * math.pi * f, psd, var


def main() -> None:
    FIG.mkdir(exist_ok=True)
    fig = plt.figure(figsize=(12, 11))
    grid = fig.add_gridspec(3, 2, height_ratios=[1, 1, 0.8])
    axes = [fig.add_subplot(grid[i // 2, i % 2]) for i in range(4)]
    wave = np.geomspace(1.0, 500.0, 400)
    worst = 0.0
    print(f"{'spectrum':15s} {'channel':15s} " + " ".join(f"{lo:g}-{hi:g} m".rjust(9) for lo, hi in OCTAVES))
    for sp in SPECTRA:
        omega, psd, var = sample_psd(sp)
        for ax, c in zip(axes, CHANNELS, strict=True):
            ax.loglog(
                wave, irs.psd(sp, c, 2 * math.pi / wave), color=COLORS[sp], lw=1.2, label=f"{sp} target"
            )
            keep = omega > 0
            ax.loglog(2 * math.pi / omega[keep], psd[c][keep], color=COLORS[sp], lw=0, marker=".", ms=2.5)
            dbs = []
            for lo, hi in OCTAVES:
                sel = (omega >= 2 * math.pi / hi) & (omega <= 2 * math.pi / lo)
                dbs.append(10 * math.log10(psd[c][sel].mean() / irs.psd(sp, c, omega[sel]).mean()))
            worst = max(worst, max(abs(d) for d in dbs))
            rms_target = math.sqrt(irs.band_variance(sp, c, BAND)) * 1e3
            print(
                f"{sp:15s} {c:15s} "
                + " ".join(f"{d:+9.2f}" for d in dbs)
                + f"   rms {rms_target:6.2f} mm (sample {math.sqrt(var[c]) * 1e3:6.2f} mm)"
            )
    print(f"worst octave deviation: {worst:.2f} dB (acceptance: 2 dB)")
    for ax, c in zip(axes, CHANNELS, strict=True):
        ax.axvspan(BAND[0], BAND[1], color="0.92", zorder=0)
        ax.set_xlim(500, 1)  # long waves left, short right
        ax.set_ylim(1e-12, 1e-2)
        ax.set_title(c.replace("_", " "))
        ax.set_xlabel("wavelength (m)")
        ax.set_ylabel("PSD, one-sided (m$^2$/(rad/m))")
        ax.set_xticks(TICKS, [f"{t:g}" for t in TICKS])
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize=8, loc="lower left")
    tr = irs.generate("erri-b176-low", LENGTH, seed=0, band=BAND, dx=DX)
    ax = fig.add_subplot(grid[2, :])
    sel = tr.x <= 200.0
    for c in CHANNELS:
        ax.plot(tr.x[sel], 1e3 * getattr(tr, c)[sel], lw=0.9, label=c.replace("_", " "))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("irregularity (mm)")
    ax.set_title("erri-b176-low, seed 0, band 3-70 m: the first 200 m")
    ax.legend(fontsize=8, ncol=4, loc="upper right")
    ax.grid(True, lw=0.3)
    fig.suptitle(
        f"Generated irregularities against their spectra: lines target, dots Welch over 10 seeds x {LENGTH:g} m "
        f"(shaded: the band 3-70 m; worst octave: {worst:.2f} dB)",
        fontsize=11,
    )
    fig.tight_layout()
    out = FIG / "track_irregularity_psd.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
