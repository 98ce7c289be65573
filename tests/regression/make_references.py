"""Write the reference results of the regression decks (tests/regression/references/*.json).

Run it deliberately, when a change of results is intended and understood, and commit the
new references with the change that moved them (say which quantities moved and why):

    .venv/bin/python tests/regression/make_references.py            # every deck
    .venv/bin/python tests/regression/make_references.py track_small # some decks

The references are made by the installed railvti (``./dev.sh setup`` first).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time

import regression as R


def _commit() -> str:
    try:
        out = subprocess.run(
            ["git", "-C", str(R.ROOT), "describe", "--always", "--dirty"],
            capture_output=True,
            text=True,
            check=True,
        )
        return out.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    names = [d.name for d in R.DECKS]
    parser.add_argument(
        "decks", nargs="*", metavar="deck", help=f"deck names (default: all): {', '.join(names)}"
    )
    args = parser.parse_args(argv)
    unknown = [n for n in args.decks if n not in names]
    if unknown:
        parser.error(f"unknown deck(s) {unknown}; known: {names}")
    import railvti

    chosen = [R.deck(n) for n in args.decks] if args.decks else list(R.DECKS)
    R.REFERENCES.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for d in chosen:
            t0 = time.perf_counter()
            cases = R.run_deck(d, tmp)
            R.write_reference(
                d,
                cases,
                deck=d.path.relative_to(R.ROOT).as_posix(),
                railvti_version=railvti.__version__,
                source=_commit(),
                made_by="tests/regression/make_references.py",
            )
            print(f"{d.reference.relative_to(R.ROOT)}: {len(cases)} cases [{time.perf_counter() - t0:.1f} s]")
    return 0


if __name__ == "__main__":
    sys.exit(main())
