"""Closed-form references for validating the axisymmetric finite elements.

* Free-free Timoshenko beam of circular cross-section: exact solution of the
  Timoshenko equations, split into modes symmetric and antisymmetric about
  mid-length (2 x 2 frequency determinants); shear coefficient of a solid
  circle kappa = 6 (1 + nu) / (7 + 6 nu) (Cowper 1966).
* Kirchhoff annular plate clamped at the inner radius b and free at the outer
  radius a, nodal diameters k: W = A J_k + B Y_k + C I_k + D K_k of lambda r,
  lambda^4 = rho h omega^2 / D (Leissa, Vibration of Plates, NASA SP-160, 1969,
  sec. 2.3): 4 x 4 determinant, roots by bracketing.
* Wheelset bending (k = 1) from an independent lumped model: the stepped axle
  as Timoshenko beam elements (cubic Hermite, Przemieniecki 1968, with shear
  and rotary inertia), each wheel (hub, web, rim, flange) a rigid body of the
  same mass and diametral inertia. It brackets the axisymmetric FE from above
  (rigid webs); the gap is the web flexibility.
"""

from __future__ import annotations

import numpy as np
from scipy import linalg, optimize, special


def _roots(fun, x_lo: float, x_hi: float, n: int, steps: int = 4000) -> list[float]:
    xs = np.linspace(x_lo, x_hi, steps)
    vals = np.array([fun(x) for x in xs])
    out: list[float] = []
    for i in range(steps - 1):
        if np.sign(vals[i]) != np.sign(vals[i + 1]) and np.isfinite(vals[i]) and np.isfinite(vals[i + 1]):
            r = optimize.brentq(fun, xs[i], xs[i + 1], xtol=1e-13)
            # keep roots only, not sign flips through poles
            if abs(fun(r)) < 1e-6 * (abs(vals[i]) + abs(vals[i + 1]) + 1e-300) + 1e-12:
                out.append(r)
        if len(out) >= n:
            break
    return out


def timoshenko_free_free(
    length: float, diameter: float, young: float, poisson: float, density: float, n_modes: int = 4
) -> np.ndarray:
    """Bending natural frequencies (Hz) of a free-free solid circular Timoshenko beam."""
    g = young / (2.0 * (1.0 + poisson))
    kap = 6.0 * (1.0 + poisson) / (7.0 + 6.0 * poisson)
    area = np.pi * diameter**2 / 4.0
    inertia = np.pi * diameter**4 / 64.0
    ei, kga, ra, ri = young * inertia, kap * g * area, density * area, density * inertia
    half = 0.5 * length

    def det(w: float, sym: bool) -> float:
        # k s^4 + ... : roots s^2 = a^2 (real) and -b^2 (oscillatory)
        c4, c2, c0 = kga * ei, w * w * (kga * ri + ra * ei), ra * w * w * (ri * w * w - kga)
        disc = np.sqrt(c2 * c2 - 4.0 * c4 * c0)
        a = np.sqrt((-c2 + disc) / (2.0 * c4))
        b = np.sqrt((c2 + disc) / (2.0 * c4))
        # w = cosh(a x) (sym) / sinh(a x); psi = ((kga s^2 + ra w^2)/(kga s)) w-amplitude
        pa = (kga * a * a + ra * w * w) / (kga * a)
        pb = (-kga * b * b + ra * w * w) / (kga * b)
        x = half
        if sym:
            # w = C1 cosh(ax) + C2 cos(bx); psi = C1 pa sinh(ax) + C2 pb sin(bx)
            wp = [a * np.sinh(a * x), -b * np.sin(b * x)]
            ps = [pa * np.sinh(a * x), pb * np.sin(b * x)]
            psp = [pa * a * np.cosh(a * x), pb * b * np.cos(b * x)]
        else:
            # w = C1 sinh(ax) + C2 sin(bx); psi = C1 pa cosh(ax) - C2 pb cos(bx)
            wp = [a * np.cosh(a * x), b * np.cos(b * x)]
            ps = [pa * np.cosh(a * x), -pb * np.cos(b * x)]
            psp = [pa * a * np.sinh(a * x), pb * b * np.sin(b * x)]
        m = np.array([psp, [wp[0] - ps[0], wp[1] - ps[1]]])
        m /= np.abs(m).max(axis=0)
        return float(np.linalg.det(m))

    w_hi = 2.0 * np.pi * 20.0 * np.sqrt(ei / ra) / length**2 * (n_modes + 2) ** 2
    w_hi = min(w_hi, 0.95 * np.sqrt(kga / ri))
    roots = _roots(lambda w: det(w, True), 1e-3, w_hi, n_modes) + _roots(
        lambda w: det(w, False), 1e-3, w_hi, n_modes
    )
    return np.sort(np.array(roots))[:n_modes] / (2.0 * np.pi)


