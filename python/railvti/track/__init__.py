"""Flexible ring track (2.5-D rail FE on discrete sleepers) and the rigid track element."""
from __future__ import annotations

from .element import TrackElement
from .ring import DEFAULTS, NUMERICS, RingTrack, TrackModes
from .section import RailSection, rail_section

__all__ = ["DEFAULTS", "NUMERICS", "RailSection", "RingTrack", "TrackElement", "TrackModes", "rail_section"]
