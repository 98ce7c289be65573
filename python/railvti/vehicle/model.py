"""An assembled System in the Fortran core: sent once, reached by a handle.

:class:`VehicleModel` copies a System's matrices, nonlinear elements, wheelset DOF maps,
contact table, material and friction into the Fortran registry (``vehicle_model_create_c``)
and frees them when the object goes away. ``System.native`` makes one per System on first
use and keeps it for the System's lifetime, so every static solve, force evaluation and
time-integration chunk of that System passes only the handle and the per-call values
(:class:`CallSettings`: speed, contact model, FASTSIM size, BEM state).
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._native import core
from .._status import check

if TYPE_CHECKING:   # pragma: no cover
    from .assembly import System

#: Contact models: name -> Fortran id (vehicle_contact CMODEL_*). 'bem': the BEM normal +
#: steady-rolling solvers (railvti.vehicle.bem), with the Hertz + Kalker tangent in Newton.
CONTACT_MODELS = {"hertz-kalker": 1, "hertz-fastsim": 2, "bem": 3}
#: Outputs per wheel (second index of SimulationResult.wheel).
WHEEL_OUTPUTS = ("Q", "Y", "Fx", "N_tread", "N_flange", "xi", "eta", "spin", "energy",
                 "contact_angle", "a", "b", "y_cp", "M_x", "M_spin")
NWO = len(WHEEL_OUTPUTS)


@dataclass(frozen=True)
class CallSettings:
    """The per-call values of the Fortran vehicle shims.

    Attributes
    ----------
    speed : float
        Forward speed v0, m/s.
    contact : int
        Fortran contact model id (:data:`CONTACT_MODELS`).
    fastsim_n : int
        FASTSIM strips and points per strip.
    bem : int
        Handle of the BEM contact state (contact 'bem'), else 0.
    """

    speed: float
    contact: int
    fastsim_n: int = 8
    bem: int = 0

    def args(self) -> tuple[float, int, int, int]:
        """(speed, contact, fastsim_n, bem) in the shims' order."""
        return (self.speed, self.contact, self.fastsim_n, self.bem)


class VehicleModel:
    """A System stored in the Fortran core, freed when this object is collected.

    Parameters
    ----------
    system : System
        The assembled system (its arrays are copied into Fortran once).

    Raises
    ------
    InputError
        The system's arrays are inconsistent (table size, DOF indices) or the core's model
        registry is full.
    """

    def __init__(self, system: "System") -> None:
        t = system.table
        handle, info = core.vehicle_model_create_c(
            system.m, system.c, system.k, system.f0, system.etype, system.eg, system.epar,
            system.iws, system.itr, t.data_roll, t.y0, t.dy, t.roll0, t.droll, t.r_nominal, t.r0,
            t.material.shear_modulus, system.friction)
        check(info, "vehicle model")
        self.handle = int(handle)
        self.n = int(system.n)
        self.n_wheelsets = int(system.iws.shape[1])
        self._free = weakref.finalize(self, core.vehicle_model_free_c, self.handle)

    def close(self) -> None:
        """Free the Fortran model now (idempotent; later calls give InputError)."""
        self._free()

    @property
    def alive(self) -> bool:
        """Whether the Fortran model still exists."""
        return self._free.alive

    def force(self, cs: CallSettings, q: np.ndarray, v: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
        """F(q, v), wheel outputs (NWO, 2, nw), dF/dq, dF/dv and the status."""
        return core.vehicle_force_c(self._handle(), self.n_wheelsets, *cs.args(), q, v, NWO)

    def static(self, cs: CallSettings, q: np.ndarray, tol: float, maxit: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, float, int]:
        """Steady state from q (updated in place): v, F, wheel outputs, iterations, last
        correction and the status."""
        return core.vehicle_static_c(self._handle(), self.n_wheelsets, *cs.args(), tol, maxit, q,
                                     NWO)

    def run(self, cs: CallSettings, h: float, nsteps: int, nevery: int, alpha: float,
            tol: float, maxit: int, maxsub: int, qmax: float, rtol: float, t: np.ndarray,
            q: np.ndarray, v: np.ndarray, a: np.ndarray, nout: int) -> tuple:
        """nsteps HHT steps from (t, q, v, a), all updated in place: (tout, qout, vout, wout,
        stats, status, tfail); rtol: Newton's residual tolerance, max |r| in N or N m; see
        vehicle_newmark%newmark_run."""
        return core.vehicle_run_c(self._handle(), self.n_wheelsets, *cs.args(), h, nsteps,
                                  nevery, alpha, tol, maxit, maxsub, qmax, rtol, t, q, v, a, nout, NWO)

    def _handle(self) -> int:
        # a closed model passes 0, which the core rejects as a bad handle
        return self.handle if self._free.alive else 0
