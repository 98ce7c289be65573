"""Rigid wheelset kinematics: the creepages at a contact reference point and the axle torque.

The wheelset moves with its centre's velocity v_c = (V, v_y, v_z) (track frame: x forward,
y left, z up) and turns with the angular velocity

    Omega = omega a + roll_rate e_x' + yaw_rate e_z',

a the axle (to the left wheel), e_x', e_z' the wheelset's own forward and vertical axes
(the rotation R = Rz(yaw) Rx(roll) of :func:`railvti.geometry.frames.axle_direction`);
``omega`` > 0 rolls forward. These are CONTACT's VS, VY, VZ, VROLL, VYAW and VPITCH (module 1,
``wr_creep_cref``), which also takes the body components of the Euler rates as the angular
velocity. The rail is at rest.

Creepages at a patch's reference point (a :class:`~railvti.geometry.ContactPoint` of the
rigid pose): the wheel's material point Q there is the rail point lifted by the point's
separation along n (a point of the undeformed wheel surface, at the rolling radius). Its
velocity is v_Q = v_c + Omega x (Q - c), split into the part of the rotation about the axle
(v_pitch = omega a x (Q - c)) and the rest (v_trans). As in CONTACT, the reference speed is
the mean of the two forward speeds, V_ref = (|v_trans,x| + |v_pitch,x|) / 2 (Kalker's
rolling velocity: the material of the two bodies passes through the patch at V and at
omega r), and

    xi = v_Q . t_x / V_ref,   eta = v_Q . t_y / V_ref,   phi = Omega . n / V_ref,

the wheel's velocity relative to the rail (railvti's sign: Kalker's, forces on the wheel).
The rigid slip in the patch is then w = V_ref (xi - phi y, eta + phi x) about the reference
point (x, y in the contact frame), which is how the rolling solver takes it.

At CONTACT's contact reference point (:mod:`railvti.contact.wheelset_reference`), as CONTACT
evaluates it (``wr_creep_cref``): Q is the wheel point at the approach ``pen`` below the
reference point P on the rail, Q = P - pen n (n into the wheel), and the velocities are those
of the LOADED wheelset (centre c lowered by its sink), v_Q = v_c + Omega x (Q - c).

Implements no equation of the paper (rigid-body kinematics; CONTACT's definitions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError
from ..geometry import ContactPoint, Creepages, WheelsetPose


@dataclass(frozen=True)
class WheelsetMotion:
    """Rigid-body velocities of a wheelset in the track frame (x forward, y left, z up).

    Attributes
    ----------
    speed : float
        Forward speed V of the wheelset centre, m/s (> 0; CONTACT's VS).
    omega : float or None
        Angular velocity about the axle, rad/s (> 0 rolling forward; CONTACT's -VPITCH);
        None: free rolling (found from the torque balance about the axle).
    lateral_velocity, vertical_velocity : float
        Velocity of the wheelset centre along y (left) and z (up), m/s (CONTACT's VY, VZ
        with their signs flipped: CONTACT's y points right and its z down).
    roll_rate, yaw_rate : float
        Rates of roll (about x, positive raises the left wheel) and of yaw (about z up),
        rad/s (CONTACT's VROLL and -VYAW).
    """

    speed: float
    omega: float | None = None
    lateral_velocity: float = 0.0
    vertical_velocity: float = 0.0
    roll_rate: float = 0.0
    yaw_rate: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "speed", _checks.positive("speed", self.speed))
        if self.omega is not None:
            object.__setattr__(
                self,
                "omega",
                _checks.positive(
                    "omega (angular velocity about the axle, rad/s, > 0 rolling forward)", self.omega
                ),
            )
        for name in ("lateral_velocity", "vertical_velocity", "roll_rate", "yaw_rate"):
            object.__setattr__(self, name, _checks.finite(name, getattr(self, name)))


@dataclass(frozen=True)
class RigidSlip:
    """Rigid slip of the wheel over the rail at a patch's reference point.

    Attributes
    ----------
    creepage : Creepages
        xi, eta (1) along t_x, t_y and spin phi (1/m) along n, over ``reference_speed``.
    reference_speed : float
        V_ref = (|v_trans,x| + |v_pitch,x|) / 2, m/s: the rolling speed of the patch.
    wheel_velocity : ndarray (3,)
        Velocity of the wheel's material point at the reference point, m/s (track frame).
    """

    creepage: Creepages
    reference_speed: float
    wheel_velocity: np.ndarray


def body_axes(pose: WheelsetPose) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The wheelset's forward, axle and vertical axes e_x', a, e_z' in track coordinates."""
    cr, sr = np.cos(pose.roll), np.sin(pose.roll)
    cy, sy = np.cos(pose.yaw), np.sin(pose.yaw)
    return (np.array([cy, sy, 0.0]), np.array([-sy * cr, cy * cr, sr]), np.array([sy * sr, -cy * sr, cr]))


def angular_velocity(pose: WheelsetPose, motion: WheelsetMotion, omega: float) -> np.ndarray:
    """Omega = omega a + roll_rate e_x' + yaw_rate e_z', rad/s (track coordinates)."""
    ex, a, ez = body_axes(pose)
    return omega * a + motion.roll_rate * ex + motion.yaw_rate * ez


def rigid_slip(
    contact: ContactPoint,
    motion: WheelsetMotion,
    omega: float,
    *,
    loaded: WheelsetPose | None = None,
    approach: float = 0.0,
) -> RigidSlip:
    """Creepages of the wheel over the (fixed) rail at a contact reference point.

    Parameters
    ----------
    contact : ContactPoint
        The patch's reference point, with its (half) wheelset's pose.
    motion : WheelsetMotion
        The wheelset's velocities.
    omega : float
        Angular velocity about the axle, rad/s (> 0): ``motion.omega``, or the free-rolling
        value being iterated.
    loaded : WheelsetPose, optional
        CONTACT's evaluation: the loaded pose of the (half) wheelset; the wheel point is then
        Q = P - approach n relative to the loaded centre. None: Q = P + separation n
        relative to the rigid pose's centre (the point of smallest gap's own wheel point).
    approach : float
        The patch's approach along n, m (with ``loaded``).

    Returns
    -------
    RigidSlip
        Small-angle check: xi = (V - omega r) / V_ref with V_ref = (V + omega r) / 2.
    """
    if not isinstance(contact, ContactPoint):
        raise InputError("contact must be a railvti.geometry.ContactPoint")
    omega = _checks.positive("omega", omega)
    if loaded is None:
        pose = contact.pose
        rel = contact.position + contact.separation * contact.normal - pose.centre
    else:
        pose = loaded
        rel = contact.position - _checks.finite("approach", approach) * contact.normal - pose.centre
    ex, a, ez = body_axes(pose)
    v_pitch = np.cross(omega * a, rel)
    v_trans = np.array([motion.speed, motion.lateral_velocity, motion.vertical_velocity]) + np.cross(
        motion.roll_rate * ex + motion.yaw_rate * ez, rel
    )
    v_ref = 0.5 * (abs(v_trans[0]) + abs(v_pitch[0]))
    if v_ref <= 0.0:
        raise InputError("the patch's rolling speed (|forward speed| + |omega r|) / 2 is zero")
    v = v_trans + v_pitch
    spin = angular_velocity(pose, motion, omega) @ contact.normal
    return RigidSlip(
        Creepages(
            xi=float(v @ contact.t_x) / v_ref, eta=float(v @ contact.t_y) / v_ref, phi=float(spin) / v_ref
        ),
        float(v_ref),
        v,
    )


def patch_moment(
    contact: ContactPoint,
    centre: np.ndarray,
    force: np.ndarray,
    fn: float,
    x_cp: float,
    y_cp: float,
    mz: float,
) -> np.ndarray:
    """Moment of a patch's tractions about a point (the loaded wheelset's centre), N m.

    The tractions act in the tangent plane at the reference point P; about P they give
    Fn (y_cp t_x - x_cp t_y) + Mz n (the pressure's centre (x_cp, y_cp) in the contact frame,
    the spin moment Mz of the tangential tractions about P); about the centre c the force
    adds (P - c) x F.

    Parameters
    ----------
    contact : ContactPoint
        The patch's reference point P and contact frame.
    centre : ndarray (3,)
        The point c the moment is taken about, track coordinates, m.
    force : ndarray (3,)
        Resultant force on the wheel, track coordinates, N.
    fn : float
        Normal force, N.
    x_cp, y_cp : float
        Centre of pressure in the contact frame, m.
    mz : float
        Spin moment about the normal through P, N m.

    Returns
    -------
    ndarray (3,)
        Track coordinates.
    """
    tx, ty, n = contact.t_x, contact.t_y, contact.normal
    about_p = fn * (y_cp * tx - x_cp * ty) + mz * n
    return np.cross(contact.position - np.asarray(centre, dtype=float), force) + about_p


__all__ = ["WheelsetMotion", "RigidSlip", "body_axes", "angular_velocity", "rigid_slip", "patch_moment"]
