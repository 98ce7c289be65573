"""The ``railvti`` command: run decks, plot results, list case types.

* SIGINT and SIGTERM are handled from the first thing :func:`main` does, before the heavy
  imports (numpy, h5py, Dask: this module imports them inside the commands): a signal before
  the cases start ends the command at once with exit 130 / 143 and one line, a half-started
  Dask cluster shut down (its worker processes killed); from then on the batch runner's
  :class:`railvti.runner.batch.SignalGuard` keeps the completed cases.
* An expected failure (a ``railvti.errors`` class) prints one line; an unexpected exception
  one line and a hint; ``--debug`` prints their tracebacks (a failed case's is also stored in
  the results file).
* A closed stdout (``railvti cases | head -3``) ends quietly: exit 141 (SIGPIPE's), or for
  ``run`` the run goes on to its end with its lines discarded.
"""

from __future__ import annotations

import argparse
import atexit
import contextlib
import difflib
import gc
import io
import logging
import os
import signal
import sys
import threading
from pathlib import Path
from typing import Any, Iterator

from ..errors import InputError, RailvtiError

log = logging.getLogger("railvti")
#: Exit status when stdout's reader went away (128 + SIGPIPE, as a shell reports it).
EXIT_SIGPIPE = 141
#: Exit status of an exception that is not a railvti error (a bug: the hint says --debug).
EXIT_UNEXPECTED = 1


def _run(args: argparse.Namespace) -> int:
    from .. import resources
    from . import cost
    from .batch import check_deck, check_output
    from .deck import read_deck
    from .output_lock import OutputLock

    _check_options(args)
    deck = Path(args.deck)
    cases = read_deck(deck)
    out = Path(args.output) if args.output else deck.with_suffix(".h5")
    check_output(out, deck, force=args.force)
    if out.is_symlink():  # write the file it points to (the link stays a link)
        out = Path(os.path.realpath(out))
        check_output(out, deck, force=args.force)
    limits = {
        resources.ENV: args.max_memory,
        cost.ENV_TIME: args.max_time,
        cost.ENV_DECK_TIME: args.max_deck_time,
    }
    old = {env: os.environ.get(env) for env in limits}
    note = lambda line: print(line, file=sys.stderr)  # noqa: E731
    try:
        # the lock before the deck check: no other run can change the file in between
        with OutputLock(out, str(deck.resolve()), note=note):
            args.resume = check_deck(out, deck, cases, args.resume, args.force, note)
            for env, value in limits.items():
                if value is None:
                    continue
                if not str(value).strip():  # '' too: refused, not the default in silence
                    raise InputError(f"{env}: an empty value; give a size or a time, or none")
                os.environ[env] = str(value)
            resources.memory_limit()  # a bad size: InputError before any case
            if args.max_time:
                cost.parse_time(args.max_time, "--max-time")
            if args.max_deck_time:
                cost.parse_time(args.max_deck_time, "--max-deck-time")
            return _run_checked(args, deck, cases, out)
    finally:
        for env, value in old.items():
            if value is None:
                os.environ.pop(env, None)
            else:
                os.environ[env] = value


def _check_options(args: argparse.Namespace) -> None:
    """Refuse bad option values at once, before the deck is read or Dask imported."""
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be at least 1, got {args.workers}")
    if args.scheduler is not None:
        from .sweeps import scheduler_address

        scheduler_address(args.scheduler, "--scheduler")
    if args.max_memory is not None and not args.max_memory.strip():
        raise InputError("--max-memory '': give a size such as 8G, 500M, 1e9 or none")


def _bar(n: int, serial: bool) -> Any:
    """The progress bar of a run of ``n`` cases (on stderr)."""
    from tqdm import tqdm

    desc = "cases" if serial else "tasks"
    return tqdm(total=n, desc=desc, unit="case", file=sys.stderr, dynamic_ncols=True)


def _bar_writer() -> Any:
    """A line writer that keeps the progress bar below the lines (tqdm.write)."""
    from tqdm import tqdm

    return lambda line: tqdm.write(line, file=sys.stdout)


