"""The contract between the input-deck runner and each capability.

A deck is a Fortran namelist file of ``&case ... /`` groups. Each group has a
``type`` key naming a :class:`CaseType`; the runner checks the group's keys
against the type's ``defaults`` (unknown key or missing required value ->
InputError), calls ``run`` with the completed parameters, and writes the
returned :class:`CaseOutput` to HDF5. ``plot``, if given, draws a stored case.

Each area registers its case types in :data:`REGISTRY` through
:func:`register` (see ``railvti.runner.deck_registry``).
"""

from __future__ import annotations

import contextlib
import contextvars
import logging
import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator, Protocol, runtime_checkable

import numpy as np

from .errors import InputError

__all__ = [
    "REQUIRED",
    "Streamed",
    "CaseOutput",
    "Key",
    "Alias",
    "CaseType",
    "as_written",
    "REGISTRY",
    "validate",
    "register",
    "split_labels",
    "MAX_NAME",
    "Case",
    "name_problem",
    "DECK_READERS",
    "register_deck_reader",
    "STREAM_TAIL_SECONDS",
    "ROW_BYTES",
    "history_bytes",
    "HistorySink",
    "offering_sinks",
    "case_sink",
]

log = logging.getLogger("railvti")


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


#: Marks a key in ``CaseType.defaults`` that the deck must give.
REQUIRED: Any = _Required()


@dataclass(frozen=True)
class Streamed:
    """A dataset a case streamed to a file while it ran (railvti.runner.stream): ``name`` (its HDF5
    path) in the file ``path``; copied into the case's group when the case is written."""

    path: str
    name: str


@dataclass
class CaseOutput:
    """What one case returns to the runner.

    Attributes
    ----------
    summary : str
        One line for the console.
    datasets : dict
        name -> (array, unit string); written as HDF5 datasets with a ``units`` attribute.
        The array may be a :class:`Streamed` reference (a history streamed to a file).
    scalars : dict
        name -> (value, unit string); written as attributes of the case's ``results`` group.
    attrs : dict
        dataset name -> {attribute: value}: labels written beside ``units`` (``axes``,
        ``dof_names``, ``empty_slots``...; see railvti.runner.results).
    """

    summary: str
    datasets: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)
    scalars: dict[str, tuple[float | int | str, str]] = field(default_factory=dict)
    attrs: dict[str, dict[str, Any]] = field(default_factory=dict)


