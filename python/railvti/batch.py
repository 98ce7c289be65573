"""Running the cases of a deck into one results file without losing finished work.

* Each case runs isolated: any exception (not only railvti's) becomes that case's recorded
  error, with its traceback in the log and in the file; the other cases still run.
* Each finished case is written at once (:class:`railvti.results.ResultsWriter`: a new
  version of the file in a temporary file beside it, renamed over the old one), so there is a
  valid file after every case; ``--resume`` keeps the cases already complete (status 'ok' and
  the same parameters) and runs the others.
* SIGINT (Ctrl-C) and SIGTERM stop the run: the case running is marked 'interrupted' in the
  file, the completed ones are kept, no temporary file is left. The long Fortran loops are
  called in slices of ~0.1-0.2 s (Gauss-Seidel and CG normal contact, the vehicle time loop),
  and the steady rolling call runs in a worker thread while the main thread waits for
  signals (railvti.contact.workspace.call_interruptibly), so a run stops within about that
  (docs/results.md lists the calls that still finish first). SIGKILL leaves the previous complete file (or none) and at
  most one ``.NAME.PID.XXXX.tmp`` file beside it.
* The output path is checked before any case runs (:func:`check_output`).
* A case with a long time history streams it (railvti.stream) to a temporary file beside the
  output as it runs; its datasets are copied into the case's group when the case is written,
  and the file is deleted then (also after an error or a signal). SIGKILL during such a case
  leaves the previous complete file and that stream file (``.NAME.PID.XXXX.tmp``).

Exit status of ``railvti run`` (:data:`EXIT_CODES`).
"""
from __future__ import annotations

import contextlib
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
from typing import Any, Iterator

from .casetypes import CaseOutput
from .deck import Case
from .errors import InputError
from .resources import check_memory, memory_limit, size_text
from .stream import CaseStream, history_bytes, stream_threshold, STREAM_TAIL_SECONDS
from .results import CaseRecord, ResultsWriter, completed, group_name, is_results_file, params_digest, temp_path

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

#: A case expected to take longer than this (s) or more memory than this (bytes) is
#: announced before it starts.
ANNOUNCE_SECONDS = 60.0
ANNOUNCE_BYTES = 500e6


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
        self.received: str | None = None     # the last signal, whatever became of it
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
            self._resend_later(signum, 0.01)    # raise it once out of the callback
            return
        if self._live:
            self._live = False
            if self._resend:
                self._resend_later(signum, RESEND_SECONDS)
            raise Interrupted(name)
        self.pending = self.pending or name

    def _resend_later(self, signum: int, delay: float) -> None:
        def again() -> None:
            if self._inside:            # the Interrupted was swallowed: raise it again
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
    if out.exists() or out.is_symlink():
        try:
            st = os.stat(out)
        except OSError as exc:
            raise InputError(f"output {out}: {exc.strerror}") from None
        if stat.S_ISDIR(st.st_mode):
            raise InputError(f"output {out} is a directory: give a file name (-o DIR/results.h5)")
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"output {out} is not a regular file (a device, pipe or socket): "
                             "railvti writes only regular files")
        if deck is not None and deck.exists() and os.path.samefile(out, deck):
            raise InputError(f"output {out} is the deck itself: give another name with -o")
        if not force and not is_results_file(out):
            raise InputError(f"output {out} exists and is not a railvti results file: give "
                             "another name, or --force to replace it")
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


@dataclass(frozen=True)
class Estimate:
    """Rough memory (bytes) and wall time (s) of a case; NaN when unknown."""

    memory: float = float("nan")
    seconds: float = float("nan")


#: Wall time per time step of the vehicle time loop, s (hunting at 400 km/h on this project's
#: 2-core test machine: ~4 ms with Hertz + FASTSIM or Kalker; BEM much more).
_STEP_SECONDS = {"bem": 0.1}
_STEP_SECONDS_DEFAULT = 4e-3
#: Bytes stored per output time of a vehicle run (q, v: 2 x ~60 states; 12 x 2 x 4 wheel
#: outputs), times the copies made while gathering and writing.
_OUTPUT_BYTES = (2 * 60 + 12 * 2 * 4) * 8 * 3


