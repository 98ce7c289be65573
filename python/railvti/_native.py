"""The compiled Fortran core. Only railvti's own modules import this."""

from __future__ import annotations

try:
    from . import _core as core  # noqa: F401
except ImportError as exc:  # pragma: no cover - a broken install
    raise ImportError(
        "railvti's compiled core (railvti._core) is missing: build and install the "
        "package with `./dev.sh test` or `pip install .` from the source tree"
    ) from exc
