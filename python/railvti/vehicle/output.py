"""The output interval of a vehicle run: the periodic excitations its stored history resolves.

The rule (docs/vehicle.md, "Output interval"): a scenario's stored outputs resolve the known
periodic excitations of the scene, each with at least :data:`SAMPLES_PER_PERIOD` samples per
period:

- hunting, every model: its frequency is bounded above by Klingel's kinematic frequency
  f_K = v / (2 pi) sqrt(lambda / (r0 b0)) (lambda the equivalent conicity, r0 the rolling
  radius, b0 half the distance of the rolling circles); a bogie hunts below it;
- the sleeper passing v / sleeper spacing, models on the ring track (RF and FF): the
  wheels run over discrete supports (200 km/h on 0.6 m: 92.6 Hz).

The elastic modes of the wheelsets (FR, FF: up to ``f_max``, 800 Hz by default) and of the
ring (up to ``f_limit``) are no excitations: they answer the two above, and what they add to
the forces lies at the excitation frequencies; their coordinates are stored at the same
interval and resolved only when the user asks for a finer ``output_dt``.

Ten samples per period: the largest sample of a sinusoid sampled ten times per period lies
within 1 - cos(pi / 10) = 4.9 % of its amplitude in the worst phase (five samples: 19 %),
so peak forces read from the history are meaningful; a spectrum needs only more than two.

The default interval is the scene's own (10 ms centred running, 2 ms hunting and sweeps) or,
when an excitation needs it, the largest multiple of the step h not above 1 / (10 f); at
least h (every step stored). A given ``output_dt`` is rounded to a multiple of h by
:func:`railvti.vehicle.simulate.simulate`; when that interval exceeds the Nyquist limit
1 / (2 f) of an excitation, the excitation folds onto a false frequency in the history
(92.6 Hz stored every 10 ms shows at 7.4 Hz): :class:`railvti.errors.AliasingWarning`.
"""

from __future__ import annotations

import logging
import math
import warnings
from dataclasses import dataclass
from typing import Sequence

from .._checks import positive
from ..errors import AliasingWarning

log = logging.getLogger(__name__)

#: Samples per period of each known excitation in a default output interval.
SAMPLES_PER_PERIOD = 10
#: Half the distance of the rolling circles, m (standard gauge: 1500 mm between them).
ROLLING_HALF_DISTANCE = 0.75


@dataclass(frozen=True)
class Excitation:
    """A periodic excitation of a run: its name and frequency, Hz."""

    name: str
    frequency: float

    @property
    def nyquist_dt(self) -> float:
        """The largest output interval that does not alias it, 1 / (2 f), s."""
        return 0.5 / self.frequency


def hunting(
    speed: float, conicity: float, rolling_radius: float, half_distance: float = ROLLING_HALF_DISTANCE
) -> Excitation:
    """Hunting, at Klingel's kinematic frequency (an upper bound of a bogie's), Hz.

    Parameters
    ----------
    speed : float
        Forward speed, m/s.
    conicity : float
        Equivalent conicity, 1.
    rolling_radius : float
        Nominal rolling radius r0, m.
    half_distance : float
        Half the distance of the rolling circles b0, m.
    """
    f = speed / (2.0 * math.pi) * math.sqrt(conicity / (rolling_radius * half_distance))
    return Excitation("hunting (Klingel's kinematic frequency)", f)


def sleeper_passing(speed: float, spacing: float) -> Excitation:
    """The sleeper passing v / spacing (speed m/s, spacing m), Hz."""
    return Excitation(f"sleeper passing (v / {spacing:g} m)", speed / spacing)


def default_interval(excitations: Sequence[Excitation], h: float, base: float) -> float:
    """The default output interval, s: ``base``, or the largest multiple of the step ``h``
    that gives every excitation :data:`SAMPLES_PER_PERIOD` samples per period; at least h."""
    dt = float(base)
    for e in excitations:
        dt = min(dt, 1.0 / (SAMPLES_PER_PERIOD * e.frequency))
    if dt >= base:
        return float(base)
    return max(1, math.floor(dt / h * (1.0 + 1e-9))) * h


def check_interval(
    output_dt: float, h: float, excitations: Sequence[Excitation], key: str = "output_dt"
) -> float:
    """``output_dt`` checked (> 0); an :class:`~railvti.errors.AliasingWarning` (also logged)
    for each excitation whose Nyquist limit the interval actually stored (``output_dt``
    rounded to a multiple of h, as simulate does) exceeds. Returns output_dt."""
    output_dt = positive(key, output_dt)
    stored = max(1, round(output_dt / h)) * h
    for e in excitations:
        if stored > e.nyquist_dt * (1.0 + 1e-9):
            n = math.ceil(e.nyquist_dt / h * (1.0 - 1e-9)) - 1
            fix = (
                f"an {key} of at most {n * h:.4g} s ({n} step(s) of h = {h:g} s, below "
                f"1 / (2 f) = {e.nyquist_dt:.4g} s) resolves it"
                if n >= 1
                else f"the step h = {h:g} s itself exceeds 1 / (2 f) = {e.nyquist_dt:.4g} s: shorten h"
            )
            msg = (
                f"{key} = {output_dt:g} s (stored every {stored:g} s) aliases the "
                f"{e.name} at {e.frequency:.4g} Hz, which would show at "
                f"{_alias(e.frequency, stored):.3g} Hz; {fix} (the default stores "
                f"{SAMPLES_PER_PERIOD} samples per period)"
            )
            log.warning(msg)
            warnings.warn(msg, AliasingWarning, stacklevel=3)
    return output_dt


def _alias(f: float, dt: float) -> float:
    """The frequency at which f shows when sampled every dt, Hz."""
    fs = 1.0 / dt
    return abs(f - fs * round(f / fs))


def output_interval(
    output_dt: float | None, h: float, excitations: Sequence[Excitation], base: float, key: str = "output_dt"
) -> float:
    """The output interval of a run, s: the given ``output_dt`` (checked, warned when it
    aliases an excitation) or :func:`default_interval`."""
    if output_dt is None:
        return default_interval(excitations, h, base)
    return check_interval(output_dt, h, excitations, key)


__all__ = [
    "SAMPLES_PER_PERIOD",
    "ROLLING_HALF_DISTANCE",
    "Excitation",
    "hunting",
    "sleeper_passing",
    "default_interval",
    "check_interval",
    "output_interval",
]
