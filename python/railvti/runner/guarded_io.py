"""HDF5 files written so that a full disk (or any write error) never reaches the HDF5 library.

Why: when a write fails inside HDF5 (ENOSPC on a full disk), the library cannot close the
file: its metadata cache stays dirty, h5py prints an "Exception ignored" traceback for every
object it frees afterwards (2,153 lines in issue 31), and at the interpreter's exit the HDF5
library's own clean-up tries to flush the half-closed file again and crashes the process
(exit 139, segmentation fault, measured on a 2 MB tmpfs with h5py 3.16 / HDF5 2.0).

How: the file is opened through h5py's ``fileobj`` driver on a :class:`GuardedFile`, a
file-like object whose writes never fail as far as HDF5 can tell. The first failed write is
remembered (:attr:`GuardedFile.error`); it and every later write are kept in memory instead
(reads see them), so HDF5 goes on, closes the file cleanly and frees everything. The writer
then raises :class:`WriteFailed` and deletes the file. The writers check
:meth:`GuardedFile.check` between datasets and blocks, so little is written after a failure.

The driver's calls run Python code inside HDF5, where a signal handler may raise (Ctrl-C
while a history streams). An exception must not reach HDF5 from there (it would be a failed
write, with the consequences above): each call runs to its end and the exception is raised
again by the next :meth:`GuardedFile.check`, after HDF5 has returned.
"""

from __future__ import annotations

import errno
import itertools
import os
from pathlib import Path
from typing import Any

import h5py

_MEMORY_NAMES = itertools.count()  # names of in-memory files (HDF5 knows open files by name)

#: The system calls that write (tests replace them to simulate a full disk).
_pwrite = os.pwrite
_ftruncate = os.ftruncate
_fsync = os.fsync


class WriteFailed(OSError):
    """A results or stream file could not be written (disk full, quota, I/O error): the run
    stops with exit status 3 (``railvti.runner.batch.EXIT_OUTPUT``); it is not a case's error."""


class GuardedFile:
    """A binary file for h5py's ``fileobj`` driver whose writes never raise.

    Parameters
    ----------
    path : path
        The file; ``mode`` 'w' creates or truncates it, 'a' opens an existing one for update.

    Attributes
    ----------
    error : OSError or None
        The first write error (None: every byte reached the file).
    """

    def __init__(self, path: str | Path, mode: str = "w") -> None:
        self.path = Path(path)
        flags = os.O_RDWR | (os.O_CREAT | os.O_TRUNC if mode == "w" else 0)
        self._fd = os.open(self.path, flags, 0o666)
        self._pos = 0
        self._end = os.fstat(self._fd).st_size
        self.error: OSError | None = None
        self.pending: BaseException | None = None  # raised in a call, raised again by check()
        self._lost: list[tuple[int, bytes]] = []  # writes after the error, in order

    def _whole(self, fn: Any, *args: Any) -> Any:
        """fn(*args) run to its end: a KeyboardInterrupt (a signal handler) raised inside is
        kept for :meth:`check` and the call made again (each call is idempotent: writes
        and reads at fixed offsets); another exception becomes the write error."""
        start = self._pos
        for _ in range(1000):
            self._pos = start
            try:
                return fn(*args)
            except Exception as exc:  # noqa: BLE001 - HDF5 must not see it
                if self.error is None:
                    self.error = OSError(errno.EIO, f"{type(exc).__name__}: {exc}")
                self._pos = start
                return fn(*args)  # a write now goes to memory only
            except BaseException as exc:  # noqa: BLE001 - KeyboardInterrupt, SystemExit
                self.pending = self.pending or exc
        raise RuntimeError("GuardedFile: interrupted 1000 times in one call")

    # -- the file-like interface h5py's fileobj driver uses ----------------------------------
    def seek(self, pos: int, whence: int = 0) -> int:
        """Move the position (whence 0: from the start, 1: from here, 2: from the end)."""
        self._pos = {0: 0, 1: self._pos, 2: self._end}[whence] + int(pos)
        return self._pos

    def tell(self) -> int:
        """The position, bytes."""
        return self._pos

    def readinto(self, buf: Any) -> int:
        """Fill ``buf`` from the position (zeros past the end), the lost writes laid over."""
        return self._whole(self._readinto, buf)

    def _readinto(self, buf: Any) -> int:
        mv = memoryview(buf).cast("B")
        n = len(mv)
        data = os.pread(self._fd, n, self._pos) if n else b""
        mv[: len(data)] = data
        mv[len(data) :] = bytes(n - len(data))
        for off, lost in self._lost:  # later writes win: in order
            lo, hi = max(off, self._pos), min(off + len(lost), self._pos + n)
            if lo < hi:
                mv[lo - self._pos : hi - self._pos] = lost[lo - off : hi - off]
        self._pos += n
        return n

    def read(self, size: int = -1) -> bytes:
        """Read ``size`` bytes (-1: to the end)."""
        n = self._end - self._pos if size is None or size < 0 else size
        buf = bytearray(max(n, 0))
        self.readinto(buf)
        return bytes(buf)

    def write(self, buf: Any) -> int:
        """Write at the position; after a failure keep the bytes in memory instead."""
        return self._whole(self._write, buf)

    def _write(self, buf: Any) -> int:
        data = memoryview(buf).cast("B")
        n, pos, done = len(data), self._pos, 0
        if self.error is None:
            try:
                while done < n:
                    k = _pwrite(self._fd, data[done:], pos + done)
                    if k <= 0:
                        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
                    done += k
            except OSError as exc:
                self.error = exc
        if done < n:
            self._lost.append((pos + done, bytes(data[done:])))
        self._pos = pos + n
        self._end = max(self._end, self._pos)
        return n

    def truncate(self, size: int | None = None) -> int:
        """Set the file's length (HDF5 does so when it closes the file)."""
        return self._whole(self._truncate, size)

    def _truncate(self, size: int | None) -> int:
        size = self._pos if size is None else int(size)
        if self.error is None:
            try:
                _ftruncate(self._fd, size)
            except OSError as exc:
                self.error = exc
        self._end = size
        return size

    def flush(self) -> None:
        """Nothing to do: every write goes to the operating system at once."""

    def fileno(self) -> int:
        """The file descriptor."""
        return self._fd

    # -- for the writers --------------------------------------------------------------------
    def check(self) -> None:
        """Raise the exception a signal raised inside a call, then :class:`WriteFailed` if
        a write has failed."""
        if self.pending is not None:
            exc, self.pending = self.pending, None
            raise exc
        if self.error is not None:
            raise failure(self.path, self.error)

    def sync(self) -> None:
        """fsync the file (raises WriteFailed)."""
        self.check()
        try:
            _fsync(self._fd)
        except OSError as exc:
            self.error = exc
            raise failure(self.path, exc) from None

    def close(self) -> None:
        """Close the descriptor (the lost writes are dropped)."""
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1
            self._lost.clear()


