"""The flexible wheelset in the coach against railvti.wheelset: FRF peaks (issue 14, dynamic
acceptance).

The coupled model FR (``build_fr``: free-free modes k_max 2 / 800 Hz of the leading wheelset
with its residual flexibility, journal springs to the moving bogie, Coriolis couplings and the
rigid wheelset's gyroscopic term), the wheel-rail contact removed, linearised
(``flexible_linear.linear_matrices``): the lateral point receptance at the right wheel's contact point
(force on the rigid wheelset and the rim, response rigid + elastic), at rest and at 300 km/h.
Reference: ``Wheelset.frf`` (the axle-fixed model, eq. 11: modes of the wheelset on its primary
springs grounded to a fixed bogie, k <= 6, f <= 3000 Hz, modal damping 0.5 %).

Same wheelset in both: the coach's wheelset mass and inertias are set to the FE wheelset's
(``analytic.wheelset_mass_properties``; the benchmark coach's 1813 kg / 1120 kg m^2 include
axle boxes and discs the FE mesh does not have) and the primary dampers are removed (the
reference's suspension is springs only). Also printed: the default coach (its own inertias
and dampers), which moves the k = 1 pair and the 560 Hz mode.

Peaks: local maxima of |H| (prominence of log |H| >= 0.5) between 60 and 600 Hz on a
0.05 Hz grid, refined by a parabola; each reference peak is matched with the nearest
coupled one. Labels: the harmonic k with the largest share of the reference model's
eigenvector nearest to the peak.

Run: .venv/bin/python validation/wheelset_fr_frf.py   (about 2 min; writes
validation/figures/wheelset_fr_frf.png)
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.linalg import eig  # noqa: E402
from scipy.signal import find_peaks  # noqa: E402

from railvti import scenarios  # noqa: E402
from railvti.vehicle.flexible import build_fr  # noqa: E402
from railvti.vehicle.flexible_linear import contact_receptance  # noqa: E402
from railvti.vehicle.params import Coach  # noqa: E402
from railvti.wheelset import Wheelset, analytic  # noqa: E402

FIG = Path(__file__).resolve().parent / "figures"
FIG.mkdir(exist_ok=True)
F = np.arange(40.0, 620.0, 0.05)
BAND = (60.0, 600.0)


def peaks(f: np.ndarray, h: np.ndarray, prominence: float = 0.5) -> np.ndarray:
    """Peak frequencies of |h| in BAND (parabola through the three grid points), Hz."""
    a = np.log(np.abs(h))
    idx, _ = find_peaks(a, prominence=prominence)
    out = []
    for j in idx:
        if not BAND[0] <= f[j] <= BAND[1]:
            continue
        y0, y1, y2 = a[j - 1], a[j], a[j + 1]
        out.append(f[j] + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2) * (f[1] - f[0]))
    return np.array(out)


def harmonic_of(model, fpk: float) -> str:
    """The harmonic (and family at speed) of the reference eigenvector nearest fpk."""
    n = model.k.size
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-model.stiffness, -(model.gyro + model.damping)]])
    lam, vec = eig(a)
    i = np.argmin(np.abs(np.abs(lam.imag) / (2 * np.pi) - fpk))
    w = np.abs(vec[:n, i]) ** 2
    ks = {int(k): w[model.k == k].sum() for k in np.unique(model.k)}
    return f"k={max(ks, key=ks.get)}"


def fe_coach(ws: Wheelset, dampers: bool) -> Coach:
    mp = analytic.wheelset_mass_properties(ws.geometry)
    kw = dict(
        wheelset_mass=mp["mass"],
        wheelset_roll_inertia=mp["roll_inertia"],
        wheelset_yaw_inertia=mp["roll_inertia"],
        wheelset_pitch_inertia=mp["spin_inertia"],
    )
    if not dampers:
        kw.update(primary_cx=0.0, primary_cy=0.0, primary_cz=0.0)
    return Coach(**kw)


def main() -> None:
    ws = Wheelset()
    table = scenarios.wheel_table()
    fig, axes = plt.subplots(2, 1, figsize=(10, 8), sharex=True)
    worst = 0.0
    for ax, kmh in zip(axes, (0.0, 300.0)):
        v = kmh / 3.6
        t0 = time.perf_counter()
        ref_model = ws.axle_fixed(v)
        h_ref = ws.frf(F, v, "lateral", "lateral", model=ref_model)
        sy, lay = build_fr(fe_coach(ws, dampers=False), table, v, flexible=(0,), wheelset=ws)
        h_fr = contact_receptance(sy, lay[0], F)
        sy_d, lay_d = build_fr(Coach(), table, v, flexible=(0,), wheelset=ws)
        h_d = contact_receptance(sy_d, lay_d[0], F)
        p_ref, p_fr, p_d = peaks(F, h_ref), peaks(F, h_fr, 0.1), peaks(F, h_d, 0.1)
        print(
            f"\n{kmh:.0f} km/h ({time.perf_counter() - t0:.0f} s): lateral receptance at "
            "the right wheel, peaks 60-600 Hz"
        )
        print("  harmonic | reference Hz | FR (same wheelset) Hz | error | FR (default coach) Hz | error")
        for fp in p_ref:
            a = p_fr[np.argmin(np.abs(p_fr - fp))]
            b = p_d[np.argmin(np.abs(p_d - fp))]
            worst = max(worst, abs(a / fp - 1.0))
            print(
                f"  {harmonic_of(ref_model, fp):8s} | {fp:12.2f} | {a:21.2f} | "
                f"{100 * (a / fp - 1):+.3f} % | {b:21.2f} | {100 * (b / fp - 1):+.2f} %"
            )
        ax.semilogy(
            F, np.abs(h_ref), "k-", lw=2.5, alpha=0.35, label="railvti.wheelset (axle-fixed, fixed bogie)"
        )
        ax.semilogy(F, np.abs(h_fr), "C0-", lw=1.0, label="FR in the coach, same wheelset, contact removed")
        ax.semilogy(
            F, np.abs(h_d), "C3:", lw=1.0, label="FR in the default coach (its inertias, primary dampers)"
        )
        for fp in p_ref:
            ax.axvline(fp, color="0.8", lw=0.5, zorder=0)
        ax.set_title(f"Lateral point receptance at the right contact point, {kmh:.0f} km/h")
        ax.set_ylabel("|H|, m/N")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("frequency, Hz")
    fig.tight_layout()
    fig.savefig(FIG / "wheelset_fr_frf.png", dpi=120)
    print(f"\nlargest peak-frequency error, same wheelset: {100 * worst:.3f} % (acceptance: 1 %)")


if __name__ == "__main__":
    main()
