"""Wheel-rail force quantities of EN 14363: Y/Q per wheel, the track-shifting force Sigma Y
per wheelset, the vertical wheel force Q, and their limits.

Forces are those of the rail on the wheel (SimulationResult.Q, .Y: Y along track y, + left).
"""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = [
    "wheel_forces",
    "static_wheel_load",
    "flange_climb_ratio",
    "track_shifting_force",
    "prudhomme_limit",
    "en14363_sum_y_limit",
    "q_limit",
    "Q_LIMIT_CAPS",
]


def wheel_forces(result) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t, Q, Y) of a run: t (nt,) s, Q and Y (nt, 2, nw) N (wheel 0 left, 1 right).

    Raises InputError for a result without per-wheel outputs or with NaN in them."""
    w = getattr(result, "wheel", None)
    if w is None or np.ndim(w) != 4 or np.size(w) == 0 or np.shape(w)[2] != 2:
        raise InputError("the result has no per-wheel outputs (wheel: (nt, quantity, 2, nw)) to assess")
    t = np.asarray(result.t, dtype=float)
    q, y = np.asarray(result.Q, dtype=float), np.asarray(result.Y, dtype=float)
    for name, a in (("Q", q), ("Y", y)):
        bad = ~np.isfinite(a)
        if np.any(bad):
            i = int(np.argwhere(bad)[0][0])
            raise InputError(f"wheel force {name} is NaN or inf at t = {t[i]:.6g} s (sample {i})")
    return t, q, y


def static_wheel_load(q: np.ndarray) -> float:
    """The static wheel load Q0 (N) from a run's vertical forces (nt, 2, nw): the time mean of
    their sum over all wheels, divided by the number of wheels. On straight level track the
    wheels carry the weight on average, so this is the static load to within the mean of
    the vertical dynamics (a symmetric vehicle: all wheels alike)."""
    q = np.asarray(q, dtype=float)
    return float(np.mean(np.sum(q, axis=(1, 2))) / (q.shape[1] * q.shape[2]))


def flange_climb_ratio(y: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(nt, 2, nw) Y/Q of every wheel as a flange-climb ratio: the lateral force of the rail
    towards the track centre (-Y on the left wheel, +Y on the right) over Q; 0 where
    Q < 1 % of the largest Q (a lifted wheel), as SimulationResult.y_over_q."""
    q = np.asarray(q, dtype=float)
    yin = np.asarray(y, dtype=float) * np.array([-1.0, 1.0])[None, :, None]
    ok = q > 0.01 * max(float(q.max()), 1e-30)
    return np.where(ok, yin / np.where(ok, q, 1.0), 0.0)


def track_shifting_force(y: np.ndarray) -> np.ndarray:
    """(nt, nw) the track-shifting force Sigma Y of every wheelset: Y_left + Y_right, N (the
    lateral force of the rails on the wheelset, track y; the wheelset pushes the track by
    minus this)."""
    return np.sum(np.asarray(y, dtype=float), axis=1)


def prudhomme_limit(axle_load: float) -> float:
    """Prud'homme's limit of the track-shifting force, N: 10 kN + P0 / 3, P0 the static axle
    load (N) (Prud'homme 1967; UIC 518, EN 14363 with alpha = 1)."""
    return 10.0e3 + _checks.positive("static axle load", axle_load) / 3.0


def en14363_sum_y_limit(wheel_load: float, alpha: float = 0.85) -> float:
    """EN 14363's limit of the 2 m sliding mean of Sigma Y, N: alpha (10 kN + 2 Q0 / 3), Q0 the
    static wheel load (N); alpha = 1 for locomotives, power units and passenger coaches,
    0.85 for freight wagons (EN 14363:2005 / UIC 518:2009, (Sigma Y_2m)_lim)."""
    return _checks.positive("alpha", alpha) * (
        10.0e3 + 2.0 * _checks.positive("static wheel load", wheel_load) / 3.0
    )


#: Upper bounds of EN 14363's Q_lim = 90 kN + Q0 by speed: (up to km/h, cap N) (UIC 518:2009 /
#: EN 14363:2005 as commonly quoted; not checked against the standards' text here).
Q_LIMIT_CAPS = ((160.0, 200e3), (200.0, 190e3), (250.0, 180e3), (300.0, 170e3), (float("inf"), 160e3))


def q_limit(wheel_load: float, speed: float) -> float:
    """EN 14363's limit of the maximum vertical wheel force, N: 90 kN + Q0, at most the
    speed's cap (:data:`Q_LIMIT_CAPS`; ``speed`` in m/s)."""
    kmh = 3.6 * _checks.positive("speed", speed)
    cap = next(c for v, c in Q_LIMIT_CAPS if kmh <= v)
    return min(90.0e3 + _checks.positive("static wheel load", wheel_load), cap)