def annular_plate_clamped_free(
    inner: float,
    outer: float,
    thickness: float,
    young: float,
    poisson: float,
    density: float,
    k: int,
    n_modes: int = 2,
) -> np.ndarray:
    """Natural frequencies (Hz) of a Kirchhoff annular plate, clamped inside, free outside."""
    dp = young * thickness**3 / (12.0 * (1.0 - poisson**2))
    nu = poisson

    def rows(lam: float) -> np.ndarray:
        b, a = inner, outer
        cols = []
        for fun, dfun in (
            (special.jv, special.jvp),
            (special.yv, special.yvp),
            (special.iv, special.ivp),
            (special.kv, special.kvp),
        ):
            wb = fun(k, lam * b)
            wpb = lam * dfun(k, lam * b, 1)
            w, w1 = fun(k, lam * a), lam * dfun(k, lam * a, 1)
            w2, w3 = lam**2 * dfun(k, lam * a, 2), lam**3 * dfun(k, lam * a, 3)
            r = a
            mr = w2 + nu * (w1 / r - k * k * w / r**2)
            lap_d = w3 + w2 / r - w1 / r**2 - k * k * w1 / r**2 + 2.0 * k * k * w / r**3
            vr = lap_d - (1.0 - nu) * k * k / r**2 * (w1 - w / r)
            cols.append([wb, wpb, mr, vr])
        m = np.array(cols).T
        m /= np.abs(m).max(axis=0)
        return m

    def det(lam: float) -> float:
        return float(np.linalg.det(rows(lam)))

    lam_hi = (n_modes + 3) * 3.5 / (outer - inner) + 1.0
    lams = _roots(det, 0.2 / outer, lam_hi, n_modes, steps=6000)
    rho_h = density * thickness
    return np.array([lam**2 * np.sqrt(dp / rho_h) / (2.0 * np.pi) for lam in lams])


def wheel_rigid_body(geometry) -> tuple[float, float, float]:
    """Mass (kg), axial centre of mass (m) and diametral inertia about it (kg m^2)
    of the right-hand wheel of a :class:`WheelsetGeometry` (all of its meridian
    blocks outside the wheel-seat radius)."""
    rho = geometry.density
    blocks = [b for b in geometry.blocks() if b.y0 >= 0.0 and b.r0 >= geometry.seat_radius - 1e-12]
    ms = np.array([rho * np.pi * (b.r1**2 - b.r0**2) * (b.y1 - b.y0) for b in blocks])
    yc = np.array([0.5 * (b.y0 + b.y1) for b in blocks])
    mass = float(ms.sum())
    y_cm = float(ms @ yc / mass)
    jd = sum(
        m * ((b.r1**2 + b.r0**2) / 4.0 + (b.y1 - b.y0) ** 2 / 12.0 + (y - y_cm) ** 2)
        for m, y, b in zip(ms, yc, blocks)
    )
    return mass, y_cm, float(jd)


def wheelset_mass_properties(geometry) -> dict[str, float]:
    """Rigid-body mass properties of a :class:`WheelsetGeometry` (no brake
    discs, no axleboxes), integrated exactly over its meridian blocks.

    Returns
    -------
    dict
        ``wheel_mass`` (one wheel, kg), ``axle_mass`` (kg), ``mass`` (wheelset, kg),
        ``wheel_diametral_inertia`` (one wheel about its own centre of mass, kg m^2),
        ``spin_inertia`` (about the axle, kg m^2) and ``roll_inertia`` (about a
        diameter through the wheelset centre: the roll and yaw inertia, kg m^2).
    """
    rho = geometry.density
    blocks = geometry.blocks()
    ms = np.array([rho * np.pi * (b.r1**2 - b.r0**2) * (b.y1 - b.y0) for b in blocks])
    axle = np.array([b.r1 <= geometry.seat_radius + 1e-12 for b in blocks])
    spin = sum(m * (b.r1**2 + b.r0**2) / 2.0 for m, b in zip(ms, blocks))
    roll = sum(
        m * ((b.r1**2 + b.r0**2) / 4.0 + (b.y1 - b.y0) ** 2 / 12.0 + (0.5 * (b.y0 + b.y1)) ** 2)
        for m, b in zip(ms, blocks)
    )
    m_w, _, j_w = wheel_rigid_body(geometry)
    return {
        "wheel_mass": m_w,
        "axle_mass": float(ms[axle].sum()),
        "mass": float(ms.sum()),
        "wheel_diametral_inertia": j_w,
        "spin_inertia": float(spin),
        "roll_inertia": float(roll),
    }


