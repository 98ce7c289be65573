"""A disk cache of built tables: what a new process (a Dask worker, the next run) would
otherwise build again, stored under a digest of everything it depends on.

The vehicle's contact table (railvti.vehicle.table.wheel_table, ~3.5 s), the strip geometry
(railvti.vehicle.strip.strip_geometry, ~0.3 s with its scipy import) and the profiles'
equivalent conicity (railvti.vehicle.systems.hunting_conicity, ~0.5 s) are built once per
process; every worker of a sweep paid them before its first task (issue 33, docs/sweeps.md
"Scaling"). Loaded, they take milliseconds and are the built arrays bit for bit.

Where
    ``$RAILVTI_CACHE_DIR`` when it is set; set to the empty string, the cache is off (every
    table is built, nothing is read or written). Otherwise the platform's user cache folder:
    ``$XDG_CACHE_HOME/railvti`` or ``~/.cache/railvti`` (Linux), ``~/Library/Caches/railvti``
    (macOS), ``%LOCALAPPDATA%\\railvti\\Cache`` (Windows).
Key
    sha256 over the entry's kind, :data:`FORMAT_VERSION`, railvti's and numpy's versions, a
    fingerprint of the installed package's code (its ``.py`` files and compiled core: an
    edited development install never reads what older code built) and the builder's inputs
    (arrays by dtype, shape and bytes; floats exactly; dataclasses field by field).
File
    ``KIND-KEY.npz``, uncompressed, no pickled objects (read with ``allow_pickle=False``):
    the arrays, the key, the format version and a sha256 of the arrays. Written to a
    temporary file in the cache folder and renamed over the entry (atomic: two processes
    writing one entry at once leave one whole file, a reader sees a whole file or none).
    Read with validation: a file that does not open, belongs to another key or format, or
    whose checksum does not match is ignored with a warning on the ``railvti`` logger; the
    caller builds the table again and rewrites the entry. The most recently used entries of a
    kind are kept, at most :data:`MAX_ENTRIES` and :data:`MAX_BYTES` together.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import logging
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from ._native import core

__all__ = [
    "ENV",
    "FORMAT_VERSION",
    "MAX_BYTES",
    "MAX_ENTRIES",
    "Recorder",
    "cache_dir",
    "code_fingerprint",
    "digest",
    "load",
    "store",
]

log = logging.getLogger("railvti")

#: The environment variable naming the cache folder ("" turns the cache off).
ENV = "RAILVTI_CACHE_DIR"
#: Version of the file layout; part of every key.
FORMAT_VERSION = 1
#: Entries of one kind kept (the most recently used); older ones are removed on a write.
MAX_ENTRIES = 16
#: Bytes of one kind kept: the most recently used entries up to this size (the newest always),
#: so large builds (a ring track's entry is ~31 MB) keep a few, not MAX_ENTRIES.
MAX_BYTES = 128 * 2**20
#: A temporary file older than this (s) is a crashed writer's and is removed.
_STALE_TMP = 3600.0
_warned: set[str] = set()


def cache_dir() -> Path | None:
    """The cache folder (:data:`ENV`, else the platform's user cache folder), or None when the
    cache is off (``RAILVTI_CACHE_DIR=""``). Not created here."""
    env = os.environ.get(ENV)
    if env is not None:
        return Path(env).expanduser() if env.strip() else None
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA") or str(Path.home() / "AppData" / "Local")
        return Path(base, "railvti", "Cache")
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "railvti"
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    return Path(xdg if xdg.strip() else Path.home() / ".cache") / "railvti"


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """sha256 of the installed railvti package's code: every ``.py`` file and compiled
    extension in its folder and the Fortran core that was loaded (wherever an editable
    install keeps it), by name and content (~3 MB, read once per process)."""
    root = Path(__file__).resolve().parent
    files = {p.resolve() for p in root.rglob("*") if p.suffix in (".py", ".so", ".pyd") and p.is_file()}
    files.add(Path(core.__file__).resolve())
    h = hashlib.sha256()
    for p in sorted(files):
        h.update(p.name.encode() + b"\0")
        h.update(p.read_bytes())
    return h.hexdigest()


def _feed(h: Any, x: Any) -> None:
    """Feed one key part into the hash h, typed and length-prefixed (no two parts alike)."""
    if x is None:
        h.update(b"N")
    elif isinstance(x, (bool, np.bool_)):
        h.update(b"b1" if x else b"b0")
    elif isinstance(x, (int, np.integer)):
        h.update(b"i" + str(int(x)).encode() + b";")
    elif isinstance(x, (float, np.floating)):
        h.update(b"f" + float(x).hex().encode() + b";")
    elif isinstance(x, str):
        b = x.encode()
        h.update(b"s%d:" % len(b) + b)
    elif isinstance(x, np.ndarray):
        a = np.ascontiguousarray(x)
        h.update(b"a" + a.dtype.str.encode() + repr(a.shape).encode() + b":")
        h.update(a.tobytes())
    elif isinstance(x, (tuple, list)):
        h.update(b"t%d:" % len(x))
        for item in x:
            _feed(h, item)
    elif dataclasses.is_dataclass(x) and not isinstance(x, type):
        fields = [f for f in dataclasses.fields(x) if f.compare]
        _feed(h, type(x).__qualname__)
        _feed(h, tuple((f.name, getattr(x, f.name)) for f in fields))
    else:
        raise TypeError(f"cache key: cannot digest a {type(x).__name__}")


def digest(kind: str, *parts: Any) -> str:
    """The key of an entry of ``kind`` built from ``parts`` (numbers, strings, arrays,
    tuples, dataclasses such as Profile and Material): sha256 hex over them, the format,
    railvti's and numpy's versions and :func:`code_fingerprint`."""
    h = hashlib.sha256()
    _feed(h, (kind, FORMAT_VERSION, __version__, np.__version__, code_fingerprint()))
    _feed(h, parts)
    return h.hexdigest()


def _checksum(arrays: dict[str, np.ndarray]) -> str:
    """sha256 over the arrays by name, dtype, shape, memory order and bytes."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = arrays[name]
        order = "F" if a.flags.f_contiguous and not a.flags.c_contiguous else "C"
        h.update(f"{name}|{a.dtype.str}|{a.shape}|{order}|".encode())
        h.update(a.tobytes(order=order))
    return h.hexdigest()


def _path(kind: str, key: str) -> Path | None:
    d = cache_dir()
    return None if d is None else d / f"{kind}-{key}.npz"


def _warn(path: Path, why: str) -> None:
    log.warning("railvti cache: ignored %s (%s); the table is built again", path, why)


def load(kind: str, key: str) -> dict[str, np.ndarray] | None:
    """The arrays of the entry (kind, key), validated, or None (no entry, cache off, or a
    damaged or foreign file: then a warning, and the caller builds and stores it again).

    Validation: the file opens as an ``.npz`` without pickled objects, names this key and
    format, and the sha256 of its arrays is the one stored with them."""
    path = _path(kind, key)
    if path is None or not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            meta = {k: z[k] for k in ("_key", "_format", "_sum")}
            arrays = {k[2:]: z[k] for k in z.files if k.startswith("a_")}
        stored_key, fmt, stored_sum = str(meta["_key"]), int(meta["_format"]), str(meta["_sum"])
    except Exception as exc:  # noqa: BLE001 - any damage (zip, header, pickle, truncation): rebuild
        _warn(path, f"unreadable: {type(exc).__name__}: {exc}")
        return None
    if stored_key != key or fmt != FORMAT_VERSION:
        _warn(path, "another key or format")
        return None
    if _checksum(arrays) != stored_sum:
        _warn(path, "checksum mismatch")
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # recently used: kept by the pruning
    log.debug("railvti cache: loaded %s", path)
    return arrays


def store(kind: str, key: str, arrays: dict[str, Any]) -> Path | None:
    """Write the entry (kind, key) atomically (temporary file + rename); returns its path, or
    None when the cache is off or the folder cannot be written (a warning once per folder:
    the run goes on without the cache)."""
    path = _path(kind, key)
    if path is None:
        return None
    arrs = {k: np.asarray(v) for k, v in arrays.items()}
    payload = {f"a_{k}": v for k, v in arrs.items()}
    payload.update(_key=np.array(key), _format=np.array(FORMAT_VERSION), _sum=np.array(_checksum(arrs)))
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **payload)
        os.chmod(tmp, 0o644)  # mkstemp's 0600 would hide a shared cache folder's entries
        os.replace(tmp, path)
        tmp = None
    except OSError as exc:
        if str(path.parent) not in _warned:
            _warned.add(str(path.parent))
            log.warning(
                "railvti cache: cannot write in %s (%s); tables are built in each process", path.parent, exc
            )
        return None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
    _prune(path.parent, kind)
    return path