@dataclass(frozen=True)
class Key:
    """What a deck key means and which values it takes (checked before any case runs).

    Attributes
    ----------
    unit : str
        SI unit ('1' for a number without unit, '' for text and flags).
    meaning : str
        One line for ``railvti cases``.
    kind : {'float', 'int', 'str', 'flag', 'floats'}
        A real number, an integer, a text, 0 or 1, or one or more reals.
    lo, hi : float or None
        Bounds of a number (each element of 'floats'); ``lo_open``/``hi_open`` exclude them.
    choices : tuple of str
        The allowed texts of a 'str' key (compared without case); empty: any text.
    optional : bool
        ``None`` (the key left out) is allowed.
    why : str
        Why a plausibility bound is where it is (said in the error message).
    """

    unit: str
    meaning: str
    kind: str = "float"
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple[str, ...] = ()
    optional: bool = False
    why: str = ""

    def bounds(self) -> str:
        """The allowed range as text, e.g. '0 < mu <= 1' is '(0, 1]' here, with the unit."""
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind == "flag":
            return "0 or 1"
        if self.lo is None and self.hi is None:
            return ""
        lo = "-inf" if self.lo is None else f"{self.lo:g}"
        hi = "inf" if self.hi is None else f"{self.hi:g}"
        unit = f" {self.unit}" if self.unit not in ("", "1", "-") else ""
        left = "(" if self.lo_open or self.lo is None else "["
        right = ")" if self.hi_open or self.hi is None else "]"
        return f"{left}{lo}, {hi}{right}{unit}"

    def choice(self, value: str) -> str | None:
        """The allowed choice that ``value`` names (without regard to case and spaces), or None."""
        folded = {c.lower(): c for c in self.choices}
        return folded.get(value.strip().lower())

    def problem(self, name: str, value: Any) -> str | None:
        """Why ``value`` is not allowed for key ``name`` (a message naming key and bound), or None."""
        if value is None:
            return None if self.optional else f"key '{name}' needs a value"
        if self.kind == "str":
            if not isinstance(value, str):
                return f"key '{name}' must be a text in quotes, got {value!r}"
            if self.choices and self.choice(value) is None:
                return f"key '{name}' = {value!r} must be {self.bounds()}"
            return None
        if self.kind == "floats":
            values = value if isinstance(value, (list, tuple)) else [value]
            if not values:
                return f"key '{name}' needs at least one value"
            for v in values:
                msg = self._number(name, v, integer=False)
                if msg:
                    return msg
            return None
        return self._number(name, value, integer=self.kind in ("int", "flag"))

    def _number(self, name: str, value: Any, integer: bool) -> str | None:
        kind = "an integer" if integer else "a number"
        if self.kind == "flag":
            kind = "0 or 1"
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            return f"key '{name}' must be {kind}, got {value!r}"
        v = float(value)
        if not math.isfinite(v):
            return f"key '{name}' must be finite, got {v}"
        if integer and not v.is_integer():
            return f"key '{name}' must be {kind}, got {value!r}"
        if self.kind == "flag" and v not in (0.0, 1.0):
            return f"key '{name}' must be 0 or 1, got {value!r}"
        bad = (self.lo is not None and (v < self.lo or (self.lo_open and v == self.lo))) or (
            self.hi is not None and (v > self.hi or (self.hi_open and v == self.hi))
        )
        if bad:
            why = f" ({self.why})" if self.why else ""
            return f"key '{name}' = {value!r} is outside {self.bounds()}{why}"
        return None


