"""Sweeps: one deck case (or a Python call) run over lists or ranges of its keys, each point
a task, run serially or on a dask.distributed cluster.

A sweep in a deck (docs/sweeps.md)::

    &case
        name = 'hunt', type = 'vehicle', scenario = 'hunting', duration = 2.0
        sweep = 'product'                          ! or 'zip' (default 'product')
        sweep_range_speed_kmh = 300, 460, 20       ! start, stop (included), step
        sweep_y0 = 0.006, 0.0005                   ! a list of values
    /

``sweep_KEY = v1, v2, ...`` lists the values of the case key ``KEY`` (an alias such as
``speed_kmh`` is converted as a fixed key is), ``sweep_range_KEY = start, stop, step`` gives
them as a range with ``stop`` included. ``sweep = 'product'`` runs every combination (the
first key varies slowest), ``'zip'`` takes the i-th value of every key together (the lists must
be equally long). Each point is a case named ``NAME.KEY_VALUE[.KEY_VALUE]`` (or ``NAME.pNNNN``
when that name would be too long or not unique), checked with the rest of the deck before any
case runs, and written to its own HDF5 group with the attributes ``sweep`` (the base name) and
``sweep_point`` (its values, JSON).

Running: :func:`run_on_client` sends every case (deck cases and sweep points alike) as a task to
a dask.distributed client and writes each finished one at once through the batch runner's
writer (railvti.runner.batch: only this process writes the file; the workers return their records).
``railvti run`` does this on a ``LocalCluster`` by default; ``--serial`` runs in-process
without importing dask. Dask is imported only inside the functions that use it: ``import
railvti`` and the serial path do not import it.
"""
from __future__ import annotations

import contextlib
import itertools
import json
import logging
import math
import os
import signal
import sys
import threading
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

from ..casetypes import CaseType, REGISTRY
from .deck import MAX_NAME, Case, name_problem
from ..errors import InputError
from .guarded_io import WriteFailed

log = logging.getLogger("railvti")

#: The key that names the combination rule, and the prefixes of the swept keys.
MODE_KEY = "sweep"
VALUES_PREFIX = "sweep_"
RANGE_PREFIX = "sweep_range_"
MODES = ("product", "zip")
#: Most points of one sweep (the results file is rewritten after each: keep it moderate).
MAX_POINTS = 2000
#: Environment of each worker process: one thread for BLAS/OpenMP (one task per core).
#: No tqdm bars in the workers (they would interleave on the console): the driver's bar counts tasks.
WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "TQDM_DISABLE": "1"}


@dataclass(frozen=True)
class SweepPoint(Case):
    """A case made by a sweep: ``sweep`` is the base case's name, ``point`` the swept keys
    and values as written in the deck (``(('speed_kmh', 300.0), ...)``)."""

    sweep: str = ""
    point: tuple = ()

    @property
    def point_json(self) -> str:
        """The swept values as JSON (the group's ``sweep_point`` attribute)."""
        return json.dumps(dict(self.point))


@dataclass(frozen=True)
class SweepSpec:
    """A sweep declared in a deck group: the combination rule and (key, values) per axis."""

    mode: str
    axes: tuple[tuple[str, tuple], ...]


def _as_list(value: Any) -> list:
    return list(value) if isinstance(value, (list, tuple)) else [value]


def _range(key: str, value: Any) -> tuple[list[float], str | None]:
    """The values of ``sweep_range_KEY = start, stop, step`` (stop included)."""
    v = _as_list(value)
    if len(v) != 3 or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in v):
        return [], (f"key '{RANGE_PREFIX}{key}' must be three numbers: start, stop, step; "
                    f"got {value!r}")
    start, stop, step = (float(x) for x in v)
    if not all(math.isfinite(x) for x in (start, stop, step)) or step == 0.0 \
            or (stop - start) / step < -1e-9:
        return [], (f"key '{RANGE_PREFIX}{key}' = {start:g}, {stop:g}, {step:g}: the step must be "
                    "non-zero and go from start towards stop")
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    if n > MAX_POINTS:
        return [], f"key '{RANGE_PREFIX}{key}' gives {n} values; at most {MAX_POINTS}"
    return [float(f"{start + i * step:.12g}") for i in range(n)], None


