"""Variant RF: the coach's rigid wheelsets on the flexible ring track (docs/vehicle.md, "Variant RF").

The four rigid track elements of variant RR are replaced by one :class:`~railvti.track.RingTrack`
of two rails under the whole coach. Each wheel's contact point moves along its rail,
x_c = x_offset + x_wheelset + v0 t (mod the ring length); the rail head's motion there
(lateral, vertical, roll at the crown, from the kept ring modes) is expressed as the pose
(y, z, roll) of a track element of that wheel's own, so the wheel-rail contact of variant RR is
evaluated unchanged against it and its generalised forces on that pose drive the modes through
the same rows (moving loads). The rows are time-dependent attachment rows of a modal block;
the Fortran time loop evaluates them once per (sub-)step (fortran/vehicle/vehicle_ring.f90),
so the per-step cost is linear in the kept modes.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from .._native import core
from .._status import check
from ..errors import InputError
from ..track.coupling import rail_of_wheel, wheel_head_shapes
from .assembly import System, build_coach
from .modal_blocks import RESIDUAL_ZETA, ModalBlocks
from .model import VehicleModel

if TYPE_CHECKING:  # pragma: no cover
    from ..track.ring import RingTrack
    from .params import Coach
    from .table import WheelTable

#: Points per wheel: the pose (y, z, roll) of the track element under it.
POINT_COMPONENTS = ("y", "z", "roll")
#: Times per block of RingRows.displacement (bounds its work arrays: ~0.1 GB at n_sl 128).
DISPLACEMENT_BLOCK = 64


@dataclass(frozen=True)
class RingRows:
    """The kept ring modes' data for the Fortran row evaluation, and the contact points.

    Attributes
    ----------
    modes : ndarray (nk,) int
        Indices of the kept modes in the ring's modal form (``RingTrack.lam``).
    bpos, kpos, voff : ndarray (ng + 1,) int
        Per kept group: start of its basis functions, of its kept modes, of its packed
        eigenvector entries (0-based).
    kap, fam, rail, obs : ndarray
        The groups' rail basis functions: wave number (rad/m), family, rail, crown
        observation traces (4, nbt).
    vk : ndarray
        Packed eigenvector entries over the basis functions (nb_g x nk_g per group, column-major).
    crho : ndarray (8,) int
        Rail (1 left, 2 right) of each contact point, c = 2 wheelset + wheel.
    cx0 : ndarray (8,)
        Position of each contact point along the ring at t = 0, m.
    ctr : ndarray (3, 4, 8)
        Map of the rail-local head values (x, eta, zeta, roll) onto the point's track-element
        pose (y, z, roll) in the vehicle's frame: the cant, the mirror and the element's arms.
    speed : float
        v0, m/s.
    length : float
        Ring length, m.
    rail_distance : float
        Distance between the rail axes, m.
    rtab : ndarray (3, 3, n_table, 2) or None
        The truncated modes' compliance R at each contact point over one bay per rail,
        divided by rscale^2 (None: no residual flexibility).
    bay : float
        Sleeper spacing, m (the table's period).
    rscale : float
        sqrt of the largest diagonal compliance, sqrt(m/N): the residual coordinates z have
        rows L(x) (L L^T = rtab) and stiffness I / rscale^2, so that z is a displacement of
        the size of the residual deflection (the correction test in m stays meaningful, e.g.
        with the BEM's noisy forces).
    mtab, ctab : ndarray (3, 3, n_table, 2) or None
        The truncated modes' inertia and damping moments at the same points, divided by
        rscale^4: sum phi phi^T / lambda^2 and sum phi c phi^T / lambda^2 (the w^2 and i w
        terms of their receptance; :func:`residual_inertia`).
    rpost : ndarray (3, 3, 2) or None
        A constant change of the residual coordinates per rail: rows L(x) rpost (None: the
        identity).
    """

    modes: np.ndarray
    bpos: np.ndarray
    kpos: np.ndarray
    voff: np.ndarray
    kap: np.ndarray
    fam: np.ndarray
    rail: np.ndarray
    obs: np.ndarray
    vk: np.ndarray
    crho: np.ndarray
    cx0: np.ndarray
    ctr: np.ndarray
    speed: float
    length: float
    rail_distance: float
    rtab: np.ndarray | None = None
    bay: float = 0.0
    rscale: float = 1.0
    mtab: np.ndarray | None = None
    ctab: np.ndarray | None = None
    rpost: np.ndarray | None = None

    @property
    def n_modes(self) -> int:
        """Number of kept ring modes."""
        return int(self.modes.size)

    @property
    def n_residual(self) -> int:
        """Number of residual coordinates (3 per contact point, or none)."""
        return 0 if self.rtab is None else 3 * int(self.crho.size)

    def residual_rows(self, t: np.ndarray | float) -> np.ndarray:
        """Rows L P (nt, 3, 3, 8) of the residual coordinates at each contact point: L the
        lower Cholesky factor of the residual compliance R(x) interpolated linearly over the
        bay table, P the rail's ``rpost`` (vehicle_ring%ring_residual_eval)."""
        ts = np.atleast_1d(np.asarray(t, dtype=float))
        nrx = self.rtab.shape[2]
        out = np.zeros((ts.size, 3, 3, self.crho.size))
        for c in range(self.crho.size):
            x = np.mod(self.cx0[c] + self.speed * ts, self.length)
            sx = np.mod(x, self.bay) / self.bay * nrx
            i0 = np.minimum(sx.astype(int), nrx - 1)
            w = sx - i0
            i1 = (i0 + 1) % nrx
            tab = self.rtab[:, :, :, self.crho[c] - 1]
            r = (1 - w)[:, None, None] * tab[:, :, i0].transpose(2, 0, 1) + w[:, None, None] * tab[
                :, :, i1
            ].transpose(2, 0, 1)
            out[:, :, :, c] = np.linalg.cholesky(r) @ self.post[:, :, self.crho[c] - 1]
        return out

    @property
    def post(self) -> np.ndarray:
        """The residual coordinates' change of coordinates per rail (3, 3, 2)."""
        if self.rpost is None:
            return np.repeat(np.eye(3)[:, :, None], 2, axis=2)
        return self.rpost

    def rows(self, t: np.ndarray | float) -> np.ndarray:
        """The contact points' rows at times t (numpy; the Fortran loop evaluates the same).

        Returns
        -------
        ndarray (nt, 3, 8, nk)
            Pose (y, z, roll) of the element under each contact point per unit modal
            coordinate.
        """
        ts = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.zeros((ts.size, 3, self.crho.size, self.n_modes))
        for c in range(self.crho.size):
            x = np.mod(self.cx0[c] + self.speed * ts, self.length)
            tb = self._trig(x) * self.obs[None]  # (nt, 4, nbt)
            tb[:, :, self.rail != self.crho[c]] = 0.0
            psi = np.zeros((ts.size, 4, self.n_modes))
            for g in range(self.bpos.size - 1):
                b0, b1, k0, k1 = self.bpos[g], self.bpos[g + 1], self.kpos[g], self.kpos[g + 1]
                v = self.vk[self.voff[g] : self.voff[g + 1]].reshape(b1 - b0, k1 - k0, order="F")
                psi[:, :, k0:k1] = tb[:, :, b0:b1] @ v
            out[:, :, c, :] = np.einsum("ij,tjr->tir", self.ctr[:, :, c], psi)
        return out

    def displacement(self, t: np.ndarray, qm: np.ndarray) -> np.ndarray:
        """The contact points' element poses rows(t) @ qm(t) along a history, without the rows.

        Parameters
        ----------
        t : ndarray (nt,)
            Times, s.
        qm : ndarray (nt, nk)
            The kept ring modes' coordinates.

        Returns
        -------
        ndarray (nt, 3, 8)

        Notes
        -----
        The basis functions folded per wave number as the Fortran rows are
        (vehicle_ring%ring_rows_fold, :meth:`_folded`): qm is contracted with each group's
        sine and cosine coefficients once per rail, then each point sums its sines and cosines
        of the few wave numbers, O(nt nk) instead of O(nt n_basis nk_g) with a sine and cosine
        per basis function and time (1.2 s a 2 s FF run at n_sl 40, issue 33). Evaluated
        :data:`DISPLACEMENT_BLOCK` times at a time to bound the work arrays.
        """
        ts = np.atleast_1d(np.asarray(t, dtype=float))
        qm = np.atleast_2d(qm)
        out = np.empty((ts.size, 3, self.crho.size))
        for i0 in range(0, ts.size, DISPLACEMENT_BLOCK):
            blk = slice(i0, i0 + DISPLACEMENT_BLOCK)
            out[blk] = self._displacement(ts[blk], qm[blk])
        return out

    def _folded(self) -> tuple[tuple[np.ndarray, list[tuple[int, int, np.ndarray]]], ...]:
        """Per rail (1, 2): the wave numbers of its folded columns (nw,) and per group (k0, k1,
        W) with W (nk_g, 8 nw_g) the coefficients of sin(k th) (4 components) then cos(k th)
        over the group's kept modes (vehicle_ring%ring_rows_fold's S_k, C_k). Cached."""
        got = self.__dict__.get("_fold")
        if got is not None:
            return got
        kn = np.rint(self.kap * self.length / (2.0 * np.pi)).astype(int)
        kn = np.where(self.fam == 0, 0, kn)
        out = []
        for rho in (1, 2):
            waves, groups = [], []
            for g in range(self.bpos.size - 1):
                b0, b1, k0, k1 = self.bpos[g], self.bpos[g + 1], self.kpos[g], self.kpos[g + 1]
                if k1 == k0:
                    continue
                v = self.vk[self.voff[g] : self.voff[g + 1]].reshape(b1 - b0, k1 - k0, order="F")
                on = np.nonzero(self.rail[b0:b1] == rho)[0]
                ks, j = np.unique(kn[b0 + on], return_inverse=True)
                # each function's factor of sin (0) and cos (1) per component: fam 1 u_x sin,
                # the others cos; fam 2 u_x -cos, the others sin; fam 0 a constant (cos 0 = 1)
                f = self.fam[b0 + on]
                sc = np.zeros((on.size, 2, 4))
                sc[f == 1, 0, 0], sc[f == 1, 1, 1:] = 1.0, 1.0
                sc[f == 2, 1, 0], sc[f == 2, 0, 1:] = -1.0, 1.0
                sc[f == 0, 1, :] = 1.0
                sc *= self.obs[:, b0 + on].T[:, None, :]
                coef = np.zeros((ks.size, 2, 4, k1 - k0))  # [wave, sin/cos, component, mode]
                np.add.at(coef, j, sc[:, :, :, None] * v[on][:, None, None, :])
                waves.append(ks)
                groups.append((int(k0), int(k1), coef.reshape(-1, k1 - k0).T.copy()))
            out.append((np.concatenate(waves) if waves else np.zeros(0, int), groups))
        fold = tuple(out)
        object.__setattr__(self, "_fold", fold)
        return fold

    def _displacement(self, ts: np.ndarray, qm: np.ndarray) -> np.ndarray:
        """:meth:`displacement` of one block of times (nt, 3, 8)."""
        out = np.empty((ts.size, 3, self.crho.size))
        fold = self._folded()
        amps = []
        for _waves, groups in fold:  # per rail: the amplitudes of each wave's sine and cosine
            a = [(qm[:, k0:k1] @ w).reshape(ts.size, -1, 2, 4) for k0, k1, w in groups]
            amps.append(np.concatenate(a, axis=1) if a else np.zeros((ts.size, 0, 2, 4)))
        for c in range(self.crho.size):
            waves = fold[self.crho[c] - 1][0]
            th = 2.0 * np.pi * np.mod(self.cx0[c] + self.speed * ts, self.length) / self.length
            ku, ix = np.unique(waves, return_inverse=True)  # one sine and cosine per wave number
            kx = th[:, None] * ku[None, :]
            a = amps[self.crho[c] - 1]
            psi = np.einsum("tj,tji->ti", np.sin(kx)[:, ix], a[:, :, 0])
            psi += np.einsum("tj,tji->ti", np.cos(kx)[:, ix], a[:, :, 1])
            out[:, :, c] = psi @ self.ctr[:, :, c].T
        return out

    def _trig(self, x: np.ndarray) -> np.ndarray:
        """track_ring%trig_at for every basis function: (nt, 4, nbt)."""
        kx = x[:, None] * self.kap[None, :]
        s, co = np.sin(kx), np.cos(kx)
        one = np.ones_like(kx)
        f1 = self.fam == 1
        f2 = self.fam == 2
        comp_x = np.where(f1, s, np.where(f2, -co, one))
        comp_o = np.where(f1, co, np.where(f2, s, one))
        return np.stack([comp_x, comp_o, comp_o, comp_o], axis=1)


@dataclass(frozen=True)
class RingSystem(System):
    """A System whose wheelsets run on the ring track (variant RF).

    Attributes
    ----------
    ring : RingRows
        The kept ring modes and contact points (the modal block's last ``ring.n_modes``
        coordinates); the 24 attachment points are (y, z, roll) of each wheel's element,
        point 6 wheelset + 3 wheel + component.

    Notes
    -----
    :attr:`native` also puts the wheelsets on the ring and sets its rows to t = 0 on every
    access (a static solve and a run's initial force are at t = 0; the run sets the rows of
    each step itself).
    """

    ring: RingRows | None = None

    @property
    def native(self) -> VehicleModel:
        model = self.__dict__.get("_native")
        fresh = model is None or not model.alive
        model = super().native
        r = self.ring
        if fresh and r is not None:
            nw = int(self.iws.shape[1])
            p0 = self.modal.phi.shape[0] - 6 * nw  # the ring's points are the last 6 nw
            rlpt = (np.arange(6 * nw).reshape(nw, 2, 3).transpose(2, 1, 0) + 1 + p0).astype(np.int32)
            info = core.vehicle_ring_attach_c(
                model.handle,
                np.arange(1, nw + 1, dtype=np.int32),
                np.asfortranarray(rlpt),
                self.modal.n_modes - r.n_modes - r.n_residual,
                r.n_modes,
                r.bpos,
                r.kpos,
                r.voff,
                r.kap,
                r.fam,
                r.rail,
                np.asfortranarray(r.obs),
                r.vk,
                r.crho,
                r.cx0,
                np.asfortranarray(r.ctr),
                r.speed,
                r.length,
            )
            check(info, "ring track rows")
            if r.n_residual:
                info = core.vehicle_ring_residual_c(
                    model.handle, r.bay, np.asfortranarray(r.rtab), np.asfortranarray(r.post)
                )
                check(info, "ring track residual flexibility")
        if r is not None:
            check(core.vehicle_ring_time_c(model.handle, 0.0), "ring track time")
        return model

    def rail_deflection(self, t: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Rail-head motion under each wheel along a history.

        Parameters
        ----------
        t : ndarray (nt,)
            Times, s.
        x : ndarray (nt, n_state)
            States (DOFs then modal coordinates).

        Returns
        -------
        ndarray (nt, 3, 2, nw)
            The element pose (y m, z m, roll rad; vehicle frame) under wheel [., ., k, w];
            z is the vertical displacement of the rail head's crown.
        """
        r = self.ring
        x = np.atleast_2d(x)
        m0 = self.n_state - r.n_modes - r.n_residual
        u = r.displacement(t, x[:, m0 : m0 + r.n_modes])
        if r.n_residual:
            z = x[:, m0 + r.n_modes :].reshape(x.shape[0], -1, 3)  # (nt, 8, 3)
            u = u + np.einsum("tijc,tcj->tic", r.residual_rows(t), z)
        nw = int(self.iws.shape[1])
        return u.reshape(-1, 3, nw, 2).transpose(0, 1, 3, 2)


def _check_span(n_sleepers: int, spacing: float, span: float) -> None:
    if n_sleepers * spacing < span + 2.0 * spacing:
        n_min = int(math.ceil(span / spacing - 1e-9)) + 2
        raise InputError(
            f"ring of {n_sleepers} sleepers ({n_sleepers * spacing:.4g} m) too short "
            f"for the coach: its wheelsets span {span:.4g} m; take n_sleepers >= "
            f"{n_min} (the span plus two sleeper bays)"
        )


def check_ring_length(n_sleepers: int, spacing: float, coach: "Coach") -> None:
    """InputError when a ring of n_sleepers bays of ``spacing`` (m) cannot hold the coach's
    wheelsets (span 2 (half_bogie_distance + half_wheelbase)) plus two sleeper bays."""
    s = _checks.positive("sleeper_spacing", spacing)
    span = 2.0 * (coach["half_bogie_distance"] + coach["half_wheelbase"])
    _check_span(int(n_sleepers), s, span)


#: The residual tables per ring (weakly: a ring's tables go with it), keyed by the truncated
#: modes and n_table: they do not depend on the speed or the wheelsets' positions.
_RESIDUAL_TABLES: "weakref.WeakKeyDictionary[RingTrack, dict]" = weakref.WeakKeyDictionary()


def _residual_tables(track: "RingTrack", trunc: np.ndarray, n_table: int) -> tuple:
    """The truncated modes' compliance, inertia and damping moments over one bay per rail,
    scaled (see :class:`RingRows` rtab, mtab, ctab, rscale); cached per ring (read-only
    arrays; a build per run took 0.1-0.3 s of RF's and FF's call, issue 33)."""
    memo = _RESIDUAL_TABLES.setdefault(track, {})
    key = (trunc.tobytes(), int(n_table))
    if key in memo:
        return memo[key]
    a = track.params["sleeper_spacing"]
    half = 0.5 * track.params["rail_distance"]
    rtab, mtab, ctab = (np.zeros((3, 3, n_table, 2)) for _ in range(3))
    lam, cm = track.lam[trunc], track.cmod[trunc]
    for k in range(2):
        yp = half if k == 0 else -half
        elem = np.array([[0, 1, 0, 0], [0, 0, 1, -yp], [0, 0, 0, 1.0]])
        for i in range(n_table):
            h = elem @ wheel_head_shapes(track, i * a / n_table, k)[:, trunc]
            rtab[:, :, i, k] = (h / lam) @ h.T
            mtab[:, :, i, k] = (h / lam**2) @ h.T
            ctab[:, :, i, k] = (h * (cm / lam**2)) @ h.T
    rscale = math.sqrt(max(float(np.max(rtab[[0, 1, 2], [0, 1, 2]])), 1e-300))
    rtab /= rscale**2
    mtab /= rscale**4
    ctab /= rscale**4
    for arr in (rtab, mtab, ctab):
        arr.flags.writeable = False
    memo[key] = (rtab, mtab, ctab, rscale)
    return memo[key]


def ring_rows(
    track: "RingTrack",
    x_wheelsets: np.ndarray,
    speed: float,
    *,
    f_limit: float | None = None,
    x_offset: float = 0.0,
    residual: bool = True,
    n_table: int = 24,
) -> RingRows:
    """Pack the ring modes up to ``f_limit`` and the wheels' contact points.

    With ``residual`` (and modes truncated) the truncated modes' static compliance at a
    contact point, R(x) = sum_r rows_r(x) rows_r(x)^T / lambda_r over the element pose, is
    tabulated at ``n_table`` positions over one sleeper bay per rail (the ring repeats with
    the bay); the cross-compliance between different wheels is left out.

    Raises
    ------
    InputError
        No mode at or below f_limit; a ring shorter than the wheelsets' span plus two bays.
    """
    xw = np.asarray(x_wheelsets, dtype=float)
    length = float(track.length)
    a = track.params["sleeper_spacing"]
    span = float(xw.max() - xw.min())
    _check_span(track.n_sleepers, a, span)
    om = np.sqrt(track.lam)
    if f_limit is None:
        sel = np.arange(om.size)
    else:
        fl = _checks.positive("f_limit", f_limit)
        sel = np.where(om <= 2 * math.pi * fl)[0]
    if sel.size == 0:
        raise InputError(
            f"no ring mode at or below f_limit = {f_limit} Hz (the lowest is "
            f"{om.min() / (2 * math.pi):.4g} Hz)"
        )
    keep = np.zeros(om.size, bool)
    keep[sel] = True
    bpos, kpos, voff = [0], [0], [0]
    kap, fam, rail, obs, vk, modes = [], [], [], [], [], []
    for g in range(track.mpos.size - 1):
        m0, m1 = int(track.mpos[g]), int(track.mpos[g + 1])
        kept = np.where(keep[m0:m1])[0]
        if kept.size == 0:
            continue
        b0, b1 = int(track.bpos[g]), int(track.bpos[g + 1])
        nt = m1 - m0
        v = track.vflat[track.vpos[g] : track.vpos[g] + nt * nt].reshape(nt, nt, order="F")
        o = b0 + np.argsort(track.rail[b0:b1], kind="stable")  # rail 1's functions first
        kap.append(track.kap[o])
        fam.append(track.fam[o])
        rail.append(track.rail[o])
        obs.append(track.obs[:, o])
        vk.append(v[o - b0][:, kept].ravel(order="F"))
        modes.append(m0 + kept)
        bpos.append(bpos[-1] + b1 - b0)
        kpos.append(kpos[-1] + kept.size)
        voff.append(voff[-1] + (b1 - b0) * kept.size)
    nw = xw.size
    half = 0.5 * track.params["rail_distance"]
    crho = np.zeros(2 * nw, np.int32)
    cx0 = np.zeros(2 * nw)
    ctr = np.zeros((3, 4, 2 * nw))
    for w in range(nw):
        for k in range(2):
            c = 2 * w + k
            m = rail_of_wheel(k)
            beta = track._geom[1][m.rail - 1]
            cs, sn = math.cos(beta), math.sin(beta)
            cant = np.array([[1, 0, 0, 0], [0, cs, -sn, 0], [0, sn, cs, 0], [0, 0, 0, 1.0]])
            yp = half if k == 0 else -half  # the rail's crown, vehicle y (left +)
            elem = np.array([[0, 1, 0, 0], [0, 0, 1, -yp], [0, 0, 0, 1.0]])
            ctr[:, :, c] = elem @ m.transform @ cant
            crho[c] = m.rail
            cx0[c] = x_offset + xw[w]
    rtab, mtab, ctab, rscale = None, None, None, 1.0
    trunc = np.where(~keep)[0]
    if residual and trunc.size:
        rtab, mtab, ctab, rscale = _residual_tables(track, trunc, n_table)
    return RingRows(
        modes=np.concatenate(modes),
        bpos=np.array(bpos, np.int32),
        kpos=np.array(kpos, np.int32),
        voff=np.array(voff, np.int32),
        kap=np.concatenate(kap),
        fam=np.concatenate(fam).astype(np.int32),
        rail=np.concatenate(rail).astype(np.int32),
        obs=np.asfortranarray(np.concatenate(obs, axis=1)),
        vk=np.concatenate(vk),
        crho=crho,
        cx0=cx0,
        ctr=ctr,
        speed=float(speed),
        length=length,
        rail_distance=2 * half,
        rtab=rtab,
        bay=float(a),
        rscale=rscale,
        mtab=mtab,
        ctab=ctab,
    )


def residual_inertia_of(rr: RingRows, stiffness_scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Mass and damping of the residual coordinates z (rows L(x), stiffness s I / rscale^2)
    that give the truncated modes' receptance to first order in w^2 and i w.

    The truncated modes' receptance at a point is, for w below their frequencies,
    R - i w D + w^2 M + ... with R = sum phi phi^T / lambda, D = sum phi c phi^T / lambda^2,
    M = sum phi phi^T / lambda^2 (the Rayleigh / residual-mode expansion). A coordinate block
    (K_z - w^2 M_z + i w C_z) behind rows L gives L K_z^-1 L^T + L K_z^-1 (w^2 M_z - i w C_z)
    K_z^-1 L^T + ...; with K_z = k I, k = s / rscale^2: M_z = k^2 L^-1 M L^-T, C_z likewise.
    They vary along the bay with x; the block takes their average over the bay table (per
    rail), in the Cholesky coordinates of each entry.

    Parameters
    ----------
    rr : RingRows
        With the residual tables (``ring_rows(..., residual=True)``).
    stiffness_scale : float
        The ring's stiffness factor s (modal stiffness x s, damping x sqrt(s)).

    Returns
    -------
    mz, cz : ndarray (3, 3, 2)
        Per rail: the bay-averaged mass and damping of the residual coordinates.
    """
    if rr.mtab is None or rr.ctab is None:
        raise InputError(
            "the ring rows carry no residual inertia table (residual=False or no mode truncated)"
        )
    nrx = rr.rtab.shape[2]
    mz, cz = np.zeros((3, 3, 2)), np.zeros((3, 3, 2))
    for rho in range(2):
        for i in range(nrx):
            li = np.linalg.inv(np.linalg.cholesky(rr.rtab[:, :, i, rho]))
            # M_s = M / s^2, D_s = D / s^1.5 and k = s / rscale^2 (tables / rscale^4)
            mz[:, :, rho] += li @ rr.mtab[:, :, i, rho] @ li.T / nrx
            cz[:, :, rho] += li @ rr.ctab[:, :, i, rho] @ li.T * math.sqrt(stiffness_scale) / nrx
    return mz, cz


def residual_scaling(rr: RingRows) -> np.ndarray:
    """The massless residual coordinates' change of coordinates D per rail (3, 3, 2), diagonal:
    column j of the rows L D moves the point's pose (y, z in m, roll in rad) by at most 1 per
    unit coordinate over the bay table, so that Newton's correction test (m, rad) measures
    each coordinate by the motion it gives the rail, as for the rigid DOFs.

    L (L L^T = R / rscale^2) has columns of very different size: the element pose's z and
    roll are nearly opposite in R (the rail head moves as z + y_rail roll, a small
    difference of large terms), and its last column is ~0.03 where the first two are
    ~0.6-0.8 (ring n_sleepers 40, 500 Hz). Unscaled, a correction of 1e-9 in that coordinate
    moved the rail by 3e-11 rad: the test was 30 times stricter there than on the rigid DOFs
    (issue 33; from the unmerged ring-newton branch: RF/FF centred at 300 km/h 3.7 -> 2.8
    Newton iterations a step). The compliance L D (D^2)^-1 D L^T = R and so the model are
    unchanged; the runs move within the Newton tolerance (1e-9 m on the rail's pose: ~0.8 N).
    """
    nrx = rr.rtab.shape[2]
    post = np.zeros((3, 3, 2))
    for rho in range(2):
        cmax = np.zeros(3)
        for i in range(nrx):
            cmax = np.maximum(cmax, np.abs(np.linalg.cholesky(rr.rtab[:, :, i, rho])).max(axis=0))
        post[:, :, rho] = np.diag(1.0 / np.where(cmax > 0.0, cmax, 1.0))
    return post


def residual_blocks(
    rr: RingRows, stiffness_scale: float = 1.0, residual_hz: float | None = None, inertia: bool = False
) -> tuple[RingRows, list, list]:
    """The residual coordinates' blocks, one per contact point (unit mass unless massless).

    Parameters
    ----------
    rr : RingRows
        With the residual tables.
    stiffness_scale : float
        The ring's stiffness factor s.
    residual_hz : float, optional
        An isotropic mass: the natural frequency (Hz) with damping ratio RESIDUAL_ZETA.
    inertia : bool
        The truncated modes' inertia and damping (:func:`residual_inertia_of`).

    Returns
    -------
    rr : RingRows
        The rows with the change of coordinates the blocks need (``rpost``).
    stiffness, damping : list of ndarray (3, 3)
        Per contact point. Without residual_hz and inertia: massless coordinates of
        stiffness s D^2 / rscale^2 behind rows L D (compliance R / s) and no damping, D =
        :func:`residual_scaling` (each coordinate moves the point's pose by its own size).
    """
    s = stiffness_scale
    nc = rr.crho.size
    if residual_hz is None and not inertia:
        post = residual_scaling(rr)
        stiff = [s / rr.rscale**2 * post[:, :, r - 1] @ post[:, :, r - 1] for r in rr.crho]
        return replace(rr, rpost=post), stiff, [np.zeros((3, 3))] * nc
    stiff = [np.eye(3) * s / rr.rscale**2] * nc
    damp = [np.zeros((3, 3))] * nc
    if residual_hz is not None:
        # a mass mu per coordinate: z' = sqrt(mu) z, rows L / sqrt(mu), K / mu = w^2 I
        w = 2.0 * math.pi * _checks.positive("residual_hz", residual_hz)
        mu = (s / rr.rscale**2) / w**2
        rr = replace(rr, rpost=rr.post / math.sqrt(mu))
        stiff = [np.eye(3) * w**2] * nc
        damp = [np.eye(3) * 2.0 * RESIDUAL_ZETA * w] * nc
    elif inertia:
        # unit-mass coordinates z = A z', A = M_z^-1/2: rows L A, K = k A A, C = A C_z A
        mz, cz = residual_inertia_of(rr, s)
        post = np.zeros((3, 3, 2))
        for rho in range(2):
            ev, vec = np.linalg.eigh(mz[:, :, rho])
            post[:, :, rho] = (vec / np.sqrt(ev)) @ vec.T
        rr = replace(rr, rpost=post)
        k = s / rr.rscale**2
        stiff = [k * post[:, :, r - 1] @ post[:, :, r - 1] for r in rr.crho]
        damp = [post[:, :, r - 1] @ cz[:, :, r - 1] @ post[:, :, r - 1] for r in rr.crho]
    return rr, stiff, damp


def build_rf(
    coach: "Coach",
    table: "WheelTable",
    speed: float,
    track: "RingTrack",
    *,
    f_limit: float | None = None,
    x_offset: float = 0.0,
    stiffness_scale: float = 1.0,
    residual: bool = True,
    base: System | None = None,
    residual_hz: float | None = None,
    residual_inertia: bool = False,
) -> RingSystem:
    """Variant RF: the coach's rigid wheelsets on the flexible ring track; with ``base`` an
    FR system on rigid ground, variant FF (flexible wheelsets on the ring).

    Parameters
    ----------
    coach : Coach
    table : WheelTable
    speed : float
        v0, m/s (the contact points move along the ring at v0).
    track : RingTrack
        The ring (length n_sleepers x spacing, longer than the wheelsets' span plus two bays).
    f_limit : float, optional
        Keep the ring modes up to this frequency, Hz (default: all).
    residual : bool
        Keep the truncated modes' static compliance at each contact point (residual
        flexibility, :func:`ring_rows`): three massless coordinates per wheel after the modes.
    x_offset : float
        Position along the ring of the coach centre at t = 0, m (sleeper s at s x spacing).
    stiffness_scale : float
        Multiplies the ring's modal stiffness (its damping by the square root: the same
        damping ratios); 1 is the ring itself, a large value a nearly rigid ring (a check).
    base : System, optional
        The coach on rigid ground to put on the ring (``build_coach(..., track=False)``, the
        default), or an FR system built with ``track=False`` (variant FF): its modal blocks,
        points and couplings come first, the ring's block and its 6 points per wheelset are
        appended (the ring coordinates stay the state's last).
    residual_hz : float, optional
        Give the residual coordinates a mass: each contact point's 3 x 3 block then has the
        natural frequency residual_hz (Hz) and the damping ratio :data:`RESIDUAL_ZETA`, its
        static compliance unchanged (the same static deflection). None (default): massless
        coordinates (a quasi-static point compliance). With a mass, Newton goes through
        flange-only contact where the massless coordinates stop it (docs/vehicle.md,
        "Variants RF and FF: limits"); the step must resolve residual_hz (h omega <= 2).
    residual_inertia : bool
        Give the residual coordinates the truncated modes' own inertia and damping to first
        order (:func:`residual_inertia_of`: per contact point a 3 x 3 block with mass and
        damping matrices, averaged over the bay), the static compliance unchanged. With it
        the point receptance follows the ring's direct FRF to f_limit / 2 within 1 % where
        the static residual errs by 7 % (validation/track_modal_receptance.py). Excludes
        ``residual_hz``.

    Returns
    -------
    RingSystem
        DOFs of the coach on rigid ground, then the kept ring modes (names
        ``ring_g<group>_<index>``).

    Raises
    ------
    InputError
        Speed <= 0, a ring too short, no mode kept, stiffness_scale <= 0, both
        residual_hz and residual_inertia.
    """
    v0 = _checks.positive("speed", speed)
    if residual_hz is not None and residual_inertia:
        raise InputError(
            "residual_hz and residual_inertia both give the ring's residual coordinates a mass: choose one"
        )
    s = _checks.positive("stiffness_scale", stiffness_scale)
    x_offset = _checks.finite("x_offset", x_offset)
    if base is None:
        base = build_coach(coach, table, track=False)
    elif np.any(np.asarray(base.itr) > 0):
        raise InputError(
            "the base system of the ring track must have no track elements (build it with track=False)"
        )
    rr = ring_rows(track, base.x_wheelsets, v0, f_limit=f_limit, x_offset=x_offset, residual=residual)
    lam = track.lam[rr.modes] * s
    cm = track.cmod[rr.modes] * math.sqrt(s)
    om = np.sqrt(lam)
    phi = rr.rows(0.0)[0].reshape(-1, rr.n_modes, order="F")  # point 3 c + i
    names = tuple(f"ring_g{int(track.group[m])}_{int(m)}" for m in rr.modes)
    mb = ModalBlocks.diagonal(om, cm / (2.0 * om), phi, names=names)
    if rr.n_residual:
        nc = rr.crho.size
        rr, stiff, damp = residual_blocks(rr, s, residual_hz, residual_inertia)
        lres = rr.residual_rows(0.0)[0]
        pr = np.zeros((3 * nc, 3 * nc))
        for c in range(nc):
            pr[3 * c : 3 * c + 3, 3 * c : 3 * c + 3] = lres[:, :, c]
        massless = residual_hz is None and not residual_inertia
        mb = ModalBlocks(
            mb.damping + tuple(damp),
            mb.stiffness + tuple(stiff),
            np.hstack([mb.phi, pr]),
            names=names + tuple(f"ring_res{c // 2 + 1}{'LR'[c % 2]}_{i}" for c in range(nc) for i in "yzr"),
            massless=(False,) * rr.n_modes + (massless,) * nc,
        )
    if base.modal is not None:
        mb = _append_blocks(base.modal, mb)
    base = base.with_modal(mb)
    fields = {f: getattr(base, f) for f in base.__dataclass_fields__}
    return RingSystem(**fields, ring=rr)


def _append_blocks(first: ModalBlocks, ring: ModalBlocks) -> ModalBlocks:
    """The modal blocks of ``first`` (variant FR's wheelsets) followed by the ring's: blocks
    and names concatenated, Phi block-diagonal (first's points, then the ring's), first's
    point elements and couplings unchanged (their point indices stay valid)."""
    n1, m1 = first.phi.shape
    n2, m2 = ring.phi.shape
    phi = np.zeros((n1 + n2, m1 + m2))
    phi[:n1, :m1] = first.phi
    phi[n1:, m1:] = ring.phi
    ml1 = first.massless or (False,) * len(first.damping)
    ml2 = ring.massless or (False,) * len(ring.damping)
    return ModalBlocks(
        first.damping + ring.damping,
        first.stiffness + ring.stiffness,
        phi,
        elements=first.elements,
        names=first.names + ring.names,
        couplings=first.couplings,
        massless=ml1 + ml2,
    )


def set_time(system: RingSystem, t: float) -> None:
    """Set the system's ring rows to time t (the next force or static call sees them)."""
    check(core.vehicle_ring_time_c(system.native.handle, _checks.finite("t", t)), "ring track time")


__all__ = [
    "POINT_COMPONENTS",
    "DISPLACEMENT_BLOCK",
    "RingRows",
    "RingSystem",
    "check_ring_length",
    "ring_rows",
    "residual_inertia_of",
    "residual_blocks",
    "residual_scaling",
    "build_rf",
    "set_time",
]
