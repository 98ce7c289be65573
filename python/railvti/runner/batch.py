"""Running the cases of a deck into one results file without losing finished work.

* Each case runs isolated: any exception (not only railvti's) becomes that case's recorded
  error, with its traceback in the log and in the file; the other cases still run.
* Each finished case is written at once (:class:`railvti.runner.results.ResultsWriter`: a new
  version of the file in a temporary file beside it, renamed over the old one), so there is a
  valid file after every case; ``--resume`` keeps the cases already complete (status 'ok' and
  the same parameters) and runs the others.
* SIGINT (Ctrl-C) and SIGTERM stop the run: the case running is marked 'interrupted' in the
  file, the completed ones are kept, no temporary file is left. The long Fortran loops are
  called in slices of ~0.1-0.2 s (Gauss-Seidel and CG normal contact, the vehicle time loop),
  and the steady rolling call runs in a worker thread while the main thread waits for
  signals (railvti.contact.workspace.call_interruptibly), so a run stops within about that
  (docs/results.md lists the calls that still finish first). SIGKILL leaves the previous
  complete file (or none) and at most one ``.NAME.PID.XXXX.tmp`` file beside it.
* The output path is checked before any case runs (:func:`check_output`).
* A case with a long time history streams it (railvti.runner.stream) to a temporary file beside the
  output as it runs; its datasets are copied into the case's group when the case is written,
  and the file is deleted then (also after an error or a signal). SIGKILL during such a case
  leaves the previous complete file and that stream file (``.NAME.PID.XXXX.tmp``).

Exit status of ``railvti run`` (:data:`EXIT_CODES`).
"""

from __future__ import annotations

import contextlib
import errno
import logging
import os
import signal
import stat
import threading
import time
import traceback
import weakref
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator

from ..casetypes import Case, CaseOutput
from ..errors import InputError, RailvtiError
from .cost import announce
from .stream import CaseStream
from .results import (
    CaseRecord,
    ResultsWriter,
    completed,
    group_name,
    is_results_file,
    params_digest,
    temp_path,
)
from .results import damage, deck_owner
from .guarded_io import WriteFailed
from .output_lock import OutputLock

log = logging.getLogger("railvti")
#: The logger of failed cases' tracebacks, at DEBUG level: shown by ``railvti --debug``
#: (and -v); the console otherwise shows one line per failure, the file keeps the traceback.
TRACEBACK_LOGGER = "railvti.traceback"
tb_log = logging.getLogger(TRACEBACK_LOGGER)

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_INPUT = 2
EXIT_OUTPUT = 3
EXIT_SIGINT = 128 + signal.SIGINT
EXIT_SIGTERM = 128 + signal.SIGTERM

#: Exit status of ``railvti run`` and what it means.
EXIT_CODES = {
    EXIT_OK: "every case ran",
    EXIT_FAILED: "some cases failed (each recorded with its error; the others ran)",
    EXIT_INPUT: "nothing ran: a bad deck, output path or option",
    EXIT_OUTPUT: "the results file could not be written during the run (it holds the cases written before)",
    EXIT_SIGINT: "stopped by SIGINT (Ctrl-C): completed cases kept, the running one marked interrupted",
    EXIT_SIGTERM: "stopped by SIGTERM: as for SIGINT",
}


class Interrupted(KeyboardInterrupt):
    """A run stopped by a signal (SIGINT or SIGTERM)."""

    def __init__(self, signame: str) -> None:
        super().__init__(signame)
        self.signame = signame


#: Seconds after which a signal is sent again when the Interrupted it raised was swallowed
#: (raised inside a weakref callback or a __del__, where Python prints "Exception ignored"
#: and goes on: h5py's object registry does this while a history streams).
RESEND_SECONDS = 0.25


def _swallows(frame: Any, depth: int = 3) -> bool:
    """Whether an exception raised in ``frame`` would be swallowed: a weakref callback or a
    ``__del__`` among the innermost ``depth`` frames (Python prints it and goes on)."""
    for _ in range(depth):
        if frame is None:
            return False
        code = frame.f_code
        if code.co_name == "__del__" or code.co_filename == weakref.__file__:
            return True
        frame = frame.f_back
    return False