def _run_checked(args: argparse.Namespace, deck: Path, cases: list, out: Path) -> int:
    from . import cost
    from .batch import EXIT_OUTPUT, Interrupted, SignalGuard, resume_hint, run_cases

    problems = cost.check_cost(cases)
    if problems:
        raise InputError("\n".join(problems))
    for line in cost.resolution_warnings(cases):
        print(f"railvti: warning: {line}", file=sys.stderr)
    # no LocalCluster where its start-up (worker processes importing railvti) outweighs the work
    serial = args.serial or (args.scheduler is None and args.workers is None and cost.small_deck(cases))

    # tqdm only with a bar to show (its import looks up its version: importlib.metadata, some
    # 25 ms of a quiet run, issue 33)
    shown = len(cases) >= 2 and not args.quiet
    line_out = _bar_writer() if shown else lambda line: print(line, file=sys.stdout)

    def write(line: str) -> None:
        try:
            line_out(line)
        except BrokenPipeError:  # stdout's reader went away: the run goes on
            _stdout_closed()

    # the guard from before the cluster starts: a signal during its start-up stops at once
    # (the half-started cluster killed, railvti.runner.sweeps.local_client), later ones keep the
    # completed cases (run_cases)
    with SignalGuard() as guard:
        # a signal before the guard whose Stopped was swallowed on its way (a library's
        # `except ImportError` around an optional C extension: its import turns it into one)
        _signal_instead()
        try:
            with contextlib.ExitStack() as stack:
                with guard.live(resend=False):
                    client = stack.enter_context(_client(args, serial, len(cases), write))
                bar = _bar(len(cases), serial) if shown else None
                if bar is not None:
                    stack.callback(bar.close)
                report = run_cases(
                    cases,
                    out,
                    _deck_text(deck),
                    resume=args.resume,
                    write=write,
                    progress=None if bar is None else lambda c: bar.set_postfix_str(c.name[-30:]),
                    client=client,
                    bar=bar,
                    deck_path=str(deck.resolve()),
                    guard=guard,
                )
        except Exception:
            # a signal inside a C extension's import (Dask's) comes out as its ImportError
            if guard.received is None:
                raise
            signame = guard.received
        except Interrupted as exc:
            signame = exc.signame
        else:
            signame = None
    if signame is not None:
        where = "before any case ran" if serial else "while the Dask cluster started"
        kept = f"{out} is unchanged" if out.exists() else f"{out} was not written"
        _say(f"railvti: stopped by {signame} {where}: no case ran, {kept}")
        return 128 + signal.Signals[signame].value
    n = len(cases)
    if report.error:
        _say(f"railvti: error: {report.error}; continue with: {resume_hint(deck, out)}")
    if report.interrupted and not out.exists():  # the first cases had not yet started
        _say(
            f"interrupted by {report.interrupted} before any case finished: {out} was not "
            f"written; continue with: {resume_hint(deck, out)}",
            sys.stdout,
        )
    elif report.interrupted:
        _say(
            f"interrupted by {report.interrupted}: wrote {out} ({report.ok + report.skipped} of {n} "
            f"cases complete); continue with: {resume_hint(deck, out)}",
            sys.stdout,
        )
    elif report.status != EXIT_OUTPUT:
        _say(
            f"wrote {out} ({report.ok + report.skipped} of {n} cases ok"
            + (f", {report.skipped} kept from before" if report.skipped else "")
            + ")",
            sys.stdout,
        )
    return report.status


@contextlib.contextmanager
def _client(args: argparse.Namespace, serial: bool, n_cases: int, write: Any) -> Iterator[Any]:
    """The Dask client of a run: none (--serial, or a deck of one case), an existing
    scheduler (--scheduler ADDRESS), or a LocalCluster of --workers processes (default: the
    cores, at most one per case)."""
    if serial:
        yield None
        return
    from . import sweeps

    if args.scheduler:
        with sweeps.remote_client(args.scheduler, what="--scheduler") as client:
            n = len(client.scheduler_info().get("workers", {}))
            write(f"dask: scheduler {args.scheduler} with {n} workers")
            yield client
        return
    n = args.workers or min(sweeps.default_workers(), n_cases)
    with sweeps.local_client(n) as client:
        write(f"dask: LocalCluster of {n} worker processes, 1 thread each")
        yield client


