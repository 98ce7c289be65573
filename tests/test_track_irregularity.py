"""railvti.track.TrackIrregularity: the rails' positions from the EN 13848 channels, the
mirror, and bad input."""

from __future__ import annotations

import numpy as np
import pytest

from railvti.errors import InputError
from railvti.track import TrackIrregularity


def _track() -> TrackIrregularity:
    x = np.linspace(0.0, 10.0, 11)
    return TrackIrregularity(x, 1e-3 * np.sin(x), 2e-3 * np.cos(x), 4e-3 * np.sin(2 * x), 1e-3 * x / 10)


def test_rails_give_back_the_channels() -> None:
    """The channels are the rails' means and differences (EN 13848-1 definitions)."""
    tr = _track()
    y, z = tr.rails()
    np.testing.assert_allclose(0.5 * (y[0] + y[1]), tr.alignment, atol=1e-15)
    np.testing.assert_allclose(y[0] - y[1], tr.gauge, atol=1e-15)
    np.testing.assert_allclose(0.5 * (z[0] + z[1]), tr.vertical_level, atol=1e-15)
    np.testing.assert_allclose(z[0] - z[1], tr.cross_level, atol=1e-15)


def test_mirror_swaps_the_rails() -> None:
    """In the mirror the left rail becomes the right one at -y, same height."""
    tr = _track()
    y, z = tr.rails()
    ym, zm = tr.mirrored().rails()
    np.testing.assert_allclose(ym, -y[::-1], atol=1e-15)
    np.testing.assert_allclose(zm, z[::-1], atol=1e-15)


@pytest.mark.parametrize(
    ("x", "match"),
    [
        ([0.0], "at least 2"),
        ([0.0, 1.0, 1.0], "strictly increasing at sample 2"),
        ([0.0, np.nan], "not finite"),
    ],
)
def test_bad_x(x, match) -> None:
    z = np.zeros(len(x))
    with pytest.raises(InputError, match=match):
        TrackIrregularity(np.array(x), z, z, z, z)


def test_channel_shape_named() -> None:
    with pytest.raises(InputError, match="gauge: shape"):
        TrackIrregularity(np.arange(3.0), np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(2))
