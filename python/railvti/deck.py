"""Input decks: Fortran namelist files of ``&case ... /`` groups, parsed with f90nml, and
CONTACT's wheel-rail decks (``.inp``, read by :mod:`railvti.contact.contact_deck`).

Example::

    &case
        name = 'hertz_circle'
        type = 'normal'
        nx = 64, ny = 64, dx = 1.0e-4, dy = 1.0e-4
        gap = 'hertz', gap_a = 1.087, gap_b = 1.087
        fn = 1.0e4
    /

Every group must be ``&case``; its ``type`` selects a registered case type
(:mod:`railvti.casetypes`) whose keys it may use. The whole deck is checked
before any case runs.
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import f90nml

from .casetypes import REQUIRED, CaseType
from .deck_registry import case_types
from .errors import InputError


@dataclass(frozen=True)
class Case:
    """One checked case of a deck.

    Attributes
    ----------
    index : int
        Position in the deck, from 1.
    name : str
    case_type : CaseType
    params : dict
        Every key of the case type, the deck's value or the default.
    """

    index: int
    name: str
    case_type: CaseType
    params: dict[str, Any]

    @property
    def label(self) -> str:
        """``case N 'name'`` for messages."""
        return f"case {self.index} '{self.name}'"


def _suggest(key: str, known: list[str]) -> str:
    close = difflib.get_close_matches(key, known, n=1, cutoff=0.5)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _check_group(index: int, group: dict[str, Any], types: dict[str, CaseType]) -> Case:
    where = f"case {index}"
    group = dict(group)
    if "type" not in group or group["type"] is None:
        raise InputError(f"{where}: missing key 'type' (one of {sorted(types)})")
    tname = str(group.pop("type")).strip().lower()
    if tname not in types:
        raise InputError(f"{where}: unknown type '{tname}'{_suggest(tname, sorted(types))}; "
                         f"known types: {', '.join(sorted(types))}")
    ctype = types[tname]
    name = str(group.pop("name", None) or f"{tname}_{index}")
    where = f"case {index} '{name}'"
    known = sorted(ctype.defaults)
    for key, value in group.items():
        if key not in ctype.defaults:
            raise InputError(f"{where}: unknown key '{key}' for type '{tname}'{_suggest(key, known)}")
        if value is None:
            raise InputError(f"{where}: key '{key}' has no value")
    params = {}
    for key, default in ctype.defaults.items():
        if key in group:
            params[key] = group[key]
        elif default is REQUIRED:
            raise InputError(f"{where}: missing value for required key '{key}'")
        else:
            params[key] = default
    return Case(index=index, name=name, case_type=ctype, params=params)


def parse_deck(text: str) -> list[Case]:
    """Parse and check the text of a deck.

    Raises
    ------
    InputError
        A syntax error, a group other than ``&case``, an unknown type or key,
        a key without a value or a missing required key (each named).
    """
    try:
        nml = f90nml.reads(text)
    except Exception as exc:  # f90nml raises ValueError and others on syntax errors
        raise InputError(f"deck is not a valid Fortran namelist: {exc}") from None
    groups: list[dict[str, Any]] = []
    for gname in dict.fromkeys(str(k) for k in nml.keys()):  # cogroup keys print as the name
        if gname != "case":
            raise InputError(f"unknown namelist group '&{gname}': a deck holds only '&case' groups")
        value = nml[gname]
        groups.extend(value if isinstance(value, list) else [value])
    if not groups:
        raise InputError("deck holds no '&case' group")
    types = case_types()
    return [_check_group(i + 1, g, types) for i, g in enumerate(groups)]


def read_deck(path: str | Path) -> list[Case]:
    """Read and check a deck file: a namelist deck (see :func:`parse_deck`), or a CONTACT
    wheel-rail deck if its name ends in ``.inp`` (:func:`railvti.contact.contact_deck.read_contact_deck`)."""
    path = Path(path)
    if path.suffix.lower() == ".inp":
        from .contact.contact_deck import read_contact_deck
        return read_contact_deck(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(f"cannot read deck {path}: {exc.strerror}") from None
    return parse_deck(text)
