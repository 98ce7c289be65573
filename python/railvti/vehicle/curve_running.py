"""The coach through a curve (railvti.scenarios.curving): entering it on its transition,
running on the arc and leaving it, with the steady curving quantities per wheel.

Steady curving (:meth:`CurveRun.steady`): the means over the stretch where the whole coach
is on the arc, after the wheelsets' first 20 % of it, per wheel: Q and Y (track axes), Y/Q,
the angle of attack (the wheelset's yaw against the track's tangent, positive nose to the
left), the share of the time with flange contact, T gamma; per wheelset the sum of the
lateral forces; and the check of the whole coach's lateral balance, sum Y = M a_unb
(:meth:`railvti.track.TrackCurve.unbalanced_acceleration`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .. import _checks
from ..errors import InputError
from ..track.curve import TrackCurve
from .equilibrium import contact_state
from .model_choice import auto_contact, auto_variant
from .params import Coach
from .run_result import SimulationResult
from .simulate import simulate
from .systems import check_variant, resolve_geometry, scenario_system, time_step

__all__ = ["CurveRun", "SteadyCurving", "curving"]

#: Straight track run before the curve's start and after its end by default, m.
LEAD_IN = 30.0


@dataclass(frozen=True)
class SteadyCurving:
    """Steady curving quantities (module docstring), per [wheel (0 left, 1 right), wheelset].

    Attributes
    ----------
    Q, Y, y_over_q : ndarray (2, nw)
        Mean wheel load and lateral force (N, track axes) and Y/Q.
    angle_of_attack : ndarray (nw,)
        Mean yaw of each wheelset against the track's tangent, rad.
    flange_contact : ndarray (2, nw)
        Share of the outputs with flange contact (N_flange > 0).
    t_gamma : ndarray (2, nw)
        Mean T gamma, N.
    sum_y : ndarray (nw,)
        Mean lateral force per wheelset (both wheels), N.
    sum_y_coach, mass_times_a : float
        The whole coach's mean lateral force (vehicle frame), and its mass times the
        unbalanced lateral acceleration in the canted plane, signed as the rails push (+ left
        in a left-hand curve), N.
    cant_deficiency : float
        EN 13803's cant deficiency, m.
    window : tuple of float
        The times averaged over, s.
    """

    Q: np.ndarray
    Y: np.ndarray
    y_over_q: np.ndarray
    angle_of_attack: np.ndarray
    flange_contact: np.ndarray
    t_gamma: np.ndarray
    sum_y: np.ndarray
    sum_y_coach: float
    mass_times_a: float
    cant_deficiency: float
    window: tuple[float, float]

    def table(self) -> str:
        """One screen: per wheel Q, Y, Y/Q, flange contact, T gamma; per wheelset angle of
        attack and sum Y; the coach's balance."""
        lines = [
            f"steady curving over t = {self.window[0]:.2f}-{self.window[1]:.2f} s, "
            f"cant deficiency {self.cant_deficiency * 1e3:.0f} mm",
            "wheelset wheel      Q kN    Y kN    Y/Q  flange  Tgamma N  AoA mrad  sumY kN",
        ]
        for w in range(self.Q.shape[1]):
            for k, side in enumerate(("left", "right")):
                extra = (
                    f"  {self.angle_of_attack[w] * 1e3:8.2f}  {self.sum_y[w] / 1e3:7.2f}" if k == 0 else ""
                )
                lines.append(
                    f"{w + 1:8d} {side:5s} {self.Q[k, w] / 1e3:8.2f} {self.Y[k, w] / 1e3:7.2f} "
                    f"{self.y_over_q[k, w]:6.3f}  {self.flange_contact[k, w]:6.2f}  {self.t_gamma[k, w]:8.1f}"
                    + extra
                )
        lines.append(
            f"coach: sum Y {self.sum_y_coach / 1e3:.3f} kN against M a_unb {self.mass_times_a / 1e3:.3f} kN "
            f"({100 * (self.sum_y_coach / self.mass_times_a - 1):+.2f} %)"
            if self.mass_times_a != 0
            else f"coach: sum Y {self.sum_y_coach / 1e3:.3f} kN (balanced cant)"
        )
        return "\n".join(lines)