def _num(params: dict[str, Any], key: str, default: float) -> float:
    try:
        v = float(params.get(key, default))
    except (TypeError, ValueError):
        return default
    return v if v == v else default


def estimate(case: Case) -> Estimate:
    """A rough estimate of what a case needs (vehicle histories and contact grids)."""
    p = case.params
    t = case.case_type.name
    if t == "vehicle":
        duration = _num(p, "duration", 3.0)
        h = max(_num(p, "h", 1e-3), 1e-9)
        output_dt = max(_num(p, "output_dt", 0.002), h)
        runs = 1.0
        if p.get("scenario") == "critical_speed":
            lo, hi = _num(p, "speeds_kmh_min", 160.0), _num(p, "speeds_kmh_max", 440.0)
            runs = max(1.0, (hi - lo) / max(_num(p, "speeds_kmh_step", 20.0), 1e-9) + 1.0)
        per_step = _STEP_SECONDS.get(str(p.get("contact")), _STEP_SECONDS_DEFAULT)
        kept = duration
        if runs == 1.0 and history_bytes(duration, output_dt) > stream_threshold():
            kept = min(duration, STREAM_TAIL_SECONDS + 1.0)   # streamed: the tail and a chunk
        return Estimate(memory=kept / output_dt * _OUTPUT_BYTES,
                        seconds=runs * duration / h * per_step)
    if t in ("normal", "rolling"):
        n = _num(p, "nx", 0.0) * _num(p, "ny", 0.0)
        return Estimate(memory=n * 8 * 40)      # the fields and 4 N FFT buffers of a few kernels
    if t == "wheel_rail":
        # one wheel of at 0.2 mm: ~0.07 s (0.5 s at worst); time ~ elements ~ 1 / (dx dy)
        elements = (2e-4 * 2e-4) / max(_num(p, "dx", 2e-4) * _num(p, "dy", 2e-4), 1e-12)
        wheels = 2.0 if str(p.get("side", "both")).strip().lower() == "both" else 1.0
        return Estimate(seconds=0.1 * wheels * elements)
    return Estimate()


#: A deck whose estimated run time is below this runs in the main process, without a Dask
#: LocalCluster: the cluster's start-up (worker processes that each import railvti, ~3-5 s
#: on a 2-core machine) would cost more than it saves (CONTACT's A-2.2 deck of 21
#: positions: 15.7 s with the cluster, 5.0 s without, 1.4 s of solves).
SERIAL_SECONDS = 10.0


def small_deck(cases: list[Case]) -> bool:
    """The deck is one case, or its cases' estimated times are known and add up to less than
    :data:`SERIAL_SECONDS`."""
    if len(cases) < 2:
        return True
    total = sum(estimate(c).seconds for c in cases)
    return total == total and total < SERIAL_SECONDS


def _duration_text(s: float) -> str:
    if s >= 3600:
        return f"{s / 3600:.1f} h"
    return f"{s / 60:.0f} min" if s >= 60 else f"{s:.0f} s"


def check_resources(cases: list[Case]) -> list[str]:
    """Problems of cases whose estimated memory exceeds the limit (see railvti.resources)."""
    out = []
    for c in cases:
        e = estimate(c)
        if e.memory == e.memory:
            try:
                check_memory(f"{c.label}", e.memory, "shorten 'duration' or raise 'output_dt'"
                             if c.case_type.name == "vehicle" else "use a coarser grid")
            except InputError as exc:
                out.append(str(exc))
    return out


def announce(case: Case, write: Any) -> None:
    """Say what a case is expected to need before it starts, when that is large."""
    e = estimate(case)
    parts = []
    if e.memory == e.memory and e.memory > ANNOUNCE_BYTES:
        parts.append(f"~{size_text(e.memory)} of memory (limit {size_text(memory_limit())})")
    if e.seconds == e.seconds and e.seconds > ANNOUNCE_SECONDS:
        parts.append(f"~{_duration_text(e.seconds)}")
    if parts:
        write(f"{case.label}: expected to need {' and '.join(parts)} (rough estimate)")


