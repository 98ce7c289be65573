"""The vehicle's wheels on the ring track's rails: which rail, and the change of lateral axis.

The vehicle's frame has x forward, y to the **left**, z up (docs/vehicle.md); wheel side 0 is
the left wheel. The ring's frame has x along the ring (the direction of travel), y to the
**right**, z up: rail 1 at y = -rail_distance / 2 is the left rail, rail 2 the right one
(docs/track.md, "Frames"). The two frames differ by the reflection y -> -y, so a wheel's
quantities map onto its rail as

    (u_x, u_y, u_z, roll)_ring = diag(1, -1, 1, -1) (u_x, u_y, u_z, roll)_vehicle

and the same for forces and moments (F_x, F_y, F_z, M_x): the roll about x is the rotation
from y towards z, and reflecting y reverses it. The map is its own inverse.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from .ring import RingTrack

#: The reflection y -> -y over (x, y, z, roll about x).
REFLECT_Y = np.diag([1.0, -1.0, 1.0, -1.0])

_SIDES = {"left": 0, "right": 1}


@dataclass(frozen=True)
class RailOfWheel:
    """Where a vehicle wheel runs on the ring track.

    Attributes
    ----------
    rail : int
        Ring rail index, 1 (left) or 2 (right).
    lateral_sign : float
        y_ring = lateral_sign * y_vehicle; also the sign of the roll about x. Always -1
        (the frames are mirror images); kept explicit so that the coupling code says it.
    transform : ndarray (4, 4)
        Maps (x, y, z, roll) vectors, and (F_x, F_y, F_z, M_x) loads, from the vehicle's
        frame to the ring's and back (it is its own inverse).
    """

    rail: int
    lateral_sign: float
    transform: np.ndarray

    def to_ring(self, v: np.ndarray) -> np.ndarray:
        """A (4, ...) array of (x, y, z, roll) rows in the vehicle's frame, in the ring's."""
        return np.tensordot(self.transform, np.asarray(v, float), axes=1)

    def to_vehicle(self, v: np.ndarray) -> np.ndarray:
        """A (4, ...) array of (x, y, z, roll) rows in the ring's frame, in the vehicle's."""
        return np.tensordot(self.transform, np.asarray(v, float), axes=1)


def rail_of_wheel(side: int | str) -> RailOfWheel:
    """The ring rail under a vehicle wheel, and the lateral sign between the two frames.

    Parameters
    ----------
    side : {0, 1, 'left', 'right'}
        The wheel's side as the vehicle counts it: 0 or 'left' is the wheel at y > 0 (the
        vehicle's y points to the left), 1 or 'right' the wheel at y < 0.

    Returns
    -------
    RailOfWheel
        rail 1 for the left wheel, rail 2 for the right one; lateral sign -1.

    Raises
    ------
    InputError
        Any other side.
    """
    if isinstance(side, str):
        if side not in _SIDES:
            raise InputError(f"side must be 'left', 'right', 0 or 1, got {side!r}")
        side = _SIDES[side]
    elif isinstance(side, (bool, np.bool_)) or side not in (0, 1):
        raise InputError(f"side must be 'left', 'right', 0 or 1, got {side!r}")
    return RailOfWheel(rail=int(side) + 1, lateral_sign=-1.0, transform=REFLECT_Y.copy())


def wheel_head_shapes(track: RingTrack, x: float, side: int | str, s: float | None = None) -> np.ndarray:
    """Rail-head shapes under a vehicle wheel, in the vehicle's frame.

    Parameters
    ----------
    track : RingTrack
        The ring track.
    x : float
        Position of the contact point along the ring, m.
    side : {0, 1, 'left', 'right'}
        The wheel's side as the vehicle counts it (see :func:`rail_of_wheel`).
    s : float, optional
        Lateral position of the contact point on the rail head, m: the rail section's eta
        (from the rail's axis, tilted with the rail's cant) with the vehicle's sign, positive
        to the left (towards the gauge corner on the right rail, away from it on the left
        one); the ring's s is ``lateral_sign * s`` (:meth:`RingTrack.head_shapes`). Default:
        the crown.

    Returns
    -------
    ndarray (4, n_modes)
        Rows u_x, u_y, u_z (m) and roll about x (rad) per unit modal coordinate, with the
        vehicle's y (to the left) and its roll. Dotted with a load (F_x, F_y, F_z in N, M_x in
        N m) in the vehicle's frame, they give the load's modal forces.
    """
    m = rail_of_wheel(side)
    return m.to_vehicle(track.head_shapes(x, m.rail, None if s is None else m.lateral_sign * s))


__all__ = ["REFLECT_Y", "RailOfWheel", "rail_of_wheel", "wheel_head_shapes"]
