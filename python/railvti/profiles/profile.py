"""The :class:`Profile` object: a wheel or rail cross-section as a smooth function z(y)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from .._spline import NotAKnotSpline
from ..errors import InputError

#: Plausible lateral extent of a wheel or rail profile, m. A profile in m read as mm is
#: 1000 times too small (a few hundredths of a millimetre); one in mm read as m is too large.
MIN_WIDTH = 0.02
MAX_WIDTH = 0.5

KINDS = ("wheel", "rail")


def _segments_cross(y: np.ndarray, z: np.ndarray) -> tuple[int, int] | None:
    """First pair (i, j) of non-adjacent polyline segments that cross, or None."""
    p0 = np.c_[y[:-1], z[:-1]]
    p1 = np.c_[y[1:], z[1:]]
    n = len(p0)
    d = p1 - p0
    # Segment pairs are tested block-wise to keep memory small for long profiles.
    for i0 in range(0, n, 256):
        a0, da = p0[i0 : i0 + 256, None, :], d[i0 : i0 + 256, None, :]
        b0, db = p0[None, :, :], d[None, :, :]
        den = da[..., 0] * db[..., 1] - da[..., 1] * db[..., 0]
        w = b0 - a0
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (w[..., 0] * db[..., 1] - w[..., 1] * db[..., 0]) / den
            u = (w[..., 0] * da[..., 1] - w[..., 1] * da[..., 0]) / den
        hit = (den != 0) & (t > 0) & (t < 1) & (u > 0) & (u < 1)
        ii, jj = np.nonzero(hit)
        ii = ii + i0
        keep = np.abs(ii - jj) > 1
        if keep.any():
            k = int(np.argmax(keep))
            return int(ii[k]), int(jj[k])
    return None


@dataclass(frozen=True)
class Profile:
    """A wheel or rail profile: a cross-section curve z(y) with a cubic-spline representation.

    Coordinates (SIMPACK / CONTACT convention, SI metres):

    * ``y`` lateral, positive towards the **field side** (away from the track centre); for
      a wheel the flange is at negative ``y``, for a rail the gauge face is at negative ``y``.
    * ``z`` vertical, positive **downwards**. For a wheel, ``z`` is the increase of the
      radius over the nominal radius at ``y = 0`` (tread datum): the flange has large ``z``.
      For a rail, ``z`` is the depth below the profile origin (rail top near ``z = 0``).

    Parameters
    ----------
    y, z : array_like
        Profile points, m. ``y`` must be strictly monotone (it is sorted to increasing);
        points must be finite; the polyline must not cross itself.
    kind : {'wheel', 'rail'}
        What the profile is.
    name : str
        A label.
    max_slope : float
        Points at the two ends where ``|dz/dy|`` exceeds this (near-vertical flanks, e.g.
        below a rail's gauge corner) are trimmed before the spline is made; 20 (87 deg)
        by default. Interior points are never trimmed.

    Raises
    ------
    InputError
        NaN/inf points, fewer than 4 points, implausible size (a profile in m declared
        as mm), a self-intersecting polyline, or ``y`` not monotone.
    """

    y: np.ndarray
    z: np.ndarray
    kind: str = "rail"
    name: str = ""
    max_slope: float = 20.0
    _spline: NotAKnotSpline = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InputError(f"kind must be one of {KINDS}, got {self.kind!r}")
        y = np.array(self.y, dtype=np.float64).ravel()
        z = np.array(self.z, dtype=np.float64).ravel()
        if y.shape != z.shape:
            raise InputError(f"profile y and z differ in length ({y.size} and {z.size})")
        if y.size < 4:
            raise InputError(f"profile {self.name!r} needs at least 4 points, got {y.size}")
        for nm, a in (("y", y), ("z", z)):
            bad = ~np.isfinite(a)
            if bad.any():
                raise InputError(
                    f"profile {self.name!r}: {nm} has {int(bad.sum())} NaN/inf value(s), "
                    f"first at point {int(np.argmax(bad))}"
                )
        width = float(y.max() - y.min())
        height = float(z.max() - z.min())
        if width < MIN_WIDTH or max(width, height) > MAX_WIDTH:
            raise InputError(
                f"profile {self.name!r} has an implausible size: {width * 1e3:.4g} mm wide, "
                f"{height * 1e3:.4g} mm high (expected {MIN_WIDTH * 1e3:.0f}..{MAX_WIDTH * 1e3:.0f} mm); "
                "are the coordinates in m where mm was declared, or the reverse?"
            )
        dy = np.diff(y)
        if np.all(dy < 0):
            y, z, dy = y[::-1], z[::-1], -dy[::-1]
        if not np.all(dy > 0):
            # a graph over strictly monotone y cannot cross itself: only now is it worth looking
            cross = _segments_cross(y, z)
            if cross is not None:
                i, j = cross
                raise InputError(
                    f"profile {self.name!r} intersects itself: segment {i} "
                    f"(y = {y[i] * 1e3:.3f} mm) crosses segment {j} (y = {y[j] * 1e3:.3f} mm)"
                )
            k = int(np.argmax(dy <= 0)) if dy[0] > 0 else int(np.argmax(dy >= 0))
            raise InputError(
                f"profile {self.name!r} is not a function z(y): y is not monotone "
                f"at point {k + 1} (y = {y[k + 1] * 1e3:.4f} mm)"
            )
        ms = _checks.positive("max_slope", self.max_slope)
        slope = np.abs(np.diff(z) / dy)
        ok = slope <= ms
        if not ok.any():
            raise InputError(f"profile {self.name!r}: every segment is steeper than max_slope={ms}")
        first = int(np.argmax(ok))
        last = len(ok) - int(np.argmax(ok[::-1]))  # one past the last good segment
        y, z = y[first : last + 1], z[first : last + 1]
        if y.size < 4:
            raise InputError(f"profile {self.name!r} has fewer than 4 points below max_slope={ms}")
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)
        object.__setattr__(self, "max_slope", ms)
        object.__setattr__(self, "_spline", NotAKnotSpline(y, z))

    # -- smooth representation -------------------------------------------------------
    @property
    def y_min(self) -> float:
        """Smallest lateral coordinate of the profile, m."""
        return float(self.y[0])

    @property
    def y_max(self) -> float:
        """Largest lateral coordinate of the profile, m."""
        return float(self.y[-1])

    def _arg(self, y: np.ndarray | float) -> np.ndarray:
        a = np.asarray(y, dtype=np.float64)
        if np.any((a < self.y[0] - 1e-12) | (a > self.y[-1] + 1e-12)):
            raise InputError(
                f"y outside the profile {self.name!r} ({self.y[0] * 1e3:.3f}..{self.y[-1] * 1e3:.3f} mm)"
            )
        return np.clip(a, self.y[0], self.y[-1])

    def height(self, y: np.ndarray | float) -> np.ndarray:
        """Profile coordinate z(y), m (positive downwards; see the class docstring)."""
        return self._spline(self._arg(y))

    def slope(self, y: np.ndarray | float) -> np.ndarray:
        """dz/dy (dimensionless)."""
        return self._spline(self._arg(y), 1)

    def curvature(self, y: np.ndarray | float) -> np.ndarray:
        """Signed curvature z'' / (1 + z'^2)^(3/2), 1/m.

        Positive where the profile is convex seen from below (z downwards): a rail
        crown of radius R gives +1/R; a hollow wheel tread gives a positive value too,
        so the relative (Hertz) curvature of a wheel-rail pair is ``rail - wheel``.
        """
        a = self._arg(y)
        d1 = self._spline(a, 1)
        return self._spline(a, 2) / (1.0 + d1 * d1) ** 1.5

    def sample(self, step: float = 5e-5) -> tuple[np.ndarray, np.ndarray]:
        """The spline sampled at a uniform step (m) over its whole range: (y, z)."""
        step = _checks.positive("step", step)
        n = max(int(np.ceil((self.y[-1] - self.y[0]) / step)) + 1, 4)
        yy = np.linspace(self.y[0], self.y[-1], n)
        return yy, self._spline(yy)


__all__ = ["MIN_WIDTH", "MAX_WIDTH", "KINDS", "Profile"]
