"""Long time histories written to HDF5 as they are computed, with bounded memory.

* :class:`HistoryStream` appends blocks of rows (one block per chunk of the vehicle time loop)
  to resizable, chunked datasets of one group of an HDF5 file, and flushes after each block.
  ``railvti.vehicle.simulate(..., stream_to=...)`` uses it: the run then keeps in memory only
  the last :data:`STREAM_TAIL_SECONDS` of its history.
* :class:`CaseStream` is the per-case stream file of ``railvti run``: a temporary file beside
  the output (``.OUT.h5.PID.XXXXXXXX.tmp``, like the runner's other temporary files), whose
  datasets are copied into the case's group when the case is written (the results file is
  still replaced atomically, after the case) and which is deleted then. A case type asks for
  it with :func:`case_stream`, which returns a stream only under ``railvti run`` and only for
  a history larger than :func:`stream_threshold` (``RAILVTI_STREAM_ABOVE``).

docs/results.md ("Long time histories") states the guarantees.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
from typing import Any, Callable, Iterator

import h5py
import numpy as np

from ..casetypes import ROW_BYTES, STREAM_TAIL_SECONDS, Streamed, case_sink, history_bytes, offering_sinks
from ..errors import InputError
from ..resources import parse_size
from .guarded_io import GuardedFile, WriteFailed, open_h5
from .results import temp_path

#: Environment variable: a case whose stored time history would exceed this size (bytes, or
#: '64M', '1G'; '0' streams every history, 'none' never) streams it under ``railvti run``.
STREAM_ENV = "RAILVTI_STREAM_ABOVE"

#: Default of :data:`STREAM_ENV`, bytes: 64 s of a hunting history at the deck's default
#: 2 ms output interval (:data:`ROW_BYTES` per output, ~1 MB per simulated second).
DEFAULT_STREAM_BYTES = 64e6

#: Target size of one HDF5 chunk of a streamed dataset, bytes.
CHUNK_BYTES = 256 * 1024

Derived = Callable[[dict[str, np.ndarray], dict[str, dict[str, Any]]], np.ndarray]


def stream_threshold() -> float:
    """History size above which ``railvti run`` streams a case (:data:`STREAM_ENV`), bytes."""
    text = os.environ.get(STREAM_ENV, "").strip()
    if not text:
        return DEFAULT_STREAM_BYTES
    if text in ("0", "0.0"):
        return 0.0
    try:
        return parse_size(text)
    except InputError as exc:
        raise InputError(
            f"environment variable {STREAM_ENV} = {text!r}: {exc} (0 streams every vehicle history)"
        ) from None


class HistoryStream:
    """Rows appended block by block to resizable, chunked datasets of one HDF5 group: a
    :class:`railvti.casetypes.HistorySink` writing HDF5.

    Parameters
    ----------
    path : path
        The HDF5 file (created, or opened for appending).
    group : str
        The group holding the datasets (created if missing).
    store : sequence of str, optional
        The names of the appended blocks to store (default: all).
    derived : dict, optional
        name -> function(block, attrs) -> array: further datasets computed from each block
        (e.g. one column of ``q``; ``attrs`` is :attr:`attrs`, e.g. ``attrs['q']['dof_names']``
        as the writer set it), stored beside the others.
    compression : str or None
        HDF5 filter of the datasets (default None: writing keeps pace with the time loop;
        gzip at level 4 costs ~25 ns per byte, 70 % more than the run itself at one output
        per step; the runner compresses when it copies a stream into the results file).

    The file is opened by the first block. Each :meth:`append` writes every dataset, then
    counts the block's rows as committed
    (:attr:`rows`); :meth:`close` cuts every dataset to the committed rows (a block cut short
    by a signal leaves no partial row), writes the attributes set in :attr:`attrs`
    (name -> {attribute: value}) and the group's ``rows``, and closes the file. The file is
    not flushed after each block (that would compress each dataset's partly filled HDF5 chunk
    again every block): only a closed stream is a valid file. The runner does not need more:
    after SIGKILL the results file is the previous complete one, the stream file is garbage.
    """

    def __init__(
        self,
        path: str | Path,
        group: str = "history",
        *,
        store: Any = None,
        derived: dict[str, Derived] | None = None,
        compression: str | None = None,
    ) -> None:
        self.path = Path(path)
        self.group_name = group
        self.store = None if store is None else set(store)
        self.derived = dict(derived or {})
        self.attrs: dict[str, dict[str, Any]] = {}
        self.compression = compression
        self.rows = 0
        self._names: list[str] = []
        self._closed = False
        self.failed = False  # a write failed: not a valid stream
        self._file: h5py.File | None = None  # opened by the first block
        self._fh: GuardedFile | None = None

    def _open(self) -> None:
        # through a GuardedFile: a full disk raises WriteFailed here, never inside HDF5
        # (railvti.runner.guarded_io says why: HDF5 cannot close a file whose write failed)
        mode = "a" if self.path.is_file() and self.path.stat().st_size > 0 else "w"
        try:
            self._fh = GuardedFile(self.path, mode)
        except OSError as exc:
            raise WriteFailed(
                exc.errno, f"cannot open the stream file: {exc.strerror}", str(self.path)
            ) from None
        try:
            self._file = open_h5(self._fh, mode)
        except (OSError, ValueError) as exc:
            self._fh.close()
            raise InputError(f"cannot open the stream file {self.path}: {exc}") from None
        if self.group_name in self._file and len(self._file[self.group_name]):
            self._file.close()
            self._fh.close()
            self._file = None
            raise InputError(f"{self.path}: group {self.group_name!r} already holds datasets")
        self._group = self._file.require_group(self.group_name)

    @property
    def where(self) -> str:
        """'FILE::GROUP' of the stream."""
        return f"{self.path}::{self.group_name}"

    def __enter__(self) -> "HistoryStream":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def _dataset(self, name: str, block: np.ndarray) -> h5py.Dataset:
        if name in self._group:
            return self._group[name]
        row = max(1, int(np.prod(block.shape[1:])) * block.dtype.itemsize)
        rows = int(min(max(64, CHUNK_BYTES // row), 65536))
        return self._group.create_dataset(
            name,
            shape=(0,) + block.shape[1:],
            dtype=block.dtype,
            maxshape=(None,) + block.shape[1:],
            chunks=(rows,) + block.shape[1:],
            compression=self.compression,
        )

    def append(self, block: dict[str, np.ndarray]) -> None:
        """Append one block: name -> array (k, ...), the same k for every name."""
        if self._closed:
            raise InputError(f"the stream {self.where} is closed")
        arrays = {k: np.asarray(v) for k, v in block.items() if self.store is None or k in self.store}
        arrays.update({k: np.asarray(f(block, self.attrs)) for k, f in self.derived.items()})
        sizes = {a.shape[0] for a in arrays.values()}
        if len(sizes) != 1:
            raise InputError(f"a stream block needs the same number of rows in every array, got {sizes}")
        k = sizes.pop()
        if k == 0:
            return
        if self._file is None:
            self._open()
        for name, a in arrays.items():
            d = self._dataset(name, a)
            d.resize(self.rows + k, axis=0)
            d[self.rows : self.rows + k] = a
        self._fh.check()  # a full disk: WriteFailed (the run stops with exit 3)
        self.rows += k

    def read(self, name: str, columns: Any = None) -> np.ndarray:
        """The rows of dataset ``name`` appended so far (``columns``: only those indices of
        its second axis), read through the open file."""
        if self._file is None or name not in self._group:
            raise InputError(f"the stream {self.where} holds no dataset {name!r}")
        d = self._group[name]
        if columns is None:
            return d[: self.rows]
        cols = [int(c) for c in columns]
        order = np.argsort(cols)
        out = d[: self.rows, sorted(cols)]  # h5py reads increasing indices
        back = np.empty_like(order)
        back[order] = np.arange(len(cols))
        return out[:, back]

    def names(self) -> list[str]:
        """The datasets of the stream."""
        return list(self._group.keys()) if self._file is not None else list(self._names)

    def close(self) -> None:
        """Cut every dataset to the committed rows, write :attr:`attrs`, close the file.

        Raises
        ------
        WriteFailed
            The file could not be written (disk full...): it is not a valid stream.
        """
        self._closed = True
        if self._file is None:
            return
        try:
            self._names = list(self._group.keys())
            for name in self._group:
                d = self._group[name]
                if d.shape[0] != self.rows:
                    d.resize(self.rows, axis=0)
                for k, v in self.attrs.get(name, {}).items():
                    d.attrs[k] = v
            self._group.attrs["rows"] = self.rows
        finally:
            self._file.close()
            self._file = None
            fh, self._fh = self._fh, None
            error, pending = fh.error, fh.pending
            fh.close()
        if pending is not None:  # a signal inside HDF5's last writes
            raise pending
        if error is not None:
            self.failed = True
            raise WriteFailed(error.errno, error.strerror or str(error), str(self.path))

    def streamed(self, name: str) -> Streamed:
        """A reference to one dataset of the stream (copied when a case is written)."""
        return Streamed(str(self.path), f"{self.group_name}/{name}")

    def substitute(self, data: dict[str, tuple]) -> dict[str, tuple]:
        """``data`` (name -> (array, unit[, labels])) with the arrays this stream holds
        replaced by references to the streamed datasets."""
        held = set(self.names())
        return {k: ((self.streamed(k),) + tuple(v[1:]) if k in held else v) for k, v in data.items()}


class CaseStream:
    """The stream file of one case under ``railvti run`` (see the module docstring)."""

    def __init__(self, out: str | Path) -> None:
        self.out = Path(out)
        self.stream: HistoryStream | None = None

    def open(self, nbytes: float, **kw: Any) -> HistoryStream | None:
        """A new HistoryStream in a temporary file beside the output when ``nbytes`` (the
        history's size in memory) exceeds :func:`stream_threshold`; else None."""
        if not nbytes > stream_threshold():
            return None
        if self.stream is not None:
            raise InputError("a case opens at most one stream")
        try:
            path = temp_path(self.out)
        except OSError as exc:
            raise WriteFailed(
                exc.errno, f"cannot create a stream file: {exc.strerror}", str(self.out)
            ) from None
        self.stream = HistoryStream(path, **kw)
        return self.stream

    def close(self) -> None:
        """Close the stream (its datasets cut to the committed rows)."""
        if self.stream is not None:
            self.stream.close()

    def remove(self) -> None:
        """Close and delete the stream file (also when it could not be written)."""
        if self.stream is not None:
            stream, self.stream = self.stream, None
            try:
                stream.close()
            except WriteFailed:
                pass  # reported where the run noticed it; the file goes anyway
            finally:
                stream.path.unlink(missing_ok=True)

    @contextlib.contextmanager
    def active(self) -> Iterator["CaseStream"]:
        """:func:`case_stream` returns this case's stream inside."""
        with offering_sinks(self.open):
            yield self


#: The stream a case should write its time history to (the case-type contract's
#: railvti.casetypes.case_sink): a :class:`HistoryStream` under ``railvti run`` when the
#: history (``nbytes`` in memory) exceeds :func:`stream_threshold`, else None.
case_stream = case_sink


# the history-sink contract (railvti.casetypes) is this module's too
__all__ = [
    "CaseStream",
    "HistoryStream",
    "STREAM_ENV",
    "STREAM_TAIL_SECONDS",
    "case_stream",
    "history_bytes",
    "stream_threshold",
    "ROW_BYTES",
    "Streamed",
    "case_sink",
]