class SignalGuard:
    """SIGINT and SIGTERM raise :class:`Interrupted` only inside :meth:`live` (while a case
    computes); elsewhere (writing the file, between cases) they are held in ``pending`` and
    the runner stops at its next check. Restores the previous handlers on exit.

    If the case is still inside :meth:`live` :data:`RESEND_SECONDS` after the signal (the
    exception was swallowed), the signal is sent again."""

    def __init__(self) -> None:
        self.pending: str | None = None
        self.received: str | None = None  # the last signal, whatever became of it
        self._live = False
        self._inside = False
        self._resend = True
        self._timer: threading.Timer | None = None
        self._old: dict[int, Any] = {}

    def __enter__(self) -> "SignalGuard":
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._old[sig] = signal.signal(sig, self._handler)
        return self

    def __exit__(self, *exc: Any) -> None:
        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old.clear()

    def _handler(self, signum: int, frame: Any) -> None:
        name = signal.Signals(signum).name
        self.received = name
        if self._live and _swallows(frame):
            self._resend_later(signum, 0.01)  # raise it once out of the callback
            return
        if self._live:
            self._live = False
            if self._resend:
                self._resend_later(signum, RESEND_SECONDS)
            raise Interrupted(name)
        self.pending = self.pending or name

    def _resend_later(self, signum: int, delay: float) -> None:
        def again() -> None:
            if self._inside:  # the Interrupted was swallowed: raise it again
                self._live = True
                os.kill(os.getpid(), signum)

        if self._timer is not None:
            self._timer.cancel()
        self._timer = threading.Timer(delay, again)
        self._timer.daemon = True
        self._timer.start()

    @contextlib.contextmanager
    def live(self, resend: bool = True) -> Iterator[None]:
        """Signals interrupt the code inside (raising Interrupted). ``resend=False``: no
        second signal when the code is still inside after :data:`RESEND_SECONDS` (code
        that cleans up inside, as an interrupted cluster start-up does)."""
        if self.pending:
            raise Interrupted(self.pending)
        self._live = True
        self._inside = True
        self._resend = resend
        try:
            yield
        finally:
            self._live = False
            self._inside = False
            if self._timer is not None:
                self._timer.cancel()
                self._timer = None


def check_output(out: Path, deck: Path | None = None, force: bool = False) -> None:
    """Refuse an output path before any work: a directory, a device or other non-regular
    file, the deck itself, an existing file that is not a railvti results file (unless
    ``force``), or a folder where no file can be created.

    Raises
    ------
    InputError
        Naming the path and the problem.
    """
    try:
        there = out.exists() or out.is_symlink()
    except OSError as exc:  # a name too long, a loop of links...
        raise InputError(f"output {out}: {exc.strerror}") from None
    if there:
        try:
            st = os.stat(out)
        except FileNotFoundError:
            raise InputError(
                f"output {out} is a symbolic link to {os.readlink(out)}, which does "
                "not exist: give the target's path or another name"
            ) from None
        except OSError as exc:
            raise InputError(f"output {out}: {exc.strerror}") from None
        if stat.S_ISDIR(st.st_mode):
            raise InputError(f"output {out} is a directory: give a file name (-o DIR/results.h5)")
        if not stat.S_ISREG(st.st_mode):
            raise InputError(
                f"output {out} is not a regular file (a device, pipe or socket): "
                "railvti writes only regular files"
            )
        if deck is not None and deck.exists() and os.path.samefile(out, deck):
            raise InputError(f"output {out} is the deck itself: give another name with -o")
        if not force and not is_results_file(out):
            raise InputError(
                f"output {out} exists and is not a railvti results file: give "
                "another name, or --force to replace it"
            )
    parent = out.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the output folder {parent}: {exc.strerror}") from None
    if not parent.is_dir():
        raise InputError(f"output folder {parent} is not a directory")
    try:
        temp_path(out).unlink()
    except OSError as exc:
        raise InputError(f"cannot write in the output folder {parent}: {exc.strerror}") from None


