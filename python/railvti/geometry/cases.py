"""Deck case type ``geometry_table``: the rigid contact table of a wheel/rail pair."""
from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .. import _checks
from .. import profiles as P
from ..casetypes import Alias, CaseOutput, CaseType, Key, register, validate
from ..wheelset.geometry import WheelsetGeometry
from .conicity import equivalent_conicity, klingel_wavelength
from .placement import TrackLayout
from .table import FLANGE_CLIMB, NO_CONTACT, STATUS_NAMES, TABLE_ARRAYS, ContactTable, contact_table


def _mm(length: float) -> float:
    """A length in m as the deck's mm value."""
    return round(length * 1e3, 9)


#: Deck keys (and defaults) that name a wheel/rail pair on the track, shared by the case
#: types ``geometry_table`` and ``loaded_wheelset``: see :func:`deck_profiles` and
#: :func:`deck_layout`. The layout defaults are those of TrackLayout and WheelsetGeometry.
PAIR_DEFAULTS: dict[str, Any] = {
    "wheel": "s1002", "rail": "uic60", "cant": 0.025,
    "gauge_mm": _mm(TrackLayout.gauge), "gauge_depth_mm": _mm(TrackLayout.gauge_depth),
    "back_to_back_mm": _mm(WheelsetGeometry.back_to_back), "radius_mm": _mm(WheelsetGeometry.wheel_radius),
}


_WHY_SHIFT = "beyond 50 mm the flange has left the rail"
#: Units, meanings and bounds of the keys shared by the wheel/rail pair case types.
PAIR_KEYS: dict[str, Key] = {
    "wheel": Key("", "wheel profile: 's1002' or a profile file (SIMPACK .prw, or two columns y z in mm)", "str"),
    "rail": Key("", "rail profile: 'uic60' (inclined by cant) or a profile file, taken as already canted", "str"),
    "cant": Key("1", "rail inclination, tan (for 'uic60'; 1:40 = 0.025)", lo=-0.2, hi=0.2),
    "gauge_mm": Key("mm", "track gauge", lo=900.0, hi=1700.0, why="narrow 1000 mm to Iberian 1668 mm gauge"),
    "gauge_depth_mm": Key("mm", "depth below the rail top at which the gauge is measured", lo=0.0, hi=30.0,
                          lo_open=True),
    "back_to_back_mm": Key("mm", "wheelset back-to-back distance", lo=850.0, hi=1650.0),
    "radius_mm": Key("mm", "nominal wheel rolling radius", lo=150.0, hi=800.0,
                     why="railway wheels have radii of 0.2-0.6 m"),
    "y_min_mm": Key("mm", "first lateral shift of the wheelset (to the left)", lo=-50.0, hi=50.0, why=_WHY_SHIFT),
    "y_max_mm": Key("mm", "last lateral shift of the wheelset", lo=-50.0, hi=50.0, why=_WHY_SHIFT),
    "n": Key("1", "number of shifts from y_min_mm to y_max_mm", "int", 2, 100001),
    "yaw_mrad_per_mm": Key("mrad/mm", "yaw angle rising with the shift", lo=-20.0, hi=20.0),
    "amplitude_mm": Key("mm", "amplitude for the equivalent conicity", lo=0.0, hi=20.0, lo_open=True),
}