def _deck_text(deck: Path) -> str:
    try:
        return deck.read_bytes().decode("utf-8", "replace")
    except OSError:
        return ""


def _plot(args: argparse.Namespace) -> int:
    from .plots import plot_results  # matplotlib: only for plotting, not at every start

    notes: list[str] = []
    paths = plot_results(args.results, args.output, points=args.points, notes=notes)
    for p in paths:
        print(p)
    for line in notes:
        print(f"railvti: note: {line}", file=sys.stderr)
    if not paths:
        print(
            f"railvti: error: no figure written from {args.results}"
            + (": every case above was left out" if notes else ": it holds no case"),
            file=sys.stderr,
        )
        return 1
    return 0


def _summary(args: argparse.Namespace) -> int:
    from .summary import summary

    print(summary(args.results, args.plots))
    return 0


def _default_text(default: object) -> str:
    from ..casetypes import REQUIRED

    if default is REQUIRED:
        return "(required)"
    if default is None:
        return "(none)"
    if isinstance(default, float):
        return f"{default:.6g}"
    text = repr(default)
    return text if len(text) <= 14 else "..." + text[-11:]


def _cases(args: argparse.Namespace) -> int:
    from .deck_registry import case_types

    types = case_types()
    names = sorted(types)
    if args.type:
        want = args.type.strip().lower()
        if want not in types:
            close = difflib.get_close_matches(want, names, n=1, cutoff=0.5)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise InputError(f"unknown case type '{args.type}'{hint}; known types: {', '.join(names)}")
        names = [want]
    for name in names:
        ctype = types[name]
        print(f"type = '{name}'" + (f": {ctype.summary}" if ctype.summary else ""))
        print(f"    {'key':28s} {'default':>14s}  {'unit':8s} meaning; allowed values")
        for key, default in ctype.defaults.items():
            spec = ctype.keys.get(key)
            unit = (spec.unit or "-") if spec else "?"
            meaning = spec.meaning if spec else ""
            bounds = spec.bounds() if spec else ""
            print(
                f"    {key:28s} {_default_text(default):>14s}  {unit:8s} {meaning}"
                + (f"; {bounds}" if bounds else "")
            )
        for alias, a in ctype.aliases.items():
            to = ctype.keys[a.key].unit if a.key in ctype.keys else ""
            note = (
                "old name, deprecated"
                if a.deprecated
                else f"the same in {a.unit} (x {a.scale:.6g}" + (f" to {to})" if to else ")")
            )
            print(f"    {alias:28s} {'':>14s}  {a.unit or '':8s} alias of '{a.key}': {note}")
        print()
    print(
        "units: SI; '1' a number without unit, '-' a text or a 0/1 flag; 'railvti cases TYPE' lists one type"
    )
    print(
        "sweeps: any key as sweep_KEY = v1, v2, ... or sweep_range_KEY = start, stop, step, "
        "with sweep = 'product' or 'zip' (docs/sweeps.md)"
    )
    return 0


def _say(line: str, stream: Any = None) -> None:
    """Print one line (stderr by default); a closed stream is not an error."""
    try:
        print(line, file=stream or sys.stderr, flush=True)
    except BrokenPipeError:
        if stream is sys.stdout:
            _stdout_closed()
    except (OSError, ValueError):  # stderr closed as well: nobody to tell
        pass