def check_deck(
    out: Path,
    deck: Path | str,
    cases: list[Case],
    resume: bool = False,
    force: bool = False,
    note: Any = None,
) -> bool:
    """Refuse an existing results file written from another deck (railvti.runner.results.deck_owner
    says which files belong to a deck, and why), unless ``force``: plain ``-o`` would
    replace it, ``--resume`` would mix two decks' cases in one file. With ``resume``, also
    refuse a damaged file (railvti.runner.results.damage: every dataset is read once). Returns
    whether the run resumes: with ``force`` another deck's or a damaged file is replaced,
    never resumed (``note`` says so).

    Raises
    ------
    InputError
        Naming the file, the deck it was written from, and how to go on.
    """
    if not out.is_file() or not is_results_file(out):
        return resume
    try:
        owner = deck_owner(out, deck, cases)
    except (OSError, KeyError, ValueError) as exc:  # a damaged results file
        if force:
            return False
        raise InputError(
            f"output {out} cannot be read as a results file ({exc}): give "
            "another -o, or --force to replace it"
        ) from None
    if owner.same:
        hurt = damage(out) if resume else ""
        if hurt and not force:
            raise InputError(
                f"output {out} is damaged ({hurt}): --resume cannot keep its "
                "cases; give another -o, or --force to replace it"
            )
        if hurt and note is not None:
            note(f"note: output {out} is damaged ({hurt}); --force: it is replaced")
        return resume and not hurt
    if force:
        if note is not None:
            note(
                f"note: output {out} was {owner.describe()}; --force: it is replaced"
                + (", none of its cases kept" if resume else "")
            )
        return False
    what = "--resume would mix two decks' cases in one file" if resume else "running would replace it"
    raise InputError(
        f"output {out} was {owner.describe()}: {what}; give another -o, or --force to replace it"
    )


@dataclass
class RunReport:
    """What a run did: its exit status and counts; ``error`` the one line saying why the
    file could not be written (status :data:`EXIT_OUTPUT`)."""

    status: int
    ok: int = 0
    failed: int = 0
    skipped: int = 0
    interrupted: str | None = None
    error: str | None = None
    failure: OSError | None = None


def _streamed_partial(res: Any, stream: Any) -> tuple[dict, dict]:
    """Datasets and labels of an interrupted run's streamed history: every dataset of the
    stream (t, q, v and the per-wheel histories), referenced for copying."""
    wheel_units = getattr(res, "WHEEL_UNITS", {})
    labels = res._save_attrs()
    nw = res.wheel.shape[-1]
    per_wheel = {
        "axes": ["t", "wheel", "wheelset"],
        "wheel": ["left", "right"],
        "wheelset": [f"ws{w + 1}" for w in range(nw)],
    }
    units = {
        "t": "s",
        "q": "m or rad (per dof_names)",
        "v": "m/s or rad/s (per dof_names)",
        "y_ws1": "m",
        "vy_ws1": "m/s",
        "ws_y": "m",
    }
    data = {}
    for name in stream.names():
        unit = units.get(name) or wheel_units.get(name.removeprefix("wheel_"), "1")
        data[name] = (stream.streamed(name), unit)
        if name.startswith("wheel_"):
            labels[name] = per_wheel
    labels["ws_y"] = {"axes": ["t", "wheelset"], "wheelset": per_wheel["wheelset"]}
    labels.update({k: {"axes": ["t"]} for k in ("t", "y_ws1", "vy_ws1")})  # as a finished case's
    return data, {k: v for k, v in labels.items() if k in data}


def partial_output(res: Any, stream: CaseStream | None = None) -> CaseOutput | None:
    """The time history an interrupted vehicle run had completed (its exception's
    ``partial`` SimulationResult) as a CaseOutput, or None. A history streamed to the case's
    ``stream`` (``res.streamed``) is referenced there whole (the SimulationResult holds only
    its tail)."""
    if res is None or not hasattr(res, "_save_attrs"):
        return None
    stat_units = getattr(res, "STAT_UNITS", {})
    hs = stream.stream if stream is not None else None
    if getattr(res, "streamed", "") and hs is not None and res.streamed == hs.where:
        hs.close()
        data, labels = _streamed_partial(res, hs)
    else:
        labels = res._save_attrs()
        data = {
            "t": (res.t, "s"),
            "q": (res.q, "m or rad (per dof_names)"),
            "v": (res.v, "m/s or rad/s (per dof_names)"),
            "wheel": (res.wheel, "per quantity: see quantity_units"),
        }
    scalars = {
        f"stat_{k}": (v, stat_units.get(k, "1")) for k, v in res.stats.items() if isinstance(v, (int, float))
    }
    t_end = float(res.t[-1]) if len(res.t) else 0.0
    return CaseOutput(
        summary=f"interrupted: the time history up to t = {t_end:.3f} s is kept",
        datasets=data,
        scalars=scalars,
        attrs=labels,
    )


