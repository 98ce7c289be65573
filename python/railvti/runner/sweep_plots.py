"""Plots of the sweeps in a results file: one summary chart per sweep (its scalar results
over the swept keys) and, for small sweeps, each point's own plots."""

from __future__ import annotations

import json
import logging
import textwrap
from pathlib import Path
from typing import Any

import numpy as np

from .._plotting import pyplot
from ..casetypes import CaseType
from .deck_registry import case_types

log = logging.getLogger("railvti")


#: Per-point plots are drawn for sweeps of at most this many points (``railvti plot --points``:
#: every point); larger sweeps get their summary plot only.
MAX_POINT_PLOTS = 4
#: The quantity a sweep of a case type is plotted by: dataset, factor, unit, meaning.
HEADLINES = {
    "vehicle": (
        "amplitude_last_second",
        1e3,
        "mm",
        "leading wheelset's lateral amplitude over the last second",
    ),
}


def _key_unit(ctype: CaseType | None, key: str) -> str:
    """The unit of a swept key as written in the deck (an alias's own unit)."""
    if ctype is None:
        return ""
    if key in ctype.aliases:
        return ctype.aliases[key].unit
    spec = ctype.keys.get(key)
    return spec.unit if spec is not None and spec.unit not in ("", "1") else ""


def _label(key: str, value: Any, unit: str) -> str:
    return f"{key} = {_short(value)}" + (f" {unit}" if unit else "")


def _short(value: Any) -> str:
    """A swept value for a legend: 8e+10, not 80000000000."""
    return f"{value:.4g}" if isinstance(value, float) else str(value)


#: Names of result quantities for the axes of sweep plots (else the dataset's name in words).
QUANTITIES = {
    "approach": "approach",
    "area": "contact area",
    "fn": "normal force",
    "pmax": "peak pressure",
    "hertz_a": "Hertz semi-axis a",
    "hertz_b": "Hertz semi-axis b",
    "fx": "longitudinal creep force",
    "fy": "lateral creep force",
    "mz": "spin moment",
    "conicity": "equivalent conicity",
}


def _quantity(ctype: CaseType | None, key: str) -> str:
    """'normal force fn, N' for an axis: the swept key's meaning (up to its first
    parenthesis, colon or semicolon), its name and unit."""
    unit = _key_unit(ctype, key)
    meaning = ""
    if ctype is not None:
        target = ctype.aliases[key].key if key in ctype.aliases else key
        spec = ctype.keys.get(target)
        if spec is not None and spec.meaning:
            cut = min([i for i in (spec.meaning.find(c) for c in "(:;") if i >= 0] or [len(spec.meaning)])
            meaning = spec.meaning[:cut].strip()
            meaning = meaning if len(meaning) <= 40 else meaning[:38] + ".."
    text = f"{meaning} ({key})" if meaning and meaning != key else key
    return f"{text}, {unit}" if unit else text


def sweep_points(f: Any) -> dict[str, list[tuple[dict, Any]]]:
    """Sweep name -> [(point values, h5py group)] of an open results file, in file order."""
    out: dict[str, list[tuple[dict, Any]]] = {}
    for _, g in f.items():
        name = g.attrs.get("sweep") if hasattr(g, "attrs") else None
        if name:
            out.setdefault(str(name), []).append((json.loads(str(g.attrs["sweep_point"])), g))
    return out


def plot_sweeps(f: Any, outdir: Path, stem: str) -> list[Path]:
    """One summary plot per sweep of an open results file (``stem_SWEEP_sweep.png``): the
    headline quantity (:data:`HEADLINES`, else the numeric scalar results) against the swept
    key with the most values, one line per value of the other keys; failed points marked.
    A sweep of at most :data:`MAX_POINT_PLOTS` vehicle hunting runs gets the leading
    wheelset's time histories and phase portraits overlaid (``stem_SWEEP_phase.png``)."""
    types = case_types()
    paths = []
    for name, points in sweep_points(f).items():
        ctype = types.get(str(points[0][1].attrs.get("type")))
        ok = [(p, g) for p, g in points if g.attrs.get("status") == "ok"]
        try:
            if ok and "vy_ws1" in ok[0][1] and len(points) <= MAX_POINT_PLOTS:
                paths.append(_plot_phases(pyplot(), name, ok, ctype, outdir / f"{stem}_{name}_phase.png"))
            else:
                p = _plot_summary(pyplot(), name, points, ctype, outdir / f"{stem}_{name}_sweep.png")
                if p is not None:
                    paths.append(p)
        except Exception as exc:  # noqa: BLE001 - one bad sweep must not stop the others
            log.error("no plot for sweep %s: %s: %s", name, type(exc).__name__, exc)
    return paths


#: Most lines a sweep plot's legend lists (the others are counted under it).
MAX_LEGEND = 20


