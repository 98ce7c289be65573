"""Measured track irregularities in a CSV file: read one into a TrackIrregularity, write one.

The format (UTF-8 text, comma separated)::

    # lines starting with # are comments, anywhere; blank lines are skipped
    x [m], vertical_level [mm], alignment [mm], cross_level [mm], gauge [mm]
    0.00, 0.12, -0.40, 0.05, 0.30
    0.25, 0.18, -0.38, 0.02, 0.31
    ...

The first row that is not a comment is the header: each column is ``name [unit]`` with the
name ``x`` or one of the four channels of :data:`railvti.track.CHANNELS` (any order, each
once, all five present; names and units in any case) and the unit ``m`` or ``mm``
(converted to m on reading). Every
further row holds one finite number per column; x strictly increases, at least 2 rows. The
conventions of the channels (y left, z up, cross level = left minus right rail height) are
those of :class:`railvti.track.TrackIrregularity`. Every error names the file and the line.
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError
from .irregularity import CHANNELS, TrackIrregularity

__all__ = ["COLUMNS", "UNITS", "read_csv", "write_csv"]

#: The columns a file must have (in any order).
COLUMNS = ("x", *CHANNELS)
#: Accepted units -> metres per unit.
UNITS = {"m": 1.0, "mm": 1.0e-3}

_HEADER_CELL = re.compile(r"^(?P<name>[^\[\]]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?$")


def _header(path: Path, line: int, text: str) -> tuple[list[str], list[float]]:
    """The columns' names and their scales to m, from the header row."""
    names, scales = [], []
    for i, cell in enumerate(text.split(",")):
        m = _HEADER_CELL.match(cell.strip())
        name = m.group("name").strip().lower() if m else cell.strip()
        if not m or name not in COLUMNS:
            raise InputError(
                f"{path}, line {line}: column {i + 1} {name!r} is not one of {', '.join(COLUMNS)} "
                "(header cells are 'name [unit]')"
            )
        if name in names:
            raise InputError(f"{path}, line {line}: column {name!r} appears twice")
        unit = m.group("unit")
        if unit is None or not unit.strip():
            raise InputError(
                f"{path}, line {line}: column {name!r} has no unit; write '{name} [m]' or '{name} [mm]'"
            )
        unit = unit.strip()
        if unit.lower() not in UNITS:
            raise InputError(
                f"{path}, line {line}: column {name!r}: unknown unit {unit!r}; valid: {', '.join(UNITS)}"
            )
        names.append(name)
        scales.append(UNITS[unit.lower()])
    missing = [c for c in COLUMNS if c not in names]
    if missing:
        raise InputError(f"{path}, line {line}: missing column(s) {', '.join(missing)} in the header")
    return names, scales


def _row(path: Path, line: int, text: str, names: list[str]) -> list[float]:
    cells = text.split(",")
    if len(cells) != len(names):
        raise InputError(f"{path}, line {line}: {len(cells)} values, the header names {len(names)} columns")
    values = []
    for name, cell in zip(names, cells, strict=True):
        try:
            v = float(cell)
        except ValueError:
            raise InputError(f"{path}, line {line}: {name}: {cell.strip()!r} is not a number") from None
        if not math.isfinite(v):
            raise InputError(f"{path}, line {line}: {name}: {cell.strip()!r} is not finite")
        values.append(v)
    return values


def read_csv(path: str | os.PathLike) -> TrackIrregularity:
    """Read a measured track irregularity from a CSV file (format: the module's docstring).

    Parameters
    ----------
    path : str or path-like
        The file.

    Returns
    -------
    TrackIrregularity
        x and the four channels in m; ``source`` is ``"file <path>"``.

    Raises
    ------
    InputError
        Naming the file and line: no header, an unknown or missing column, a missing or unknown
        unit, a row with the wrong number of values, a value that is not a finite number, x not
        strictly increasing, fewer than 2 rows. A file that cannot be read raises InputError too.
    """
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8-sig").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the track irregularity file ({exc})") from None
    names: list[str] | None = None
    scales: list[float] = []
    rows: list[list[float]] = []
    row_lines: list[int] = []
    for number, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text or text.startswith("#"):
            continue
        if names is None:
            names, scales = _header(path, number, text)
            continue
        rows.append(_row(path, number, text, names))
        row_lines.append(number)
    if names is None:
        raise InputError(f"{path}: no header row (expected e.g. 'x [m], {' [mm], '.join(CHANNELS)} [mm]')")
    if len(rows) < 2:
        where = f"line {row_lines[-1]}" if row_lines else f"line {len(lines)}"
        raise InputError(f"{path}, {where}: {len(rows)} data row(s); a track needs at least 2")
    data = np.array(rows) * np.array(scales)
    cols = {name: data[:, i] for i, name in enumerate(names)}
    x = cols["x"]
    bad = np.flatnonzero(np.diff(x) <= 0.0)
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"{path}, line {row_lines[i + 1]}: x = {x[i + 1]:.9g} m does not increase "
            f"(line {row_lines[i]}: x = {x[i]:.9g} m); x must be strictly increasing"
        )
    return TrackIrregularity(x, *(cols[c] for c in CHANNELS), source=f"file {path}")


def write_csv(path: str | os.PathLike, irr: TrackIrregularity) -> None:
    """Write a track irregularity as a CSV file that :func:`read_csv` reads back.

    x in m, the channels in mm, 17 significant digits (read back to within a rounding of the
    mm -> m scaling, ~1e-16 relative); the source as a comment. Atomic: written to a temporary
    file in the same folder, then renamed over ``path``, so a reader never sees half a file.

    Parameters
    ----------
    path : str or path-like
        The file to write (replaced if it exists).
    irr : TrackIrregularity
        The track.
    """
    if not isinstance(irr, TrackIrregularity):
        raise InputError(f"irr: a TrackIrregularity, got {type(irr).__name__}")
    path = Path(path)
    header = "x [m], " + ", ".join(f"{c} [mm]" for c in CHANNELS)
    source = " ".join(irr.source.split())  # one comment line
    out = [
        "# railvti track irregularity, EN 13848-1 channels: y left, z up, cross level = left - right height",
        *([f"# source: {source}"] if source else []),
        header,
    ]
    data = np.column_stack([irr.x, *(1.0e3 * getattr(irr, c) for c in CHANNELS)])
    out.extend(", ".join(repr(float(v)) for v in row) for row in data)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write("\n".join(out) + "\n")
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
        tmp = None
    finally:
        if tmp is not None:
            os.unlink(tmp)
