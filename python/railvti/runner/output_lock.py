"""One run at a time writes a results file: a lock file beside it.

``railvti run DECK -o OUT.h5`` holds ``.OUT.h5.lock`` (in the output's folder) from before
the first case until it exits. The file says who holds it (JSON: ``pid``, ``host``,
``started`` (ISO time), ``deck``); the lock itself is the kernel's ``flock`` on that file, so
it ends with the process however the process ends (SIGKILL included) and two runs can never
both hold it. A second run on the same output is refused with a message naming the first
(its PID, host, deck and start time). A lock file left by a process that died (its ``flock``
gone) is taken over with a note naming the dead run.

Where ``flock`` is not available (some network file systems: ENOLCK, EOPNOTSUPP) the lock
falls back to the file alone: it is live when its PID runs on this host, stale otherwise.

Why not HDF5's own file locking: the results file is replaced after every case (a new file
renamed over the old), so a lock on one version of it says nothing about the next.
"""

from __future__ import annotations

import datetime
import errno
import fcntl
import json
import os
import socket
import threading
from pathlib import Path
from typing import Any

from ..errors import InputError
from .results import side_name

#: Locks this process holds: resolved lock path -> [OutputLock, depth] (a lock is re-entrant
#: within one process: the CLI takes it before the cluster starts, run_cases again).
_HELD: dict[str, list[Any]] = {}
_HELD_LOCK = threading.Lock()


def lock_path(out: str | Path) -> Path:
    """The lock file of an output: ``.NAME.lock`` beside it."""
    out = Path(out)
    return out.parent / f".{side_name(out)}.lock"


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs on this host."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # it exists, owned by someone else
        return True
    return True


def _read_owner(fd: int) -> dict[str, Any]:
    """The holder's record in an open lock file ({} if empty or not ours)."""
    try:
        text = os.pread(fd, 4096, 0).decode("utf-8", "replace")
        owner = json.loads(text) if text.strip() else {}
    except (OSError, ValueError):
        return {}
    return owner if isinstance(owner, dict) else {}


def describe(owner: dict[str, Any]) -> str:
    """'PID 123 on host H, deck D, started T' (what is known of it)."""
    if not owner:
        return "a run that left no record"
    parts = [f"PID {owner.get('pid', '?')} on host {owner.get('host', '?')}"]
    if owner.get("deck"):
        parts.append(f"deck {owner['deck']}")
    if owner.get("started"):
        parts.append(f"started {owner['started']}")
    return ", ".join(parts)


class OutputLock:
    """The lock of one results file (a context manager; re-entrant within a process).

    Parameters
    ----------
    out : path
        The results file.
    deck : str
        The deck, named in the lock file (what a refused second run prints).
    note : callable, optional
        ``note(line)`` says that a stale lock was taken over (default: nothing).

    Raises
    ------
    InputError
        On entry, when another live run holds the lock (the message names it), or when the
        lock file cannot be created.
    """

    def __init__(self, out: str | Path, deck: str = "", note: Any = None) -> None:
        self.path = lock_path(out)
        self.out = Path(out)
        self.deck = str(deck)
        self.note = note or (lambda line: None)
        self._fd = -1
        self._key = ""
        self.took_over: dict[str, Any] | None = None

    def __enter__(self) -> "OutputLock":
        self._key = str(self.path.parent.resolve() / self.path.name)
        with _HELD_LOCK:
            held = _HELD.get(self._key)
            if held is not None:
                held[1] += 1
                return self
            self._acquire()
            _HELD[self._key] = [self, 1]
        return self

    def __exit__(self, *exc: Any) -> None:
        with _HELD_LOCK:
            held = _HELD.get(self._key)
            if held is None:
                return
            held[1] -= 1
            if held[1] > 0:
                return
            del _HELD[self._key]
            held[0]._release()

    # -------------------------------------------------------------------------------------
    def _acquire(self) -> None:
        for _ in range(20):  # a holder that unlinks the file as we open it: again
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
            except OSError as exc:
                raise InputError(
                    f"cannot create the lock file {self.path} of output {self.out}: {exc.strerror}"
                ) from None
            try:
                if self._lock(fd):
                    if self._same_file(fd):
                        self._claim(fd)
                        return
                    os.close(fd)  # the file was replaced under us: take the new one
                    continue
            except BaseException:
                os.close(fd)
                raise
            owner = _read_owner(fd)
            os.close(fd)
            raise InputError(
                f"output {self.out} is being written by another run ({describe(owner)}): "
                f"wait for it to end or give another -o (lock file {self.path})"
            )
        raise InputError(f"cannot take the lock file {self.path} of output {self.out}: it keeps changing")

    def _lock(self, fd: int) -> bool:
        """Take the flock (False: another process holds it)."""
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            return False
        except OSError as exc:
            if exc.errno not in (errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOSYS, errno.EINVAL):
                raise InputError(f"cannot lock {self.path}: {exc.strerror}") from None
        # no flock here: the record decides (live if its PID runs on this host)
        owner = _read_owner(fd)
        mine = owner.get("host") == socket.gethostname()
        return not owner or (mine and not _alive(int(owner.get("pid", 0) or 0)))

    def _same_file(self, fd: int) -> bool:
        try:
            return os.path.samestat(os.fstat(fd), os.stat(self.path))
        except OSError:
            return False

    def _claim(self, fd: int) -> None:
        """Write our record (noting the dead run whose record was there)."""
        old = _read_owner(fd)
        if old and old.get("pid") != os.getpid():
            self.took_over = old
            self.note(
                f"note: took over the lock of output {self.out} from a run that is no "
                f"longer running ({describe(old)})"
            )
        record = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "started": datetime.datetime.now().isoformat(timespec="seconds"),
            "deck": self.deck,
        }
        data = (json.dumps(record) + "\n").encode()
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, data, 0)
        except OSError:
            pass  # a full disk: the flock still holds; the record stays empty
        self._fd = fd

    def _release(self) -> None:
        if self._fd < 0:
            return
        try:
            if self._same_file(self._fd):
                self.path.unlink(missing_ok=True)  # while still holding the flock
        except OSError:
            pass
        finally:
            os.close(self._fd)  # releases the flock
            self._fd = -1


__all__ = ["OutputLock", "describe", "lock_path"]
