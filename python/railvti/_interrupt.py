"""Long single Fortran calls that Ctrl-C / SIGTERM can stop.

A Fortran call that cannot run in resumable slices (a Newton solve, an ARPACK eigen-solve) runs
in a worker thread, its f2py shim releasing the GIL (``!f2py threadsafe``), while the calling
(main) thread waits in steps of :data:`POLL_SECONDS`: a signal's Python handler then runs, and
its exception propagates, within that. A Fortran call cannot be stopped from outside: an
interrupted call runs on to its end in the background, so whatever it works on must be neither
freed nor used by another call meanwhile (``on_abandon`` / ``on_end``).
(``railvti.contact.workspace.call_interruptibly`` is the same for the contact workspaces.)
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable

#: Seconds between the waiting thread's checks for signals.
POLL_SECONDS = 0.05


def acquire(lock: threading.Lock) -> None:
    """Take ``lock``, waiting in steps of :data:`POLL_SECONDS` (Ctrl-C raises meanwhile)."""
    while not lock.acquire(timeout=POLL_SECONDS):
        pass


def wait_while(busy: Callable[[], bool]) -> None:
    """Sleep in steps of :data:`POLL_SECONDS` while ``busy()``."""
    while busy():
        time.sleep(POLL_SECONDS)


def call_in_worker(
    fn: Callable[..., Any],
    *args: Any,
    on_abandon: Callable[[], None] | None = None,
    on_end: Callable[[], None] | None = None,
    name: str = "railvti-fortran",
) -> Any:
    """``fn(*args)`` in a daemon worker thread while this thread waits for it.

    Parameters
    ----------
    fn : callable
        The call, normally an f2py routine that releases the GIL.
    *args
        Its arguments.
    on_abandon : callable, optional
        Run in this thread when the wait is interrupted (Ctrl-C, SIGTERM's exception) while
        the call still runs, before the exception propagates.
    on_end : callable, optional
        Run in the worker when the call ends, interrupted or not (release what it held).
    name : str
        The worker thread's name.

    Returns
    -------
    The call's result; its exception is re-raised here.
    """
    box: dict = {}
    done = threading.Event()
    lock = threading.Lock()  # the call's end against its abandonment

    def work() -> None:
        try:
            box["out"] = fn(*args)
        except BaseException as exc:  # noqa: BLE001 - re-raised in the caller's thread
            box["exc"] = exc
        finally:
            with lock:
                box["ended"] = True
                if on_end is not None:
                    on_end()
            done.set()

    try:
        threading.Thread(target=work, name=name, daemon=True).start()
    except BaseException:
        if on_end is not None:
            on_end()
        raise
    try:
        while not done.wait(POLL_SECONDS):
            pass
    except BaseException:
        with lock:
            if "ended" not in box and on_abandon is not None:
                on_abandon()
        raise
    if "exc" in box:
        raise box["exc"]
    return box["out"]
