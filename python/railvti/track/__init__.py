"""Flexible ring track (2.5-D rail FE on discrete sleepers) and the rigid track element."""

from __future__ import annotations

from .coupling import RailOfWheel, rail_of_wheel, wheel_head_shapes
from .curve import TrackCurve
from .element import TrackElement
from .irregularity import CHANNELS, TrackIrregularity
from .ring import DEFAULTS, NUMERICS, RingTrack, TrackModes
from .section import HeadSurface, RailSection, head_surface, rail_section

__all__ = [
    "CHANNELS",
    "DEFAULTS",
    "NUMERICS",
    "HeadSurface",
    "RailOfWheel",
    "RailSection",
    "RingTrack",
    "TrackCurve",
    "TrackElement",
    "TrackIrregularity",
    "TrackModes",
    "head_surface",
    "rail_of_wheel",
    "rail_section",
    "wheel_head_shapes",
]
