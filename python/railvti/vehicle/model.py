"""An assembled System in the Fortran core: sent once, reached by a handle.

:class:`VehicleModel` copies a System's matrices, nonlinear elements, wheelset DOF maps,
contact table, material and friction into the Fortran registry (``vehicle_model_create_c``)
and frees them when the object goes away. ``System.native`` makes one per System on first
use and keeps it for the System's lifetime, so every static solve, force evaluation and
time-integration chunk of that System passes only the handle and the per-call values
(:class:`CallSettings`: speed, contact model, FASTSIM size, BEM state).

Flexible bodies enter as :class:`ModalBlocks` (railvti.vehicle.modal_blocks, with the point
elements and couplings; re-exported here): modal coordinates with block-diagonal damping
(+ gyroscopic) and stiffness matrices, coupled to the rigid DOFs only through attachment points
u = Phi Q and :class:`PointElement` forces (docs/vehicle_integrator.md). A System carrying
them (``System.modal``) is attached to its handle once; the integrator condenses the modal
rows onto the points, so its cost per step is linear in the number of modes.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import core
from .._status import check
from ..errors import InputError
from .modal_blocks import (
    COUPLING_KINDS,
    POINT_ELEMENT_KINDS,
    RESIDUAL_ZETA,
    ModalBlocks,
    ModalCouplings,
    PointElement,
    RimFollow,
    compliance_block,
    with_mass,
)

__all__ = [
    "WHEEL_OUTPUTS",
    "NWO",
    "NWO_CORE",
    "RunCarry",
    "POINT_ELEMENT_KINDS",
    "PointElement",
    "RimFollow",
    "COUPLING_KINDS",
    "ModalCouplings",
    "ModalBlocks",
    "compliance_block",
    "RESIDUAL_ZETA",
    "with_mass",
    "CallSettings",
    "VehicleModel",
]

#: Outputs per wheel (second index of SimulationResult.wheel).
WHEEL_OUTPUTS = (
    "Q",
    "Y",
    "Fx",
    "N_tread",
    "N_flange",
    "xi",
    "eta",
    "spin",
    "energy",
    "contact_angle",
    "a",
    "b",
    "y_cp",
    "M_x",
    "M_spin",
    "T_gamma",
    "F_t",
)
NWO = len(WHEEL_OUTPUTS)
#: Rows per wheel the Fortran core computes and carries: WHEEL_OUTPUTS, then the contact's
#: lateral arm on the wheel (m, normal-force weighted; where flexible rims that follow the
#: contact point take their rows, vehicle_contact's output IO_ARM = 18), kept internal.
NWO_CORE = NWO + 1


class RunCarry:
    """The force F(q, v) and the wheel outputs of a run's current state, carried from one call
    of the Fortran time loop to the next (:meth:`VehicleModel.run`), as the accelerations are.

    Attributes
    ----------
    f : numpy.ndarray
        Force at the state, (n_state,), N or N m (Fortran-ordered, updated in place).
    w : numpy.ndarray
        Wheel outputs at the state, (NWO, 2, n_wheelsets).
    valid : bool
        False until a call has filled them: that call evaluates them at its start.
    """

    def __init__(self, f: np.ndarray, w: np.ndarray, valid: bool = False) -> None:
        self.f, self.w, self.valid = f, w, valid

    @classmethod
    def fresh(cls, n_state: int, n_wheelsets: int) -> "RunCarry":
        """An empty carry: the first call evaluates the force at its start."""
        return cls(np.zeros(n_state, order="F"), np.zeros((NWO_CORE, 2, n_wheelsets), order="F"))


@dataclass(frozen=True)
class CallSettings:
    """The per-call values of the Fortran vehicle shims.

    Attributes
    ----------
    speed : float
        Forward speed v0, m/s.
    contact : int
        Fortran contact model id (``ContactModel.fortran_id``, the ``CMODEL_*`` of
        vehicle_contact: :func:`railvti.vehicle.contact_models.parse_contact_model`).
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

    def __init__(self, system: Any) -> None:  # a railvti.vehicle.assembly.System (which makes this)
        t = system.table
        handle, info = core.vehicle_model_create_c(
            system.m,
            system.c,
            system.k,
            system.f0,
            system.etype,
            system.eg,
            system.epar,
            system.iws,
            system.itr,
            t.data_roll,
            t.y0,
            t.dy,
            t.roll0,
            t.droll,
            t.r_nominal,
            t.r0,
            t.material.shear_modulus,
            system.friction,
            np.asfortranarray(system.spin_inertia, dtype=np.float64),
        )
        check(info, "vehicle model")
        self.handle = int(handle)
        self.n = int(system.n)
        self.n_wheelsets = int(system.iws.shape[1])
        self._free = weakref.finalize(self, core.vehicle_model_free_c, self.handle)
        if system.strip is not None:
            info = core.vehicle_strip_attach_c(self.handle, *system.strip.args())
            check(info, "strip contact")
        mb = system.modal
        if mb is not None:
            bs, bb, kb = mb.packed()
            ptype, prig, ppt, ppar = mb.element_arrays(self.n)
            info = core.vehicle_modal_attach_c(self.handle, bs, bb, kb, mb.phi, ptype, prig, ppt, ppar)
            check(info, "modal blocks")
            if mb.couplings is not None:
                kinds, pts, g, par, rw, rp, ra = mb.couplings.arrays(self.n, mb.n_points)
                info = core.vehicle_modal_couple_c(self.handle, kinds, pts, g, par, rw, rp, ra)
                check(info, "modal couplings")
                if mb.couplings.rim_euler is not None:
                    cp = mb.couplings
                    if np.any(cp.rim_euler >= mb.n_points):
                        raise InputError("an Eulerian rim point outside the points")
                    info = core.vehicle_modal_euler_c(
                        self.handle,
                        np.asfortranarray(cp.rim_euler + 1, dtype=np.int32),
                        np.asfortranarray(cp.rim_omega),
                    )
                    check(info, "Eulerian rim rows")
                if mb.couplings.rim_follow is not None:
                    info = core.vehicle_modal_follow_c(self.handle, *mb.couplings.rim_follow.args())
                    check(info, "rim rows that follow the contact point")
            if mb.massless is not None:
                info = core.vehicle_modal_mass_c(self.handle, np.asfortranarray(mb.mass))
                check(info, "modal masses")
        #: size of the integrator's state: rigid DOFs plus modal coordinates
        self.n_state = self.n + (mb.n_modes if mb is not None else 0)

    def close(self) -> None:
        """Free the Fortran model now (idempotent; later calls give InputError)."""
        self._free()

    @property
    def alive(self) -> bool:
        """Whether the Fortran model still exists."""
        return self._free.alive

    def force(
        self, cs: CallSettings, q: np.ndarray, v: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
        """F(q, v), wheel outputs (NWO, 2, nw), dF/dq, dF/dv and the status."""
        f, w, jq, jv, info = core.vehicle_force_c(
            self._handle(), self.n_wheelsets, *cs.args(), q, v, NWO_CORE
        )
        return f, w[:NWO], jq, jv, info

    def follow_rows(self, s: np.ndarray, n_points: int, n_modes: int) -> np.ndarray:
        """The modal rows (n_points, n_modes) with the flexible rims' contact points at s (2,
        nfr), m from the taping line (0 left, 1 right), as a time step sets them
        (vehicle_follow_rows_c; build_fr's follow_contact)."""
        phi, info = core.vehicle_follow_rows_c(
            self._handle(), np.asfortranarray(s, dtype=float), n_points, n_modes
        )
        check(info, "rows that follow the contact point")
        return phi

    def state_force(
        self, cs: CallSettings, x: np.ndarray, xd: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, int]:
        """Force over the whole state (rigid DOFs and modal coordinates, n_state) with the
        point elements, the wheel outputs and the status (vehicle_state_force_c)."""
        f, w, info = core.vehicle_state_force_c(self._handle(), self.n_wheelsets, *cs.args(), x, xd, NWO_CORE)
        return f, w[:NWO], info

    def static(
        self, cs: CallSettings, q: np.ndarray, tol: float, maxit: int
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, float, int]:
        """Steady state from q (updated in place): v, F, wheel outputs, iterations, last
        correction and the status."""
        v, f, w, it, resid, info = core.vehicle_static_c(
            self._handle(), self.n_wheelsets, *cs.args(), tol, maxit, q, NWO_CORE
        )
        return v, f, w[:NWO], it, resid, info

    def run(
        self,
        cs: CallSettings,
        h: float,
        nsteps: int,
        nevery: int,
        alpha: float,
        tol: float,
        maxit: int,
        maxsub: int,
        qmax: float,
        rtol: float,
        t: np.ndarray,
        q: np.ndarray,
        v: np.ndarray,
        a: np.ndarray,
        nout: int,
        scheme: int = 0,
        carry: "RunCarry | None" = None,
    ) -> tuple:
        """nsteps HHT steps from (t, q, v, a), all updated in place: (tout, qout, vout, wout,
        stats, status, tfail); rtol: Newton's residual tolerance, max |r| in N or N m; scheme
        1: the energy-conserving midpoint rule (alpha 0); see vehicle_newmark%newmark_run.
        ``carry`` holds the force and wheel outputs at (q, v) from the previous call of the
        same run (updated in place), so that a run split into calls takes the same steps as
        one call; None (or a fresh carry) evaluates them at (q, v) first."""
        carry = carry if carry is not None else RunCarry.fresh(q.size, self.n_wheelsets)
        out = core.vehicle_run_c(
            self._handle(),
            *cs.args(),
            h,
            nsteps,
            nevery,
            alpha,
            tol,
            maxit,
            maxsub,
            qmax,
            rtol,
            scheme,
            t,
            q,
            v,
            a,
            carry.f,
            carry.w,
            int(carry.valid),
            nout,
            nw=self.n_wheelsets,
            nwo=NWO_CORE,
        )
        carry.valid = True
        tout, qout, vout, wout = out[:4]
        return (tout, qout, vout, wout[:NWO]) + tuple(out[4:])

    def _handle(self) -> int:
        # a closed model passes 0, which the core rejects as a bad handle
        return self.handle if self._free.alive else 0