def split_sweep(group: dict[str, Any]) -> tuple[dict[str, Any], SweepSpec | None, list[str]]:
    """Take the sweep keys out of a deck group.

    Returns
    -------
    group : dict
        The group without ``sweep``, ``sweep_KEY`` and ``sweep_range_KEY``.
    spec : SweepSpec or None
        None when the group declares no sweep.
    problems : list of str
        Bad sweep keys (without the case label).
    """
    rest: dict[str, Any] = {}
    axes: list[tuple[str, tuple]] = []
    problems: list[str] = []
    mode: Any = None
    for key, value in group.items():
        k = str(key)
        if k == MODE_KEY:
            mode = value
        elif k.startswith(RANGE_PREFIX):
            values, msg = _range(k[len(RANGE_PREFIX):], value)
            if msg:
                problems.append(msg)
            axes.append((k[len(RANGE_PREFIX):], tuple(values)))
        elif k.startswith(VALUES_PREFIX):
            values = _as_list(value)
            if not values or any(x is None for x in values):
                problems.append(f"key '{k}' needs one or more values")
            axes.append((k[len(VALUES_PREFIX):], tuple(values)))
        else:
            rest[key] = value
    if mode is None and not axes:
        return rest, None, problems
    if mode is None:
        mode = "product"
    if not isinstance(mode, str) or mode.strip().lower() not in MODES:
        problems.append(f"key '{MODE_KEY}' = {mode!r} must be one of {', '.join(map(repr, MODES))}")
        mode = "product"
    mode = mode.strip().lower()
    if not axes:
        problems.append(f"key '{MODE_KEY}' without swept keys: add sweep_KEY = values or "
                        "sweep_range_KEY = start, stop, step")
    names = [k for k, _ in axes]
    for k in sorted({k for k in names if names.count(k) > 1}):
        problems.append(f"key '{k}' is swept twice (sweep_{k} and sweep_range_{k}): give it once")
    if mode == "zip" and len({len(v) for _, v in axes}) > 1:
        problems.append("sweep = 'zip' needs lists of equal length: " +
                        ", ".join(f"{k} has {len(v)}" for k, v in axes))
    return rest, SweepSpec(mode, tuple(axes)), problems


def _value_text(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.12g}"
    return str(value)


def _point_names(base: str, points: list[tuple]) -> list[str]:
    """``base.KEY_VALUE...`` per point, or ``base.pNNNN`` when those are too long, unsafe or
    not unique."""
    names = [".".join([base] + [f"{k}_{_value_text(v)}" for k, v in p]) for p in points]
    if len(set(names)) == len(names) and all(name_problem(n) is None for n in names):
        return names
    width = max(4, len(str(len(points))))
    return [f"{base[:MAX_NAME - width - 2]}.p{i:0{width}d}" for i in range(len(points))]


def _combine(spec: SweepSpec) -> list[tuple]:
    """The points of a sweep: tuples of (key, value), in order."""
    keys = [k for k, _ in spec.axes]
    if spec.mode == "zip":
        combos = zip(*(v for _, v in spec.axes))
    else:
        combos = itertools.product(*(v for _, v in spec.axes))
    return [tuple(zip(keys, c)) for c in combos]


def _resolve(ctype: CaseType, key: str, value: Any) -> tuple[str, Any, str | None]:
    """(case key, value in its unit, problem) of a swept key given in the deck."""
    if key in ctype.defaults:
        spec = ctype.keys.get(key)
        if spec is not None and spec.choices and isinstance(value, str):
            value = spec.choice(value) or value
        return key, value, None
    alias = ctype.aliases.get(key)
    if alias is None:
        return key, value, f"unknown key '{key}' for type '{ctype.name}' in the sweep"
    if alias.factor != 1.0:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return alias.key, value, f"swept key '{key}' must be a number, got {value!r}"
        value = float(value) * alias.factor
    return alias.key, value, None


