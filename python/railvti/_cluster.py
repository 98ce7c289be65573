"""Dask clients: a LocalCluster started and stopped promptly, a scheduler's address checked
within seconds, and :func:`client_from` for the callers that take a client, 'local' or an
address (the runner's sweeps and the scenarios' speed scans alike).

dask and distributed are imported only inside the functions that start or reach a cluster:
importing this module, the serial paths and ``railvti run --serial`` do not import them.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import multiprocessing
import os
import signal
import socket
import sys
import threading
import time
from typing import Any, Callable

from .errors import InputError

log = logging.getLogger("railvti")

#: Environment of each worker process: one thread for BLAS/OpenMP (one task per core).
#: No tqdm bars in the workers (they would interleave on the console): the driver's bar counts tasks.
WORKER_ENV = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "TQDM_DISABLE": "1",
}
#: Dask settings of the LocalCluster's workers: no statistical profiler (a thread that samples
#: the task's stack every 10 ms: 2.8 % of a core per idle worker against 0.6 % without it,
#: benchmarks/bench_sweeps.py; the dashboard's profile page stays empty).
WORKER_CONFIG = {"distributed.worker.profile.enabled": False}


def default_workers() -> int:
    """Workers of the default LocalCluster: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def _quiet_dask() -> None:
    """Dask's own messages off the console (scheduler and nanny start and stop, and on an
    interrupt the tasks it cannot reschedule and the workers it kills): the run's lines and
    progress bar are what the user reads; errors still show, everything with -v."""
    if log.getEffectiveLevel() > logging.DEBUG:
        logging.getLogger("distributed").setLevel(logging.ERROR)


#: The warning filter given to multiprocessing's resource tracker (see local_client).
_TRACKER_QUIET = "ignore:resource_tracker:UserWarning"


@contextlib.contextmanager
def local_client(n_workers: int | None = None) -> Any:
    """A dask.distributed Client on a new LocalCluster: ``n_workers`` processes (default:
    the cores), one thread each, BLAS/OpenMP limited to one thread in each
    (:data:`WORKER_ENV`), Dask's worker settings :data:`WORKER_CONFIG`; closed on exit.

    An exception during the start-up (a signal's, raised in this thread while it waits for
    the cluster) abandons the half-started cluster: its worker processes are killed at once
    (:func:`_abandon_start`), none is left behind, and the exception propagates."""
    from distributed import Client, LocalCluster
    from distributed.deploy.spec import SpecCluster

    _quiet_dask()
    n = default_workers() if n_workers is None else int(n_workers)
    if n < 1:
        raise InputError(f"--workers must be at least 1, got {n}")
    # set before each worker process starts (BLAS reads its thread count when it loads): the
    # nanny sets these in this process's environment to spawn; restored afterwards
    import dask

    pre = {**dask.config.get("distributed.nanny.pre-spawn-environ", {}), **WORKER_ENV}
    saved = {k: os.environ.get(k) for k in pre}
    children = set(multiprocessing.active_children())
    clusters = set(SpecCluster._instances)
    # the semaphores of the workers we kill (_kill_workers) are cleaned up by
    # multiprocessing's resource tracker, which then warns of them on the console after
    # the command ended; it takes its warning filters from ours when it starts (now)
    if _TRACKER_QUIET not in sys.warnoptions:
        sys.warnoptions.append(_TRACKER_QUIET)
    try:
        try:
            with dask.config.set({"distributed.nanny.pre-spawn-environ": pre, **WORKER_CONFIG}):
                cluster = _start_without_sigint(
                    lambda: LocalCluster(
                        n_workers=n,
                        threads_per_worker=1,
                        processes=True,
                        dashboard_address=":0",
                        silence_logs=logging.CRITICAL,
                    )
                )  # a heartbeat lost at close
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        client = Client(cluster)
    except BaseException:
        _abandon_start(children, clusters)
        raise
    try:
        with client:
            yield client
    finally:
        _kill_workers(cluster)
        cluster.close()


def _start_without_sigint(start: Callable[[], Any]) -> Any:
    """``start()`` in a helper thread with SIGINT blocked, while this thread waits (a signal
    interrupts the wait). The threads the helper starts, and the worker processes they
    spawn, inherit the blocked SIGINT: a terminal's Ctrl-C, sent to the whole process group,
    then reaches only this process, which stops the run and kills the workers, instead of
    each worker printing its own KeyboardInterrupt traceback (during its imports, a second
    or two)."""
    box: dict[str, Any] = {}
    done = threading.Event()

    def helper() -> None:
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            box["result"] = start()
        except BaseException as exc:  # noqa: BLE001 - re-raised in the waiting thread
            box["error"] = exc
        finally:
            done.set()

    threading.Thread(target=helper, name="railvti-cluster-start", daemon=True).start()
    while not done.wait(0.05):
        pass
    if "error" in box:
        raise box["error"]
    return box["result"]


#: Sweeps, 0.05 s apart, that kill an interrupted start-up's worker processes.
ABANDON_SWEEPS = 5


