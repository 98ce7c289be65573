"""The ``railvti`` command: run decks, plot results, list case types."""
from __future__ import annotations

import argparse
import contextlib
import difflib
import logging
import os
import sys
from pathlib import Path
from typing import Any, Iterator

from tqdm import tqdm

from .casetypes import REQUIRED
from .deck import read_deck
from . import cost, resources
from .deck_registry import case_types
from .batch import (EXIT_CODES, EXIT_INPUT, EXIT_OUTPUT, check_deck, check_output, check_resources, resume_hint,
                    run_cases, small_deck)
from .output_lock import OutputLock
from .errors import InputError, RailvtiError

log = logging.getLogger("railvti")


def _run(args: argparse.Namespace) -> int:
    deck = Path(args.deck)
    cases = read_deck(deck)
    out = Path(args.output) if args.output else deck.with_suffix(".h5")
    check_output(out, deck, force=args.force)
    if out.is_symlink():          # write the file it points to (the link stays a link)
        out = Path(os.path.realpath(out))
        check_output(out, deck, force=args.force)
    limits = {resources.ENV: args.max_memory, cost.ENV_TIME: args.max_time,
              cost.ENV_DECK_TIME: args.max_deck_time}
    old = {env: os.environ.get(env) for env in limits}
    note = lambda line: print(line, file=sys.stderr)      # noqa: E731
    try:
        # the lock before the deck check: no other run can change the file in between
        with OutputLock(out, str(deck.resolve()), note=note):
            args.resume = check_deck(out, deck, cases, args.resume, args.force, note)
            for env, value in limits.items():
                if value:
                    os.environ[env] = str(value)
            resources.memory_limit()             # a bad size or time: InputError before any case
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


def _run_checked(args: argparse.Namespace, deck: Path, cases: list, out: Path) -> int:
    problems = check_resources(cases)
    if problems:
        raise InputError("\n".join(problems))
    for line in cost.resolution_warnings(cases):
        print(f"railvti: warning: {line}", file=sys.stderr)
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be at least 1, got {args.workers}")
    # no LocalCluster where its start-up (worker processes importing railvti) outweighs the work
    serial = args.serial or (args.scheduler is None and args.workers is None and small_deck(cases))
    bar = tqdm(total=len(cases), desc="cases" if serial else "tasks", unit="case",
               disable=len(cases) < 2 or args.quiet, file=sys.stderr, dynamic_ncols=True)

    def write(line: str) -> None:
        tqdm.write(line, file=sys.stdout)

    try:
        with _client(args, serial, len(cases), write) as client:
            report = run_cases(cases, out, _deck_text(deck), resume=args.resume, write=write,
                               progress=lambda c: bar.set_postfix_str(c.name[-30:]),
                               client=client, bar=bar, deck_path=str(deck.resolve()))
    finally:
        bar.close()
    n = len(cases)
    if report.error:
        print(f"railvti: error: {report.error}; continue with: {resume_hint(deck, out)}",
              file=sys.stderr)
    if report.interrupted:
        print(f"interrupted by {report.interrupted}: wrote {out} ({report.ok + report.skipped} of {n} "
              f"cases complete); continue with: {resume_hint(deck, out)}")
    elif report.status != EXIT_OUTPUT:
        print(f"wrote {out} ({report.ok + report.skipped} of {n} cases ok"
              + (f", {report.skipped} kept from before" if report.skipped else "") + ")")
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
        with sweeps.remote_client(args.scheduler) as client:
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
    from .plots import plot_results      # matplotlib: only for plotting, not at every start
    notes: list[str] = []
    paths = plot_results(args.results, args.output, points=args.points, notes=notes)
    for p in paths:
        print(p)
    for line in notes:
        print(f"railvti: note: {line}", file=sys.stderr)
    if not paths:
        print(f"railvti: error: no figure written from {args.results}"
              + (": every case above was left out" if notes else ": it holds no case"), file=sys.stderr)
        return 1
    return 0


def _summary(args: argparse.Namespace) -> int:
    from .summary import summary
    print(summary(args.results, args.plots))
    return 0