def run_case(case: Case, guard: SignalGuard, stream: CaseStream | None = None) -> CaseRecord:
    """Run one case; any exception becomes the record's error (with its traceback),
    a signal the record's ``interrupted``. With ``stream`` the case may stream a long time
    history to it (railvti.runner.stream.case_stream); the stream is closed on return (the caller
    writes the record, then removes the stream file)."""
    t0 = time.perf_counter()
    active = stream.active() if stream is not None else contextlib.nullcontext()
    try:
        with active, guard.live():
            output = case.case_type.run(case.params)
    except KeyboardInterrupt as exc:  # Interrupted, or Ctrl-C without the guard's handler
        return CaseRecord(
            case,
            output=partial_output(getattr(exc, "partial", None), stream),
            interrupted=getattr(exc, "signame", "SIGINT"),
            wall_time=time.perf_counter() - t0,
        )
    except WriteFailed:  # its stream file: the disk, not the case (exit 3)
        raise
    except Exception as exc:  # noqa: BLE001 - isolation: any failure is this case's alone
        tb = traceback.format_exc()  # to the file; the console's line and --debug: _account
        return CaseRecord(
            case, error=f"{type(exc).__name__}: {exc}", traceback=tb, wall_time=time.perf_counter() - t0
        )
    finally:
        if stream is not None:
            stream.close()
    return CaseRecord(case, output=output, wall_time=time.perf_counter() - t0)


def _store(writer: ResultsWriter, rec: CaseRecord) -> None:
    """Write one record; a result that cannot be stored (a value HDF5 refuses) becomes the
    case's error.

    Raises
    ------
    WriteFailed
        The file itself cannot be written (disk full, I/O error): the run stops.
    """
    try:
        writer.write([rec])
        return
    except WriteFailed:
        raise
    except OSError as exc:  # an OSError of the file itself (the writer wraps its own)
        raise WriteFailed(exc.errno, exc.strerror or str(exc), str(writer.path)) from None
    except Exception as exc:  # noqa: BLE001 - a bad result value: record it as the case's error
        tb = traceback.format_exc()
        tb_log.debug("%s: its results cannot be stored:\n%s", rec.case.label, tb.rstrip())
        rec.output = None
        rec.error = f"cannot store the results: {type(exc).__name__}: {exc}"
        rec.traceback = tb
    try:
        writer.write([rec])  # the record without its results
    except WriteFailed:
        raise
    except Exception as exc:  # noqa: BLE001 - even that cannot be stored: the file's fault
        code = exc.errno if isinstance(exc, OSError) and exc.errno else errno.EIO
        raise WriteFailed(code, f"{type(exc).__name__}: {exc}", str(writer.path)) from None


def _cases(n: int) -> str:
    return f"{n} case" if n == 1 else f"{n} cases"


def write_error(out: Path, exc: OSError, kept: int, lost: list[Case], not_run: int) -> str:
    """The one line that says why a run stopped on its output: the error, what the file
    holds, what is not in it."""
    why = exc.strerror or str(exc)
    code = f" (errno {exc.errno})" if exc.errno else ""
    held = f"it keeps the {_cases(kept)} written before" if kept else "no case of this run is in it"
    line = f"cannot write {out}: {why}{code}; {held} (no temporary file left)"
    if lost:
        names = ", ".join(c.label for c in lost[:3]) + (" ..." if len(lost) > 3 else "")
        line += f"; finished but not written: {names}"
    if not_run:
        line += f"; {_cases(not_run)} more not in it"
    return line


#: Said after the line of a case that failed with an exception railvti does not expect.
UNEXPECTED_HINT = " (unexpected: its traceback is in the results file; 'railvti run --debug' prints it)"


def expected_error(error: str) -> bool:
    """Whether a record's error ('ExceptionClass: message') is one of railvti's own
    (:class:`railvti.errors.RailvtiError` and its subclasses, wherever defined): a failure the
    code foresaw and explained, not a bug."""
    names, todo = set(), [RailvtiError]
    while todo:
        cls = todo.pop()
        names.add(cls.__name__)
        todo.extend(cls.__subclasses__())
    return error.split(":", 1)[0].strip() in names