@dataclass
class RunReport:
    """What a run did: its exit status and counts."""

    status: int
    ok: int = 0
    failed: int = 0
    skipped: int = 0
    interrupted: str | None = None


def _streamed_partial(res: Any, stream: Any) -> tuple[dict, dict]:
    """Datasets and labels of an interrupted run's streamed history: every dataset of the
    stream (t, q, v and the per-wheel histories), referenced for copying."""
    from .vehicle.cases import WHEEL_UNITS
    labels = res._save_attrs()
    nw = res.wheel.shape[-1]
    per_wheel = {"axes": ["t", "wheel", "wheelset"], "wheel": ["left", "right"],
                 "wheelset": [f"ws{w + 1}" for w in range(nw)]}
    units = {"t": "s", "q": "m or rad (per dof_names)", "v": "m/s or rad/s (per dof_names)",
             "y_ws1": "m", "vy_ws1": "m/s", "ws_y": "m"}
    data = {}
    for name in stream.names():
        unit = units.get(name) or WHEEL_UNITS.get(name.removeprefix("wheel_"), "1")
        data[name] = (stream.streamed(name), unit)
        if name.startswith("wheel_"):
            labels[name] = per_wheel
    labels["ws_y"] = {"axes": ["t", "wheelset"], "wheelset": per_wheel["wheelset"]}
    return data, {k: v for k, v in labels.items() if k in data}


def partial_output(res: Any, stream: CaseStream | None = None) -> CaseOutput | None:
    """The time history an interrupted vehicle run had completed (its exception's
    ``partial`` SimulationResult) as a CaseOutput, or None. A history streamed to the case's
    ``stream`` (``res.streamed``) is referenced there whole (the SimulationResult holds only
    its tail)."""
    if res is None or not hasattr(res, "_save_attrs"):
        return None
    from .vehicle.cases import STAT_UNITS
    hs = stream.stream if stream is not None else None
    if getattr(res, "streamed", "") and hs is not None and res.streamed == hs.where:
        hs.close()
        data, labels = _streamed_partial(res, hs)
    else:
        labels = res._save_attrs()
        data = {"t": (res.t, "s"), "q": (res.q, "m or rad (per dof_names)"),
                "v": (res.v, "m/s or rad/s (per dof_names)"),
                "wheel": (res.wheel, "per quantity: see quantity_units")}
    scalars = {f"stat_{k}": (v, STAT_UNITS.get(k, "1")) for k, v in res.stats.items()
               if isinstance(v, (int, float))}
    t_end = float(res.t[-1]) if len(res.t) else 0.0
    return CaseOutput(summary=f"interrupted: the time history up to t = {t_end:.3f} s is kept",
                      datasets=data, scalars=scalars, attrs=labels)


def run_case(case: Case, guard: SignalGuard, stream: CaseStream | None = None) -> CaseRecord:
    """Run one case; any exception becomes the record's error (with its traceback),
    a signal the record's ``interrupted``. With ``stream`` the case may stream a long time
    history to it (railvti.stream.case_stream); the stream is closed on return (the caller
    writes the record, then removes the stream file)."""
    t0 = time.perf_counter()
    active = stream.active() if stream is not None else contextlib.nullcontext()
    try:
        with active, guard.live():
            output = case.case_type.run(case.params)
    except KeyboardInterrupt as exc:    # Interrupted, or Ctrl-C without the guard's handler
        return CaseRecord(case, output=partial_output(getattr(exc, "partial", None), stream),
                          interrupted=getattr(exc, "signame", "SIGINT"),
                          wall_time=time.perf_counter() - t0)
    except Exception as exc:  # noqa: BLE001 - isolation: any failure is this case's alone
        tb = traceback.format_exc()    # to the file; the console's line and --debug: _account
        return CaseRecord(case, error=f"{type(exc).__name__}: {exc}", traceback=tb,
                          wall_time=time.perf_counter() - t0)
    finally:
        if stream is not None:
            stream.close()
    return CaseRecord(case, output=output, wall_time=time.perf_counter() - t0)