def _stdout_closed() -> int:
    """stdout's reader went away (``railvti cases | head``): point stdout at /dev/null, so
    that later lines and the interpreter's final flush do not fail again, and return
    :data:`EXIT_SIGPIPE`."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError, io.UnsupportedOperation):
        pass  # not a file descriptor (a test's capture): nothing to flush
    return EXIT_SIGPIPE


class Stopped(KeyboardInterrupt):
    """A signal before the batch runner's guard took over.

    A subclass, not KeyboardInterrupt itself: CPython notes an exact KeyboardInterrupt
    passing through an ``exec`` of a text (dataclasses and namedtuples do that while modules
    import) and at exit kills the process with SIGINT (status -2, after our message) instead
    of returning our status."""

    def __init__(self, signame: str) -> None:
        super().__init__(signame)
        self.signame = signame


#: The signals :func:`_raise_signal` received during this call of :func:`main`.
_RECEIVED: list[str] = []


def _raise_signal(signum: int, frame: Any) -> None:
    """A signal before the batch runner's guard: stop where we are."""
    _RECEIVED.append(signal.Signals(signum).name)
    raise Stopped(signal.Signals(signum).name)


@contextlib.contextmanager
def _signals_raise() -> Iterator[None]:
    """SIGINT and SIGTERM raise KeyboardInterrupt inside (SIGTERM's default would kill the
    process without a word); the previous handlers restored on exit."""
    old = {}
    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGINT, signal.SIGTERM):
            old[sig] = signal.signal(sig, _raise_signal)
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)


def _parser() -> argparse.ArgumentParser:
    from .batch import EXIT_CODES
    from .cost import SERIAL_SECONDS

    parser = argparse.ArgumentParser(prog="railvti", description="railway vehicle-track interaction")
    parser.add_argument("-v", "--verbose", action="store_true", help="log debug messages")
    debug = argparse.ArgumentParser(add_help=False)
    debug.add_argument(
        "--debug",
        action="store_true",
        default=argparse.SUPPRESS,
        help="print the traceback of every error (a failed case's is also in the results file)",
    )
    parser.add_argument("--debug", action="store_true", default=False, help=argparse.SUPPRESS)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser(
        "run",
        help="run every case of a deck and write one HDF5 file",
        parents=[debug],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Run every case of a deck into one HDF5 file, written again after each case "
        "(a valid file at every moment; Ctrl-C or SIGTERM stop within about a second "
        "and keep the completed cases, also while the cluster starts). The cases and "
        "sweep points run as tasks on a Dask LocalCluster (one process per core, one "
        "thread each) unless --serial or --scheduler; only this process writes the "
        "file.\n\n"
        "Small decks run serially, without a cluster: a deck of one case, or one whose "
        "cases' estimated run times are all known\nand add up to less than "
        f"{SERIAL_SECONDS:g} s, runs in this process, as with --serial (starting the "
        "cluster takes ~3-5 s).\n--workers N or --scheduler force a cluster.\n\n"
        "An expected failure (bad input, a grid too small, no convergence) prints one "
        "line; --debug adds the tracebacks.",
        epilog="exit status:\n" + "\n".join(f"  {k:3d}  {v}" for k, v in EXIT_CODES.items()),
    )
    p.add_argument("deck")
    p.add_argument("-o", "--output", help="HDF5 file (default: the deck's name with .h5)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.add_argument(
        "--resume",
        action="store_true",
        help="keep the cases already complete in the output (same parameters) and run the others",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="replace an existing output file that is not a railvti results file, "
        "or one written from another deck",
    )
    p.add_argument(
        "--max-memory",
        metavar="SIZE",
        help="memory limit of a case, e.g. 8G or none (default: 80%% of the available memory)",
    )
    p.add_argument(
        "--max-time",
        metavar="TIME",
        help="time limit of a case's estimate, e.g. 8h, 30min or none (default: 2h; env RAILVTI_MAX_TIME)",
    )
    p.add_argument(
        "--max-deck-time",
        metavar="TIME",
        help="time limit of the deck's cases added up (default: 24h; env RAILVTI_MAX_DECK_TIME)",
    )
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--serial", action="store_true", help="run the cases one after another in this process (no Dask)"
    )
    g.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run the cases as tasks on an existing Dask cluster, ADDRESS as "
        "tcp://host:port (refused at once if malformed, within 5 s if no "
        "scheduler answers)",
    )
    g.add_argument(
        "--workers",
        metavar="N",
        type=int,
        help="worker processes of the LocalCluster (default: the cores, at most one "
        "per case); forces a cluster even for a small deck",
    )
    p.set_defaults(func=_run)
    p = sub.add_parser("plot", help="write PNG plots of a results file", parents=[debug])
    p.add_argument("results")
    p.add_argument("-o", "--output", help="folder for the PNGs (default: beside the file)")
    p.add_argument(
        "--points",
        action="store_true",
        help="also plot every point of a large sweep (default: its summary plot only)",
    )
    p.set_defaults(func=_plot)
    p = sub.add_parser(
        "summary", help="one screen: each case, each sweep's table, what each figure shows", parents=[debug]
    )
    p.add_argument("results")
    p.add_argument("--plots", help="folder of the PNGs (default: beside the file)")
    p.set_defaults(func=_summary)
    p = sub.add_parser(
        "cases", help="list the deck case types, or one type's keys with units and meanings", parents=[debug]
    )
    p.add_argument(
        "type", nargs="?", help="a case type: list its keys (default, unit, meaning, allowed range)"
    )
    p.set_defaults(func=_cases)
    return parser


