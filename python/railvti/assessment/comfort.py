"""Ride indices: Sperling's Wz and EN 12299's mean comfort N_MV (simplified method).

**Sperling's Wz.** For a harmonic acceleration of amplitude a (cm/s^2) at frequency f,
Sperling's index is Wz = (a^3 B(f)^3)^(1/10) = (a B(f))^0.3, B the weighting of
:func:`railvti.assessment.filters.sperling`; it is the continuous form of Sperling's
Wz = 0.896 (a^3 F(f) / f)^(1/10) with his piecewise frequency factor F (vertical 0.325 f^2
for 0.5-5.9 Hz, 400 / f^2 for 5.9-20 Hz, 1 above; lateral 0.8 f^2 for 0.5-5.4 Hz,
650 / f^2 for 5.4-26 Hz, 1 above), within 3 %. For a broadband signal this module sums
energies: the weighted signal's rms a_w gives the amplitude-equivalent sqrt(2) a_w and
Wz = (100 sqrt(2) a_w)^0.3 (a_w in m/s^2), i.e. Wz = (2 integral B^2 G df)^0.15 with G the
one-sided acceleration PSD in (cm/s^2)^2/Hz (as janiex/SimulinkMatlab sperling.m); for a
sine it is the closed form exactly. (Sperling's own rule for several frequencies,
Wz = (sum Wz_i^10)^(1/10), adds cubes of amplitudes and depends on how the spectrum is cut
into lines: not used.)

**N_MV, EN 12299:2009 simplified (standard) method.** Floor accelerations weighted by Wd
(x, y) and Wb (z), rms over consecutive 5 s blocks, the 95th percentile of the 60 blocks of
each 5 min: N_MV = 6 sqrt(a_XP95^2 + a_YP95^2 + a_ZP95^2) (a in m/s^2). A run shorter than
5 min gives the percentile of the blocks it has (at least one: a run shorter than 5 s
raises InputError): an indicative value, flagged ``indicative``; a run of several 5 min
windows gives the largest N_MV of its windows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError
from .filters import sperling, weighting
from .windows import check_history, sampling_rate

__all__ = ["sperling_wz", "sperling_wz_sine", "sperling_wz_piecewise", "NMV", "n_mv"]


def _after(t: np.ndarray, discard: float, name: str) -> np.ndarray:
    k = t >= t[0] + _checks.non_negative("discard", discard)
    if np.count_nonzero(k) < 2:
        raise InputError(f"{name}: nothing left after discarding the first {discard:g} s")
    return k


def sperling_wz(t: np.ndarray, a: np.ndarray, direction: str, discard: float = 0.0) -> float:
    """Sperling's Wz of acceleration ``a`` (m/s^2, (nt,)) at times ``t`` (s, even):
    'vertical' or 'lateral'; the first ``discard`` seconds (the filter's start) left out of
    the rms."""
    t, a = check_history(f"Sperling Wz ({direction})", t, a)
    aw = sperling(direction).apply(a, sampling_rate(t, "Sperling Wz"))
    k = _after(t, discard, "Sperling Wz")
    rms = math.sqrt(float(np.mean(aw[k] ** 2)))
    return (100.0 * math.sqrt(2.0) * rms) ** 0.3


def sperling_wz_sine(amplitude: float, f: float, direction: str) -> float:
    """The closed form for a sine of ``amplitude`` (m/s^2) at ``f`` (Hz):
    (100 a |B(f)|)^0.3, B evaluated from Sperling's continuous formula."""
    ff = _checks.positive("frequency", f)
    b = 0.588 * math.sqrt(
        (1.911 * ff**2 + (0.25 * ff**2) ** 2)
        / ((1.0 - 0.277 * ff**2) ** 2 + (1.563 * ff - 0.0368 * ff**3) ** 2)
    )
    if direction == "lateral":
        b *= 1.25
    elif direction != "vertical":
        raise InputError(f"Sperling direction must be 'vertical' or 'lateral', got {direction!r}")
    return (100.0 * abs(amplitude) * b) ** 0.3


def sperling_wz_piecewise(amplitude: float, f: float, direction: str) -> float:
    """Sperling's original Wz = 0.896 (a^3 F(f) / f)^(1/10) (a in cm/s^2) with his piecewise
    frequency factor F (see the module docstring): for a sine of ``amplitude`` (m/s^2)."""
    ff = _checks.positive("frequency", f)
    if direction == "vertical":
        fac = 0.325 * ff**2 if ff < 5.9 else (400.0 / ff**2 if ff < 20.0 else 1.0)
    elif direction == "lateral":
        fac = 0.8 * ff**2 if ff < 5.4 else (650.0 / ff**2 if ff < 26.0 else 1.0)
    else:
        raise InputError(f"Sperling direction must be 'vertical' or 'lateral', got {direction!r}")
    return 0.896 * ((100.0 * abs(amplitude)) ** 3 * fac / ff) ** 0.1


@dataclass(frozen=True)
class NMV:
    """EN 12299's mean comfort index of one floor point.

    Attributes
    ----------
    value : float
        N_MV, the largest over the run's 5 min windows, 1.
    p95 : ndarray (3,)
        The 95th percentiles of the 5 s rms of the weighted x, y, z accelerations in the
        window of ``value``, m/s^2.
    blocks : int
        Number of 5 s blocks in that window (60 for a full 5 min).
    indicative : bool
        True when the run is shorter than 5 min (fewer than 60 blocks).
    """

    value: float
    p95: np.ndarray
    blocks: int
    indicative: bool


def n_mv(t: np.ndarray, ax: np.ndarray | None, ay: np.ndarray, az: np.ndarray, discard: float = 0.0) -> NMV:
    """N_MV (EN 12299 simplified method) from floor accelerations (m/s^2) at times ``t`` (s,
    evenly spaced); ``ax`` None for a model without longitudinal carbody motion (its term
    is then 0). The first ``discard`` seconds are left out."""
    ay = np.asarray(ay, dtype=float)
    ax = np.zeros_like(ay) if ax is None else np.asarray(ax, dtype=float)
    t, acc = check_history("N_MV", t, np.stack([ax, ay, np.asarray(az, dtype=float)], axis=1))
    fs = sampling_rate(t, "N_MV")
    wd, wb = weighting("Wd"), weighting("Wb")
    w = np.stack([wd.apply(acc[:, 0], fs), wd.apply(acc[:, 1], fs), wb.apply(acc[:, 2], fs)], axis=1)
    k = _after(t, discard, "N_MV")
    t, w = t[k], w[k]
    n = int(round(5.0 * fs))
    nblocks = (t.size) // n
    if nblocks < 1:
        raise InputError(
            f"N_MV: the run ({t[-1] - t[0]:.3g} s after discarding) is shorter than one 5 s block"
        )
    rms = np.sqrt(np.mean(w[: nblocks * n].reshape(nblocks, n, 3) ** 2, axis=1))  # (nblocks, 3)
    best = None
    for s in range(0, nblocks - 59, 60) if nblocks >= 60 else (0,):  # whole 5 min windows only
        chunk = rms[s : s + 60]
        p95 = np.percentile(chunk, 95.0, axis=0)
        val = 6.0 * float(np.sqrt(np.sum(p95**2)))
        if best is None or val > best.value:
            best = NMV(value=val, p95=p95, blocks=len(chunk), indicative=len(chunk) < 60)
    return best
