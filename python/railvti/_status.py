"""The one translator of Fortran status codes into railvti exceptions.

The codes, their names and messages are defined once, in
``fortran/common/common_status.f90``; this module reads them from the compiled core
(``status_describe_c``) and maps each to an exception class. No other module compares
an ``info`` value with a number: they call :func:`check` or compare with :class:`Status`.
"""

from __future__ import annotations

import enum
from functools import lru_cache

from ._native import core
from .errors import (
    ConvergenceError,
    DivergenceError,
    GridTooSmallError,
    InputError,
    NoContactError,
    RailvtiError,
)


class Status(enum.IntEnum):
    """Status codes of the Fortran kernels (mirror of common_status; a test keeps them equal)."""

    OK = 0
    NOT_CONVERGED = 1
    NO_CONTACT = 2
    BAD_ARGUMENT = 3
    BAD_HANDLE = 4
    SIZE_MISMATCH = 5
    NO_MEMORY = 6
    FFTW_PLAN = 7
    SINGULAR = 8
    NOT_POSITIVE_DEFINITE = 9
    LAPACK = 10
    EIGEN_FAILED = 11
    NOT_FINITE = 12
    DIVERGED = 13
    GRID_EDGE = 14
    OUTSIDE_TABLE = 15
    BAD_ELEMENT = 16
    MOTION_TOO_LARGE = 17
    CONTACT_NOT_CONVERGED = 18


#: The exception raised for each failing code.
EXCEPTIONS: dict[Status, type[RailvtiError]] = {
    Status.NOT_CONVERGED: ConvergenceError,
    Status.NO_CONTACT: NoContactError,
    Status.BAD_ARGUMENT: InputError,
    Status.BAD_HANDLE: InputError,
    Status.SIZE_MISMATCH: InputError,
    Status.NO_MEMORY: RailvtiError,
    Status.FFTW_PLAN: RailvtiError,
    Status.SINGULAR: ConvergenceError,
    Status.NOT_POSITIVE_DEFINITE: ConvergenceError,
    Status.LAPACK: ConvergenceError,
    Status.EIGEN_FAILED: ConvergenceError,
    Status.NOT_FINITE: ConvergenceError,
    Status.DIVERGED: ConvergenceError,
    Status.GRID_EDGE: GridTooSmallError,
    Status.OUTSIDE_TABLE: DivergenceError,
    Status.BAD_ELEMENT: InputError,
    Status.MOTION_TOO_LARGE: DivergenceError,
    Status.CONTACT_NOT_CONVERGED: DivergenceError,
}


@lru_cache(maxsize=None)
def describe(code: int) -> tuple[str, str]:
    """Name and message of a status code, as the Fortran core defines them."""
    name, msg, _ = core.status_describe_c(int(code))
    return _text(name), _text(msg)


def last_code() -> int:
    """The largest status code the Fortran core defines."""
    return int(core.status_describe_c(0)[2])


def _text(raw: object) -> str:
    if isinstance(raw, (bytes, bytearray)):
        raw = raw.decode("ascii", "replace")
    elif hasattr(raw, "tobytes"):  # numpy 0-d character array
        raw = raw.tobytes().decode("ascii", "replace")
    return str(raw).strip().strip("\x00").strip()


def error(info: int, context: str, *, exc: type[RailvtiError] | None = None, **attrs: object) -> RailvtiError:
    """The exception for a failing status: ``context`` says what failed, the message why.

    Parameters
    ----------
    info : int
        Status code returned by a shim.
    context : str
        What was being done, e.g. ``"normal contact"`` or ``"ring group 3"``.
    exc : type, optional
        Override the class chosen from :data:`EXCEPTIONS` (e.g. a subclass for the caller).
    **attrs
        Passed to ConvergenceError subclasses (``iterations``, ``residual``, ``result``).
    """
    try:
        code = Status(int(info))
    except ValueError:
        return RailvtiError(f"{context}: unknown status code {int(info)} from the Fortran core")
    name, msg = describe(code)
    cls = exc or EXCEPTIONS.get(code, RailvtiError)
    text = f"{context}: {msg} [{name}]"
    if issubclass(cls, ConvergenceError):
        return cls(text, **attrs)  # type: ignore[arg-type]
    return cls(text)


def check(info: int, context: str, **attrs: object) -> None:
    """Raise the exception for ``info`` unless it is :attr:`Status.OK`."""
    if int(info) != Status.OK:
        raise error(info, context, **attrs)
