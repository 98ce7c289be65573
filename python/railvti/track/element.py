"""The rigid track element (paper Fig. 10): one rigid body under each wheelset with lateral,
vertical and roll motion on linear springs and dampers to the ground.

Its parameters come from the flexible ring track's low-frequency receptances: the body's
displacement under the two rail loads equals the rail-head displacement, so with b half the
rail distance and H the per-rail receptance of a load pattern,

    k_z = 2 / H_v(0)          (both rails pushed down in phase)
    k_y = 2 / H_y(0)          (both rails pushed sideways in phase)
    k_phi = 2 b^2 / H_a(0)    (opposite vertical loads: the roll moment 2 F b)

and each mass (inertia) and damper put the body's resonance where the flexible track's first
resonance f0 of that pattern is, with the same peak height:
m = k / (2 pi f0)^2, c = 2 / (omega0 |H(omega0)|) (2 b^2 / ... for roll).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError


@dataclass(frozen=True)
class TrackElement:
    """Rigid track element under one wheelset (lateral y, vertical z, roll phi).

    Parameters
    ----------
    inertia : tuple of float
        (m_y kg, m_z kg, I_phi kg m^2): the effective masses that move laterally and
        vertically (they differ on a real track, so the fit keeps both) and the roll inertia.
    stiffness : tuple of float
        (k_y N/m, k_z N/m, k_phi N m/rad) to the ground.
    damping : tuple of float
        (c_y N s/m, c_z N s/m, c_phi N m s/rad).
    rail_distance : float
        Distance between the rail heads, m.
    """

    inertia: tuple[float, float, float]
    stiffness: tuple[float, float, float]
    damping: tuple[float, float, float]
    rail_distance: float = 1.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "rail_distance", _checks.positive("rail_distance", self.rail_distance))
        if len(self.inertia) != 3 or len(self.stiffness) != 3 or len(self.damping) != 3:
            raise InputError("inertia, stiffness and damping must each have 3 values (y, z, roll)")
        m = tuple(_checks.positive(f"inertia[{i}]", v) for i, v in enumerate(self.inertia))
        object.__setattr__(self, "inertia", m)
        k = tuple(_checks.positive(f"stiffness[{i}]", v) for i, v in enumerate(self.stiffness))
        c = tuple(_checks.non_negative(f"damping[{i}]", v) for i, v in enumerate(self.damping))
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "damping", c)

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass, damping and stiffness matrices (3 x 3) in (y, z, phi)."""
        return np.diag(self.inertia), np.diag(self.damping), np.diag(self.stiffness)

    def receptance(self, freqs: np.ndarray, direction: str = "vertical") -> np.ndarray:
        """Per-rail receptance, m/N, for the load patterns of RingTrack.receptance.

        'vertical' and 'lateral_inphase' load the body with 2F, 'vertical_opposite' with a
        roll moment 2 F b; 'lateral' (opposite lateral loads) does not load a rigid body.
        """
        f = _checks.finite_array("freqs", freqs, ndim=1)
        w = 2 * math.pi * f
        b = 0.5 * self.rail_distance
        if direction == "vertical":
            i, gain = 1, 2.0
        elif direction == "lateral_inphase":
            i, gain = 0, 2.0
        elif direction == "vertical_opposite":
            i, gain = 2, 2.0 * b * b
        elif direction == "lateral":
            return np.zeros_like(w, dtype=complex)
        else:
            raise InputError(f"unknown direction {direction!r}")
        mm = self.inertia[i]
        return gain / (self.stiffness[i] - mm * w * w + 1j * w * self.damping[i])

    @classmethod
    def from_ring(
        cls, track, f_search: tuple[float, float] = (20.0, 400.0), position: str = "midspan"
    ) -> "TrackElement":
        """Fit the element to a RingTrack's low-frequency receptances (see module doc)."""
        b = 0.5 * track.params["rail_distance"]
        f = np.linspace(f_search[0], f_search[1], 800)
        out = []
        for direction, gain in (
            ("lateral_inphase", 2.0),
            ("vertical", 2.0),
            ("vertical_opposite", 2.0 * b * b),
        ):
            h0 = track.static_modal(direction, position)
            if not h0 > 0:
                raise InputError(f"{direction}: static receptance {h0} is not positive")
            k = gain / h0
            h = np.abs(track.receptance(f, direction, position))
            i = int(np.argmax(h))
            w0 = 2 * math.pi * f[i]
            out.append((k, k / w0**2, gain / (w0 * h[i])))
        return cls(
            inertia=(out[0][1], out[1][1], out[2][1]),
            stiffness=(out[0][0], out[1][0], out[2][0]),
            damping=(out[0][2], out[1][2], out[2][2]),
            rail_distance=2 * b,
        )


__all__ = ["TrackElement"]
