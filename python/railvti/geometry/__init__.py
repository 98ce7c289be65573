"""Wheel-rail contact geometry: rigid wheelset on rigid rails, geometry table, gap fields, creepages.

Track frame: x forward, y to the left, z up (:mod:`railvti.geometry.frames`). The wheelset is
a :class:`railvti.wheelset.WheelsetGeometry`; the rails stand as a :class:`TrackLayout` says.
See :mod:`railvti.geometry.table` for the method.
"""

from __future__ import annotations

from .placement import ProfileLayout, TrackLayout, layout
from .table import (
    FLANGE_CLIMB,
    NO_CONTACT,
    OK,
    STATUS_NAMES,
    ContactPoint,
    GeometryTable,
    WheelsetContact,
    WheelsetPose,
    contact_points,
    geometry_table,
)
from .field import Creepages, GapField, creepages, gap_field
from .conicity import conicity_of_delta_r, equivalent_conicity, klingel_wavelength

__all__ = [
    "TrackLayout",
    "ProfileLayout",
    "layout",
    "ContactPoint",
    "GeometryTable",
    "WheelsetContact",
    "WheelsetPose",
    "contact_points",
    "geometry_table",
    "OK",
    "NO_CONTACT",
    "FLANGE_CLIMB",
    "STATUS_NAMES",
    "GapField",
    "Creepages",
    "gap_field",
    "creepages",
    "conicity_of_delta_r",
    "equivalent_conicity",
    "klingel_wavelength",
]
