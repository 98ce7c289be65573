"""The ``railvti`` command: run decks, plot results, list case types."""
from __future__ import annotations

import argparse
import difflib
import logging
import sys
import time
from pathlib import Path

from tqdm import tqdm

from .casetypes import REQUIRED
from .deck import read_deck
from .deck_registry import case_types
from .errors import InputError, RailvtiError
from .plots import plot_results
from .results import CaseRecord, write_results

log = logging.getLogger("railvti")


def _run(args: argparse.Namespace) -> int:
    deck = Path(args.deck)
    cases = read_deck(deck)
    out = Path(args.output) if args.output else deck.with_suffix(".h5")
    records = []
    failed = 0
    bar = tqdm(cases, desc="cases", unit="case", disable=len(cases) < 2 or args.quiet, file=sys.stderr)
    for case in bar:
        bar.set_postfix_str(case.name)
        t0 = time.perf_counter()
        try:
            output = case.case_type.run(case.params)
        except RailvtiError as exc:
            failed += 1
            records.append(CaseRecord(case, error=f"{type(exc).__name__}: {exc}"))
            tqdm.write(f"{case.label}: FAILED: {type(exc).__name__}: {exc}", file=sys.stdout)
            continue
        records.append(CaseRecord(case, output=output))
        tqdm.write(f"{case.label}: {output.summary} [{time.perf_counter() - t0:.2f} s]", file=sys.stdout)
    write_results(out, records, deck.read_text())
    print(f"wrote {out} ({len(cases) - failed} of {len(cases)} cases ok)")
    return 1 if failed else 0


def _plot(args: argparse.Namespace) -> int:
    for p in plot_results(args.results, args.output):
        print(p)
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
            note = "old name, deprecated" if a.deprecated else f"the same in {a.unit} (x {a.factor:.6g})"
            print(f"    {alias:28s} {'':>14s}  {a.unit or '':8s} alias of '{a.key}': {note}")
        print()
    print("units: SI; '1' a number without unit, '-' a text or a 0/1 flag; "
          "'railvti cases TYPE' lists one type")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``railvti`` command; returns the exit status."""
    parser = argparse.ArgumentParser(prog="railvti", description="railway vehicle-track interaction")
    parser.add_argument("-v", "--verbose", action="store_true", help="log debug messages")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="run every case of a deck and write one HDF5 file")
    p.add_argument("deck")
    p.add_argument("-o", "--output", help="HDF5 file (default: the deck's name with .h5)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)
    p = sub.add_parser("plot", help="write PNG plots of a results file")
    p.add_argument("results")
    p.add_argument("-o", "--output", help="folder for the PNGs (default: beside the file)")
    p.set_defaults(func=_plot)
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
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
