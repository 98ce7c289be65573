"""Subsurface stresses below a contact patch, from the tractions on the boundary-element grid.

The tractions are piecewise constant on the grid's rectangular elements; each element's
stress field in the half-space is Love's closed-form rectangle integral of the Boussinesq
(pressure) and Cerruti (shear) solutions (``fortran/contact/contact_subsurface.f90``,
docs/contact_subsurface.md). The fields are summed over the loaded elements directly at
arbitrary points, or by FFT convolution per depth on planes through the element centres.

Conventions: coordinates (x, y, z) with x, y the grid's axes and z >= 0 the depth into the
body, m; stresses in Pa with tension positive (a compressive stress is negative); the
components in Voigt order xx, yy, zz, yz, xz, xy. The body is loaded by the pressure p
(pressing into it) and the shear tractions (qx, qy) acting on its surface. A
:class:`~railvti.contact.RollingResult`'s ``tx, ty`` act on the wheel: the rail carries
``(qx, qy) = -(tx, ty)`` (``body='rail'``, its depth pointing down) and the wheel
``(tx, ty)`` (``body='wheel'``, depth pointing up, the frame mirrored in z: the xz and yz
components then have the signs of the mirrored frame).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .._native import core
from .._status import Status, error
from ..errors import InputError
from ..material import Material
from .grid import Grid
from .normal import NormalResult
from .rolling import RollingResult

log = logging.getLogger(__name__)

#: Voigt order of the stress components.
COMPONENTS = ("xx", "yy", "zz", "yz", "xz", "xy")
_METHODS = ("auto", "direct", "fft")
#: Cost of one element's stress at one point (12 corner functions), s, for the 'auto' choice.
_DIRECT_COST = 6e-7
#: Cost of one lattice corner (three loads) and of one FFT point-log, s.
_CORNER_COST = 5e-7
_FFT_COST = 4e-9
#: Largest memory of the stress arrays of one call, bytes.
MAX_BYTES = 4.0e9


@dataclass(frozen=True)
class SubsurfaceResult:
    """Stresses on the grid ``x`` x ``y`` x ``z`` below a contact patch.

    Attributes
    ----------
    x, y : ndarray
        Positions along the grid's x (rolling) and y (lateral) axes, m.
    z : ndarray
        Depths below the surface, m (> 0).
    stress : ndarray, shape (len(x), len(y), len(z), 6)
        Stress components xx, yy, zz, yz, xz, xy, Pa, tension positive.
    principal : ndarray, shape (len(x), len(y), len(z), 3)
        Principal stresses s1 >= s2 >= s3, Pa.
    von_mises : ndarray, shape (len(x), len(y), len(z))
        Von Mises equivalent stress sqrt(3 J2), Pa.
    tresca : ndarray, shape (len(x), len(y), len(z))
        Tresca equivalent stress s1 - s3 (twice the largest shear stress), Pa.
    method : str
        'direct' or 'fft'.
    body : str
        'rail', 'wheel' or 'given' (tractions given as acting on the body).
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    stress: np.ndarray
    principal: np.ndarray
    von_mises: np.ndarray
    tresca: np.ndarray
    method: str
    body: str

    def component(self, name: str) -> np.ndarray:
        """One stress component by name ('xx', 'yy', 'zz', 'yz', 'xz' or 'xy'), Pa."""
        if name not in COMPONENTS:
            raise InputError(f"component must be one of {COMPONENTS}, got {name!r}")
        return self.stress[..., COMPONENTS.index(name)]

    def _at(self, field: np.ndarray) -> tuple[float, float, float]:
        i, j, k = np.unravel_index(int(np.argmax(field)), field.shape)
        return float(self.x[i]), float(self.y[j]), float(self.z[k])

    @property
    def max_von_mises(self) -> float:
        """Largest von Mises stress on the grid, Pa."""
        return float(self.von_mises.max())

    @property
    def max_von_mises_at(self) -> tuple[float, float, float]:
        """(x, y, z) of the largest von Mises stress on the grid, m."""
        return self._at(self.von_mises)

    @property
    def max_tresca(self) -> float:
        """Largest Tresca stress s1 - s3 on the grid, Pa."""
        return float(self.tresca.max())

    @property
    def max_tresca_at(self) -> tuple[float, float, float]:
        """(x, y, z) of the largest Tresca stress on the grid, m."""
        return self._at(self.tresca)


