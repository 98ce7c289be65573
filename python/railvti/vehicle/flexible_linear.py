"""Linear analyses of an FR system: its M, C, K without the contact, a rim point's
receptance, the state force's tangents and the eigenvalues (:mod:`railvti.vehicle.flexible`
builds the system). Dense tools for checks and stability, not for the time loop.
"""

from __future__ import annotations

import numpy as np

from .._status import check
from ..errors import InputError
from .assembly import System
from .flexible import FRLayout
from .model import CallSettings
from .contact_models import contact_id
from .equilibrium import static_equilibrium

__all__ = [
    "linear_matrices",
    "contact_receptance",
    "TANGENT_STEP",
    "state_tangent",
    "eigenvalues",
    "tangent_eigenvalues",
]


def linear_matrices(system: System) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Dense M, C, K (n_state x n_state) of an FR system without its wheel-rail contact,
    linearised about zero: the coach's M, C, K with its scalar elements' linear parts (a dry
    friction element's slope p1 / p2 + p3 at rest, a bump stop inside its clearance: none),
    the modal blocks (M = the modal masses, massless residual blocks included) and the
    journal ('split') and Coriolis ('gyro') couplings through Phi. A check tool for
    frequency responses (dense: O(n_state^3) per frequency), not for the time loop.

    Returns
    -------
    m, c, k : ndarray (n_state, n_state)
    """
    mb = system.modal
    if mb is None or mb.couplings is None:
        raise InputError("linear_matrices needs an FR system")
    n, nm = system.n, mb.n_modes
    nt = n + nm
    m, c, k = np.zeros((nt, nt)), np.zeros((nt, nt)), np.zeros((nt, nt))
    m[:n, :n], c[:n, :n], k[:n, :n] = system.m, system.c, system.k
    cp = mb.couplings
    omega = next(
        (float(cp.params[0, e]) for e, kind in enumerate(cp.kinds) if kind == "gyro"), 0.0
    )  # the spin Omega of the rigid-elastic couplings
    for w in range(system.iws.shape[1]):  # the rigid gyroscopic moments (build_coach)
        a, b = system.iws[2, w] - 1, system.iws[3, w] - 1
        c[a, b] -= system.spin_inertia[w] * omega
        c[b, a] += system.spin_inertia[w] * omega
    for e in range(system.eg.shape[1]):
        p = system.epar[:, e]
        if system.etype[e] == 1:  # friction: p1 tanh(gd / p2) + p3 gd
            cd = p[2] + (p[0] / p[1] if p[0] != 0.0 and p[1] > 0.0 else 0.0)
            g = system.eg[:, e]
            c[:n, :n] += cd * np.outer(g, g)
    m[n:, n:] = np.diag(mb.mass)
    mb.place_blocks(c, k, n)
    cp = mb.couplings
    for e, kind in enumerate(cp.kinds):
        ph = mb.phi[cp.points[e]]
        g = cp.directions[:, e]
        kk, cc, _ = cp.params[:, e]
        if kind == "split":
            for mat, v in ((k, kk), (c, cc)):
                mat[n:, :n] -= v * np.outer(ph, g)
                mat[n:, n:] += v * np.outer(ph, ph)
                mat[:n, n:] -= v * np.outer(g, ph)
        else:  # gyro: g_p += k g.v, g_r -= g k u_p'
            c[n:, :n] -= kk * np.outer(ph, g)
            c[:n, n:] += kk * np.outer(g, ph)
    return m, c, k


def contact_receptance(
    system: System, layout: FRLayout, freqs: np.ndarray, wheel: int = 1, direction: str = "lateral"
) -> np.ndarray:
    """Point receptance at a wheel's rim point of an FR system with the wheel-rail contact
    removed (:func:`linear_matrices`): a force at the rim reference point acts on the rigid
    wheelset (with its roll moment about the centre) and on the rim point; the response is
    the point's displacement, rigid plus elastic (m/N).

    Parameters
    ----------
    system : System
    layout : FRLayout
        The flexible wheelset.
    freqs : array_like
        Frequencies, Hz (> 0).
    wheel : int
        0 left, 1 right.
    direction : {'lateral', 'vertical'}

    Returns
    -------
    ndarray of complex (nf,)
    """
    if wheel not in (0, 1) or direction not in ("lateral", "vertical"):
        raise InputError(f"wheel 0 or 1 and direction 'lateral' or 'vertical', got {wheel!r}, {direction!r}")
    f = np.asarray(freqs, dtype=float)
    if np.any(~(f > 0)):
        raise InputError("freqs must be > 0")
    m, c, k = linear_matrices(system)
    n = system.n
    i = layout.wheelset + 1
    l0, r0 = system.modal.couplings.rim_arms[:, 0]
    sg = 1.0 if wheel == 0 else -1.0
    b = np.zeros(m.shape[0])
    if direction == "lateral":
        b[system.index(f"ws{i}_y")] = 1.0
        b[system.index(f"ws{i}_roll")] = r0  # M_x = -z F_y at z = -r0
        row = layout.points.start + 3 * wheel
    else:
        b[system.index(f"ws{i}_z")] = 1.0
        b[system.index(f"ws{i}_roll")] = sg * l0  # M_x = y F_z
        row = layout.points.start + 3 * wheel + 1
    b[n:] += system.modal.phi[row]
    out = np.empty(f.size, dtype=complex)
    for j, fj in enumerate(f):
        w = 2.0 * np.pi * fj
        out[j] = b @ np.linalg.solve(k - w * w * m + 1j * w * c, b)
    return out


#: Forward-difference step of :func:`state_tangent` (the same as the core's contact tangent,
#: vehicle_model%contact_tangent: variant FR with decoupled modes then linearises exactly as RR).
TANGENT_STEP = 1.0e-8


def state_tangent(
    system: System, speed: float, x: np.ndarray, xd: np.ndarray, contact: str = "hertz-kalker"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The force over the whole state of an FR system and its tangents at (x, xd).

    Forward differences (step :data:`TANGENT_STEP`) of the core's state force (the coach's
    elements, the modal blocks, the journal and Coriolis couplings and the contact on the
    deformed rims with its Eulerian term) over every state entry: dense, O(n_state^2), a tool
    for linear analyses (:func:`eigenvalues`), not for the time loop.

    Returns
    -------
    f : ndarray (n_state,)
    jq, jv : ndarray (n_state, n_state)
        dF/dx and dF/dxd.
    """
    if system.modal is None:
        raise InputError("state_tangent needs a system with modal blocks (variant FR)")
    nt = system.n_state
    x = np.array(x, dtype=float)
    xd = np.array(xd, dtype=float)
    if x.shape != (nt,) or xd.shape != (nt,):
        raise InputError(f"x and xd must have the state's size {nt}")
    cs = CallSettings(float(speed), contact_id(contact))

    def force(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        f, _, info = system.native.state_force(cs, a, b)
        check(info, "FR state force (linearisation)")
        return np.array(f)

    f0 = force(x, xd)
    jq, jv = np.empty((nt, nt)), np.empty((nt, nt))
    for j in range(nt):
        xp = x.copy()
        xp[j] += TANGENT_STEP
        jq[:, j] = (force(xp, xd) - f0) / TANGENT_STEP
        vp = xd.copy()
        vp[j] += TANGENT_STEP
        jv[:, j] = (force(x, vp) - f0) / TANGENT_STEP
    return f0, jq, jv


def eigenvalues(
    system: System,
    speed: float,
    q: np.ndarray | None = None,
    v: np.ndarray | None = None,
    contact: str = "hertz-kalker",
) -> np.ndarray:
    """Eigenvalues (1/s) of an FR system linearised about (q, v), flexible DOFs included.

    Default (q, v): the FR steady state of centred running (static_equilibrium, with the
    spin rates; the modes statically deflected). The first-order system
    ``[I 0; 0 M] z' = [0 I; Jq Jv] z`` (:func:`state_tangent`) is solved as a generalised
    eigenproblem because the residual flexibility's coordinates are massless (M singular):
    their algebraic equations give infinite eigenvalues, which are dropped. As for RR
    (railvti.vehicle.equilibrium.eigenvalues) each wheelset's free spin angle adds a zero.

    Returns
    -------
    ndarray of complex
        The finite eigenvalues.
    """
    if system.modal is None:
        raise InputError(
            "flexible_linear.eigenvalues needs an FR system; use "
            "railvti.vehicle.equilibrium.eigenvalues for RR"
        )
    if q is None:
        q, v, _ = static_equilibrium(system, speed, contact, return_velocity=True)
    if v is None:
        v = np.zeros(system.n_state)
    _, jq, jv = state_tangent(system, speed, q, v, contact)
    return tangent_eigenvalues(system, jq, jv)


def tangent_eigenvalues(system: System, jq: np.ndarray, jv: np.ndarray) -> np.ndarray:
    """Finite eigenvalues (1/s) of ``[I 0; 0 M] z' = [0 I; jq jv] z`` with the system's mass M.

    The tangents (:func:`state_tangent`) may be of another system of the same layout and mass;
    the massless residual coordinates' infinite eigenvalues are dropped (:func:`eigenvalues`).
    """
    from scipy.linalg import eigvals

    n, nt = system.n, system.n_state
    mass = np.zeros((nt, nt))
    mass[:n, :n] = system.m
    mass[n:, n:] = np.diag(system.modal.mass)
    a = np.zeros((2 * nt, 2 * nt))
    a[:nt, nt:] = np.eye(nt)
    a[nt:, :nt] = jq
    a[nt:, nt:] = jv
    b = np.eye(2 * nt)
    b[nt:, nt:] = mass
    ev = eigvals(a, b)
    return ev[np.isfinite(ev)]
