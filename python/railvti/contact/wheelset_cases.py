"""Deck case type ``loaded_wheelset``: normal and rolling contact of a loaded wheelset over a
sweep of lateral shifts (the Manchester Contact Benchmark's case A-2.2 by default), and the
per-patch result arrays that the ``wheel_rail`` case type shares."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .. import _checks
from .._checks import MAX_FRICTION, MAX_SPEED
from ..casetypes import Alias, CaseOutput, CaseType, Key, register, validate
from ..geometry.cases import (
    PAIR_DEFAULTS,
    PAIR_KEYS,
    PAIR_MM_ALIASES,
    deck_layout,
    deck_profiles,
    mm_aliases,
    profile_problems,
    sweep_problems,
    wheelset_problems,
)
from .cases import KEYS as CONTACT_KEYS
from ..material import Material
from .wheelset import WheelsetSolution, solve_wheelset
from .wheelset_plots import case_title, plot_fields, plot_sweep

#: Patches kept per wheel in the result arrays.
MAX_PATCHES = 2
_QUANTITIES = {  # name: (unit, getter); forces on the wheel, track frame x forward, y left, z up
    "contact_angle": ("rad", lambda p: p.contact_angle),
    "x_ref": ("m", lambda p: p.contact.position[0]),
    "y_ref": ("m", lambda p: p.contact.position[1]),
    "z_ref": ("m", lambda p: p.contact.position[2]),
    "y_rail": ("m", lambda p: p.contact.y_rail),
    "y_wheel": ("m", lambda p: p.contact.y_wheel),
    "rolling_radius": ("m", lambda p: p.contact.rolling_radius),
    "xi": ("1", lambda p: p.creepage.xi if p.creepage else np.nan),
    "eta": ("1", lambda p: p.creepage.eta if p.creepage else np.nan),
    "phi": ("1/m", lambda p: p.creepage.phi if p.creepage else np.nan),
    "v_ref": ("m/s", lambda p: p.reference_speed),
    "approach": ("m", lambda p: p.approach),
    "fn": ("N", lambda p: p.fn),
    "fx": ("N", lambda p: p.fx),
    "fy": ("N", lambda p: p.fy),
    "mz": ("N m", lambda p: p.mz),
    "x_cp": ("m", lambda p: p.centre_of_pressure[0]),
    "y_cp": ("m", lambda p: p.centre_of_pressure[1]),
    "fx_track": ("N", lambda p: p.force_track[0]),
    "fy_track": ("N", lambda p: p.force_track[1]),
    "fz_track": ("N", lambda p: p.force_track[2]),
    "pmax": ("Pa", lambda p: p.pmax),
    "n_contact": ("1", lambda p: p.n_contact),
    "n_adhesion": ("1", lambda p: p.n_adhesion),
    "n_slip": ("1", lambda p: p.n_slip),
    "n_regions": ("1", lambda p: p.n_regions),
}
#: Units of the per-patch arrays of :func:`sweep_arrays`.
UNITS = {k: v[0] for k, v in _QUANTITIES.items()}


def patch_slots(first: tuple[str, ...] = ()) -> dict[str, Any]:
    """HDF5 labels of a per-patch array (..., 2 wheels, MAX_PATCHES) of :func:`sweep_arrays`."""
    return {
        "axes": [*first, "wheel", "patch"],
        "wheel": ["left", "right"],
        "empty_slots": f"NaN: the wheel has fewer than {MAX_PATCHES} contact patches",
    }


def wheel_nan_labels(axes: list[str]) -> dict[str, dict[str, Any]]:
    """The labels of the per-wheel datasets ``fz`` and ``sinks`` (``axes``, e.g. ['wheel'] or
    ['shift', 'wheel']) with the meaning of their NaN: a wheel not solved (the other wheel of
    a half wheelset, ``side = 'left'`` or 'right')."""
    nan = "NaN: the wheel was not solved (a half wheelset of the other side)"
    return {k: {"axes": list(axes), "wheel": ["left", "right"], "nan": nan} for k in ("fz", "sinks")}


def sweep_arrays(solutions: list[WheelsetSolution]) -> dict[str, np.ndarray]:
    """Per-patch quantities of a sweep as arrays (n_positions, 2 wheels, MAX_PATCHES); NaN where
    a wheel has fewer patches. Forces on the wheel; contact frame (fx, fy, mz) or track frame
    (x forward, y left, z up)."""
    n = len(solutions)
    out = {k: np.full((n, 2, MAX_PATCHES), np.nan) for k in _QUANTITIES}
    for i, s in enumerate(solutions):
        for w, side in enumerate(("left", "right")):
            for k, p in enumerate(s.wheel(side)[:MAX_PATCHES]):
                for name, (_, get) in _QUANTITIES.items():
                    out[name][i, w, k] = get(p)
    return out


#: Keys of a loaded wheelset shared by ``loaded_wheelset`` and ``wheel_rail``.
WHEELSET_KEYS: dict[str, Key] = {
    "fz": Key(
        "N",
        "vertical load per wheel (the vertical contact force)",
        lo=0.0,
        hi=1e6,
        lo_open=True,
        why="1 MN is five times the wheel load of a 40 t heavy-haul axle",
    ),
    "mu": Key(
        "1",
        "friction coefficient (0: normal contact only)",
        lo=0.0,
        hi=MAX_FRICTION,
        why="dry steel on steel is about 0.3-0.6",
    ),
    "speed": Key("m/s", "rolling speed (0: normal contact only)", lo=0.0, hi=MAX_SPEED, why="600 km/h"),
    "omega": Key(
        "rad/s", "angular velocity about the axle, > 0 rolling forward (0: free rolling)", lo=0.0, hi=2000.0
    ),
    "shear_modulus": CONTACT_KEYS["shear_modulus"],
    "poisson": CONTACT_KEYS["poisson"],
    "dx": Key("m", "element length of the contact grid along x", lo=0.0, hi=0.01, lo_open=True),
}
#: Old names of keys (deprecated): g, nu as in the 'normal' and 'rolling' case types.
MATERIAL_ALIASES = {"g": Alias("shear_modulus"), "nu": Alias("poisson")}
_KEYS = {
    **PAIR_KEYS,
    **WHEELSET_KEYS,
    "n": Key("1", "number of shifts from y_min to y_max", "int", 1, 10001),
    "field_at": Key("m", "shift whose pressure and traction fields are stored", lo=-0.05, hi=0.05),
}


def check(params: dict[str, Any]) -> list[str]:
    """Consistency of a 'loaded_wheelset' case."""
    out = profile_problems(params) + sweep_problems(params) + wheelset_problems(params)
    if not out and not params["y_min"] <= params["field_at"] <= params["y_max"]:
        out.append(
            f"field_at = {params['field_at']:g} must lie in [y_min, y_max] = "
            f"[{params['y_min']:g}, {params['y_max']:g}] (m)"
        )
    return out


def run(params: dict[str, Any]) -> CaseOutput:
    """Loaded-wheelset sweep.

    Keys: wheel, rail, cant (as ``geometry_table``), y_min, y_max (m), n, yaw_per_y (rad/m),
    fz (N per wheel: the vertical contact force, normal and tangential), mu, speed (m/s;
    mu = 0 or speed = 0: normal contact only), omega (rad/s, the wheelset's angular velocity;
    0: free rolling, no torque about the axle), shear_modulus (Pa), poisson, dx, gauge,
    gauge_depth, back_to_back, radius, field_at (the shift whose pressure and traction fields
    are stored), m; the mm-suffixed aliases (``dx_mm``...) are converted on reading. The roll
    is load-controlled (both wheels touch; each carries its load).
    """
    params = validate("loaded_wheelset", params)
    wheel, rail = deck_profiles(params)
    n = _checks.positive_int("n", params["n"])
    y = np.linspace(_checks.finite("y_min", params["y_min"]), _checks.finite("y_max", params["y_max"]), n)
    yaw = y * _checks.finite("yaw_per_y", params["yaw_per_y"])
    track, ws = deck_layout(params)
    mat = Material(shear_modulus=params["shear_modulus"], poisson=params["poisson"])
    mu, speed = float(params["mu"]), float(params["speed"])
    rolling = mu > 0 and speed > 0
    dx = _checks.positive("dx", params["dx"])
    omega = _checks.non_negative("omega", params["omega"])
    kw = {"omega": omega} if rolling and omega > 0 else {}
    sols = [
        solve_wheelset(
            wheel,
            rail,
            yi,
            wi,
            params["fz"],
            mu if rolling else None,
            speed if rolling else None,
            mat,
            dx,
            track=track,
            wheelset=ws,
            **kw,
        )
        for yi, wi in zip(y, yaw)
    ]
    arr = sweep_arrays(sols)
    ds = {
        "y": (y, "m"),
        "yaw": (yaw, "rad"),
        "status": (
            np.array([[s.geometry.status[0] != "ok", s.geometry.status[1] != "ok"] for s in sols], dtype=int),
            "0 ok, 1 no contact or flange climb",
        ),
    }
    ds.update({k: (v, _QUANTITIES[k][0]) for k, v in arr.items()})
    labels = {k: patch_slots(("y (lateral shift)",)) for k in arr}
    if rolling:
        ds["omega"] = (np.array([s.omega for s in sols]), "rad/s")
        ds["axle_torque"] = (np.array([s.axle_torque for s in sols]), "N m")
    ds["fz"] = (np.array([s.fz for s in sols]), "N")
    k_field = int(np.argmin(np.abs(y - params["field_at"])))
    store_patch_fields(ds, sols[k_field], attrs=labels)
    fl = np.nanmax(arr["contact_angle"][:, 0, :], axis=1)
    flange = y[fl > 1.0]
    summary = (
        f"loaded wheelset: {n} shifts, Fn left {np.nanmin(arr['fn'][:, 0, 0]):.0f}-"
        f"{np.nanmax(arr['fn'][:, 0, 0]):.0f} N"
        + (f", flange contact (> 1 rad) from {flange.min() * 1e3:.1f} mm" if flange.size else "")
    )
    out = CaseOutput(summary=summary, datasets=ds, attrs=labels)
    out.scalars["field_at"] = (float(y[k_field]), "m")
    return out


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Patch quantities against the shift and the stored patches' pressure maps."""
    r = group["results"] if "results" in group else group
    arrays = {k: np.asarray(r[k]) for k in _QUANTITIES if k in r}
    y = np.asarray(r["y"])
    title = "loaded wheelset, " + case_title(
        group,
        (
            ("fz", "Fz", 1e-3, " kN"),
            ("mu", "mu", 1.0, ""),
            ("speed", "speed", 1.0, " m/s"),
            ("yaw_per_y", "yaw/y", 1.0, " rad/m"),
        ),
    )
    paths = [plot_sweep(y, arrays, Path(outdir) / f"{stem}_sweep.png", title=title)]
    fields = {}
    for name in r:
        if name.startswith("field_") and name.endswith("_pressure"):
            key = name[len("field_") : -len("_pressure")]
            fields[key] = {
                q: np.asarray(r[f"field_{key}_{q}"])
                for q in ("pressure", "x", "y", "tx", "ty")
                if f"field_{key}_{q}" in r
            }
    if fields:
        at = case_title(group, (("field_at", "fields at y =", 1e3, " mm"),)).split(": ")[-1]
        paths.append(plot_fields(fields, Path(outdir) / f"{stem}_patches.png", f"{title}; {at}"))
    return paths