def expand(case: Case, spec: SweepSpec, given: Iterable[str] = ()) -> tuple[list[Case], list[str]]:
    """The points of a sweep over ``case`` (its index and name are the base's), and the
    problems of the sweep's keys (without the case label; each point's values are checked by
    the caller with the case type's checks, as any case).

    Parameters
    ----------
    given : iterable of str
        Keys given fixed in the same deck group (a key may not be both fixed and swept).
    """
    ctype = case.case_type
    problems = []
    given = set(given)
    for key, _ in spec.axes:
        target = ctype.aliases[key].key if key in ctype.aliases else key
        clash = sorted(k for k in given if k == key or k == target
                       or (k in ctype.aliases and ctype.aliases[k].key == target))
        if clash:
            problems.append(f"key '{clash[0]}' is both given and swept: give it once")
    points = _combine(spec)
    if len(points) > MAX_POINTS:
        problems.append(f"the sweep has {len(points)} points; at most {MAX_POINTS}")
    if problems:
        return [], problems
    seen_problems: set[str] = set()
    out: list[Case] = []
    first: dict[str, int] = {}          # a point's resolved values -> its number, from 1
    for i, (name, point) in enumerate(zip(_point_names(case.name, points), points), 1):
        params = dict(case.params)
        for key, value in point:
            target, v, msg = _resolve(ctype, key, value)
            if msg and msg not in seen_problems:
                seen_problems.add(msg)
                problems.append(msg)
            params[target] = v
        # the same case twice is the same run twice, and two groups of one name in the file
        same = repr([(k, params[ctype.aliases[k].key if k in ctype.aliases else k]) for k, _ in point])
        if same in first:
            problems.append(f"the sweep has the same point twice: points {first[same]} and {i} are "
                            + ", ".join(f"{k} = {_value_text(v)}" for k, v in point)
                            + ": give each point once")
        first.setdefault(same, i)
        out.append(SweepPoint(index=case.index, name=name, case_type=ctype, params=params,
                              sweep=case.name, point=tuple(point)))
    return ([] if problems else out), problems


def sweep(case_type: str, params: dict[str, Any], axes: dict[str, Sequence[Any]], *,
          mode: str = "product", name: str = "sweep") -> list[Case]:
    """Declare a sweep in Python: the cases of ``case_type`` over ``axes``.

    Parameters
    ----------
    case_type : str
        A registered case type ('vehicle', 'normal', ...; ``railvti cases``).
    params : dict
        The fixed keys (the type's defaults for the others).
    axes : dict
        Key -> sequence of values (deck key names and units, aliases such as ``speed_kmh``
        allowed).
    mode : {'product', 'zip'}
    name : str
        The base name of the points.

    Returns
    -------
    list of Case
        Checked, numbered from 1, ready for :func:`run`.

    Raises
    ------
    InputError
        Every problem of the sweep and of its points, at once.
    """
    from .deck_registry import case_types
    ctype = case_types().get(case_type)
    if ctype is None:
        raise InputError(f"unknown case type {case_type!r}; known: {', '.join(sorted(REGISTRY))}")
    given, problems = ctype.resolve_aliases(dict(params))
    unknown = sorted(k for k in given if k not in ctype.defaults)
    problems += [f"unknown key '{k}' for type '{case_type}'" for k in unknown]
    if problems:
        raise InputError(f"sweep '{name}': " + "; ".join(problems))
    base_params = {k: v for k, v in ctype.defaults.items() if not _required(v)}
    base_params.update(given)                  # each point is checked below, as a whole
    group = {f"{VALUES_PREFIX}{k}": list(v) for k, v in axes.items()}
    group[MODE_KEY] = mode
    _, spec, problems = split_sweep(group)
    if spec is None or problems:
        raise InputError(f"sweep '{name}': " + "; ".join(problems or ["no swept keys"]))
    base = Case(index=1, name=name, case_type=ctype, params=base_params)
    cases, problems = expand(base, spec, given=[k for k in params if k in axes])
    for c in cases:
        problems += [f"{c.name}: {p}" for p in ctype.problems(c.params)]
    if problems:
        raise InputError(f"sweep '{name}': " + "; ".join(problems))
    return [replace(c, index=i + 1) for i, c in enumerate(cases)]


def _required(value: Any) -> bool:
    from ..casetypes import REQUIRED
    return value is REQUIRED


# ---------------------------------------------------------------------------------------------
# Running on dask.distributed


def run_task(case: Case) -> Any:
    """Run one case on a worker and return its :class:`railvti.runner.results.CaseRecord` (the
    worker never writes the results file). Signals are the worker's business: no guard."""
    from .batch import SignalGuard, run_case
    return run_case(case, SignalGuard(), None)


