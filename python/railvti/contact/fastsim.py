"""FASTSIM: Kalker's simplified theory of rolling contact, on an ellipse and strip-wise.

Kalker (1982), "A fast algorithm for the simplified theory of rolling
contact", Vehicle System Dynamics 11, 1-13. The surface displacement is taken
proportional to the local traction, ``u = L tau``, with one flexibility per
creepage component chosen so that the simplified theory reproduces Kalker's
linear theory for small creepage on an ellipse with semi-axes a (rolling
direction x) and b::

    L1 = 8 a / (3 C11 G),  L2 = 8 a / (3 C22 G),  L3 = pi a^2 / (4 C23 G sqrt(a b))

The tractions are marched along strips y = const from the leading edge
(x = +a(y), particles move in -x) with ``dtau_x/dx = xi/L1 - phi y/L3``,
``dtau_y/dx = eta/L2 + phi x/L3`` and scaled back onto the Coulomb disc
``|tau| <= mu p`` where they leave it (slip). The kernel is Fortran
(``fortran/contact/contact_fastsim.f90``).

Slip: ``s = L_eff (tau - tau_trial) / h`` per unit rolled distance (h the step),
``L_eff`` Kalker's creepage-weighted flexibility; slip velocity ``V |s|`` and
frictional power density ``|tau| V |s|``. This is the simplified theory's
slip, only a rough estimate of the elastic half-space's.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from .. import _checks
from .._native import core
from .._status import Status, error
from ..errors import InputError, RailvtiError
from ..material import Material
from .grid import Grid
from .kalker import A_OVER_B_RANGE, KalkerRangeError, kalker_table

log = logging.getLogger(__name__)

__all__ = ["FastsimResult", "fastsim", "fastsim_grid", "equivalent_ellipse"]

_PRESSURE = {"parabolic": 1, "hertz": 2}
_LMODE = {"ellipse": 1, "strip": 2}


@dataclass(frozen=True)
class FastsimResult:
    """Creep forces and traction fields of a FASTSIM computation.

    Fields are ``(nx, ny)`` arrays, index ``[i, j]`` = element i of strip j.
    For the elliptic form, i = 0 is the leading edge of each strip and the
    x positions differ from strip to strip; for the strip-wise form the fields
    live on the BEM grid.

    Attributes
    ----------
    fx, fy : float
        Creep forces on the body, N (Kalker's signs: ``Fx = -G a b C11 xi``
        in the linear limit).
    mz : float
        Spin moment about the origin, ``sum (x ty - y tx) dA``, N m.
    x, y : ndarray, shape (nx, ny)
        Element centres, m.
    element_area : ndarray, shape (nx, ny)
        Element areas, m^2.
    pressure : ndarray, shape (nx, ny)
        Normal pressure used, Pa.
    tx, ty : ndarray, shape (nx, ny)
        Tangential traction on the body, Pa.
    slip : ndarray of bool, shape (nx, ny)
        True where the element slides (traction on the Coulomb bound).
    slip_velocity : ndarray, shape (nx, ny)
        Magnitude of the simplified theory's slip velocity, m/s.
    power_density : ndarray, shape (nx, ny)
        Frictional power density ``|tau| |slip velocity|``, W/m^2.
    power : float
        Total frictional power, W.
    a, b : float
        Semi-axes of the (equivalent) ellipse, m.
    coefficients : tuple of float
        (C11, C22, C23) used for the flexibilities.
    """

    fx: float
    fy: float
    mz: float
    x: np.ndarray
    y: np.ndarray
    element_area: np.ndarray
    pressure: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    slip: np.ndarray
    slip_velocity: np.ndarray
    power_density: np.ndarray
    power: float
    a: float
    b: float
    coefficients: tuple[float, float, float]


def _creepage(creepage: Any) -> tuple[float, float, float]:
    try:
        values = tuple(creepage)
    except TypeError:
        raise InputError("creepage must be a sequence (xi, eta, phi)") from None
    if len(values) != 3:
        raise InputError(f"creepage must have 3 entries (xi, eta, phi), got {len(values)}")
    xi, eta, phi = (_checks.finite(n, v) for n, v in zip(("xi", "eta", "phi"), values))
    return xi, eta, phi


@lru_cache(maxsize=1)
def _fortran_table() -> tuple[np.ndarray, np.ndarray]:
    """Kalker's Table E.3 (:func:`~railvti.contact.kalker.kalker_table`, the one copy) in
    the layout of the Fortran kalker_interp: a/b (n,) and the columns (n, 9) C11, C22,
    C23 at nu = 0, 0.25, 0.5."""
    ab, c = kalker_table()
    cols = np.asfortranarray(np.moveaxis(c, 1, 0).reshape(len(ab), 9))
    return np.ascontiguousarray(ab, dtype=float), cols


def _coefficients(a_over_b: float, poisson: float) -> tuple[float, float, float]:
    """Kalker's C11, C22, C23 by the Fortran kalker_interp (the same interpolation as
    :func:`~railvti.contact.kalker.kalker_coefficients`, without scipy's call overhead)."""
    c11, c22, c23, info, ibad = core.fastsim_kalker_c(np.array([a_over_b]), poisson, *_fortran_table())
    if info == Status.BAD_ARGUMENT:
        if ibad > 0:
            raise KalkerRangeError(
                f"a/b = {a_over_b:.6g} lies outside Kalker's Table E.3 "
                f"[{A_OVER_B_RANGE[0]}, {A_OVER_B_RANGE[1]}]"
            )
        raise KalkerRangeError(f"poisson = {poisson} lies outside [0, 0.5]")
    if info != Status.OK:  # pragma: no cover - kalker_interp reports BAD_ARGUMENT only
        raise error(info, "Kalker interpolation failed", exc=RailvtiError)
    return float(c11[0]), float(c22[0]), float(c23[0])