def _legend(fig: Any, ax: Any, title: str) -> None:
    """One legend for the figure, right of its panels (not over them): the lines of ``ax``,
    at most :data:`MAX_LEGEND` listed; ``title`` names the keys of the entries."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return
    more = len(handles) - MAX_LEGEND
    if more > 0:
        handles, labels = handles[:MAX_LEGEND], labels[:MAX_LEGEND]
        title += f"\n(first {MAX_LEGEND} of {MAX_LEGEND + more} lines)"
    fig.legend(
        handles,
        labels,
        loc="center left",
        bbox_to_anchor=(1.0, 0.5),
        fontsize=7,
        title=title or None,
        title_fontsize=7,
        frameon=False,
    )


def _plot_phases(plt: Any, name: str, points: list, ctype: CaseType | None, path: Path) -> Path:
    fig, ax = plt.subplots(1, 2, figsize=(10.0, 3.8), gridspec_kw={"width_ratios": [1.6, 1]})
    keys = list(points[0][0]) if points else []
    for p, g in points:
        label = ", ".join(_short(v) for v in p.values())
        y, vy, t = (np.asarray(g[k]) for k in ("y_ws1", "vy_ws1", "t"))
        ax[0].plot(t, y * 1e3, lw=0.8, label=label)
        ax[1].plot(y * 1e3, vy, lw=0.6)
    ax[0].set_xlabel("time, s")
    ax[0].set_ylabel("lateral displacement y, mm")
    ax[0].set_title("leading wheelset: lateral displacement", fontsize=9)
    ax[1].set_xlabel("lateral displacement y, mm")
    ax[1].set_ylabel("lateral velocity dy/dt, m/s")
    ax[1].set_title("phase portrait", fontsize=9)
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(f"sweep '{name}'{_what(points)}", fontsize=10)
    fig.tight_layout()
    _legend(fig, ax[0], "\n".join(_key_title(ctype, k) for k in keys))
    fig.savefig(path, dpi=80, bbox_inches="tight")
    plt.close(fig)
    return path


def _key_title(ctype: CaseType | None, key: str) -> str:
    unit = _key_unit(ctype, key)
    return f"{key}, {unit}" if unit and unit != "-" else key


def _what(points: list) -> str:
    """', hunting, model RR, hertz-fastsim on the strips' for a vehicle sweep (its first
    point's scenario, model, contact and geometry), else ''."""
    for _, g in points:
        if "contact" in g and "scenario" in g:

            def text(k: str) -> str:
                v = g[k][()] if k in g else b""
                return v.decode() if isinstance(v, bytes) else str(v)

            contact = text("contact") + (" on the strips" if text("geometry") == "strip" else "")
            return f", {text('scenario')}, model {text('model')}, {contact}"
    return ""


def _scalar_results(g: Any) -> dict[str, tuple[float, str]]:
    """Numeric 0-d datasets of a case group (not the run statistics)."""
    out = {}
    for k, d in g.items():
        if k == "inputs" or k.startswith("stat_") or not hasattr(d, "shape") or d.shape != ():
            continue
        v = d[()]
        if isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool):
            out[k] = (float(v), str(d.attrs.get("units", "")))
    return out


def _plot_summary(plt: Any, name: str, points: list, ctype: CaseType | None, path: Path) -> Path | None:
    keys = list(points[0][0])
    numeric = [k for k in keys if all(isinstance(p[k], (int, float)) for p, _ in points)]
    if not numeric:
        return None
    xkey = max(numeric, key=lambda k: len({p[k] for p, _ in points}))
    others = [k for k in keys if k != xkey]
    head = HEADLINES.get(ctype.name if ctype is not None else "")
    ok = [(p, g) for p, g in points if g.attrs.get("status") == "ok"]
    if head is not None and ok and head[0] in ok[0][1]:
        quantities = [(head[0], head[1], head[2], head[3])]
    elif ok:
        quantities = [(k, 1.0, u, k) for k, (_, u) in list(_scalar_results(ok[0][1]).items())[:4]]
    else:
        quantities = []
    n = max(1, len(quantities))
    fig, axes = plt.subplots(n, 1, figsize=(6.4, 1.2 + 2.8 * n), squeeze=False, sharex=True)
    for ax, (q, factor, unit, meaning) in zip(axes[:, 0], quantities or [(None, 1, "", "")]):
        lines: dict[tuple, list] = {}
        for p, g in points:
            lines.setdefault(tuple(p[k] for k in others), []).append((p[xkey], g))
        for combo, pts in lines.items():
            label = ", ".join(_short(v) for v in combo)
            good = [
                (x, float(np.asarray(g[q])) * factor)
                for x, g in pts
                if q is not None and g.attrs.get("status") == "ok" and q in g
            ]
            if good:
                xs, ys = zip(*sorted(good))
                ax.plot(xs, ys, "o-", ms=4, label=label or None)
            bad = [x for x, g in pts if g.attrs.get("status") != "ok"]
            if bad:
                ax.plot(bad, [0.0] * len(bad), "rx", ms=8, label=f"failed ({label})" if label else "failed")
        what = ""
        if q:
            what = QUANTITIES.get(q, meaning if meaning != q else q.replace("_", " "))
            text = f"{what}, {unit}" if unit and unit not in ("1", "-") else what
            ax.set_ylabel(textwrap.fill(text, 32), fontsize=9)  # a long name: two lines
        ax.set_title(meaning if meaning not in (q, what) else "", fontsize=9)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(_quantity(ctype, xkey))
    fig.suptitle(f"sweep '{name}': {len(points)} points{_what(points)}", fontsize=10)
    fig.tight_layout()
    _legend(fig, axes[0, 0], "\n".join(_key_title(ctype, k) for k in others))
    fig.savefig(path, dpi=80, bbox_inches="tight")
    plt.close(fig)
    return path


__all__ = ["HEADLINES", "MAX_POINT_PLOTS", "plot_sweeps", "sweep_points"]