def _store(writer: ResultsWriter, rec: CaseRecord, out: Path, write: Any) -> bool:
    """Write one record; a result that cannot be stored (a value HDF5 refuses) becomes the
    case's error. False when the file itself cannot be written (disk full, I/O error)."""
    try:
        writer.write([rec])
        return True
    except OSError as exc:
        write(f"railvti: error: cannot write {out}: {exc.strerror or exc}")
        return False
    except Exception as exc:  # noqa: BLE001 - a bad result value: record it as the case's error
        tb = traceback.format_exc()
        tb_log.debug("%s: its results cannot be stored:\n%s", rec.case.label, tb.rstrip())
        rec.output = None
        rec.error = f"cannot store the results: {type(exc).__name__}: {exc}"
        rec.traceback = tb
    try:
        writer.write([rec])
        return True
    except Exception as exc:  # noqa: BLE001
        write(f"railvti: error: cannot write {out}: {exc}")
        return False


#: Said after the line of a case that failed with an exception railvti does not expect.
UNEXPECTED_HINT = (" (unexpected: its traceback is in the results file; "
                   "'railvti run --debug' prints it)")


def expected_error(error: str) -> bool:
    """Whether a record's error ('ExceptionClass: message') is one of railvti's own
    (:class:`railvti.errors.RailvtiError` and its subclasses, wherever defined): a failure the
    code foresaw and explained, not a bug."""
    from .errors import RailvtiError
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


def run_cases(cases: list[Case], out: Path, deck_text: str, *, resume: bool = False,
              write: Any = print, progress: Any = None, client: Any = None,
              on_record: Any = None, bar: Any = None, guard: SignalGuard | None = None) -> RunReport:
    """Run ``cases`` into the results file ``out`` (checked beforehand with
    :func:`check_output`), each finished case written at once.

    Parameters
    ----------
    write : callable
        Prints one line for the user.
    progress : callable, optional
        ``progress(case)`` before each case of a serial run (e.g. a progress bar's postfix).
    client : distributed.Client, optional
        Run the cases as tasks on this Dask client (railvti.sweeps.run_on_client); each
        finished one is written here, by this process, as it arrives. None: one after
        another in this process (dask is not imported).
    on_record : callable, optional
        ``on_record(record)`` after each record is stored.
    bar : tqdm, optional
        Advanced by one per finished case, its postfix the count of failures; its total is
        set to the cases to run.
    guard : SignalGuard, optional
        Already installed by the caller (from before a cluster's start-up); default: one
        installed for the run.
    """
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
    writer = ResultsWriter(out, deck_text, keep=resume)

    def finish(rec: CaseRecord) -> bool:
        """Store a record (False: the file cannot be written) and count it."""
        if not _store(writer, rec, out, write):
            report.status = EXIT_OUTPUT
            return False
        _account(rec, report, write)
        if on_record is not None:
            on_record(rec)
        if bar is not None:
            bar.update(1)
            bar.set_postfix_str(f"failed {report.failed}" if report.failed else "")
        return True

    with contextlib.nullcontext(guard) if guard is not None else SignalGuard() as guard:
        if client is not None and todo:
            from .sweeps import run_on_client
            stop = run_on_client(todo, client, finish, guard)
            if report.status == EXIT_OUTPUT:
                return report
            report.interrupted = report.interrupted or stop
        for case in (todo if client is None else []):
            if guard.pending:
                break
            if progress is not None:
                progress(case)
            announce(case, write)
            stream = CaseStream(out)
            try:
                rec = run_case(case, guard, stream)
                stored = finish(rec)
            finally:
                stream.remove()
            if not stored:
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


__all__ = ["EXIT_CODES", "Interrupted", "SignalGuard", "check_output", "check_resources",
           "estimate", "run_case", "run_cases", "RunReport"]
