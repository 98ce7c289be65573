"""Wear and rolling contact fatigue indices of a contact patch.

* **T gamma** (the energy index): the creep forces' work on the creepages per unit rolled
  distance, ``T gamma = -(Fx xi + Fy eta)`` in N (= J/m), forces on the wheel; spin is left out,
  as in the usual definition (Pearce and Sherratt, Wear 144 (1991) 343-351). The vehicle's
  time loop gives it per wheel, summed over the wheel's points (``SimulationResult`` output
  ``T_gamma``).
* **Archard wear** from the boundary-element fields: the depth worn per unit time at each
  element, ``dz/dt = k p |s| / H`` (Archard, J. Appl. Phys. 24 (1953) 981-988; p the pressure,
  s the local slip velocity, H the hardness, k the dimensionless wear coefficient), and the
  depth one passage of the patch wears across the track, ``dz(y) = sum_x k p |s| / H dx / V``.
  The coefficient by default from Jendel's wear map for wheel and rail steel (Jendel, Wear 253
  (2002) 89-99, after Lim and Ashby): k = 300-400e-4 where p > 0.8 H, else 1-10e-4 below a slip
  velocity of 0.2 m/s, 30-40e-4 from 0.2 to 0.7 m/s and 1-10e-4 above (the middle of each band
  here: :data:`JENDEL_K`).
* **Surface fatigue index** (Ekberg, Kabo and Andersson, Fatigue Fract. Engng Mater. Struct.
  25 (2002) 899-909): ``FI_surf = f - 2 pi a b k / (3 Fn)`` with the traction coefficient
  ``f = |(Fx, Fy)| / Fn`` and k the material's yield stress in pure shear: surface-initiated
  RCF is predicted where FI_surf > 0 (the load lies beyond the shakedown limit of Johnson's map
  for a Hertz patch, whose maximum pressure is 3 Fn / (2 pi a b)).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = [
    "JENDEL_K",
    "ArchardWear",
    "archard_wear",
    "jendel_coefficient",
    "surface_fatigue_index",
    "t_gamma",
]

#: Jendel's wear map (Wear 253 (2002) 89-99), the middle of each band: (seizure, p > 0.8 H),
#: (mild, slip < 0.2 m/s), (severe, 0.2-0.7 m/s), (mild, > 0.7 m/s).
JENDEL_K = (350e-4, 5.5e-4, 35e-4, 5.5e-4)


class _Fields(Protocol):
    """A patch with BEM fields: railvti.contact.RollingResult or railvti.vehicle.bem.BemPatch."""

    pressure: np.ndarray
    slip_velocity_x: np.ndarray
    slip_velocity_y: np.ndarray
    speed: float


def t_gamma(fx: np.ndarray | float, fy: np.ndarray | float, xi, eta) -> np.ndarray | float:
    """T gamma = -(Fx xi + Fy eta), N: the creep forces' (on the wheel, N) work on the
    creepages (1) per unit rolled distance; >= 0 for forces that oppose the creepages."""
    return -(np.asarray(fx) * np.asarray(xi) + np.asarray(fy) * np.asarray(eta))


def jendel_coefficient(pressure: np.ndarray, slip_speed: np.ndarray, hardness: float) -> np.ndarray:
    """Jendel's wear coefficient k (1) per element from its pressure (Pa) and slip speed |s|
    (m/s), for a hardness H (Pa): the map's bands (module docstring), their middle values."""
    p = np.asarray(pressure, dtype=float)
    s = np.asarray(slip_speed, dtype=float)
    k = np.where(s < 0.2, JENDEL_K[1], np.where(s <= 0.7, JENDEL_K[2], JENDEL_K[3]))
    return np.where(p > 0.8 * hardness, JENDEL_K[0], k)


