"""Vehicle-track time simulation: a passenger coach with rigid wheelsets on rigid track
elements (variant RR), online wheel-rail contact from precomputed tables, Newmark/HHT
integration with Newton iterations in Fortran.

Track frame x forward, y left, z up (see :mod:`railvti.geometry`).
"""

from __future__ import annotations

from .bem import BemGrid, BemOptions, BemPatch, BemState
from .assembly import DOF_NAMES, System, build_coach, build_single_wheelset
from .model import VehicleModel
from .params import DEFAULTS, Coach
from ..errors import DivergenceError
from .contact_models import CONTACT_MODELS, ContactModel, parse_contact_model
from .equilibrium import (
    bem_state,
    contact_state,
    eigenvalues,
    force_and_tangent,
    lateral_disturbance,
    static_equilibrium,
)
from .model import WHEEL_OUTPUTS
from .run_result import SimulationResult, WheelSummary
from .simulate import simulate
from .table import WheelTable, linearised_table, wheel_table

__all__ = [
    "Coach",
    "DEFAULTS",
    "DOF_NAMES",
    "System",
    "build_coach",
    "build_single_wheelset",
    "CONTACT_MODELS",
    "ContactModel",
    "parse_contact_model",
    "WHEEL_OUTPUTS",
    "DivergenceError",
    "SimulationResult",
    "WheelSummary",
    "contact_state",
    "eigenvalues",
    "force_and_tangent",
    "lateral_disturbance",
    "simulate",
    "static_equilibrium",
    "WheelTable",
    "linearised_table",
    "wheel_table",
    "BemGrid",
    "BemOptions",
    "BemPatch",
    "BemState",
    "bem_state",
    "VehicleModel",
]
