"""Limit-cycle criteria on the amplitude envelope of a time history (the criteria of
:func:`railvti.critical_search.nonlinear_critical_speed`, issue 30 item 5).

The envelope (:func:`envelope`) is half the peak-to-peak lateral displacement of the leading
wheelset in consecutive windows of ``window`` s. A run carries a living cycle when the
envelope's fitted growth rate over the second half of the run is above ``-rate_tol`` and its
last window above a floor (:func:`cycle_verdict`); a small disturbance grows when its
envelope's last window exceeds its first (:func:`growth_rate` > 0).
"""

from __future__ import annotations

import math

import numpy as np

from . import _checks
from .errors import InputError

__all__ = ["envelope", "growth_rate", "cycle_verdict"]


def envelope(t: np.ndarray, y: np.ndarray, window: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude envelope of a time history: half the peak-to-peak of ``y`` in consecutive
    windows of ``window`` s counted back from the end (each sample closes an interval of the
    sampling step; a partial first window is dropped).

    Parameters
    ----------
    t : ndarray
        Times, s, increasing.
    y : ndarray
        The signal (the leading wheelset's lateral displacement, m).
    window : float
        Window length, s (a few hunting periods: 0.5 s holds 2.5-3.5 periods at 5-7 Hz).

    Returns
    -------
    tc : ndarray
        Window centres, s.
    a : ndarray
        Half the peak-to-peak in each window, m.
    """
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    window = _checks.positive("window", window)
    span = t[-1] - t[0] + (t[1] - t[0] if t.size > 1 else 0.0)  # samples end intervals
    n = int(math.floor(span / window + 1e-9))
    if n < 1:
        raise InputError(f"window = {window:g} s is longer than the run ({span:g} s)")
    edges = t[-1] - window * np.arange(n, -1, -1)
    tc, a = np.empty(n), np.empty(n)
    for k in range(n):
        m = (t >= edges[k] - 1e-12) & (t <= edges[k + 1] + 1e-12)
        tc[k] = 0.5 * (edges[k] + edges[k + 1])
        a[k] = 0.5 * float(np.ptp(y[m])) if m.any() else 0.0
    return tc, a


def _log_slope(tc: np.ndarray, a: np.ndarray) -> float:
    """Least-squares slope of ln a against tc, 1/s (a floored at 1e-12 m)."""
    if tc.size < 2:
        return 0.0
    return float(np.polyfit(tc, np.log(np.maximum(a, 1e-12)), 1)[0])


def growth_rate(t: np.ndarray, y: np.ndarray, window: float = 0.5) -> float:
    """Mean growth rate of the envelope between its first and last windows,
    ln(A_last / A_first) / (their distance), 1/s.

    Positive: the motion ends larger than it started (it grows, or settles on a cycle above
    the disturbance); negative: it decays. The decay boundary's criterion: the sign alone
    decides (no threshold). The first window holds the release from the disturbance, so
    A_first is about the disturbance itself; a motion that grows and then saturates on a
    cycle keeps its sign however long the run (a fitted slope over the run would tend to 0).
    """
    tc, a = envelope(t, y, window)
    if tc.size < 2:
        raise InputError(f"window = {window:g} s: the run must hold at least two windows")
    a = np.maximum(a, 1e-12)
    return float(np.log(a[-1] / a[0]) / (tc[-1] - tc[0]))


def cycle_verdict(
    t: np.ndarray,
    y: np.ndarray,
    *,
    threshold: float,
    rate_tol: float,
    window: float = 0.5,
    collapse: float | None = None,
) -> tuple[str, float, float]:
    """Is a limit cycle alive at the end of this run?

    Parameters
    ----------
    t, y : ndarray
        Times (s) and the leading wheelset's lateral displacement (m).
    threshold : float
        The floor, m: a last window below it is no cycle (dead at once).
    rate_tol : float
        1/s: alive when the envelope's fitted growth rate over the second half of the run
        is at least ``-rate_tol``; otherwise still dying ('decaying': continue the run).
    window : float
        Envelope window, s.
    collapse : float, optional
        A run carried in on a cycle: dead when the last window is below ``collapse`` times
        the first (the run has left the branch it followed, even if what remains decays
        slowly enough to pass ``rate_tol``). None: no such check (a start from a shift).

    Returns
    -------
    verdict : str
        'alive', 'dead' (below the floor, or collapsed) or 'decaying' (above the floor,
        falling faster than ``rate_tol``).
    amplitude : float
        The envelope's last window, m.
    rate : float
        The fitted growth rate over the second half, 1/s.
    """
    tc, a = envelope(t, y, window)
    half = tc >= 0.5 * (t[0] + t[-1])
    rate = _log_slope(tc[half], a[half]) if half.sum() >= 2 else _log_slope(tc, a)
    amp = float(a[-1])
    if amp < threshold or (collapse is not None and amp < collapse * float(a[0])):
        return "dead", amp, rate
    return ("alive" if rate >= -rate_tol else "decaying"), amp, rate