register(
    CaseType(
        name="loaded_wheelset",
        defaults={
            "wheel": PAIR_DEFAULTS["wheel"],
            "rail": PAIR_DEFAULTS["rail"],
            "cant": PAIR_DEFAULTS["cant"],
            "y_min": 0.0,
            "y_max": 0.01,
            "n": 21,
            "yaw_per_y": 2.4,
            "fz": 1.0e4,
            "mu": 0.3,
            "speed": 2.0,
            "omega": 0.0,
            "shear_modulus": 82.0e9,
            "poisson": 0.28,
            "dx": 0.0002,
            "gauge": PAIR_DEFAULTS["gauge"],
            "gauge_depth": PAIR_DEFAULTS["gauge_depth"],
            "back_to_back": PAIR_DEFAULTS["back_to_back"],
            "radius": PAIR_DEFAULTS["radius"],
            "field_at": 0.0,
        },
        run=run,
        plot=plot,
        keys=_KEYS,
        check=check,
        aliases={
            **MATERIAL_ALIASES,
            **{k: v for k, v in PAIR_MM_ALIASES.items() if k != "amplitude_mm"},
            **mm_aliases("dx", "field_at"),
        },
        summary="loaded wheelset over a sweep of lateral shifts: every patch, normal and rolling contact",
    )
)