def _abandon_start(children: set, clusters: set) -> None:
    """Kill the worker processes of a LocalCluster whose start-up was interrupted (those of
    this process's children not in ``children``) and forget the cluster (not in
    ``clusters``): a graceful close of a half-started cluster waits for workers that never
    come, and dask's atexit hook would try it again (seconds, then an AssertionError)."""
    from distributed.deploy.spec import SpecCluster

    # the half-started nannies' "Task exception was never retrieved" once their workers die
    logging.getLogger("asyncio").setLevel(logging.CRITICAL)
    # a worker whose spawn was under way joins the children a few ms later: sweep a while
    for _ in range(ABANDON_SWEEPS):
        for proc in set(multiprocessing.active_children()) - children:
            try:
                proc.kill()
            except (OSError, ValueError):
                pass
        time.sleep(0.05)
    for cluster in set(SpecCluster._instances) - clusters:
        SpecCluster._instances.discard(cluster)


def _kill_workers(cluster: Any) -> None:
    """Kill a LocalCluster's worker processes (ours, their tasks finished or abandoned): a
    graceful close waits seconds for a worker busy in a Fortran call, an interrupted run must
    stop within a second."""
    for nanny in list(getattr(cluster, "workers", {}).values()):
        try:
            os.kill(nanny.process.process.pid, signal.SIGKILL)
        except (AttributeError, ProcessLookupError, OSError):
            pass


#: Seconds to open a TCP connection to a scheduler's address before it counts as unreachable
#: (a port where nothing listens refuses at once; a host that drops the packets waits this).
CONNECT_TIMEOUT = 3.0
#: Seconds from the start of :func:`remote_client` until a scheduler must have answered: an
#: unreachable or silent address, or one where something else answers (an HTTP proxy), fails
#: within this, naming the address (``railvti run --scheduler`` within 5 s of its start).
SCHEDULER_TIMEOUT = 4.0
#: Schemes of a scheduler address Dask can connect to.
SCHEMES = ("tcp", "tls", "ws", "wss", "ucx", "inproc")
#: The expected form of a scheduler address, said in every refusal.
ADDRESS_FORM = "tcp://host:port (as 'dask scheduler' prints it, e.g. tcp://10.0.0.5:8786)"
_HOST_CHARS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-_")


def scheduler_address(address: Any, what: str = "client") -> tuple[str, str, int]:
    """Check the form of a scheduler address without contacting it (and without importing
    Dask): ``[SCHEME://]HOST:PORT`` with SCHEME one of :data:`SCHEMES` (default tcp), HOST a
    name, an IPv4 address or ``[IPv6]``, PORT in 1..65535.

    Parameters
    ----------
    address : str
    what : str
        How the message names the address ('client', '--scheduler').

    Returns
    -------
    (scheme, host, port) : tuple
        ``port`` 0 for 'inproc' and 'ucx' addresses (no TCP port to check).

    Raises
    ------
    InputError
        Naming the address, what is wrong and :data:`ADDRESS_FORM`.
    """

    def bad(why: str) -> InputError:
        return InputError(f"{what} {address!r}: malformed scheduler address ({why}); expected {ADDRESS_FORM}")

    if not isinstance(address, str):
        raise bad(f"a {type(address).__name__}, not a text")
    text = address.strip()
    if not text:
        raise bad("empty")
    scheme, sep, rest = text.partition("://")
    if not sep:
        scheme, rest = "tcp", text
    scheme = scheme.lower()
    if scheme not in SCHEMES:
        raise bad(f"unknown scheme '{scheme}://'; Dask speaks {', '.join(SCHEMES)}")
    if scheme in ("inproc", "ucx"):
        if not rest:
            raise bad("nothing after the scheme")
        return scheme, rest, 0
    if "/" in rest or "?" in rest or "#" in rest:
        raise bad("a path after host:port")
    if rest.startswith("["):
        host, close, tail = rest[1:].partition("]")
        if not close or not host or not tail.startswith(":"):
            raise bad("an IPv6 address is written [addr]:port")
        if any(ch not in "0123456789abcdefABCDEF:." for ch in host):
            raise bad(f"'{host}' is not an IPv6 address")
        port_text = tail[1:]
    else:
        host, colon, port_text = rest.rpartition(":")
        if not colon:
            raise bad("missing port number")
        if not host:
            raise bad("missing host name")
        if ":" in host:
            raise bad("several ':' (an IPv6 address is written [addr]:port)")
        if any(ch not in _HOST_CHARS for ch in host):
            raise bad(f"'{host}' is not a host name")
    if not (port_text.isascii() and port_text.isdigit()) or not 1 <= int(port_text) <= 65535:
        raise bad(f"port '{port_text}' is not a number in 1..65535")
    return scheme, host, int(port_text)