def _common(material: Any, mu: Any, speed: Any) -> tuple[float, float]:
    if not isinstance(material, Material):
        raise InputError("material must be a railvti.Material")
    return _checks.non_negative("mu", mu), _checks.positive("speed", speed)


def _power(
    tx: np.ndarray, ty: np.ndarray, sx: np.ndarray, sy: np.ndarray, speed: float, area: np.ndarray
) -> tuple[np.ndarray, np.ndarray, float]:
    sv = speed * np.hypot(sx, sy)
    dens = np.hypot(tx, ty) * sv
    return sv, dens, float((dens * area).sum())


def fastsim(
    a: float,
    b: float,
    fn: float,
    material: Material,
    mu: float,
    creepage: Any,
    *,
    nx: int = 30,
    ny: int = 30,
    speed: float = 1.0,
    pressure: str = "parabolic",
) -> FastsimResult:
    """FASTSIM on an elliptic contact patch.

    Parameters
    ----------
    a, b : float
        Semi-axes, m; a along the rolling direction x.
    fn : float
        Normal force, N (> 0).
    material : Material
        Shear modulus G and Poisson's ratio nu (for Kalker's coefficients).
    mu : float
        Coefficient of friction (>= 0).
    creepage : (xi, eta, phi)
        Longitudinal and lateral creepage (-), spin (1/m).
    nx, ny : int
        Elements per strip and number of strips (of equal width 2b/ny).
    speed : float
        Rolling speed V, m/s; scales only the slip velocity and power.
    pressure : {'parabolic', 'hertz'}
        Normal pressure: Kalker's parabolic ``2 fn/(pi a b) (1 - x^2/a^2 - y^2/b^2)``
        (FASTSIM's usual choice) or Hertz's semi-ellipsoid; either is scaled
        so that its discrete sum is fn.

    Returns
    -------
    FastsimResult

    Raises
    ------
    InputError
        a, b or fn <= 0, mu < 0, speed <= 0, a non-finite creepage, bad nx, ny
        or pressure; :class:`~railvti.contact.kalker.KalkerRangeError` when a/b
        is outside [0.1, 10].

    Examples
    --------
    >>> from railvti.material import STEEL
    >>> r = fastsim(6e-3, 4e-3, 80e3, STEEL, 0.3, (1e-3, 0.0, 0.0))
    >>> round(r.fx / 80e3, 3)
    -0.102
    """
    a = _checks.positive("a", a)
    b = _checks.positive("b", b)
    fn = _checks.positive("fn", fn)
    mu, speed = _common(material, mu, speed)
    xi, eta, phi = _creepage(creepage)
    nx = _checks.positive_int("nx", nx)
    ny = _checks.positive_int("ny", ny)
    if nx * ny > 10_000_000:
        raise InputError(f"nx * ny = {nx * ny} is too large (limit 1e7)")
    if pressure not in _PRESSURE:
        raise InputError(f"pressure must be one of {sorted(_PRESSURE)}, got {pressure!r}")
    c = _coefficients(a / b, material.poisson)
    g = material.shear_modulus
    x, y, pn, tx, ty, sx, sy, slip, fx, fy, mz, info = core.fastsim_fields_c(
        a, b, g, *c, mu, fn, xi, eta, phi, nx, ny, _PRESSURE[pressure]
    )
    if info != Status.OK:  # pragma: no cover - the checks above exclude it
        raise error(info, "FASTSIM kernel failed", exc=RailvtiError)
    aj = a * np.sqrt(np.maximum(0.0, 1.0 - (y / b) ** 2))
    area = np.broadcast_to(2.0 * aj / nx * (2.0 * b / ny), (nx, ny)).copy()
    sv, dens, power = _power(tx, ty, sx, sy, speed, area)
    return FastsimResult(
        fx=float(fx),
        fy=float(fy),
        mz=float(mz),
        x=x,
        y=np.broadcast_to(y, (nx, ny)).copy(),
        element_area=area,
        pressure=pn,
        tx=tx,
        ty=ty,
        slip=slip.astype(bool),
        slip_velocity=sv,
        power_density=dens,
        power=power,
        a=a,
        b=b,
        coefficients=tuple(float(v) for v in c),
    )


