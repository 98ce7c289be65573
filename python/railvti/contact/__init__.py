"""Wheel-rail contact: the boundary-element (half-space) model on a regular grid,
Hertz's solution beside it."""
from __future__ import annotations

from .grid import Grid
from .hertz import HertzResult, hertz, hertz_gap
from .influence import convolve, influence_field
from .normal import NormalResult, solve_normal
from .rolling import RollingResult, solve_rolling, solve_tangential

__all__ = ["Grid", "HertzResult", "hertz", "hertz_gap", "convolve", "influence_field",
           "NormalResult", "solve_normal",
           "RollingResult", "solve_rolling", "solve_tangential"]
