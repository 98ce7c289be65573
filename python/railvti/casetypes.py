"""The contract between the input-deck runner and each capability.

A deck is a Fortran namelist file of ``&case ... /`` groups. Each group has a
``type`` key naming a :class:`CaseType`; the runner checks the group's keys
against the type's ``defaults`` (unknown key or missing required value ->
InputError), calls ``run`` with the completed parameters, and writes the
returned :class:`CaseOutput` to HDF5. ``plot``, if given, draws a stored case.

Each area registers its case types in :data:`REGISTRY` through
:func:`register` (see ``railvti.deck_registry``).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


#: Marks a key in ``CaseType.defaults`` that the deck must give.
REQUIRED: Any = _Required()


@dataclass
class CaseOutput:
    """What one case returns to the runner.

    Attributes
    ----------
    summary : str
        One line for the console.
    datasets : dict
        name -> (array, unit string); written as HDF5 datasets with a ``units`` attribute.
    scalars : dict
        name -> (value, unit string); written as attributes of the case's ``results`` group.
    attrs : dict
        dataset name -> {attribute: value}: labels written beside ``units`` (``axes``,
        ``dof_names``, ``empty_slots``...; see railvti.results).
    """

    summary: str
    datasets: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)
    scalars: dict[str, tuple[float | int | str, str]] = field(default_factory=dict)
    attrs: dict[str, dict[str, Any]] = field(default_factory=dict)


@dataclass(frozen=True)
class CaseType:
    """One kind of deck case.

    Attributes
    ----------
    name : str
        The value of the deck's ``type`` key.
    defaults : dict
        Every allowed key (besides ``type`` and ``name``) and its default;
        :data:`REQUIRED` for keys that must be given. Units in the docstring of ``run``.
    run : callable
        ``run(params: dict) -> CaseOutput``. Raises railvti errors on bad input.
    plot : callable or None
        ``plot(group: h5py.Group, outdir: Path, stem: str) -> list[Path]``.
    """

    name: str
    defaults: dict[str, Any]
    run: Callable[[dict[str, Any]], CaseOutput]
    plot: Callable[[Any, Path, str], list[Path]] | None = None


REGISTRY: dict[str, CaseType] = {}


def register(case_type: CaseType) -> CaseType:
    """Add a case type to the registry (its name must be new)."""
    if case_type.name in REGISTRY:
        raise ValueError(f"case type {case_type.name!r} registered twice")
    REGISTRY[case_type.name] = case_type
    return case_type
