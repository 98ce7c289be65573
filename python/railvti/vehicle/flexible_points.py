"""What the attachment points of an FR or FF system carry at a state: the point forces, one
wheelset's attachment loads and deflections, the rims' deformation and camber, the rail
head's roll and the rim-rail angle (:mod:`railvti.vehicle.flexible` builds the system).
"""

from __future__ import annotations

import numpy as np

from .._status import check
from ..errors import InputError
from .assembly import System
from .flexible import FRLayout
from .modal_blocks import ModalBlocks
from .model import CallSettings
from .contact_models import contact_id

__all__ = [
    "point_forces",
    "attachment_loads",
    "attachment_deflection",
    "rim_deformation",
    "rim_camber_change",
    "rail_head_roll",
    "rim_rail_angle_change",
]


def point_forces(
    system: System, speed: float, x: np.ndarray, xd: np.ndarray | None = None, contact: str = "hertz-kalker"
) -> np.ndarray:
    """The forces g_p on the attachment points of an FR system at state x (rates xd): the
    contact's generalised forces on the rims, the journal springs' forces, the Coriolis terms.

    Evaluated by the core on a probe system with the same couplings whose modes are the
    points themselves (phi = I, B = K = 0): its modal forces are g_p.

    Returns
    -------
    ndarray (n_points,)
        N on displacement points, N m on rotation points.
    """
    mb = system.modal
    if mb is None or mb.couplings is None:
        raise InputError("point_forces needs an FR system (modal blocks with couplings)")
    npt = mb.n_points
    probe = ModalBlocks(
        damping=(np.zeros((npt, npt)),),
        stiffness=(np.zeros((npt, npt)),),
        phi=np.eye(npt),
        couplings=mb.couplings,
    )
    ps = system.with_modal(probe)
    n = system.n
    x = np.asarray(x, dtype=float)
    xd = np.zeros_like(x) if xd is None else np.asarray(xd, dtype=float)
    xp = np.concatenate([x[:n], mb.phi @ x[n:]])
    xdp = np.concatenate([xd[:n], mb.phi @ xd[n:]])
    f, _, info = ps.native.state_force(CallSettings(speed, contact_id(contact)), xp, xdp)
    check(info, "FR point forces")
    return np.asarray(f[n:])


def attachment_loads(system: System, layout: FRLayout, gp: np.ndarray) -> np.ndarray:
    """The 14 loads over railvti.wheelset.rim_rows.ATTACHMENT_DOFS (contact right x, y, z,
    rx, left ..., journal right x, y, z, left ...) of one flexible wheelset from the point
    forces gp (the rims' x force is not coupled: 0)."""
    g = np.asarray(gp)[layout.points]
    f = np.zeros(14)
    f[5:8] = g[0:3]  # left rim (FE side 1): y, z, rx
    f[1:4] = g[3:6]  # right rim (FE side 0)
    f[11:14] = g[6:9]  # left journal
    f[8:11] = g[9:12]  # right journal
    return f


def attachment_deflection(system: System, layout: FRLayout, x: np.ndarray) -> np.ndarray:
    """The 14 attachment displacements (ATTACHMENT_DOFS order; rim x from its row 0) of one
    flexible wheelset at state x: the coupled model's u = Phi Q."""
    u = system.modal.phi[layout.points] @ np.asarray(x)[system.n :]
    d = np.full(14, np.nan)
    d[5:8], d[1:4] = u[0:3], u[3:6]
    d[11:14], d[8:11] = u[6:9], u[9:12]
    return d


def rim_deformation(system: System, x: np.ndarray) -> np.ndarray:
    """The rims' elastic deformation at state x (or states, rows of a 2-D x).

    Returns
    -------
    ndarray (..., 3, 2, 4)
        (dy, dz, drx) [m, m, rad] of wheel 0 left / 1 right of each wheelset (zero for a
        rigid one), track axes: dy + left, dz up, drx about x (+: the wheel's points at
        larger y rise).
    """
    mb = system.modal
    if mb is None or mb.couplings is None:
        raise InputError("rim_deformation needs an FR system")
    x = np.asarray(x, dtype=float)
    u = x[..., system.n :] @ mb.phi.T
    out = np.zeros(x.shape[:-1] + (3, 2, 4))
    cp = mb.couplings
    for j, i in enumerate(cp.rim_wheelsets):
        out[..., :, :, i] = u[..., cp.rim_points[:, :, j]]
    return out