@dataclass(frozen=True)
class Alias:
    """Another name of a key: an old name (``deprecated``), or the same quantity in another
    unit named by ``unit``: a value times ``factor`` divided by ``divisor`` is in the key's
    unit (``factor`` 1e-3 from mm to m; ``divisor`` 3.6 from km/h to m/s, so that 300 km/h
    is 300 / 3.6 m/s exactly as the Python API's ``speed_kmh=`` gives it). Aliases are
    resolved when a deck is read; the case's parameters hold the key."""

    key: str
    factor: float = 1.0
    deprecated: bool = True
    unit: str = ""
    divisor: float = 1.0

    @property
    def scale(self) -> float:
        """The key's unit per the alias's (0.277778 for km/h to m/s), for listings."""
        return self.factor / self.divisor

    @property
    def converts(self) -> bool:
        """Whether the alias is in another unit than its key."""
        return self.factor != 1.0 or self.divisor != 1.0

    def to_key(self, value: Any) -> float:
        """A number given under the alias, in the key's unit."""
        return float(value) * self.factor / self.divisor


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
    keys : dict
        key -> :class:`Key`: unit, meaning and allowed values of each key of ``defaults``.
    check : callable or None
        ``check(params) -> list[str]``: consistency and plausibility between keys, run after
        every key passed its own check; each message names the keys and the bound.
    aliases : dict
        Other accepted names of keys (old names, unit-suffixed variants): name -> :class:`Alias`.
    summary : str
        One line for ``railvti cases``.
    """

    name: str
    defaults: dict[str, Any]
    run: Callable[[dict[str, Any]], CaseOutput]
    plot: Callable[[Any, Path, str], list[Path]] | None = None
    keys: dict[str, Key] = field(default_factory=dict)
    check: Callable[[dict[str, Any]], list[str]] | None = None
    aliases: dict[str, Alias] = field(default_factory=dict)
    summary: str = ""

    def problems(
        self, params: dict[str, Any], written: dict[str, tuple[str, Any]] | None = None
    ) -> list[str]:
        """Every problem of a case's complete parameters: each key's type and range, then
        the case type's consistency check. Empty if the case may run.

        ``written`` (:meth:`aliases_written`): the keys the case gave under an alias; a
        problem of such a key names the alias and the value as written (``y_min_mm = 4``),
        not only the converted key."""
        out = self._problems(params)
        if not written:
            return out
        units = {k: self.keys[k].unit for k in written if k in self.keys}
        return [as_written(m, written, units) for m in out]

    def aliases_written(self, given: dict[str, Any]) -> dict[str, tuple[str, Any]]:
        """key -> (alias, value as written) for the keys ``given`` names by an alias."""
        return {self.aliases[k].key: (k, v) for k, v in given.items() if k in self.aliases}

    def _problems(self, params: dict[str, Any]) -> list[str]:
        out = []
        for name, value in params.items():
            spec = self.keys.get(name)
            if spec is None:
                if name not in self.defaults:
                    out.append(f"unknown key '{name}'")
                    continue
                spec = _implicit_key(self.defaults[name])
                if spec is None:
                    continue
            msg = spec.problem(name, value)
            if msg:
                out.append(msg)
        for name, default in self.defaults.items():
            if name not in params and default is REQUIRED:
                out.append(f"missing value for required key '{name}'")
        if not out and self.check is not None:
            out.extend(self.check(params))
        return out

    def resolve_aliases(self, given: dict[str, Any]) -> tuple[dict[str, Any], list[str]]:
        """Rename aliased keys of ``given`` (converting suffixed units); return the new dict
        and the problems (a key given under two names). Deprecated names log a warning."""
        out: dict[str, Any] = {}
        problems = []
        for name, value in given.items():
            alias = self.aliases.get(name)
            if alias is None:
                if name in out:
                    problems.append(f"key '{name}' is given twice (also as an alias)")
                out[name] = value
                continue
            if alias.key in given or alias.key in out:
                problems.append(f"key '{name}' and key '{alias.key}' name the same quantity: give one")
                continue
            if alias.deprecated:
                msg = f"deck key '{name}' of type '{self.name}' is deprecated: use '{alias.key}'" + (
                    f" (unit {self.keys[alias.key].unit})" if alias.key in self.keys else ""
                )
                warnings.warn(msg, DeprecationWarning, stacklevel=3)
                log.warning(msg)
            if alias.converts and value is not None:
                try:
                    value = (
                        [alias.to_key(v) for v in value]
                        if isinstance(value, (list, tuple))
                        else alias.to_key(value)
                    )
                except (TypeError, ValueError):
                    problems.append(f"key '{name}' must be a number, got {value!r}")
                    continue
            out[alias.key] = value
        return out, problems

    def validate(self, params: dict[str, Any]) -> dict[str, Any]:
        """Check a case's parameters for the Python API and return them with aliases resolved.

        An alias beside its key's default value replaces it (``dict(defaults)`` updated with
        ``speed_kmh=200`` means 200 km/h); beside another value it is a conflict.

        Raises
        ------
        InputError
            Every problem, listed in one message.
        """
        params = dict(params)
        problems = []
        written = self.aliases_written(params)
        for name in [k for k in params if k in self.aliases]:
            target = self.aliases[name].key
            if target in params and params[target] == self.defaults.get(target, object()):
                del params[target]
            given, probs = self.resolve_aliases(
                {name: params.pop(name), **({target: params[target]} if target in params else {})}
            )
            problems += probs
            params.update(given)
        problems += self.problems(params, written)
        if problems:
            raise InputError(f"{self.name} case: " + "; ".join(problems))
        return params


def as_written(message: str, written: dict[str, tuple[str, Any]], units: dict[str, str] | None = None) -> str:
    """``message`` naming the keys a case gave under an alias as the case wrote them:
    ``key 'y_max' = 0.08`` becomes ``key 'y_max_mm' = 80.0 (y_max = 0.08 m)`` (``units``:
    key -> unit), and a message that names such a key otherwise (a consistency check:
    ``y_min = 0.004 must be < y_max = 0.002 (m)``) gets ``(the case gave y_min_mm = 4.0,
    y_max_mm = 2.0)``."""
    named = []
    units = units or {}

    def converted(key: str, text: str) -> str:
        try:
            text = f"{float(text):.6g}"
        except ValueError:
            pass
        unit = units.get(key, "")
        return f"{key} = {text}" + (f" {unit}" if unit and unit not in ("1", "-") else "")

    for key, (alias, value) in written.items():
        pattern = re.compile(rf"key '{re.escape(key)}' = (\S+)")
        message, n = pattern.subn(
            lambda m: f"key '{alias}' = {value!r} ({converted(key, m.group(1))})", message
        )
        if n == 0 and re.search(rf"(?<![\w']){re.escape(key)}(?![\w'])", message):
            named.append(f"{alias} = {value!r}")
    return message + (f" (the case gave {', '.join(named)})" if named else "")


REGISTRY: dict[str, CaseType] = {}


def _implicit_key(default: Any) -> Key | None:
    """The check of a key without a :class:`Key`: its default's type, finite."""
    if isinstance(default, bool) or default is None or default is REQUIRED:
        return None
    if isinstance(default, int):
        return Key("", "", "int")
    if isinstance(default, float):
        return Key("", "", "float")
    if isinstance(default, str):
        return Key("", "", "str")
    if isinstance(default, (list, tuple)):
        return Key("", "", "floats")
    return None


