"""HDF5 results of a deck run (h5py); saving and loading one result object is
:mod:`railvti.runner.result_objects`.

Layout of a ``railvti run`` file (docs/results.md has the full description):

* file attributes: ``railvti_version``, ``deck`` (the deck's text), ``layout`` (this layout's
  version);
* one group per case, ``/NNN_name`` (NNN its position in the deck), with attributes ``type``,
  ``name``, ``status`` ('ok', 'error: <exception>: <message>' or 'interrupted: <signal> ...'),
  ``summary`` (ok cases), ``traceback`` (failed cases), ``wall_time`` (s) and
  ``params_digest`` (what ``railvti run --resume`` compares to know a case is done);
* a subgroup ``inputs``: the case's parameters as attributes (as before), and the same as
  scalar or 1-D datasets each with ``units`` and ``meaning`` attributes, so a case can be
  re-made from its group alone (:func:`case_deck`);
* the results as datasets, each with a ``units`` attribute, and where an array has more than
  one axis or labelled entries an ``axes`` attribute (one label per axis) and label
  attributes (``dof_names``, ``quantities``, ``wheel``...); ``empty_slots`` says what NaN
  marks where a result has fixed-size slots that may be unused.

The file is rewritten after every case: the new version (built in memory from the last one
up to :data:`MEMORY_IMAGE_BYTES`, else on disk from a copy) is written to a temporary file in
the same folder (``.NAME.PID.XXXX.tmp``, created with mode 0666 less the umask), flushed to
disk and renamed over the old one (``os.replace``), so whatever stops a run, the output is the
previous complete version or the new one, never a half-written file.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import re
import secrets
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from .. import __version__
from ..casetypes import CaseOutput, Streamed, split_labels  # noqa: F401 (split_labels: a name of this module too)
from ..casetypes import Case
from .guarded_io import GuardedFile, WriteFailed, failure, file_image, memory_h5, open_h5
from .h5_lowlevel import new_dataset, set_attr

__all__ = [
    "LAYOUT",
    "MAX_GROUP_NAME",
    "MEMORY_IMAGE_BYTES",
    "CaseRecord",
    "group_name",
    "params_digest",
    "attr_value",
    "AXIS_NAMES",
    "default_axes",
    "COPY_BLOCK_BYTES",
    "INTERRUPTED_COPY_BYTES",
    "INTERRUPTED_COPY_ENV",
    "write_case",
    "SIDE_NAME_MAX",
    "side_name",
    "temp_path",
    "is_results_file",
    "ResultsWriter",
    "deck_digest",
    "DeckOwner",
    "deck_owner",
    "completed",
    "damage",
    "write_results",
    "case_deck",
]

#: Version of the HDF5 layout written here.
LAYOUT = 2

#: Largest results file built in memory (the last version kept between cases, the new one
#: written with one write instead of copying the file and writing through the ``fileobj``
#: driver; memory: about three times this); larger files, whose write is the disk's time
#: either way, and cases with a streamed history are written on disk (0: every version on
#: disk).
MEMORY_IMAGE_BYTES = 16 * 2**20

#: Longest case group name (longer names are cut and end in a digest of the full name).
MAX_GROUP_NAME = 120


@dataclass
class CaseRecord:
    """A case with its output, or the error or signal that stopped it.

    Attributes
    ----------
    case : Case
    output : CaseOutput or None
    error : str or None
        'ExceptionClass: message' of a failed case.
    traceback : str
        The failed case's traceback.
    interrupted : str or None
        The signal that stopped the case ('SIGINT', 'SIGTERM').
    wall_time : float
        Seconds the case ran.
    """

    case: Case
    output: CaseOutput | None = None
    error: str | None = None
    traceback: str = ""
    interrupted: str | None = None
    wall_time: float = float("nan")

    @property
    def status(self) -> str:
        """The group's ``status`` attribute."""
        if self.interrupted is not None:
            return f"interrupted: {self.interrupted} after {self.wall_time:.1f} s"
        if self.error is not None:
            return f"error: {self.error}"
        return "ok"