@dataclass(frozen=True)
class ArchardWear:
    """Archard wear of one patch (module docstring).

    Attributes
    ----------
    depth_rate : ndarray (nx, ny)
        Depth worn per unit time at each element while it is in the patch, m/s.
    depth_per_pass : ndarray (ny,)
        Depth one passage of the patch wears at each lateral position, m.
    volume_rate : float
        Volume worn per unit time, m^3/s (sum of depth_rate dA).
    volume_per_distance : float
        Volume worn per metre rolled, m^3/m (volume_rate / V).
    coefficient : ndarray (nx, ny)
        The wear coefficient used per element, 1.
    """

    depth_rate: np.ndarray
    depth_per_pass: np.ndarray
    volume_rate: float
    volume_per_distance: float
    coefficient: np.ndarray


def _steps(patch: _Fields) -> tuple[float, float]:
    """The element sizes dx, dy of a patch (a Grid's, or the spacing of BemPatch's x, y)."""
    grid = getattr(patch, "grid", None)
    if grid is not None:
        return float(grid.dx), float(grid.dy)
    x, y = np.asarray(patch.x), np.asarray(patch.y)
    if x.ndim != 2 or x.shape[0] < 2 or x.shape[1] < 2:
        raise InputError("patch: its element centres x, y must be (nx, ny) arrays with nx, ny >= 2")
    return float(x[1, 0] - x[0, 0]), float(y[0, 1] - y[0, 0])


def archard_wear(patch: _Fields, hardness: float, coefficient: float | None = None) -> ArchardWear:
    """Archard wear of a patch from its pressure and slip-velocity fields.

    Parameters
    ----------
    patch : RollingResult or BemPatch
        A steady rolling solution with its fields (pressure, Pa; slip velocity, m/s; speed, m/s).
    hardness : float
        Hardness H of the worn body, Pa (e.g. about 2.4e9 for wheel steel of 240 HB).
    coefficient : float, optional
        A constant wear coefficient k (1); None: Jendel's map per element
        (:func:`jendel_coefficient`).

    Returns
    -------
    ArchardWear
    """
    h = _checks.positive("hardness", hardness)
    p = np.asarray(patch.pressure, dtype=float)
    s = np.hypot(
        np.asarray(patch.slip_velocity_x, dtype=float), np.asarray(patch.slip_velocity_y, dtype=float)
    )
    if p.shape != s.shape or p.ndim != 2:
        raise InputError(f"patch: pressure {p.shape} and slip velocity {s.shape} must be the same (nx, ny)")
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(s))):
        raise InputError("patch: its pressure or slip velocity is not finite")
    v = _checks.positive("patch speed", float(patch.speed))
    if coefficient is None:
        k = jendel_coefficient(p, s, h)
    else:
        k = np.full(p.shape, _checks.positive("coefficient", coefficient))
    dx, dy = _steps(patch)
    rate = k * np.clip(p, 0.0, None) * s / h
    vol = float(rate.sum() * abs(dx * dy))
    return ArchardWear(
        depth_rate=rate,
        depth_per_pass=rate.sum(axis=0) * abs(dx) / v,
        volume_rate=vol,
        volume_per_distance=vol / v,
        coefficient=k,
    )


def surface_fatigue_index(
    ft: np.ndarray | float, fn: np.ndarray | float, a: np.ndarray | float, b, shear_yield: float
) -> np.ndarray | float:
    """Ekberg's surface fatigue index FI_surf = f - 2 pi a b k / (3 Fn) (module docstring).

    Parameters
    ----------
    ft : float or ndarray
        Tangential creep force |(Fx, Fy)|, N.
    fn : float or ndarray
        Normal force, N; where it is 0 (no contact) the index is -inf (no load, no fatigue),
        never NaN.
    a, b : float or ndarray
        Semi-axes of the Hertz patch, m.
    shear_yield : float
        Yield stress in pure shear k, Pa (Ekberg et al. use about 300 MPa for wheel steel).

    Returns
    -------
    float or ndarray
        FI_surf (1); > 0: surface-initiated RCF predicted.
    """
    k = _checks.positive("shear_yield", shear_yield)
    ft, fn, a, b = (np.asarray(x, dtype=float) for x in (ft, fn, a, b))
    loaded = fn > 0.0
    safe = np.where(loaded, fn, 1.0)
    fi = np.where(loaded, ft / safe - 2.0 * np.pi * a * b * k / (3.0 * safe), -np.inf)
    return fi if fi.ndim else float(fi)
