"""Modes of one circumferential harmonic of an axisymmetric body (Fortran core)."""

from __future__ import annotations

import logging
import threading
from dataclasses import dataclass

import numpy as np

from .. import _cache, _checks, _interrupt
from .._native import core
from .._status import Status, error
from ..errors import InputError
from .mesh import MeridianMesh

log = logging.getLogger(__name__)

#: Modes requested in the first call to the Fortran solver (grown x4 while full).
_FIRST_BUFFER = 48

#: Held by a wheelset_modes_c call (ARPACK keeps its iteration state in SAVEd variables: one
#: call at a time), until its end, also when Ctrl-C abandoned it (:func:`_modes_call`).
_ARPACK = threading.Lock()


def _modes_call(*args):
    """``core.wheelset_modes_c(*args)`` (~1 s for the default mesh) in a worker thread, the
    shim releasing the GIL, while the main thread waits for signals: Ctrl-C / SIGTERM raise
    here within ~0.05 s (:func:`railvti._interrupt.call_in_worker`). An interrupted call runs
    on to its end in the background, holding :data:`_ARPACK`, so the next call waits for it."""
    _interrupt.acquire(_ARPACK)
    return _interrupt.call_in_worker(
        core.wheelset_modes_c, *args, on_end=_ARPACK.release, name="railvti-wheelset-modes"
    )


@dataclass(frozen=True)
class HarmonicModes:
    """Modes of harmonic k, normalised to unit modal mass.

    Attributes
    ----------
    k : int
        Circumferential harmonic.
    freq_hz : ndarray (nm,)
        Natural frequencies of the non-rotating body, Hz.
    shapes : ndarray (nm, nn, 3)
        Nodal amplitudes (U_r, U_y, U_theta), m per sqrt(kg); set A of eq. 7.
    coriolis : ndarray (nm, nm)
        Gamma = Phi^T C Phi; the body-frame gyroscopic matrix is 2 Omega Gamma
        (k = 0, skew) or 2 Omega [[0, Gamma], [-Gamma, 0]] on (A, B) (k > 0).
    inplane_mass : ndarray (nm, nm)
        Phi^T Mc Phi, mass of the (r, theta) motion (centrifugal softening).
    prestress_stiffness : ndarray (nm, nm)
        Phi^T K_sigma Phi, geometric stiffness of the centrifugal prestress at
        1 rad/s (scale by Omega^2).
    n_equations : int
        Free degrees of freedom of the harmonic.
    bandwidth : int
        Half-bandwidth of the assembled matrices.
    """

    k: int
    freq_hz: np.ndarray
    shapes: np.ndarray
    coriolis: np.ndarray
    inplane_mass: np.ndarray
    prestress_stiffness: np.ndarray
    n_equations: int
    bandwidth: int

    @property
    def lam(self) -> np.ndarray:
        """Eigenvalues omega^2, (rad/s)^2."""
        return (2.0 * np.pi * self.freq_hz) ** 2


def check_harmonic(k: object, name: str = "harmonic k") -> int:
    """Return k as an int, or raise InputError unless it is an integer >= 0."""
    try:
        ok = not isinstance(k, bool) and float(k).is_integer() and int(k) >= 0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise InputError(f"{name} must be an integer >= 0, got {k!r}")
    return int(k)


def solve_harmonic(
    mesh: MeridianMesh,
    k: int,
    young: float,
    poisson: float,
    density: float,
    f_max: float,
    fixed: np.ndarray | None = None,
    springs: tuple[tuple[int, int, float], ...] = (),
    n_max: int = 400,
) -> HarmonicModes:
    """All modes of harmonic k up to f_max.

    Parameters
    ----------
    mesh : MeridianMesh
        Meridian mesh, m.
    k : int
        Circumferential harmonic, >= 0.
    young, poisson, density : float
        E (Pa), nu, rho (kg/m^3).
    f_max : float
        Highest frequency wanted, Hz.
    fixed : ndarray (nn, 3) of bool, optional
        Clamped components (U_r, U_y, U_theta).
    springs : tuple of (node, component, stiffness)
        Springs to the ground: zero-based node, component 0 r, 1 y, 2 theta, N/m.
    n_max : int
        Most modes returned.

    Returns
    -------
    HarmonicModes

    Raises
    ------
    InputError
        k < 0; an inverted element or one with r <= 0 (its number in the message); no free
        degree of freedom left for this harmonic.
    ConvergenceError
        The eigen-solver failed or stopped early (K - sigma M not positive definite: a
        negative stiffness?), or the k = 0 prestress system could not be factorised.
    """
    k = check_harmonic(k)
    f_max = _checks.positive("f_max", f_max)
    nn = mesh.n_nodes
    fx = np.zeros((3, nn), dtype=np.int32, order="F")
    if fixed is not None:
        fx[:, :] = np.asarray(fixed, dtype=bool).T
    if springs:
        sn = np.array([s[0] + 1 for s in springs], dtype=np.int32)
        sc = np.array([s[1] + 1 for s in springs], dtype=np.int32)
        sk = np.array([s[2] for s in springs], dtype=np.float64)
    else:
        sn, sc, sk = np.ones(1, np.int32), np.ones(1, np.int32), np.zeros(1)
    n_max = _checks.positive_int("n_max", n_max)
    xn = np.asfortranarray(mesh.nodes.T, dtype=np.float64)
    conn = np.asfortranarray(mesh.conn.T + 1, dtype=np.int32)
    lam_max = (2.0 * np.pi * f_max) ** 2
    # The shim returns fixed-size buffers (phi is 3 x nn x n_buf doubles: 34 MB
    # for 3500 nodes and 400 modes), so start small and grow only when the
    # buffer came back full (the solver may have stopped at n_buf modes).
    n_buf = min(n_max, _FIRST_BUFFER)
    # the eigen-solves' outputs on disk (railvti._cache): a later process replays them
    rec = _cache.Recorder(
        "wheelset-modes", xn, conn, k, young, poisson, density, fx, sn, sc, sk, lam_max, n_max
    )
    while True:
        nm, lam, phi, gam, mcq, kgq, neq, kd, info, bad, sinfo = rec.call(
            "wheelset_modes_c",
            _modes_call,
            xn,
            conn,
            k,
            young,
            poisson,
            density,
            fx,
            sn,
            sc,
            sk,
            lam_max,
            n_buf,
        )
        if info != Status.OK or nm < n_buf or n_buf >= n_max:
            break
        n_buf = min(n_max, 4 * n_buf)
    if info == Status.OK:
        rec.finish()
    if info != Status.OK:
        raise _modes_error(info, k, int(bad), int(sinfo), int(nm))
    lam = np.clip(lam[:nm], 0.0, None)
    log.debug("k=%d: %d modes below %.0f Hz, %d equations, bandwidth %d", k, nm, f_max, neq, kd)
    return HarmonicModes(
        k=k,
        freq_hz=np.sqrt(lam) / (2.0 * np.pi),
        # a copy: a transposed view would keep the whole f2py buffer alive
        shapes=np.transpose(phi[:, :, :nm], (2, 1, 0)).copy(),
        coriolis=gam[:nm, :nm].copy(),
        inplane_mass=mcq[:nm, :nm].copy(),
        prestress_stiffness=kgq[:nm, :nm].copy(),
        n_equations=int(neq),
        bandwidth=int(kd),
    )


