"""Argument checks shared by the public API: each raises InputError naming the argument."""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

from .errors import InputError

#: Highest speed of a vehicle, km/h: above the fastest wheel-on-rail runs (574.8 km/h,
#: TGV 2007) the contact and creep models are not meant to hold.
MAX_SPEED_KMH = 600.0
#: km/h per m/s: the package's one speed conversion (speeds are m/s inside; km/h lives in
#: deck aliases, suffixed keyword aliases such as ``speed_kmh=`` and labels only).
KMH_PER_M_S = 3.6
#: The same in m/s.
MAX_SPEED = MAX_SPEED_KMH / KMH_PER_M_S
#: Largest wheel-rail friction coefficient: dry clean steel reaches ~0.6; 1 is a generous bound.
MAX_FRICTION = 1.0


def _text_problem(name: str, value: Any) -> str | None:
    """Why ``value`` (a text, or an array of texts) is refused where a number is expected:
    the API converts no text to a number (``fn='1e4'`` is a mistake a deck would refuse)."""
    if isinstance(value, (str, bytes)) or np.asarray(value).dtype.kind in "USa":
        if not isinstance(value, (str, bytes)):
            return (
                f"{name} must hold numbers, got the texts {value!r} (give numbers, not "
                "quoted texts: the API converts no text to a number)"
            )
        example = value.decode(errors="replace") if isinstance(value, bytes) else value
        if not isinstance(example, str) or not re.fullmatch(r"\s*[-+0-9.eE]+\s*", example):
            example = "1e4"
        return (
            f"{name} must be a number, got the text {value!r} (give {name}={example.strip()}, "
            f"not {name}={example.strip()!r}: the API converts no text to a number)"
        )
    return None


def finite(name: str, value: Any) -> float:
    """Return ``value`` as a float, or raise if it is not a finite number (a text such as
    '1e4' is refused, not converted)."""
    if isinstance(value, (str, bytes)):
        raise InputError(_text_problem(name, value))
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be finite, got {v}")
    return v


def positive(name: str, value: Any) -> float:
    """Return ``value`` as a float, or raise unless it is finite and > 0."""
    v = finite(name, value)
    if v <= 0.0:
        raise InputError(f"{name} must be > 0, got {v}")
    return v


def non_negative(name: str, value: Any) -> float:
    """Return ``value`` as a float, or raise unless it is finite and >= 0."""
    v = finite(name, value)
    if v < 0.0:
        raise InputError(f"{name} must be >= 0, got {v}")
    return v


def positive_int(name: str, value: Any, minimum: int = 1) -> int:
    """Return ``value`` as an int, or raise unless it is an integer >= minimum (a number,
    not a text)."""
    v = finite(name, value)
    if isinstance(value, bool) or not v.is_integer():
        raise InputError(f"{name} must be an integer, got {value!r}")
    v = int(value)
    if v < minimum:
        raise InputError(f"{name} must be >= {minimum}, got {v}")
    return v


def finite_array(
    name: str, value: Any, shape: tuple[int, ...] | None = None, ndim: int | None = None
) -> np.ndarray:
    """Return a Fortran-ordered float64 copy of ``value``; raise on NaN, inf, wrong shape or
    texts (not converted to numbers)."""
    try:
        text = _text_problem(name, value)
    except (TypeError, ValueError):  # a ragged sequence: np.array below names it
        text = None
    if text:
        raise InputError(text)
    try:
        a = np.array(value, dtype=np.float64, order="F")
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of numbers") from None
    if ndim is not None and a.ndim != ndim:
        raise InputError(f"{name} must have {ndim} dimensions, got shape {a.shape}")
    if shape is not None and a.shape != tuple(shape):
        raise InputError(f"{name} must have shape {tuple(shape)}, got {a.shape}")
    bad = ~np.isfinite(a)
    if bad.any():
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        raise InputError(f"{name} has {int(bad.sum())} non-finite value(s), first at index {idx}")
    return a


def speed_kmh(name: str, value: Any) -> float:
    """Return a vehicle speed in km/h as a float; raise unless 0 < value <= MAX_SPEED_KMH."""
    return _kmh(name, value)


def _kmh(name: str, value: Any) -> float:
    v = finite(name, value)
    if not 0.0 < v <= MAX_SPEED_KMH:
        raise InputError(
            f"{name} = {v:g} km/h must be in (0, {MAX_SPEED_KMH:g}] km/h (the fastest "
            "wheel-on-rail run was 575 km/h)"
        )
    return v


def from_kmh(value: Any) -> Any:
    """A speed (or an array of speeds) given in km/h, in m/s."""
    return value / KMH_PER_M_S


def to_kmh(value: Any) -> Any:
    """A speed (or an array of speeds) in m/s, in km/h: for labels and printed text."""
    return value * KMH_PER_M_S


def speed_si(speed: Any, speed_kmh: Any, default_kmh: float | None = None, name: str = "speed") -> float:
    """A vehicle speed in m/s from exactly one of ``speed`` (m/s, the SI argument) and
    ``speed_kmh`` (its suffixed alias, km/h), or ``default_kmh`` when neither is given:
    the one conversion at the public API's edge.

    Raises
    ------
    InputError
        Both given, neither (without a default), or a speed outside (0, MAX_SPEED].
    """
    if speed is not None and speed_kmh is not None:
        raise InputError(f"give the {name} once: {name} (m/s) or {name}_kmh (km/h), not both")
    if speed is not None:
        v = finite(name, speed)
        if not 0.0 < v <= MAX_SPEED:
            raise InputError(f"{name} = {v:g} m/s must be in (0, {MAX_SPEED:.4g}] m/s")
        return v
    if speed_kmh is None:
        if default_kmh is None:
            raise InputError(f"the {name} is required: {name} (m/s) or {name}_kmh (km/h)")
        speed_kmh = default_kmh
    return from_kmh(_kmh(f"{name}_kmh", speed_kmh))


def friction(name: str, value: Any, allow_zero: bool = False) -> float:
    """Return a friction coefficient; raise unless it is in (0, MAX_FRICTION] ([0, ...] with
    ``allow_zero``)."""
    v = finite(name, value)
    if v < 0.0 or v > MAX_FRICTION or (v == 0.0 and not allow_zero):
        raise InputError(
            f"{name} = {v:g} must be in {'[' if allow_zero else '('}0, {MAX_FRICTION:g}] "
            "(dry steel on steel is about 0.3-0.6)"
        )
    return v
