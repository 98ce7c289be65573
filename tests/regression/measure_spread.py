"""Measure how far the regression decks' results move with what should not matter.

Each deck runs in a fresh process under every combination of an OpenBLAS kernel set
(``OPENBLAS_CORETYPE`` unset, Haswell, SkylakeX, Sandybridge) and a thread count (1 or 2:
``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS``, ``RAILVTI_THREADS``), and each run is
compared with the stored reference. Printed, per deck and quantity, is the largest fraction
of its tolerance that any of these runs used (``regression.quantity_usage``); the tolerances
in ``regression.py`` are to keep that fraction at or below 1 / MARGIN. The table is also
written to ``references/spread.json`` (made by this script, read by nobody but people).

    .venv/bin/python tests/regression/measure_spread.py                 # the default decks
    .venv/bin/python tests/regression/measure_spread.py vehicle_short   # some decks

It takes about eight times the decks' own run time.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import regression as R

#: The margin between a tolerance and the largest difference measured here.
MARGIN = 10.0
CORETYPES = ("", "Haswell", "SkylakeX", "Sandybridge")
THREADS = (1, 2)

_CHILD = """
import json, sys
sys.path.insert(0, {here!r})
import regression as R
cases = R.run_deck(R.deck({name!r}), {tmp!r})
json.dump(cases, open({out!r}, "w"))
"""


def run_in(env_over: dict[str, str], name: str, tmp: str) -> dict:
    """The summary of deck ``name`` run in a fresh interpreter with ``env_over`` set."""
    out = Path(tmp) / f"{name}.json"
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE",)}
    env.update({k: v for k, v in env_over.items() if v})
    code = _CHILD.format(here=str(R.HERE), name=name, tmp=tmp, out=str(out))
    subprocess.run([sys.executable, "-c", code], env=env, check=True, cwd=tmp, stdout=subprocess.DEVNULL)
    return json.loads(out.read_text())


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("decks", nargs="*", help="deck names (default: the default suite's)")
    args = parser.parse_args(argv)
    chosen = [R.deck(n) for n in args.decks] if args.decks else [d for d in R.DECKS if not d.slow]
    table: dict[str, dict[str, list]] = {}
    worst_all = 0.0
    for d in chosen:
        ref = R.read_reference(d)["cases"]
        worst: dict[str, list] = {}
        for ct in CORETYPES:
            for nt in THREADS:
                env = {
                    "OPENBLAS_CORETYPE": ct,
                    "OPENBLAS_NUM_THREADS": str(nt),
                    "OMP_NUM_THREADS": str(nt),
                    "RAILVTI_THREADS": str(nt),
                }
                label = f"{ct or 'unset'}/{nt}"
                t0 = time.perf_counter()
                with tempfile.TemporaryDirectory() as tmp:
                    new = run_in(env, d.name, tmp)
                for key, u in R.usage(new, ref).items():
                    if not math.isnan(u) and u > worst.get(key, [0.0, ""])[0]:
                        worst[key] = [u, label]
                print(f"{d.name} {label}: {time.perf_counter() - t0:.1f} s", file=sys.stderr)
        table[d.name] = dict(sorted(worst.items(), key=lambda kv: -kv[1][0]))
        top = list(table[d.name].items())[:5]
        print(
            f"{d.name}: largest fraction of a tolerance used "
            + (", ".join(f"{k} {u:.2g} ({lab})" for k, (u, lab) in top) if top else "0")
        )
        worst_all = max([worst_all] + [u for u, _ in worst.values()])
    out = R.REFERENCES / "spread.json"
    old = json.loads(out.read_text()) if out.exists() else {}
    old.update(
        {
            k: {q: [float(f"{u:.3g}") if math.isfinite(u) else str(u), lab] for q, (u, lab) in v.items()}
            for k, v in table.items()
        }
    )
    out.write_text(json.dumps(old, indent=1, sort_keys=True) + "\n")
    print(f"largest fraction of a tolerance used: {worst_all:.3g} (to stay <= {1 / MARGIN:g})")
    return 0 if worst_all <= 1.0 / MARGIN else 1


if __name__ == "__main__":
    sys.exit(main())
