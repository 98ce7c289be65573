"""Deck case type ``geometry_table``: the rigid geometry table of a wheel/rail pair."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .. import _checks
from .. import profiles as P
from ..casetypes import Alias, CaseOutput, CaseType, Key, register, validate
from ..errors import InputError
from ..wheelset.geometry import WheelsetGeometry
from .conicity import equivalent_conicity, klingel_wavelength
from .placement import TrackLayout
from .plots import plot_table
from .table import FLANGE_CLIMB, NO_CONTACT, STATUS_NAMES, TABLE_ARRAYS, GeometryTable, geometry_table

__all__ = [
    "PAIR_DEFAULTS",
    "PAIR_KEYS",
    "mm_aliases",
    "PAIR_MM_ALIASES",
    "profile_problems",
    "sweep_problems",
    "wheelset_problems",
    "check_table",
    "deck_profiles",
    "deck_layout",
    "run",
    "plot",
]


#: Deck keys (and defaults) that name a wheel/rail pair on the track, shared by the case
#: types ``geometry_table`` and ``loaded_wheelset``: see :func:`deck_profiles` and
#: :func:`deck_layout`. The layout defaults are those of TrackLayout and WheelsetGeometry (m).
PAIR_DEFAULTS: dict[str, Any] = {
    "wheel": "s1002",
    "rail": "uic60",
    "cant": 0.025,
    "gauge": TrackLayout.gauge,
    "gauge_depth": TrackLayout.gauge_depth,
    "back_to_back": WheelsetGeometry.back_to_back,
    "radius": WheelsetGeometry.wheel_radius,
}


_WHY_SHIFT = "beyond 50 mm the flange has left the rail"
#: Units, meanings and bounds of the keys shared by the wheel/rail pair case types.
PAIR_KEYS: dict[str, Key] = {
    "wheel": Key(
        "", "wheel profile: 's1002' or a profile file (SIMPACK .prw, or two columns y z in mm)", "str"
    ),
    "rail": Key(
        "", "rail profile: 'uic60' (inclined by cant) or a profile file, taken as already canted", "str"
    ),
    "cant": Key("1", "rail inclination, tan (for 'uic60'; 1:40 = 0.025)", lo=-0.2, hi=0.2),
    "gauge": Key("m", "track gauge", lo=0.9, hi=1.7, why="narrow 1000 mm to Iberian 1668 mm gauge"),
    "gauge_depth": Key(
        "m", "depth below the rail top at which the gauge is measured", lo=0.0, hi=0.03, lo_open=True
    ),
    "back_to_back": Key("m", "wheelset back-to-back distance", lo=0.85, hi=1.65),
    "radius": Key(
        "m", "nominal wheel rolling radius", lo=0.15, hi=0.8, why="railway wheels have radii of 0.2-0.6 m"
    ),
    "y_min": Key("m", "first lateral shift of the wheelset (to the left)", lo=-0.05, hi=0.05, why=_WHY_SHIFT),
    "y_max": Key("m", "last lateral shift of the wheelset", lo=-0.05, hi=0.05, why=_WHY_SHIFT),
    "n": Key("1", "number of shifts from y_min to y_max", "int", 2, 100001),
    "yaw_per_y": Key("rad/m", "yaw angle rising with the shift", lo=-20.0, hi=20.0),
    "amplitude": Key("m", "amplitude for the equivalent conicity", lo=0.0, hi=0.02, lo_open=True),
}


def mm_aliases(*keys: str) -> dict[str, Alias]:
    """The documented mm-suffixed aliases ``<key>_mm`` of SI length keys (m): value x 1e-3."""
    return {f"{k}_mm": Alias(k, 1e-3, deprecated=False, unit="mm") for k in keys}


#: The suffixed aliases of the pair keys: the same quantities in mm (and mrad/mm), as
#: profiles and drawings give them; the keys are SI.
PAIR_MM_ALIASES: dict[str, Alias] = {
    **mm_aliases("gauge", "gauge_depth", "back_to_back", "radius", "y_min", "y_max", "amplitude"),
    "yaw_mrad_per_mm": Alias("yaw_per_y", 1.0, deprecated=False, unit="mrad/mm"),
}


def profile_problems(params: dict[str, Any], keys: tuple[str, str] = ("wheel", "rail")) -> list[str]:
    """Profile keys that name neither a standard profile nor an existing file."""
    std = {"wheel": "s1002", "rail": "uic60"}
    out = []
    for key, kind in zip(keys, ("wheel", "rail")):
        v = params[key]
        if isinstance(v, str) and v.strip().lower() != std[kind] and not Path(v).is_file():
            out.append(f"key '{key}' = {v!r}: neither '{std[kind]}' nor an existing profile file")
    return out


def sweep_problems(params: dict[str, Any]) -> list[str]:
    """The shift range of a sweep: y_min < y_max (or equal with one shift)."""
    lo, hi, n = params["y_min"], params["y_max"], params["n"]
    if lo > hi or (lo == hi and n > 1):
        return [f"y_min = {lo:g} must be < y_max = {hi:g} (m)" + (" or n = 1" if lo == hi else "")]
    return []


def wheelset_problems(params: dict[str, Any], **extra: str) -> list[str]:
    """The deck's wheelset dimensions (back_to_back, radius and the ``extra`` keys: key ->
    WheelsetGeometry field) against the other dimensions of ``WheelsetGeometry()`` they are
    built with: a message naming the case's keys, not the fixed dimensions it cannot set."""
    keys = {"back_to_back": "back_to_back", "radius": "wheel_radius", **extra}
    try:
        WheelsetGeometry(**{f: params[k] for k, f in keys.items()})
    except InputError as exc:
        given = ", ".join(f"{k} = {params[k]:g} m" for k in keys)
        return [
            f"{given} do not fit the default wheelset's other dimensions (WheelsetGeometry(): "
            f"journal_spacing {WheelsetGeometry.journal_spacing:g} m, hub_radius "
            f"{WheelsetGeometry.hub_radius:g} m, rim_depth {WheelsetGeometry.rim_depth:g} m; "
            f"back_to_back up to about 1.55 m, radius from about 0.22 m): "
            f"{str(exc).replace('; increase journal_spacing', '')}"
        ]  # not a key here
    return []


