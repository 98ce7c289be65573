"""Track irregularities: the four EN 13848-1 channels along the track, and the rail positions
they give under a wheel.

The channels, each a deviation from the design track in m, sampled at increasing ``x`` (m,
the distance along the track; x forward as in the vehicle's frame):

* ``vertical_level``: the mean of the two rails' vertical positions, z up;
* ``alignment``: the mean of the two rails' lateral positions, y to the left (the vehicle's y);
* ``cross_level``: left rail height minus right rail height;
* ``gauge``: the gauge deviation, positive for a wider gauge (the left rail moves left).

So the left rail (wheel side 0) lies at y = alignment + gauge / 2, z = vertical_level +
cross_level / 2, and the right rail (side 1) at y = alignment - gauge / 2, z = vertical_level -
cross_level / 2 (:meth:`TrackIrregularity.rails`). Mirroring the track (y -> -y, left <-> right)
flips the sign of alignment and cross level and keeps level and gauge.

Generated from standard spectra (railvti.track.irregularity_spectra) or read from a measured
file (railvti.track.irregularity_file); both give this class.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from railvti.errors import InputError

__all__ = ["CHANNELS", "TrackIrregularity"]

#: The channel names, in the order of :meth:`TrackIrregularity.channels`.
CHANNELS = ("vertical_level", "alignment", "cross_level", "gauge")


@dataclass(frozen=True)
class TrackIrregularity:
    """The four irregularity channels along the track (module docstring for the conventions).

    Attributes
    ----------
    x : ndarray (n,)
        Distance along the track, m, strictly increasing, n >= 2.
    vertical_level, alignment, cross_level, gauge : ndarray (n,)
        The channels at x, m.
    source : str
        Where they come from (a spectrum with its seed and band, or a file name), for the
        results file.
    """

    x: np.ndarray
    vertical_level: np.ndarray
    alignment: np.ndarray
    cross_level: np.ndarray
    gauge: np.ndarray
    source: str = field(default="")

    def __post_init__(self) -> None:
        x = np.asarray(self.x, dtype=np.float64)
        if x.ndim != 1 or x.size < 2:
            raise InputError(f"x: a 1-D array of at least 2 positions (m), got shape {x.shape}")
        if not np.all(np.isfinite(x)):
            raise InputError("x: not finite")
        bad = np.flatnonzero(np.diff(x) <= 0.0)
        if bad.size:
            i = int(bad[0])
            raise InputError(
                f"x: not strictly increasing at sample {i + 1} (x = {x[i]:.6g} m, then {x[i + 1]:.6g} m)"
            )
        object.__setattr__(self, "x", x)
        for name in CHANNELS:
            c = np.asarray(getattr(self, name), dtype=np.float64)
            if c.shape != x.shape:
                raise InputError(f"{name}: shape {c.shape}, expected {x.shape} (one value per x)")
            if not np.all(np.isfinite(c)):
                raise InputError(f"{name}: not finite")
            object.__setattr__(self, name, c)

    def channels(self) -> np.ndarray:
        """The channels as one array (4, n), in the order of :data:`CHANNELS`, m."""
        return np.stack([getattr(self, n) for n in CHANNELS])

    def rails(self) -> tuple[np.ndarray, np.ndarray]:
        """The rails' lateral and vertical positions at x.

        Returns
        -------
        y, z : ndarray (2, n)
            Lateral (to the left) and vertical (up) position of the left [0] and right [1]
            rail, m.
        """
        y = np.stack([self.alignment + 0.5 * self.gauge, self.alignment - 0.5 * self.gauge])
        z = np.stack(
            [self.vertical_level + 0.5 * self.cross_level, self.vertical_level - 0.5 * self.cross_level]
        )
        return y, z

    def mirrored(self) -> TrackIrregularity:
        """The same track seen in a mirror (y -> -y): alignment and cross level change sign."""
        return TrackIrregularity(
            self.x,
            self.vertical_level,
            -self.alignment,
            -self.cross_level,
            self.gauge,
            source=f"{self.source} (mirrored)" if self.source else "mirrored",
        )
