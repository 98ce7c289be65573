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


#: The module registering the reader of each other deck format, by its suffix: a deck of that
#: format imports its reader's area only (a CONTACT deck not the vehicle's, track's and
#: assessment's modules: ~0.1 s of every run of a CONTACT deck, issue 33).
_READERS = {".inp": "railvti.contact.contact_deck"}


def _import_area(name: str) -> None:
    try:
        importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name is None or not name.startswith(exc.name):
            raise


def case_types() -> dict[str, CaseType]:
    """Import every area present and return the registry (type name -> CaseType)."""
    for name in _AREAS:
        _import_area(name)
    return REGISTRY


def deck_readers(suffix: str | None = None) -> dict[str, Callable[[Path], list[Case]]]:
    """Return the readers of other deck formats (suffix -> reader): with ``suffix`` one of
    :data:`_READERS`, after importing that reader's module only, else after importing every
    area present."""
    module = _READERS.get(suffix.lower()) if suffix else None
    if module is not None:
        _import_area(module)
    if module is None or suffix.lower() not in DECK_READERS:
        case_types()
    return DECK_READERS


__all__ = ["case_types", "deck_readers"]
