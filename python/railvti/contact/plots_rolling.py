"""Plots of a stored rolling case: traction vectors over the pressure,
the stick/slip map and the frictional power density."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np


def plot_rolling(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Three panels: traction vectors over the pressure, stick/slip, power density."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    x = group["x"][()] * 1e3
    y = group["y"][()] * 1e3
    p = group["pressure"][()] / 1e6
    tx = group["tx"][()] / 1e6
    ty = group["ty"][()] / 1e6
    status = group["status"][()]
    pd = group["power_density"][()] / 1e6
    dx, dy = x[1] - x[0], y[1] - y[0]
    ext = (x[0] - dx / 2, x[-1] + dx / 2, y[0] - dy / 2, y[-1] + dy / 2)
    inside = p > 0
    ii, jj = np.nonzero(inside)
    pad = 2
    xl = (
        (x[max(ii.min() - pad, 0)] - dx, x[min(ii.max() + pad, len(x) - 1)] + dx)
        if ii.size
        else (x[0], x[-1])
    )
    yl = (
        (y[max(jj.min() - pad, 0)] - dy, y[min(jj.max() + pad, len(y) - 1)] + dy)
        if jj.size
        else (y[0], y[-1])
    )

    fig, axes = plt.subplots(1, 3, figsize=(14.0, 4.4))
    ax = axes[0]
    im = ax.imshow(p.T, origin="lower", cmap="Greys", extent=ext, aspect="equal")
    fig.colorbar(im, ax=ax, label="pressure (MPa)", shrink=0.8)
    step = max(1, int(max(np.ptp(ii) if ii.size else 1, np.ptp(jj) if jj.size else 1) / 24))
    X, Y = np.meshgrid(x, y, indexing="ij")
    sel = np.zeros_like(inside)
    sel[::step, ::step] = True
    sel &= inside
    tmax = max(np.hypot(tx, ty).max(), 1e-30)
    ax.quiver(
        X[sel],
        Y[sel],
        tx[sel],
        ty[sel],
        color="C3",
        angles="xy",
        scale_units="xy",
        scale=tmax / (2.0 * step * dx),
    )
    ax.set_title(
        f"tangential traction on the wheel\narrows: longest = {tmax:.3g} MPa "
        f"(drawn {2.0 * step * dx:.2g} mm long)",
        fontsize=10,
    )
    ax = axes[1]
    cmap = ListedColormap(["white", "#4c72b0", "#dd8452"])
    ax.imshow(
        status.T,
        origin="lower",
        cmap=cmap,
        vmin=-0.5,
        vmax=2.5,
        extent=ext,
        aspect="equal",
        interpolation="nearest",
    )
    ax.set_title("adhesion (blue) / slip (orange)")
    ax = axes[2]
    im = ax.imshow(np.where(inside, pd, np.nan).T, origin="lower", cmap="inferno", extent=ext, aspect="equal")
    fig.colorbar(im, ax=ax, label="power density (MW/m$^2$)", shrink=0.8)
    ax.set_title(f"frictional power, total {float(group['power'][()]):.4g} W")
    for ax in axes:
        ax.set_xlim(*xl)
        ax.set_ylim(*yl)
        ax.set_xlabel("x, rolling direction (mm)")
    axes[0].set_ylabel("y, lateral (mm)")
    fx, fy, mz = (float(group[k][()]) for k in ("fx", "fy", "mz"))
    fn = float(group["fn"][()]) if "fn" in group else max(abs(fx), abs(fy))
    a = max(abs(x[-1] - x[0]), abs(y[-1] - y[0])) * 1e-3  # the grid's size, m

    def shown(v: float, ref: float) -> str:  # solver noise (below 1e-7 of the load) as 0
        return "0" if abs(v) <= 1e-7 * ref else f"{v:.4g}"

    fig.suptitle(
        f"{group.attrs['name']}: Fx = {shown(fx, fn)} N, Fy = {shown(fy, fn)} N, "
        f"Mz = {shown(mz, fn * a)} N m  (particles move in -x)"
    )
    fig.tight_layout()
    path = outdir / f"{stem}_rolling.png"
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return [path]


__all__ = ["plot_rolling"]
