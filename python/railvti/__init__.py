"""railvti: railway vehicle-track interaction.

A Fortran numerical core (boundary-element wheel-rail contact, flexible track
and wheelsets, time integration) with a Python front end. SI units throughout.
"""
from __future__ import annotations

from . import errors
from .errors import ConvergenceError, GridTooSmallError, InputError, NoContactError, RailvtiError
from .material import STEEL, Material

__version__ = "0.1.0"

__all__ = [
    "Material", "STEEL", "errors", "RailvtiError", "InputError", "GridTooSmallError",
    "NoContactError", "ConvergenceError", "__version__",
]
