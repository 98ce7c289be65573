"""Charts of a loaded-wheelset sweep and of its contact patches (Kaiser Figs 11-12, 17)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from .._plotting import pyplot


def plot_sweep(
    y: np.ndarray,
    arrays: dict[str, np.ndarray],
    path: str | Path,
    xlabel: str = "lateral shift y, mm",
    title: str = "",
) -> Path:
    """Contact angle, position, forces, pmax and creepages per wheel and patch against the shift
    (``y`` in m, drawn in mm); ``title`` names the case above the panels."""
    plt = pyplot()
    panels = [
        ("contact_angle", "contact angle, rad", 1.0),
        ("y_rail", "contact position on rail, mm", 1e3),
        ("fn", "Fn, kN", 1e-3),
        ("fx", "Fx, kN", 1e-3),
        ("fy", "Fy, kN", 1e-3),
        ("pmax", "pmax, MPa", 1e-6),
        ("xi", "xi (solid), eta (dotted), -", 1.0),
        ("phi", "spin phi, 1/m", 1.0),
    ]
    panels = [p for p in panels if p[0] in arrays and np.isfinite(arrays[p[0]]).any()]
    ncol = 2
    nrow = (len(panels) + 1) // 2
    fig, axes = plt.subplots(nrow, ncol, figsize=(10, 2.4 * nrow), sharex=True)
    axes = np.atleast_1d(axes).ravel()
    for ax, (key, label, scale) in zip(axes, panels):
        for w, (side, col) in enumerate((("left", "C0"), ("right", "C3"))):
            for k, ls in enumerate(("-", "--")):
                v = arrays[key][:, w, k] * scale
                if np.isfinite(v).any():
                    ax.plot(y * 1e3, v, ls, color=col, marker=".", ms=3, label=f"{side} wheel, patch {k + 1}")
                if key == "xi":
                    ax.plot(y * 1e3, arrays["eta"][:, w, k], ":", color=col)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    for ax in axes[-ncol:]:
        ax.set_xlabel(xlabel)
    for ax in axes[len(panels) :]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return Path(path)


def plot_fields(fields: dict[str, dict[str, np.ndarray]], path: str | Path, title: str = "") -> Path:
    """Pressure maps of patches (key 'left0', 'right0', ...) with traction vectors if present
    (each panel's largest traction drawn one sampling step long; its value in the panel title)."""
    plt = pyplot()
    keys = list(fields)
    ncol = min(2, len(keys))
    nrow = -(-len(keys) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.0 * ncol, 3.6 * nrow), squeeze=False)
    for ax in axes.ravel()[len(keys) :]:
        ax.set_visible(False)
    for ax, key in zip(axes.ravel(), keys):
        f = fields[key]
        x, y, p = f["x"] * 1e3, f["y"] * 1e3, f["pressure"] * 1e-6
        im = ax.pcolormesh(y, x, p, shading="nearest", cmap="viridis")
        ax.contour(y, x, p, levels=[1e-9], colors="w", linewidths=0.6)
        if f.get("tx") is not None:
            s = max(1, p.shape[0] // 16), max(1, p.shape[1] // 16)
            Y, X = np.meshgrid(y, x)
            tx, ty = f["tx"][:: s[0], :: s[1]], f["ty"][:: s[0], :: s[1]]
            tmax = max(float(np.hypot(tx, ty).max()), 1e-30)
            step = max(s[0] * abs(x[1] - x[0]), s[1] * abs(y[1] - y[0]))
            # the largest traction is drawn one sampling step long
            ax.quiver(
                Y[:: s[0], :: s[1]],
                X[:: s[0], :: s[1]],
                ty,
                tx,
                color="w",
                angles="xy",
                scale_units="xy",
                scale=tmax / step,
                width=0.004,
            )
            key = f"{field_label(key)}\narrows: traction, longest = {tmax * 1e-6:.0f} MPa"
        fig.colorbar(im, ax=ax, label="p, MPa")
        ax.set_aspect("equal")
        ax.set_xlabel("lateral y (contact frame), mm")
        ax.set_ylabel("rolling x, mm")
        ax.set_title(key, fontsize=9)
    if title:
        fig.suptitle(wrap_title(title, fig.get_figwidth(), 10), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return Path(path)


def wrap_title(text: str, width_in: float, fontsize: float = 10.0) -> str:
    """``text`` broken into lines that fit a figure ``width_in`` inches wide at ``fontsize``
    points (a character of DejaVu Sans is ~0.6 em wide on average), between its ', '-separated
    items where possible: a one-panel figure's long title is otherwise cut at both edges."""
    chars = max(int(width_in * 72.0 / (0.6 * fontsize)) - 2, 20)
    lines: list[str] = []
    for item in text.split(", "):
        if lines and len(lines[-1]) + 2 + len(item) <= chars:
            lines[-1] += ", " + item
        else:
            if lines:
                lines[-1] += ","
            lines.extend(textwrap.wrap(item, chars, break_on_hyphens=False) or [""])
    return "\n".join(lines)


def case_title(group, keys: tuple[tuple[str, str, float, str], ...]) -> str:
    """'NAME: fz 10000 N, mu 0.3, ...' from a stored case's inputs; keys: (input, label,
    factor, unit) each shown when stored and numeric."""
    parts = []
    inputs = group["inputs"] if "inputs" in group else {}
    for key, label, factor, unit in keys:
        if key not in inputs:
            continue
        try:
            value = float(np.asarray(inputs[key])) * factor + 0.0  # + 0.0: no '-0'
            parts.append(f"{label} {value:.4g}{unit}")
        except (TypeError, ValueError):
            pass
    name = group.attrs.get("name", "")
    name = name.decode() if isinstance(name, bytes) else str(name)
    return f"{name}: " + ", ".join(parts) if name else ", ".join(parts)


def field_label(key: str) -> str:
    """'left wheel, patch 1' for a stored field's key 'left0'."""
    side, n = key.rstrip("0123456789"), key[len(key.rstrip("0123456789")) :]
    return f"{side} wheel, patch {int(n) + 1}" if side in ("left", "right") and n else key


__all__ = ["plot_sweep", "plot_fields", "wrap_title", "case_title", "field_label"]