@dataclass(frozen=True)
class CurveRun:
    """A run through a curve: the history, the curve and where the coach was.

    Attributes
    ----------
    run : SimulationResult
    curve : TrackCurve
    x_start : float
        The coach's reference position (carbody centre) at t = 0, m along the track.
    mass : float
        The coach's mass carried by the wheels, kg.
    x_wheelsets : ndarray (nw,)
        The wheelsets' positions ahead of the reference, m.
    """

    run: SimulationResult
    curve: TrackCurve
    x_start: float
    mass: float
    x_wheelsets: np.ndarray

    def position(self) -> np.ndarray:
        """The reference's position along the track at the outputs, m."""
        return self.x_start + self.run.speed * self.run.t

    def steady(self, skip: float = 0.2) -> SteadyCurving:
        """The steady curving quantities over the outputs where every wheelset is on the arc,
        after the first ``skip`` share of that stretch (module docstring)."""
        c = self.curve
        a0 = c.start + c.transition_in
        a1 = a0 + c.arc_length
        x = self.position()
        on = (x + self.x_wheelsets.min() >= a0) & (x + self.x_wheelsets.max() <= a1)
        idx = np.flatnonzero(on)
        if idx.size < 5:
            raise InputError(
                "steady curving: fewer than 5 outputs with the whole coach on the arc "
                "(lengthen the arc or the run)"
            )
        idx = idx[int(skip * idx.size) :]
        r = self.run
        q, y = r.wheel_output("Q")[idx], r.wheel_output("Y")[idx]
        if r.rail is not None:  # the ring: Y in the vehicle's frame (the rail head rolls)
            y_frame = y - q * r.rail[idx, 2]
        else:
            y_frame = y
        yaw = np.stack([r.dof(f"ws{w + 1}_yaw")[idx] for w in range(q.shape[2])], axis=1)
        qm = q.mean(axis=0)
        ym = y.mean(axis=0)
        v = r.speed
        return SteadyCurving(
            Q=qm,
            Y=ym,
            y_over_q=np.where(qm > 0, ym / np.where(qm > 0, qm, 1.0), 0.0),
            angle_of_attack=yaw.mean(axis=0),
            flange_contact=(r.wheel_output("N_flange")[idx] > 0).mean(axis=0),
            t_gamma=r.wheel_output("T_gamma")[idx].mean(axis=0),
            sum_y=y_frame.sum(axis=1).mean(axis=0),
            sum_y_coach=float(y_frame.sum(axis=(1, 2)).mean()),
            mass_times_a=self.mass * c.unbalanced_acceleration(v) * float(np.sign(c.radius)),
            cant_deficiency=c.cant_deficiency(v),
            window=(float(r.t[idx[0]]), float(r.t[idx[-1]])),
        )


def curving(
    speed_kmh: float | None = None,
    curve: TrackCurve | None = None,
    variant: str = "RR",
    contact: str = "hertz-fastsim",
    *,
    speed: float | None = None,
    x_start: float | None = None,
    duration: float | None = None,
    h: float | None = None,
    coach: Coach | None = None,
    **kw: Any,
) -> CurveRun:
    """The coach through a curve: from the straight before it, over the transitions and the
    arc, onto the straight after it (or the part of that a given ``x_start`` and ``duration``
    cover).

    Parameters
    ----------
    speed_kmh : float, optional
        Speed, km/h (the suffixed alias of ``speed``); default 160 km/h.
    curve : TrackCurve
        The curve (radius, cant, transitions; railvti.track.TrackCurve).
    variant, contact : str
        'RR', 'FR', 'RF', 'FF' or 'auto' (variant_tolerance, variant_quantities; scene 'curve');
        'hertz-kalker', 'hertz-fastsim', 'bem' or 'auto' (the cheapest measured
        model within ``tolerance`` on ``quantities``, keywords of **kw:
        railvti.vehicle.model_choice, scene 'curve').
    speed : float, optional
        Speed, m/s.
    x_start : float, optional
        The coach's reference (carbody centre) position at t = 0, m along the track: the
        start is the steady state there. Default: the leading wheelset LEAD_IN (30 m) before
        the curve.
    duration : float, optional
        Simulated time, s; default: until the last wheelset is LEAD_IN past the curve.
    h : float, optional
        Time step, s (the variant's default).
    coach : Coach, optional
        Vehicle parameters.
    **kw
        Passed to simulate (``output_dt`` default 10 ms, ...) and to the variant's system.

    Returns
    -------
    CurveRun
    """
    if not isinstance(curve, TrackCurve):
        raise InputError(f"curve must be a railvti.track.TrackCurve, got {type(curve).__name__}")
    v = _checks.speed_si(speed, speed_kmh, 160.0)
    choice = vchoice = None
    if variant == "auto":
        variant, vchoice = auto_variant(kw, "curve")
    if contact == "auto":
        contact, choice = auto_contact(kw, "curve")
    check_variant(variant, contact, "curving")
    coach = coach or Coach()
    kw["geometry"] = resolve_geometry(contact, kw.get("geometry"))
    sy, _ = scenario_system(variant, coach, v, kw)
    xw = np.asarray(sy.x_wheelsets, dtype=float)
    x0 = curve.start - LEAD_IN - xw.max() if x_start is None else _checks.finite("x_start", x_start)
    if duration is None:
        duration = (curve.end + LEAD_IN - xw.min() - x0) / v
    duration = _checks.positive("duration", duration)
    h = time_step(sy, h)
    kw.setdefault("output_dt", 0.01)
    with contact_state(sy, contact, kw.pop("bem", None), kw.pop("bem_options", None)) as st:
        run = simulate(
            sy, v, duration, contact=contact, h=h, bem=st, curve=curve, x_start=x0, coach=coach, **kw
        )
    run = replace(run, model_choice=choice, variant_choice=vchoice)
    return CurveRun(run=run, curve=curve, x_start=x0, mass=coach.total_mass, x_wheelsets=xw)
