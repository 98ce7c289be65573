"""Wheel-rail contact: the boundary-element (half-space) model on a regular grid, with
Hertz, Kalker's linear theory and FASTSIM beside it, and the loaded wheelset."""

from __future__ import annotations

from .grid import Grid
from .hertz import HertzResult, hertz, hertz_gap
from .influence import convolve, convolve_field, influence_field
from .normal import NormalResult, SubPatches, solve_normal
from .rolling import RollingResult, solve_rolling, solve_tangential
from .creep_table import CreepForceTable, creep_force_table
from .kalker import kalker_coefficients
from .fastsim import FastsimResult, fastsim, fastsim_grid
from .wheelset import WheelsetPatch, WheelsetSolution, solve_wheelset
from .transient import TransientResult, shift_problem, solve_transient, transient_rolling
from .dissimilar import (
    BodyPair,
    CompressionResult,
    DissimilarRollingResult,
    solve_dissimilar_rolling,
    solve_progressive_compression,
)
from .viscoelastic import (
    ViscoelasticLineResult,
    ViscoelasticMaterial,
    ViscoelasticResult,
    solve_viscoelastic,
    solve_viscoelastic_line,
)
from .viscoelastic_rolling import ViscoelasticRollingResult, solve_viscoelastic_rolling
from .subsurface import SubsurfaceResult, subsurface_stress, subsurface_stress_fields

__all__ = [
    "Grid",
    "HertzResult",
    "hertz",
    "hertz_gap",
    "convolve",
    "convolve_field",
    "influence_field",
    "NormalResult",
    "SubPatches",
    "solve_normal",
    "RollingResult",
    "solve_rolling",
    "solve_tangential",
    "CreepForceTable",
    "creep_force_table",
    "kalker_coefficients",
    "FastsimResult",
    "fastsim",
    "fastsim_grid",
    "WheelsetPatch",
    "WheelsetSolution",
    "solve_wheelset",
    "TransientResult",
    "shift_problem",
    "solve_transient",
    "transient_rolling",
    "BodyPair",
    "CompressionResult",
    "DissimilarRollingResult",
    "solve_dissimilar_rolling",
    "solve_progressive_compression",
    "ViscoelasticMaterial",
    "ViscoelasticLineResult",
    "ViscoelasticResult",
    "solve_viscoelastic",
    "solve_viscoelastic_line",
    "ViscoelasticRollingResult",
    "solve_viscoelastic_rolling",
    "SubsurfaceResult",
    "subsurface_stress",
    "subsurface_stress_fields",
]
