"""The wheel-rail contact models of the time simulation: one spec per model, parsed once.

A contact model is named by users as a string ('hertz-kalker', 'hertz-fastsim', 'bem': the
``contact`` argument of :func:`railvti.vehicle.simulate` and of the scenarios, the deck key
``contact``) and by the Fortran core as an integer (``wheelset_contact``'s ``model``).
:func:`parse_contact_model` turns the one into a :class:`ContactModel`, which carries the
other and everything the Python side asks of a model (needs a BEM state, its default Newton
tolerance, the contact geometries it reads). Every check of a contact model and every
conversion to the Fortran id goes through it.

The same model on both sides of the f2py boundary (``fortran/vehicle/vehicle_contact.f90``):

=================  ======================  ==  ===================================================
name               Fortran constant        id  model
=================  ======================  ==  ===================================================
'hertz-kalker'     CMODEL_HERTZ_KALKER     1   Hertz + Kalker's linear theory, Shen-Hedrick-Elkins
'hertz-fastsim'    CMODEL_HERTZ_FASTSIM    2   Hertz + FASTSIM
'bem'              CMODEL_BEM              3   BEM normal + steady rolling (Hertz + Kalker tangent)
=================  ======================  ==  ===================================================

tests/test_contact_models.py reads the Fortran constants and checks this table against them.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError

__all__ = [
    "GEOMETRIES",
    "ContactModel",
    "HERTZ_KALKER",
    "HERTZ_FASTSIM",
    "BEM",
    "CONTACT_MODELS",
    "parse_contact_model",
    "contact_id",
]

#: Contact geometries of the time simulation: the table's Hertz points, or the strip
#: potential (railvti.vehicle.strip).
GEOMETRIES = ("table", "strip")


@dataclass(frozen=True)
class ContactModel:
    """One wheel-rail contact model of the time simulation.

    Attributes
    ----------
    name : str
        The name users write ('hertz-kalker', ...): the ``contact`` argument and deck key.
    fortran_name : str
        Its constant in ``fortran/vehicle/vehicle_contact.f90`` (``CMODEL_*``).
    fortran_id : int
        That constant's value: the ``model`` the shims take (:class:`CallSettings` ``contact``).
    needs_bem : bool
        The model solves the BEM contact: a run needs a BEM state
        (:class:`railvti.vehicle.bem.BemState`, one per run).
    newton_tol : float
        Default Newton tolerance on the correction of :func:`railvti.vehicle.simulate`, m or
        rad.
    geometries : tuple of str
        The contact geometries (:data:`GEOMETRIES`) the model reads.
    default_geometry : str
        The geometry of a run that names none.
    static_restart : bool
        The static equilibrium restarts from Hertz + Kalker's when this model's Newton
        stalls (discretised creep forces: FASTSIM and the BEM).
    description : str
        One line for labels and error messages.
    """

    name: str
    fortran_name: str
    fortran_id: int
    needs_bem: bool
    newton_tol: float
    geometries: tuple[str, ...]
    default_geometry: str
    static_restart: bool
    description: str

    def resolve_geometry(self, geometry: str | None) -> str:
        """The contact geometry of a run: ``geometry`` checked against the model, or the
        model's default when None.

        Raises
        ------
        InputError
            An unknown geometry, or one the model does not read.
        """
        g = self.default_geometry if geometry is None else geometry
        if g not in GEOMETRIES:
            raise InputError(f"unknown contact geometry {g!r}: one of {GEOMETRIES}")
        if g not in self.geometries:
            readers = " and ".join(repr(m.name) for m in CONTACT_MODELS.values() if g in m.geometries)
            raise InputError(
                f"geometry={g!r} is the geometry of {readers}; the "
                f"{self.description} reads the {self.default_geometry}'s gap fields"
            )
        return g


#: Hertz + Kalker's linear theory with the Shen-Hedrick-Elkins saturation.
HERTZ_KALKER = ContactModel(
    name="hertz-kalker",
    fortran_name="CMODEL_HERTZ_KALKER",
    fortran_id=1,
    needs_bem=False,
    newton_tol=1e-9,
    geometries=("table", "strip"),
    default_geometry="strip",
    static_restart=False,
    description="Hertz + Kalker contact",
)
#: Hertz + FASTSIM.
HERTZ_FASTSIM = ContactModel(
    name="hertz-fastsim",
    fortran_name="CMODEL_HERTZ_FASTSIM",
    fortran_id=2,
    needs_bem=False,
    newton_tol=1e-9,
    geometries=("table", "strip"),
    default_geometry="strip",
    static_restart=True,
    description="Hertz + FASTSIM contact",
)
#: The BEM normal + steady-rolling solvers on the table's gap fields (railvti.vehicle.bem),
#: with the Hertz + Kalker tangent in Newton: a calibrated cheap tangent, hence the looser
#: default tolerance (hunting at 300 km/h, 0.1 s: the leading wheelset moves by 2e-8 m and
#: the BEM solves per step drop by 19 %).
BEM = ContactModel(
    name="bem",
    fortran_name="CMODEL_BEM",
    fortran_id=3,
    needs_bem=True,
    newton_tol=1e-8,
    geometries=("table",),
    default_geometry="table",
    static_restart=True,
    description="BEM contact",
)

#: The contact models by name (the strings users write), in the Fortran ids' order.
CONTACT_MODELS: dict[str, ContactModel] = {m.name: m for m in (HERTZ_KALKER, HERTZ_FASTSIM, BEM)}


def parse_contact_model(contact: str | ContactModel) -> ContactModel:
    """The spec of a contact model named as users write it (a spec is returned as it is).

    Raises
    ------
    InputError
        An unknown name, naming the allowed ones.
    """
    if isinstance(contact, ContactModel):
        return contact
    spec = CONTACT_MODELS.get(contact) if isinstance(contact, str) else None
    if spec is None:
        raise InputError(f"unknown contact model {contact!r}; one of {sorted(CONTACT_MODELS)}")
    return spec


def contact_id(contact: str | ContactModel) -> int:
    """The Fortran id (``CMODEL_*``) of a contact model,
    ``parse_contact_model(contact).fortran_id``."""
    return parse_contact_model(contact).fortran_id
