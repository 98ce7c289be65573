"""Collects the deck case types of every area into casetypes.REGISTRY."""
from __future__ import annotations

import importlib

from ..casetypes import REGISTRY, CaseType

# Each area's module registers its case types when imported.
_AREAS = (
    "railvti.contact.cases",
    "railvti.contact.wheelset_cases",
    "railvti.contact.wheel_rail_cases",
    "railvti.geometry.cases",
    "railvti.track.cases",
    "railvti.wheelset.cases",
    "railvti.vehicle.cases",
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
