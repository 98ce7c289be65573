"""The contact model and the variant chosen per scene: ``contact='auto'`` and ``variant='auto'``
(the issue's ``model='auto'``; issue 34, item 5).

The cheapest contact model (and its geometry and BEM grid) whose **measured** error on that
kind of scene stays within the user's tolerance on the quantities asked for. The errors are
those of the speed-against-accuracy studies, each against the BEM at 0.5 mm on its scene
(the reference of the study; its own discretisation error is not in the table): the tables
below, with the script that measured them. Cost: the CPU real-time factor (RTF) of the same
study, one thread.

Scenes:

* ``hunting-tread``: hunting with tread contact only (RR, 300 and 350 km/h; the worse of the
  two), ``validation/vehicle_bem_speed_accuracy.py``, docs/speed_accuracy.md;
* ``hunting-flange``: hunting into flange contact (RR, 400 km/h), same script;
* ``centred-ring``: centred running on the ring track (FF, 300 km/h), same script;
* ``curve``: steady curving (RR, R 1200 m, 150 mm cant, 160 km/h),
  ``validation/vehicle_curving_models.py``, docs/vehicle_curving.md.

A scene's kind is decided by the scenario: hunting runs a cheap pre-run (Hertz + Kalker on
the table) and is ``hunting-flange`` if that reaches flange contact (:func:`flange_scene`).

The variants (:func:`choose_variant`, ``variant='auto'`` of the scenarios) are chosen the same
way from :data:`VARIANT_SCENES`' tables, each against the richest variant measured on it: FF
for centred running (the sleeper passing's dynamic Q, which the rigid track elements lack)
and for the critical speed (the four-variant study's strip folds), RF for steady curving.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType

from .. import _checks
from ..errors import InputError
from .bem import BemOptions

__all__ = [
    "FLANGE_SHARE",
    "SCENES",
    "ModelChoice",
    "auto_contact",
    "choose_contact",
    "flange_scene",
    "measured",
]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ModelChoice:
    """One candidate (or the chosen) contact model of a scene.

    Attributes
    ----------
    label : str
        Model, geometry and grid, e.g. 'bem 1.0 mm' or 'hertz-fastsim (strip)'.
    contact : str
        The ``contact`` argument ('hertz-kalker', 'hertz-fastsim', 'bem').
    geometry : str
        'table' or 'strip'.
    bem_dx : float or None
        The BEM's element size, m.
    rtf : float
        Measured CPU real-time factor on the scene, one thread.
    errors : Mapping[str, float]
        Measured relative error against the 0.5 mm BEM per quantity, 1 (0.05 is 5 %).
    scene : str
    source : str
        The script and page that measured it.
    """

    label: str
    contact: str
    geometry: str
    bem_dx: float | None
    rtf: float
    errors: MappingProxyType
    scene: str = ""
    source: str = ""
    quantities: tuple[str, ...] = field(default=())

    def line(self) -> str:
        """One line: the model, its cost and its expected errors on the quantities asked."""
        errs = ", ".join(f"{q} {100 * self.errors[q]:.2f} %" for q in (self.quantities or tuple(self.errors)))
        return (
            f"contact 'auto' on scene '{self.scene}': {self.label} (RTF {self.rtf:g}; expected error "
            f"against the 0.5 mm BEM: {errs}; measured by {self.source})"
        )


_SPEED_ACC = "validation/vehicle_bem_speed_accuracy.py (docs/speed_accuracy.md)"
_CURVE = "validation/vehicle_curving_models.py (docs/vehicle_curving.md)"

#: label -> (contact, geometry, BEM dx in m)
_MODELS = {
    "hertz-kalker (table)": ("hertz-kalker", "table", None),
    "hertz-fastsim (table)": ("hertz-fastsim", "table", None),
    "hertz-kalker (strip)": ("hertz-kalker", "strip", None),
    "hertz-fastsim (strip)": ("hertz-fastsim", "strip", None),
    "bem 1.5 mm": ("bem", "strip", 1.5e-3),
    "bem 1.0 mm": ("bem", "strip", 1.0e-3),
    "bem 0.75 mm": ("bem", "strip", 0.75e-3),
}

#: scene -> (source, {label: (RTF, {quantity: relative error})}): the measured tables.
_TABLES: dict[str, tuple[str, dict[str, tuple[float, dict[str, float]]]]] = {
    # docs/speed_accuracy.md, hunting at 300 and 350 km/h: the worse of the two per entry
    "hunting-tread": (
        _SPEED_ACC,
        {
            "hertz-kalker (table)": (0.08, {"amplitude": 4.45, "q_max": 0.181, "y_max": 0.034}),
            "hertz-fastsim (table)": (0.16, {"amplitude": 4.42, "q_max": 0.211, "y_max": 0.034}),
            "hertz-fastsim (strip)": (0.51, {"amplitude": 2.25, "q_max": 0.0038, "y_max": 0.032}),
            "bem 1.5 mm": (2.3, {"amplitude": 0.248, "q_max": 0.0003, "y_max": 0.010}),
            "bem 1.0 mm": (7.7, {"amplitude": 0.065, "q_max": 0.0004, "y_max": 0.013}),
            "bem 0.75 mm": (13.3, {"amplitude": 0.025, "q_max": 0.0003, "y_max": 0.0069}),
        },
    ),
    "hunting-flange": (
        _SPEED_ACC,
        {
            "hertz-kalker (table)": (0.11, {"amplitude": 0.0064, "q_max": 1.10, "y_max": 0.299}),
            "hertz-fastsim (table)": (0.26, {"amplitude": 0.013, "q_max": 1.07, "y_max": 0.387}),
            "hertz-fastsim (strip)": (0.70, {"amplitude": 0.015, "q_max": 0.382, "y_max": 0.058}),
            "bem 1.5 mm": (19.3, {"amplitude": 0.0073, "q_max": 0.0079, "y_max": 0.048}),
            "bem 1.0 mm": (25.6, {"amplitude": 0.0082, "q_max": 0.041, "y_max": 0.041}),
            "bem 0.75 mm": (65.2, {"amplitude": 0.0011, "q_max": 0.023, "y_max": 0.033}),
        },
    ),
    "centred-ring": (
        _SPEED_ACC,
        {
            "hertz-kalker (table)": (12.5, {"dynamic_q": 0.015, "q_max": 0.0005, "y_max": 0.093}),
            "hertz-fastsim (table)": (12.7, {"dynamic_q": 0.017, "q_max": 0.0005, "y_max": 0.025}),
            "hertz-fastsim (strip)": (13.3, {"dynamic_q": 0.0015, "q_max": 0.0, "y_max": 0.061}),
            "bem 1.5 mm": (26.0, {"dynamic_q": 0.0003, "q_max": 0.0001, "y_max": 0.080}),
            "bem 1.0 mm": (38.6, {"dynamic_q": 0.0024, "q_max": 0.0, "y_max": 0.182}),
            "bem 0.75 mm": (54.4, {"dynamic_q": 0.0012, "q_max": 0.0, "y_max": 0.021}),
        },
    ),
    # validation/vehicle_curving_models.py (load 5.6): sum Y per wheelset and angle of attack
    # relative to their largest reference value, Q per wheel, T gamma of the outer leading wheel
    "curve": (
        _CURVE,
        {
            "hertz-kalker (table)": (
                0.10,
                {"sum_y": 0.0088, "q": 0.0011, "angle_of_attack": 0.0077, "t_gamma": 0.055},
            ),
            "hertz-fastsim (table)": (
                0.19,
                {"sum_y": 0.0024, "q": 0.0010, "angle_of_attack": 0.042, "t_gamma": 0.029},
            ),
            "hertz-kalker (strip)": (
                0.16,
                {"sum_y": 0.0001, "q": 0.0013, "angle_of_attack": 0.082, "t_gamma": 0.067},
            ),
            "hertz-fastsim (strip)": (
                0.16,
                {"sum_y": 0.0030, "q": 0.0006, "angle_of_attack": 0.021, "t_gamma": 0.025},
            ),
            "bem 1.5 mm": (0.91, {"sum_y": 0.0049, "q": 0.0007, "angle_of_attack": 0.032, "t_gamma": 0.003}),
            "bem 1.0 mm": (2.44, {"sum_y": 0.0017, "q": 0.0003, "angle_of_attack": 0.012, "t_gamma": 0.002}),
            "bem 0.75 mm": (
                3.53,
                {"sum_y": 0.0005, "q": 0.0001, "angle_of_attack": 0.0085, "t_gamma": 0.002},
            ),
        },
    ),
}

#: The scenes with a measured table.
SCENES = tuple(_TABLES)


def measured(scene: str) -> list[ModelChoice]:
    """The measured candidates of a scene, cheapest first."""
    if scene not in _TABLES:
        raise InputError(f"scene {scene!r}: no measured model table; the scenes are {SCENES}")
    source, table = _TABLES[scene]
    out = []
    for label, (rtf, errs) in table.items():
        contact, geometry, dx = _MODELS[label]
        out.append(
            ModelChoice(label, contact, geometry, dx, rtf, MappingProxyType(dict(errs)), scene, source)
        )
    return sorted(out, key=lambda m: m.rtf)


def choose_contact(scene: str, tolerance: float, quantities: Sequence[str] | None = None) -> ModelChoice:
    """The cheapest measured model of ``scene`` whose error on every quantity asked is at most
    ``tolerance``.

    Parameters
    ----------
    scene : str
        One of :data:`SCENES`.
    tolerance : float
        Largest relative error accepted against the 0.5 mm BEM, 1 (0.05: 5 %).
    quantities : sequence of str, optional
        The quantities that matter (the scene's measured ones: see :func:`measured`); None:
        all of them.

    Returns
    -------
    ModelChoice
        With ``quantities`` set to those asked; its :meth:`~ModelChoice.line` says what was
        chosen and the error to expect (also logged).

    Raises
    ------
    InputError
        Unknown scene or quantity, or no measured model within the tolerance (the message
        gives the smallest error measured per quantity).
    """
    cands = measured(scene)
    chosen = _cheapest(cands, scene, tolerance, quantities, "contact model")
    log.info(chosen.line())
    return chosen


def _cheapest(cands: list, scene: str, tolerance: float, quantities: Sequence[str] | None, what: str):
    """The first of ``cands`` (cheapest first; ModelChoice or VariantChoice) whose errors on
    ``quantities`` (None: all measured) are within ``tolerance``, with them set; InputError
    for an unknown quantity or when none is within (naming the smallest errors)."""
    tol = _checks.positive("tolerance", tolerance)
    known = tuple(cands[0].errors)
    qs = tuple(known if quantities is None else quantities)
    bad = [q for q in qs if q not in known]
    if bad or not qs:
        raise InputError(f"quantities {bad or list(qs)}: scene {scene!r} has measured errors of {known}")
    for c in cands:
        if all(c.errors[q] <= tol for q in qs):
            return replace(c, quantities=qs)
    best = {q: min(c.errors[q] for c in cands) for q in qs}
    raise InputError(
        f"tolerance {tol:g}: no measured {what} on scene {scene!r} is within it on {list(qs)}; "
        "the smallest errors measured are "
        + ", ".join(f"{q} {100 * e:.2f} %" for q, e in best.items())
        + (
            " (the 0.5 mm BEM is the study's reference: give contact='bem' with its grid yourself)"
            if what == "contact model"
            else ""
        )
    )


#: A pre-run's flange normal force above this share of the static wheel load makes a hunting
#: scene 'hunting-flange' (a flange-root touch of a few per cent does not).
FLANGE_SHARE = 0.1


def flange_scene(flange_normal_max: float, wheel_load: float) -> str:
    """The hunting scene of a pre-run whose largest flange normal force was
    ``flange_normal_max`` (N) for a static wheel load ``wheel_load`` (N)."""
    return "hunting-flange" if flange_normal_max > FLANGE_SHARE * wheel_load else "hunting-tread"


def auto_contact(kw: dict, scene: str) -> tuple[str, ModelChoice]:
    """``contact='auto'`` of a scenario: the choice for ``scene`` from the scenario's keywords
    ``tolerance`` (default 0.05) and ``quantities`` (default: all measured), both popped from
    ``kw``, which gets the chosen ``geometry`` and, for a BEM, ``bem_options`` with its grid.
    InputError when ``kw`` already fixes the geometry or the BEM's options (the choice owns
    them)."""
    tol = kw.pop("tolerance", 0.05)
    qs = kw.pop("quantities", None)
    fixed = [k for k in ("geometry", "bem_options", "bem") if kw.get(k) is not None]
    if fixed:
        raise InputError(f"contact='auto' chooses the contact model, its geometry and grid: drop {fixed}")
    choice = choose_contact(scene, tol, qs)
    kw["geometry"] = choice.geometry
    if choice.bem_dx is not None:
        kw["bem_options"] = BemOptions(dx=choice.bem_dx)
    return choice.contact, choice


@dataclass(frozen=True)
class VariantChoice:
    """One candidate (or the chosen) variant of a scene (``model='auto'``).

    Attributes
    ----------
    variant : str
        'RR', 'FR', 'RF' or 'FF'.
    rtf : float
        Measured CPU real-time factor on the scene (Hertz + FASTSIM, one thread).
    errors : Mapping[str, float]
        Measured relative error against the scene's richest variant per quantity, 1.
    scene, source : str
    quantities : tuple of str
        The quantities asked for (set on the chosen one).
    """

    variant: str
    rtf: float
    errors: MappingProxyType
    scene: str = ""
    source: str = ""
    quantities: tuple[str, ...] = field(default=())

    def line(self) -> str:
        """One line: the variant, its cost and its expected errors on the quantities asked."""
        errs = ", ".join(f"{q} {100 * self.errors[q]:.2f} %" for q in (self.quantities or tuple(self.errors)))
        return (
            f"model 'auto' on scene '{self.scene}': variant {self.variant} (RTF {self.rtf:g}; expected error "
            f"against the richest variant: {errs}; measured by {self.source})"
        )


_VARIANTS_SRC = "validation/vehicle_variant_choice.py (docs/speed_accuracy.md)"
#: scene -> (source, {variant: (RTF, {quantity: relative error against the reference})}).
_VARIANT_TABLES: dict[str, tuple[str, dict[str, tuple[float, dict[str, float]]]]] = {
    # centred running at 300 km/h, 0.2 s, against FF: the sleeper passing's dynamic Q
    "centred": (
        _VARIANTS_SRC,
        {
            "RR": (0.15, {"dynamic_q": 1.0, "q_max": 0.0407}),
            "FR": (0.73, {"dynamic_q": 1.0, "q_max": 0.0407}),
            "RF": (4.54, {"dynamic_q": 0.002, "q_max": 0.0028}),
            "FF": (5.20, {"dynamic_q": 0.0, "q_max": 0.0}),
        },
    ),
    # the strip folds of the four-variant study against FF's 280.0 km/h (README); the cost of
    # hunting at 300 km/h (benchmarks/bench_vehicle_variants.py, CPU over simulated time)
    "critical-speed": (
        "validation/vehicle_four_study.py (README, docs/vehicle_scenarios.md)",
        {
            "RR": (0.34, {"critical_speed": 0.0446}),
            "FR": (0.80, {"critical_speed": 0.0089}),
            "RF": (2.30, {"critical_speed": 0.0446}),
            "FF": (2.50, {"critical_speed": 0.0}),
        },
    ),
    # steady curving R 1200 m, 160 km/h against RF (FR and FF do not run curves yet):
    # validation/vehicle_curving.py's steady tables
    "curve": (
        "validation/vehicle_curving.py (docs/vehicle_curving.md)",
        {
            "RR": (0.29, {"sum_y": 0.0046, "angle_of_attack": 0.011}),
            "RF": (3.7, {"sum_y": 0.0, "angle_of_attack": 0.0}),
        },
    ),
}

#: The scenes with a measured variant table.
VARIANT_SCENES = tuple(_VARIANT_TABLES)


def choose_variant(scene: str, tolerance: float, quantities: Sequence[str] | None = None) -> VariantChoice:
    """The cheapest measured variant of ``scene`` whose error on every quantity asked is at
    most ``tolerance`` (against the scene's richest variant; see :func:`choose_contact`).

    Raises
    ------
    InputError
        Unknown scene or quantity, or no variant within the tolerance.
    """
    if scene not in _VARIANT_TABLES:
        raise InputError(f"scene {scene!r}: no measured variant table; the scenes are {VARIANT_SCENES}")
    source, table = _VARIANT_TABLES[scene]
    cands = sorted(
        (VariantChoice(v, rtf, MappingProxyType(dict(e)), scene, source) for v, (rtf, e) in table.items()),
        key=lambda c: c.rtf,
    )
    chosen = _cheapest(cands, scene, tolerance, quantities, "variant")
    log.info(chosen.line())
    return chosen


def auto_variant(kw: dict, scene: str) -> tuple[str, VariantChoice]:
    """``model='auto'`` (variant 'auto') of a scenario: the variant for ``scene`` from the
    keywords ``variant_tolerance`` (default 0.05) and ``variant_quantities`` (default: all
    measured), both popped from ``kw``."""
    choice = choose_variant(scene, kw.pop("variant_tolerance", 0.05), kw.pop("variant_quantities", None))
    return choice.variant, choice
