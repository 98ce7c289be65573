"""The coach's wheelset as one body for every model (issue 30, item 1).

RR's rigid wheelset and the rigid-body part of FR's flexible wheelset are the same body: the
FE wheelset's rigid part (:class:`railvti.wheelset.Wheelset`, its meridian section integrated
exactly by :func:`railvti.wheelset.analytic.wheelset_mass_properties`) plus the lumped parts
that make it the coach's wheelset (:func:`coach_wheelset`):

* two axle-mounted brake discs (rotating: they add to the spin inertia and so to the
  gyroscopic moments);
* two axleboxes at the journal centres (not rotating: mass and roll/yaw inertia only), whose
  mass is the remainder that keeps the Manchester Benchmark's confirmed wheelset mass of
  1813 kg (railvti.vehicle.params): the housing, the bearings and the unsprung share of the
  primary suspension.

The parts ride on the rigid-body motion only: in variant FR they do not load the elastic modes
(the FE mesh is the bare wheelset; docs/vehicle.md, "One wheelset body").
:data:`railvti.vehicle.params.DEFAULTS` quotes the resulting ``wheelset_mass``,
``wheelset_roll_inertia``, ``wheelset_yaw_inertia`` and ``wheelset_pitch_inertia`` (the spin
inertia); tests/test_wheelset_body.py checks them against :func:`coach_wheelset`.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..wheelset.analytic import wheelset_mass_properties
from ..wheelset.geometry import WheelsetGeometry

#: The benchmark's wheelset mass, kg (Iwnicki 1998, confirmed; railvti.vehicle.params).
BENCHMARK_MASS = 1813.0


@dataclass(frozen=True)
class LumpedPart:
    """A rigid part attached to the wheelset, symmetric about its own axis (the axle, y).

    Attributes
    ----------
    name : str
    mass : float
        kg.
    y : float
        Lateral position of its centre of mass on the axle, m (+ left).
    radius_out, radius_in, length : float
        The annulus (outer, inner radius, axial length, m) whose uniform mass gives its
        inertias.
    rotating : bool
        Spins with the axle (brake disc) or not (axlebox): only rotating parts add spin inertia.
    source : str
    """

    name: str
    mass: float
    y: float
    radius_out: float
    radius_in: float
    length: float
    rotating: bool
    source: str

    @property
    def spin_inertia(self) -> float:
        """About the axle, kg m^2 (0 for a part that does not rotate): m (r_o^2 + r_i^2) / 2."""
        if not self.rotating:
            return 0.0
        return self.mass * (self.radius_out**2 + self.radius_in**2) / 2.0

    @property
    def diametral_inertia(self) -> float:
        """About a diameter through the wheelset centre, kg m^2 (parallel axes):
        m ((r_o^2 + r_i^2) / 4 + L^2 / 12 + y^2)."""
        return self.mass * (
            (self.radius_out**2 + self.radius_in**2) / 4.0 + self.length**2 / 12.0 + self.y**2
        )


_DISC = (
    "assumption: a typical 640 mm ventilated axle-mounted brake disc of a passenger "
    "coach with its hub, 120 kg, at +-0.40 m"
)
_AXLEBOX = (
    "remainder to the benchmark's 1813 kg (Iwnicki 1998 [confirmed]) over two "
    "axleboxes at the journal centres (+-1.0 m, railvti.wheelset.WheelsetGeometry); "
    "inertia of a 0.15 m radius cylinder of the journal's length"
)


def _parts(bare_mass: float, geometry: WheelsetGeometry) -> tuple[LumpedPart, ...]:
    discs = tuple(
        LumpedPart(f"brake disc {s}", 120.0, y, 0.32, 0.12, 0.11, True, _DISC)
        for s, y in (("left", 0.40), ("right", -0.40))
    )
    m_box = 0.5 * (BENCHMARK_MASS - bare_mass - sum(d.mass for d in discs))
    yj = 0.5 * geometry.journal_spacing
    boxes = tuple(
        LumpedPart(f"axlebox {s}", m_box, y, 0.15, 0.0, geometry.journal_length, False, _AXLEBOX)
        for s, y in (("left", yj), ("right", -yj))
    )
    return discs + boxes


@dataclass(frozen=True)
class WheelsetBody:
    """The coach's wheelset: the bare FE wheelset's rigid part plus its lumped parts.

    Attributes
    ----------
    mass : float
        kg.
    roll_inertia, yaw_inertia : float
        About the longitudinal and vertical axes through the wheelset centre, kg m^2.
    spin_inertia : float
        About the axle, of the rotating parts (the gyroscopic moments' I_y), kg m^2.
    bare : dict
        The bare FE wheelset's properties (:func:`wheelset_mass_properties`).
    parts : tuple of LumpedPart
    """

    mass: float
    roll_inertia: float
    yaw_inertia: float
    spin_inertia: float
    bare: dict
    parts: tuple

    def coach_params(self) -> dict[str, float]:
        """The four :class:`~railvti.vehicle.params.Coach` keys of this body."""
        return {
            "wheelset_mass": self.mass,
            "wheelset_roll_inertia": self.roll_inertia,
            "wheelset_yaw_inertia": self.yaw_inertia,
            "wheelset_pitch_inertia": self.spin_inertia,
        }


def coach_wheelset(geometry: WheelsetGeometry | None = None) -> WheelsetBody:
    """The coach's wheelset body (:class:`WheelsetBody`) on a wheelset geometry.

    Parameters
    ----------
    geometry : WheelsetGeometry, optional
        The FE wheelset's geometry and material (default: ``WheelsetGeometry()``, the
        wheelset of variants FR and FF).

    Returns
    -------
    WheelsetBody
        Mass and inertias: the bare wheelset plus its parts (two brake discs, two axleboxes
        making up the benchmark's 1813 kg).
    """
    g = geometry if geometry is not None else WheelsetGeometry()
    bare = wheelset_mass_properties(g)
    parts = _parts(bare["mass"], g)
    roll = bare["roll_inertia"] + sum(p.diametral_inertia for p in parts)
    return WheelsetBody(
        mass=bare["mass"] + sum(p.mass for p in parts),
        roll_inertia=roll,
        yaw_inertia=roll,
        spin_inertia=bare["spin_inertia"] + sum(p.spin_inertia for p in parts),
        bare=bare,
        parts=parts,
    )


__all__ = ["BENCHMARK_MASS", "LumpedPart", "WheelsetBody", "coach_wheelset"]
