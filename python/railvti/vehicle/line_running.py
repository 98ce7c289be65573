"""The coach on a real line (railvti.scenarios.line_run): an irregular track (measured or from
a standard spectrum) with or without a curve, from the static equilibrium on perfect track
before the irregularity's faded start, at the line speed.

The irregularity (railvti.vehicle.irregular_track) and the curve (railvti.vehicle.curving)
enter the same run: both are read at the wheels' positions x_start + v t + a_w along the
track. The assessment of the run (EN 14363, EN 12299) is :func:`railvti.assessment.assess`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _checks
from ..errors import InputError
from ..track.curve import TrackCurve
from ..track.irregularity import TrackIrregularity
from .curving import attached_curve
from .equilibrium import contact_state, static_equilibrium
from .irregular_track import check_irregularity, fade_in, on_track, run_span
from .params import Coach
from .run_result import SimulationResult
from .simulate import exact_modal, simulate
from .systems import check_variant, resolve_geometry, run_output_dt, scenario_system, time_step

__all__ = ["LineRun", "line_run"]


@dataclass(frozen=True)
class LineRun:
    """A run over a line.

    Attributes
    ----------
    run : SimulationResult
    irregularity : TrackIrregularity
        The track as run (faded in).
    curve : TrackCurve or None
    x_start : float
        The coach's reference (carbody centre) at t = 0, m along the track.
    coach : Coach
    """

    run: SimulationResult
    irregularity: TrackIrregularity
    curve: TrackCurve | None
    x_start: float
    coach: Coach

    def position(self) -> np.ndarray:
        """The reference's position along the track at the outputs, m."""
        return self.x_start + self.run.speed * self.run.t


def line_run(
    speed_kmh: float | None = None,
    irregularity: TrackIrregularity | None = None,
    curve: TrackCurve | None = None,
    variant: str = "RR",
    contact: str = "hertz-fastsim",
    *,
    speed: float | None = None,
    duration: float | None = None,
    x_start: float | None = None,
    h: float | None = None,
    output_dt: float | None = None,
    lead_in: float = 20.0,
    coach: Coach | None = None,
    **kw: Any,
) -> LineRun:
    """The coach over an irregular line, through a curve if given.

    Parameters
    ----------
    speed_kmh : float, optional
        Speed, km/h (or ``speed`` in m/s, exactly one).
    irregularity : TrackIrregularity
        The track's irregularity along x (railvti.track: ``generate_irregularity`` or
        ``read_irregularity_csv``); it also sets the route's extent.
    curve : TrackCurve, optional
        A curve on the same x (any variant).
    variant, contact : str
        'RR', 'FR', 'RF' or 'FF'; the contact model.
    duration : float, optional
        Simulated time, s; default: until the leading wheelset reaches the irregularity's end.
    x_start : float, optional
        The coach's reference position at t = 0, m; default: the trailing wheelset at the
        irregularity's start.
    h, output_dt : float, optional
        Time step and output interval, s (the variant's defaults; output 10 ms shortened to
        resolve the sleeper passing and hunting).
    lead_in : float
        The irregularity is zero up to the leading wheelset's start and faded in over this
        length, m, so that the run starts from its static equilibrium on perfect track.
    coach : Coach, optional
    **kw
        Passed to simulate and to the variant's system.

    Returns
    -------
    LineRun
    """
    if irregularity is None:
        raise InputError("line_run needs an irregularity (a railvti.track.TrackIrregularity)")
    irr = check_irregularity(irregularity)
    if curve is not None and not isinstance(curve, TrackCurve):
        raise InputError(f"curve must be a railvti.track.TrackCurve, got {type(curve).__name__}")
    v = _checks.speed_si(speed, speed_kmh)
    check_variant(variant, contact, "line_run")
    coach = coach or Coach()
    kw["geometry"] = resolve_geometry(contact, kw.get("geometry"))
    sy, _ = scenario_system(variant, coach, v, kw)
    exact = exact_modal(sy, kw.get("integrator", "hht"), kw.get("alpha", 0.0), kw.get("modal_step"))
    h = time_step(sy, h, exact)
    output_dt = run_output_dt(sy, v, h, output_dt, 0.01)
    xw = np.asarray(sy.x_wheelsets, dtype=float)
    x0, duration = run_span(irr, xw, v, h, x_start, duration)
    if lead_in != 0.0:
        irr = fade_in(irr, x0 + float(xw.max()), _checks.non_negative("lead_in", lead_in))
    with contact_state(sy, contact, kw.pop("bem", None), kw.pop("bem_options", None)) as st:
        with attached_curve(sy, curve, v, x0, duration, coach), on_track(sy, irr, v, x0):
            q0, v0, _ = static_equilibrium(sy, v, contact, bem=st, return_velocity=True)
        run = simulate(
            sy,
            v,
            duration,
            contact=contact,
            h=h,
            output_dt=output_dt,
            q0=q0,
            v0=v0,
            bem=st,
            irregularity=irr,
            curve=curve,
            x_start=x0,
            coach=coach,
            **kw,
        )
    return LineRun(run=run, irregularity=irr, curve=curve, x_start=x0, coach=coach)