#: SI names of the pair keys in mm (the key keeps the profile's mm; the alias converts).
PAIR_SI_ALIASES: dict[str, Alias] = {
    **{k[:-3]: Alias(k, 1e3, deprecated=False, unit="m")
       for k in ("gauge_mm", "gauge_depth_mm", "back_to_back_mm", "radius_mm", "y_min_mm", "y_max_mm",
                 "amplitude_mm")},
    "yaw_per_y": Alias("yaw_mrad_per_mm", 1.0, deprecated=False, unit="rad/m"),
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
    """The shift range of a sweep: y_min_mm < y_max_mm (or equal with one shift)."""
    lo, hi, n = params["y_min_mm"], params["y_max_mm"], params["n"]
    if lo > hi or (lo == hi and n > 1):
        return [f"y_min_mm = {lo:g} must be < y_max_mm = {hi:g} (mm)" + (" or n = 1" if lo == hi else "")]
    return []


def check_table(params: dict[str, Any]) -> list[str]:
    """Consistency of a 'geometry_table' case."""
    return profile_problems(params) + sweep_problems(params)


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
        Keys ``gauge_mm``, ``gauge_depth_mm``, ``back_to_back_mm`` and ``radius_mm`` (the
        wheel's nominal rolling radius), mm.

    Returns
    -------
    TrackLayout, WheelsetGeometry
        The wheelset has the other dimensions of ``WheelsetGeometry()``.
    """
    track = TrackLayout(gauge=params["gauge_mm"] * 1e-3, gauge_depth=params["gauge_depth_mm"] * 1e-3)
    wheelset = WheelsetGeometry(back_to_back=params["back_to_back_mm"] * 1e-3,
                                wheel_radius=params["radius_mm"] * 1e-3)
    return track, wheelset


def run(params: dict[str, Any]) -> CaseOutput:
    """Contact table case.

    Keys: wheel ('s1002' or a file), rail ('uic60' or a file; a file is taken as already
    canted), cant (tan, for 'uic60'), y_min_mm, y_max_mm, n (positions), yaw_mrad_per_mm
    (yaw rising with the shift), gauge_mm, gauge_depth_mm, back_to_back_mm, radius_mm,
    amplitude_mm (for the equivalent conicity).
    """
    params = validate("geometry_table", params)
    wheel, rail = deck_profiles(params)
    n = _checks.positive_int("n", params["n"], 2)
    y = np.linspace(_checks.finite("y_min_mm", params["y_min_mm"]),
                    _checks.finite("y_max_mm", params["y_max_mm"]), n) * 1e-3
    yaw = y * 1e3 * _checks.finite("yaw_mrad_per_mm", params["yaw_mrad_per_mm"]) * 1e-3
    track, ws = deck_layout(params)
    t = contact_table(wheel, rail, y, yaw, track=track, wheelset=ws)
    status = ", ".join(f"{code} {name}" for code, name in STATUS_NAMES.items())
    units = {"y": "m", "yaw": "rad", "rise": "m", "roll": "rad", "status": status,
             "n_contact": "1", "separation": "m", "contact_angle": "rad", "rolling_radius": "m",
             "y_wheel": "m", "y_rail": "m", "x": "m", "y_track": "m", "z_track": "m", "delta_r": "m"}
    out = CaseOutput(summary="", datasets={k: (np.asarray(v), units[k]) for k, v in t.as_dict().items()})
    axes = ["y (lateral shift)", "wheel", "candidate point (0 carries the wheel)"]
    for k, (v, _) in out.datasets.items():
        if v.ndim >= 2:
            out.attrs[k] = {"axes": axes[:v.ndim], "wheel": ["left", "right"]}
            if v.ndim == 3:
                out.attrs[k]["empty_slots"] = "NaN: the wheel has fewer candidate points"
        elif v.ndim == 1 and k != "y":
            out.attrs[k] = {"axes": ["y (lateral shift)"]}
    amp = _checks.positive("amplitude_mm", params["amplitude_mm"]) * 1e-3
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
    out.summary = (f"contact table: {n} positions, {nok} without contact, "
                   f"{int(climb.sum())} with {STATUS_NAMES[FLANGE_CLIMB]}{msg}")
    return out


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Delta-r, contact angle and roll against y from a stored case."""
    from .plots import plot_table
    r = group["results"] if "results" in group else group
    t = ContactTable(**{k: np.asarray(r[k]) for k in TABLE_ARRAYS}, wheel_radius=float("nan"),
                     tolerance=float("nan"))
    p = Path(outdir) / f"{stem}_contact_table.png"
    return [plot_table(t, p)]


register(CaseType(
    name="geometry_table",
    defaults={"wheel": PAIR_DEFAULTS["wheel"], "rail": PAIR_DEFAULTS["rail"], "cant": PAIR_DEFAULTS["cant"],
              "y_min_mm": -10.0, "y_max_mm": 10.0, "n": 201, "yaw_mrad_per_mm": 0.0,
              "gauge_mm": PAIR_DEFAULTS["gauge_mm"], "gauge_depth_mm": PAIR_DEFAULTS["gauge_depth_mm"],
              "back_to_back_mm": PAIR_DEFAULTS["back_to_back_mm"], "radius_mm": PAIR_DEFAULTS["radius_mm"],
              "amplitude_mm": 3.0},
    run=run, plot=plot, keys=PAIR_KEYS, check=check_table, aliases=PAIR_SI_ALIASES,
    summary="rigid contact table of a wheel/rail pair over lateral shifts; equivalent conicity"))