def _modes_error(info: int, k: int, bad_element: int, solver_info: int, nm: int) -> Exception:
    """The exception for a failing wheelset_modes_c status, with what the user can act on."""
    try:
        code = Status(int(info))
    except ValueError:
        return error(info, f"harmonic k={k}")
    what = {
        Status.BAD_ELEMENT: f"meridian element {bad_element} (1-based) is inverted or has r <= 0 "
        "(bad geometry)",
        # k, n_max and f_max are checked above, so a bad argument here is the DOF count.
        Status.BAD_ARGUMENT: "no free degree of freedom left for this harmonic",
        Status.SIZE_MISMATCH: "wheelset_modes_c rejected its arguments (mesh or spring numbering)",
        Status.SINGULAR: "centrifugal prestress: the k = 0 stiffness could not be factorised",
        Status.NOT_POSITIVE_DEFINITE: "K - sigma M is not positive definite (negative stiffness?)",
        Status.NOT_CONVERGED: f"eigen-solver for k={k} did not converge ({nm} modes)",
    }.get(code, f"eigen-solver for k={k} failed")
    if code not in (Status.BAD_ELEMENT, Status.BAD_ARGUMENT, Status.SIZE_MISMATCH, Status.SINGULAR):
        what += f" (LAPACK/ARPACK info {solver_info})"
    return error(info, f"harmonic k={k}: {what}", iterations=0)


def eq11_blocks(
    lam: np.ndarray, gam: np.ndarray, mc: np.ndarray, k: int, omega: float, zeta: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One harmonic's constant blocks of the axle-fixed modal model (Kaiser eq. 11).

    Parameters
    ----------
    lam : ndarray (n,)
        The harmonic's kept eigenvalues omega_i^2 (non-rotating), rad^2/s^2.
    gam, mc : ndarray (n, n)
        Its Coriolis matrix Gamma and centrifugal matrix Mc - K_sigma (zero without the
        centrifugal terms) between the kept modes.
    k : int
        The harmonic.
    omega : float
        Spin, rad/s.
    zeta : float
        Modal damping ratio.

    Returns
    -------
    gyro : ndarray (n, n) for k = 0, (2n, 2n) for k > 0 (Q_A block, then Q_B)
        G = 2 Omega Gamma (k = 0) or 2 Omega [[0, Gamma + k I], [-(Gamma + k I), 0]].
    stiffness_diag : ndarray (n, n)
        K of the k = 0 block, or the (equal) diagonal block of Q_A and Q_B for k > 0:
        Lambda - Omega^2 Mc - k^2 Omega^2 I - 2 k Omega^2 Gamma.
    damping : ndarray, the shape of gyro
        diag(2 zeta omega_i).
    """
    w = np.sqrt(lam)
    n = lam.size
    if k == 0:
        return 2.0 * omega * gam, np.diag(lam) - omega**2 * mc, np.diag(2.0 * zeta * w)
    eye = np.eye(n)
    gk = gam + k * eye
    gyro = 2.0 * omega * np.block([[np.zeros((n, n)), gk], [-gk, np.zeros((n, n))]])
    kd = np.diag(lam) - omega**2 * mc - (k * omega) ** 2 * eye - 2.0 * k * omega**2 * gam
    return gyro, kd, np.diag(np.concatenate([2.0 * zeta * w] * 2))


__all__ = ["HarmonicModes", "check_harmonic", "solve_harmonic", "eq11_blocks"]