def _account(rec: CaseRecord, report: RunReport, write: Any) -> None:
    """Count a stored record in the report and say what became of its case."""
    if rec.interrupted:
        report.interrupted = rec.interrupted
        write(f"{rec.case.label}: INTERRUPTED by {rec.interrupted} after {rec.wall_time:.1f} s")
    elif rec.error is not None:
        report.failed += 1
        hint = "" if expected_error(rec.error) else UNEXPECTED_HINT
        error = "; ".join(ln.strip() for ln in rec.error.splitlines() if ln.strip())  # one line
        write(f"{rec.case.label}: FAILED: {error}{hint}")
        if rec.traceback:
            tb_log.debug("%s failed:\n%s", rec.case.label, rec.traceback.rstrip())
    else:
        report.ok += 1
        write(f"{rec.case.label}: {rec.output.summary} [{rec.wall_time:.2f} s]")


def run_cases(
    cases: list[Case],
    out: Path,
    deck_text: str,
    *,
    resume: bool = False,
    write: Any = print,
    progress: Any = None,
    client: Any = None,
    on_record: Any = None,
    bar: Any = None,
    deck_path: str = "",
    guard: SignalGuard | None = None,
) -> RunReport:
    """Run ``cases`` into the results file ``out`` (checked beforehand with
    :func:`check_output` and :func:`check_deck`), each finished case written at once, under
    the output's lock (railvti.runner.output_lock: a second run on ``out`` is refused). A file
    that cannot be written stops the run: status :data:`EXIT_OUTPUT`, ``report.error``
    says why in one line, the file is its last complete version.

    Parameters
    ----------
    write : callable
        Prints one line for the user.
    progress : callable, optional
        ``progress(case)`` before each case of a serial run (e.g. a progress bar's postfix).
    client : distributed.Client, optional
        Run the cases as tasks on this Dask client (:func:`run_on_client`); each
        finished one is written here, by this process, as it arrives. None: one after
        another in this process (dask is not imported).
    on_record : callable, optional
        ``on_record(record)`` after each record is stored.
    bar : tqdm, optional
        Advanced by one per finished case, its postfix the count of failures; its total is
        set to the cases to run.
    deck_path : str
        The deck's file, recorded in the results file and in the lock.
    guard : SignalGuard, optional
        Already installed by the caller (from before a cluster's start-up); default: one
        installed for the run.
    """
    with OutputLock(out, deck_path or "(API call)", note=write):
        return _run_locked(
            cases,
            out,
            deck_text,
            resume=resume,
            write=write,
            progress=progress,
            client=client,
            on_record=on_record,
            bar=bar,
            deck_path=deck_path,
            guard=guard,
        )


def _run_locked(
    cases: list[Case],
    out: Path,
    deck_text: str,
    *,
    resume: bool,
    write: Any,
    progress: Any,
    client: Any,
    on_record: Any,
    bar: Any,
    deck_path: str,
    guard: SignalGuard | None,
) -> RunReport:
    report = RunReport(status=EXIT_OK)
    done = completed(out) if resume else {}
    todo = []
    for c in cases:
        if done.get(group_name(c)) == params_digest(c):
            report.skipped += 1
        else:
            todo.append(c)
    if resume:
        write(f"resume: {report.skipped} of {len(cases)} cases already complete in {out}")
    if bar is not None:
        bar.reset(total=len(todo))
    writer = ResultsWriter(out, deck_text, keep=resume, deck_path=deck_path, cases=cases)
    stored: list[Case] = []

    def stop_on(exc: OSError, lost: list[Case]) -> None:
        """The file cannot be written: say so in report.error (one line)."""
        report.status = EXIT_OUTPUT
        report.failure = exc
        report.error = write_error(
            out, exc, len(stored) + report.skipped, lost, len(todo) - len(stored) - len(lost)
        )

    def finish(rec: CaseRecord) -> bool:
        """Store a record (False: the file cannot be written) and count it."""
        try:
            _store(writer, rec)
        except WriteFailed as exc:
            stop_on(exc, [rec.case])
            return False
        stored.append(rec.case)
        _account(rec, report, write)
        if on_record is not None:
            on_record(rec)
        if bar is not None:
            bar.update(1)
            bar.set_postfix_str(f"failed {report.failed}" if report.failed else "")
        return True

    with contextlib.nullcontext(guard) if guard is not None else SignalGuard() as guard:
        if client is not None and todo:
            stop = run_on_client(todo, client, finish, guard)
            if report.status == EXIT_OUTPUT:
                return report
            report.interrupted = report.interrupted or stop
        for case in todo if client is None else []:
            if guard.pending:
                break
            if progress is not None:
                progress(case)
            announce(case, write)
            stream = CaseStream(out)
            try:
                rec = run_case(case, guard, stream)
                ok = finish(rec)
            except WriteFailed as exc:  # the case's stream file
                stop_on(exc, [])
                ok = False
            finally:
                stream.remove()
            if not ok:
                return report
            if rec.interrupted:
                break
        if guard.pending and not report.interrupted:
            report.interrupted = guard.pending
    if report.interrupted:
        report.status = EXIT_SIGTERM if report.interrupted == "SIGTERM" else EXIT_SIGINT
    elif report.failed:
        report.status = EXIT_FAILED
    return report