def _check_address(address: str, timeout: float = CONNECT_TIMEOUT, what: str = "client") -> None:
    """InputError unless ``address`` is a well-formed scheduler address
    (:func:`scheduler_address`) whose host and port accept a TCP connection within
    ``timeout`` s (Dask itself retries a refused connection until its own timeout, 30 s by
    default)."""
    scheme, host, port = scheduler_address(address, what)
    if scheme in ("inproc", "ucx"):
        return  # no TCP port to try: Dask's own connect decides
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except OSError as exc:
        why = (
            f"no answer within {timeout:g} s"
            if isinstance(exc, TimeoutError)
            else exc.strerror or type(exc).__name__
        )
        raise InputError(
            f"{what} {address!r}: no Dask scheduler reachable at {host}:{port} ({why})"
        ) from None


def _probe_scheduler(address: str, timeout: float) -> None:
    """Ask the scheduler at ``address`` who it is (Dask's 'identity' call), all within
    ``timeout`` s: a distributed.Client bounds its connection by its timeout but not the
    handshake after it, so a listener that never answers would hang it for ever.

    Raises
    ------
    TimeoutError
        No answer within ``timeout``.
    Exception
        Whatever the reply raised (not Dask's protocol: an HTTP proxy's reply read as a Dask
        frame asks numpy for exabytes), or the reply was not a scheduler's.
    """
    from distributed.comm import connect

    async def identity() -> Any:
        comm = await connect(address, timeout=timeout)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    reply = asyncio.run(asyncio.wait_for(identity(), timeout))
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        kind = reply.get("type") if isinstance(reply, dict) else type(reply).__name__
        raise ValueError(f"a {kind} answered, not a Scheduler")


@contextlib.contextmanager
def remote_client(address: str, timeout: float = SCHEDULER_TIMEOUT, what: str = "client") -> Any:
    """A Client connected to an existing scheduler (``tcp://host:8786``); closed on exit.

    Parameters
    ----------
    address : str
        ``[SCHEME://]HOST:PORT`` (:func:`scheduler_address`).
    timeout : float
        Seconds, from the call, within which a scheduler must have answered.
    what : str
        How messages name the address ('client', '--scheduler').

    Raises
    ------
    InputError
        A malformed address (at once, before Dask is imported), one where nothing accepts a
        connection within :data:`CONNECT_TIMEOUT` s (at once for a port where nothing
        listens), or one where no Dask scheduler answers within ``timeout`` s (something
        else listening there, a firewall); the message names the address.
    """
    t0 = time.monotonic()
    scheduler_address(address, what)
    from distributed import Client

    _quiet_dask()
    _check_address(address, min(CONNECT_TIMEOUT, timeout), what)
    left = max(timeout - (time.monotonic() - t0), 0.5)

    class _Client(Client):
        """A Client that, failing to start, counts as closed: Client.__del__ would
        otherwise try to close it, waiting twice the timeout for a scheduler that is not
        there, then print its TimeoutError as 'Exception ignored'."""

        def start(self, **kwargs: Any) -> None:
            try:
                super().start(**kwargs)
            except BaseException:
                self.status = "closed"
                self._loop_runner.stop(timeout=1.0)
                raise

    try:
        _probe_scheduler(address, left)
        left = max(timeout - (time.monotonic() - t0), 1.0)
        client = _Client(address, timeout=left)
    except Exception as exc:  # noqa: BLE001 - whatever answered there, it is not a scheduler
        # (an HTTP proxy's reply read as a Dask frame asks numpy for exabytes: say so briefly)
        why = "no answer" if isinstance(exc, (TimeoutError, OSError)) else "not Dask's protocol"
        raise InputError(
            f"{what} {address!r}: no Dask scheduler answered there within "
            f"{timeout:g} s ({why}: {type(exc).__name__}); expected "
            f"{ADDRESS_FORM}"
        ) from None
    try:
        yield client
    finally:
        client.close()


def check_client(client: Any) -> None:
    """InputError unless ``client`` is a Client, 'local' or a scheduler address that accepts
    a connection (:func:`_check_address`): said before any work, within seconds."""
    if isinstance(client, str):
        if client != "local":
            _check_address(client)
    elif not all(hasattr(client, k) for k in ("submit", "map", "gather")):
        raise InputError(
            f"client must be a distributed.Client, a scheduler address "
            f"('tcp://host:port') or 'local', got {client!r}"
        )


@contextlib.contextmanager
def client_from(client: Any, workers: int | None = None) -> Any:
    """A client from what the caller gave: a Client (kept open), a scheduler address, or
    'local' (a LocalCluster for the call). Anything else is an InputError."""
    if isinstance(client, str) and client == "local":
        with local_client(workers) as c:
            yield c
    elif isinstance(client, str):
        with remote_client(client) as c:
            yield c
    else:
        check_client(client)
        yield client


__all__ = [
    "ADDRESS_FORM",
    "CONNECT_TIMEOUT",
    "SCHEDULER_TIMEOUT",
    "SCHEMES",
    "WORKER_ENV",
    "WORKER_CONFIG",
    "check_client",
    "client_from",
    "default_workers",
    "local_client",
    "remote_client",
    "scheduler_address",
]
