"""Plots of wheelset mode shapes (meridian section) and FRFs."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def plot_mode(ax, mesh, shape: np.ndarray, title: str = "", scale: float | None = None) -> None:
    """Draw the deformed meridian section (r, y) of one mode (set A at azimuth 0)."""
    x = mesh.nodes
    u = shape[:, :2]
    if scale is None:
        scale = 0.08 * np.ptp(x[:, 0]) / max(np.abs(u).max(), 1e-30)
    corners = [0, 2, 8, 6, 0]
    for el in mesh.conn:
        p = x[el[corners]]
        ax.plot(p[:, 1], p[:, 0], color="0.8", lw=0.3)
        q = p + scale * u[el[corners]]
        ax.plot(q[:, 1], q[:, 0], color="C0", lw=0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("y, m")
    ax.set_ylabel("r, m")
    ax.set_title(title, fontsize=8)


def plot_frf(path: Path, freqs: np.ndarray, curves: dict[str, np.ndarray], title: str) -> Path:
    """Magnitude of receptances (m/N) on a log scale, one curve per label."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.6), dpi=90)
    for label, h in curves.items():
        ax.semilogy(freqs, np.abs(h), lw=1.0, label=label)
    ax.set_xlabel("frequency, Hz")
    ax.set_ylabel("|receptance|, m/N")
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


__all__ = ["plot_mode", "plot_frf"]
