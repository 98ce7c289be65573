"""Charts of vehicle runs: time histories, phase portrait, bifurcation diagram."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._plotting import pyplot


#: Smallest range drawn on a history's value axis, per unit of the chart: a history that
#: varies less is drawn flat at its value, with the value and its spread written on the
#: chart (numerical noise, 1e-18 mm or 0.1 N on a 54.5 kN wheel load, is not drawn as a signal).
MIN_SPAN = {"mm": 0.01, "kN": 0.1, "m/s": 1e-4, "1": 0.01}


def _readable(ax, values, unit: str, axis: str = "y") -> None:
    """No offset on the value axis; at least :data:`MIN_SPAN` of it around a flat history."""
    ax.ticklabel_format(axis=axis, useOffset=False)
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    span = MIN_SPAN[unit]
    if v.size == 0 or v.max() - v.min() >= span:
        return
    c = 0.5 * (v.max() + v.min())
    (ax.set_ylim if axis == "y" else ax.set_xlim)(c - span, c + span)
    ax.text(
        0.01,
        0.97 if axis == "y" else 0.03,
        f"flat {axis}: {c:.6g} {unit} (spread {v.max() - v.min():.1e})",
        transform=ax.transAxes,
        va="top" if axis == "y" else "bottom",
        fontsize=7,
    )


def plot_history(
    t: np.ndarray,
    y: np.ndarray,
    vy: np.ndarray,
    Q: np.ndarray,
    Y: np.ndarray,
    outdir: Path,
    stem: str,
    title: str = "",
) -> list[Path]:
    """Leading wheelset lateral displacement and wheel forces against time, and the phase
    portrait (y against dy/dt). Q, Y: (nt, 2, nw). ``title``: the run (scenario, speed,
    model, contact). A flat history is drawn flat with its value (:data:`MIN_SPAN`)."""
    plt = pyplot()
    outdir = Path(outdir)
    fig, ax = plt.subplots(3, 1, figsize=(6.4, 6.4), sharex=True)
    ax[0].plot(t, y * 1e3, lw=0.8)
    ax[0].set_ylabel("y wheelset 1, mm")
    _readable(ax[0], y * 1e3, "mm")
    ax[1].plot(t, Q[:, 0, 0] / 1e3, lw=0.8, label="left")
    ax[1].plot(t, Q[:, 1, 0] / 1e3, lw=0.8, label="right")
    ax[1].set_ylabel("Q wheelset 1, kN")
    ax[1].legend(fontsize=8)
    _readable(ax[1], Q[:, :, 0] / 1e3, "kN")
    ax[2].plot(t, Y[:, 0, 0] / 1e3, lw=0.8, label="left")
    ax[2].plot(t, Y[:, 1, 0] / 1e3, lw=0.8, label="right")
    ax[2].set_ylabel("Y wheelset 1, kN")
    ax[2].set_xlabel("time, s")
    _readable(ax[2], Y[:, :, 0] / 1e3, "kN")
    for a in ax:
        a.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    p1 = outdir / f"{stem}_history.png"
    fig.savefig(p1, dpi=80)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(4.8, 4.2))
    ax.plot(y * 1e3, vy, lw=0.6)
    ax.plot(y[-1:] * 1e3, vy[-1:], "o", ms=3, color="C0", label="last state")  # seen if flat
    ax.legend(fontsize=7, loc="upper right")
    ax.set_xlabel("y wheelset 1, mm")
    ax.set_ylabel("dy/dt, m/s")
    _readable(ax, y * 1e3, "mm", axis="x")
    _readable(ax, vy, "m/s")
    ax.set_title("phase portrait" + (f"\n{title}" if title else ""), fontsize=9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    p2 = outdir / f"{stem}_phase.png"
    fig.savefig(p2, dpi=80)
    plt.close(fig)
    return [p1, p2]


def plot_wheels(
    t: np.ndarray, q_dof: np.ndarray, Q: np.ndarray, Y: np.ndarray, nadal: float, path: Path, title: str = ""
) -> Path:
    """All eight wheels: per wheelset (columns) the lateral displacement, Q of both wheels and
    the flange-climb ratio Y/Q (-Y/Q left, Y/Q right: the rail pushing the wheel towards the
    track centre) with Nadal's limit. q_dof: (nt, nw) wheelset lateral displacements, m;
    Q, Y: (nt, 2, nw), N."""
    plt = pyplot()
    nw = Q.shape[-1]
    fig, ax = plt.subplots(3, nw, figsize=(3.0 * nw, 6.4), sharex=True, sharey="row", squeeze=False)
    yout = Y * np.array([-1.0, 1.0])[None, :, None]
    ok = Q > 0.01 * max(float(Q.max()), 1e-30)
    yq = np.where(ok, yout / np.where(ok, Q, 1.0), 0.0)
    for w in range(nw):
        ax[0, w].plot(t, q_dof[:, w] * 1e3, lw=0.8)
        ax[0, w].set_title(f"wheelset {w + 1}", fontsize=9)
        for s, lab in ((0, "left"), (1, "right")):
            ax[1, w].plot(t, Q[:, s, w] / 1e3, lw=0.7, label=lab)
            ax[2, w].plot(t, yq[:, s, w], lw=0.7, label=lab)
    # rows share their value axis: flat (noise only) when the whole row is
    _readable(ax[0, 0], q_dof * 1e3, "mm")
    _readable(ax[1, 0], Q / 1e3, "kN")
    for w in range(nw):
        if np.isfinite(nadal):  # an interrupted case stores no limit
            ax[2, w].axhline(nadal, color="r", lw=0.8, ls="--", label=f"Nadal {nadal:.2f}")
        ax[2, w].set_xlabel("time, s")
        for a in ax[:, w]:
            a.grid(alpha=0.3)
    ax[0, 0].set_ylabel("y, mm")
    ax[1, 0].set_ylabel("Q, kN")
    ax[2, 0].set_ylabel("Y/Q (flange side +)")
    ax[1, 0].legend(fontsize=7)
    ax[2, 0].legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return Path(path)


def plot_bifurcation(
    speeds: np.ndarray,
    upper: np.ndarray,
    decay: np.ndarray,
    linear_kmh: float,
    path: Path,
    equivalent: tuple | None = None,
    title: str = "",
    critical_kmh: float | None = None,
) -> Path:
    """Limit-cycle amplitude against speed (continuation branch and small-disturbance runs);
    ``equivalent`` = (speeds km/h, amplitudes m): linear critical speeds at the equivalent
    conicity of each amplitude (describing-function estimate of the cycle). ``critical_kmh``:
    the nonlinear critical speed, marked by a vertical line (NaN: none found in the range,
    said on the chart; None: not marked)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.0, 3.8))
    if critical_kmh is not None and np.isfinite(critical_kmh):
        ax.axvline(
            critical_kmh, color="C3", lw=1.2, label=f"critical speed (nonlinear), {critical_kmh:.0f} km/h"
        )
    elif critical_kmh is not None:
        ax.text(
            0.02,
            0.97,
            f"no critical speed found in {np.nanmin(speeds):.0f}-{np.nanmax(speeds):.0f} km/h",
            transform=ax.transAxes,
            va="top",
            fontsize=8,
            color="C3",
        )
    ax.plot(speeds, upper * 1e3, "o-", label="from a large cycle (speed lowered)")
    ax.plot(speeds, decay * 1e3, "s--", label="from a 0.5 mm disturbance")
    if equivalent is not None:
        ax.plot(
            equivalent[0],
            np.asarray(equivalent[1]) * 1e3,
            "k^",
            ms=5,
            label="linear at the equivalent conicity of the amplitude",
        )
    if np.isfinite(linear_kmh):
        ax.axvline(
            linear_kmh, color="k", lw=0.8, ls=":", label=f"linear (3 mm conicity), {linear_kmh:.0f} km/h"
        )
    ax.set_xlabel("speed, km/h")
    ax.set_ylabel("amplitude wheelset 1, mm")
    if title:
        ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return Path(path)


