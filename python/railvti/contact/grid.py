"""The regular grid of boundary elements that covers the potential contact area."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError


@dataclass(frozen=True)
class Grid:
    """Rectangular grid of ``nx x ny`` elements of size ``dx x dy``.

    Element ``[i, j]`` is centred at ``(x0 + i dx, y0 + j dy)``; x is the rolling
    direction. Fields on the grid are ``(nx, ny)`` arrays.

    Parameters
    ----------
    nx, ny : int
        Number of elements in x and y (>= 2).
    dx, dy : float
        Element size, m.
    x0, y0 : float, optional
        Centre of the first element, m. By default the grid is centred on the origin.
    """

    nx: int
    ny: int
    dx: float
    dy: float
    x0: float | None = None
    y0: float | None = None

    def __post_init__(self) -> None:
        nx = _checks.positive_int("nx", self.nx, minimum=2)
        ny = _checks.positive_int("ny", self.ny, minimum=2)
        dx = _checks.positive("dx", self.dx)
        dy = _checks.positive("dy", self.dy)
        x0 = -0.5 * (nx - 1) * dx if self.x0 is None else _checks.finite("x0", self.x0)
        y0 = -0.5 * (ny - 1) * dy if self.y0 is None else _checks.finite("y0", self.y0)
        for name, value in (("nx", nx), ("ny", ny), ("dx", dx), ("dy", dy), ("x0", x0), ("y0", y0)):
            object.__setattr__(self, name, value)
        if nx * ny > 50_000_000:
            raise InputError(f"grid of {nx} x {ny} elements is too large (limit 5e7)")

    @classmethod
    def covering(cls, a: float, b: float, n_per_semiaxis: int = 20, margin: float = 1.25) -> "Grid":
        """A centred grid over the ellipse with semi-axes a (x) and b (y), m.

        The element size is ``min(a, b) / n_per_semiaxis`` in both directions and
        the grid extends ``margin`` times the semi-axes to each side.
        """
        a = _checks.positive("a", a)
        b = _checks.positive("b", b)
        n = _checks.positive_int("n_per_semiaxis", n_per_semiaxis)
        h = min(a, b) / n
        nx = 2 * int(np.ceil(margin * a / h))
        ny = 2 * int(np.ceil(margin * b / h))
        return cls(nx=nx, ny=ny, dx=h, dy=h)

    @property
    def shape(self) -> tuple[int, int]:
        """``(nx, ny)``."""
        return (self.nx, self.ny)

    @property
    def x(self) -> np.ndarray:
        """Element centres in x, m, shape (nx,)."""
        return self.x0 + self.dx * np.arange(self.nx)

    @property
    def y(self) -> np.ndarray:
        """Element centres in y, m, shape (ny,)."""
        return self.y0 + self.dy * np.arange(self.ny)

    @property
    def element_area(self) -> float:
        """dx dy, m^2."""
        return self.dx * self.dy

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Element-centre coordinates as two ``(nx, ny)`` arrays (``indexing='ij'``)."""
        return np.meshgrid(self.x, self.y, indexing="ij")


__all__ = ["Grid"]