def _prune(folder: Path, kind: str) -> None:
    """Keep the most recently used entries of kind, at most MAX_ENTRIES and MAX_BYTES (the
    newest always); remove crashed writers' temporary files."""
    now = time.time()
    entries = []
    for p in folder.glob(f"{kind}-*.npz"):
        with contextlib.suppress(OSError):  # another process removed it first
            st = p.stat()
            entries.append((st.st_mtime, st.st_size, p))
    total = 0
    for i, (_, size, p) in enumerate(sorted(entries, reverse=True)):
        total += size
        if i >= MAX_ENTRIES or (i > 0 and total > MAX_BYTES):
            with contextlib.suppress(OSError):  # another process removed it first
                p.unlink()
    for p in folder.glob(f".{kind}-*.tmp"):
        with contextlib.suppress(OSError):  # another process removed it first
            if now - p.stat().st_mtime > _STALE_TMP:
                p.unlink()


def _type_code(x: Any) -> str:
    """A recorded output's type: "a" array, "i" integer (replayed as int), "f" float."""
    if isinstance(x, np.ndarray):
        return "a"
    if isinstance(x, (int, np.integer)) and not isinstance(x, (bool, np.bool_)):
        return "i"
    if isinstance(x, (float, np.floating)):
        return "f"
    raise TypeError(f"cache recorder: cannot record a {type(x).__name__}")