def group_name(case: Case) -> str:
    """The HDF5 group of a case: ``NNN_name``, '/' replaced, cut to :data:`MAX_GROUP_NAME`."""
    name = re.sub(r"[/\x00]", "_", case.name) or "_"
    full = f"{case.index:03d}_{name}"
    if len(full) > MAX_GROUP_NAME:
        digest = hashlib.sha1(case.name.encode("utf-8", "replace")).hexdigest()[:10]
        full = f"{full[: MAX_GROUP_NAME - 11]}~{digest}"
    return full


def params_digest(case: Case) -> str:
    """A digest of a case's type, name and parameters (equal digests: the same case)."""
    text = json.dumps(
        [case.case_type.name, case.name, sorted(case.params.items())], default=repr, sort_keys=True
    )
    return hashlib.sha256(text.encode("utf-8", "replace")).hexdigest()


def attr_value(value: Any) -> Any:
    """A value as an HDF5 attribute stores it (None as 'none', text without NULs, text
    sequences as variable-length strings)."""
    if value is None:
        return "none"
    if isinstance(value, str):
        return value.replace("\x00", "\\0")  # HDF5 strings end at a NUL
    if isinstance(value, (list, tuple)):
        arr = np.asarray(value)
        return arr.astype(object).astype(h5py.string_dtype()) if arr.dtype.kind == "U" else arr
    return value


def _set_attr(obj: Any, name: str, value: Any) -> None:
    """obj.attrs[name] = value (``obj`` an h5py object or its identifier), through h5py's
    low-level calls for numbers and text (railvti.runner.h5_lowlevel: the same HDF5 objects,
    a case writes some 220 attributes)."""
    set_attr(obj, name, value)


def _data(value: Any) -> Any:
    """A value h5py can store as a dataset (text arrays as variable-length UTF-8)."""
    arr = np.asarray(value)
    if arr.dtype.kind == "U":
        return arr.astype(object).astype(h5py.string_dtype())
    return arr if arr.ndim else value


def _input_unit(case: Case, key: str) -> tuple[str, str]:
    """(unit, meaning) of a deck key: from the case type's key table when it has one, else
    from the key's name (``_mm``, ``_kmh``...), else 'see railvti cases'."""
    spec = getattr(case.case_type, "keys", {}).get(key) if hasattr(case.case_type, "keys") else None
    if spec is not None:
        unit = getattr(spec, "unit", "") or ("text" if isinstance(case.params.get(key), str) else "1")
        return unit, getattr(spec, "meaning", "") or ""
    return _guess_unit(key, case.params.get(key)), ""


_UNIT_SUFFIXES = (
    ("_kmh", "km/h"),
    ("_mm", "mm"),
    ("_deg", "deg"),
    ("_hz", "Hz"),
    ("_s", "s"),
    ("_m", "m"),
    ("_n", "N"),
    ("_pa", "Pa"),
    ("_kg", "kg"),
)
_KNOWN_UNITS = {
    "shear_modulus": "Pa",
    "g": "Pa",
    "poisson": "1",
    "nu": "1",
    "dx": "m",
    "dy": "m",
    "x0": "m",
    "y0": "m",
    "gap_a": "1/m",
    "gap_b": "1/m",
    "bump_separation": "m",
    "bump_height": "m",
    "fn": "N",
    "approach": "m",
    "tol": "1",
    "max_iter": "1",
    "mu": "1",
    "xi": "1",
    "eta": "1",
    "phi": "1/m",
    "speed": "m/s",
    "duration": "s",
    "h": "s",
    "alpha": "1",
    "output_dt": "s",
    "semi_a": "m",
    "semi_b": "m",
    "nx": "1",
    "ny": "1",
    "n": "1",
    "cant": "1 (tan of the rail inclination)",
    "yaw_mrad_per_mm": "mrad/mm",
}


#: Units by a word in the key's name (the first match), for keys without a Key table entry.
_UNIT_WORDS = (
    ("stiffness", "N/m"),
    ("damping_ratio", "1"),
    ("damping", "N s/m"),
    ("young", "Pa"),
    ("density", "kg/m^3"),
    ("mass", "kg"),
    ("poisson", "1"),
    ("loss_factor", "1"),
    ("factor", "1"),
    ("mesh_max_area", "m^2"),
    ("kappa", "1/m"),
    ("n_", "1"),
    ("k_max", "1"),
    ("web_steps", "1"),
    ("f_", "Hz"),
    ("omega", "rad/s"),
    ("fz", "N"),
    ("radius", "m"),
    ("length", "m"),
    ("width", "m"),
    ("spacing", "m"),
    ("distance", "m"),
    ("offset", "m"),
    ("height", "m"),
    ("depth", "m"),
    ("size", "m"),
    ("thickness", "m"),
    ("back_to_back", "m"),
    ("arc_step", "m"),
    ("k_", "N/m"),
)


