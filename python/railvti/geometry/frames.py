"""The track frame and the wheelset's axle: side indices, mirror signs, the axle direction.

Track frame: x forward (rolling direction), y lateral to the LEFT, z UP; right-handed.
The left rail is at y > 0. Profiles are placed mirror-symmetrically: a profile's local
y (towards the field side) becomes track +y on the left and -y on the right.
"""

from __future__ import annotations

import numpy as np

#: Index of the left and right wheel / rail in per-side arrays.
LEFT, RIGHT = 0, 1
#: Names of the sides, by index.
SIDES = ("left", "right")
#: +1 on the left wheel/rail, -1 on the right: track y = sign * (offset + local y).
SIGN = (1.0, -1.0)


def axle_direction(roll: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """Unit vectors of the axle (pointing to the left wheel) of a rolled and yawed wheelset.

    The wheelset's rotation is R = Rz(yaw) Rx(roll); the axle is R e_y.

    Parameters
    ----------
    roll, yaw : ndarray (n,)
        Roll about x (positive raises the left wheel) and yaw about z, rad.

    Returns
    -------
    ndarray (n, 3)
        Axle unit vectors in track coordinates.
    """
    cr = np.cos(roll)
    return np.stack([-np.sin(yaw) * cr, np.cos(yaw) * cr, np.sin(roll)], axis=-1)


__all__ = ["SIDES", "SIGN", "axle_direction"]
