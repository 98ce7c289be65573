"""Model RF's truncated ring against the ring's direct FRF (issue 15, acceptance point 2).

The contact point of a wheel on the ring sees the kept ring modes (``ring_rows``: the modes
up to ``f_limit``, rows = the element pose (y, z, roll) under the wheel) plus the truncated
modes' static compliance tabulated over a bay (``RingRows.residual_rows``, the residual
flexibility of model RF). Its point receptance is then

    H_RF(f) = Phi_k diag(1 / (lambda_r - w^2 + i w c_r)) Phi_k^T + R(x)

in the pose coordinates, mapped to the crown's (u_y, u_z) by the element's arms. The direct
FRF is the ring's, all modes of its modal form: ``RingTrack.head_receptance`` (one rail's
head loaded, the Fortran ``ring_frf`` over RingTrack.head_shapes) and ``RingTrack.receptance``
(both rails loaded in the 'vertical' / 'lateral' pattern; RF keeps no truncated compliance
between two contact points, so its pattern receptance lacks the cross-rail part of R).

With ``ring_residual_inertia`` the residual coordinates also carry the truncated modes'
first-order inertia and damping (``residual_blocks``: a 3 x 3 mass and damper per point,
averaged over the bay), H_RF = ... + L (K_z - w^2 I + i w C_z)^-1 L^T.

Printed per case (vertical / lateral, midspan / above a sleeper) and residual (static,
inertia): the largest relative error up to f_limit / 2 and the frequency up to which it
stays within 2 %; then, at the point itself, the same error with the truncated modes exact
but undamped, with their first-order damping (-i w sum phi^2 c / lambda^2) and inertia
(+ w^2 sum phi^2 / lambda^2) alone and together. Writes
validation/figures/track_modal_receptance.png.

    python validation/track_modal_receptance.py [--n-sleepers 40] [--f-limit 500] [--f-max 3000]
        [--figure validation/figures/track_modal_receptance.png]
"""

from __future__ import annotations

import argparse
import logging
import math
import time
from pathlib import Path

import numpy as np

from railvti.track import RingTrack
from railvti.vehicle.ring_coupling import residual_blocks, ring_rows

FIG = Path(__file__).parent / "figures"
#: (name, vehicle-frame crown component, RingTrack row) of the two directions.
DIRECTIONS = (("vertical", 1, 2), ("lateral", 0, 1))


def rf_point_receptance(
    track: RingTrack,
    x: float,
    freqs: np.ndarray,
    f_limit: float,
    residual: bool = True,
    inertia: bool = False,
) -> np.ndarray:
    """Receptance (nf, 2, 3, 3) of the crown (u_y, u_z, roll; vehicle frame) under each wheel
    of a wheelset at x, from model RF's rows and residual blocks (``residual_blocks``: static,
    or with the truncated modes' inertia and damping); [f, wheel, resp, load]."""
    rr = ring_rows(track, np.array([x]), 1.0, f_limit=f_limit, residual=residual)
    rows = rr.rows(0.0)[0]  # (3, 2, nk)
    w = 2 * math.pi * np.asarray(freqs)
    den = track.lam[rr.modes][None] - w[:, None] ** 2 + 1j * w[:, None] * track.cmod[rr.modes][None]
    half = 0.5 * track.params["rail_distance"]
    out = np.empty((w.size, 2, 3, 3), complex)
    if residual and rr.n_residual:
        rr, stiff, damp = residual_blocks(rr, 1.0, None, inertia)
        lres = rr.residual_rows(0.0)[0]
    mass = np.eye(3) if inertia else np.zeros((3, 3))
    for k in range(2):
        yp = half if k == 0 else -half
        ei = np.linalg.inv(np.array([[1, 0, 0], [0, 1, -yp], [0, 0, 1.0]]))  # pose -> crown
        ph = rows[:, k, :]
        h = np.einsum("im,fm,jm->fij", ph, 1.0 / den, ph)
        if residual and rr.n_residual:
            lr = lres[:, :, k]
            blk = stiff[k][None] - w[:, None, None] ** 2 * mass + 1j * w[:, None, None] * damp[k]
            h = h + np.einsum("ab,fbc,dc->fad", lr, np.linalg.inv(blk), lr)
        out[:, k] = np.einsum("ab,fbc,dc->fad", ei, h, ei)
    return out