def plot_patch(
    x: np.ndarray,
    y: np.ndarray,
    pressure: np.ndarray,
    tx: np.ndarray,
    ty: np.ndarray,
    power_density: np.ndarray,
    path: Path,
    title: str = "",
) -> Path:
    """Contact-patch fields on the (non-uniform, strip-wise) ellipse grid: pressure, the
    tangential traction magnitude with its direction, the friction power density."""
    plt = pyplot()
    fig, ax = plt.subplots(1, 3, figsize=(10.5, 3.4))
    xm, ym = np.asarray(x) * 1e3, np.asarray(y) * 1e3
    for a, field, label in (
        (ax[0], pressure / 1e6, "pressure, MPa"),
        (ax[1], np.hypot(tx, ty) / 1e6, "|traction|, MPa"),
        (ax[2], power_density / 1e6, "friction power, W/mm^2"),
    ):
        if xm.shape == np.shape(field) and xm.ndim == 2:  # a (strip-wise) grid: filled cells
            sc = a.pcolormesh(ym, xm, np.asarray(field), shading="nearest", cmap="viridis")
        else:
            sc = a.scatter(ym.ravel(), xm.ravel(), c=np.asarray(field).ravel(), s=6, cmap="viridis")
        fig.colorbar(sc, ax=a, shrink=0.85)
        a.set_title(label, fontsize=9)
        a.set_xlabel("y (lateral), mm")
        a.set_aspect("equal")
    ax[0].set_ylabel("x (rolling), mm")
    loaded = np.asarray(pressure) > 0
    n = max(1, int(np.sqrt(max(int(loaded.sum()), 1)) // 10))  # about 10 arrows across
    k = (slice(None, None, n), slice(None, None, n))
    sub = loaded[k]  # arrows only where the wheel touches the rail
    txk, tyk = np.asarray(tx)[k][sub], np.asarray(ty)[k][sub]
    tmax = max(float(np.nanmax(np.hypot(txk, tyk), initial=0.0)), 1e-30)
    pts = np.column_stack([ym[k][sub].ravel(), xm[k][sub].ravel()])
    # the largest traction drawn as long as the mean spacing of the arrows' points, mm
    step = (
        float(np.sqrt(np.ptp(pts[:, 0]) * np.ptp(pts[:, 1]) / max(len(pts), 1))) if len(pts) > 1 else 0.0
    ) or 1.0
    ax[1].quiver(
        ym[k][sub],
        xm[k][sub],
        tyk,
        txk,
        color="w",
        angles="xy",
        scale_units="xy",
        scale=tmax / step,
        width=0.004,
    )
    ax[1].set_title(f"|traction|, MPa\narrows: traction, longest = {tmax / 1e6:.0f} MPa", fontsize=9)
    if loaded.any() and loaded.mean() < 0.5:  # a patch much smaller than its grid (BEM)
        pad = 2.0 * max(float(np.ptp(xm)) / max(xm.shape[0], 1), float(np.ptp(ym)) / max(ym.shape[-1], 1))
        for a in ax:
            a.set_xlim(ym[loaded].min() - pad, ym[loaded].max() + pad)
            a.set_ylim(xm[loaded].min() - pad, xm[loaded].max() + pad)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return Path(path)


__all__ = ["MIN_SPAN", "plot_history", "plot_wheels", "plot_bifurcation", "plot_patch"]
