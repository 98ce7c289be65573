"""Parametrised passenger wheelset: axle with journals, collars and wheel seats,
two monobloc wheels (hub, straight web, rim with flange); meridian section as
blocks for the structured mesher, and outline checks.

Defaults (m) describe a 920 mm passenger wheelset on standard gauge:
nominal rolling radius 0.46 and back-to-back 1.36 (issue 6); rim 135 mm wide
(EN 13262 monobloc wheels); taping line 70 mm from the inner rim face; flange
28 mm high and 32.5 mm thick (EN 13715 S1002 new profile); journal centres 2.0 m
apart with 130 mm journals, 195 mm wheel seats and a 170 mm axle body (typical
EN 13103 passenger trailer axle). The web tapers from 45 mm at the hub to
22 mm at the rim (typical of 920 mm monobloc wheels); the mesher needs
axis-parallel blocks, so the taper is a staircase of ``web_steps`` straight
segments and the web is plane (a real web is curved).

These are typical values, not one manufacturer's drawing: no public drawing of
a 920 mm high-speed trailer wheelset could be retrieved. Check on the whole:
the free-free bending modes of the default (86.8, 146.5, 293.4, 560.5 Hz) lie
within 3.3 % of a published FE model of a high-speed EMU wheelset (87, 143, 284,
576 Hz: Wu, Cai, Jin, Xiao et al., Appl. Sci. 10 (2020) 5880, Fig. 8). Masses:
wheel 358 kg, axle 378 kg, bare wheelset 1094 kg (no brake discs or axleboxes;
``analytic.wheelset_mass_properties``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np

from .. import _checks
from ..errors import InputError
from .mesh import Block, MeridianMesh, check_simple_polygon, mesh_blocks


@dataclass(frozen=True)
class WheelsetGeometry:
    """Dimensions (m), material and mesh sizes of a symmetric wheelset.

    The axle runs along y with y = 0 at mid-length; r is the radius.

    Attributes
    ----------
    wheel_radius : float
        Nominal rolling radius r0 at the taping line (tread), m.
    back_to_back : float
        Distance between the inner rim faces (flange backs), m; 1.36 is the nominal value of
        standard-gauge wheelsets (EN 13260). The rigid contact geometry (railvti.geometry)
        uses this class too: its back_to_back, wheel_radius and contact_offset place the
        wheel profiles.
    rim_width, rim_depth : float
        Axial width and radial depth of the rim below r0, m.
    flange_height, flange_width : float
        Flange above r0 and its axial width at the inner rim face, m.
    web_thickness_hub, web_thickness_rim : float
        Axial thickness of the web at the hub and at the rim, m (linear taper).
    web_steps : int
        Straight segments approximating the taper.
    web_offset : float
        Axial position of the web centre relative to the rim centre (+ outward), m.
    hub_radius, hub_width, hub_offset : float
        Hub outer radius, axial width, centre relative to the rim centre (+ outward), m.
    seat_radius, body_radius, collar_radius, journal_radius : float
        Axle radii at the wheel seats, the body between them, the collars
        (dust-guard seats) and the journals, m.
    journal_spacing, journal_length : float
        Distance between journal centres and journal length, m.
    contact_offset : float
        Taping line (contact point; the wheel profile's tread datum y = 0) from the inner
        rim face, m; 0.070 for EN 13715 profiles such as S1002.
    young, poisson, density : float
        Steel: E (Pa), nu, rho (kg/m^3).
    mesh_size, axle_mesh_size : float
        Target element edge in the wheels and in the axle, m.
    """

    wheel_radius: float = 0.46
    back_to_back: float = 1.36
    rim_width: float = 0.135
    rim_depth: float = 0.065
    flange_height: float = 0.028
    flange_width: float = 0.0325
    web_thickness_hub: float = 0.045
    web_thickness_rim: float = 0.022
    web_steps: int = 4
    web_offset: float = -0.02
    hub_radius: float = 0.14
    hub_width: float = 0.18
    hub_offset: float = -0.035
    seat_radius: float = 0.0975
    body_radius: float = 0.085
    collar_radius: float = 0.08
    journal_radius: float = 0.065
    journal_spacing: float = 2.0
    journal_length: float = 0.19
    contact_offset: float = 0.07
    young: float = 210e9
    poisson: float = 0.3
    density: float = 7850.0
    mesh_size: float = 0.02
    axle_mesh_size: float = 0.04

    def __post_init__(self) -> None:
        signed = {"web_offset", "hub_offset"}
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in signed:
                object.__setattr__(self, f.name, _checks.finite(f.name, v))
            elif f.name == "web_steps":
                object.__setattr__(self, f.name, _checks.positive_int(f.name, v))
            elif f.name == "poisson":
                nu = _checks.finite("poisson", v)
                if not 0.0 <= nu < 0.5:
                    raise InputError(f"poisson must lie in [0, 0.5), got {nu}")
                object.__setattr__(self, f.name, nu)
            else:
                object.__setattr__(self, f.name, _checks.positive(f.name, v))
        self._check_outline()

    # --- axial stations of the right-hand half (y > 0) ---
    @property
    def rim_y(self) -> tuple[float, float]:
        """Inner and outer rim face, m."""
        y0 = 0.5 * self.back_to_back
        return y0, y0 + self.rim_width

    @property
    def rim_centre(self) -> float:
        """Axial position of the rim centre, m."""
        return 0.5 * sum(self.rim_y)

    @property
    def hub_y(self) -> tuple[float, float]:
        """Hub (and wheel seat) axial extent, m."""
        c = self.rim_centre + self.hub_offset
        return c - 0.5 * self.hub_width, c + 0.5 * self.hub_width

    def web_segments(self) -> list[tuple[float, float, float, float]]:
        """Web staircase: (r0, r1, y0, y1) of each straight segment, m."""
        c = self.rim_centre + self.web_offset
        rs = np.linspace(self.hub_radius, self.rim_inner_radius, self.web_steps + 1)
        out = []
        for i in range(self.web_steps):
            f = (i + 0.5) / self.web_steps
            t = (1.0 - f) * self.web_thickness_hub + f * self.web_thickness_rim
            out.append((float(rs[i]), float(rs[i + 1]), c - 0.5 * t, c + 0.5 * t))
        return out

    @property
    def web_y(self) -> tuple[float, float]:
        """Web axial extent (widest segment), m."""
        seg = self.web_segments()
        return min(s[2] for s in seg), max(s[3] for s in seg)

    @property
    def journal_y(self) -> tuple[float, float]:
        """Journal axial extent, m."""
        c = 0.5 * self.journal_spacing
        return c - 0.5 * self.journal_length, c + 0.5 * self.journal_length

    @property
    def contact_y(self) -> float:
        """Axial position of the right-hand contact point (taping line), m."""
        return self.rim_y[0] + self.contact_offset

    @property
    def rim_inner_radius(self) -> float:
        """Radius of the rim's inner surface (web-rim junction), m."""
        return self.wheel_radius - self.rim_depth

    def wheel_outline(self) -> np.ndarray:
        """Closed meridian outline (r, y) of the right-hand wheel, m."""
        r0, rr, rh, rs = self.wheel_radius, self.rim_inner_radius, self.hub_radius, self.seat_radius
        (yr0, yr1), (yh0, yh1) = self.rim_y, self.hub_y
        yf1, rf = yr0 + self.flange_width, r0 + self.flange_height
        seg = self.web_segments() if rr > rh else [(rh, rr, *self.web_y)]
        outer = [p for (a, b, _, y1) in seg for p in ((a, y1), (b, y1))]
        inner = [p for (a, b, y0, _) in reversed(seg) for p in ((b, y0), (a, y0))]
        return np.array(
            [
                (rs, yh0),
                (rs, yh1),
                (rh, yh1),
                *outer,
                (rr, yr1),
                (r0, yr1),
                (r0, yf1),
                (rf, yf1),
                (rf, yr0),
                (rr, yr0),
                *inner,
                (rh, yh0),
            ]
        )

    def axle_outline(self) -> np.ndarray:
        """Closed meridian outline (r, y) of the right-hand half axle, m."""
        (yh0, yh1), (yj0, yj1) = self.hub_y, self.journal_y
        return np.array(
            [
                (0.0, 0.0),
                (self.body_radius, 0.0),
                (self.body_radius, yh0),
                (self.seat_radius, yh0),
                (self.seat_radius, yh1),
                (self.collar_radius, yh1),
                (self.collar_radius, yj0),
                (self.journal_radius, yj0),
                (self.journal_radius, yj1),
                (0.0, yj1),
            ]
        )

    def _check_outline(self) -> None:
        check_simple_polygon(self.axle_outline(), "axle")
        check_simple_polygon(self.wheel_outline(), "wheel")
        (yr0, yr1), (yh0, yh1), (yw0, yw1) = self.rim_y, self.hub_y, self.web_y
        if not (yh0 - 1e-12 <= yw0 and yw1 <= yh1 + 1e-12 and yr0 - 1e-12 <= yw0 and yw1 <= yr1 + 1e-12):
            raise InputError(
                "the web must lie axially within both the hub and the rim "
                f"(web {yw0:.4f}..{yw1:.4f} m, hub {yh0:.4f}..{yh1:.4f} m, "
                f"rim {yr0:.4f}..{yr1:.4f} m)"
            )
        if yh0 <= 0.0:
            raise InputError("the two hubs overlap at mid-axle: hub_width/hub_offset too large")
        yj0 = self.journal_y[0]
        if yj0 < yh1:
            raise InputError(
                f"the axle meridian outline intersects itself: the journal starts at "
                f"y = {yj0:.4f} m, inside the wheel seat (ends at {yh1:.4f} m); "
                "increase journal_spacing"
            )
        if not self.contact_offset < self.rim_width:
            raise InputError("contact_offset must lie within the rim width")
        if self.flange_width >= self.rim_width:
            raise InputError("flange_width must be smaller than rim_width")

    def blocks(self) -> list[Block]:
        """The meridian section (both halves) as blocks for the mesher."""
        h, ha = self.mesh_size, self.axle_mesh_size
        (yr0, yr1), (yh0, yh1), (yj0, yj1) = self.rim_y, self.hub_y, self.journal_y
        half = [
            Block(0.0, self.body_radius, 0.0, yh0, ha),
            Block(0.0, self.seat_radius, yh0, yh1, ha),
            Block(0.0, self.collar_radius, yh1, yj0, ha),
            Block(0.0, self.journal_radius, yj0, yj1, ha),
            Block(self.seat_radius, self.hub_radius, yh0, yh1, h),
            *[Block(a, b, y0, y1, h) for (a, b, y0, y1) in self.web_segments()],
            Block(self.rim_inner_radius, self.wheel_radius, yr0, yr1, h),
            Block(self.wheel_radius, self.wheel_radius + self.flange_height, yr0, yr0 + self.flange_width, h),
        ]
        out = []
        for b in half:
            out.append(b)
            out.append(Block(b.r0, b.r1, -b.y1, -b.y0, b.size))
        return out

    def mesh(self) -> MeridianMesh:
        """Structured nine-node mesh of the whole meridian section."""
        yc = self.contact_y
        yj = 0.5 * self.journal_spacing
        return mesh_blocks(self.blocks(), extra_y=(yc, -yc, yj, -yj))

    def as_dict(self) -> dict[str, float]:
        """All parameters as a plain dict."""
        return asdict(self)


__all__ = ["WheelsetGeometry"]
