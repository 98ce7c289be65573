"""Profile readers: SIMPACK ``.prw`` / ``.prr`` files and plain two-column text or CSV, and
:func:`load` (a standard profile's name or a file, as decks give them)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from .profile import Profile
from .standard import s1002, uic60

#: Length units accepted for plain text files, as metres per unit.
UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254}

_DATA_DIR = Path(__file__).resolve().parent.parent / "data" / "profiles"


def example_path(name: str) -> Path:
    """Path of a profile file shipped with railvti (see ``railvti/data/profiles/NOTICE.md``).

    ``name`` is e.g. ``'MBench_S1002_v3.prw'`` or ``'MBench_UIC60_v3.prr'``.
    """
    p = _DATA_DIR / name
    if not p.is_file():
        have = sorted(q.name for q in _DATA_DIR.glob("*.pr?"))
        raise InputError(f"no shipped profile {name!r}; available: {have}")
    return p


def _num(text: str) -> float:
    return float(text.strip().strip("'\"").replace("D", "E").replace("d", "e"))


def _read_simpack(path: Path, unit: str | None, kind: str | None, name: str) -> Profile:
    header: dict[str, str] = {}
    pts: list[tuple[float, float]] = []
    in_points = False
    for lineno, raw in enumerate(path.read_text(errors="replace").splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("!"):
            continue
        low = line.lower()
        if low.startswith("point.begin"):
            in_points = True
            continue
        if low.startswith("point.end"):
            in_points = False
            continue
        if in_points:
            parts = line.split("!")[0].replace(",", " ").split()
            if len(parts) < 2:
                raise InputError(f"{path.name}:{lineno}: a point needs y and z, got {line!r}")
            try:
                pts.append((_num(parts[0]), _num(parts[1])))
            except ValueError:
                raise InputError(f"{path.name}:{lineno}: not a number in {line!r}") from None
            continue
        m = re.match(r"([\w.]+)\s*=\s*([^!]*)", line)
        if m:
            header.setdefault(m.group(1).lower(), m.group(2).strip())  # first wins: header.type
    if not pts:
        raise InputError(f"{path.name}: no profile points between point.begin and point.end")
    a = np.array(pts, dtype=np.float64)
    y, z = a[:, 0], a[:, 1]

    def hv(key: str, default: float) -> float:
        try:
            return _num(header[key]) if key in header else default
        except ValueError:
            raise InputError(f"{path.name}: header {key} = {header[key]!r} is not a number") from None

    # SIMPACK's processing order: shift, rotate, bounds, mirror, inversion, units.
    y = y + hv("shift.y", 0.0)
    z = z + hv("shift.z", 0.0)
    rot = hv("rotate", 0.0) / hv("units.ang.f", 1.0)
    if rot:
        y, z = y * np.cos(rot) - z * np.sin(rot), y * np.sin(rot) + z * np.cos(rot)
    ylo, yhi = hv("bound.y.min", 1.0), hv("bound.y.max", 0.0)
    if ylo < yhi:
        keep = (y >= ylo) & (y <= yhi)
        y, z = y[keep], z[keep]
    zlo, zhi = hv("bound.z.min", 1.0), hv("bound.z.max", 0.0)
    if zlo < zhi:
        keep = (z >= zlo) & (z <= zhi)
        y, z = y[keep], z[keep]
    if int(hv("mirror.y", 0)):
        y = -y
    if int(hv("mirror.z", 0)):
        z = -z
    if unit is not None:
        scale = _unit_scale(unit)
    else:
        factor = hv("units.len.f", 1.0)
        if not np.isfinite(factor) or factor <= 0:
            raise InputError(f"{path.name}: units.len.f must be > 0, got {factor}")
        scale = 1.0 / factor
    ftype = header.get("type")
    file_kind = {"0": "rail", "1": "wheel"}.get(ftype.strip() if ftype else "", None)
    k = kind or file_kind
    if k is None:
        k = "wheel" if path.suffix.lower() == ".prw" else "rail"
    return Profile(y * scale, z * scale, kind=k, name=name)


def _unit_scale(unit: str) -> float:
    try:
        return UNITS[unit.strip().lower()]
    except (KeyError, AttributeError):
        raise InputError(f"unit must be one of {sorted(UNITS)}, got {unit!r}") from None


def _read_columns(path: Path, unit: str, kind: str, name: str, z_up: bool) -> Profile:
    scale = _unit_scale(unit)
    rows: list[tuple[float, float]] = []
    for lineno, raw in enumerate(path.read_text(errors="replace").splitlines(), 1):
        line = raw.split("#")[0].split("!")[0].strip()
        if not line or line.startswith("%"):
            continue
        parts = [p for p in re.split(r"[,;\s]+", line) if p]
        if len(parts) < 2:
            raise InputError(f"{path.name}:{lineno}: expected two columns y z, got {raw!r}")
        try:
            rows.append((_num(parts[0]), _num(parts[1])))
        except ValueError:
            if rows:
                raise InputError(f"{path.name}:{lineno}: not a number in {raw!r}") from None
            continue  # a header line before the data
    if not rows:
        raise InputError(f"{path.name}: no numeric two-column data")
    a = np.array(rows, dtype=np.float64)
    z = -a[:, 1] if z_up else a[:, 1]
    return Profile(a[:, 0] * scale, z * scale, kind=kind, name=name)


def read(path: str | Path, unit: str | None = None, kind: str | None = None, z_up: bool = False) -> Profile:
    """Read a wheel or rail profile.

    Parameters
    ----------
    path : str or Path
        A SIMPACK profile (``.prw`` wheel, ``.prr`` rail: header processing such as
        ``mirror.y``, ``shift``, ``rotate``, ``units.len.f`` is applied), or a plain text /
        CSV file of two columns y, z (comma, semicolon or blank separated; lines starting
        with ``#``, ``!`` or ``%`` and a header line are skipped).
    unit : {'mm', 'm', 'cm', 'in'}, optional
        Length unit of the file. Required for plain text; for SIMPACK files it overrides
        ``units.len.f``. A profile whose size is implausible in the declared unit (e.g.
        metres declared as mm) is rejected.
    kind : {'wheel', 'rail'}, optional
        Required for plain text; SIMPACK files give it in their header.
    z_up : bool
        Plain text only: the file's z is positive upwards (it is negated; railvti's z
        points down).

    Returns
    -------
    Profile
        In railvti's coordinates (m, y towards the field side, z downwards). The file must
        already use that lateral orientation (flange / gauge face at negative y).

    Raises
    ------
    InputError
        Missing file, unknown unit or kind, no data, NaN, implausible size,
        self-intersecting or non-monotone profile.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"profile file not found: {p}")
    if kind is not None and kind not in ("wheel", "rail"):
        raise InputError(f"kind must be 'wheel' or 'rail', got {kind!r}")
    if p.suffix.lower() in (".prw", ".prr"):
        return _read_simpack(p, unit, kind, p.stem)
    if unit is None:
        raise InputError(f"{p.name}: give the length unit of a plain text profile (unit='mm' or 'm')")
    if kind is None:
        raise InputError(f"{p.name}: give kind='wheel' or kind='rail' for a plain text profile")
    return _read_columns(p, unit, kind, p.stem, z_up)


def load(spec: str | Path, kind: str, *, cant: float = 0.0) -> Profile:
    """A profile named as in a deck: a standard profile's name or a profile file.

    Parameters
    ----------
    spec : str or Path
        ``'s1002'`` (a wheel), ``'uic60'`` (a rail, inclined by ``cant``), a SIMPACK file
        (``.prw`` / ``.prr``) or a plain two-column text file in mm (see :func:`read`); a
        file's rail is taken as already canted.
    kind : {'wheel', 'rail'}
        What the profile must be.
    cant : float
        Rail inclination (tan) for ``'uic60'``.

    Returns
    -------
    Profile

    Raises
    ------
    InputError
        An unknown name or a missing file, or a bad file (see :func:`read`).
    """
    s = str(spec).strip()
    if s.lower() == "s1002" and kind == "wheel":
        return s1002()
    if s.lower() == "uic60" and kind == "rail":
        return uic60(cant=cant)
    path = Path(s)
    if path.suffix.lower() in (".prw", ".prr"):
        return read(path)
    if not path.is_file():
        raise InputError(f"{kind} must be 's1002'/'uic60' or a profile file, got {spec!r}")
    return read(path, unit="mm", kind=kind)


__all__ = ["UNITS", "example_path", "read", "load"]
