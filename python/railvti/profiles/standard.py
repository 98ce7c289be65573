"""Standard profiles generated from their analytic definitions.

* S1002 wheel: EN 13715 (the UIC 510-2 S1002 definition), sections A to H, each a
  polynomial or a circular arc in the standard's coordinates (mm; y from the tread datum,
  positive towards the flange; F(y) the height of the profile, flange positive). The
  coefficients are those of the standard's table; the generated profile matches the
  Manchester benchmark's S1002 file to about 1e-6 mm (tests/test_profiles.py).
* UIC60 / 60E1 rail head: EN 13674-1 drawing of 60E1: crown arc R300 over a chord of
  20.456 mm, arcs R80 to a chord of 52.053 mm, R13 down to the 1:20 head flanks, and an
  R3 fillet towards the 1:2.75 underside of the head (only down to the fillet's vertical
  tangent: the profile must be a function z(y)).
"""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError
from .profile import Profile

# --- S1002 (EN 13715), lengths in mm. The standard's y axis runs from the tread datum
# (y = 0, 70 mm from the flange back) with the flange at negative y: the same orientation as
# railvti's profiles, so y needs no flip. F(y) is the profile height, flange positive
# (= railvti's wheel z, positive downwards towards the rail).
# Section B, y in [-26, 32.15796]: F = sum_k c_k y^k (the standard's alternating signs folded in).
_S1002_B = (
    0.0,
    -3.358537058e-2,
    1.565681624e-3,
    -2.810427944e-5,
    5.844240864e-8,
    -1.562379023e-8,
    5.309217349e-15,
    -5.957839843e-12,
    2.646656573e-13,
)
# Section C, y in [-35, -26]: F = -sum_k c_k y^k.
_S1002_C = (
    4.320221063e3,
    1.038384026e3,
    1.065501873e2,
    6.051367875,
    2.054332446e-1,
    4.169739389e-3,
    4.687195829e-5,
    2.252755540e-7,
)
#: Section boundaries (mm): H | G | F | E | D | C | B | A.
S1002_BREAKS_MM = (-70.0, -62.764705, -49.662352, -39.764473, -38.426669, -35.0, -26.0, 32.15796, 60.0)


def _arc(y: np.ndarray, c: float, r: float) -> np.ndarray:
    return np.sqrt(np.maximum(r * r - (y + c) ** 2, 0.0))


def s1002_mm(y_mm: np.ndarray) -> np.ndarray:
    """S1002 height F (mm, flange positive) at y (mm, flange at y < 0), by EN 13715 sections A-H.

    NaN outside [-70, 60] mm.
    """
    y = np.asarray(y_mm, dtype=np.float64)
    b = S1002_BREAKS_MM
    conds = [
        (y >= b[0]) & (y < b[1]),
        (y >= b[1]) & (y < b[2]),
        (y >= b[2]) & (y < b[3]),
        (y >= b[3]) & (y < b[4]),
        (y >= b[4]) & (y < b[5]),
        (y >= b[5]) & (y < b[6]),
        (y >= b[6]) & (y < b[7]),
        (y >= b[7]) & (y <= b[8]),
    ]
    with np.errstate(invalid="ignore"):
        vals = [
            9.519259302 + _arc(y, 49.5, 20.5),  # H: arc R20.5, flange back
            16.0 + _arc(y, 55.0, 12.0),  # G: arc R12, flange tip
            8.834924130 + _arc(y, 58.558326413, 20.0),  # F: arc R20
            -93.576667419 - 2.747477419 * y,  # E: straight flange face, 70 deg
            16.446 - _arc(y, 26.210665, 13.0),  # D: arc R13, flange root
            -np.polynomial.polynomial.polyval(y, _S1002_C),  # C: polynomial, throat
            np.polynomial.polynomial.polyval(y, _S1002_B),  # B: polynomial, tread
            1.364323640 - 0.066666667 * y,  # A: straight, field-side chamfer
        ]
    return np.select(conds, vals, default=np.nan)


def s1002(step: float = 5e-5, y_min: float = -0.0699, y_max: float = 0.060) -> Profile:
    """The S1002 wheel profile (EN 13715) generated from its analytic definition.

    Parameters
    ----------
    step : float
        Sampling step of the spline's knots, m (0.05 mm by default).
    y_min, y_max : float
        Lateral range, m, within [-0.070, 0.060] (the flange back at -70 mm is vertical
        and is left out by default).

    Returns
    -------
    Profile
        kind 'wheel', y from the tread datum (flange at y < 0), z the radius increase, m.
    """
    step = _checks.positive("step", step)
    lo, hi = _checks.finite("y_min", y_min), _checks.finite("y_max", y_max)
    if not (-0.070 <= lo < hi <= 0.060):
        raise InputError(f"S1002 is defined for -0.070 <= y_min < y_max <= 0.060 m, got {lo}, {hi}")
    n = int(np.ceil((hi - lo) / step)) + 1
    y_mm = np.linspace(lo, hi, n) * 1e3
    return Profile(y_mm * 1e-3, s1002_mm(y_mm) * 1e-3, kind="wheel", name="S1002 (EN 13715)")


