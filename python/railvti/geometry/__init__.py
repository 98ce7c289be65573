"""Wheel-rail contact geometry: rigid wheelset on rigid rails, contact table, gap fields, creepages.

Track frame: x forward, y to the left, z up. See :mod:`railvti.geometry.table`.
"""
from __future__ import annotations

from ._setup import Layout, Track, WheelsetGeometry, layout
from .table import (FLANGE_CLIMB, NO_CONTACT, OK, STATUS_NAMES, ContactPoint, ContactTable,
                    WheelsetContact, WheelsetPose, contact_points, contact_table)

__all__ = ["Track", "WheelsetGeometry", "Layout", "layout", "ContactPoint", "ContactTable",
           "WheelsetContact", "WheelsetPose", "contact_points", "contact_table",
           "OK", "NO_CONTACT", "FLANGE_CLIMB", "STATUS_NAMES"]
from .field import Creepages, GapField, creepages, gap_field  # noqa: E402
from .conicity import equivalent_conicity, klingel_wavelength  # noqa: E402

__all__ += ["GapField", "Creepages", "gap_field", "creepages", "equivalent_conicity",
            "klingel_wavelength"]