def default_workers() -> int:
    """Workers of the default LocalCluster: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:        # not Linux
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
    (:data:`WORKER_ENV`); closed on exit.

    An exception during the start-up (a signal's, raised in this thread while it waits for
    the cluster) abandons the half-started cluster: its worker processes are killed at once
    (:func:`_abandon_start`), none is left behind, and the exception propagates."""
    import multiprocessing
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
            with dask.config.set({"distributed.nanny.pre-spawn-environ": pre}):
                cluster = _start_without_sigint(lambda: LocalCluster(
                    n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                    silence_logs=logging.CRITICAL))       # a heartbeat lost at close
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
    import multiprocessing
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
        return InputError(f"{what} {address!r}: malformed scheduler address ({why}); "
                          f"expected {ADDRESS_FORM}")
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
    import socket
    scheme, host, port = scheduler_address(address, what)
    if scheme in ("inproc", "ucx"):
        return                        # no TCP port to try: Dask's own connect decides
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except OSError as exc:
        why = (f"no answer within {timeout:g} s" if isinstance(exc, TimeoutError)
               else exc.strerror or type(exc).__name__)
        raise InputError(f"{what} {address!r}: no Dask scheduler reachable at {host}:{port} "
                         f"({why})") from None


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
    import asyncio
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
        raise InputError(f"{what} {address!r}: no Dask scheduler answered there within "
                         f"{timeout:g} s ({why}: {type(exc).__name__}); expected "
                         f"{ADDRESS_FORM}") from None
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
        raise InputError(f"client must be a distributed.Client, a scheduler address "
                         f"('tcp://host:port') or 'local', got {client!r}")


@contextlib.contextmanager
def _client_from(client: Any, workers: int | None = None) -> Any:
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


def run_on_client(cases: list[Case], client: Any, on_record: Callable[[Any], bool],
                  guard: Any = None) -> str | None:
    """Submit every case to ``client`` and call ``on_record(record)`` in this process as each
    finishes (in the order they finish). ``on_record`` returns False to stop (the file cannot
    be written). Returns the signal that stopped the run, or None.

    Each case is a task with a key from its position and name (``railvti-NNN-name``), so
    dask never merges two points; no task is retried on another worker after an exception
    (its record carries it)."""
    from distributed import as_completed
    from .batch import Interrupted
    from .results import group_name
    stamp = f"{os.getpid()}-{time.time_ns()}"
    futures, by_key = [], {}
    for c in cases:
        key = f"railvti-{group_name(c)}-{stamp}"
        by_key[key] = c
        futures.append(client.submit(run_task, c, key=key, pure=False, retries=0))
    stop: str | None = None
    t_start = time.monotonic()
    ac = as_completed(futures)
    try:
        while True:
            try:
                with (guard.live() if guard is not None else contextlib.nullcontext()):
                    fut = next(ac)
            except StopIteration:
                break
            except Interrupted as exc:
                stop = exc.signame
                break
            rec = _record(fut, by_key)
            if not on_record(rec):
                break
            if guard is not None and guard.pending:
                stop = guard.pending
                break
    finally:
        if stop is not None:
            _mark_interrupted(client, futures, by_key, stop, time.monotonic() - t_start,
                              on_record)
        for f in futures:
            if not f.done():
                f.cancel()
    return stop


def _mark_interrupted(client: Any, futures: list, by_key: dict[str, Case], signame: str,
                      elapsed: float, on_record: Callable[[Any], bool]) -> None:
    """Record the cases a signal stopped while a worker was running them as interrupted (as
    the serial path records its running case); queued cases stay absent (``--resume`` runs
    them)."""
    from .results import CaseRecord
    try:
        running = client.run(lambda dask_worker: [ts.key for ts in dask_worker.state.executing])
    except Exception:  # noqa: BLE001 - a worker gone or busy: nothing to mark
        return
    keys = {k for ks in running.values() for k in ks}
    for f in futures:
        if f.key in keys and not f.done() and f.key in by_key:
            if not on_record(CaseRecord(by_key[f.key], interrupted=signame, wall_time=elapsed)):
                return


def _record(fut: Any, by_key: dict[str, Case]) -> Any:
    """The CaseRecord of a finished future (a task lost with its worker becomes the case's
    error)."""
    try:
        return fut.result()
    except Exception as exc:  # noqa: BLE001 - a worker died or the task could not run
        import traceback
        from .results import CaseRecord
        case = by_key.get(fut.key)
        if case is None:
            raise
        return CaseRecord(case, error=f"{type(exc).__name__}: {exc} (the task did not return)",
                          traceback=traceback.format_exc())


