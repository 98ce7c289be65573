"""Collects the deck case types of every area into casetypes.REGISTRY (and the readers of
other deck formats into casetypes.DECK_READERS)."""

from __future__ import annotations

import importlib

from typing import Callable
from pathlib import Path

from ..casetypes import DECK_READERS, REGISTRY, Case, CaseType

# Each area's module registers its case types when imported.
_AREAS = (
    "railvti.contact.cases",
    "railvti.contact.dissimilar_cases",
    "railvti.contact.wheelset_cases",
    "railvti.contact.wheel_rail_cases",
    "railvti.contact.contact_deck",
    "railvti.contact.transient_cases",
    "railvti.contact.viscoelastic_cases",
    "railvti.contact.subsurface_cases",
    "railvti.geometry.cases",
    "railvti.track.cases",
    "railvti.wheelset.cases",
    "railvti.vehicle.cases",
    "railvti.vehicle.line_case",
)


def case_types() -> dict[str, CaseType]:
    """Import every area present and return the registry (type name -> CaseType)."""
    for name in _AREAS:
        try:
            importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name is None or not name.startswith(exc.name):
                raise
    return REGISTRY


def deck_readers() -> dict[str, Callable[[Path], list[Case]]]:
    """Import every area present and return the readers of other deck formats (suffix ->
    reader)."""
    case_types()
    return DECK_READERS


__all__ = ["case_types", "deck_readers"]
