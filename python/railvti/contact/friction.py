"""Friction laws beyond constant Coulomb friction: static and kinetic coefficients,
slip-velocity-dependent ("falling") friction, and what they do to creep-force curves.

The laws (``fortran/contact/contact_friction.f90``; v the slip velocity, m/s;
``d = mu_static - mu_kinetic``; ``v_h`` the slip velocity at which ``d`` is halved):

* ``'coulomb'``: ``mu_static`` in adhesion, ``mu_kinetic`` in slip (a jump law;
  equal coefficients are today's constant Coulomb law, solved by the unchanged path);
* ``'linear'``: ``mu = mu_kinetic + d max(0, 1 - v / (2 v_h))``;
* ``'rational'``: ``mu = mu_kinetic + d / (1 + v / v_h)``;
* ``'exponential'``: ``mu = mu_kinetic + d exp(-ln2 v / v_h)``; Polach's
  ``mu = mu0 ((1 - A) exp(-B v) + A)`` (Polach 2005, Wear 258, 992-1000) is this law
  with ``mu_static = mu0``, ``mu_kinetic = A mu0``, ``v_h = ln2 / B``
  (:meth:`FrictionLaw.polach`).

With falling friction an element's problem can have several solutions (adhesion beside
slip, or several slip magnitudes). ``root_rule = 'continuous'`` (the default) takes the one
nearest to the slip of the current iterate (BEM; the answer then follows the warm start,
e.g. along a creep curve) or of the upstream element (FASTSIM); ``'smallest'`` the one with
the smallest slip (adhesion when admissible). The number of elements where the final
problem had more than one solution is reported (``n_multiple``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _checks
from .._checks import MAX_FRICTION
from .._native import core
from .._status import Status, error
from ..errors import ConvergenceError, GridTooSmallError, InputError, RailvtiError
from ..material import Material
from .grid import Grid
from .kalker import kalker_coefficients
from .normal import solve_normal
from .rolling import (
    DEFAULT_BLOCK,
    DEFAULT_INNER,
    DIRECT_CALL_WORK,
    RollingResult,
    rolling_result,
    solve_tangential,
    start_tractions,
)
from .workspace import call_directly, call_interruptibly, workspace

_KINDS = {"coulomb": 0, "linear": 1, "rational": 2, "exponential": 3}
_RULES = {"smallest": 0, "continuous": 1}
_METHODS = {"gs": 1, "fftgs": 2}
_PRODUCTS = {"auto": 0, "fft": 1, "direct": 2}
_DEFAULT_MAX_ITER = {"gs": 500, "fftgs": 2000}
_EDGE_MESSAGE = (
    "the contact area reaches the last two element rows at the leading grid edge: enlarge the grid"
)
LN2 = math.log(2.0)

#: Deck keys of a friction law (SI), their units and meanings.
FRICTION_KEYS = {
    "friction_law": ("", "'coulomb', 'linear', 'rational', 'exponential' or 'polach'"),
    "mu_static": ("1", "static coefficient (adhesion, v = 0); Polach's mu0"),
    "mu_kinetic": ("1", "kinetic coefficient (large slip velocity); default mu_static"),
    "friction_halving_speed_m_s": ("m/s", "slip velocity at which mu_static - mu_kinetic is halved"),
    "polach_a": ("1", "Polach's A = mu_infinity / mu0, in [0, 1]"),
    "friction_decay_s_m": ("s/m", "Polach's B, the exponential decay rate with the slip velocity"),
    "friction_root_rule": ("", "'smallest' or 'continuous': which of several element solutions"),
}


@dataclass(frozen=True)
class FrictionLaw:
    """A friction law (see the module doc).

    Attributes
    ----------
    law : {'coulomb', 'linear', 'rational', 'exponential'}
    mu_static : float
        Coefficient at zero slip velocity (adhesion), in [0, 1].
    mu_kinetic : float
        Coefficient at large slip velocity, in [0, mu_static].
    halving_speed_m_s : float
        Slip velocity at which ``mu_static - mu_kinetic`` is halved, m/s (> 0; unused by
        'coulomb').
    root_rule : {'smallest', 'continuous'}
        Which solution of an element problem with several: the smallest slip (adhesion
        when admissible), or the one nearest to the slip of the current iterate (BEM) or
        of the upstream element (FASTSIM).
    """

    law: str
    mu_static: float
    mu_kinetic: float
    halving_speed_m_s: float = 1.0
    root_rule: str = "continuous"

    def __post_init__(self) -> None:
        if self.root_rule not in _RULES:
            raise InputError(f"friction_root_rule must be one of {sorted(_RULES)}, got {self.root_rule!r}")
        if self.law not in _KINDS:
            raise InputError(f"friction_law must be one of {sorted(_KINDS) + ['polach']}, got {self.law!r}")
        mus = _checks.finite("mu_static", self.mu_static)
        muk = _checks.finite("mu_kinetic", self.mu_kinetic)
        if not 0.0 <= mus <= MAX_FRICTION:
            raise InputError(f"mu_static = {mus:g} must be in [0, {MAX_FRICTION:g}]")
        if muk < 0.0:
            raise InputError(f"mu_kinetic = {muk:g} must be >= 0")
        if muk > mus:
            raise InputError(
                f"mu_kinetic = {muk:g} > mu_static = {mus:g}: the kinetic coefficient must not exceed the "
                "static one (a friction law that rises with the slip velocity is not supported)"
            )
        vh = _checks.finite("friction_halving_speed_m_s", self.halving_speed_m_s)
        if vh <= 0.0:
            raise InputError(f"friction_halving_speed_m_s = {vh:g} must be > 0 (m/s)")
        object.__setattr__(self, "mu_static", mus)
        object.__setattr__(self, "mu_kinetic", muk)
        object.__setattr__(self, "halving_speed_m_s", vh)

    @classmethod
    def constant(cls, mu: float) -> FrictionLaw:
        """Today's Coulomb law, ``mu_static = mu_kinetic = mu``."""
        return cls("coulomb", mu, mu)

    @classmethod
    def polach(cls, mu0: float, a: float, b_s_m: float) -> FrictionLaw:
        """Polach's ``mu = mu0 ((1 - A) exp(-B v) + A)`` (Polach 2005, eq. 5).

        Parameters
        ----------
        mu0 : float
            Maximum friction coefficient (at zero slip velocity).
        a : float
            ``A = mu_infinity / mu0``, in [0, 1] (key ``polach_a``).
        b_s_m : float
            ``B``, the decay rate, s/m (> 0; key ``friction_decay_s_m``).
        """
        a = _checks.finite("polach_a", a)
        if not 0.0 <= a <= 1.0:
            raise InputError(f"polach_a = {a:g} must be in [0, 1] (A = mu_infinity / mu0)")
        b = _checks.finite("friction_decay_s_m", b_s_m)
        if b <= 0.0:
            raise InputError(f"friction_decay_s_m = {b:g} must be > 0 (s/m)")
        mu0 = _checks.finite("mu_static", mu0)
        return cls("exponential", mu0, a * mu0, LN2 / b)

    @classmethod
    def from_keys(cls, keys: dict[str, Any]) -> FrictionLaw:
        """The law of a deck's keys (:data:`FRICTION_KEYS`); a key the law does not use is refused."""
        unknown = sorted(set(keys) - set(FRICTION_KEYS))
        if unknown:
            raise InputError(f"unknown friction keys {unknown}; known: {sorted(FRICTION_KEYS)}")
        law = str(keys.get("friction_law", "coulomb")).lower()
        if "mu_static" not in keys:
            raise InputError("mu_static is required for a friction law")
        used = {
            "coulomb": {"mu_kinetic"},
            "polach": {"polach_a", "friction_decay_s_m"},
        }.get(law, {"mu_kinetic", "friction_halving_speed_m_s"})
        extra = sorted(set(keys) - used - {"friction_law", "mu_static", "friction_root_rule"})
        if extra:
            raise InputError(f"friction_law = {law!r} does not use the keys {extra}")
        if law == "polach":
            for k in ("polach_a", "friction_decay_s_m"):
                if k not in keys:
                    raise InputError(f"friction_law = 'polach' needs {k}")
            law_p = cls.polach(keys["mu_static"], keys["polach_a"], keys["friction_decay_s_m"])
            return dataclasses.replace(law_p, root_rule=str(keys.get("friction_root_rule", "continuous")))
        if law != "coulomb" and "friction_halving_speed_m_s" not in keys:
            raise InputError(f"friction_law = {law!r} needs friction_halving_speed_m_s (m/s)")
        return cls(
            law,
            keys["mu_static"],
            keys.get("mu_kinetic", keys["mu_static"]),
            keys.get("friction_halving_speed_m_s", 1.0),
            str(keys.get("friction_root_rule", "continuous")),
        )

    @property
    def is_constant(self) -> bool:
        """True for today's constant Coulomb law (``mu_static == mu_kinetic``)."""
        return self.mu_static == self.mu_kinetic

    @property
    def max_slope_s_m(self) -> float:
        """Largest ``-d mu / d v``, s/m (0 for 'coulomb')."""
        d = self.mu_static - self.mu_kinetic
        factor = {"coulomb": 0.0, "linear": 0.5, "rational": 1.0, "exponential": LN2}[self.law]
        return factor * d / self.halving_speed_m_s

    def _args(self) -> tuple[int, float, float, float]:
        return _KINDS[self.law], self.mu_static, self.mu_kinetic, self.halving_speed_m_s

    @property
    def _rule(self) -> int:
        return _RULES[self.root_rule]

    def mu(self, slip_velocity_m_s: Any) -> np.ndarray:
        """Friction coefficient at slip velocities (m/s, >= 0), by the Fortran law."""
        v = np.atleast_1d(np.asarray(slip_velocity_m_s, dtype=np.float64))
        if not np.all(np.isfinite(v)) or np.any(v < 0.0):
            raise InputError("slip velocities must be finite and >= 0 (m/s)")
        return core.friction_mu_c(*self._args(), v)


