"""Sliding means and rms values over a window in time (a distance window L at speed V is the
time window L / V), and the percentiles the standards take of them.

The signal is taken as piecewise linear between its samples: the sliding mean at t_i is
(1 / W) times the integral of that line over [t_i - W, t_i], exact for any W (not only
whole numbers of samples), defined from t_0 + W on.
"""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = ["check_history", "sampling_rate", "sliding_mean", "sliding_rms", "time_window", "percentile_abs"]


def check_history(name: str, t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``t`` (nt,) strictly increasing and finite, ``y`` (nt, ...) finite: as float arrays;
    InputError naming ``name`` otherwise."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.ndim != 1 or y.shape[:1] != t.shape:
        raise InputError(f"{name}: times {t.shape} and values {y.shape} do not match")
    if t.size < 2:
        raise InputError(f"{name}: at least 2 samples are needed, got {t.size}")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0.0):
        raise InputError(f"{name}: the times must be finite and strictly increasing")
    bad = ~np.isfinite(y)
    if np.any(bad):
        i = int(np.argwhere(bad)[0][0])
        raise InputError(f"{name}: NaN or inf at t = {t[i]:.6g} s (sample {i})")
    return t, y


def sampling_rate(t: np.ndarray, name: str = "signal") -> float:
    """1 / dt of evenly spaced times ``t`` (s), Hz; InputError if they are not even (to 1e-6)."""
    dt = np.diff(np.asarray(t, dtype=float))
    if dt.size < 2:
        raise InputError(f"{name}: {dt.size + 1} output time(s): too few to filter")
    if np.ptp(dt) > 1e-6 * dt.mean():
        raise InputError(f"{name}: the output times must be evenly spaced for the standards' filters")
    return 1.0 / float(dt.mean())


def time_window(length_m: float, speed: float) -> float:
    """The time a distance ``length_m`` (m) takes at ``speed`` (m/s), s."""
    return _checks.positive("window length", length_m) / _checks.positive("speed", speed)


def sliding_mean(t: np.ndarray, y: np.ndarray, window: float, name: str = "signal") -> tuple:
    """Sliding mean of ``y`` (nt, ...) over the past ``window`` seconds.

    Returns
    -------
    t_out : ndarray (m,)
        The times where a whole window lies within the record (t >= t_0 + window).
    mean : ndarray (m, ...)
        The mean of the piecewise-linear signal over [t - window, t].

    Raises
    ------
    InputError
        The record is shorter than the window, or holds NaN.
    """
    t, y = check_history(name, t, y)
    w = _checks.positive("window", window)
    span = t[-1] - t[0]
    if span < w * (1.0 - 1e-12):
        raise InputError(f"{name}: the record ({span:.4g} s) is shorter than the {w:.4g} s window")
    dt = np.diff(t).reshape((-1,) + (1,) * (y.ndim - 1))
    cum = np.concatenate([np.zeros((1,) + y.shape[1:]), np.cumsum(0.5 * dt * (y[1:] + y[:-1]), axis=0)])
    i0 = int(np.searchsorted(t, t[0] + w * (1.0 - 1e-12)))
    idx = np.arange(i0, t.size)
    ts = np.maximum(t[idx] - w, t[0])
    k = np.clip(np.searchsorted(t, ts, side="right") - 1, 0, t.size - 2)
    frac = ((ts - t[k]) / (t[k + 1] - t[k])).reshape((-1,) + (1,) * (y.ndim - 1))
    ys = y[k] + frac * (y[k + 1] - y[k])
    dts = (ts - t[k]).reshape(frac.shape)
    start = cum[k] + 0.5 * dts * (y[k] + ys)
    return t[idx], (cum[idx] - start) / w


def sliding_rms(t: np.ndarray, y: np.ndarray, window: float, name: str = "signal") -> tuple:
    """Sliding rms of ``y`` over the past ``window`` seconds: the square root of the
    :func:`sliding_mean` of y^2 (trapezoidal in y^2 between samples). Returns (t_out, rms)."""
    t_out, m = sliding_mean(t, np.square(np.asarray(y, dtype=float)), window, name)
    return t_out, np.sqrt(np.maximum(m, 0.0))


def percentile_abs(y: np.ndarray, q: float = 99.85) -> float:
    """The larger of |the q % percentile| and |the (100 - q) % percentile| of ``y`` (all
    samples together): EN 14363's F2 = 99.85 % / F1 = 0.15 % pair of a two-sided quantity,
    linear interpolation between order statistics (numpy's default)."""
    y = np.asarray(y, dtype=float).ravel()
    if y.size == 0:
        raise InputError("percentile of an empty signal")
    return float(max(abs(np.percentile(y, q)), abs(np.percentile(y, 100.0 - q))))
