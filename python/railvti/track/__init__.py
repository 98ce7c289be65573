"""Flexible ring track (2.5-D rail FE on discrete sleepers), the rigid track element, and track
irregularities (standard spectra, generated or measured tracks)."""

from __future__ import annotations

from .coupling import RailOfWheel, rail_of_wheel, wheel_head_shapes
from .curve import TrackCurve
from .element import TrackElement
from .irregularity import CHANNELS, TrackIrregularity
from .irregularity_file import read_csv as read_irregularity_csv
from .irregularity_file import write_csv as write_irregularity_csv
from .irregularity_spectra import SPECTRA as IRREGULARITY_SPECTRA
from .irregularity_spectra import band_variance as irregularity_band_variance
from .irregularity_spectra import generate as generate_irregularity
from .irregularity_spectra import psd as irregularity_psd
from .ring import DEFAULTS, NUMERICS, RingTrack, TrackModes
from .section import HeadSurface, RailSection, head_surface, rail_section

__all__ = [
    "CHANNELS",
    "DEFAULTS",
    "NUMERICS",
    "HeadSurface",
    "IRREGULARITY_SPECTRA",
    "RailOfWheel",
    "RailSection",
    "RingTrack",
    "TrackCurve",
    "TrackElement",
    "TrackIrregularity",
    "TrackModes",
    "generate_irregularity",
    "head_surface",
    "irregularity_band_variance",
    "irregularity_psd",
    "rail_of_wheel",
    "rail_section",
    "read_irregularity_csv",
    "wheel_head_shapes",
    "write_irregularity_csv",
]
