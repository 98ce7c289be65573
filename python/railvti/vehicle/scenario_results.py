"""The results of the scenarios (railvti.scenarios): centred running, the bifurcation
sweep and the critical speed, with their units."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._checks import to_kmh
from .run_result import WHEEL_SIDES, SimulationResult

__all__ = ["CentredRunning", "Bifurcation", "CriticalSpeed", "WHEEL_SIDES", "kmh_label"]


def kmh_label(speed: Any) -> Any:
    """A speed (or speeds), m/s, as the km/h of a label in a results file: to 1e-9 km/h, so
    that a speed given in km/h (a deck's ``speed_kmh``, a sweep's ``speeds_kmh``) is stored
    as given."""
    out = np.round(to_kmh(np.asarray(speed, dtype=float)), 9)
    return float(out) if out.ndim == 0 else out


@dataclass(frozen=True)
class CentredRunning:
    """Centred running: static equilibrium and a short run from it.

    Attributes
    ----------
    Q, Y : ndarray (2, 4)
        Vertical and lateral (track y, + left) wheel forces at the end of the run,
        [wheel 0 left / 1 right, wheelset], N.
    static_wheel_load : float
        Weight of the coach / 8, N.
    q_static : ndarray
        Static equilibrium state.
    run : SimulationResult
    speed : float
        The speed, m/s (``speed_kmh``: km/h, for labels).
    contact : str
        The contact model.
    patch : FastsimResult or BemPatch
        The leading wheelset's right contact patch at the end of the run (the paper's
        Figs 11-14). contact='bem': the BEM fields themselves (pressure, tractions, slip
        velocity, friction power density on the 0.75 mm grid). Otherwise: Hertz pressure,
        FASTSIM tractions, slip and friction power density on a 40 x 40 strip grid of the
        Hertz ellipse, from the run's normal force, semi-axes and creepages.
    variant : str
        'RR', 'FR' or 'RF'.
    rim_angle : ndarray (2, 4) or None
        Variants FR and FF: the change of the rim-rail relative angle at the end of the run,
        rad [wheel, wheelset]: rim_camber - rail_roll (+: the inner edge, towards the track
        centre, rises; railvti.vehicle.flexible_points.rim_rail_angle_change); None for RR and RF.
    rim_camber : ndarray (2, 4) or None
        Variants FR and FF: the rims' elastic camber alone, rad, same convention
        (railvti.vehicle.flexible_points.rim_camber_change); None for RR and RF.
    rail_roll : ndarray (2, 4) or None
        Variants FR and FF: the rail head's elastic roll under each wheel, rad, same convention
        (railvti.vehicle.flexible_points.rail_head_roll; zero on FR's rigid track); None otherwise.
    rail : ndarray (nt, 3, 2, 4) or None
        Variant RF: the rail head's motion under each wheel at the run's outputs, the pose
        (y m, z m, roll rad) of the element under wheel [., ., wheel, wheelset] in the
        vehicle's frame (RingSystem.rail_deflection); None otherwise.
    system : System
        The system the run used (railvti.vehicle.systems): labels its coordinates without
        rebuilding it.
    layouts : list
        Variants FR and FF: the wheelsets' layouts with the mode labels; [] otherwise.
    """

    Q: np.ndarray
    Y: np.ndarray
    static_wheel_load: float
    q_static: np.ndarray
    run: SimulationResult
    speed: float
    contact: str
    patch: Any = None
    variant: str = "RR"
    rim_angle: np.ndarray | None = None
    rail: np.ndarray | None = None
    rim_camber: np.ndarray | None = None
    rail_roll: np.ndarray | None = None
    system: Any = field(default=None, repr=False, compare=False)
    layouts: list = field(default_factory=list, repr=False, compare=False)

    @property
    def speed_kmh(self) -> float:
        """The speed, km/h (for labels)."""
        return to_kmh(self.speed)

    @property
    def q_error(self) -> float:
        """max |Q / static load - 1| over the eight wheels."""
        return float(np.max(np.abs(self.Q / self.static_wheel_load - 1.0)))

    def case_data(self) -> tuple[dict, dict]:
        """The final loads' part of a results file: (datasets, scalars), each name ->
        (value, unit[, labels])."""
        final = {
            "axes": ["wheel", "wheelset"],
            "wheel": WHEEL_SIDES,
            "wheelset": [f"ws{w + 1}" for w in range(np.shape(self.Q)[-1])],
        }
        data = {"Q_final": (self.Q, "N", final), "Y_final": (self.Y, "N", final)}
        scalars = {"static_wheel_load": (self.static_wheel_load, "N"), "max_Q_error": (self.q_error, "1")}
        return data, scalars


@dataclass(frozen=True)
class Bifurcation:
    """Limit-cycle amplitude of the leading wheelset against speed.

    The speeds are stored in m/s; their km/h twins for labels are the properties
    ``speeds_kmh``, ``critical_kmh``, ``flange_kmh``, ``extended_kmh``, ``no_decay_below_kmh``
    and ``no_cycle_up_to_kmh``.

    Attributes
    ----------
    speeds : ndarray
        Swept speeds, m/s (``speeds_kmh``: km/h).
    upper : ndarray
        Amplitude (m) on the branch followed down in speed from a large limit cycle.
    decay : ndarray
        Amplitude (m) after ``duration`` from a small disturbance ``y_small`` (0: decayed).
    critical : float
        Nonlinear critical speed, m/s (``critical_kmh``: km/h): the lowest speed with a sustained
        limit cycle on the upper branch (amplitude > threshold), to the sweep's step. NaN when
        there is none: see ``no_decay_below`` and ``no_cycle_up_to``.
    flange : float
        Lowest speed of the upper branch with an amplitude above ``flange_amplitude``
        (flange-contact hunting), m/s (``flange_kmh``: km/h).
    linear : float or None
        A linear critical speed to compare with, m/s (not set by :func:`bifurcation`).
    branch : str
        Which cycle defines ``critical``: 'flange cycle' (the leading bogie's flanges
        carry load in the cycle at that speed: max flange normal force above 1 % of the static
        wheel load over the last second), 'tread cycle' (no flange contact), or 'none'.
    branch_amplitude : float
        The leading wheelset's amplitude in that cycle, m (compare with the flange clearance,
        about 6.3 mm for S1002 / UIC60 1:40).
    branch_flange_force : float
        Max flange normal force on the leading bogie's wheels in that cycle (last second), N.
    extended : ndarray
        Speeds below the requested sweep that were added because the cycle had not died at
        its bottom (empty when the sweep sufficed), m/s (``extended_kmh``: km/h).
    no_decay_below : float
        NaN when the branch died within the (extended) sweep; otherwise the floor ``v_min``
        at which the extension stopped with the cycle still alive: the critical speed is
        below it and ``critical`` is NaN ("below X km/h: no decay found"); m/s
        (``no_decay_below``: m/s).
    no_cycle_up_to : float
        NaN, or the top of the sweep when no cycle was sustained even there (critical speed
        above the sweep; ``critical`` NaN), m/s (``no_cycle_up_to_kmh``: km/h).
    variant : str
        'RR', 'FR', 'RF' or 'FF'.
    details : dict
        'flange_force' (N, per speed); variant FR also 'h' (the step at each speed, s) and
        'modal_restarts' (speeds, m/s, at which the upper branch's modal coordinates were
        restarted from the static state instead of carried over; empty when every mode
        set matched).
    """

    speeds: np.ndarray
    upper: np.ndarray
    decay: np.ndarray
    critical: float
    threshold: float
    flange: float = float("nan")
    linear: float | None = None
    details: dict = field(default_factory=dict)
    branch: str = "none"
    branch_amplitude: float = float("nan")
    branch_flange_force: float = float("nan")
    extended: np.ndarray = field(default_factory=lambda: np.zeros(0))
    no_decay_below: float = float("nan")
    no_cycle_up_to: float = float("nan")
    variant: str = "RR"

    @property
    def speeds_kmh(self) -> np.ndarray:
        """Swept speeds, km/h."""
        return to_kmh(np.asarray(self.speeds))

    @property
    def critical_kmh(self) -> float:
        """Nonlinear critical speed, km/h (NaN: none, see :attr:`message`)."""
        return to_kmh(self.critical)

    @property
    def flange_kmh(self) -> float:
        """Lowest speed of flange-contact hunting on the upper branch, km/h."""
        return to_kmh(self.flange)

    @property
    def linear_kmh(self) -> float | None:
        """The linear critical speed given to compare with, km/h (None: not given)."""
        return None if self.linear is None else to_kmh(self.linear)

    @property
    def extended_kmh(self) -> np.ndarray:
        """Speeds added below the requested sweep, km/h."""
        return to_kmh(np.asarray(self.extended))

    @property
    def no_decay_below_kmh(self) -> float:
        """The extended sweep's floor with the cycle still alive, km/h (NaN otherwise)."""
        return to_kmh(self.no_decay_below)

    @property
    def no_cycle_up_to_kmh(self) -> float:
        """The top of a sweep without a sustained cycle, km/h (NaN otherwise)."""
        return to_kmh(self.no_cycle_up_to)

    def case_data(self, steps: bool = False) -> tuple[dict, dict]:
        """The sweep's part of a results file: (datasets, scalars), each name -> (value,
        unit[, labels]); speeds as km/h labels (:func:`kmh_label`); ``steps``: the time step
        at each speed too (``details['h']``, the flexible variants)."""
        axis = {"axes": ["speed"]}
        data: dict[str, tuple] = {"speeds_kmh": (kmh_label(self.speeds), "km/h", axis)}
        if steps:
            data["step"] = (self.details["h"], "s", {"axes": ["speed"], "meaning": "time step at each speed"})
        data["upper_amplitude"] = (self.upper, "m", axis)
        data["decay_amplitude"] = (self.decay, "m", axis)
        data["upper_flange_force"] = (self.details["flange_force"], "N", axis)
        scalars = {
            "critical_speed_nonlinear": (kmh_label(self.critical), "km/h"),
            "critical_branch": (self.branch, ""),
            "critical_branch_amplitude": (self.branch_amplitude, "m"),
            "no_decay_below_kmh": (kmh_label(self.no_decay_below), "km/h"),
            "no_cycle_up_to_kmh": (kmh_label(self.no_cycle_up_to), "km/h"),
            "flange_hunting_speed": (kmh_label(self.flange), "km/h"),
        }
        return data, scalars

    @property
    def message(self) -> str:
        """One line: the nonlinear critical speed and its branch, or why there is none."""
        if np.isfinite(self.no_decay_below_kmh):
            return (
                f"below {self.no_decay_below_kmh:.0f} km/h: no decay found (the cycle is "
                f"sustained at every speed swept down to there)"
            )
        if np.isfinite(self.no_cycle_up_to_kmh):
            return f"no sustained cycle up to {self.no_cycle_up_to_kmh:.0f} km/h"
        ext = f"; sweep extended down to {self.extended_kmh.min():.0f} km/h" if self.extended_kmh.size else ""
        return (
            f"nonlinear critical speed {self.critical_kmh:.0f} km/h ({self.branch}, "
            f"amplitude {self.branch_amplitude * 1e3:.2f} mm, max flange force "
            f"{self.branch_flange_force / 1e3:.1f} kN{ext})"
        )


