"""Results of the loaded wheelset (:func:`railvti.contact.wheelset.solve_wheelset`): each
contact patch's forces, moments and fields (:class:`WheelsetPatch`), the wheelset's balance at
one position (:class:`WheelsetSolution`), and the patch result built from a solved patch state.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry import ContactPoint, Creepages, WheelsetContact
from ..geometry.frames import SIDES
from .grid import Grid
from .wheelset_patch import PatchState

__all__ = ["WheelsetPatch", "WheelsetSolution", "count_regions", "patch_result"]


@dataclass(frozen=True)
class WheelsetPatch:
    """One contact patch of a loaded wheelset.

    Forces act on the wheel. ``fn`` along the rail normal (into the wheel), ``fx``, ``fy``
    along the contact frame's ``t_x`` (rolling) and ``t_y`` (lateral, to the track's left).

    Attributes
    ----------
    side : str
        'left' or 'right'.
    contact : ContactPoint
        The candidate point (rigid pose) the patch grows from: its reference point (the grid's
        origin, where the creepages are taken and the forces and moments are reduced to).
    contact_angle : float
        rad.
    creepage : Creepages or None
        Rigid creepages xi, eta (-) and spin phi (1/m) at the reference point, over
        ``reference_speed``; None without rolling.
    reference_speed : float
        Rolling speed V_ref of the patch, m/s (nan without rolling).
    approach : float
        Approach of the patch along its normal, m.
    fn, fx, fy : float
        Forces on the wheel in the contact frame, N (fx = fy = 0 without rolling).
    mz : float
        Spin moment of the tangential tractions about the normal through the reference
        point, N m.
    centre_of_pressure : tuple of float
        (x, y) of the pressure's centre in the contact frame, m.
    force_track : ndarray (3,)
        The force in track coordinates (x forward, y left, z up), N.
    moment_track : ndarray (3,)
        Moment of the tractions about the reference point, track coordinates, N m:
        Fn (y_cp t_x - x_cp t_y) + Mz n.
    pmax : float
        Largest pressure, Pa.
    n_contact, n_adhesion, n_slip : int
        Elements in contact, in adhesion, in slip (adhesion = contact without rolling).
    grid : Grid
        The patch's grid (x along t_x, y along t_y, origin at the reference point).
    gap, pressure : ndarray (nx, ny)
        Undeformed gap (m) and pressure (Pa).
    tx, ty : ndarray (nx, ny) or None
        Tangential tractions on the wheel, Pa; None without rolling.
    rolling : RollingResult or None
        The full steady-rolling result (slip, slip velocity, power density, power, ...).
    """

    side: str
    contact: ContactPoint
    contact_angle: float
    creepage: Creepages | None
    reference_speed: float
    approach: float
    fn: float
    fx: float
    fy: float
    mz: float
    centre_of_pressure: tuple[float, float]
    force_track: np.ndarray
    moment_track: np.ndarray
    pmax: float
    n_contact: int
    n_adhesion: int
    n_slip: int
    grid: Grid
    gap: np.ndarray
    pressure: np.ndarray
    tx: np.ndarray | None = None
    ty: np.ndarray | None = None
    rolling: object | None = None

    @property
    def n_regions(self) -> int:
        """Separate contact areas in the patch (edge-connected elements in contact): a patch
        grows around one candidate point but may hold two areas joined by a low ridge."""
        return count_regions(self.pressure > 0.0)


@dataclass(frozen=True)
class WheelsetSolution:
    """Contact of a loaded wheelset at one position.

    Attributes
    ----------
    geometry : WheelsetContact
        The rigid-pose contact search (pose, candidate points, status per wheel).
    left, right : list of WheelsetPatch
        Loaded patches of each wheel (unloaded candidates, and a wheel not solved, are empty).
    fz : tuple of float
        Vertical (track z) force on the left and right wheel from all their patches, normal
        and tangential forces, N (nan for a wheel not solved).
    sink, roll : float
        Load-controlled roll: vertical motion w (m, down) and extra roll theta (rad) of the
        wheelset from the rigid pose. Prescribed roll: the mean sink of the half wheelsets
        solved, and 0.
    sinks : tuple of float
        Downward motion of each wheel's profile reference circle centre (on the axle at the
        tread datum), m: w -+ theta * contact_y, or each half wheelset's own sink.
    pose_roll : float
        Roll angle of the pose the geometry was taken at, rad (prescribed, or from the two
        wheels' contact constraint).
    roll_prescribed : bool
        The roll was prescribed (each wheel a half wheelset).
    omega : float or None
        Angular velocity about the axle, rad/s (prescribed or free-rolling); None without rolling.
    free_rolling : bool
        omega was found from the torque balance about the axle.
    axle_torque : float
        Torque of the contact forces and moments about the axle, N m (the wheels solved);
        ~0 with free rolling; nan without rolling.
    iterations : int
        Load-control Newton iterations (all outer iterations together).
    outer_iterations : int
        Rolling solves per patch (balance with tangential forces and free rolling); 0
        without rolling.
    """

    geometry: WheelsetContact
    left: list[WheelsetPatch]
    right: list[WheelsetPatch]
    fz: tuple[float, float]
    sink: float
    roll: float
    sinks: tuple[float, float]
    pose_roll: float
    roll_prescribed: bool
    omega: float | None
    free_rolling: bool
    axle_torque: float
    iterations: int
    outer_iterations: int

    @property
    def patches(self) -> list[WheelsetPatch]:
        """All patches, left wheel first."""
        return self.left + self.right

    def wheel(self, side: str) -> list[WheelsetPatch]:
        """Patches of 'left' or 'right'."""
        if side not in SIDES:
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.left if side == "left" else self.right


def count_regions(mask: np.ndarray) -> int:
    """Number of edge-connected regions of True in a 2-D mask (4-neighbourhood): the runs of
    True along axis 0 in each column, joined (union-find) with the runs they overlap in the
    next column."""
    parent: list[int] = []

    def root(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    prev: list[tuple[int, int, int]] = []
    m = np.asarray(mask, dtype=np.int8)
    pad = np.zeros((1, m.shape[1]), dtype=np.int8)
    edges = np.diff(np.concatenate([pad, m, pad]), axis=0)
    for j in range(m.shape[1]):
        starts, ends = np.flatnonzero(edges[:, j] == 1), np.flatnonzero(edges[:, j] == -1)
        cur = []
        for a, b in zip(starts.tolist(), ends.tolist()):
            k = len(parent)
            parent.append(k)
            for pa, pb, pk in prev:
                if pa < b and a < pb:  # the runs [a, b) and [pa, pb) touch
                    parent[root(pk)] = root(k)
            cur.append((a, b, k))
        prev = cur
    return sum(1 for k in range(len(parent)) if root(k) == k)


def patch_result(pt: PatchState) -> WheelsetPatch:
    """The result of a solved patch (forces on the wheel, its moment, fields, rolling result)."""
    cp = pt.cp
    x_cp, y_cp = pt.centre_of_pressure()
    r = pt.rolling
    fx, fy, mz = (r.fx, r.fy, r.mz) if r is not None else (0.0, 0.0, 0.0)
    n_adh = int(r.adhesion.sum()) if r is not None else pt.n_contact
    n_slip = int(r.slip.sum()) if r is not None else 0
    return WheelsetPatch(
        side=cp.side,
        contact=cp,
        contact_angle=cp.contact_angle,
        creepage=pt.slip.creepage if r is not None else None,
        reference_speed=pt.slip.reference_speed if r is not None else float("nan"),
        approach=pt.approach,
        fn=pt.fn,
        fx=fx,
        fy=fy,
        mz=mz,
        centre_of_pressure=(x_cp, y_cp),
        force_track=pt.force(),
        moment_track=pt.fn * (y_cp * cp.t_x - x_cp * cp.t_y) + mz * cp.normal,
        pmax=pt.pmax,
        n_contact=pt.n_contact,
        n_adhesion=n_adh,
        n_slip=n_slip,
        grid=pt.grid,
        gap=pt.gap,
        pressure=pt.p,
        tx=None if r is None else r.tx,
        ty=None if r is None else r.ty,
        rolling=r,
    )