@dataclass(frozen=True)
class FrictionRollingResult:
    """Steady rolling with a friction law.

    Attributes
    ----------
    rolling : RollingResult
        The solution (its ``mu`` is the law's ``mu_static``).
    law : FrictionLaw
    n_multiple : int
        Elements whose final element problem had more than one solution (the smallest slip
        was taken); 0 when every element problem was unique.
    """

    rolling: RollingResult
    law: FrictionLaw
    n_multiple: int

    @property
    def fx(self) -> float:
        """Longitudinal creep force, N."""
        return self.rolling.fx

    @property
    def fy(self) -> float:
        """Lateral creep force, N."""
        return self.rolling.fy

    @property
    def mu_local(self) -> np.ndarray:
        """``|t| / p`` in the slip area (the law at the local slip velocity), nan elsewhere."""
        r = self.rolling
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(r.slip, np.hypot(r.tx, r.ty) / r.pressure, np.nan)


def solve_tangential_friction(
    pressure: np.ndarray,
    grid: Grid,
    material: Material,
    law: FrictionLaw,
    creepage: tuple[float, float, float],
    speed: float,
    method: str = "fftgs",
    tol: float = 1e-7,
    max_iter: int | None = None,
    t0: tuple | None = None,
    product: str = "auto",
) -> FrictionRollingResult:
    """Steady rolling tangential problem for a given pressure with a friction law.

    Parameters
    ----------
    pressure, grid, material, creepage, speed, method, tol, max_iter, t0, product
        As in :func:`~railvti.contact.solve_tangential`; the speed sets the slip velocity
        ``V |s|`` at which the law is evaluated.
    law : FrictionLaw
        A constant law (``mu_static == mu_kinetic``) runs today's solver unchanged.

    Returns
    -------
    FrictionRollingResult

    Raises
    ------
    InputError, GridTooSmallError, ConvergenceError
        As :func:`~railvti.contact.solve_tangential`.
    """
    if not isinstance(law, FrictionLaw):
        raise InputError("law must be a railvti.contact.friction.FrictionLaw")
    if law.is_constant:
        r = solve_tangential(
            pressure,
            grid,
            material,
            law.mu_static,
            creepage,
            speed,
            method=method,
            tol=tol,
            max_iter=max_iter,
            t0=t0,
            product=product,
        )
        return FrictionRollingResult(rolling=r, law=law, n_multiple=0)
    if not isinstance(grid, Grid) or not isinstance(material, Material):
        raise InputError("grid must be a railvti.contact.Grid and material a railvti.Material")
    p = _checks.finite_array("pressure", pressure, shape=grid.shape)
    if p.min() < 0.0:
        raise InputError("pressure must be >= 0 everywhere")
    xi, eta, phi = (_checks.finite(n, v) for n, v in zip(("xi", "eta", "phi"), creepage))
    speed = _checks.positive("speed", speed)
    if method not in _METHODS or product not in _PRODUCTS:
        raise InputError(f"method must be one of {sorted(_METHODS)} and product one of {sorted(_PRODUCTS)}")
    tol = _checks.positive("tol", tol)
    max_iter = _checks.positive_int("max_iter", _DEFAULT_MAX_ITER[method] if max_iter is None else max_iter)
    tx, ty = start_tractions(grid, t0)
    if p[-2:, :].max() > 0.0:
        raise GridTooSmallError(_EDGE_MESSAGE)
    # as solve_tangential: a long solve in a worker thread that Ctrl-C can leave
    call = call_interruptibly if grid.nx * grid.ny * max_iter > DIRECT_CALL_WORK else call_directly
    status, sx, sy, iters, resid, nmulti, info = call(
        workspace(grid, material, tangential=True),
        core.rolling_friction_solve_c,
        p,
        grid.x0,
        grid.y0,
        xi,
        eta,
        phi,
        *law._args(),
        law._rule,
        speed,
        _METHODS[method],
        DEFAULT_BLOCK,
        DEFAULT_INNER,
        tol,
        max_iter,
        _PRODUCTS[product],
        tx,
        ty,
    )
    if info == Status.GRID_EDGE:
        raise GridTooSmallError(_EDGE_MESSAGE)
    if info not in (Status.OK, Status.NOT_CONVERGED, Status.NO_CONTACT):
        if info == Status.NOT_FINITE:
            raise ConvergenceError(
                "rolling solver with a friction law produced non-finite values",
                iterations=int(iters),
                residual=float("inf"),
            )
        raise error(info, "rolling contact solver failed internally", exc=RailvtiError)
    r = rolling_result(
        grid, p, (tx, ty), (sx, sy), status, law.mu_static, (xi, eta, phi), speed, method, int(iters),
        float(resid), info in (Status.OK, Status.NO_CONTACT),
    )  # fmt: skip
    result = FrictionRollingResult(rolling=r, law=law, n_multiple=int(nmulti))
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"rolling solver with the {law.law} friction law did not converge: residual {resid:.3g} > "
            f"tol {tol:.3g} after {iters} sweeps",
            iterations=int(iters),
            residual=float(resid),
            result=result,
        )
    return result


