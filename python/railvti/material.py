"""Elastic material of a body in contact (shared by both bodies when they are quasi-identical;
:class:`railvti.contact.dissimilar.BodyPair` pairs two different ones)."""

from __future__ import annotations

from dataclasses import dataclass

from . import _checks
from .errors import InputError


@dataclass(frozen=True)
class Material:
    """Linear elastic material, shared by wheel and rail (quasi-identical bodies) or one
    body's (a :class:`~railvti.contact.dissimilar.BodyPair` of two).

    Parameters
    ----------
    shear_modulus : float
        Shear modulus G, Pa (> 0).
    poisson : float
        Poisson's ratio nu, in (-1, 0.5) (the range of a stable isotropic solid; issue 35).
    """

    shear_modulus: float
    poisson: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "shear_modulus", _checks.positive("shear_modulus", self.shear_modulus))
        nu = _checks.finite("poisson", self.poisson)
        if not -1.0 < nu < 0.5:
            raise InputError(f"poisson must lie in (-1, 0.5), got {nu}")
        object.__setattr__(self, "poisson", nu)

    @property
    def young_modulus(self) -> float:
        """Young's modulus E = 2 G (1 + nu), Pa."""
        return 2.0 * self.shear_modulus * (1.0 + self.poisson)

    @property
    def contact_modulus(self) -> float:
        """Hertz's combined modulus E* of two such bodies, 1/E* = 2 (1 - nu^2)/E, Pa."""
        return self.shear_modulus / (1.0 - self.poisson)


#: Wheel and rail steel as in the Manchester Contact Benchmark (G = 82 GPa, nu = 0.28).
STEEL = Material(shear_modulus=82.0e9, poisson=0.28)

__all__ = ["Material", "STEEL"]
