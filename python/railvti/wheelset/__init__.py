"""Flexible rotating wheelset: axisymmetric finite elements with circumferential
harmonics, modes per harmonic, axle-fixed modal coordinates and the gyroscopic
frequency response (Kaiser, chapter 2)."""

from __future__ import annotations

from .fe import HarmonicModes, solve_harmonic
from .flexible import FlexibleWheelset
from .geometry import WheelsetGeometry
from .mesh import Block, MeridianMesh, mesh_blocks, rectangle_mesh
from .model import AxleFixedModel, ModeTable, PrimarySuspension, Wheelset

__all__ = [
    "Wheelset",
    "FlexibleWheelset",
    "WheelsetGeometry",
    "PrimarySuspension",
    "ModeTable",
    "AxleFixedModel",
    "HarmonicModes",
    "solve_harmonic",
    "Block",
    "MeridianMesh",
    "mesh_blocks",
    "rectangle_mesh",
]