def fastsim_forces(
    a: float, b: float, fn, material: Material, mu: float, xi, eta, phi, *, nx: int = 30, ny: int = 30
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Creep forces only, vectorised over load cases (FASTSIM, parabolic pressure).

    Parameters
    ----------
    a, b : float
        Semi-axes, m.
    fn, xi, eta, phi : float or array_like
        Normal force (N), creepages (-) and spin (1/m), broadcast together.
    material, mu, nx, ny
        As in :func:`fastsim`.

    Returns
    -------
    fx, fy, mz : ndarray
        Forces (N) and spin moment (N m), the broadcast shape.
    """
    a = _checks.positive("a", a)
    b = _checks.positive("b", b)
    mu, _ = _common(material, mu, 1.0)
    nx = _checks.positive_int("nx", nx)
    ny = _checks.positive_int("ny", ny)
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (fn, xi, eta, phi)))
    for name, v in zip(("fn", "xi", "eta", "phi"), arrays):
        if not np.isfinite(v).all():
            raise InputError(f"{name} must be finite")
    if (arrays[0] <= 0.0).any():
        raise InputError("fn must be > 0")
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(v.ravel()) for v in arrays]
    c = _coefficients(a / b, material.poisson)
    fx, fy, mz = core.fastsim_ellipse_c(a, b, material.shear_modulus, *c, mu, *flat, nx, ny)
    return fx.reshape(shape), fy.reshape(shape), mz.reshape(shape)


def equivalent_ellipse(pressure: np.ndarray, grid: Grid) -> tuple[float, float]:
    """Equivalent ellipse of a contact patch on a grid.

    ``b`` is half the lateral extent of the elements with ``p > 0`` and ``a``
    keeps the area, ``a = A / (pi b)``.

    Returns
    -------
    a, b : float
        Semi-axes, m.
    """
    contact = pressure > 0.0
    cols = np.flatnonzero(contact.any(axis=0))
    if cols.size == 0:
        raise InputError("pressure has no element > 0: no contact")
    b = 0.5 * grid.dy * (cols[-1] - cols[0] + 1)
    area = contact.sum() * grid.element_area
    return area / (np.pi * b), b


def fastsim_grid(
    p: Any,
    grid: Grid,
    material: Material,
    mu: float,
    creepage: Any,
    speed: float = 1.0,
    *,
    flexibility: str = "ellipse",
    ellipse: tuple[float, float] | None = None,
) -> FastsimResult:
    """Strip-wise FASTSIM on a (possibly non-elliptic) patch with a given pressure.

    Each grid column (constant y) is a strip; each run of elements with
    ``p > 0`` is marched from its leading edge (largest x) with zero traction
    there, so non-convex patches with several runs per strip are handled.

    Parameters
    ----------
    p : ndarray, shape (nx, ny), or NormalResult
        Normal pressure, Pa (e.g. ``solve_normal(...).pressure``).
    grid : Grid
        The grid of p.
    material : Material
    mu : float
        Coefficient of friction (>= 0).
    creepage : (xi, eta, phi)
        Creepages (-) and spin (1/m); spin acts about the grid origin.
    speed : float
        Rolling speed, m/s (slip velocity and power only).
    flexibility : {'ellipse', 'strip'}
        'ellipse': Kalker's L1, L2, L3 of the equivalent ellipse on every strip.
        'strip': the same scaled on each run by its half-length a_r,
        ``L_r = L a_r sum(a_r)/sum(a_r^2)``: short strips are stiffer, as in
        strip theories (cf. Sichani, Enblom & Berg 2016, FaStrip), and the
        linear longitudinal force of the equivalent ellipse is kept.
    ellipse : (a, b), optional
        Semi-axes of the equivalent ellipse, m; by default
        :func:`equivalent_ellipse` (lateral extent, same area).

    Returns
    -------
    FastsimResult

    Raises
    ------
    InputError
        Bad arguments; no element in contact; equivalent a/b outside Kalker's
        table (:class:`~railvti.contact.kalker.KalkerRangeError`).
    """
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    if hasattr(p, "pressure"):
        p = p.pressure
    pa = _checks.finite_array("p", p, shape=grid.shape)
    if (pa < 0.0).any():
        raise InputError("p must be >= 0 everywhere")
    mu, speed = _common(material, mu, speed)
    xi, eta, phi = _creepage(creepage)
    if flexibility not in _LMODE:
        raise InputError(f"flexibility must be one of {sorted(_LMODE)}, got {flexibility!r}")
    if ellipse is None:
        ae, be = equivalent_ellipse(pa, grid)
    else:
        ae, be = (_checks.positive(n, v) for n, v in zip(("ellipse a", "ellipse b"), ellipse))
        if not (pa > 0.0).any():
            raise InputError("pressure has no element > 0: no contact")
    c = _coefficients(ae / be, material.poisson)
    tx, ty, sx, sy, slip, fx, fy, mz, info = core.fastsim_strips_c(
        grid.dx,
        grid.dy,
        grid.x0,
        grid.y0,
        pa,
        material.shear_modulus,
        *c,
        ae,
        be,
        mu,
        xi,
        eta,
        phi,
        _LMODE[flexibility],
    )
    if info != Status.OK:  # pragma: no cover - the checks above exclude it
        raise error(info, "strip-wise FASTSIM kernel failed", exc=RailvtiError)
    x, y = grid.mesh()
    area = np.full(grid.shape, grid.element_area)
    sv, dens, power = _power(tx, ty, sx, sy, speed, area)
    log.debug("fastsim_grid: equivalent ellipse a=%.4g b=%.4g, Fx=%.4g Fy=%.4g", ae, be, fx, fy)
    return FastsimResult(
        fx=float(fx),
        fy=float(fy),
        mz=float(mz),
        x=x,
        y=y,
        element_area=area,
        pressure=pa,
        tx=tx,
        ty=ty,
        slip=slip.astype(bool),
        slip_velocity=sv,
        power_density=dens,
        power=power,
        a=float(ae),
        b=float(be),
        coefficients=tuple(float(v) for v in c),
    )
