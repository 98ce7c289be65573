"""A one-screen summary of a results file (``railvti summary FILE``): each case in a line, each
sweep as a table of its headline quantity, and what each kind of figure in the plot folder
shows. ``./dev.sh run`` ends with it."""

from __future__ import annotations

import json
import shutil
import textwrap
from pathlib import Path

import h5py
import numpy as np

from ..errors import InputError
from .sweep_plots import HEADLINES, MAX_POINT_PLOTS, sweep_points

#: What each kind of PNG shows, by the end of its name (the first match counts).
FIGURES = (
    (
        "_patch.png",
        "contact patch of the leading wheelset's right wheel: pressure (MPa), "
        "tangential traction (MPa, arrows: direction) and friction power density "
        "(W/mm^2); BEM fields with contact 'bem', else Hertz + FASTSIM",
    ),
    (
        "_sweep.png",
        "a sweep: its headline quantity against the swept key, one line per value "
        "of the other keys; over speed and disturbance, a bifurcation diagram "
        "(limit-cycle amplitude from a large and from a small start)",
    ),
    (
        "_phase.png",
        "phase portrait of the leading wheelset (lateral velocity against lateral "
        "displacement): a closed orbit is a limit cycle, a spiral to the centre a "
        "decaying motion; a small sweep overlays its points with y(t)",
    ),
    (
        "_history.png",
        "leading wheelset against time: lateral displacement, vertical (Q) and "
        "lateral (Y) forces of both wheels",
    ),
    (
        "_wheels.png",
        "all eight wheels against time: lateral displacement, Q, and the "
        "flange-climb ratio Y/Q with Nadal's limit",
    ),
    (
        "_bifurcation.png",
        "bifurcation diagram of a critical_speed case: amplitude against "
        "speed, continuation and small-disturbance branches",
    ),
    ("_pressure.png", "normal pressure on the contact grid"),
    (
        "_line.png",
        "a line case over the position along the track: the rails' input under the leading "
        "wheelset, its Q and Y, and the track-shifting force against Prud'homme's limit "
        "(grey: the curve)",
    ),
)


def _text(v: object) -> str:
    return v.decode() if isinstance(v, bytes) else str(v)


def _headline(g: h5py.Group) -> str:
    """The first clause of a case's summary, and its contact patch's figures if it has one."""
    text = _text(g.attrs.get("summary", "")).split(";")[0]
    if _text(g.attrs.get("type", "")) == "vehicle":
        text = text.split(":")[0]  # 'hunting 250 km/h (hertz-fastsim)'
    if "amplitude_last_second" in g:
        text += (
            f": amplitude {float(g['amplitude_last_second'][()]) * 1e3:.2f} mm "
            "(leading wheelset, last second)"
        )
    elif "patch_pressure" in g:
        pmax = float(np.max(g["patch_pressure"][()])) / 1e6
        text += (
            f": patch of wheelset 1 right: pmax {pmax:.0f} MPa, "
            f"{float(g['patch_power'][()]):.0f} W friction power"
        )
    return text


def _sweep_table(name: str, points: list, width: int) -> list[str]:
    """A sweep's headline quantity as a table: the most varied key down, the others across."""
    g0 = points[0][1]
    head = HEADLINES.get(_text(g0.attrs.get("type", "")))
    keys = list(points[0][0])
    if head is None or len(keys) > 2:
        ok = sum(g.attrs.get("status") == "ok" for _, g in points)
        return [f"sweep '{name}': {len(points)} points, {ok} ok"]
    qname, factor, unit, meaning = head
    row = max(keys, key=lambda k: len({json.dumps(p[k]) for p, _ in points}))
    col = [k for k in keys if k != row]
    cols = list(dict.fromkeys(p[col[0]] for p, _ in points)) if col else [None]
    rows = list(dict.fromkeys(p[row] for p, _ in points))
    cell = {}
    for p, g in points:
        ok = g.attrs.get("status") == "ok" and qname in g
        cell[(p[row], p[col[0]] if col else None)] = f"{float(g[qname][()]) * factor:.2f}" if ok else "failed"
    out = [f"sweep '{name}' ({len(points)} points): {meaning}, {unit}"]
    out.append(f"  {row:>12s} | " + " | ".join(f"{col[0]} = {c}" if col else qname for c in cols))
    for r in rows:
        out.append(
            f"  {r!s:>12s} | "
            + " | ".join(
                f"{cell.get((r, c), '-'):>{max(8, len(col[0]) + 3 + len(str(c))) if col else 8}s}"
                for c in cols
            )
        )
    return [line[:width] for line in out]


def summary(path: str | Path, plots: str | Path | None = None) -> str:
    """The summary text of a results file; ``plots`` the folder of its PNGs (default: beside
    the file).

    Raises
    ------
    InputError
        When the file cannot be read.
    """
    path = Path(path)
    plots = Path(plots) if plots is not None else path.parent
    width = max(80, min(140, shutil.get_terminal_size((120, 40)).columns))
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"cannot open results file {path}: {exc}") from None
    lines = []
    with f:
        groups = [(k, g) for k, g in f.items() if isinstance(g, h5py.Group)]
        n_ok = sum(g.attrs.get("status") == "ok" for _, g in groups)
        wall = sum(float(g.attrs.get("wall_time", 0.0)) for _, g in groups)
        lines.append(
            f"{path}: {len(groups)} cases, {n_ok} ok, {len(groups) - n_ok} not "
            f"(compute time {wall:.0f} s summed over the cases)"
        )
        sweeps = sweep_points(f)
        shown = [
            (k, g)
            for k, g in groups  # a large sweep: in its table below
            if len(sweeps.get(_text(g.attrs.get("sweep", "")), [])) <= MAX_POINT_PLOTS
        ]
        wname = min(34, max((len(k) for k, _ in shown), default=10))
        for k, g in shown:
            status = _text(g.attrs.get("status", ""))
            text = _headline(g) if status == "ok" else status
            lines.append(f"  {k[:wname]:{wname}s} {text}"[:width])
        for name, points in sweeps.items():
            if len(points) > MAX_POINT_PLOTS:
                lines += _sweep_table(name, points, width)
        for k, g in shown:  # a line case's assessment table (railvti.assessment)
            if _text(g.attrs.get("type", "")) == "line" and "assessment_passed" in g:
                lines.append(f"assessment of {k}:")
                lines += ["  " + t for t in _text(g["assessment_passed"].attrs.get("table", "")).splitlines()]
    pngs = sorted(plots.glob(f"{path.stem}_*.png")) if plots.is_dir() else []
    if pngs:
        lines.append(f"figures in {plots}/ ({len(pngs)} PNG files):")
        seen = set()
        for suffix, meaning in FIGURES:
            mine = [p for p in pngs if p.name.endswith(suffix) and p not in seen]
            seen.update(mine)
            if mine:
                lines.append(
                    textwrap.fill(
                        f"*{suffix} ({len(mine)}): {meaning}",
                        width,
                        initial_indent="  ",
                        subsequent_indent="      ",
                    )
                )
    return "\n".join(lines)


__all__ = ["FIGURES", "summary"]
