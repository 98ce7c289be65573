"""Exceptions raised by railvti.

Every failure a user can cause or meet is one of these; the Fortran core
reports problems as named status codes (fortran/common/common_status.f90) that
``railvti._status`` maps to these classes, in one place.
"""

from __future__ import annotations


class RailvtiError(Exception):
    """Base class of all railvti errors."""


class InputError(RailvtiError, ValueError):
    """Bad input: a value out of range, a NaN, a deck with an unknown key."""


class GridTooSmallError(InputError):
    """The contact area reaches the edge of the potential contact grid."""


class NoContactError(InputError):
    """The bodies do not touch for the given approach or position."""


class ConvergenceError(RailvtiError, RuntimeError):
    """An iterative solver stopped before reaching its tolerance.

    Attributes
    ----------
    iterations : int
        Iterations done.
    residual : float
        Relative residual reached.
    result : object or None
        The unconverged result, for inspection.
    """

    def __init__(
        self, message: str, iterations: int = 0, residual: float = float("nan"), result: object | None = None
    ) -> None:
        super().__init__(message)
        self.iterations = iterations
        self.residual = residual
        self.result = result


class DivergenceError(ConvergenceError):
    """The time integration diverged (Newton failed, NaN, or a wheelset left its table)."""


class AliasingWarning(UserWarning):
    """An output interval too coarse for a known periodic excitation of the run (the
    sleeper passing, hunting): the stored history shows it at a false frequency
    (railvti.vehicle.output)."""


__all__ = [
    "RailvtiError",
    "InputError",
    "GridTooSmallError",
    "NoContactError",
    "ConvergenceError",
    "DivergenceError",
    "AliasingWarning",
]