@dataclass(frozen=True)
class CriticalSpeed:
    """A critical speed and what defines it.

    Attributes
    ----------
    speed : float
        The critical speed, m/s; NaN when the nonlinear sweep found none (see ``message``).
        In km/h: the property ``kmh`` (or ``float()``), for labels.
    method : str
        'linear' or 'nonlinear'.
    branch : str
        nonlinear: 'tread cycle', 'flange cycle' or 'none' (:class:`Bifurcation`); linear:
        'linear (equivalent conicity)'.
    damper_state : str
        The dry-friction yaw damper's state: linear, :data:`DAMPER_STATES`; nonlinear, 'as
        simulated (stick-slip, regularised)'.
    frequency_hz : float
        linear: the hunting frequency at the critical speed; nonlinear: NaN.
    no_decay_below : float
        nonlinear: the floor of the extended sweep where the cycle was still alive (NaN
        otherwise), m/s (``no_decay_below_kmh``: km/h).
    bifurcation : Bifurcation or None
    variant : str
        'RR', 'FR', 'RF' or 'FF'.
    """

    speed: float
    method: str
    branch: str
    damper_state: str
    frequency_hz: float = float("nan")
    no_decay_below: float = float("nan")
    bifurcation: Bifurcation | None = None
    variant: str = "RR"

    def __float__(self) -> float:
        return float(self.kmh)

    @property
    def kmh(self) -> float:
        """The critical speed, km/h (NaN: none found)."""
        return to_kmh(self.speed)

    @property
    def no_decay_below_kmh(self) -> float:
        """nonlinear: the extended sweep's floor with the cycle still alive, km/h (else NaN)."""
        return to_kmh(self.no_decay_below)

    @property
    def message(self) -> str:
        """One line: the value, its method, branch and damper state, or why there is none."""
        if self.method == "nonlinear" and self.bifurcation is not None:
            return self.bifurcation.message
        return (
            f"linear critical speed {self.kmh:.1f} km/h, {self.frequency_hz:.2f} Hz; yaw "
            f"damper {self.damper_state}"
        )