def resume_hint(deck: Path, out: Path) -> str:
    """The command that continues an interrupted run."""
    return f"railvti run {deck} -o {out} --resume"


# ---------------------------------------------------------------------------------------------
# The cases as tasks on a dask.distributed client (the client: railvti._cluster)


#: The Dask event topic on which a worker announces the key of each case it starts: the
#: client keeps the set as the run goes, so a signal knows the running cases without asking
#: the (busy) workers, a round trip of up to seconds on a loaded machine.
STARTED_TOPIC = "railvti-case-started"


def run_task(case: Case) -> Any:
    """Run one case on a worker and return its :class:`railvti.runner.results.CaseRecord` (the
    worker never writes the results file). Signals are the worker's business: no guard."""
    _announce_start()
    return run_case(case, SignalGuard(), None)


def _announce_start() -> None:
    """Log the running task's key on :data:`STARTED_TOPIC` (nothing outside a worker)."""
    try:
        from distributed import get_worker

        worker = get_worker()
        worker.log_event(STARTED_TOPIC, worker.get_current_task())
    except (ImportError, ValueError, AttributeError):
        pass


def run_on_client(
    cases: list[Case], client: Any, on_record: Callable[[Any], bool], guard: Any = None
) -> str | None:
    """Submit every case to ``client`` and call ``on_record(record)`` in this process as each
    finishes (in the order they finish). ``on_record`` returns False to stop (the file cannot
    be written). Returns the signal that stopped the run, or None.

    Each case is a task with a key from its position and name (``railvti-NNN-name``), so
    dask never merges two points; no task is retried on another worker after an exception
    (its record carries it)."""
    from distributed import as_completed

    stamp = f"{os.getpid()}-{time.time_ns()}"
    futures, by_key = [], {}
    started: set[str] = set()
    # subscribed before the tasks are submitted (one ordered stream to the scheduler)
    client.subscribe_topic(STARTED_TOPIC, lambda event: started.add(event[1]))
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
                with guard.live() if guard is not None else contextlib.nullcontext():
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
            _mark_interrupted(set(started), futures, by_key, stop, time.monotonic() - t_start, on_record)
        for f in futures:
            if not f.done():
                f.cancel()
        with contextlib.suppress(Exception):  # a client already closed by the signal
            client.unsubscribe_topic(STARTED_TOPIC)
    return stop


def _mark_interrupted(
    started: set[str],
    futures: list,
    by_key: dict[str, Case],
    signame: str,
    elapsed: float,
    on_record: Callable[[Any], bool],
) -> None:
    """Record the cases a signal stopped while a worker was running them (started, not
    done) as interrupted (as the serial path records its running case); queued cases stay
    absent (``--resume`` runs them)."""
    for f in futures:
        if f.key in started and not f.done() and f.key in by_key:
            if not on_record(CaseRecord(by_key[f.key], interrupted=signame, wall_time=elapsed)):
                return


def _record(fut: Any, by_key: dict[str, Case]) -> Any:
    """The CaseRecord of a finished future (a task lost with its worker becomes the case's
    error)."""
    try:
        return fut.result()
    except Exception as exc:  # noqa: BLE001 - a worker died or the task could not run
        case = by_key.get(fut.key)
        if case is None:
            raise
        return CaseRecord(
            case,
            error=f"{type(exc).__name__}: {exc} (the task did not return)",
            traceback=traceback.format_exc(),
        )


__all__ = [
    "EXIT_CODES",
    "Interrupted",
    "SignalGuard",
    "check_deck",
    "check_output",
    "run_case",
    "run_cases",
    "run_on_client",
    "run_task",
    "RunReport",
]