class Recorder:
    """A build's expensive calls, stored as one entry and replayed in the next process.

    A builder (the ring track's rail and group bases, a wheelset harmonic's eigen-solve)
    routes each expensive call through :meth:`call`; its outputs are recorded, and
    :meth:`finish` stores them under ``digest(kind, *parts)``. The next build with the same
    parts replays them in order, each one only when the digest of that call's own inputs
    (name and arguments, or the ``key`` given) is the recorded one: a mismatch runs the call
    and every later one, and the entry is rewritten. Everything the builder computes from
    the outputs is computed as before, so a replayed build is the built one bit for bit.

    Parameters
    ----------
    kind : str
        The entry's kind (file name prefix).
    *parts
        What the build depends on (any :func:`digest` part).
    """

    def __init__(self, kind: str, *parts: Any) -> None:
        self.kind = kind
        self.key = digest(kind, *parts) if cache_dir() is not None else ""
        self._saved = load(kind, self.key) if self.key else None
        self._out: dict[str, np.ndarray] = {}
        self._n = 0
        self.replayed = 0
        self.ran = 0

    def call(self, name: str, fn: Any, *args: Any, key: Any = None) -> Any:
        """``fn(*args)`` (a tuple or a single output: arrays, ints, floats), or the recorded
        outputs of this call when its inputs (``name`` and ``args``, or ``key`` when given:
        everything the outputs depend on) digest as recorded."""
        tag = f"c{self._n}_"
        self._n += 1
        if not self.key:
            return fn(*args)
        h = hashlib.sha256()
        _feed(h, (name, args if key is None else key))
        kd = h.hexdigest()
        saved = self._saved
        if saved is not None and str(saved.get(tag + "key", "")) == kd:
            types = str(saved[tag + "types"])
            out = tuple(
                int(saved[f"{tag}{i}"])
                if t == "i"
                else float(saved[f"{tag}{i}"])
                if t == "f"
                else saved[f"{tag}{i}"]
                for i, t in enumerate(types[1:])
            )
            self.replayed += 1
            single = types[0] == "1"
        else:
            self._saved = None  # this call and every later one run
            res = fn(*args)
            single = not isinstance(res, tuple)
            out = (res,) if single else res
            self.ran += 1
        types = "1" if single else "n"
        for i, x in enumerate(out):
            t = _type_code(x)
            types += t
            self._out[f"{tag}{i}"] = np.asarray(x) if t != "a" else x
        self._out[tag + "types"] = np.array(types)
        self._out[tag + "key"] = np.array(kd)
        return out[0] if single else out

    def finish(self) -> None:
        """Store the recorded calls when any of them ran (nothing when all were replayed or
        the cache is off)."""
        if self.key and self.ran:
            store(self.kind, self.key, self._out)