@dataclass(frozen=True)
class CreepCurve:
    """A creep-force curve: forces against the longitudinal creepage at fixed eta, phi.

    Attributes
    ----------
    xi : ndarray
        Longitudinal creepages, in the order solved.
    fx, fy : ndarray
        Creep forces, N.
    converged : ndarray of bool
    iterations : ndarray of int
    residual : ndarray
    n_multiple : ndarray of int
        Elements with several solutions of their element problem, per creepage.
    fn : float
        Normal force, N.
    """

    xi: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    residual: np.ndarray
    n_multiple: np.ndarray
    fn: float


def creep_curve_friction(
    gap: np.ndarray,
    grid: Grid,
    material: Material,
    law: FrictionLaw,
    fn: float,
    xi: Any,
    speed: float,
    eta: float = 0.0,
    phi: float = 0.0,
    tol: float = 1e-7,
    max_iter: int | None = None,
) -> CreepCurve:
    """Creep-force curve with a friction law on the BEM grid: the normal problem once,
    then steady rolling at each creepage, warm-started from the previous one (creepages
    in the given order: ascending follows the loading branch). A creepage that does not
    converge is kept with ``converged = False`` (never raised).

    Parameters
    ----------
    gap, grid, material, fn
        As in :func:`~railvti.contact.solve_rolling`.
    law : FrictionLaw
    xi : array_like
        Longitudinal creepages.
    speed : float
        Rolling speed, m/s.
    eta, phi : float
        Lateral creepage (1) and spin (1/m).
    tol, max_iter
        As in :func:`solve_tangential_friction`.

    Returns
    -------
    CreepCurve
    """
    fn = _checks.positive("fn", fn)
    xs = np.atleast_1d(np.asarray(xi, dtype=np.float64))
    if xs.size == 0 or not np.all(np.isfinite(xs)):
        raise InputError("xi must be a non-empty array of finite creepages")
    normal = solve_normal(gap, grid, material, fn=fn)
    out = {k: [] for k in ("fx", "fy", "converged", "iterations", "residual", "n_multiple")}
    t0 = None
    for x in xs:
        try:
            r = solve_tangential_friction(
                normal.pressure, grid, material, law, (x, eta, phi), speed, tol=tol, max_iter=max_iter, t0=t0
            )
            ok = True
        except ConvergenceError as exc:
            r, ok = exc.result, False
        rr = r.rolling
        out["fx"].append(rr.fx)
        out["fy"].append(rr.fy)
        out["converged"].append(ok)
        out["iterations"].append(rr.iterations)
        out["residual"].append(rr.residual)
        out["n_multiple"].append(r.n_multiple)
        t0 = (rr.tx, rr.ty)
    return CreepCurve(xi=xs, fn=normal.fn, **{k: np.asarray(v) for k, v in out.items()})


