"""Charts of profiles with contact points and of the geometry table (matplotlib, Agg)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..profiles import Profile
from .frames import SIGN, axle_direction
from .table import FLANGE_CLIMB, GeometryTable, WheelsetContact

__all__ = ["plot_profiles", "plot_table"]


def _mpl():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_profiles(
    wheel: Profile, rail: Profile, contacts: list[WheelsetContact], path: str | Path, side: str = "left"
) -> Path:
    """Rail and wheel (at each contact's pose, in the track cross-section) with contact points."""
    plt = _mpl()
    k = 0 if side == "left" else 1
    sg = SIGN[k]
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=90)
    first = contacts[0].pose.layout
    ry, rz = rail.sample(1e-4)
    ax.plot(sg * (first.rail_offset + ry) * 1e3, (first.rail_top - rz) * 1e3, "k", lw=1.5, label="rail")
    for wc in contacts:
        pose, lay = wc.pose, wc.pose.layout
        ws, wz = wheel.sample(2e-4)
        a = axle_direction(np.array([pose.roll]), np.array([0.0]))[0]  # cross-section (yaw ignored)
        w = sg * (lay.wheelset.contact_y + ws)
        r = lay.wheelset.wheel_radius + wz
        down = np.array([0.0, a[2], -a[1]])
        y = pose.y + w * a[1] + r * down[1]
        z = pose.z + w * a[2] + r * down[2]
        (line,) = ax.plot(y * 1e3, z * 1e3, lw=1, label=f"wheel, y = {pose.y * 1e3:.1f} mm")
        for p in wc.wheel(side):
            ax.plot(
                p.position[1] * 1e3,
                p.position[2] * 1e3,
                "o",
                color=line.get_color(),
                mfc="none" if not p.in_contact else line.get_color(),
                ms=6,
            )
    ax.set_xlabel("track y, mm (left rail; o: contact points, open: not touching)")
    ax.set_ylabel("z, mm")
    ax.set_aspect("equal")
    ax.set_ylim(-40, 35)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(f"{wheel.name} on {rail.name}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return Path(path)


def plot_table(
    table: GeometryTable,
    path: str | Path,
    conicity: tuple[np.ndarray, np.ndarray] | None = None,
    title: str = "",
) -> Path:
    """Delta-r, contact angles and roll against the lateral shift (and conicity vs amplitude);
    ``title``: the wheel/rail pair."""
    plt = _mpl()
    n = 4 if conicity is not None else 3
    fig, axs = plt.subplots(1, n, figsize=(3.2 * n, 3.2), dpi=90)
    y = table.y * 1e3
    axs[0].plot(y, table.delta_r * 1e3, "k")
    axs[0].set_ylabel("delta r = r_left - r_right, mm")
    for k, nm in ((0, "left"), (1, "right")):
        axs[1].plot(y, table.contact_angle[:, k, 0], ".", ms=2, label=nm)
    axs[1].set_ylabel("contact angle (carrying point), rad")
    axs[1].legend(fontsize=7)
    axs[2].plot(y, table.roll * 1e3, "k")
    axs[2].set_ylabel("roll, mrad")
    climb = np.any(table.status == FLANGE_CLIMB, axis=1)
    for ax in axs[:3]:
        ax.set_xlabel("lateral shift y, mm")
        ax.grid(alpha=0.3)
        if climb.any():
            ax.fill_between(
                y,
                0,
                1,
                where=climb,
                transform=ax.get_xaxis_transform(),
                color="r",
                alpha=0.08,
                label="flange climb",
            )
    if conicity is not None:
        amp, con = conicity
        axs[3].plot(amp * 1e3, con, "k")
        axs[3].set_xlabel("amplitude, mm")
        axs[3].set_ylabel("equivalent conicity (EN 15302)")
        axs[3].grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return Path(path)
