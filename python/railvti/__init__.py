"""railvti: railway vehicle-track interaction.

A Fortran numerical core (boundary-element wheel-rail contact, flexible track
and wheelsets, time integration) with a Python front end. SI units throughout.
"""

from __future__ import annotations

from typing import Any

from . import errors
from .errors import ConvergenceError, GridTooSmallError, InputError, NoContactError, RailvtiError

__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    """``Material`` and ``STEEL`` on first use (PEP 562): ``import railvti.runner.cli`` then loads no
    numpy, so the ``railvti`` command installs its signal handlers within ~0.05 s of its start."""
    if name in ("Material", "STEEL"):
        from . import material

        return getattr(material, name)
    raise AttributeError(f"module 'railvti' has no attribute {name!r}")


__all__ = [
    "Material",
    "STEEL",
    "errors",
    "RailvtiError",
    "InputError",
    "GridTooSmallError",
    "NoContactError",
    "ConvergenceError",
    "__version__",
]
