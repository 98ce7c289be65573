"""The result of a time simulation: :class:`SimulationResult` (the histories, their units and
the labels of their HDF5 layout) and :class:`WheelSummary` (the eight wheels over a window).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .. import _checks
from ..errors import InputError
from .analytic import nadal_limit
from .model import WHEEL_OUTPUTS

__all__ = ["WHEEL_SIDES", "WHEEL_UNITS", "STAT_UNITS", "SimulationResult", "WheelSummary", "flange_angle"]

#: The wheels of a wheelset in the results' axes (index 0 left, 1 right).
WHEEL_SIDES = ["left", "right"]
#: Units of the per-wheel outputs (:data:`~railvti.vehicle.model.WHEEL_OUTPUTS`).
WHEEL_UNITS = {
    "Q": "N",
    "Y": "N",
    "Fx": "N",
    "N_tread": "N",
    "N_flange": "N",
    "spin": "1/m",
    "energy": "J",
    "contact_angle": "rad",
    "a": "m",
    "b": "m",
    "y_cp": "m",
    "M_x": "N m",
    "M_spin": "N m",
    "T_gamma": "N",
    "F_t": "N",
}
#: Units of SimulationResult.stats (stored as stat_NAME).
STAT_UNITS = {
    "newton_iterations": "1",
    "tangents": "1",
    "max_error_estimate": "m",
    "steps": "1",
    "substepped_steps": "1",
    "smallest_step": "s",
    "newton_residual": "1 (relative to stat_load_scale)",
    "newton_residual_max": "1 (relative to stat_load_scale)",
    "newton_correction": "m or rad",
    "newton_correction_max": "m or rad",
    "load_scale": "N",
    "newton_tol": "m or rad",
    "newton_rtol": "1",
    "wall_time": "s",
    "real_time_factor": "1 (wall time / simulated time)",
    "failed_at": "s",
    "interrupted_at": "s",
    "bem_grid": "1, 1, m (nx, ny, dx)",
}


def _dof_unit(name: str, rate: bool) -> str:
    """'m' or 'rad' (per second with rate) of a state name such as 'ws1_y', 'bogie1_roll'."""
    last = name.rsplit("_", 1)[-1]
    if name.startswith("ring_res") and last == "r":
        last = "roll"  # variant RF's residual coordinate of the element's roll
    if last in ("x", "y", "z"):
        unit = "m"
    elif last in ("roll", "pitch", "yaw", "beta"):
        unit = "rad"
    else:
        unit = "1"  # modal coordinates: mass-normalised
    return f"{unit}/s" if rate and unit != "1" else unit


def _pose_labels(nw: int) -> dict[str, Any]:
    """Labels of an (nt, 3, 2, nw) array of rail poses (y, z, roll) under each wheel."""
    return {
        "axes": ["t", "component", "wheel", "wheelset"],
        "component": ["y", "z", "roll"],
        "column_units": ["m", "m", "rad"],
        "wheel": WHEEL_SIDES,
        "wheelset": [f"ws{w + 1}" for w in range(nw)],
    }


@dataclass(frozen=True)
class SimulationResult:
    """Time histories of one run.

    Attributes
    ----------
    t : ndarray (nt,)
        Output times, s.
    q, v : ndarray (nt, n)
        Displacements (m, rad) and velocities of every DOF (``dof_names``).
    wheel : ndarray (nt, 12, 2, nw)
        Per output time, quantity :data:`~railvti.vehicle.model.WHEEL_OUTPUTS`, wheel (0 left,
        1 right), wheelset:
        Q vertical and Y lateral (track y, + left) force of the rail on the wheel (N), the
        longitudinal creep force, the tread and flange normal forces, creepages, spin, Hertz
        energy, contact angle and semi-axes of the more loaded point, T gamma (the creep
        forces' work on the creepages summed over the wheel's points, N) and the tangential
        creep force of the more loaded point (N).
    speed : float
        Forward speed, m/s.
    contact : str
        Contact model.
    stats : dict
        Newton iterations, tangent evaluations, max local error estimate (m), steps, wall
        time (s), real-time factor (wall / simulated); Newton's convergence:
        ``newton_residual`` / ``newton_residual_max`` (max |r| over the DOFs after the last
        iteration of the last accepted step / the largest over all accepted steps, relative to
        ``load_scale``, the static wheel load in N; rotations' residuals in N m are divided by
        the same N, i.e. per metre of lever arm), ``newton_correction`` /
        ``newton_correction_max`` (the last correction max |dq|, m or rad, likewise), and the
        tolerances ``newton_tol`` (correction) and ``newton_rtol`` (residual, relative); with
        contact='bem' also the BEM counters (:data:`railvti.vehicle.bem.COUNTERS`, prefixed
        ``bem_``) and ``bem_solves_per_step`` (normal + rolling solve pairs per time step, all
        wheels).
    bem_patches : dict or None
        contact='bem': the final BEM fields (:class:`railvti.vehicle.bem.BemPatch`) of the
        loaded candidate point of every wheel, keyed (wheelset, wheel), both 0-based.
    friction : float
        Wheel-rail friction coefficient of the run.
    flange_angle : float
        Flange angle of the wheel profile, rad (:func:`flange_angle`: the largest contact
        angle of the table's flange point on the flange side), for Nadal's limit.
    streamed : str
        '' for a history kept in memory; for a run streamed to HDF5 (``stream_to``), the
        'FILE::GROUP' holding the whole history: ``t``, ``q``, ``v`` and ``wheel`` here
        then hold only its last ``stream_tail`` seconds.
    rail : ndarray (nt, 3, 2, nw) or None
        Variant RF (a system on the ring track): the rail head's motion under each wheel at the
        outputs, the pose (y m, z m, roll rad; vehicle frame) of the element under wheel
        [., ., wheel, wheelset] (``RingSystem.rail_deflection``, after a completed run); None
        on rigid track. The ring's modal coordinates are the last columns of ``q``, named in
        ``dof_names``.
    model_choice : ModelChoice or None
        A scenario run with ``contact='auto'``: the contact model chosen, its scene and the
        error to expect (:mod:`railvti.vehicle.model_choice`); None otherwise.
    variant_choice : VariantChoice or None
        A scenario run with ``variant='auto'``: the variant chosen, likewise.
    irregularity : str
        '' on the perfect track; else the irregular track's source (a spectrum with its seed
        and band, or a file), its extent and x_start (``simulate(irregularity=...)``).
    track_input : ndarray (nt, 3, 2, nw) or None
        On an irregular track: the pose (y m, z m, roll rad) of the rail element under each
        wheel from the irregularity alone at the outputs (docs/vehicle_irregularity.md),
        [., ., wheel, wheelset]; None on the perfect track.

    Per wheel: :meth:`wheels` (amplitude per wheelset, Q, Y, Y/Q against Nadal's limit, the
    worst wheel) and :attr:`nadal`.
    """

    #: The units this class gives its fields where its docstring does not end in one
    #: (railvti.runner.result_objects.save reads them here: the result owns its file layout's units).
    FIELD_UNITS: ClassVar[dict[str, Any]] = {
        "t": "s",
        "q": "m or rad (per dof_names)",
        "v": "m/s or rad/s (per dof_names)",
        "wheel": "per quantity: see the quantities and quantity_units attributes",
        "speed": "m/s",
        "h": "s",
        "friction": "1",
        "flange_angle": "rad",
        "rail": "m, m, rad (per component: y, z, roll of the element under each wheel)",
        "irregularity": "text",
        "track_input": "m, m, rad (per component: y, z, roll of the irregular rail under each wheel)",
        "stats": STAT_UNITS,
    }
    #: Units of the per-wheel outputs and of the statistics (for the runner's records).
    WHEEL_UNITS: ClassVar[dict[str, str]] = WHEEL_UNITS
    STAT_UNITS: ClassVar[dict[str, str]] = STAT_UNITS

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    wheel: np.ndarray
    dof_names: tuple
    speed: float
    contact: str
    h: float
    stats: dict = field(default_factory=dict)
    bem_patches: dict | None = None
    friction: float = float("nan")
    flange_angle: float = float("nan")
    streamed: str = ""
    rail: np.ndarray | None = None
    model_choice: Any = None
    variant_choice: Any = None
    irregularity: str = ""
    track_input: np.ndarray | None = None

    def _save_attrs(self) -> dict:
        """Labels written beside the arrays by :func:`railvti.runner.result_objects.save`."""
        nw = self.wheel.shape[-1]
        return {
            "q": {"axes": ["t", "state"], "dof_names": list(self.dof_names)},
            "v": {"axes": ["t", "state"], "dof_names": list(self.dof_names)},
            "t": {"axes": ["t"]},
            "wheel": {
                "axes": ["t", "quantity", "wheel", "wheelset"],
                "quantities": list(WHEEL_OUTPUTS),
                "quantity_units": [WHEEL_UNITS.get(n, "1") for n in WHEEL_OUTPUTS],
                "wheel": WHEEL_SIDES,
                "wheelset": [f"ws{w + 1}" for w in range(nw)],
            },
            **{name: _pose_labels(nw) for name in ("rail", "track_input") if getattr(self, name) is not None},
        }

    def case_data(self) -> tuple[dict, dict]:
        """The run's part of a results file (a deck case of type ``vehicle``): (datasets,
        scalars), each name -> (value, unit[, labels]): the history (t, q, v with each
        column's unit, the per-wheel outputs), the statistics and the wheels' maxima over the
        last second (:meth:`wheels`; its summary line: ``wheels().line()``)."""
        data: dict[str, tuple] = {}
        scalars: dict[str, tuple] = {}
        nw = self.wheel.shape[-1]
        wheelsets = [f"ws{w + 1}" for w in range(nw)]
        names = list(self.dof_names)
        data["t"] = (self.t, "s", {"axes": ["t"]})
        data["q"] = (
            self.q,
            "m or rad (per column: column_units)",
            {
                "axes": ["t", "state"],
                "dof_names": names,
                "column_units": [_dof_unit(n, False) for n in names],
            },
        )
        data["v"] = (
            self.v,
            "m/s or rad/s (per column: column_units)",
            {"axes": ["t", "state"], "dof_names": names, "column_units": [_dof_unit(n, True) for n in names]},
        )
        data["y_ws1"] = (self.y_ws1, "m", {"axes": ["t"]})
        data["vy_ws1"] = (self.vy_ws1, "m/s", {"axes": ["t"]})
        per_wheel = {"axes": ["t", "wheel", "wheelset"], "wheel": WHEEL_SIDES, "wheelset": wheelsets}
        for i, name in enumerate(WHEEL_OUTPUTS):
            data[f"wheel_{name}"] = (self.wheel[:, i], WHEEL_UNITS.get(name, "1"), per_wheel)
        for k, v in self.stats.items():
            scalars[f"stat_{k}"] = (v, STAT_UNITS.get(k, "1"))
        ws = self.wheels()
        last = {"over": f"the last {ws.window:g} s"}
        data["ws_y"] = (
            np.stack([self.dof(f"ws{w + 1}_y") for w in range(nw)], 1),
            "m",
            {"axes": ["t", "wheelset"], "wheelset": wheelsets},
        )
        data["wheel_amplitude"] = (ws.amplitude, "m", {"axes": ["wheelset"], "wheelset": wheelsets, **last})
        per_wheel_max = {"axes": ["wheel", "wheelset"], "wheel": WHEEL_SIDES, "wheelset": wheelsets, **last}
        data["wheel_Q_max"] = (ws.Q_max, "N", per_wheel_max)
        data["wheel_Y_max"] = (ws.Y_max, "N", per_wheel_max)
        data["wheel_YQ_max"] = (ws.YQ_max, "1", per_wheel_max)
        scalars["nadal_limit"] = (ws.nadal, "1")
        scalars["flange_angle"] = (ws.flange_angle, "rad")
        scalars["friction"] = (ws.friction, "1")
        scalars["exceeds_nadal"] = (int(ws.exceeds_nadal), "1 (flag: 1 = a wheel above Nadal's limit)")
        if self.model_choice is not None:  # contact='auto': what was chosen and why
            mc = self.model_choice
            scalars["auto_contact"] = (mc.label, "text")
            scalars["auto_scene"] = (mc.scene, "text")
            scalars["auto_choice"] = (mc.line(), "text")
            for q in mc.quantities:
                scalars[f"auto_expected_error_{q}"] = (mc.errors[q], "1 (relative, against the 0.5 mm BEM)")
        if self.variant_choice is not None:  # variant='auto'
            vc = self.variant_choice
            scalars["auto_variant"] = (vc.variant, "text")
            scalars["auto_variant_choice"] = (vc.line(), "text")
            for q in vc.quantities:
                scalars[f"auto_variant_expected_error_{q}"] = (
                    vc.errors[q],
                    "1 (relative, against the richest variant)",
                )
        if self.irregularity:
            scalars["irregularity"] = (self.irregularity, "text")
        if self.track_input is not None:
            data["track_input"] = (
                self.track_input,
                "m, m, rad (per component: y, z, roll)",
                _pose_labels(nw),
            )
        return data, scalars

    @property
    def nadal(self) -> float:
        """Nadal's limit Y/Q for this run's flange angle and friction."""
        return nadal_limit(self.flange_angle, self.friction)

    @property
    def y_over_q(self) -> np.ndarray:
        """(nt, 2, nw) flange-climb ratio of every wheel: the lateral force of the rail on the
        wheel towards the track centre (-Y on the left wheel, +Y on the right) over Q; 0
        where Q < 1 % of the largest Q of the run (wheel lifted)."""
        q = self.Q
        yout = self.Y * np.array([-1.0, 1.0])[None, :, None]
        ok = q > 0.01 * max(float(q.max()), 1e-30)
        return np.where(ok, yout / np.where(ok, q, 1.0), 0.0)

    def wheels(self, window: float = 1.0) -> "WheelSummary":
        """Per wheelset and wheel over the last ``window`` seconds: lateral amplitude, max Q,
        max |Y|, max Y/Q against Nadal's limit, and the worst wheel."""
        return WheelSummary.of(self, window)

    def dof(self, name: str) -> np.ndarray:
        """Time history of one DOF by name (e.g. 'ws1_y')."""
        if name not in self.dof_names:
            raise InputError(f"unknown DOF {name!r}")
        return self.q[:, self.dof_names.index(name)]

    def wheel_output(self, name: str) -> np.ndarray:
        """(nt, 2, nw) history of one per-wheel output."""
        if name not in WHEEL_OUTPUTS:
            raise InputError(f"unknown wheel output {name!r}; one of {WHEEL_OUTPUTS}")
        return self.wheel[:, WHEEL_OUTPUTS.index(name)]

    @property
    def y_ws1(self) -> np.ndarray:
        """Leading wheelset's lateral displacement, m."""
        return self.dof("ws1_y")

    @property
    def vy_ws1(self) -> np.ndarray:
        """Leading wheelset's lateral velocity, m/s."""
        return self.v[:, self.dof_names.index("ws1_y")]

    @property
    def Q(self) -> np.ndarray:
        """Vertical wheel forces (nt, 2, nw), N."""
        return self.wheel_output("Q")

    @property
    def Y(self) -> np.ndarray:
        """Lateral wheel forces (nt, 2, nw), N (track y, + left)."""
        return self.wheel_output("Y")


def flange_angle(table) -> float:
    """The flange angle of a contact table's wheel profile, rad: the largest contact angle of
    the flange-side candidate point (slot 1) over y >= 0 (70.0 deg for S1002 on UIC60 1:40,
    reached at y = 7 mm; beyond it the contact climbs towards the flange tip)."""
    d = table.at("delta", 1)
    return float(np.max(d[table.y >= 0.0]))


_SIDE = ("left", "right")


@dataclass(frozen=True)
class WheelSummary:
    """All eight wheels of a run over its last window (arrays (2, nw): wheel 0 left / 1 right,
    wheelset 0-based; amplitude (nw,)).

    Attributes
    ----------
    amplitude : ndarray (nw,)
        Half the peak-to-peak lateral displacement of each wheelset, m.
    Q_max, Y_max : ndarray (2, nw)
        Largest vertical force and largest |Y| (lateral, track y), N.
    YQ_max : ndarray (2, nw)
        Largest flange-climb ratio (:attr:`SimulationResult.y_over_q`).
    nadal : float
        Nadal's limit for ``flange_angle`` (rad) and ``friction``.
    worst_yq, worst_q : tuple (wheel, wheelset)
        The wheel with the largest Y/Q relative to Nadal's limit and the one with the
        largest Q.
    """

    window: float
    amplitude: np.ndarray
    Q_max: np.ndarray
    Y_max: np.ndarray
    YQ_max: np.ndarray
    nadal: float
    flange_angle: float
    friction: float
    worst_yq: tuple
    worst_q: tuple

    @classmethod
    def of(cls, res: "SimulationResult", window: float = 1.0) -> "WheelSummary":
        """The summary of ``res`` over its last ``window`` seconds."""
        k = res.t >= res.t[-1] - _checks.positive("window", window)
        nw = res.wheel.shape[-1]
        amp = np.array([0.5 * float(np.ptp(res.dof(f"ws{w + 1}_y")[k])) for w in range(nw)])
        q = res.Q[k].max(axis=0)
        y = np.abs(res.Y[k]).max(axis=0)
        yq = res.y_over_q[k].max(axis=0)
        wy = np.unravel_index(int(np.argmax(yq)), yq.shape)
        wq = np.unravel_index(int(np.argmax(q)), q.shape)
        return cls(
            window=float(window),
            amplitude=amp,
            Q_max=q,
            Y_max=y,
            YQ_max=yq,
            nadal=res.nadal,
            flange_angle=res.flange_angle,
            friction=res.friction,
            worst_yq=(int(wy[0]), int(wy[1])),
            worst_q=(int(wq[0]), int(wq[1])),
        )

    @property
    def exceeds_nadal(self) -> bool:
        """Any wheel above Nadal's limit."""
        return bool(np.any(self.YQ_max > self.nadal))

    def line(self) -> str:
        """One line naming the worst wheel (largest Y/Q against Nadal, largest Q)."""
        s, w = self.worst_yq
        sq, wq = self.worst_q
        yq = self.YQ_max[s, w]
        flag = "ABOVE" if yq > self.nadal else "below"
        return (
            f"worst wheel: wheelset {w + 1} {_SIDE[s]} Y/Q {yq:.2f} ({flag} Nadal "
            f"{self.nadal:.2f}: {math.degrees(self.flange_angle):.1f} deg, mu "
            f"{self.friction:g}); largest Q {self.Q_max[sq, wq] / 1e3:.0f} kN at wheelset "
            f"{wq + 1} {_SIDE[sq]}; amplitudes " + "/".join(f"{a * 1e3:.1f}" for a in self.amplitude) + " mm"
        )
