"""Where a run's time goes, by area: the self-time shares of a ``perf record`` file grouped by
the Fortran module a sample fell in (issue 33, the per-step profiles of docs/speed_accuracy.md).

Groups: ``BEM kernels`` (FFTW and the ``contact_*`` modules with ``common_anderson``: the
half-space solves), ``BEM coupling`` (``vehicle_bem``: patches, linear updates), ``strip
contact`` (``vehicle_strip``, ``vehicle_contact``), ``creep`` (``contact_fastsim`` is counted
here when no BEM ran), ``modal blocks`` (``vehicle_modal*``, ``vehicle_ring*``), ``Newton,
LAPACK`` (``vehicle_newmark`` and OpenBLAS), ``Python`` (the interpreter) and ``other`` (libc,
libgfortran, the kernel, the system build's other modules). perf records the whole process:
the system build is in it unless the run replays it from the disk cache.

    perf record -F 499 -o run.data -- python benchmarks/bench_vehicle_bem_rtf.py 2 --variant FF --cases new
    python benchmarks/perf_shares.py run.data [more.data ...]
"""

from __future__ import annotations

import collections
import re
import subprocess
import sys

LINE = re.compile(r"\s*([\d.]+)%\s+(\S+)\s+\[.\]\s+(.*)")
MODULE = re.compile(r"__(\w+?)_MOD_")


def group(dso: str, symbol: str, bem: bool) -> str:
    """The area of one sample's shared object and symbol (module procedures are named
    ``__<module>_MOD_<name>`` by gfortran)."""
    m = MODULE.match(symbol)
    mod = m.group(1) if m else ""
    if (
        "fftw" in dso
        or mod == "common_anderson"
        or (mod.startswith("contact_") and (bem or mod != "contact_fastsim"))
    ):
        return "BEM kernels" if bem else "contact kernels"
    if mod == "contact_fastsim":
        return "creep (FASTSIM)"
    if mod == "vehicle_bem":
        return "BEM coupling"
    if mod in ("vehicle_strip", "vehicle_contact"):
        return "strip contact"
    if mod.startswith(("vehicle_modal", "vehicle_ring")):
        return "modal blocks"
    if mod == "vehicle_newmark" or "openblas" in dso:
        return "Newton, LAPACK"
    if "python" in dso:
        return "Python"
    return "other"


def shares(path: str) -> dict[str, float]:
    """Self-time shares (%) of one perf file by area."""
    out = subprocess.run(
        ["perf", "report", "-i", path, "--stdio", "--sort", "dso,symbol", "--no-children", "-q"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    rows = [
        (float(m.group(1)), m.group(2), m.group(3).strip()) for m in map(LINE.match, out.splitlines()) if m
    ]
    bem = any(MODULE.match(s) and MODULE.match(s).group(1) == "vehicle_bem" for _, _, s in rows)
    total: collections.Counter[str] = collections.Counter()
    for p, dso, sym in rows:
        total[group(dso, sym, bem)] += p
    return dict(total)


def main(paths: list[str]) -> None:
    for path in paths:
        s = shares(path)
        parts = ", ".join(f"{k} {v:.1f} %" for k, v in sorted(s.items(), key=lambda kv: -kv[1]))
        print(f"{path}: {parts}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: perf_shares.py PERF_DATA [...]")
    main(sys.argv[1:])