def run(cases: list[Case], client: Any = None, *, out: str | Path | None = None,
        resume: bool = False, workers: int | None = None, deck_text: str = "",
        progress: bool = False) -> list[Any]:
    """Run cases (deck cases, sweep points) serially or on a Dask cluster.

    Parameters
    ----------
    cases : list of Case
        From :func:`railvti.runner.deck.read_deck` or :func:`sweep`.
    client : None, 'local', str or distributed.Client
        None: in this process, one after another (dask is not imported). 'local': a new
        LocalCluster of ``workers`` processes (default: the cores). Another text: the address
        of a running scheduler (``tcp://host:8786``). A Client: used as it is (not closed).
    out : path, optional
        Write the results file (one writer, this process; each case as it finishes). Without
        it, a temporary file is used and removed.
    resume : bool
        With ``out``: keep its complete cases and run the others.
    workers : int, optional
        Workers of the 'local' cluster.
    progress : bool
        A progress bar (tasks, failures, time left).

    Returns
    -------
    list of CaseRecord
        In the order of ``cases``; the cases kept by ``resume`` are absent.
    """
    import tempfile
    from .batch import run_cases
    from .results import group_name
    records: dict[int, Any] = {}
    tmpdir = None
    if out is None:
        tmpdir = tempfile.TemporaryDirectory(prefix="railvti-sweep-")
        out = Path(tmpdir.name) / "sweep.h5"
    try:
        with contextlib.ExitStack() as stack:
            c = None if client is None else stack.enter_context(_client_from(client, workers))
            bar = stack.enter_context(task_bar(len(cases), disable=not progress))
            report = run_cases(cases, Path(out), deck_text, resume=resume, write=log.info,
                               client=c, bar=bar,
                               on_record=lambda r: records.__setitem__(group_name(r.case), r))
            if report.error:              # the file could not be written: the run stopped
                raise WriteFailed(report.failure.errno, report.error, str(out))
    finally:
        if tmpdir is not None:
            tmpdir.cleanup()
    return [records[group_name(c)] for c in cases if group_name(c) in records]


@contextlib.contextmanager
def task_bar(total: int, disable: bool = False) -> Any:
    """A tqdm bar on stderr counting finished tasks (postfix: failures; tqdm's estimate of
    the time left)."""
    import sys
    from tqdm import tqdm
    bar = tqdm(total=total, desc="tasks", unit="task", disable=disable, file=sys.stderr,
               dynamic_ncols=True)
    try:
        yield bar
    finally:
        bar.close()



# ---------------------------------------------------------------------------------------------
# Plots of sweeps

#: Per-point plots are drawn for sweeps of at most this many points (``railvti plot --points``:
#: every point); larger sweeps get their summary plot only.
MAX_POINT_PLOTS = 4
#: The quantity a sweep of a case type is plotted by: dataset, factor, unit, meaning.
HEADLINES = {
    "vehicle": ("amplitude_last_second", 1e3, "mm",
                "leading wheelset's lateral amplitude over the last second"),
}


def _key_unit(ctype: CaseType | None, key: str) -> str:
    """The unit of a swept key as written in the deck (an alias's own unit)."""
    if ctype is None:
        return ""
    if key in ctype.aliases:
        return ctype.aliases[key].unit
    spec = ctype.keys.get(key)
    return spec.unit if spec is not None and spec.unit not in ("", "1") else ""


def _label(key: str, value: Any, unit: str) -> str:
    return f"{key} = {_short(value)}" + (f" {unit}" if unit else "")


def _short(value: Any) -> str:
    """A swept value for a legend: 8e+10, not 80000000000."""
    return f"{value:.4g}" if isinstance(value, float) else str(value)


#: Names of result quantities for the axes of sweep plots (else the dataset's name in words).
QUANTITIES = {"approach": "approach", "area": "contact area", "fn": "normal force",
              "pmax": "peak pressure", "hertz_a": "Hertz semi-axis a", "hertz_b": "Hertz semi-axis b",
              "fx": "longitudinal creep force", "fy": "lateral creep force", "mz": "spin moment",
              "conicity": "equivalent conicity"}