def _guess_unit(key: str, value: Any) -> str:
    if isinstance(value, str):
        return "text"
    if key in _KNOWN_UNITS:
        return _KNOWN_UNITS[key]
    low = key.lower()
    if "_kmh" in low:
        return "km/h"
    for suffix, unit in _UNIT_SUFFIXES:
        if low.endswith(suffix):
            return unit
    for word, unit in _UNIT_WORDS:
        if low.startswith(word) if word.endswith("_") else word in low:
            return unit
    return "see 'railvti cases'"


def _write_inputs(g: h5py.Group, case: Case) -> None:
    gi = g.create_group("inputs")
    for key, value in case.params.items():
        _set_attr(gi, key, attr_value(value))
        unit, meaning = _input_unit(case, key)
        d = new_dataset(gi, key, _data(attr_value(value)))
        _set_attr(d, "units", unit)
        if meaning:
            _set_attr(d, "meaning", meaning)
        if value is None:
            _set_attr(d, "none", 1)


#: Datasets that are an axis of the others when their length matches (in this order).
AXIS_NAMES = ("t", "freq", "speeds_kmh", "y", "x")


def default_axes(name: str, arr: np.ndarray, output: CaseOutput) -> list[str] | None:
    """Axis labels of a result array from the case's axis datasets (``t``, ``freq``, ``x``,
    ``y``...) whose lengths match, when the case did not give them."""
    if arr.ndim == 0 or name in AXIS_NAMES:
        return [name] if arr.ndim == 1 else None
    lengths = {a: np.asarray(output.datasets[a][0]).shape for a in AXIS_NAMES if a in output.datasets}
    lengths = {a: s[0] for a, s in lengths.items() if len(s) == 1}
    if arr.ndim == 2 and {"x", "y"} <= set(lengths) and arr.shape == (lengths["x"], lengths["y"]):
        return ["x", "y"]
    first = next((a for a in AXIS_NAMES if lengths.get(a) == arr.shape[0]), None)
    if first is None:
        return None
    return [first] + [f"axis {i}" for i in range(1, arr.ndim)]


def _unit_text(units: str, arr: np.ndarray) -> str:
    """A unit for every dataset: '1' for a number without unit, 'text' for text."""
    if units:
        return units
    return "text" if arr.dtype.kind in "OSU" else "1"


#: Bytes read at a time when a streamed dataset is copied into a results file.
COPY_BLOCK_BYTES = 16 * 2**20


#: An interrupted case keeps at most this much of its streamed history (its first rows): the
#: stop waits for the copy, and must stay within a second however long the run was. The
#: environment variable RAILVTI_INTERRUPTED_COPY_MB overrides it (MB).
INTERRUPTED_COPY_BYTES = 48 * 2**20
INTERRUPTED_COPY_ENV = "RAILVTI_INTERRUPTED_COPY_MB"