def check_table(params: dict[str, Any]) -> list[str]:
    """Consistency of a 'geometry_table' case."""
    return profile_problems(params) + sweep_problems(params) + wheelset_problems(params)


def deck_profiles(params: dict[str, Any]) -> tuple[P.Profile, P.Profile]:
    """The wheel and rail profiles of a deck case.

    Parameters
    ----------
    params : dict
        Keys ``wheel`` ('s1002' or a profile file), ``rail`` ('uic60' or a profile file,
        taken as already canted) and ``cant`` (tan, for 'uic60').

    Returns
    -------
    wheel, rail : Profile
    """
    wheel = P.load(params["wheel"], "wheel")
    rail = P.load(params["rail"], "rail", cant=_checks.finite("cant", params["cant"]))
    return wheel, rail


def deck_layout(params: dict[str, Any]) -> tuple[TrackLayout, WheelsetGeometry]:
    """The track layout and the wheelset of a deck case.

    Parameters
    ----------
    params : dict
        Keys ``gauge``, ``gauge_depth``, ``back_to_back`` and ``radius`` (the wheel's
        nominal rolling radius), m.

    Returns
    -------
    TrackLayout, WheelsetGeometry
        The wheelset has the other dimensions of ``WheelsetGeometry()``.
    """
    track = TrackLayout(gauge=params["gauge"], gauge_depth=params["gauge_depth"])
    wheelset = WheelsetGeometry(back_to_back=params["back_to_back"], wheel_radius=params["radius"])
    return track, wheelset