# --- UIC60 / 60E1 head (EN 13674-1), mm, uncanted; s lateral, h height up, crown at (0, 0) ---
def _uic60_half(step_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """Field half (s >= 0) of the 60E1 head: points (s, h) in mm, from the crown outwards."""
    r1, r2, r3, rf = 300.0, 80.0, 13.0, 3.0
    c1 = np.array([0.0, -r1])
    a1 = np.arcsin(20.456 / 2 / r1)  # end of R300: chord 20.456 mm
    c2 = c1 + (r1 - r2) * np.array([np.sin(a1), np.cos(a1)])
    a2 = np.arcsin((52.053 / 2 - c2[0]) / r2)  # end of R80: chord 52.053 mm
    c3 = c2 + (r2 - r3) * np.array([np.sin(a2), np.cos(a2)])
    a3 = np.arctan2(20.0, 1.0)  # R13 ends on the 1:20 flank
    p3 = c3 + r3 * np.array([np.sin(a3), np.cos(a3)])
    # R3 fillet tangent to the flank and to the underside line through (0, -51), slope 1:2.75.
    n1 = np.array([20.0, 1.0]) / np.hypot(20.0, 1.0)  # outward normal of the flank
    n2 = np.array([1.0, -2.75]) / np.hypot(1.0, 2.75)  # outward normal of the underside
    cf = np.linalg.solve(np.array([n1, n2]), np.array([p3 @ n1 - rf, np.array([0.0, -51.0]) @ n2 - rf]))
    p4 = cf + rf * n1  # flank end = fillet start

    def arc(c: np.ndarray, r: float, t0: float, t1: float) -> np.ndarray:
        t = np.linspace(t0, t1, max(int(np.ceil(r * (t1 - t0) / step_mm)), 2) + 1)
        return c + r * np.c_[np.sin(t), np.cos(t)]

    m = max(int(np.ceil(np.hypot(*(p4 - p3)) / step_mm)), 2) + 1
    segs = [
        arc(c1, r1, 0.0, a1),
        arc(c2, r2, a1, a2)[1:],
        arc(c3, r3, a2, a3)[1:],
        (p3 + (p4 - p3) * np.linspace(0, 1, m)[:, None])[1:],
        arc(cf, rf, a3, np.pi / 2)[1:],
    ]
    pts = np.vstack(segs)
    return pts[:, 0], pts[:, 1]


def uic60(cant: float = 1.0 / 40.0, step: float = 5e-5) -> Profile:
    """The UIC60 (60E1, EN 13674-1) rail head, canted towards the track centre.

    Parameters
    ----------
    cant : float
        Rail inclination tan(angle), e.g. 1/40 (default) or 1/20; 0 for an upright rail.
        The rail is turned about the top of its crown so that its head leans towards the
        gauge side (negative y): the crown's normal tilts towards the track centre.
    step : float
        Knot spacing, m.

    Returns
    -------
    Profile
        kind 'rail'; y towards the field side, z depth below the crown, m; the head centre
        line passes through the origin before the cant is applied.
    """
    c = _checks.finite("cant", cant)
    if abs(c) > 0.2:
        raise InputError(f"cant must be a small inclination tan(angle) (|cant| <= 0.2), got {c}")
    step = _checks.positive("step", step)
    s, h = _uic60_half(step * 1e3)
    s = np.r_[-s[:0:-1], s]
    h = np.r_[h[:0:-1], h]
    th = np.arctan(c)
    # Positive rotation in the (s, h) plane tilts the crown normal (0, 1) to (-sin, cos).
    sr = s * np.cos(th) - h * np.sin(th)
    hr = s * np.sin(th) + h * np.cos(th)
    # The cant turns one flank's fillet past the vertical: keep the part where z(y) is a
    # function, cutting from the crown (the middle point) outwards at the first reversal.
    mid = len(sr) // 2
    ds = np.diff(sr)
    bad_lo = np.nonzero(ds[:mid] <= 0)[0]
    bad_hi = np.nonzero(ds[mid:] <= 0)[0]
    i0 = int(bad_lo[-1]) + 1 if bad_lo.size else 0
    i1 = mid + int(bad_hi[0]) + 1 if bad_hi.size else len(sr)
    sr, hr = sr[i0:i1], hr[i0:i1]
    return Profile(
        sr * 1e-3, -hr * 1e-3, kind="rail", name=f"UIC60 (60E1) cant 1:{1 / c:.0f}" if c else "UIC60 (60E1)"
    )


__all__ = ["S1002_BREAKS_MM", "s1002_mm", "s1002", "uic60"]