def failure(path: str | Path, exc: BaseException) -> WriteFailed:
    """A WriteFailed for ``path`` from an OSError (its errno and text kept)."""
    code = getattr(exc, "errno", None) or errno.EIO
    text = getattr(exc, "strerror", None) or str(exc) or os.strerror(code)
    return WriteFailed(code, text, str(path))


def open_h5(fh: GuardedFile, mode: str = "w") -> h5py.File:
    """An h5py File on a GuardedFile ('w': new, 'a': existing)."""
    return h5py.File(fh, mode if mode == "w" else "r+", driver="fileobj")


def memory_h5(image: bytes = b"") -> h5py.File:
    """An HDF5 file in memory (the ``core`` driver, no file behind it): new, or opened for
    update from ``image`` (a file's bytes). It never touches the disk: :func:`file_image`
    gives its bytes, written by the caller through a :class:`GuardedFile`."""
    # the file format h5py.File gives a file on disk: the earliest format that holds each
    # object (HDF5 2.0's own default is 1.8's: superblock v2, checksummed headers), no
    # creation times
    fapl = h5py.h5p.create(h5py.h5p.FILE_ACCESS)
    fapl.set_libver_bounds(h5py.h5f.LIBVER_EARLIEST, h5py.h5f.LIBVER_LATEST)
    fapl.set_alignment(1, 1)
    fapl.set_fapl_core(1 << 20, False)
    name = f"railvti-memory-{os.getpid()}-{next(_MEMORY_NAMES)}".encode()
    if image:
        fapl.set_file_image(image)
        return h5py.File(h5py.h5f.open(name, h5py.h5f.ACC_RDWR, fapl=fapl))
    fcpl = h5py.h5p.create(h5py.h5p.FILE_CREATE)
    fcpl.set_obj_track_times(False)
    return h5py.File(h5py.h5f.create(name, h5py.h5f.ACC_TRUNC, fapl=fapl, fcpl=fcpl))


def file_image(f: h5py.File) -> bytes:
    """The bytes of an open HDF5 file as it would be on disk (its metadata flushed)."""
    f.flush()
    return f.id.get_file_image()


__all__ = ["GuardedFile", "WriteFailed", "failure", "open_h5", "memory_h5", "file_image"]
