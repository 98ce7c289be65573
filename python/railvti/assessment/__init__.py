"""The standards' assessment quantities of a run: EN 14363 (running safety, track loading,
ride characteristics), EN 12299 (ride comfort) and Sperling's ride index.

>>> from railvti import scenarios
>>> from railvti.assessment import assess
>>> run = scenarios.hunting(300, contact="hertz-fastsim", duration=1.0)
>>> print(assess(run))            # the one-screen table with limits and verdicts

Modules, one concept each: :mod:`~railvti.assessment.filters` (the standards' filters as
analogue transfer functions and their digital forms), :mod:`~railvti.assessment.windows`
(sliding means over distance), :mod:`~railvti.assessment.forces` (Y/Q, Sigma Y, Q and their
limits), :mod:`~railvti.assessment.motions` (accelerations of points on the bodies),
:mod:`~railvti.assessment.comfort` (Sperling's Wz, EN 12299's N_MV),
:mod:`~railvti.assessment.table` (the table, its text and HDF5 forms) and
:mod:`~railvti.assessment.assess` (the whole assessment of a run). docs/assessment.md.
"""

from __future__ import annotations

from .assess import assess
from .comfort import NMV, n_mv, sperling_wz, sperling_wz_piecewise, sperling_wz_sine
from .filters import Filter, Section, butterworth_bandpass, butterworth_lowpass, sperling, weighting
from .forces import (
    en14363_sum_y_limit,
    flange_climb_ratio,
    prudhomme_limit,
    q_limit,
    static_wheel_load,
    track_shifting_force,
)
from .motions import derivative_error, point_acceleration
from .table import Assessment, Row
from .windows import percentile_abs, sliding_mean, sliding_rms, time_window

__all__ = [
    "assess",
    "Assessment",
    "Row",
    "Filter",
    "Section",
    "weighting",
    "sperling",
    "butterworth_lowpass",
    "butterworth_bandpass",
    "sperling_wz",
    "sperling_wz_sine",
    "sperling_wz_piecewise",
    "NMV",
    "n_mv",
    "static_wheel_load",
    "flange_climb_ratio",
    "track_shifting_force",
    "prudhomme_limit",
    "en14363_sum_y_limit",
    "q_limit",
    "point_acceleration",
    "derivative_error",
    "sliding_mean",
    "sliding_rms",
    "time_window",
    "percentile_abs",
]