def store_patch_fields(
    ds: dict, sol: WheelsetSolution, *, status: bool = False, attrs: dict | None = None
) -> None:
    """Put each patch's fields of one loaded-wheelset solution into ``ds`` as
    ``field_<side><j>_{pressure,x,y,tx,ty}`` (Pa, m), and the adhesion/slip map with
    ``status`` (0 exterior, 1 adhesion, 2 slip); their axis labels into ``attrs``
    (CaseOutput.attrs) if given."""
    for side in ("left", "right"):
        for j, p in enumerate(sol.wheel(side)[:MAX_PATCHES]):
            pre = f"field_{side}{j}"
            ds[f"{pre}_pressure"] = (p.pressure, "Pa")
            ds[f"{pre}_x"] = (p.grid.x, "m")
            ds[f"{pre}_y"] = (p.grid.y, "m")
            if p.tx is not None:
                ds[f"{pre}_tx"] = (p.tx, "Pa")
                ds[f"{pre}_ty"] = (p.ty, "Pa")
                if status:
                    ds[f"{pre}_status"] = (
                        np.asarray(p.rolling.status, dtype=np.int8),
                        "0 exterior, 1 adhesion, 2 slip",
                    )
            if attrs is not None:
                attrs[f"{pre}_x"] = {"axes": ["x (rolling)"]}
                attrs[f"{pre}_y"] = {"axes": ["y (lateral, contact frame)"]}
                for q in ("pressure", "tx", "ty", "status"):
                    if f"{pre}_{q}" in ds:
                        attrs[f"{pre}_{q}"] = {"axes": [f"{pre}_x", f"{pre}_y"]}


__all__ = [
    "MAX_PATCHES",
    "UNITS",
    "patch_slots",
    "wheel_nan_labels",
    "sweep_arrays",
    "WHEELSET_KEYS",
    "MATERIAL_ALIASES",
    "check",
    "run",
    "plot",
    "store_patch_fields",
]