#: Sign of the angle convention per wheel (0 left, 1 right): a rotation drx about the vehicle's
#: x (+: the points at larger y rise; y positive to the left) turns the wheel's or the rail's
#: inner edge (towards the track centre) up by -drx on the left and +drx on the right.
_INNER_EDGE_SIGN = np.array([-1.0, 1.0])


def rim_camber_change(system: System, x: np.ndarray) -> np.ndarray:
    """The rims' elastic camber at the contact points, rad, (..., 2, 4) [wheel 0 left /
    1 right, wheelset]: positive when the tread's inner edge (towards the track centre) rises
    against its outer edge (-drx at the left wheel, +drx at the right, drx the rim's rotation
    about the vehicle's x, :func:`rim_deformation`). Zero for a rigid wheelset. The rail's
    roll is not in it: :func:`rim_rail_angle_change` is the relative angle."""
    d = rim_deformation(system, x)[..., 2, :, :]
    return d * _INNER_EDGE_SIGN[:, None]


def rail_head_roll(system: System, x: np.ndarray, t: np.ndarray | float | None = None) -> np.ndarray:
    """The rail head's elastic roll under each wheel, rad, (..., 2, 4) [wheel, wheelset], in
    the convention of :func:`rim_camber_change` (+: the head's inner edge, towards the track
    centre, rises; -roll on the left rail, +roll on the right, roll about the vehicle's x).

    On the ring track (variants RF, FF) the roll of the track element under the wheel from the
    ring's modes (:meth:`RingSystem.rail_deflection`); on the rigid track elements of models
    RR and FR the rail head does not deform: zero (the elements' rigid roll, like the
    wheelset's, is the same for both wheels and sits in the contact geometry, not here).

    Parameters
    ----------
    system : System
    x : ndarray (n_state,) or (nt, n_state)
        State(s).
    t : float or ndarray (nt,), optional
        Time(s) of the state(s), s: needed on the ring track (the contact points move along it).

    Raises
    ------
    InputError
        A ring-track system without ``t``, or ``t`` not matching the states.
    """
    x = np.asarray(x, dtype=float)
    ring = getattr(system, "ring", None)
    if ring is None:
        return np.zeros(x.shape[:-1] + (2, int(system.iws.shape[1])))
    if t is None:
        raise InputError(
            "rail_head_roll: key 't' (the states' times, s) is needed on the ring "
            "track: the contact points move along it"
        )
    ts = np.atleast_1d(np.asarray(t, dtype=float))
    xs = np.atleast_2d(x)
    if ts.shape != (xs.shape[0],) or not np.all(np.isfinite(ts)):
        raise InputError(
            f"rail_head_roll: key 't' must be finite with one time per state "
            f"({xs.shape[0]}), got shape {ts.shape}"
        )
    roll = system.rail_deflection(ts, xs)[:, 2] * _INNER_EDGE_SIGN[:, None]
    return roll.reshape(x.shape[:-1] + roll.shape[1:])


def rim_rail_angle_change(system: System, x: np.ndarray, t: np.ndarray | float | None = None) -> np.ndarray:
    """The change of each wheel's rim-rail angle, the paper's relative angle, rad, (..., 2, 4)
    [wheel 0 left / 1 right, wheelset]: the rim's elastic camber (:func:`rim_camber_change`)
    minus the rail head's elastic roll under the wheel (:func:`rail_head_roll`), both
    positive when the inner edge (towards the track centre) rises, i.e. -drx on the left and
    +drx on the right, drx about the vehicle's x (y positive to the left). The paper's
    25 -> 26 mrad is +1 mrad. On the rigid track (variant FR) it is the camber; on the ring
    (variant FF) ``t`` is needed. The same difference is what the contact sees: it evaluates
    the wheel at the relative roll wheelset + rim - rail (vehicle_contact)."""
    return rim_camber_change(system, x) - rail_head_roll(system, x, t)
