"""Flexible rotating wheelset: axisymmetric finite elements with circumferential
harmonics, modes per harmonic, axle-fixed modal coordinates and the gyroscopic
frequency response (Kaiser, chapter 2)."""
from __future__ import annotations

from .fe import HarmonicModes, solve_harmonic
from .mesh import Block, MeridianMesh, mesh_blocks, rectangle_mesh

__all__ = ["HarmonicModes", "solve_harmonic", "Block", "MeridianMesh", "mesh_blocks",
           "rectangle_mesh"]