def _axis(name: str, values: object) -> np.ndarray:
    a = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if a.ndim != 1 or a.size == 0:
        raise InputError(
            f"subsurface {name} must be a non-empty 1-D array of positions (m), got shape {a.shape}"
        )
    if not np.all(np.isfinite(a)):
        raise InputError(f"subsurface {name} must be finite (m)")
    return a


def _depths(z: object) -> np.ndarray:
    zz = _axis("z", z)
    bad = np.flatnonzero(~(zz > 0.0))
    if bad.size:
        raise InputError(
            f"subsurface z: the depth grid must lie inside the half-space, z > 0 (m, positive into "
            f"the body; the surface is z = 0), got z[{bad[0]}] = {zz[bad[0]]:g}"
        )
    return zz


def _field(name: str, value: object, grid: Grid) -> np.ndarray:
    if value is None:
        return np.zeros(grid.shape, order="F")
    a = np.asfortranarray(value, dtype=np.float64)
    if a.shape != grid.shape:
        raise InputError(f"{name} must have the grid's shape {grid.shape}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite (Pa)")
    return a


def _centre_indices(values: np.ndarray, x0: float, h: float, n: int) -> np.ndarray | None:
    """Indices of the element centres at ``values``, or None if one is not a centre."""
    s = (values - x0) / h
    k = np.rint(s)
    if np.any(np.abs(s - k) > 1e-9) or np.any(k < 0) or np.any(k >= n):
        return None
    return k.astype(np.intp)


def _choose(method: str, grid: Grid, n_loaded: int, nxy: int, nz: int, on_centres: bool) -> str:
    if method not in _METHODS:
        raise InputError(f"method must be one of {_METHODS}, got {method!r}")
    if method == "fft" and not on_centres:
        raise InputError("method = 'fft' needs x and y at element centres of the grid (or None)")
    if method != "auto":
        return method
    if not on_centres:
        return "direct"
    m = 4 * grid.nx * grid.ny
    fft = nz * (3 * m * _CORNER_COST + 24 * m * math.log2(m) * _FFT_COST)
    direct = nxy * nz * n_loaded * _DIRECT_COST
    return "fft" if fft < direct else "direct"


def subsurface_stress_fields(
    grid: Grid,
    pressure: object,
    qx: object = None,
    qy: object = None,
    *,
    poisson: float,
    z: object,
    x: object = None,
    y: object = None,
    method: str = "auto",
    body: str = "given",
) -> SubsurfaceResult:
    """Subsurface stresses of tractions given on a grid.

    Parameters
    ----------
    grid : Grid
        The boundary-element grid of the tractions.
    pressure : array_like, shape (nx, ny)
        Normal pressure on the body, Pa (positive pressing into it).
    qx, qy : array_like, shape (nx, ny), optional
        Shear tractions acting on the body's surface along +x, +y, Pa (default zero).
    poisson : float
        Poisson's ratio of the body, in (-1, 0.5).
    z : array_like
        Depths, m, all > 0 (positive into the body).
    x, y : array_like, optional
        Positions along x and y, m (default: the element centres).
    method : {'auto', 'direct', 'fft'}
        'direct' sums over the loaded elements at each point; 'fft' convolves whole planes
        (x and y at element centres only); 'auto' takes the cheaper by an operation count.
    body : str
        Label stored in the result.

    Returns
    -------
    SubsurfaceResult
    """
    nu = float(poisson)
    if not (-1.0 < nu < 0.5):
        raise InputError(f"poisson must lie in (-1, 0.5), got {poisson!r}")
    zz = _depths(z)
    xs = grid.x if x is None else _axis("x", x)
    ys = grid.y if y is None else _axis("y", y)
    p = _field("pressure", pressure, grid)
    fx = _field("qx", qx, grid)
    fy = _field("qy", qy, grid)
    ix = _centre_indices(xs, grid.x0, grid.dx, grid.nx)
    iy = _centre_indices(ys, grid.y0, grid.dy, grid.ny)
    n_loaded = int(np.count_nonzero((p != 0) | (fx != 0) | (fy != 0)))
    how = _choose(method, grid, n_loaded, xs.size * ys.size, zz.size, ix is not None and iy is not None)
    full = grid.nx * grid.ny if how == "fft" else xs.size * ys.size
    need = (full * 6 + xs.size * ys.size * 11) * zz.size * 8.0
    if need > MAX_BYTES:
        raise InputError(
            f"subsurface grid of {xs.size} x {ys.size} x {zz.size} points needs about {need / 1e9:.3g} GB "
            f"(limit {MAX_BYTES / 1e9:g} GB): give fewer depths z or fewer positions x, y"
        )
    if how == "fft":
        sig, info, ibad = core.subsurface_planes_c(grid.dx, grid.dy, p, fx, fy, nu, zz)
        _raise(info, ibad)
        sig = sig[np.ix_(ix, iy)]
    else:
        X, Y, Z = np.meshgrid(xs, ys, zz, indexing="ij")
        sig, info, ibad = core.subsurface_points_c(
            grid.dx,
            grid.dy,
            grid.x0,
            grid.y0,
            p,
            fx,
            fy,
            nu,
            X.ravel(order="F"),
            Y.ravel(order="F"),
            Z.ravel(order="F"),
        )
        _raise(info, ibad)
        sig = sig.reshape(xs.size, ys.size, zz.size, 6, order="F")
    flat = np.asfortranarray(sig.reshape(-1, 6, order="F"))
    prin, vm, tr = core.subsurface_invariants_c(flat)
    shape = sig.shape[:3]
    log.debug("subsurface stresses: %d points, %d loaded elements, %s", flat.shape[0], n_loaded, how)
    return SubsurfaceResult(
        x=xs,
        y=ys,
        z=zz,
        stress=np.ascontiguousarray(sig),
        principal=prin.reshape(*shape, 3, order="F"),
        von_mises=vm.reshape(shape, order="F"),
        tresca=tr.reshape(shape, order="F"),
        method=how,
        body=body,
    )