def run(params: dict[str, Any]) -> CaseOutput:
    """Geometry table case.

    Keys: wheel ('s1002' or a file), rail ('uic60' or a file; a file is taken as already
    canted), cant (tan, for 'uic60'), y_min, y_max (m), n (positions), yaw_per_y (rad/m, yaw
    rising with the shift), gauge, gauge_depth, back_to_back, radius, amplitude (for the
    equivalent conicity), m. The mm-suffixed aliases (``y_min_mm``...) are converted on reading.
    """
    params = validate("geometry_table", params)
    wheel, rail = deck_profiles(params)
    n = _checks.positive_int("n", params["n"], 2)
    y = np.linspace(_checks.finite("y_min", params["y_min"]), _checks.finite("y_max", params["y_max"]), n)
    yaw = y * _checks.finite("yaw_per_y", params["yaw_per_y"])
    track, ws = deck_layout(params)
    t = geometry_table(wheel, rail, y, yaw, track=track, wheelset=ws)
    status = ", ".join(f"{code} {name}" for code, name in STATUS_NAMES.items())
    units = {
        "y": "m",
        "yaw": "rad",
        "rise": "m",
        "roll": "rad",
        "status": status,
        "n_contact": "1",
        "separation": "m",
        "contact_angle": "rad",
        "rolling_radius": "m",
        "y_wheel": "m",
        "y_rail": "m",
        "x": "m",
        "y_track": "m",
        "z_track": "m",
        "delta_r": "m",
    }
    out = CaseOutput(summary="", datasets={k: (np.asarray(v), units[k]) for k, v in t.as_dict().items()})
    axes = ["y (lateral shift)", "wheel", "candidate point (0 carries the wheel)"]
    for k, (v, _) in out.datasets.items():
        if v.ndim >= 2:
            out.attrs[k] = {"axes": axes[: v.ndim], "wheel": ["left", "right"]}
            if v.ndim == 3:
                out.attrs[k]["empty_slots"] = "NaN: the wheel has fewer candidate points"
        elif v.ndim == 1 and k != "y":
            out.attrs[k] = {"axes": ["y (lateral shift)"]}
    amp = _checks.positive("amplitude", params["amplitude"])
    msg = ""
    if np.all(yaw == 0) and -y.min() >= amp and y.max() >= amp:
        con = equivalent_conicity(t, amp)
        e0 = 0.5 * float(np.nanmedian(t.y_track[:, 0, 0] - t.y_track[::-1, 1, 0]))
        out.scalars["equivalent_conicity"] = (con, "1")
        out.scalars["klingel_wavelength"] = (klingel_wavelength(con, ws.wheel_radius, e0), "m")
        msg = f", tan(gamma_e)({amp * 1e3:g} mm) = {con:.4f}"
    climb = np.any(t.status == FLANGE_CLIMB, axis=1)
    if climb.any():
        out.scalars["flange_climb_from"] = (float(np.min(np.abs(t.y[climb]))), "m")
    nok = int(np.sum(np.any(t.status == NO_CONTACT, axis=1)))
    out.summary = (
        f"geometry table: {n} positions, {nok} without contact, "
        f"{int(climb.sum())} with {STATUS_NAMES[FLANGE_CLIMB]}{msg}"
    )
    return out


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Delta-r, contact angle and roll against y from a stored case."""
    r = group["results"] if "results" in group else group
    t = GeometryTable(
        **{k: np.asarray(r[k]) for k in TABLE_ARRAYS}, wheel_radius=float("nan"), tolerance=float("nan")
    )
    p = Path(outdir) / f"{stem}_contact_table.png"
    inputs = group["inputs"] if "inputs" in group else {}

    def given(key: str) -> str:
        if key not in inputs:
            return "?"
        v = np.asarray(inputs[key]).item()
        return Path(v.decode() if isinstance(v, bytes) else str(v)).name

    name = group.attrs.get("name", "")
    name = name.decode() if isinstance(name, bytes) else str(name)
    title = f"{name}: geometry table, wheel {given('wheel')} on rail {given('rail')}"
    if "cant" in inputs:
        title += f" (cant {float(np.asarray(inputs['cant'])):.4g})"
    return [plot_table(t, p, title=title)]


register(
    CaseType(
        name="geometry_table",
        defaults={
            "wheel": PAIR_DEFAULTS["wheel"],
            "rail": PAIR_DEFAULTS["rail"],
            "cant": PAIR_DEFAULTS["cant"],
            "y_min": -0.01,
            "y_max": 0.01,
            "n": 201,
            "yaw_per_y": 0.0,
            "gauge": PAIR_DEFAULTS["gauge"],
            "gauge_depth": PAIR_DEFAULTS["gauge_depth"],
            "back_to_back": PAIR_DEFAULTS["back_to_back"],
            "radius": PAIR_DEFAULTS["radius"],
            "amplitude": 0.003,
        },
        run=run,
        plot=plot,
        keys=PAIR_KEYS,
        check=check_table,
        aliases=PAIR_MM_ALIASES,
        summary="rigid geometry table of a wheel/rail pair over lateral shifts; equivalent conicity",
    )
)
