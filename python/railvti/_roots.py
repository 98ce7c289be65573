"""A bracketed scalar root: Brent's method (R. P. Brent, Algorithms for Minimization without
Derivatives, 1973, ch. 4), the few lines railvti needs instead of importing scipy.optimize
(~0.4 s at start-up for one function).

Each step keeps a bracket [x, x_blk] with a sign change and the best point x (smallest |f|);
it tries inverse quadratic interpolation through the last three points (a secant step when
two of them coincide) and takes the step only if it stays well inside the bracket and
shrinks fast enough, else bisects. It stops when half the bracket is below
(xtol + rtol |x|) / 2, as scipy.optimize.brentq does with the same tolerances.
"""

from __future__ import annotations

from typing import Callable

from .errors import ConvergenceError, InputError

#: 4 machine epsilons: the smallest relative tolerance that makes sense.
_RTOL = 4.0 * 2.220446049250313e-16


def brent_root(
    f: Callable[..., float],
    a: float,
    b: float,
    args: tuple = (),
    xtol: float = 2e-12,
    rtol: float = _RTOL,
    maxiter: int = 100,
) -> float:
    """A root of f in [a, b], where f(a) and f(b) differ in sign.

    Parameters
    ----------
    f : callable
        f(x, *args) -> float.
    a, b : float
        The bracket.
    args : tuple
        Extra arguments of f.
    xtol, rtol : float
        The root is located to within xtol + rtol |x|.
    maxiter : int
        Iterations before ConvergenceError.

    Returns
    -------
    float

    Raises
    ------
    InputError
        f(a) and f(b) have the same sign (no bracket).
    ConvergenceError
        Not converged in maxiter iterations.
    """
    x_prev, x = float(a), float(b)
    f_prev, fx = float(f(x_prev, *args)), float(f(x, *args))
    if f_prev == 0.0:
        return x_prev
    if fx == 0.0:
        return x
    if (f_prev > 0.0) == (fx > 0.0):
        raise InputError(f"brent_root: f({a}) = {f_prev} and f({b}) = {fx} have the same sign")
    x_blk, f_blk = x_prev, f_prev
    step = step_old = x - x_prev
    for _ in range(maxiter):
        if (f_prev > 0.0) != (fx > 0.0):
            # the sign change now lies between x_prev and x: x_prev becomes the bracket's end
            x_blk, f_blk = x_prev, f_prev
            step = step_old = x - x_prev
        if abs(f_blk) < abs(fx):
            # keep the best point in x
            x_prev, x, x_blk = x, x_blk, x
            f_prev, fx, f_blk = fx, f_blk, fx
        tol = 0.5 * (xtol + rtol * abs(x))
        half = 0.5 * (x_blk - x)
        if fx == 0.0 or abs(half) < tol:
            return x
        if abs(step_old) > tol and abs(fx) < abs(f_prev):
            if x_prev == x_blk:
                trial = -fx * (x - x_prev) / (fx - f_prev)  # secant
            else:
                s_prev = (f_prev - fx) / (x_prev - x)
                s_blk = (f_blk - fx) / (x_blk - x)
                trial = -fx * (f_blk * s_blk - f_prev * s_prev) / (s_blk * s_prev * (f_blk - f_prev))
            if 2.0 * abs(trial) < min(abs(step_old), 3.0 * abs(half) - tol):
                step_old, step = step, trial  # interpolation accepted
            else:
                step_old = step = half  # bisection
        else:
            step_old = step = half
        x_prev, f_prev = x, fx
        x += step if abs(step) > tol else (tol if half > 0.0 else -tol)
        fx = float(f(x, *args))
    raise ConvergenceError(
        f"brent_root did not converge in {maxiter} iterations (bracket [{x}, {x_blk}])", iterations=maxiter
    )
