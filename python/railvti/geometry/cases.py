"""Deck case type ``geometry_table``: the rigid contact table of a wheel/rail pair."""
from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .. import _checks
from ..casetypes import CaseOutput, CaseType, register
from ..errors import InputError
from .. import profiles as P
from ._setup import Track, WheelsetGeometry
from .conicity import equivalent_conicity, klingel_wavelength
from .table import STATUS_NAMES, contact_table


def _profile(spec: str, kind: str, cant: float) -> P.Profile:
    s = str(spec).strip()
    if s.lower() == "s1002" and kind == "wheel":
        return P.s1002()
    if s.lower() == "uic60" and kind == "rail":
        return P.uic60(cant=cant)
    path = Path(s)
    if path.suffix.lower() in (".prw", ".prr"):
        return P.read(path)
    if not path.is_file():
        raise InputError(f"{kind} must be 's1002'/'uic60' or a profile file, got {spec!r}")
    return P.read(path, unit="mm", kind=kind)


def run(params: dict[str, Any]) -> CaseOutput:
    """Contact table case.

    Keys: wheel ('s1002' or a file), rail ('uic60' or a file; a file is taken as already
    canted), cant (tan, for 'uic60'), y_min_mm, y_max_mm, n (positions), yaw_mrad_per_mm
    (yaw rising with the shift), gauge_mm, gauge_depth_mm, back_to_back_mm, radius_mm,
    amplitude_mm (for the equivalent conicity).
    """
    wheel = _profile(params["wheel"], "wheel", 0.0)
    rail = _profile(params["rail"], "rail", _checks.finite("cant", params["cant"]))
    n = _checks.positive_int("n", params["n"], 2)
    y = np.linspace(_checks.finite("y_min_mm", params["y_min_mm"]),
                    _checks.finite("y_max_mm", params["y_max_mm"]), n) * 1e-3
    yaw = y * 1e3 * _checks.finite("yaw_mrad_per_mm", params["yaw_mrad_per_mm"]) * 1e-3
    track = Track(gauge=params["gauge_mm"] * 1e-3, gauge_depth=params["gauge_depth_mm"] * 1e-3)
    ws = WheelsetGeometry(back_to_back=params["back_to_back_mm"] * 1e-3, radius=params["radius_mm"] * 1e-3)
    t = contact_table(wheel, rail, y, yaw, track=track, wheelset=ws)
    units = {"y": "m", "yaw": "rad", "rise": "m", "roll": "rad", "status": "0 ok, 1 no contact, 2 flange climb",
             "n_contact": "1", "separation": "m", "contact_angle": "rad", "rolling_radius": "m",
             "y_wheel": "m", "y_rail": "m", "x": "m", "y_track": "m", "z_track": "m", "delta_r": "m"}
    out = CaseOutput(summary="", datasets={k: (np.asarray(v), units[k]) for k, v in t.as_dict().items()})
    amp = _checks.positive("amplitude_mm", params["amplitude_mm"]) * 1e-3
    msg = ""
    if np.all(yaw == 0) and -y.min() >= amp and y.max() >= amp:
        con = equivalent_conicity(t, amp)
        e0 = 0.5 * float(np.nanmedian(t.y_track[:, 0, 0] - t.y_track[::-1, 1, 0]))
        out.scalars["equivalent_conicity"] = (con, "1")
        out.scalars["klingel_wavelength"] = (klingel_wavelength(con, ws.radius, e0), "m")
        msg = f", tan(gamma_e)({amp * 1e3:g} mm) = {con:.4f}"
    climb = np.any(t.status == 2, axis=1)
    if climb.any():
        out.scalars["flange_climb_from"] = (float(np.min(np.abs(t.y[climb]))), "m")
    nok = int(np.sum(np.any(t.status == 1, axis=1)))
    object.__setattr__(out, "summary", f"contact table: {n} positions, {nok} without contact, "
                       f"{int(climb.sum())} with {STATUS_NAMES[2]}{msg}")
    return out


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Delta-r, contact angle and roll against y from a stored case."""
    from .plots import plot_table
    from .table import ContactTable
    r = group["results"] if "results" in group else group
    names = ("y", "yaw", "rise", "roll", "status", "n_contact", "separation", "contact_angle",
             "rolling_radius", "y_wheel", "y_rail", "x", "y_track", "z_track")
    t = ContactTable(**{k: np.asarray(r[k]) for k in names}, radius=float("nan"), tolerance=float("nan"))
    p = Path(outdir) / f"{stem}_contact_table.png"
    return [plot_table(t, p)]


register(CaseType(
    name="geometry_table",
    defaults={"wheel": "s1002", "rail": "uic60", "cant": 0.025, "y_min_mm": -10.0, "y_max_mm": 10.0,
              "n": 201, "yaw_mrad_per_mm": 0.0, "gauge_mm": 1435.0, "gauge_depth_mm": 14.0,
              "back_to_back_mm": 1360.0, "radius_mm": 460.0, "amplitude_mm": 3.0},
    run=run, plot=plot))
