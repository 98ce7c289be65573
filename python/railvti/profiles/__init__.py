"""Wheel and rail profiles: standard generators, file readers and the :class:`Profile` object.

Coordinates are SI metres, y towards the field side, z positive downwards
(see :class:`Profile`).
"""

from __future__ import annotations

from .profile import Profile
from .io import example_path, load, read
from .standard import s1002, s1002_mm, uic60

__all__ = ["Profile", "s1002", "s1002_mm", "uic60", "read", "load", "example_path"]
