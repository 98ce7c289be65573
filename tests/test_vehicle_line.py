"""The line scenario and deck case (railvti.vehicle.line_running, line_case): a curve and an
irregularity in one run compose as each alone does, and the deck refuses bad input by name."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.casetypes import validate
from railvti.errors import InputError
from railvti.runner.deck_registry import case_types
from railvti.track import TrackCurve, TrackIrregularity

CURVE = TrackCurve(
    radius=1200.0, cant=0.1, transition_in=40.0, arc_length=100.0, transition_out=40.0, start=60.0
)


def _flat(length: float = 300.0) -> TrackIrregularity:
    x = np.linspace(0.0, length, int(length / 0.25) + 1)
    z = np.zeros_like(x)
    return TrackIrregularity(x, z, z, z, z, source="flat")


def test_a_flat_line_into_a_curve_is_the_curving_run() -> None:
    """A zero irregularity adds nothing: the line run into a curve equals scenarios.curving over
    the same stretch, to the bit."""
    kw = dict(duration=1.5, h=1e-3, output_dt=0.01, progress=False)
    line = scenarios.line_run(160, _flat(), CURVE, "RR", "hertz-fastsim", x_start=20.0, lead_in=0.0, **kw)
    curv = scenarios.curving(160, CURVE, "RR", "hertz-fastsim", x_start=20.0, **kw)
    assert np.array_equal(line.run.q, curv.run.q) and np.array_equal(line.run.wheel, curv.run.wheel)


def test_a_flat_straight_line_is_centred_running() -> None:
    """No curve and no irregularity: the coach stays at its static loads (Q within 1e-6)."""
    lr = scenarios.line_run(200, _flat(200.0), None, "RR", "hertz-fastsim", duration=0.5, progress=False)
    q = lr.run.wheel_output("Q")
    assert np.abs(q / q[0] - 1).max() < 1e-6
    assert lr.position()[0] == pytest.approx(lr.x_start + lr.run.speed * lr.run.t[0])


@pytest.mark.parametrize(
    ("keys", "match"),
    [
        ({"irregularity_band": [70.0, 3.0]}, "shortest first"),
        ({"irregularity": "file"}, "irregularity_file"),
        ({"curve_radius": 1200.0, "curve_start": 900.0}, "beyond route_length"),
        ({"curve_radius": 50.0}, "100 m"),
        ({"irregularity": "erri-b176-medium"}, "irregularity"),
    ],
)
def test_deck_refuses_bad_input_by_name(keys, match) -> None:
    line = case_types()["line"]
    with pytest.raises(InputError, match=match):
        validate("line", {**line.defaults, **keys})