def _copy_streamed(
    g: h5py.Group, name: str, ref: Streamed, compress: bool = True, rows: int | None = None, check: Any = None
) -> h5py.Dataset:
    """Copy a streamed dataset (railvti.runner.stream) into ``g`` as ``name``, chunked and
    compressed as a dataset written whole is (h5py's chunk shape, gzip 4), in blocks of
    :data:`COPY_BLOCK_BYTES`: memory stays bounded whatever its length. ``compress=False``
    (an interrupted case, whose stop should be prompt): not compressed, 5 x faster (180 s
    of hunting history: 1.2 s instead of 5.9 s), the file 2.3 x larger. ``rows``: only the
    first rows. ``check()`` after each block raises if the output cannot be written."""
    with h5py.File(ref.path, "r") as src:
        s = src[ref.name]
        n = s.shape[0] if rows is None else min(rows, s.shape[0])
        opts = {"compression": "gzip", "compression_opts": 4} if s.size > 16 and compress else {}
        d = g.create_dataset(
            name,
            shape=(n,) + s.shape[1:],
            dtype=s.dtype,  # as a whole write's
            **(dict(opts, chunks=True) if opts else {}),
        )
        step = max(1, COPY_BLOCK_BYTES // max(1, s.dtype.itemsize * int(np.prod(s.shape[1:]))))
        for i in range(0, n, step):
            d[i : min(i + step, n)] = s[i : min(i + step, n)]
            if check is not None:
                check()
    return d


def _write_dataset(
    g: h5py.Group,
    name: str,
    spec: tuple,
    output: CaseOutput | None = None,
    compress: bool = True,
    rows: int | None = None,
    check: Any = None,
) -> None:
    arr, units = spec[0], spec[1]
    extra = dict(spec[2]) if len(spec) > 2 else {}
    if output is not None:
        extra.update(getattr(output, "attrs", {}).get(name, {}))
    if isinstance(arr, Streamed):
        d = _copy_streamed(g, name, arr, compress, rows, check)
        _set_attr(d, "units", units or "1")
        for k, v in extra.items():
            _set_attr(d, k, attr_value(v))
        return
    arr = np.asarray(_data(arr))
    units = _unit_text(units, arr)
    if "axes" not in extra and output is not None:
        axes = default_axes(name, arr, output)
        if axes is not None:
            extra["axes"] = axes
    d = new_dataset(g, name, arr, compress=arr.ndim > 0 and arr.size > 16)
    _set_attr(d, "units", units)
    for k, v in extra.items():
        _set_attr(d, k, attr_value(v))


def _interrupted_rows(g: h5py.Group, output: CaseOutput) -> int | None:
    """Rows of an interrupted case's streamed history that fit INTERRUPTED_COPY_BYTES (None:
    all of them); a cut is noted on the case's group (attribute ``history_rows_kept``)."""
    refs = [spec[0] for spec in output.datasets.values() if isinstance(spec[0], Streamed)]
    if not refs:
        return None
    row_bytes, n = 0, None
    for ref in refs:
        with h5py.File(ref.path, "r") as src:
            s = src[ref.name]
            row_bytes += s.dtype.itemsize * int(np.prod(s.shape[1:]))
            n = s.shape[0] if n is None else min(n, s.shape[0])
    budget = INTERRUPTED_COPY_BYTES
    try:
        budget = int(float(os.environ[INTERRUPTED_COPY_ENV]) * 2**20)
    except KeyError:
        pass
    except ValueError:  # an interrupted run still ends cleanly: warn, keep the default
        logging.getLogger("railvti").warning(
            "environment variable %s = %r is not a number of MB; using %g MB",
            INTERRUPTED_COPY_ENV,
            os.environ[INTERRUPTED_COPY_ENV],
            budget / 2**20,
        )
    keep = max(1, budget // max(row_bytes, 1))
    if n is None or keep >= n:
        return None
    g.attrs["history_rows_kept"] = (
        f"{keep} of {n}: the interrupted case keeps the first "
        f"{budget / 2**20:.3g} MB of its streamed history (a "
        "prompt stop); --resume runs it again"
    )
    return keep


def write_case(f: h5py.File, rec: CaseRecord, check: Any = None) -> None:
    """Write (or replace) one case's group in an open results file; ``check()`` (if given)
    after each dataset raises if the file cannot be written (railvti.runner.guarded_io)."""
    c = rec.case
    name = group_name(c)
    if name in f:
        del f[name]
    g = f.create_group(name)
    _set_attr(g, "type", c.case_type.name)
    _set_attr(g, "name", c.name)
    _set_attr(g, "status", str(rec.status))
    _set_attr(g, "params_digest", params_digest(c))
    _set_attr(g, "wall_time", float(rec.wall_time))
    if getattr(c, "sweep", ""):  # a sweep's point (railvti.runner.sweeps.SweepPoint)
        g.attrs["sweep"] = c.sweep
        g.attrs["sweep_point"] = c.point_json
    if rec.traceback:
        g.attrs["traceback"] = rec.traceback
    _write_inputs(g, c)
    if rec.output is None:
        return
    _set_attr(g, "summary", str(rec.output.summary))
    # an interrupted case's streamed history is copied uncompressed and, beyond
    # INTERRUPTED_COPY_BYTES, only its first rows: the stop waits for the copy
    interrupted = str(rec.status).startswith("interrupted")
    rows = _interrupted_rows(g, rec.output) if interrupted else None
    check = check or (lambda: None)
    for dname, spec in rec.output.datasets.items():
        _write_dataset(g, dname, spec, rec.output, not interrupted, rows, check)
        check()
    for dname, spec in rec.output.scalars.items():
        _write_dataset(g, dname, spec, rec.output)
        check()


def _fsync(path: Path) -> None:
    with open(path, "rb") as fh:
        os.fsync(fh.fileno())


#: Longest output name used whole in the names of its side files (temporary files, the lock):
#: a longer one is cut and ends in a digest, so the side file stays under NAME_MAX (255).
SIDE_NAME_MAX = 160


def side_name(path: Path) -> str:
    """The output's name as used in its side files (cut to :data:`SIDE_NAME_MAX`)."""
    name = path.name
    if len(name.encode("utf-8", "surrogateescape")) <= SIDE_NAME_MAX:
        return name
    digest = hashlib.sha1(name.encode("utf-8", "surrogateescape")).hexdigest()[:10]
    return (
        name.encode("utf-8", "surrogateescape")[: SIDE_NAME_MAX - 11].decode("utf-8", "ignore") + "~" + digest
    )


def temp_path(path: Path) -> Path:
    """A new temporary file beside ``path`` (mode 0666 less the umask), created empty."""
    while True:
        tmp = path.parent / f".{side_name(path)}.{os.getpid()}.{secrets.token_hex(4)}.tmp"
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp


def is_results_file(path: str | Path) -> bool:
    """Whether ``path`` is an HDF5 file written by railvti (its ``railvti_version`` attribute)."""
    try:
        with h5py.File(path, "r") as f:
            return "railvti_version" in f.attrs
    except (OSError, ValueError):
        return False


class ResultsWriter:
    """Writes the cases of a run to one file, replacing it atomically after each case.

    Parameters
    ----------
    path : path
        The results file.
    deck_text : str
        The deck, stored as the file's ``deck`` attribute.
    keep : bool
        Keep the cases of an existing results file at ``path`` (``--resume``); otherwise
        the first write starts a new file (the old one stays until then).
    deck_path : str
        The deck's file (absolute), stored as ``deck_path`` (see :func:`deck_owner`).
    cases : list of Case, optional
        The deck's cases: their :func:`deck_digest` is stored as ``deck_digest``.

    A write that fails (disk full, quota, I/O error, the rename refused) raises
    :class:`railvti.runner.guarded_io.WriteFailed`; the temporary file is removed and the file at
    ``path`` is the last complete version. HDF5 never sees the failure (railvti.runner.guarded_io),
    so the process stays sound and exits normally.
    """

    def __init__(
        self,
        path: str | Path,
        deck_text: str = "",
        keep: bool = False,
        deck_path: str = "",
        cases: list[Case] | None = None,
    ) -> None:
        self.path = Path(path)
        self.deck_text = deck_text
        self.deck_path = str(deck_path)
        self.deck_digest = deck_digest(cases) if cases is not None else ""
        self._fresh = not keep
        self._own = False  # the file at path is this writer's last version (its attributes set)
        self._stamp: tuple = ()  # (device, inode, size, mtime) of that version
        self._image: bytes | None = None  # its bytes, when built in memory
        self.pending: Path | None = None

    def write(self, records: list[CaseRecord]) -> None:
        """Add or replace the groups of ``records`` and replace the file atomically.

        Raises
        ------
        WriteFailed
            The file could not be written; the previous version is untouched.
        """
        tmp: Path | None = None
        fh: GuardedFile | None = None
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            tmp = temp_path(self.path)
            self.pending = tmp
            image = self._base_image(records)
            if image is not None:  # built in memory, written in one go
                data = self._in_memory(image, records)
                fh = GuardedFile(tmp, "w")
                fh.write(data)
            else:
                self._image = None
                fh = self._on_disk(tmp, records)
            fh.sync()
            fh.close()
            os.replace(tmp, self.path)
            self._fresh = False
            self._own = True
            self._stamp = _stamp(self.path)
            if image is not None:  # the next version's base; a larger one is rebuilt on disk
                self._image = data if len(data) <= MEMORY_IMAGE_BYTES else None
        except WriteFailed:
            raise
        except OSError as exc:  # creating, copying, syncing or renaming the file
            raise failure(self.path, exc) from None
        finally:
            self.pending = None
            if fh is not None:
                fh.close()
            if tmp is not None:
                try:
                    tmp.unlink(missing_ok=True)
                except OSError:
                    pass

    def _base_image(self, records: list[CaseRecord]) -> bytes | None:
        """What the new version is built on in memory: b'' (a new file), the bytes of this
        writer's last version (kept when it was at most :data:`MEMORY_IMAGE_BYTES`), or None:
        on disk (a file of another run, a large one, or a record with a streamed history)."""
        streamed = any(
            isinstance(spec[0], Streamed) for r in records if r.output for spec in r.output.datasets.values()
        )
        if streamed or MEMORY_IMAGE_BYTES <= 0:
            return None
        if self._fresh:
            return b""
        return self._image if self._image is not None and self._mine() else None

    def _in_memory(self, image: bytes, records: list[CaseRecord]) -> bytes:
        """The new version's bytes: ``image`` (b'': a new file) with ``records`` written."""
        with memory_h5(image) as f:
            if not image:
                self._write_attrs(f)
            for rec in records:
                write_case(f, rec)
            return file_image(f)

    def _on_disk(self, tmp: Path, records: list[CaseRecord]) -> GuardedFile:
        """The new version written into ``tmp`` on disk (the file so far copied first)."""
        copy = not self._fresh and self.path.is_file() and (self._mine() or is_results_file(self.path))
        if copy:
            shutil.copyfile(self.path, tmp)
        fh = GuardedFile(tmp, "a" if copy else "w")
        try:
            with open_h5(fh, "a" if copy else "w") as f:
                if not (copy and self._mine()):  # a copy of its own last version has them
                    self._write_attrs(f)
                for rec in records:
                    write_case(f, rec, fh.check)
                    fh.check()
        except WriteFailed:
            fh.close()
            raise
        except Exception:
            fh.close()
            fh.check()  # an HDF5 error that follows a failed write: say the write's
            raise  # not: a value HDF5 refuses (the caller records it)
        return fh

    def _mine(self) -> bool:
        """Whether the file at path is still this writer's last version (the same inode,
        size and time): a results file with its attributes, not opened again to check
        (~2 ms of each case)."""
        return self._own and _stamp(self.path) == self._stamp

    def _write_attrs(self, f: h5py.File) -> None:
        f.attrs["railvti_version"] = __version__
        f.attrs["layout"] = LAYOUT
        f.attrs["deck"] = self.deck_text.replace("\x00", "\\0")
        if self.deck_path:
            f.attrs["deck_path"] = self.deck_path.replace("\x00", "\\0")
        if self.deck_digest:
            f.attrs["deck_digest"] = self.deck_digest


def _stamp(path: Path) -> tuple:
    try:
        st = os.stat(path)
    except OSError:
        return ()
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def deck_digest(cases: list[Case]) -> str:
    """A digest of a deck's case groups and types (not their parameters): equal for a deck
    whose cases' parameters changed, different once a case is added, renamed or removed."""
    text = json.dumps(sorted([group_name(c), c.case_type.name] for c in cases))
    return hashlib.sha256(text.encode("utf-8", "replace")).hexdigest()


@dataclass(frozen=True)
class DeckOwner:
    """Whether a results file belongs to a deck (:func:`deck_owner`).

    Attributes
    ----------
    same : bool
    deck_path : str
        The deck the file was written from ('' if not recorded: a file of an older railvti).
    groups : int
        Case groups in the file.
    shared : int
        Of those, groups with the name and type of a case of the deck.
    """

    same: bool
    deck_path: str = ""
    groups: int = 0
    shared: int = 0

    def describe(self) -> str:
        """'written from deck X (N cases, M of them in this deck)'."""
        src = f"written from {self.deck_path}" if self.deck_path else "written from another deck"
        cases = "1 case" if self.groups == 1 else f"{self.groups} cases"
        return f"{src} ({cases}, {self.shared} of them in this deck)"


def deck_owner(path: str | Path, deck_path: str | Path, cases: list[Case]) -> DeckOwner:
    """Whether the railvti results file ``path`` belongs to the deck (``deck_path``, its
    ``cases``).

    The rule (docs/results.md, "An output file belongs to one deck"): the file belongs to the
    deck when it was written from the same deck file (its ``deck_path`` attribute, the
    resolved path), when its ``deck_digest`` (case groups and types) is the deck's, or when
    at least half of its case groups have the name and type of a case of the deck. The
    parameters do not count: editing a case's parameters and running with ``--resume`` is
    what ``--resume`` is for (it re-runs the changed cases). A renamed or moved deck keeps
    its case names; two unrelated decks share few. A file with no case group belongs to
    any deck.
    """
    mine = {group_name(c): c.case_type.name for c in cases}
    with h5py.File(path, "r") as f:
        src = str(f.attrs.get("deck_path", ""))
        digest = str(f.attrs.get("deck_digest", ""))
        groups = {k: str(g.attrs.get("type", "")) for k, g in f.items() if isinstance(g, h5py.Group)}
    shared = sum(1 for k, t in groups.items() if mine.get(k) == t)
    here = str(Path(deck_path).resolve()) if str(deck_path) else ""
    same = (
        (bool(src) and src == here)
        or (bool(digest) and digest == deck_digest(cases))
        or not groups
        or 2 * shared >= len(groups)
    )
    return DeckOwner(same, src, len(groups), shared)


def completed(path: str | Path) -> dict[str, str]:
    """Group name -> params digest of every case of a results file with status 'ok'
    (empty if the file does not exist or is not a railvti results file)."""
    path = Path(path)
    if not path.is_file() or not is_results_file(path):
        return {}
    with h5py.File(path, "r") as f:
        return {
            k: str(g.attrs.get("params_digest", ""))
            for k, g in f.items()
            if isinstance(g, h5py.Group) and g.attrs.get("status") == "ok"
        }


def damage(path: str | Path) -> str:
    """Where a results file is damaged ('' if every case group, attribute and dataset reads):
    what ``--resume`` checks before it keeps a file's cases (a damaged file copied and
    written again would carry the damage on). Datasets are read in blocks of
    :data:`COPY_BLOCK_BYTES` (memory stays bounded; time: the file read once)."""
    where = str(path)
    try:
        with h5py.File(path, "r") as f:
            dict(f.attrs)

            def visit(name: str, obj: Any) -> None:
                nonlocal where
                where = f"{obj.name}"
                dict(obj.attrs)
                if isinstance(obj, h5py.Dataset) and obj.shape:
                    row = max(1, obj.dtype.itemsize * int(np.prod(obj.shape[1:])))
                    step = max(1, COPY_BLOCK_BYTES // row)
                    for i in range(0, obj.shape[0], step):
                        obj[i : i + step]
                elif isinstance(obj, h5py.Dataset):
                    obj[()]

            f.visititems(visit)
    except Exception as exc:  # noqa: BLE001 - any failure to read is damage
        return f"{where}: {exc}"
    return ""


def write_results(path: str | Path, records: list[CaseRecord], deck_text: str = "") -> Path:
    """Write the records of a run to ``path`` atomically and return it."""
    ResultsWriter(path, deck_text).write(records)
    return Path(path)


def case_deck(path: str | Path, group: str) -> str:
    """The ``&case`` group that re-makes a stored case (from its ``inputs`` alone)."""
    with h5py.File(path, "r") as f:
        g = f[group]
        lines = [
            "&case",
            f"    name = {_nml(str(g.attrs['name']))}",
            f"    type = {_nml(str(g.attrs['type']))}",
        ]
        for key, value in g["inputs"].attrs.items():
            if isinstance(value, str) and value == "none":
                continue
            lines.append(f"    {key} = {_nml(value)}")
    return "\n".join(lines + ["/", ""])


def _nml(value: Any) -> str:
    if isinstance(value, (bytes, np.bytes_)):
        value = value.decode()
    if isinstance(value, str):
        return "'" + value.replace("'", "''") + "'"
    if isinstance(value, np.ndarray):
        return ", ".join(_nml(v) for v in value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return ".true." if value else ".false."
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return str(value)