#: Non-empty once :func:`_quick_exit` registered its hook (once per process).
_QUICK_EXIT: list[bool] = []


def _quick_exit() -> None:
    """At the interpreter's exit, skip the final garbage collection of everything imported
    (numpy, h5py, Dask: ~0.4 s, over a second under load, of the time a Ctrl-C takes): the
    objects alive then are frozen (``gc.freeze``) first. Our files are closed explicitly;
    dask's and multiprocessing's clean-ups are atexit hooks, which still run."""
    if not _QUICK_EXIT:
        atexit.register(gc.freeze)
        _QUICK_EXIT.append(True)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``railvti`` command; returns the exit status."""
    _quick_exit()
    _RECEIVED.clear()
    with _signals_raise():  # first: a signal during the imports below stops too
        try:
            return _main(argv)
        except KeyboardInterrupt as exc:  # before any case ran (the runner handles its own)
            name = getattr(exc, "signame", "SIGINT")
            _say(f"railvti: stopped by {name} before any case ran: nothing was written")
            return 128 + signal.Signals[name].value
        except BrokenPipeError:
            return _stdout_closed()


def _signal_instead() -> None:
    """Raise :class:`Stopped` if a signal came during this command: its exception may come
    out as another one (a C extension's import turns it into ImportError)."""
    if _RECEIVED:
        raise Stopped(_RECEIVED[-1]) from None


def _main(argv: list[str] | None) -> int:
    try:
        from .batch import EXIT_INPUT, TRACEBACK_LOGGER

        args = _parser().parse_args(argv)
    except Exception:
        _signal_instead()
        raise
    logging.basicConfig(
        level=logging.DEBUG if args.verbose else logging.WARNING, format="%(levelname)s %(name)s: %(message)s"
    )
    tracebacks = logging.getLogger(TRACEBACK_LOGGER)
    level = tracebacks.level
    if args.debug:
        tracebacks.setLevel(logging.DEBUG)
    try:
        status = args.func(args)
        try:
            sys.stdout.flush()  # here, not at the interpreter's exit ("Exception ignored")
        except BrokenPipeError:  # the work is done; the reader did not want the rest
            _stdout_closed()
        return status
    except BrokenPipeError:
        raise
    except RailvtiError as exc:
        _signal_instead()
        tracebacks.debug("%s", type(exc).__name__, exc_info=True)
        _say(f"railvti: error: {exc}")
        return EXIT_INPUT
    except Exception as exc:  # noqa: BLE001 - a bug: one line, the traceback with --debug
        _signal_instead()
        tracebacks.debug("%s", type(exc).__name__, exc_info=True)
        first = (str(exc).strip().splitlines() or [""])[0]
        _say(
            f"railvti: unexpected error: {type(exc).__name__}: {first} (a bug; run again with "
            "--debug for the traceback)"
        )
        return EXIT_UNEXPECTED
    finally:
        tracebacks.setLevel(level)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

__all__ = ["EXIT_SIGPIPE", "EXIT_UNEXPECTED", "Stopped", "main"]