def validate(type_name: str, params: dict[str, Any]) -> dict[str, Any]:
    """Check the parameters of a case of the registered type ``type_name`` and return them
    with aliases resolved (:meth:`CaseType.validate`; raises InputError).

    Case runners call this first, so the Python API refuses what a deck would refuse."""
    ctype = REGISTRY.get(type_name)
    return dict(params) if ctype is None else ctype.validate(params)


def register(case_type: CaseType) -> CaseType:
    """Add a case type to the registry (its name must be new)."""
    if case_type.name in REGISTRY:
        raise ValueError(f"case type {case_type.name!r} registered twice")
    REGISTRY[case_type.name] = case_type
    return case_type


def split_labels(data: dict[str, tuple]) -> tuple[dict[str, tuple], dict[str, dict[str, Any]]]:
    """Split name -> (array, unit[, labels]) into CaseOutput's ``datasets`` (array, unit) and
    ``attrs`` (labels)."""
    return (
        {k: (v[0], v[1]) for k, v in data.items()},
        {k: dict(v[2]) for k, v in data.items() if len(v) > 2 and v[2]},
    )


# ---------------------------------------------------------------------------------------------
# A case: what the runner reads from a deck and hands to a case type

#: Longest case name (it names an HDF5 group and the plot files).
MAX_NAME = 64
_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.+-]*")


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
    written : dict
        key -> (alias, value as written) for the keys the deck gave under an alias
        (``y_min_mm = 4.0``): problems name them so.
    """

    index: int
    name: str
    case_type: CaseType
    params: dict[str, Any]
    written: dict[str, tuple[str, Any]] = field(default_factory=dict)

    @property
    def label(self) -> str:
        """``case N 'name'`` for messages (a long name cut)."""
        name = self.name if len(self.name) <= MAX_NAME else self.name[:40] + "..."
        return f"case {self.index} '{name}'"


def name_problem(name: Any) -> str | None:
    """Why ``name`` cannot name a case (an HDF5 group and plot files), or None."""
    if not isinstance(name, str):
        return f"key 'name' must be a text in quotes, got {name!r}"
    if len(name) > MAX_NAME:
        return f"key 'name' has {len(name)} characters; at most {MAX_NAME}"
    if not _NAME.fullmatch(name):
        return (
            f"key 'name' = {name!r} is not a safe name: use letters, digits, '_', '-', '.', '+' "
            "(no '/', spaces or other characters; not starting with '.', '-' or '+')"
        )
    return None


#: Readers of deck files in another format, by file suffix (lower case, with the dot):
#: path -> list of Case. An area registers its reader when imported (the CONTACT ``.inp``
#: reader of railvti.contact.contact_deck); the runner's read_deck asks here.
DECK_READERS: dict[str, Callable[[Path], list[Case]]] = {}


def register_deck_reader(suffix: str, reader: Callable[[Path], list[Case]]) -> None:
    """Read deck files ending in ``suffix`` (e.g. '.inp') with ``reader(path)``."""
    DECK_READERS[suffix.lower()] = reader


# ---------------------------------------------------------------------------------------------
# History sinks: where a long simulation writes its time history as it runs

#: Simulated time whose history a streamed run keeps in memory (its returned
#: SimulationResult holds these last seconds), s: at least the 1 s window of the summaries
#: (amplitude, largest Q, Y, Y/Q).
STREAM_TAIL_SECONDS = 2.0

#: Bytes of one output time of a vehicle history in memory, for the threshold rule: t, then
#: q and v of up to 64 states, then 15 quantities x 2 wheels x 4 wheelsets, 8 bytes each.
ROW_BYTES = 8 * (1 + 2 * 64 + 15 * 2 * 4)


def history_bytes(duration: float, output_dt: float) -> float:
    """Memory of a vehicle history kept in memory (:data:`ROW_BYTES` per output), bytes."""
    return float(duration) / max(float(output_dt), 1e-12) * ROW_BYTES


@runtime_checkable
class HistorySink(Protocol):
    """What a simulation writes its time history to as it runs (``simulate(stream_to=...)``):
    the caller makes it and hands it in (railvti.runner.stream.HistoryStream is one, writing
    HDF5), the simulation only calls these.

    Attributes
    ----------
    attrs : dict
        name -> {attribute: value}: units and labels the simulation sets for each dataset.
    where : str
        Where the whole history is ('FILE::GROUP'), recorded in the result's ``streamed``.
    """

    attrs: dict[str, dict[str, Any]]

    @property
    def where(self) -> str: ...

    def append(self, block: dict[str, Any]) -> None:
        """Append one block of rows: name -> array whose first axis is the output time."""

    def substitute(self, data: dict[str, tuple]) -> dict[str, tuple]:
        """``data`` (name -> (array, unit[, labels])) with the arrays the sink holds replaced
        by references (:class:`Streamed`) to them: a case's output that the runner copies."""

    def read(self, name: str, columns: Any = None) -> Any:
        """The whole history of dataset ``name`` appended so far (an ndarray; with
        ``columns``, only those indices of its second axis): for quantities of the whole
        run (the assessment) that the case computes after the run."""


#: The provider of sinks for the case running in this context (set by the runner while it
#: runs a case; None outside ``railvti run``): nbytes, **kw -> a HistorySink or None.
_SINK_PROVIDER: contextvars.ContextVar[Callable[..., HistorySink | None] | None] = contextvars.ContextVar(
    "railvti_sink_provider", default=None
)


@contextlib.contextmanager
def offering_sinks(provider: Callable[..., HistorySink | None]) -> Iterator[None]:
    """While inside, :func:`case_sink` asks ``provider(nbytes, **kw)`` (the runner's)."""
    token = _SINK_PROVIDER.set(provider)
    try:
        yield
    finally:
        _SINK_PROVIDER.reset(token)


def case_sink(nbytes: float, **kw: Any) -> HistorySink | None:
    """The sink a case should stream its time history to, or None (keep it in memory): under
    ``railvti run`` the runner's when the history (``nbytes`` in memory) is large enough to
    stream (railvti.runner.stream). ``kw`` go to the runner's sink (``store``, ``derived``)."""
    provider = _SINK_PROVIDER.get()
    return provider(nbytes, **kw) if provider is not None else None