def fastsim_friction(
    a: float,
    b: float,
    material: Material,
    law: FrictionLaw,
    fn: Any,
    creepage: tuple[Any, Any, Any],
    speed: float,
    slope_reduction: float = 1.0,
    nx: int = 50,
    ny: int = 50,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """FASTSIM with a friction law and a slope reduction, parabolic pressure on an ellipse.

    Parameters
    ----------
    a, b : float
        Semi-axes, m (a along the rolling direction).
    material : Material
    law : FrictionLaw
    fn : float or array_like
        Normal force(s), N.
    creepage : (xi, eta, phi)
        Each a float or an array (broadcast together with fn): creepages (1, 1) and spin (1/m).
    speed : float
        Rolling speed, m/s.
    slope_reduction : float
        Factor in (0, 1] on the creep stiffness (flexibilities divided by it): Polach's
        initial-slope reduction ``(k_A + k_S) / 2``.
    nx, ny : int
        Elements per strip and strips.

    Returns
    -------
    fx, fy, mz : ndarray
        Creep forces (N) and spin moment (N m).
    n_multiple : ndarray of int
        Elements whose element problem had several solutions, per case.
    """
    if not isinstance(law, FrictionLaw) or not isinstance(material, Material):
        raise InputError("law must be a FrictionLaw and material a Material")
    a, b = _checks.positive("a", a), _checks.positive("b", b)
    speed = _checks.positive("speed", speed)
    k = _checks.finite("slope_reduction", slope_reduction)
    if not 0.0 < k <= 1.0:
        raise InputError(f"slope_reduction = {k:g} must be in (0, 1]")
    nx, ny = _checks.positive_int("nx", nx), _checks.positive_int("ny", ny)
    arrays = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=np.float64)) for v in (fn, *creepage)))
    f, xi, eta, phi = (np.ascontiguousarray(v.ravel()) for v in arrays)
    if not all(np.all(np.isfinite(v)) for v in (f, xi, eta, phi)) or np.any(f <= 0.0):
        raise InputError("fn must be > 0 and the creepages finite")
    c11, c22, c23 = (float(c) for c in kalker_coefficients(a / b, material.poisson))
    fx, fy, mz, nm = core.fastsim_friction_c(
        a,
        b,
        material.shear_modulus,
        c11,
        c22,
        c23,
        *law._args(),
        law._rule,
        k,
        f,
        xi,
        eta,
        phi,
        speed,
        nx,
        ny,
    )
    return fx, fy, mz, nm