def wheelset_beam_k1(
    geometry, n_modes: int = 2, n_el: int = 400, extra_masses: tuple[tuple[float, float, float], ...] = ()
) -> np.ndarray:
    """Flexible free-free bending frequencies (Hz) of a wheelset as a stepped
    Timoshenko beam with rigid wheels.

    Parameters
    ----------
    geometry : WheelsetGeometry
        Axle radii and stations, wheels, material.
    n_modes : int
        Flexible modes returned (the two rigid modes are skipped).
    n_el : int
        Beam elements over the axle length (refined at every step).
    extra_masses : tuple of (y, mass, diametral inertia)
        Rigid bodies on the axle (e.g. brake discs): position (m), kg, kg m^2.

    Returns
    -------
    ndarray (n_modes,)
        Ascending frequencies, Hz.
    """
    g = geometry
    e, nu, rho = g.young, g.poisson, g.density
    gm = e / (2.0 * (1.0 + nu))
    kap = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)
    (yh0, yh1), (yj0, yj1) = g.hub_y, g.journal_y

    def radius(y: float) -> float:
        y = abs(y)
        if y < yh0:
            return g.body_radius
        if y < yh1:
            return g.seat_radius
        return g.collar_radius if y < yj0 else g.journal_radius

    mass, y_cm, jd = wheel_rigid_body(g)
    stations = [yh0, yh1, yj0, y_cm] + [abs(y) for y, _, _ in extra_masses]
    ys = np.unique(
        np.round(np.concatenate([np.linspace(-yj1, yj1, n_el + 1), stations, -np.array(stations)]), 12)
    )
    n = ys.size
    kk = np.zeros((2 * n, 2 * n))
    mm = np.zeros((2 * n, 2 * n))
    for i in range(n - 1):
        le = ys[i + 1] - ys[i]
        r = radius(0.5 * (ys[i] + ys[i + 1]))
        area, inertia = np.pi * r**2, np.pi * r**4 / 4.0
        phi = 12.0 * e * inertia / (kap * gm * area * le**2)
        ke = (
            e
            * inertia
            / (le**3 * (1.0 + phi))
            * np.array(
                [
                    [12.0, 6.0 * le, -12.0, 6.0 * le],
                    [6.0 * le, (4.0 + phi) * le**2, -6.0 * le, (2.0 - phi) * le**2],
                    [-12.0, -6.0 * le, 12.0, -6.0 * le],
                    [6.0 * le, (2.0 - phi) * le**2, -6.0 * le, (4.0 + phi) * le**2],
                ]
            )
        )
        # consistent translational and rotary mass (Euler-Bernoulli shape functions)
        mt = (
            rho
            * area
            * le
            / 420.0
            * np.array(
                [
                    [156.0, 22.0 * le, 54.0, -13.0 * le],
                    [22.0 * le, 4.0 * le**2, 13.0 * le, -3.0 * le**2],
                    [54.0, 13.0 * le, 156.0, -22.0 * le],
                    [-13.0 * le, -3.0 * le**2, -22.0 * le, 4.0 * le**2],
                ]
            )
        )
        mr = (
            rho
            * inertia
            / (30.0 * le)
            * np.array(
                [
                    [36.0, 3.0 * le, -36.0, 3.0 * le],
                    [3.0 * le, 4.0 * le**2, -3.0 * le, -(le**2)],
                    [-36.0, -3.0 * le, 36.0, -3.0 * le],
                    [3.0 * le, -(le**2), -3.0 * le, 4.0 * le**2],
                ]
            )
        )
        d = slice(2 * i, 2 * i + 4)
        kk[d, d] += ke
        mm[d, d] += mt + mr
    for y, m, j in [(y_cm, mass, jd), (-y_cm, mass, jd), *extra_masses]:
        q = int(np.argmin(np.abs(ys - y)))
        mm[2 * q, 2 * q] += m
        mm[2 * q + 1, 2 * q + 1] += j
    w = linalg.eigh(kk, mm, eigvals_only=True)
    f = np.sqrt(np.clip(w, 0.0, None)) / (2.0 * np.pi)
    return f[2 : 2 + n_modes]


__all__ = [
    "timoshenko_free_free",
    "annular_plate_clamped_free",
    "wheel_rigid_body",
    "wheelset_mass_properties",
    "wheelset_beam_k1",
]