def _raise(info: int, ibad: int) -> None:
    if int(info) == Status.BAD_ARGUMENT and int(ibad) > 0:
        raise InputError(f"subsurface z: point {int(ibad)} lies outside the half-space (z <= 0)")
    if int(info) != Status.OK:
        raise error(info, "subsurface stresses")


def subsurface_stress(
    result: NormalResult | RollingResult,
    material: Material,
    z: object,
    *,
    x: object = None,
    y: object = None,
    body: str = "rail",
    method: str = "auto",
) -> SubsurfaceResult:
    """Subsurface stresses of a solved contact in the rail or the wheel.

    Parameters
    ----------
    result : NormalResult or RollingResult
        The solved contact; a RollingResult's tangential tractions are included.
    material : Material
        The bodies' material (its Poisson's ratio sets the field).
    z : array_like
        Depths, m, all > 0 (into the body).
    x, y : array_like, optional
        Positions along the grid's x and y, m (default: the element centres).
    body : {'rail', 'wheel'}
        The body: the rail carries ``-(tx, ty)``, the wheel ``(tx, ty)`` (module docstring).
    method : {'auto', 'direct', 'fft'}
        As in :func:`subsurface_stress_fields`.

    Returns
    -------
    SubsurfaceResult
    """
    if body not in ("rail", "wheel"):
        raise InputError(f"body must be 'rail' or 'wheel', got {body!r}")
    if not isinstance(result, (NormalResult, RollingResult)):
        raise InputError(f"result must be a NormalResult or RollingResult, got {type(result).__name__}")
    qx = qy = None
    if isinstance(result, RollingResult):
        sign = -1.0 if body == "rail" else 1.0
        qx, qy = sign * result.tx, sign * result.ty
    return subsurface_stress_fields(
        result.grid,
        result.pressure,
        qx,
        qy,
        poisson=material.poisson,
        z=z,
        x=x,
        y=y,
        method=method,
        body=body,
    )


def hertz_axis_stresses(z_over_a: object, poisson: float) -> tuple[np.ndarray, np.ndarray]:
    """Hertz's stresses on the axis below a circular contact, per p0 (Johnson 1985, eq. 3.45).

    ``sigma_z = -1 / (1 + (z/a)^2)`` and ``sigma_r = sigma_theta =
    -(1 + nu) (1 - (z/a) atan(a/z)) + 1 / (2 (1 + (z/a)^2))``.

    Returns
    -------
    (sigma_r, sigma_z) : tuple of ndarray
        Per unit p0 (tension positive); on the axis the von Mises stress is |sigma_z - sigma_r|.
    """
    s = np.asarray(z_over_a, dtype=np.float64)
    sz = -1.0 / (1.0 + s * s)
    sr = -(1.0 + poisson) * (1.0 - s * np.arctan2(1.0, s)) + 0.5 / (1.0 + s * s)
    return sr, sz


__all__ = [
    "COMPONENTS",
    "SubsurfaceResult",
    "subsurface_stress",
    "subsurface_stress_fields",
    "hertz_axis_stresses",
]