def _quantity(ctype: CaseType | None, key: str) -> str:
    """'normal force fn, N' for an axis: the swept key's meaning (up to its first
    parenthesis, colon or semicolon), its name and unit."""
    unit = _key_unit(ctype, key)
    meaning = ""
    if ctype is not None:
        target = ctype.aliases[key].key if key in ctype.aliases else key
        spec = ctype.keys.get(target)
        if spec is not None and spec.meaning:
            cut = min([i for i in (spec.meaning.find(c) for c in "(:;") if i >= 0] or [len(spec.meaning)])
            meaning = spec.meaning[:cut].strip()
            meaning = meaning if len(meaning) <= 40 else meaning[:38] + ".."
    text = f"{meaning} ({key})" if meaning and meaning != key else key
    return f"{text}, {unit}" if unit else text


def sweep_points(f: Any) -> dict[str, list[tuple[dict, Any]]]:
    """Sweep name -> [(point values, h5py group)] of an open results file, in file order."""
    out: dict[str, list[tuple[dict, Any]]] = {}
    for _, g in f.items():
        name = g.attrs.get("sweep") if hasattr(g, "attrs") else None
        if name:
            out.setdefault(str(name), []).append((json.loads(str(g.attrs["sweep_point"])), g))
    return out


def plot_sweeps(f: Any, outdir: Path, stem: str) -> list[Path]:
    """One summary plot per sweep of an open results file (``stem_SWEEP_sweep.png``): the
    headline quantity (:data:`HEADLINES`, else the numeric scalar results) against the swept
    key with the most values, one line per value of the other keys; failed points marked.
    A sweep of at most :data:`MAX_POINT_PLOTS` vehicle hunting runs gets the leading
    wheelset's time histories and phase portraits overlaid (``stem_SWEEP_phase.png``)."""
    from .deck_registry import case_types
    from ..vehicle.plots import _plt
    types = case_types()
    paths = []
    for name, points in sweep_points(f).items():
        ctype = types.get(str(points[0][1].attrs.get("type")))
        ok = [(p, g) for p, g in points if g.attrs.get("status") == "ok"]
        try:
            if ok and "vy_ws1" in ok[0][1] and len(points) <= MAX_POINT_PLOTS:
                paths.append(_plot_phases(_plt(), name, ok, ctype, outdir / f"{stem}_{name}_phase.png"))
            else:
                p = _plot_summary(_plt(), name, points, ctype, outdir / f"{stem}_{name}_sweep.png")
                if p is not None:
                    paths.append(p)
        except Exception as exc:  # noqa: BLE001 - one bad sweep must not stop the others
            log.error("no plot for sweep %s: %s: %s", name, type(exc).__name__, exc)
    return paths


#: Most lines a sweep plot's legend lists (the others are counted under it).
MAX_LEGEND = 20


def _legend(fig: Any, ax: Any, title: str) -> None:
    """One legend for the figure, right of its panels (not over them): the lines of ``ax``,
    at most :data:`MAX_LEGEND` listed; ``title`` names the keys of the entries."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return
    more = len(handles) - MAX_LEGEND
    if more > 0:
        handles, labels = handles[:MAX_LEGEND], labels[:MAX_LEGEND]
        title += f"\n(first {MAX_LEGEND} of {MAX_LEGEND + more} lines)"
    fig.legend(handles, labels, loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=7,
               title=title or None, title_fontsize=7, frameon=False)


def _plot_phases(plt: Any, name: str, points: list, ctype: CaseType | None, path: Path) -> Path:
    import numpy as np
    fig, ax = plt.subplots(1, 2, figsize=(10.0, 3.8), gridspec_kw={"width_ratios": [1.6, 1]})
    keys = list(points[0][0]) if points else []
    for p, g in points:
        label = ", ".join(_short(v) for v in p.values())
        y, vy, t = (np.asarray(g[k]) for k in ("y_ws1", "vy_ws1", "t"))
        ax[0].plot(t, y * 1e3, lw=0.8, label=label)
        ax[1].plot(y * 1e3, vy, lw=0.6)
    ax[0].set_xlabel("time, s")
    ax[0].set_ylabel("lateral displacement y, mm")
    ax[0].set_title("leading wheelset: lateral displacement", fontsize=9)
    ax[1].set_xlabel("lateral displacement y, mm")
    ax[1].set_ylabel("lateral velocity dy/dt, m/s")
    ax[1].set_title("phase portrait", fontsize=9)
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(f"sweep '{name}'{_what(points)}", fontsize=10)
    fig.tight_layout()
    _legend(fig, ax[0], "\n".join(_key_title(ctype, k) for k in keys))
    fig.savefig(path, dpi=80, bbox_inches="tight")
    plt.close(fig)
    return path


def _key_title(ctype: CaseType | None, key: str) -> str:
    unit = _key_unit(ctype, key)
    return f"{key}, {unit}" if unit and unit != "-" else key


def _what(points: list) -> str:
    """', hunting, model RR, hertz-fastsim on the strips' for a vehicle sweep (its first
    point's scenario, model, contact and geometry), else ''."""
    for _, g in points:
        if "contact" in g and "scenario" in g:
            def text(k: str) -> str:
                v = g[k][()] if k in g else b""
                return v.decode() if isinstance(v, bytes) else str(v)
            contact = text("contact") + (" on the strips" if text("geometry") == "strip" else "")
            return f", {text('scenario')}, model {text('model')}, {contact}"
    return ""


def _scalar_results(g: Any) -> dict[str, tuple[float, str]]:
    """Numeric 0-d datasets of a case group (not the run statistics)."""
    import numpy as np
    out = {}
    for k, d in g.items():
        if k == "inputs" or k.startswith("stat_") or not hasattr(d, "shape") or d.shape != ():
            continue
        v = d[()]
        if isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool):
            out[k] = (float(v), str(d.attrs.get("units", "")))
    return out