def rf_pattern_receptance(
    track: RingTrack, x: float, freqs: np.ndarray, f_limit: float, direction: str, inertia: bool = False
) -> np.ndarray:
    """RingTrack.receptance's load pattern from model RF's rows: kept modes with both rails'
    rows, the residual compliance of the right rail's point only (RF has no cross term)."""
    rr = ring_rows(track, np.array([x]), 1.0, f_limit=f_limit)
    rows = rr.rows(0.0)[0]
    w = 2 * math.pi * np.asarray(freqs)
    den = track.lam[rr.modes][None] - w[:, None] ** 2 + 1j * w[:, None] * track.cmod[rr.modes][None]
    half = 0.5 * track.params["rail_distance"]
    crown = [rows[1, k] + (half if k == 0 else -half) * rows[2, k] for k in range(2)]  # u_z
    point = rf_point_receptance(track, x, freqs, f_limit, inertia=inertia)
    if direction == "vertical":  # F_z = 1 on both, u_z of the right rail (wheel 1)
        kept_cross = (crown[1] * crown[0] / den).sum(1)
        return point[:, 1, 1, 1] + kept_cross
    # outward forces, ring y of the right rail = -vehicle y: H_RR - H_RL (vehicle y)
    kept_cross = (rows[0, 1] * rows[0, 0] / den).sum(1)
    return point[:, 1, 0, 0] - kept_cross


def decomposition(
    track: RingTrack, x: float, freqs: np.ndarray, f_limit: float, row: int
) -> dict[str, np.ndarray]:
    """Why the truncation errs: the right rail's point receptance (track frame row ``row``)
    with the truncated modes static (model RF), exact undamped, with a residual damper, with
    a residual mass and with both (first order in w c / lambda and w^2 / lambda)."""
    h = track.head_shapes(x, 2)[row]
    g = h * h
    w = 2 * math.pi * np.asarray(freqs)[:, None]
    lam, c = track.lam[None], track.cmod[None]
    keep = np.sqrt(track.lam) <= 2 * math.pi * f_limit
    t = ~keep
    kept = (g[keep] / (lam[:, keep] - w**2 + 1j * w * c[:, keep])).sum(1)
    stat = (g[t] / lam[0, t]).sum()
    damp = (-1j * w * g[t] * c[:, t] / lam[:, t] ** 2).sum(1)
    mass = (w**2 * g[t] / lam[:, t] ** 2).sum(1)
    full = (g / (lam - w**2 + 1j * w * c)).sum(1)
    return {
        "full": full,
        "static residual (RF)": kept + stat,
        "exact undamped truncated": kept + (g[t] / (lam[:, t] - w**2)).sum(1),
        "+ residual damper": kept + stat + damp,
        "+ residual mass": kept + stat + mass,
        "+ damper + mass": kept + stat + damp + mass,
        "no residual": kept,
        "share": np.array(stat / full[0].real),
    }