def polach_creep_force(
    fn: float,
    a: float,
    b: float,
    material: Material,
    mu0: float,
    polach_a: float,
    decay_s_m: float,
    k_a: float,
    k_s: float,
    speed: float,
    creepage: Any,
) -> np.ndarray:
    """Polach's closed-form longitudinal creep force |F| (N) (Polach 2005, Wear 258, eqs 2-6).

    ``F = 2 Q mu / pi (k_A eps / (1 + (k_A eps)^2) + atan(k_S eps))``,
    ``eps = G C11 pi a b s / (4 Q mu)``, ``mu = mu0 ((1 - A) exp(-B V s) + A)``.

    Parameters
    ----------
    fn : float
        Wheel load Q, N.
    a, b : float
        Semi-axes, m.
    material : Material
        Its shear modulus and Poisson's ratio (Kalker's C11 for a/b).
    mu0, polach_a, decay_s_m : float
        mu0, A in [0, 1], B (s/m).
    k_a, k_s : float
        Reduction factors in the areas of adhesion and slip, ``0 < k_s <= k_a <= 1``.
    speed : float
        Rolling speed V, m/s.
    creepage : array_like
        Creepage magnitudes s.

    Returns
    -------
    ndarray
        |F|, N.
    """
    law = FrictionLaw.polach(mu0, polach_a, decay_s_m)  # checks mu0, A, B
    for name, v in (("k_a", k_a), ("k_s", k_s)):
        v = _checks.finite(name, v)
        if not 0.0 < v <= 1.0:
            raise InputError(f"{name} = {v:g} must be in (0, 1]")
    if k_s > k_a:
        raise InputError(f"k_s = {k_s:g} > k_a = {k_a:g}: Polach's reduction in slip must not exceed k_a")
    s = np.abs(np.atleast_1d(np.asarray(creepage, dtype=np.float64)))
    c11 = float(kalker_coefficients(a / b, material.poisson)[0])
    return core.polach_force_c(
        _checks.positive("fn", fn),
        a,
        b,
        material.shear_modulus,
        c11,
        law.mu_static,
        polach_a,
        decay_s_m,
        k_a,
        k_s,
        _checks.positive("speed", speed),
        s,
    )


__all__ = [
    "FRICTION_KEYS",
    "CreepCurve",
    "FrictionLaw",
    "FrictionRollingResult",
    "creep_curve_friction",
    "fastsim_friction",
    "polach_creep_force",
    "solve_tangential_friction",
]
