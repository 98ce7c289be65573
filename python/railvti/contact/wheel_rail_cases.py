"""Deck case type ``wheel_rail``: one position of a wheelset (one wheel, CONTACT's half
wheelset, or both) on its rails with its full kinematics, as a CONTACT module-1 case.

The CONTACT deck reader (:mod:`railvti.contact.contact_deck`) turns every case of a CONTACT
``.inp`` file into a case of this type; a namelist deck may use it directly. Inputs are in
railvti's conventions (SI keys, mm / mrad only as suffixed aliases; track frame x forward,
y left, z up); the console summary repeats the results in CONTACT's conventions (mm, N,
forces on the rail, y to the right, z down) for comparison with CONTACT's output.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from .. import _checks
from .. import profiles as P
from .._checks import MAX_SPEED
from ..casetypes import Alias, CaseOutput, CaseType, Key, register, validate
from ..errors import InputError
from ..geometry import TrackLayout
from ..material import Material
from ..wheelset.geometry import WheelsetGeometry
from .wheelset import REFERENCES, WheelsetPatch, WheelsetSolution, solve_wheelset
from .wheelset_plots import case_title, plot_fields
from ..geometry.cases import PAIR_KEYS, mm_aliases, profile_problems, wheelset_problems
from .wheelset_cases import (
    MATERIAL_ALIASES,
    UNITS,
    WHEELSET_KEYS,
    patch_slots,
    store_patch_fields,
    sweep_arrays,
    wheel_nan_labels,
)

_SIDES = {"left": ("left",), "right": ("right",), "both": ("left", "right")}
_PROFILE_CACHE: dict[tuple, P.Profile] = {}


def load_profile(
    spec: str, kind: str, mirror_y: bool = False, scale: float = 1.0, cant: float = 0.0
) -> P.Profile:
    """A wheel or rail profile as a CONTACT deck describes it (cached per file and options).

    Parameters
    ----------
    spec : str
        's1002', 'uic60' or a profile file: SIMPACK ``.prw``/``.prr`` (its header's units and
        mirroring applied), otherwise two columns y, z in mm.
    kind : {'wheel', 'rail'}
    mirror_y : bool
        Negate y (CONTACT's MIRRORY = 1).
    scale : float
        Factor on y and z after reading (CONTACT's SCALE; a plain file is mm times this).
    cant : float
        Rotation of a rail profile towards the track centre, rad (CONTACT's CANT).

    Returns
    -------
    Profile
    """
    scale = _checks.positive("profile scale", scale)
    cant = _checks.finite("cant", cant)
    path = Path(spec)
    stamp = path.stat().st_mtime_ns if path.is_file() else 0
    key = (str(path.resolve()) if path.is_file() else spec, stamp, kind, bool(mirror_y), scale, cant)
    hit = _PROFILE_CACHE.get(key)
    if hit is not None:
        return hit
    prof = P.load(spec, kind)
    y, z = prof.y * scale, prof.z * scale
    if mirror_y:
        y = -y
    if cant:
        if kind != "rail":
            raise InputError("cant rotates a rail profile only")
        y, z = y * math.cos(cant) + z * math.sin(cant), -y * math.sin(cant) + z * math.cos(cant)
    if mirror_y or scale != 1.0 or cant:
        prof = P.Profile(y, z, kind=kind, name=prof.name)
    if len(_PROFILE_CACHE) > 16:
        _PROFILE_CACHE.clear()
    _PROFILE_CACHE[key] = prof
    return prof


def _solve(params: dict[str, Any]) -> WheelsetSolution:
    side = str(params["side"]).strip().lower()
    if side not in _SIDES:
        raise InputError(f"side must be one of {sorted(_SIDES)}, got {params['side']!r}")
    wheel = load_profile(params["wheel"], "wheel", bool(params["wheel_mirror_y"]), params["wheel_scale"])
    rail = load_profile(
        params["rail"], "rail", bool(params["rail_mirror_y"]), params["rail_scale"], params["cant_rad"]
    )
    track = TrackLayout(
        gauge=_checks.positive("gauge", params["gauge"]),
        gauge_depth=_checks.positive("gauge_depth", params["gauge_depth"]),
    )
    ws = WheelsetGeometry(
        back_to_back=_checks.positive("back_to_back", params["back_to_back"]),
        wheel_radius=_checks.positive("radius", params["radius"]),
        contact_offset=_checks.finite("contact_offset", params["contact_offset"]),
    )
    mat = Material(shear_modulus=params["shear_modulus"], poisson=params["poisson"])
    mu, speed = _checks.non_negative("mu", params["mu"]), _checks.non_negative("speed", params["speed"])
    rolling = mu > 0 and speed > 0
    roll = params["roll"]
    roll = None if roll is None else _checks.finite("roll", roll)
    omega = _checks.non_negative("omega", params["omega"])
    kin = {}
    if rolling:
        kin = dict(
            omega=omega if omega > 0 else None,
            lateral_velocity=params["lateral_velocity"],
            vertical_velocity=params["vertical_velocity"],
            roll_rate=params["roll_rate"],
            yaw_rate=params["yaw_rate"],
        )
    return solve_wheelset(
        wheel,
        rail,
        _checks.finite("y", params["y"]),
        _checks.finite("yaw", params["yaw"]),
        params["fz"],
        mu if rolling else None,
        speed if rolling else None,
        mat,
        _checks.positive("dx", params["dx"]),
        dy=_checks.positive("dy", params["dy"]),
        roll=roll,
        side=None if side == "both" else side,
        track=track,
        wheelset=ws,
        reference=str(params["reference"]).strip().lower(),
        d_sep=_checks.positive("d_sep", params["d_sep"]),
        d_comb=_checks.positive("d_comb", params["d_comb"]),
        **kin,
    )


def contact_summary(sol: WheelsetSolution) -> list[str]:
    """Lines per wheel and patch in CONTACT's conventions: mm, N, N mm, MPa; track frame with
    y to the right and z down; forces and moments on the rail; creepages of the rail
    relative to the wheel (CKSI = -xi, CETA = eta, CPHI = phi); DELTCP positive on the left."""
    lines = []
    for w, side in enumerate(("left", "right")):
        if not math.isfinite(sol.fz[w]):
            continue
        patches = sol.wheel(side)
        f = sum((p.force_track for p in patches), np.zeros(3))
        lines.append(
            f"{side} wheel: {len(patches)} patch(es), FX_TR {-f[0]:.1f} FY_TR {f[1]:.1f} FZ_TR {f[2]:.1f} N"
            + (f", VPITCH {-sol.omega:.6f} rad/s" if sol.omega is not None else "")
            + f", ROLL {sol.pose_roll * 1e3:.4f} mrad"
        )
        for k, p in enumerate(patches, 1):
            lines.append("  " + _patch_line(k, p, 1.0 if side == "left" else -1.0))
    return lines


def _patch_line(k: int, p: WheelsetPatch, sg: float) -> str:
    x, y, z = p.contact.position * 1e3
    s = (
        f"patch {k}: XCP,YCP,ZCP {x:.3f} {-y:.3f} {-z:.4f} mm, YCP_R {-sg * p.contact.y_rail * 1e3:.3f} mm, "
        f"DELTCP {sg * p.contact_angle:.4f} rad, FN {p.fn:.1f} FX {-p.fx:.1f} FS {p.fy:.1f} N, "
        f"MN {p.mz * 1e3:.1f} N mm, PEN {p.approach * 1e3:.5f} mm, PMAX {p.pmax * 1e-6:.0f} MPa"
    )
    if p.creepage is not None:
        c = p.creepage
        s += f", CKSI {-c.xi:.4e} CETA {c.eta:.4e} CPHI {c.phi * 1e-3:.4e} 1/mm"
    n_reg = p.n_regions
    return s + (
        f", elements {p.n_contact} (adhesion {p.n_adhesion}, slip {p.n_slip})"
        + (f" in {n_reg} areas" if n_reg > 1 else "")
    )


#: Fewest elements a wheel's main contact patch spans along x or along y: a patch of at most
#: 2 x 2 elements resolves no pressure distribution (the force is shared by a few elements,
#: whatever the Hertz p0). A narrow flange patch (39 x 2 elements) is resolved along x.
MIN_PATCH_ELEMENTS = 3


def resolution_problem(sol: WheelsetSolution, params: dict[str, Any]) -> str | None:
    """Why a solution's contact is unresolved by the grid (None: it is resolved): the patch
    carrying most of a wheel's load spans fewer than :data:`MIN_PATCH_ELEMENTS` elements
    along both x and y. Small secondary patches (a flange touching) are not judged."""
    for side, patches in (("left", sol.left), ("right", sol.right)):
        if not patches:
            continue
        main = max(patches, key=lambda p: p.fn)
        inside = np.asarray(main.pressure) > 0
        nx, ny = int(inside.any(axis=1).sum()), int(inside.any(axis=0).sum())
        if max(nx, ny) < MIN_PATCH_ELEMENTS:
            return (
                f"the {side} wheel's contact patch spans {nx} x {ny} elements (x, y) of dx = "
                f"{params['dx']:g} m, dy = {params['dy']:g} m: fewer than {MIN_PATCH_ELEMENTS} "
                "along x or y do not resolve its pressure; make dx and dy smaller (the patch is "
                f"about {nx * params['dx'] * 1e3:.3g} x {ny * params['dy'] * 1e3:.3g} mm)"
            )
    return None


def run(params: dict[str, Any]) -> CaseOutput:
    """One wheelset position.

    Keys: side ('left' or 'right': that wheel as a half wheelset, CONTACT's module 1; 'both');
    wheel, rail (profile: 's1002', 'uic60' or a file), wheel_mirror_y, rail_mirror_y (0/1),
    wheel_scale, rail_scale (factors to the file's length unit: mm for plain files),
    cant_rad (extra rail rotation towards the track centre, rad); gauge, gauge_depth,
    back_to_back, contact_offset (tread datum from the flange back), radius (m);
    y (lateral shift, to the left, m), yaw, roll (rad; prescribed roll, positive raises
    the left wheel; none: load-controlled, 'both' only), fz (vertical load per wheel, N:
    normal and tangential contact forces); speed (m/s), omega (rad/s about the axle, > 0
    rolling forward; 0: free rolling, 'both' only), lateral_velocity, vertical_velocity
    (m/s, y left, z up), roll_rate, yaw_rate (rad/s); mu (mu = 0 or speed = 0: normal
    contact only), shear_modulus (Pa), poisson, dx, dy (m); reference ('contact': each
    patch's creepages at CONTACT's contact reference point, the default; 'minimum': at the
    point of smallest gap); d_sep, d_comb (m; CONTACT's D_SEP, D_COMB: with 'contact', a patch's
    areas further apart than d_comb interact with CONTACT's reduced factor); store_fields (1:
    keep each patch's pressure and tractions);
    origin (where the case comes from, for messages).
    The suffixed aliases (``gauge_mm``..., ``yaw_mrad``, ``roll_mrad``) are converted on reading.
    """
    try:
        params = validate("wheel_rail", params)
        sol = _solve(params)
    except InputError as exc:
        origin = str(params.get("origin") or "")
        raise type(exc)(f"{origin}: {exc}" if origin else str(exc)) from None
    problem = resolution_problem(sol, params)
    if problem:
        origin = str(params.get("origin") or "")
        raise InputError(f"{origin}: {problem}" if origin else problem)
    arr = {k: v[0] for k, v in sweep_arrays([sol]).items()}
    ds: dict[str, tuple[np.ndarray, str]] = {k: (v, UNITS[k]) for k, v in arr.items()}
    ds["fz"] = (np.array(sol.fz), "N")
    ds["sinks"] = (np.array(sol.sinks), "m")
    out = CaseOutput(summary="", datasets=ds, attrs={k: patch_slots() for k in arr})
    out.attrs.update(wheel_nan_labels(["wheel"]))
    out.scalars["pose_roll"] = (sol.pose_roll, "rad")
    out.scalars["load_iterations"] = (sol.iterations, "1")
    if sol.omega is not None:
        out.scalars["omega"] = (sol.omega, "rad/s")
        out.scalars["axle_torque"] = (sol.axle_torque, "N m")
        out.scalars["rolling_solves"] = (sol.outer_iterations, "1")
    if int(params["store_fields"]):
        store_patch_fields(ds, sol, status=True, attrs=out.attrs)
    lines = contact_summary(sol)
    out.summary = "\n    ".join(lines) if len(lines) > 1 else (lines[0] if lines else "no wheel solved")
    return out


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """The stored patches' pressure maps with traction vectors (store_fields = 1)."""
    r = group["results"] if "results" in group else group
    fields = {}
    for name in r:
        if name.startswith("field_") and name.endswith("_pressure"):
            key = name[len("field_") : -len("_pressure")]
            fields[key] = {
                q: np.asarray(r[f"field_{key}_{q}"])
                for q in ("pressure", "x", "y", "tx", "ty")
                if f"field_{key}_{q}" in r
            }
    title = "wheel on rail, " + case_title(
        group,
        (
            ("y", "y", 1e3, " mm"),
            ("yaw", "yaw", 1e3, " mrad"),
            ("fz", "Fz", 1e-3, " kN"),
            ("mu", "mu", 1.0, ""),
            ("speed", "speed", 1.0, " m/s"),
        ),
    )
    return [plot_fields(fields, Path(outdir) / f"{stem}_patches.png", title)] if fields else []


#: Keys of the ``wheel_rail`` case type and their defaults: the Manchester benchmark's data (its
#: profile files, shipped with railvti; the rail file is already canted 1:40).
DEFAULTS: dict[str, Any] = {
    "side": "both",
    "wheel": str(P.example_path("MBench_S1002_v3.prw")),
    "rail": str(P.example_path("MBench_UIC60_v3.prr")),
    "wheel_mirror_y": 0,
    "rail_mirror_y": 0,
    "wheel_scale": 1.0,
    "rail_scale": 1.0,
    "cant_rad": 0.0,
    "gauge": 1.435,
    "gauge_depth": 0.014,
    "back_to_back": 1.36,
    "contact_offset": 0.07,
    "radius": 0.46,
    "y": 0.0,
    "yaw": 0.0,
    "roll": None,
    "fz": 1.0e4,
    "speed": 2.0,
    "omega": 0.0,
    "lateral_velocity": 0.0,
    "vertical_velocity": 0.0,
    "roll_rate": 0.0,
    "yaw_rate": 0.0,
    "mu": 0.3,
    "shear_modulus": 82.0e9,
    "poisson": 0.28,
    "dx": 0.0002,
    "dy": 0.0002,
    "store_fields": 0,
    "origin": "",
    "reference": "contact",
    "d_sep": 0.008,
    "d_comb": 0.004,
}

_WHY_SHIFT = "beyond 50 mm the flange has left the rail"
KEYS: dict[str, Key] = {
    **{k: PAIR_KEYS[k] for k in ("wheel", "rail", "gauge", "gauge_depth", "back_to_back", "radius")},
    **WHEELSET_KEYS,
    "side": Key(
        "",
        "wheels solved: 'left' or 'right' (a half wheelset, CONTACT's module 1) or 'both'",
        "str",
        choices=tuple(_SIDES),
    ),
    "wheel_mirror_y": Key("", "1: mirror the wheel profile's y (CONTACT's MIRRORY)", "flag"),
    "rail_mirror_y": Key("", "1: mirror the rail profile's y", "flag"),
    "wheel_scale": Key(
        "1", "factor to the wheel file's length unit (mm for plain files)", lo=0.0, hi=1e4, lo_open=True
    ),
    "rail_scale": Key(
        "1", "factor to the rail file's length unit (mm for plain files)", lo=0.0, hi=1e4, lo_open=True
    ),
    "cant_rad": Key("rad", "extra rail rotation towards the track centre", lo=-0.2, hi=0.2),
    "contact_offset": Key("m", "tread datum from the flange back", lo=0.0, hi=0.2),
    "y": Key("m", "lateral shift of the wheelset, to the left", lo=-0.05, hi=0.05, why=_WHY_SHIFT),
    "yaw": Key("rad", "yaw angle of the wheelset", lo=-0.1, hi=0.1),
    "roll": Key(
        "rad",
        "prescribed roll, > 0 raises the left wheel (none: load-controlled, 'both' only)",
        lo=-0.1,
        hi=0.1,
        optional=True,
    ),
    "lateral_velocity": Key("m/s", "lateral velocity of the wheelset (y left)", lo=-MAX_SPEED, hi=MAX_SPEED),
    "vertical_velocity": Key("m/s", "vertical velocity of the wheelset (z up)", lo=-MAX_SPEED, hi=MAX_SPEED),
    "roll_rate": Key("rad/s", "roll rate of the wheelset", lo=-100.0, hi=100.0),
    "yaw_rate": Key("rad/s", "yaw rate of the wheelset", lo=-100.0, hi=100.0),
    "dy": Key("m", "element length of the contact grid along y", lo=0.0, hi=0.01, lo_open=True),
    "store_fields": Key("", "1: keep each patch's pressure and tractions", "flag"),
    "reference": Key(
        "",
        "each patch's reference point, where the creepages are taken: 'contact' (CONTACT's "
        "weighted interpenetration centre at the loaded pose) or 'minimum' (the rigid pose's point "
        "of smallest gap)",
        "str",
        choices=REFERENCES,
    ),
    "d_sep": Key(
        "m",
        "CONTACT's D_SEP: a patch's areas closer than this are one patch (reference 'contact': "
        "sets their interaction factor)",
        lo=0.0,
        hi=0.1,
        lo_open=True,
    ),
    "d_comb": Key(
        "m",
        "CONTACT's D_COMB: a patch's areas further apart than this interact with the factor "
        "((d_sep - d) / (d_sep - d_comb))^0.8 (reference 'contact')",
        lo=0.0,
        hi=0.1,
        lo_open=True,
    ),
    "origin": Key("", "where the case comes from, for messages", "str"),
}


def check(params: dict[str, Any]) -> list[str]:
    """Consistency of a 'wheel_rail' case."""
    out = profile_problems(params) + wheelset_problems(params, contact_offset="contact_offset")
    side = str(params["side"]).strip().lower()
    if side != "both" and params["roll"] is None:
        out.append(
            f"side = '{side}' needs roll (rad; or roll_mrad): a load-controlled roll needs both wheels"
        )
    if not params["d_comb"] < params["d_sep"]:
        out.append(f"d_comb ({params['d_comb']} m) must be smaller than d_sep ({params['d_sep']} m)")
    if side != "both" and params["mu"] > 0 and params["speed"] > 0 and params["omega"] == 0:
        out.append(
            f"side = '{side}' with rolling (mu, speed > 0) needs omega > 0 (rad/s): free rolling "
            "needs both wheels"
        )
    return out


#: The suffixed aliases of the SI keys: the same quantities in CONTACT's mm and mrad.
MM_ALIASES = {
    **mm_aliases(
        "gauge", "gauge_depth", "back_to_back", "contact_offset", "radius", "y", "dx", "dy", "d_sep", "d_comb"
    ),
    "yaw_mrad": Alias("yaw", 1e-3, deprecated=False, unit="mrad"),
    "roll_mrad": Alias("roll", 1e-3, deprecated=False, unit="mrad"),
}

register(
    CaseType(
        name="wheel_rail",
        defaults=DEFAULTS,
        run=run,
        plot=plot,
        keys=KEYS,
        check=check,
        aliases={**MATERIAL_ALIASES, **MM_ALIASES},
        summary="one wheelset position on its rails with its full kinematics (CONTACT module 1)",
    )
)

__all__ = [
    "load_profile",
    "contact_summary",
    "MIN_PATCH_ELEMENTS",
    "resolution_problem",
    "run",
    "plot",
    "DEFAULTS",
    "KEYS",
    "check",
    "MM_ALIASES",
]