def within(err: np.ndarray, freqs: np.ndarray, tol: float = 0.02) -> float:
    """The frequency up to which err stays within tol (the last one checked if it always does)."""
    bad = np.where(err > tol)[0]
    return float(freqs[-1]) if bad.size == 0 else float(freqs[max(bad[0] - 1, 0)])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n-sleepers", type=int, default=40, help="sleepers on the ring (RF default 40)")
    ap.add_argument("--f-limit", type=float, default=500.0, help="kept modes up to, Hz (RF default 500)")
    ap.add_argument("--f-max", type=float, default=3000.0, help="the ring's modal form up to, Hz")
    ap.add_argument("--figure", default=str(FIG / "track_modal_receptance.png"), help="chart to write")
    args = ap.parse_args()
    logging.disable(logging.WARNING)
    t0 = time.perf_counter()
    track = RingTrack(args.n_sleepers, f_max=args.f_max)
    fl = args.f_limit
    a = track.params["sleeper_spacing"]
    nk = int(np.sum(np.sqrt(track.lam) <= 2 * math.pi * fl))
    print(
        f"ring n_sl = {args.n_sleepers}, f_max = {args.f_max:g} Hz: {track.n_modes} modes "
        f"(build {time.perf_counter() - t0:.1f} s); model RF keeps {nk} up to f_limit = {fl:g} Hz"
    )
    f = np.linspace(0.0, 0.5 * fl, 251)
    fwide = np.linspace(1.0, min(1.5 * fl, args.f_max), 600)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 2, figsize=(12, 12))
    print(
        f"{'case':28s} {'residual':9s} {'max err <= f_limit/2':>21s} {'2 % holds to':>13s}  "
        f"{'pattern (RingTrack.receptance)':>31s}"
    )
    for j, (pos, x) in enumerate((("midspan", 0.5 * a), ("above a sleeper", 0.0))):
        for i, (name, comp, row) in enumerate(DIRECTIONS):
            direct = track.head_receptance(f, x, 2)[:, row, row]
            pdir = track.receptance(f, name, x)
            errs = {}
            for kind, inertia in (("static", False), ("inertia", True)):
                rf = rf_point_receptance(track, x, f, fl, inertia=inertia)[:, 1, comp, comp]
                err = errs[kind] = np.abs(rf / direct - 1)
                prf = rf_pattern_receptance(track, x, f, fl, name, inertia=inertia)
                perr = np.abs(prf / pdir - 1)
                print(
                    f"{name + ', ' + pos:28s} {kind:9s} {err.max() * 100:12.2f} % at "
                    f"{f[err.argmax()]:4.0f} Hz {within(err, f):9.0f} Hz  {perr.max() * 100:10.2f} % "
                    f"(2 % to {within(perr, f):.0f} Hz)"
                )
            dec = decomposition(track, x, f, fl, row)
            full = dec["full"]
            parts = ", ".join(
                f"{k} {np.max(np.abs(v / full - 1)) * 100:.2f} %"
                for k, v in dec.items()
                if k not in ("full", "share")
            )
            print(
                f"    truncated share of the static compliance {float(dec['share']) * 100:.1f} %; "
                f"max error up to f_limit/2 at this point: {parts}"
            )
            ax = axes[i, j]
            dw = track.head_receptance(fwide, x, 2)[:, row, row]
            rw = rf_point_receptance(track, x, fwide, fl)[:, 1, comp, comp]
            iw = rf_point_receptance(track, x, fwide, fl, inertia=True)[:, 1, comp, comp]
            nw = rf_point_receptance(track, x, fwide, fl, residual=False)[:, 1, comp, comp]
            ax.semilogy(fwide, np.abs(dw), "k-", lw=2, label=f"direct FRF, all {track.n_modes} modes")
            ax.semilogy(fwide, np.abs(rw), "C1--", label=f"{nk} modes + static residual (default)")
            ax.semilogy(fwide, np.abs(iw), "C2-.", label=f"{nk} modes + residual with inertia")
            ax.semilogy(fwide, np.abs(nw), "C0:", label=f"{nk} modes, no residual")
            ax.axvline(0.5 * fl, color="0.5", lw=0.8)
            ax.text(0.5 * fl, ax.get_ylim()[0], " f_limit/2", color="0.4", va="bottom", fontsize=8)
            ax.set_title(
                f"{name}, {pos}: error to f_limit/2 {errs['static'].max() * 100:.1f} % "
                f"(static), {errs['inertia'].max() * 100:.2f} % (inertia)",
                fontsize=10,
            )
            ax.set_ylabel(f"|{'u_z / F_z' if comp == 1 else 'u_y / F_y'}|, m/N")
            ax.set_xlabel("frequency, Hz")
            ax.grid(True, which="both", alpha=0.3)
            ex = axes[2, i]
            ex.plot(f, 100 * errs["static"], f"C{2 * j}-", label=f"{pos}: static residual (default)")
            ex.plot(
                f,
                100 * errs["inertia"],
                f"C{2 * j}--",
                label=f"{pos}: residual with inertia (ring_residual_inertia)",
            )
            ex.axhline(2.0, color="C3", lw=0.8, ls="--")
            ex.set_title(f"{name}: relative error against the direct FRF, up to f_limit / 2", fontsize=10)
            ex.set_xlabel("frequency, Hz")
            ex.set_ylabel("|H / H_direct - 1|, %")
            ex.grid(True, alpha=0.3)
            ex.legend(fontsize=8, loc="upper left")
            if i == 0 and j == 0:
                ax.legend(fontsize=8, loc="lower left")
    fig.suptitle(
        f"Ring track (n_sl = {args.n_sleepers}), right rail's head point receptance: "
        f"model RF's truncation (f_limit = {fl:g} Hz) against RingTrack.head_receptance"
    )
    fig.tight_layout()
    out = Path(args.figure)
    out.parent.mkdir(exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