def _default_text(default: object) -> str:
    if default is REQUIRED:
        return "(required)"
    if default is None:
        return "(none)"
    if isinstance(default, float):
        return f"{default:.6g}"
    text = repr(default)
    return text if len(text) <= 14 else "..." + text[-11:]


def _cases(args: argparse.Namespace) -> int:
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
            print(f"    {key:28s} {_default_text(default):>14s}  {unit:8s} {meaning}"
                  + (f"; {bounds}" if bounds else ""))
        for alias, a in ctype.aliases.items():
            to = ctype.keys[a.key].unit if a.key in ctype.keys else ""
            note = ("old name, deprecated" if a.deprecated
                    else f"the same in {a.unit} (x {a.factor:.6g}" + (f" to {to})" if to else ")"))
            print(f"    {alias:28s} {'':>14s}  {a.unit or '':8s} alias of '{a.key}': {note}")
        print()
    print("units: SI; '1' a number without unit, '-' a text or a 0/1 flag; "
          "'railvti cases TYPE' lists one type")
    print("sweeps: any key as sweep_KEY = v1, v2, ... or sweep_range_KEY = start, stop, step, "
          "with sweep = 'product' or 'zip' (docs/sweeps.md)")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``railvti`` command; returns the exit status."""
    parser = argparse.ArgumentParser(prog="railvti", description="railway vehicle-track interaction")
    parser.add_argument("-v", "--verbose", action="store_true", help="log debug messages")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser(
        "run", help="run every case of a deck and write one HDF5 file",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Run every case of a deck into one HDF5 file, written again after each case "
                    "(a valid file at every moment; Ctrl-C or SIGTERM stop within about a second "
                    "serially, a few seconds on a cluster, and keep the completed cases). The cases and sweep points run as tasks on a "
                    "Dask LocalCluster (one process per core, one thread each) unless --serial or "
                    "--scheduler; only this process writes the file.",
        epilog="exit status:\n" + "\n".join(f"  {k:3d}  {v}" for k, v in EXIT_CODES.items()))
    p.add_argument("deck")
    p.add_argument("-o", "--output", help="HDF5 file (default: the deck's name with .h5)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.add_argument("--resume", action="store_true",
                   help="keep the cases already complete in the output (same parameters) and run the others")
    p.add_argument("--force", action="store_true",
                   help="replace an existing output file that is not a railvti results file, "
                        "or one written from another deck")
    p.add_argument("--max-memory", metavar="SIZE",
                   help="memory limit of a case, e.g. 8G or none (default: 80%% of the available memory)")
    p.add_argument("--max-time", metavar="TIME",
                   help="time limit of a case's estimate, e.g. 8h, 30min or none (default: 2h; "
                        "env RAILVTI_MAX_TIME)")
    p.add_argument("--max-deck-time", metavar="TIME",
                   help="time limit of the deck's cases added up (default: 24h; env RAILVTI_MAX_DECK_TIME)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--serial", action="store_true",
                   help="run the cases one after another in this process (no Dask)")
    g.add_argument("--scheduler", metavar="ADDRESS",
                   help="run the cases as tasks on an existing Dask cluster (e.g. tcp://host:8786)")
    g.add_argument("--workers", metavar="N", type=int,
                   help="worker processes of the LocalCluster (default: the cores)")
    p.set_defaults(func=_run)
    p = sub.add_parser("plot", help="write PNG plots of a results file")
    p.add_argument("results")
    p.add_argument("-o", "--output", help="folder for the PNGs (default: beside the file)")
    p.add_argument("--points", action="store_true",
                   help="also plot every point of a large sweep (default: its summary plot only)")
    p.set_defaults(func=_plot)
    p = sub.add_parser("summary", help="one screen: each case, each sweep's table, what each figure shows")
    p.add_argument("results")
    p.add_argument("--plots", help="folder of the PNGs (default: beside the file)")
    p.set_defaults(func=_summary)
    p = sub.add_parser("cases", help="list the deck case types, or one type's keys with units and meanings")
    p.add_argument("type", nargs="?", help="a case type: list its keys (default, unit, meaning, allowed range)")
    p.set_defaults(func=_cases)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.DEBUG if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except RailvtiError as exc:
        print(f"railvti: error: {exc}", file=sys.stderr)
        return EXIT_INPUT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
