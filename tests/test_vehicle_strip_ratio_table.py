"""The strips' curvature-ratio table (railvti.vehicle.strip.strip_geometry: the strip
constant c and the Hertz and Kalker factors over x = ln(B/A)) and what it does to the forces
of a near-conformal flange-root strip (issue 30 item 4a: model FF's flange hunting with the
ring's residual flexibility stopped at 2.094 s, docs/vehicle.md "Models RF and FF: limits").

The table is differentiated: a strip's lateral force takes dc/dx times dx/dy = kappa_rail' /
(2 B), about 3e6 1/m where the wheel's flange-root curvature nearly matches the rail's gauge
corner (B -> 0). Ratios rounded to 1e-3 in ln made c a staircase whose spline slope
alternated from node to node, so that the flange slot's lateral force swung by +-2 kN over
1e-8 m (slope +-2e12 N/m, of both signs): with the ring's massless residual coordinates in
the step's equations Newton then found no root at any sub-step.
"""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.contact.hertz import hertz
from railvti.vehicle.strip import (
    STRIP_OUTPUTS,
    UPPER_CLIP,
    UPPER_FLAT,
    UPPER_LINEAR,
    saturated_log_ratio,
    strip_geometry,
    strip_wheel,
)

V, DVDY = STRIP_OUTPUTS.index("V"), STRIP_OUTPUTS.index("dV_dy")
#: The rear wheelset's right wheel at FF's 2.0935 s state (hunting 400 km/h from 4 mm,
#: default ring, residual on), mirrored into the left wheel's frame: y, zc (m), relative roll,
#: yaw (rad). On its flange root alone (23.4 deg, 89 kN); a strip at the patch's edge has
#: x = ln(B/A) ~ -5.1.
FF_POSE = (4.7027216297756552e-03, -1.7634374589951597e-03, 3.0540133969089570e-03, -7.6292992262240291e-03)


@pytest.fixture(scope="module")
def geometry():
    wheel, rail = systems.profiles()
    return strip_geometry(wheel, rail, material=scenarios.wheel_table().material)


def test_ratio_table_is_hertz_at_every_node(geometry):
    """Each node's c = 3/8 kH sqrt(rho) and Hertz a1, b1 equal a direct Hertz solve at the
    node's own ratio (not a ratio rounded to 1e-3 in ln: 2.5e-4 off in c before)."""
    x = geometry.x0 + geometry.dx * np.arange(geometry.fv.shape[0])
    rho = np.exp(saturated_log_ratio(x, UPPER_LINEAR, UPPER_FLAT, np.log(UPPER_CLIP)))
    rho = np.clip(rho, 1.0 / 25.0, UPPER_CLIP)
    mat = scenarios.wheel_table().material
    for i in range(0, x.size, 11):
        h = hertz(1.0, float(rho[i]), 1.0, mat)
        kh = h.approach**-1.5
        np.testing.assert_allclose(geometry.fv[i, 0], 0.375 * kh * np.sqrt(rho[i]), rtol=1e-9)
        np.testing.assert_allclose(geometry.fv[i, 1:3], [h.a, h.b], rtol=1e-9)


def test_flange_root_force_is_smooth_under_yaw(geometry):
    """At FF's failing pose the flange slot's lateral force (dV/dy) rises monotonically with
    the lateral position over +-0.1 um (its slope the contact's lateral stiffness, > 0; was
    +-2e12 N/m of both signs) and agrees with the difference quotient of V."""
    y0, zc, roll, yaw = FF_POSE
    dy = np.linspace(-1e-7, 1e-7, 401)
    out, _ = strip_wheel(geometry, y0 + dy, zc, roll, yaw)
    g = out[:, 1, DVDY]
    slope = np.diff(g) / np.diff(dy)
    assert slope.min() > 0.0, f"dV/dy not monotone: slope {slope.min():.3g} .. {slope.max():.3g} N/m"
    assert slope.max() < 1e11, f"slope up to {slope.max():.3g} N/m"
    fd = np.diff(out[:, 1, V]) / np.diff(dy)
    np.testing.assert_allclose(fd, 0.5 * (g[1:] + g[:-1]), rtol=0.0, atol=2.0)
