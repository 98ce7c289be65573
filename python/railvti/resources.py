"""Memory the machine has, and the limit a run must stay under (``RAILVTI_MAX_MEMORY``)."""

from __future__ import annotations

import os
import re

from .errors import InputError

#: Environment variable holding the memory limit of a run: bytes, or a size such as '8G',
#: '500M', or 'none' for no limit. ``railvti run --max-memory`` sets it.
ENV = "RAILVTI_MAX_MEMORY"

#: Share of the available memory a run may use when no limit is given.
DEFAULT_SHARE = 0.8

_SUFFIX = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}


def parse_size(text: str) -> float:
    """Bytes of a size such as '8G', '512M', '1.5e9' or 'none' (inf)."""
    t = str(text).strip().upper().removesuffix("B").removesuffix("I")
    if t in ("NONE", "INF"):
        return float("inf")
    m = re.fullmatch(r"([0-9.eE+-]+)\s*([KMGT]?)", t)
    try:
        value = float(m.group(1)) * _SUFFIX[m.group(2)] if m else float("nan")
    except ValueError:
        value = float("nan")
    if not 0 < value < float("inf"):  # 1e400 is no size: 'none' says no limit
        raise InputError(f"memory size {text!r} is not a size such as 8G, 500M, 1e9 or none")
    return value


def available_memory() -> float:
    """Bytes of memory available to new work (MemAvailable of /proc/meminfo; inf if unknown)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    return float("inf")


def memory_limit() -> float:
    """The memory limit of a run, bytes: ``RAILVTI_MAX_MEMORY`` if set, else
    :data:`DEFAULT_SHARE` of the available memory."""
    text = os.environ.get(ENV, "").strip()
    if text:
        try:
            return parse_size(text)
        except InputError as exc:
            raise InputError(
                f"environment variable {ENV} = {text!r} (set by 'railvti run "
                f"--max-memory' or the shell): {exc}"
            ) from None
    return DEFAULT_SHARE * available_memory()


def size_text(nbytes: float) -> str:
    """'1.2 GB' for a number of bytes."""
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if nbytes >= scale:
            return f"{nbytes / scale:.3g} {unit}"
    return f"{nbytes:.0f} B"


def check_memory(what: str, nbytes: float, hint: str = "") -> None:
    """InputError when ``what`` would need more than :func:`memory_limit` bytes."""
    limit = memory_limit()
    if nbytes > limit:
        source = (
            f"{ENV}={os.environ[ENV]}"
            if os.environ.get(ENV, "").strip()
            else f"{DEFAULT_SHARE:.0%} of the {size_text(available_memory())} available"
        )
        raise InputError(
            f"{what} would need about {size_text(nbytes)} of memory, more than the "
            f"limit of {size_text(limit)} ({source}){'; ' + hint if hint else ''}; "
            f"raise the limit with {ENV} or 'railvti run --max-memory SIZE'"
        )


__all__ = [
    "ENV",
    "DEFAULT_SHARE",
    "parse_size",
    "available_memory",
    "memory_limit",
    "size_text",
    "check_memory",
]
