"""Modal truncation of the free-free flexible wheelset (issue 14): cost against error.

Over f_max (highest free-free elastic mode kept, Hz) and k_max (highest harmonic kept):

* nq, the number of modal coordinates (Q_A and Q_B both counted);
* the static error under the static load case (Q = 85 kN up at each wheel's taping-line
  contact point, Q down at each journal centre): the rim's rotation about the rolling axis
  (camber) and the contact point's vertical displacement, from the kept modes alone and from
  the kept modes plus the residual flexibility (harmonics 0..6), against the static FE solve
  of harmonics 0..6 (the rigid-body parts removed mass-orthogonally);
* the error of the FRF peak frequencies of the rotating free-free wheelset at 300 km/h below
  600 Hz (k = 0: umbrella and torsion, k = 1: bending with its forward/backward split, k = 2:
  the split pair), taken as the undamped eigenfrequencies of the axle-fixed model (the peaks
  of the lightly damped FRF, zeta = 0.5 %), against the model with f_max = 5000 Hz, k_max = 6.

Prints a table and the recommended defaults; writes validation/figures/wheelset_truncation.png.
Run: .venv/bin/python validation/wheelset_truncation.py  (about a minute on 2 cores)
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railvti.wheelset import FlexibleWheelset, Wheelset  # noqa: E402
from railvti.wheelset import residual as wres  # noqa: E402
from railvti.wheelset import rim_rows as wrows  # noqa: E402
from railvti.wheelset import statics as wstat  # noqa: E402

FIG = Path(__file__).resolve().parent / "figures"
FIG.mkdir(exist_ok=True)
SPEED = 300 / 3.6
Q = 85e3
F_REF, K_REF = 5000.0, 6
F_PEAKS = 600.0
F_MAXES = (200.0, 300.0, 500.0, 800.0, 1200.0, 2000.0, 3000.0)
K_MAXES = tuple(range(7))
CAMBER, UZ, UY = (wrows.ATTACHMENT_DOFS.index(f"contact0.{c}") for c in ("rx", "z", "y"))


def load() -> np.ndarray:
    f = np.zeros(len(wrows.ATTACHMENT_DOFS))
    for name, v in (("contact0.z", Q), ("contact1.z", Q), ("journal0.z", -Q), ("journal1.z", -Q)):
        f[wrows.ATTACHMENT_DOFS.index(name)] = v
    return f


def peaks(body: FlexibleWheelset, k_max: int) -> dict[int, np.ndarray]:
    """Undamped eigenfrequencies (Hz) per harmonic of the axle-fixed model."""
    out = {}
    for k in range(k_max + 1):
        sel = np.flatnonzero(body.k == k)
        if sel.size == 0:
            out[k] = np.zeros(0)
            continue
        kk = body.stiffness[np.ix_(sel, sel)]
        gg = body.gyro[np.ix_(sel, sel)]
        n = sel.size
        ev = np.linalg.eigvals(np.block([[np.zeros((n, n)), np.eye(n)], [-kk, -gg]]))
        out[k] = np.sort(np.abs(ev.imag[ev.imag > 0])) / (2 * np.pi)
    return out


def peak_error(ref: dict[int, np.ndarray], got: dict[int, np.ndarray]) -> tuple[float, int]:
    """Largest relative error (%) of the reference peaks below F_PEAKS, and how many are missing."""
    worst, missing = 0.0, 0
    for k, fr in ref.items():
        fr = fr[fr < F_PEAKS]
        fg = got.get(k, np.zeros(0))
        for i, f in enumerate(fr):
            if i >= fg.size:
                missing += 1
            else:
                worst = max(worst, abs(fg[i] / f - 1.0) * 100.0)
    return worst, missing


def tread_camber(ws: Wheelset, f: np.ndarray) -> tuple[float, float]:
    """Reference camber of the right wheel two ways: the local slope at the loaded contact
    point (mean of the two elements there) and the least-squares slope of the vertical
    displacement over the whole tread (rad; what the rx rows measure)."""
    g = ws.geometry
    edges = wrows.rim_edges(g)
    s_tread = np.linspace(edges[0].s_face, edges[0].s_max, 41)
    uz = np.zeros(s_tread.size)
    local = 0.0
    for k in range(K_REF + 1):
        st = wstat.harmonic_statics(ws, k)
        pts = [
            wstat.point_operator(ws.mesh, edges[0], 0.0, None),
            wstat.point_operator(ws.mesh, edges[1], 0.0, None),
            wstat.point_operator(ws.mesh, None, None, ws._journal_nodes[0]),
            wstat.point_operator(ws.mesh, None, None, ws._journal_nodes[1]),
        ]
        kind = "0" if k == 0 else "A"
        e = np.array([v for p in pts for v in p[kind]])
        u = st.solve(e.T @ f)
        nodes, _, _, ny = wrows.locate(ws.mesh, *wrows.edge_point(edges[0], 0.0))
        local += float(np.sum(u[3 * nodes] * ny))  # d u_r / d y_FE at the loaded point
        for i, s in enumerate(s_tread):
            uz[i] += wstat.point_operator(ws.mesh, edges[0], float(s), None)[kind][2] @ u
    yv = -(g.contact_y + s_tread)  # right wheel: vehicle y = -y_FE
    return float(local), float(np.polyfit(yv, uz, 1)[0])


def main() -> None:
    t0 = time.perf_counter()
    ws = Wheelset()
    f = load()
    ref_body = ws.flexible_body(SPEED, k_max=K_REF, f_max=F_REF)  # solves and caches the modes
    gfull = wstat.full_compliance(
        [wstat.harmonic_statics(ws, k) for k in range(K_REF + 1)],
        ws.mesh,
        wrows.rim_edges(ws.geometry),
        (0.0, 0.0),
        ws._journal_nodes,
    )
    u_ref = wstat.static_fe_solve(ws, f, k_max=K_REF)  # independent direct solve
    print(
        f"bordered (inertia-relief) compliance against the direct solve: "
        f"{np.abs(gfull @ f - u_ref).max() / np.abs(u_ref).max():.1e} (relative)"
    )
    ref_peaks = peaks(ref_body, K_REF)
    local, fit = tread_camber(ws, f)
    print(
        f"reference: {ref_body.n} coordinates (f_max {F_REF:.0f} Hz, k_max {K_REF}); "
        f"{time.perf_counter() - t0:.1f} s"
    )
    print(
        f"static load Q = {Q / 1e3:.0f} kN per wheel, journals -Q: right wheel camber (rim "
        f"rotation about x, the tread's slope) {u_ref[CAMBER] * 1e3:+.3f} mrad (own fit "
        f"{fit * 1e3:+.3f}; the local slope at the loaded point, mesh-dependent: "
        f"{local * 1e3:+.3f} mrad), contact-point vertical displacement "
        f"{u_ref[UZ] * 1e6:+.1f} um, lateral {u_ref[UY] * 1e6:+.1f} um "
        "(rigid parts removed)"
    )
    per_k = {k: np.round(v[v < F_PEAKS], 1).tolist() for k, v in ref_peaks.items() if v.size}
    print(f"reference peaks below {F_PEAKS:.0f} Hz at 300 km/h: {per_k}")
    print(
        f"\n{'k_max':>5} {'f_max Hz':>8} {'nq':>4} {'camber err %':>13} {'+residual %':>12} "
        f"{'uz err %':>9} {'+residual %':>12} {'peak err %':>10} {'missing':>7} {'build s':>8}"
    )
    rows = []
    for k_max in K_MAXES:
        for f_max in F_MAXES:
            t = time.perf_counter()
            b = ws.flexible_body(SPEED, k_max=k_max, f_max=f_max, ds=0.01)
            dt = time.perf_counter() - t
            kept = b.static_deflection(f, residual=False)
            full = b.static_deflection(f)
            e = [abs(x[i] / u_ref[i] - 1.0) * 100.0 for i in (CAMBER, UZ) for x in (kept, full)]
            pe, miss = peak_error(ref_peaks, peaks(b, k_max))
            signed = kept[CAMBER] / u_ref[CAMBER] - 1.0
            rows.append((k_max, f_max, b.n, *e, pe, miss, dt, 0.0, signed))  # col 11: signed
            print(
                f"{k_max:>5} {f_max:>8.0f} {b.n:>4} {e[0]:>13.2f} {e[1]:>12.2e} {e[2]:>9.2f} "
                f"{e[3]:>12.2e} {pe:>10.3f} {miss:>7} {dt:>8.2f}"
            )
    rows = np.array(rows)
    n_peaks = sum(int(np.sum(v < F_PEAKS)) for v in ref_peaks.values())
    ok = rows[(rows[:, 8] == 0) & (rows[:, 7] < 1.0) & (rows[:, 4] < 2.0) & (rows[:, 6] < 2.0)]
    best = ok[np.argmin(ok[:, 2])] if ok.size else None
    if best is not None:
        print(
            f"\nrecommended: k_max = {int(best[0])}, f_max = {best[1]:.0f} Hz ({int(best[2])} "
            f"coordinates): all {n_peaks} peaks below {F_PEAKS:.0f} Hz within 1 % "
            f"({best[7]:.3f} %), static camber and deflection within 2 % with the residual "
            f"flexibility (kept modes alone: camber {best[3]:.1f} %, uz {best[5]:.1f} %)"
        )
    moving_contact(ws, f)
    print(f"total {time.perf_counter() - t0:.1f} s")
    plot(rows, n_peaks, u_ref[CAMBER])


def moving_contact(ws: Wheelset, f: np.ndarray) -> None:
    """Does the residual flexibility have to follow the contact point? k_max 2, f_max 800 Hz,
    the residual computed at s = 0, the loads at other s."""
    b = ws.flexible_body(SPEED, k_max=2, f_max=800.0, ds=0.01)
    print("\ncontact point moving (k_max 2, f_max 800 Hz), camber of the right wheel, mrad:")
    print(f"{'s mm':>6} {'FE':>8} {'kept':>8} {'+res(s)':>8} {'+res(0)':>8}")
    for s in (0.0, 0.005, -0.01, -0.03):
        ref = wstat.static_fe_solve(ws, f, (s, s), k_max=K_REF)
        r = b.attachment_rows((s, s))
        kept = r @ ((r.T @ f) / (2 * np.pi * b.freq_hz) ** 2)
        fresh = kept + wres.residual_flexibility(ws, b, (s, s)) @ f
        stale = kept + b.residual @ f
        print(
            f"{s * 1e3:>6.1f} {ref[CAMBER] * 1e3:>8.3f} {kept[CAMBER] * 1e3:>8.3f} "
            f"{fresh[CAMBER] * 1e3:>8.3f} {stale[CAMBER] * 1e3:>8.3f}"
        )


def plot(rows: np.ndarray, n_peaks: int, camber_ref: float) -> None:
    fig, ax = plt.subplots(2, 2, figsize=(12, 8.5))
    ax = ax.ravel()
    cmap = plt.get_cmap("viridis")
    for k_max in K_MAXES:
        r = rows[rows[:, 0] == k_max]
        c = cmap(k_max / max(K_MAXES))
        lab = f"k_max = {k_max}"
        ax[0].plot(r[:, 1], r[:, 2], "o-", color=c, label=lab)
        ax[1].plot(r[:, 2], camber_ref * 1e3 * (1.0 + r[:, 11]), "o-", color=c, label=lab)
        ax[2].semilogy(r[:, 2], np.maximum(r[:, 3], 1e-9), "o-", color=c, label=lab)
        ax[2].semilogy(
            r[:, 2],
            np.maximum(r[:, 4], 1e-9),
            "s--",
            color=c,
            ms=3,
            label="+ residual (round-off)" if k_max == max(K_MAXES) else None,
        )
        full = r[r[:, 8] == 0]
        ax[3].semilogy(full[:, 2], np.maximum(full[:, 7], 1e-6), "o-", color=c, label=lab)
    ax[0].set(
        xscale="log",
        yscale="log",
        xlabel="f_max, Hz",
        ylabel="modal coordinates nq",
        title="(a) cost: modal coordinates (Q_A and Q_B counted)",
    )
    ax[0].set_xticks(F_MAXES, [f"{v:.0f}" for v in F_MAXES])
    ax[0].minorticks_off()
    ax[1].axhline(camber_ref * 1e3, color="k", lw=1.2, ls=":", label="static FE = kept + residual")
    ax[1].set(
        xscale="log",
        xlabel="modal coordinates nq",
        ylabel="camber change, mrad",
        title="(b) rim rotation about x, right wheel, Q = 85 kN per wheel:\n"
        "kept modes only (lines) against the static FE solve",
    )
    ax[2].axhline(2.0, color="grey", lw=0.8, ls=":")
    ax[2].set(
        xscale="log",
        xlabel="modal coordinates nq",
        ylabel="static camber error, %",
        title="(c) static camber error against the direct FE solve\n"
        "solid: kept modes only, dashed: + residual flexibility",
    )
    ax[3].axhline(1.0, color="grey", lw=0.8, ls=":", label="1 % acceptance")
    ax[3].set(
        xscale="log",
        xlabel="modal coordinates nq",
        ylabel="largest peak-frequency error, %",
        title=f"(d) FRF peaks below {F_PEAKS:.0f} Hz at 300 km/h against f_max 5 kHz,\n"
        f"k_max 6 (truncations that keep all {n_peaks} peaks)",
    )
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    out = FIG / "wheelset_truncation.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