def _plot_summary(plt: Any, name: str, points: list, ctype: CaseType | None,
                  path: Path) -> Path | None:
    import numpy as np
    keys = list(points[0][0])
    numeric = [k for k in keys if all(isinstance(p[k], (int, float)) for p, _ in points)]
    if not numeric:
        return None
    xkey = max(numeric, key=lambda k: len({p[k] for p, _ in points}))
    others = [k for k in keys if k != xkey]
    head = HEADLINES.get(ctype.name if ctype is not None else "")
    ok = [(p, g) for p, g in points if g.attrs.get("status") == "ok"]
    if head is not None and ok and head[0] in ok[0][1]:
        quantities = [(head[0], head[1], head[2], head[3])]
    elif ok:
        quantities = [(k, 1.0, u, k) for k, (_, u) in list(_scalar_results(ok[0][1]).items())[:4]]
    else:
        quantities = []
    n = max(1, len(quantities))
    fig, axes = plt.subplots(n, 1, figsize=(6.4, 1.2 + 2.8 * n), squeeze=False, sharex=True)
    for ax, (q, factor, unit, meaning) in zip(axes[:, 0], quantities or [(None, 1, "", "")]):
        lines: dict[tuple, list] = {}
        for p, g in points:
            lines.setdefault(tuple(p[k] for k in others), []).append((p[xkey], g))
        for combo, pts in lines.items():
            label = ", ".join(_short(v) for v in combo)
            good = [(x, float(np.asarray(g[q])) * factor) for x, g in pts
                    if q is not None and g.attrs.get("status") == "ok" and q in g]
            if good:
                xs, ys = zip(*sorted(good))
                ax.plot(xs, ys, "o-", ms=4, label=label or None)
            bad = [x for x, g in pts if g.attrs.get("status") != "ok"]
            if bad:
                ax.plot(bad, [0.0] * len(bad), "rx", ms=8,
                        label=f"failed ({label})" if label else "failed")
        if q:
            what = QUANTITIES.get(q, meaning if meaning != q else q.replace("_", " "))
            ax.set_ylabel(f"{what}, {unit}" if unit and unit not in ("1", "-") else what, fontsize=9)
        ax.set_title(meaning if meaning != q else "", fontsize=9)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(_quantity(ctype, xkey))
    fig.suptitle(f"sweep '{name}': {len(points)} points{_what(points)}", fontsize=10)
    fig.tight_layout()
    _legend(fig, axes[0, 0], "\n".join(_key_title(ctype, k) for k in others))
    fig.savefig(path, dpi=80, bbox_inches="tight")
    plt.close(fig)
    return path


__all__ = ["MODES", "SweepPoint", "SweepSpec", "check_client", "expand", "local_client",
           "plot_sweeps",
           "remote_client", "run", "run_on_client", "split_sweep", "sweep", "sweep_points"]
