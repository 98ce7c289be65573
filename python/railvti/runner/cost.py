"""What a case will cost before it runs: wall time and memory from its size, the limits a run
must stay under, and the warning for a contact patch too coarse to be resolved.

The estimate counts what drives the work of each case type (contact grid elements, table
nodes, time steps, kept modes, ring sleepers, FRF lines) and multiplies by per-unit costs
measured on this project's 2-core test machine (``benchmarks/bench_cost_estimate.py`` prints
estimate against measured for each case type; its figures are in the constants' comments).
It builds no model and solves nothing: it is meant to be known in milliseconds for a deck of
thousands of cases, and right within a factor of about 3 (the machine's load alone moves
wall times by 2x), not exact. A value it cannot read (a text where a number belongs: the
deck's validation reports it) is taken as the key's default, so the estimate never fails.

Limits (each per case, plus one for the whole deck):

* time: ``RAILVTI_MAX_TIME`` (``railvti run --max-time``; default :data:`DEFAULT_MAX_TIME`,
  2 h) for one case; ``RAILVTI_MAX_DECK_TIME`` (``--max-deck-time``; default
  :data:`DEFAULT_MAX_DECK_TIME`) for the sum over the deck's cases and sweep points;
* memory: ``RAILVTI_MAX_MEMORY`` (:mod:`railvti.resources`).

A case past a limit is refused before any case runs, the message naming the case, the
estimate, the key that drives it and how to raise the limit.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from typing import Any, Callable

from .._checks import from_kmh
from ..contact.hertz import hertz
from ..errors import InputError
from ..material import Material
from ..resources import check_memory, memory_limit, size_text
from .stream import STREAM_TAIL_SECONDS, history_bytes, stream_threshold

#: Environment variable of the time limit of one case: seconds, or '90s', '30min', '2h',
#: '1d', or 'none'. ``railvti run --max-time`` sets it.
ENV_TIME = "RAILVTI_MAX_TIME"
#: Environment variable of the time limit of a whole deck (its cases and sweep points added).
ENV_DECK_TIME = "RAILVTI_MAX_DECK_TIME"
#: Default time limit of one case, s.
DEFAULT_MAX_TIME = 2 * 3600.0
#: Default time limit of a deck's cases added up, s.
DEFAULT_MAX_DECK_TIME = 24 * 3600.0

#: A case expected to take longer than this (s) or more memory than this (bytes) is
#: announced before it starts.
ANNOUNCE_SECONDS = 60.0
ANNOUNCE_BYTES = 500e6

#: A deck whose estimated run time is below this runs in the main process, without a Dask
#: LocalCluster: the cluster's start-up (worker processes that each import railvti, ~3-5 s
#: on a 2-core machine) would cost more than it saves (CONTACT's A-2.2 deck of 21
#: positions: 15.7 s with the cluster, 5.0 s without, 1.4 s of solves).
SERIAL_SECONDS = 10.0

#: Fewest grid elements across a contact patch (along x and along y) for a resolved
#: pressure and traction: below it the peak pressure and the creep forces are off by tens of
#: per cent (the Hertz ellipse on 4 elements has pmax at half of Hertz's).
MIN_ELEMENTS_ACROSS = 5.0


@dataclass(frozen=True)
class Estimate:
    """What a case is expected to need; NaN where unknown.

    Attributes
    ----------
    seconds : float
        Wall time, s (one core).
    memory : float
        Peak memory of the case's own work, bytes (above the interpreter's).
    key : str
        The key (or keys, 'nx, ny') whose value drives the cost most.
    size : str
        The size that key makes, for messages ('3.1e+06 grid elements').
    memory_key : str
        The key that drives the memory, if not ``key`` (a vehicle's stored samples:
        'duration, output_dt').
    warnings : tuple of str
        Results expected to be poor (an under-resolved contact patch), one line each.
    """

    seconds: float = float("nan")
    memory: float = float("nan")
    key: str = ""
    size: str = ""
    memory_key: str = ""
    warnings: tuple[str, ...] = field(default=())


# ---------------------------------------------------------------------------------------
# Reading values: never fails (validation reports bad values)


def _num(params: dict[str, Any], key: str, default: float) -> float:
    """``params[key]`` as a finite float, or ``default`` (missing, None, text, NaN, inf)."""
    v = params.get(key, default)
    if isinstance(v, (list, tuple)):
        v = v[0] if v else default
    if isinstance(v, bool):
        return default
    try:
        v = float(v)
    except (TypeError, ValueError, OverflowError):
        return default
    return v if math.isfinite(v) else default


def _pos(params: dict[str, Any], key: str, default: float, floor: float = 1e-300) -> float:
    """A positive value of ``key`` (``default`` unless positive), at least ``floor``."""
    v = _num(params, key, default)
    return max(v if v > 0 else default, floor)


def _count(params: dict[str, Any], key: str, default: float) -> float:
    """The length of a list key (one value for a scalar)."""
    v = params.get(key, None)
    if isinstance(v, (list, tuple)):
        return float(max(len(v), 1))
    return 1.0 if v is not None else default


def _nlogn(n: float) -> float:
    """n log2 n of the FFTs (at least n)."""
    return n * max(math.log2(max(n, 2.0)), 1.0)


def _sci(x: float) -> str:
    return f"{x:.3g}" if x < 1e5 else f"{x:.2e}"


# ---------------------------------------------------------------------------------------
# Hertz: the contact patch's semi-axes before any run


def _hertz_axes(
    A: float, B: float, fn: float, shear_modulus: float, poisson: float
) -> tuple[float, float] | None:
    """Semi-axes (a along x, b along y) of Hertz's ellipse of the gap A x^2 + B y^2 under
    fn, m; None when the inputs do not allow it."""
    try:
        if not (A > 0 and B > 0 and fn > 0):
            return None
        h = hertz(A, B, fn, Material(shear_modulus, poisson))
        return (h.a, h.b) if h.a > 0 and h.b > 0 else None
    except Exception:  # noqa: BLE001 - an estimate never fails: validation names bad keys
        return None


def _fn_from_approach(A: float, B: float, approach: float, g: float, nu: float) -> float | None:
    """The force of a Hertz contact of this approach (approach ~ fn^(2/3))."""
    try:
        unit = hertz(A, B, 1.0, Material(g, nu)).approach
        return (approach / unit) ** 1.5 if unit > 0 else None
    except Exception:  # noqa: BLE001
        return None


def _resolution(
    label: str,
    axes: tuple[float, float] | None,
    dx: float,
    dy: float,
    keys: tuple[str, str] = ("dx", "dy"),
    where: str = "",
) -> list[str]:
    """The under-resolution warning of a patch of Hertz semi-axes ``axes`` on a grid of
    dx x dy (empty if resolved or unknown)."""
    if axes is None:
        return []
    out = []
    for semi, d, key, name in ((axes[0], dx, keys[0], "a"), (axes[1], dy, keys[1], "b")):
        across = 2.0 * semi / d
        if across < MIN_ELEMENTS_ACROSS:
            out.append(
                f"{label}: the contact patch{where} is ~{across:.1f} elements across along "
                f"{'x' if name == 'a' else 'y'} (Hertz semi-axis {name} = {semi * 1e3:.3g} mm, "
                f"{key} = {d * 1e3:.3g} mm): under {MIN_ELEMENTS_ACROSS:g}, its pressure and "
                f"tractions are under-resolved; use {key} <= {2.0 * semi / 10.0:.3g} m "
                f"(10 elements across)"
            )
    return out


# ---------------------------------------------------------------------------------------
# Per case type. Each constant: measured wall time per unit on the 2-core test machine
# (benchmarks/bench_cost_estimate.py), in its comment the cases it comes from.

#: normal: s per n log2 n of the grid (Hertz 10 kN, CG: 40 x 32 0.0065 s, 160 x 128 0.028 s,
#: 320 x 256 0.14 s).
_NORMAL_S = 8e-8
#: rolling: s per n log2 n (FFT-GS with spin: 40 x 32 0.019 s, 80 x 64 0.15 s, 120 x 96 0.47 s).
_ROLLING_S = 2.5e-6
#: Bytes per grid element of a contact solve: the fields and the FFT buffers of the influence
#: kernels (320 x 256: 22.7 MB above the interpreter).
_GRID_BYTES = 300
#: Start-up of a case (imports done): material, grid, kernels, s.
_CASE_START_S = 0.01


def _grid_case(p: dict[str, Any], label: str, rolling: bool) -> Estimate:
    nx, ny = _pos(p, "nx", 64, 1), _pos(p, "ny", 64, 1)
    n = nx * ny
    per = _ROLLING_S if rolling else _NORMAL_S
    secs = _CASE_START_S + per * _nlogn(n)
    g, nu = _pos(p, "shear_modulus", 82e9), _num(p, "poisson", 0.28)
    dx, dy = _pos(p, "dx", 1e-4), _pos(p, "dy", 1e-4)
    axes = None
    if rolling and p.get("semi_a") is not None and p.get("semi_b") is not None:
        a, b = _num(p, "semi_a", -1), _num(p, "semi_b", -1)
        axes = (a, b) if a > 0 and b > 0 else None
    elif str(p.get("gap", "hertz")).strip().lower() == "hertz":
        A, B = _num(p, "gap_a", -1), _num(p, "gap_b", -1)
        fn = _num(p, "fn", -1) if p.get("fn") is not None else -1.0
        if fn <= 0 and p.get("approach") is not None and A > 0 and B > 0:
            fn = _fn_from_approach(A, B, _num(p, "approach", -1), g, nu) or -1.0
        axes = _hertz_axes(A, B, fn, g, nu)
    return Estimate(
        seconds=secs,
        memory=n * _GRID_BYTES,
        key="nx, ny",
        size=f"{_sci(n)} grid elements ({nx:.0f} x {ny:.0f})",
        warnings=tuple(_resolution(label, axes, dx, dy)),
    )


#: wheel_rail / loaded_wheelset: the grid a patch gets spans its Hertz ellipse with margins:
#: ~ _GRID_SPAN x (2a) by (2b) (the tread patch at 0.2 mm: ~ 67 x 50 elements), and the
#: loaded patch's solves on it (the pose iteration's normal solves, steady rolling) cost
#: _PATCH_S x n^1.1 + _PATCH_S2 x n^2.5 per wheel: the second term, the solvers' iterations
#: growing with the grid, takes over below 0.1 mm. Measured per wheel (both wheels of y = 0
#: less 0.07 s): 0.2 mm (3.4e3 elements) 0.14 s, 0.1 mm (1.3e4) 0.77 s, 0.05 mm (5.4e4)
#: 10.5-14 s, 0.035 mm (1.1e5) 67 s; the fit is within 15 % of each. loaded_wheelset: 0.06 s
#: per position at 0.4 mm, 0.18 s at 0.2 mm.
_GRID_SPAN = 2.0
_PATCH_S = 1.6e-5
_PATCH_S2 = 1.54e-11
#: Bytes per element of a wheel-rail patch: its gap and potential fields, the influence
#: kernels and the pose iteration's copies (0.4 mm: 5.7 MB, 0.2 mm: 8.7 MB, 0.1 mm: 23.8 MB
#: above the interpreter: ~1.5 kB per element added).
_PATCH_BYTES = 1500.0
#: Profiles and the rigid pose of one case, s; of one wheel at one position, s.
_WHEEL_RAIL_START_S = 0.07
_WHEEL_START_S = 0.01
#: The tread patch of the S1002 / UIC60 pair: wheel radius (x) and rail crown 300 mm (y).
_RAIL_CROWN = 0.3


def _wheel_axes(p: dict[str, Any]) -> tuple[float, float] | None:
    """Hertz semi-axes of the tread patch of a wheel on its rail under the load fz."""
    r = _pos(p, "radius", 0.46)
    return _hertz_axes(
        1.0 / (2.0 * r),
        1.0 / (2.0 * _RAIL_CROWN),
        _pos(p, "fz", 1e4),
        _pos(p, "shear_modulus", 82e9),
        _num(p, "poisson", 0.28),
    )


def _patch_seconds(n: float) -> float:
    """Wall time of one wheel's patch of ``n`` grid elements, s."""
    return _PATCH_S * n**1.1 + _PATCH_S2 * n**2.5


def _patch_elements(axes: tuple[float, float] | None, dx: float, dy: float) -> float:
    a, b = axes if axes is not None else (6e-3, 5e-3)
    return max(_GRID_SPAN * 2 * a / dx, 2.0) * max(_GRID_SPAN * 2 * b / dy, 2.0)


def _wheel_rail(p: dict[str, Any], label: str) -> Estimate:
    dx, dy = _pos(p, "dx", 2e-4), _pos(p, "dy", 2e-4)
    wheels = 1.0 if str(p.get("side", "both")).strip().lower() in ("left", "right") else 2.0
    axes = _wheel_axes(p)
    n = _patch_elements(axes, dx, dy)
    secs = _WHEEL_RAIL_START_S + wheels * (_WHEEL_START_S + _patch_seconds(n))
    return Estimate(
        seconds=secs,
        memory=5e6 + n * _PATCH_BYTES,
        key="dx, dy",
        size=f"~{_sci(n)} grid elements per patch",
        warnings=tuple(_resolution(label, axes, dx, dy, where=" on the tread")),
    )


def _loaded_wheelset(p: dict[str, Any], label: str) -> Estimate:
    dx = _pos(p, "dx", 2e-4)
    n_pos = max(_num(p, "n", 21), 1.0)
    axes = _wheel_axes(p)
    n = _patch_elements(axes, dx, dx)
    secs = _WHEEL_RAIL_START_S + n_pos * 2.0 * (_WHEEL_START_S + _patch_seconds(n))
    key = "n, dx" if n_pos > 50 else "dx"
    return Estimate(
        seconds=secs,
        memory=5e6 + n * _PATCH_BYTES,
        key=key,
        size=f"{n_pos:.0f} positions x ~{_sci(n)} grid elements per patch",
        warnings=tuple(_resolution(label, axes, dx, dx, ("dx", "dx"), " on the tread")),
    )


#: geometry_table: profiles and conicity, s; then s per shift (51 shifts 0.31 s, 201 1.5 s,
#: 2001 28 s, 10001 3 min).
_TABLE_START_S = 0.2
_TABLE_NODE_S = 1.6e-2
#: Bytes per shift of the table: each shift keeps its gap and potential fields (201 shifts:
#: 64 MB, 2001: 647 MB, 10001: 3.16 GB).
_TABLE_NODE_BYTES = 3.2e5


def _geometry_table(p: dict[str, Any], label: str) -> Estimate:
    n = max(_num(p, "n", 201), 1.0)
    return Estimate(
        seconds=_TABLE_START_S + _TABLE_NODE_S * n,
        memory=n * _TABLE_NODE_BYTES,
        key="n",
        size=f"{n:.0f} table nodes",
    )


#: wheelset (axisymmetric FE): s per harmonic at the default meshes (0.02 m wheel, 0.04 m
#: axle, 3 kHz): k_max 0 9.8 s, k_max 2 39 s at load ~2, 5 s and 21 s in another run at
#: load ~7 (28 s at mesh_size 0.015: the machine's load moves it more than the mesh); the
#: equations grow as mesh_size^-2, the solve faster (taken as mesh_size^-2.5); the FRF per
#: line, speed and mode.
_WS_HARMONIC_S = 11.0
_WS_FRF_S = 2e-7
_WS_BYTES_PER_EQ = 8 * 400
#: The wheelset model's own memory (measured ~100 MB at the defaults), bytes.
_WS_BASE_BYTES = 90e6


def _wheelset(p: dict[str, Any], label: str) -> Estimate:
    ms, ams = _pos(p, "mesh_size", 0.02), _pos(p, "axle_mesh_size", 0.04)
    k = max(_num(p, "k_max", 6), 0.0) + 1.0
    f_max = _pos(p, "f_max", 3000.0)
    refine = 0.7 * (0.02 / ms) ** 2.5 + 0.3 * (0.04 / ams) ** 2.5
    modes = k * max(f_max / 3000.0, 0.05) * 20.0
    lines = max(_num(p, "n_freq", 800), 1.0) * _count(p, "speeds_kmh", 2.0)
    secs = 0.3 + _WS_HARMONIC_S * k * refine * max(f_max / 3000.0, 0.3) ** 0.5 + _WS_FRF_S * lines * modes
    eq = 2000.0 * (0.7 * (0.02 / ms) ** 2 + 0.3 * (0.04 / ams) ** 2)
    key = (
        "mesh_size"
        if refine > 4
        else ("k_max" if k > 12 else ("n_freq" if lines * modes > 1e8 else "mesh_size, k_max"))
    )
    return Estimate(
        seconds=secs,
        memory=_WS_BASE_BYTES + eq * _WS_BYTES_PER_EQ + lines * 16 * 4,
        key=key,
        size=f"~{eq:.0f} FE equations x {k:.0f} harmonics, {lines:.0f} FRF lines",
    )


#: Ring track (2.5-D FE rail on discrete sleepers): the rail section's FE and reduced basis
#: (mesh 2e-4 m^2, 12 samples) ~5.5 s whatever the ring, then s per sleeper at 1 kHz
#: (track_receptance at 1 kHz, 200 lines: 8 sleepers 6.0 s, 16 6.1 s, 32 6.9 s; model RF's
#: ring of 40 at 3 kHz ~12 s); grows with f_max (modes) and the section mesh.
_RING_SLEEPER_S = 0.04
_RING_START_S = 5.5
_RING_FRF_S = 2e-6
_RING_BYTES_PER_MODE = 8 * 2000
#: The ring model's own memory (measured ~90 MB for 8 to 32 sleepers), bytes.
_RING_BASE_BYTES = 85e6


def _ring_build(p: dict[str, Any], prefix: str = "") -> tuple[float, float, float]:
    """(seconds, bytes, sleepers) of building a ring track of the case."""
    n_sl = max(_num(p, "n_sleepers", 40), 1.0)
    f_max = _pos(p, prefix + "f_max", 3000.0)
    mesh = 2e-4 / _pos(p, prefix + "mesh_max_area", 2e-4)
    kappa = _pos(p, prefix + "kappa_max", 50.0) / 50.0
    fcut = _pos(p, prefix + "f_cut_factor", 2.0) / 2.0
    samples = _pos(p, prefix + "n_samples", 12.0) / 12.0
    work = n_sl * (f_max / 1000.0) * fcut * max(kappa, 0.2) ** 0.5 * max(mesh, 0.1) * max(samples, 0.5)
    modes = n_sl * 4.0 * f_max / 3000.0 * fcut
    return (
        _RING_START_S * max(mesh, 0.1) * max(samples, 0.5) + _RING_SLEEPER_S * work,
        _RING_BASE_BYTES + modes * _RING_BYTES_PER_MODE,
        n_sl,
    )


def _track(p: dict[str, Any], label: str, receptance: bool) -> Estimate:
    secs, mem, n_sl = _ring_build(p)
    lines = max(_num(p, "n_freq", 3000), 1.0) if receptance else 0.0
    modes = n_sl * 4.0 * _pos(p, "f_max", 3000.0) / 3000.0
    secs += _RING_FRF_S * lines * modes * 3.0
    return Estimate(
        seconds=secs,
        memory=mem + lines * modes * 16.0,
        key="n_sleepers",
        size=f"{n_sl:.0f} sleepers" + (f", {lines:.0f} FRF lines" if receptance else ""),
    )


def _step_s(contact: str, geometry: str) -> float:
    """vehicle: the time loop's wall time per step (each includes sub-steps and Newton
    iterations of the hunting motion), by contact model (railvti.vehicle.contact_models
    names) and geometry, s: RR hunting at 300 km/h (bench_vehicle_strip, bench_cost_estimate)."""
    from ..vehicle.contact_models import BEM, HERTZ_FASTSIM, HERTZ_KALKER  # on first use: see _vehicle

    return {
        (HERTZ_KALKER.name, "strip"): 2.5e-3,
        (HERTZ_KALKER.name, "table"): 1.5e-3,
        (HERTZ_FASTSIM.name, "strip"): 2.5e-3,
        (HERTZ_FASTSIM.name, "table"): 1.2e-3,
        (BEM.name, "table"): 0.05,
    }.get((contact, geometry), 3e-3)


#: Extra wall time per step of the kept modes, s: FR's rotating wheelset modes cost
#: _WS_MODE_STEP_S x modes^1.33 (k_max 2: 384 modes at 5 kHz 37 ms per step, 1792 modes at
#: 20 kHz 0.29 s per step, from FR hunting of 0.02 and 0.01 s at load ~5); RF's ring modes
#: _RING_MODE_STEP_S per mode (128 sleepers, 926 modes up to 500 Hz: real-time factor 4.1
#: at h = 0.5 ms, ~2 ms per step; README).
#: With the exact modal step (a variant's default once it opts in, simulate.EXACT_BY_DEFAULT)
#: a step costs _EXACT_STEP_FACTOR times the trapezoidal one's modal part (FR hunting at
#: 300 km/h, 2 s: 0.5 ms trapezoidal 1.62-1.69 s, 1 ms exact 1.44-1.47 s of CPU: twice the
#: Newton iterations per step; docs/speed_accuracy.md).
_WS_MODE_STEP_S = 1.36e-5
_EXACT_STEP_FACTOR = 1.8
_WS_MODE_EXPONENT = 1.33
_RING_MODE_STEP_S = 2e-6
#: The BEM in the loop: building the gap tables of the eight wheels, s (BEM hunting 0.02 s:
#: 23 s); the critical speed: the linear analysis and the equilibria, s (18 s for 3 speeds of
#: 0.2 s), and each run's start (its equilibrium and the static state), s.
_BEM_START_S = 15.0
_CRITICAL_START_S = 8.0
_RUN_START_S = 1.0
#: Building the coach, the table, the conicity and the static equilibrium, s (RR hunting
#: 0.3 s: 6.5-7.1 s of which ~0.5 s of steps).
_VEHICLE_START_S = 6.0
#: Building model FR's wheelsets at k_max 2, s: ~10 s up to 5 kHz, then growing as f_max^3
#: (scenarios.fr_system: 800 Hz 17 s, 5 kHz 12 s, 20 kHz 112 s at load ~5).
_FR_BUILD_S = 10.0
_FR_BUILD_5KHZ_S = 1.6
#: Memory of the models above the interpreter (RR 77 MB, FR 240 MB, RF 122 MB), bytes.
_VEHICLE_BASE_BYTES = 75e6
_FR_BASE_BYTES = 160e6
#: Bytes per stored sample per state (q, v and the wheel outputs, with the copies made while
#: gathering and writing).
_SAMPLE_BYTES = 8 * 3


def _vehicle_modes(p: dict[str, Any]) -> tuple[float, float, float]:
    """(wheelset modes, highest kept frequency Hz, ring modes) of the case's model."""
    variant = str(p.get("model", "RR")).strip().upper()
    ws_modes, f_top, ring_modes = 0.0, 0.0, 0.0
    if variant in ("FR", "FF"):
        k = max(_num(p, "k_max", 2), 0.0) + 1.0
        f_top = _pos(p, "f_max", 800.0)
        scale = max(_num(p, "coach_wheelset_stiffness_scale", 1.0), 1e-6)
        f_top *= math.sqrt(scale)
        # the four wheelsets' modes at k_max 2 (scenarios.fr_system): 108 up to 800 Hz, 384 up
        # to 5 kHz, 1792 up to 20 kHz
        ws_modes = k / 3.0 * max(108.0 * (f_top / 800.0) ** 0.7, 0.0334 * f_top**1.1 - 7.0)
    if variant in ("RF", "FF"):
        n_sl = max(_num(p, "n_sleepers", 40), 8.0)
        f_lim = _pos(p, "f_limit", 500.0)
        ring_modes = n_sl * 7.2 * f_lim / 500.0  # 128 sleepers: 926 modes up to 500 Hz
        f_top = max(f_top, f_lim)
    return ws_modes, f_top, ring_modes


def _exact_modal(p: dict[str, Any]) -> bool:
    """Whether the case's modal blocks take the exact modal step (simulate's default for the
    model and alpha, railvti.vehicle.simulate.default_modal_step; FR)."""
    from ..vehicle.simulate import default_modal_step  # on first use: see _vehicle

    variant = str(p.get("model", "RR")).strip().upper()
    return default_modal_step(variant, alpha=_num(p, "alpha", 0.0)) != "trapezoidal"


def _vehicle_step(p: dict[str, Any], ws_modes: float, f_top: float) -> float:
    """The time step of the case, s (deck h, else railvti.scenarios' default: 1 ms, divided
    for the highest kept mode where the modal blocks take the trapezoidal step)."""
    h = _num(p, "h", -1.0) if p.get("h") is not None else -1.0
    if h > 0:
        return h
    h = 1e-3
    if f_top > 0 and not _exact_modal(p):
        h = 1e-3 / math.ceil(1e-3 * 2.0 * math.pi * f_top * 1.05 / 2.0)
    return h


def _streams(duration: float, out_dt: float) -> bool:
    """Whether ``railvti run`` streams this history (a bad RAILVTI_STREAM_ABOVE: as unset;
    the run names it)."""
    try:
        return history_bytes(duration, out_dt) > stream_threshold()
    except Exception:  # noqa: BLE001
        return False


def _vehicle(p: dict[str, Any], label: str) -> Estimate:
    # railvti.vehicle on first use: a deck without vehicle cases (a CONTACT deck) does not
    # import it (~0.1 s of its run, issue 33)
    from ..vehicle.contact_models import CONTACT_MODELS

    variant = str(p.get("model", "RR")).strip().upper()
    contact = str(p.get("contact", "hertz-kalker")).strip().lower()
    # the deck is not checked yet: an unknown model costs as the default (its check names it)
    spec = CONTACT_MODELS.get(contact)
    needs_bem = spec is not None and spec.needs_bem
    if spec is not None and len(spec.geometries) == 1:  # the BEM reads the table only
        geometry = spec.geometries[0]
    else:
        geometry = str(p.get("geometry") or "strip").strip().lower()
    duration = _pos(p, "duration", 3.0)
    ws_modes, f_top, ring_modes = _vehicle_modes(p)
    h = max(_vehicle_step(p, ws_modes, f_top), 1e-12)
    runs, key = 1.0, "duration"
    if str(p.get("scenario", "hunting")).strip().lower() == "critical_speed":
        lo, hi = _num(p, "speeds_kmh_min", 160.0), _num(p, "speeds_kmh_max", 440.0)
        step = _pos(p, "speeds_kmh_step", 20.0)
        # two runs per speed: the upper branch (speed lowered) and the decay from 0.5 mm
        runs = 2.0 * max(1.0, math.floor(max(hi - lo, 0.0) / step + 1e-9) + 1.0)
    steps = runs * duration / h
    per = (
        _step_s(contact, geometry)
        + _WS_MODE_STEP_S * ws_modes**_WS_MODE_EXPONENT * (_EXACT_STEP_FACTOR if _exact_modal(p) else 1.0)
        + _RING_MODE_STEP_S * ring_modes
    )
    start = _VEHICLE_START_S + (_BEM_START_S if needs_bem else 0.0)
    if runs > 1:
        start += _CRITICAL_START_S + _RUN_START_S * runs
    if ws_modes:
        start += (
            (max(_num(p, "k_max", 2), 0.0) + 1.0)
            / 3.0
            * (_FR_BUILD_S + _FR_BUILD_5KHZ_S * (f_top / 5000.0) ** 3)
        )
    if ring_modes:
        ring_p = {
            "n_sleepers": _num(p, "n_sleepers", 40),
            **{k[6:]: v for k, v in p.items() if k.startswith("track_")},
        }
        if ring_p.get("f_max") is None:
            ring_p["f_max"] = 3000.0  # RingTrack's (railvti.track.NUMERICS)
        ring_s, ring_bytes, _ = _ring_build(ring_p)
        start += ring_s
    secs = start + steps * per
    if p.get("h") is not None and _num(p, "h", 1e-3) < 1e-4:
        key = "h"
    elif ws_modes and f_top > 2000:  # the kept modes: the cost of a step (and its size, trapezoidal)
        key = "f_max"
    elif ring_modes and _pos(p, "f_limit", 500.0) > 2000:
        key = "f_limit"
    elif needs_bem:
        key = f"contact = '{contact}', duration"
    elif runs > 20:
        key = "speeds_kmh_step"
    out_dt = _num(p, "output_dt", -1.0) if p.get("output_dt") is not None else -1.0
    if out_dt <= 0:  # the deck's defaults (railvti.vehicle.output)
        scen = str(p.get("scenario", "hunting")).strip().lower()
        out_dt = 0.01 if scen == "centred_running" else 2e-3
        if ring_modes:  # 10 samples per period of the sleeper passing
            spacing = _pos(p, "track_sleeper_spacing", 0.6)
            out_dt = min(out_dt, spacing / _pos(p, "speed", from_kmh(300.0)) / 10.0)
    out_dt = max(out_dt, h)
    states = 2.0 * (70.0 + ws_modes + ring_modes) + 12 * 2 * 4
    samples = duration / out_dt
    kept = samples
    # RR's single runs stream a long history to the file (railvti.runner.stream) and keep its tail
    if variant == "RR" and runs == 1.0 and _streams(duration, out_dt):
        kept = min(samples, (STREAM_TAIL_SECONDS + 1.0) / out_dt)
    memory = (
        _VEHICLE_BASE_BYTES
        + (_FR_BASE_BYTES if ws_modes else 0.0)
        + kept * states * _SAMPLE_BYTES
        + (ws_modes + ring_modes) ** 2 * 8 * 4
    )
    if ring_modes:
        memory += ring_bytes
    if needs_bem:
        memory += 8 * 200e3 * 8  # eight wheels' BEM grids and kernels
    mem_key = key
    if kept * states * _SAMPLE_BYTES > 0.5 * memory:
        mem_key = "duration, output_dt"
    elif (ws_modes + ring_modes) ** 2 * 32 > 0.5 * memory:
        mem_key = "f_limit, n_sleepers" if ring_modes > ws_modes else "f_max, k_max"
    return Estimate(
        seconds=secs,
        memory=memory,
        key=key,
        memory_key=mem_key,
        size=f"{samples:.3g} stored samples, {steps:.3g} time steps (h = {h:.3g} s"
        + (f", {runs:.0f} runs)" if runs > 1 else ")")
        + (f", {ws_modes + ring_modes:.0f} kept modes" if ws_modes + ring_modes else ""),
    )


_ESTIMATORS: dict[str, Callable[[dict[str, Any], str], Estimate]] = {
    "normal": lambda p, lab: _grid_case(p, lab, rolling=False),
    "rolling": lambda p, lab: _grid_case(p, lab, rolling=True),
    "wheel_rail": _wheel_rail,
    "loaded_wheelset": _loaded_wheelset,
    "geometry_table": _geometry_table,
    "wheelset": _wheelset,
    "track_receptance": lambda p, lab: _track(p, lab, receptance=True),
    "track_element": lambda p, lab: _track(p, lab, receptance=False),
    "vehicle": _vehicle,
}


def estimate_params(type_name: str, params: dict[str, Any], label: str = "case") -> Estimate:
    """The estimate of a case of type ``type_name`` with these parameters (missing keys at
    their defaults). Never raises: an unknown type or unreadable values give NaN."""
    fn = _ESTIMATORS.get(type_name)
    if fn is None or not isinstance(params, dict):
        return Estimate()
    try:
        return fn(params, label)
    except Exception:  # noqa: BLE001 - an estimate never fails: validation names bad keys
        return Estimate()


def estimate(case: Any) -> Estimate:
    """The estimate of a deck case (railvti.runner.deck.Case)."""
    try:
        return estimate_params(case.case_type.name, case.params, case.label)
    except Exception:  # noqa: BLE001
        return Estimate()


# ---------------------------------------------------------------------------------------
# Limits

_UNITS = {"": 1.0, "MS": 1e-3, "S": 1.0, "SEC": 1.0, "MIN": 60.0, "M": 60.0, "H": 3600.0, "D": 86400.0}


def parse_time(text: Any, source: str = ENV_TIME) -> float:
    """Seconds of a time such as '7200', '90s', '30min', '2h', '1.5d' or 'none' (inf).

    Raises
    ------
    InputError
        Naming ``source`` (the variable or option) and the value.
    """
    t = str(text).strip().upper()
    if t in ("NONE", "INF"):
        return float("inf")
    m = re.fullmatch(r"([0-9.eE+]+)\s*([A-Z]*)", t)
    value = float("nan")
    if m and m.group(2) in _UNITS:
        try:
            value = float(m.group(1)) * _UNITS[m.group(2)]
        except ValueError:
            pass
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"{source} = {text!r} is not a time such as 7200, 90s, 30min, 2h or none")
    return value


def time_limit() -> float:
    """The time limit of one case, s (``RAILVTI_MAX_TIME`` or :data:`DEFAULT_MAX_TIME`)."""
    text = os.environ.get(ENV_TIME, "").strip()
    return parse_time(text, ENV_TIME) if text else DEFAULT_MAX_TIME


def deck_time_limit() -> float:
    """The time limit of a deck's cases added up, s (``RAILVTI_MAX_DECK_TIME`` or
    :data:`DEFAULT_MAX_DECK_TIME`)."""
    text = os.environ.get(ENV_DECK_TIME, "").strip()
    return parse_time(text, ENV_DECK_TIME) if text else DEFAULT_MAX_DECK_TIME


def duration_text(s: float) -> str:
    """'2.5 h', '12 min', '40 s', '0.3 s' for a number of seconds."""
    if s >= 86400 * 2:
        return f"{s / 86400:.1f} d"
    if s >= 3600:
        return f"{s / 3600:.1f} h"
    if s >= 60:
        return f"{s / 60:.0f} min"
    return f"{s:.0f} s" if s >= 10 else f"{s:.2g} s"


def _limit_source(env: str, default: float) -> str:
    return (
        f"{env}={os.environ[env]}" if os.environ.get(env, "").strip() else f"default {duration_text(default)}"
    )


def check_cost(cases: list[Any]) -> list[str]:
    """Problems of cases whose estimated time or memory exceeds the limits, each naming the
    case, the estimate, the key that drives it and how to raise the limit; and of a deck
    whose cases add up past the deck's limit. Empty if the deck may run.

    Raises
    ------
    InputError
        A limit's variable holds no valid value (naming it).
    """
    limit, deck_limit = time_limit(), deck_time_limit()
    memory_limit()  # a bad RAILVTI_MAX_MEMORY: named before any case
    out, total = [], 0.0
    for c in cases:
        e = estimate(c)
        if e.seconds == e.seconds:
            total += e.seconds
            if e.seconds > limit:
                out.append(
                    f"{c.label}: estimated ~{duration_text(e.seconds)} ({e.size}; driven by "
                    f"'{e.key}'), more than the time limit of {duration_text(limit)} per case "
                    f"({_limit_source(ENV_TIME, DEFAULT_MAX_TIME)}): reduce '{e.key}', or raise "
                    f"the limit with 'railvti run --max-time 8h' or {ENV_TIME}=8h (none: no limit)"
                )
        if e.memory == e.memory:
            try:
                check_memory(c.label, e.memory, f"{e.size}; driven by '{e.memory_key or e.key}': reduce it")
            except InputError as exc:
                out.append(str(exc))
    # one case is its own limit's; a deck of several is refused past the larger of the two
    if len(cases) > 1 and total > max(deck_limit, limit) and not out:
        out.append(
            f"the deck's {len(cases)} cases add up to ~{duration_text(total)} of computing, "
            f"more than the deck's limit of {duration_text(deck_limit)} "
            f"({_limit_source(ENV_DECK_TIME, DEFAULT_MAX_DECK_TIME)}): fewer cases or sweep "
            f"points, or raise the limit with 'railvti run --max-deck-time 3d' or "
            f"{ENV_DECK_TIME}=3d (none: no limit)"
        )
    return out


def resolution_warnings(cases: list[Any]) -> list[str]:
    """The warnings of cases whose results are expected to be under-resolved (a contact
    patch under :data:`MIN_ELEMENTS_ACROSS` elements across, from Hertz), one line each."""
    out: list[str] = []
    for c in cases:
        out.extend(estimate(c).warnings)
    return out


def small_deck(cases: list[Any]) -> bool:
    """The deck is one case, or its cases' estimated times are known and add up to less than
    :data:`SERIAL_SECONDS`."""
    if len(cases) < 2:
        return True
    total = sum(estimate(c).seconds for c in cases)
    return total == total and total < SERIAL_SECONDS


def announce(case: Any, write: Any) -> None:
    """Say what a case is expected to need before it starts, when that is large."""
    e = estimate(case)
    parts = []
    if e.memory == e.memory and e.memory > ANNOUNCE_BYTES:
        parts.append(f"~{size_text(e.memory)} of memory (limit {size_text(memory_limit())})")
    if e.seconds == e.seconds and e.seconds > ANNOUNCE_SECONDS:
        parts.append(f"~{duration_text(e.seconds)}")
    if parts:
        write(f"{case.label}: expected to need {' and '.join(parts)} ({e.size}; rough estimate)")


__all__ = [
    "Estimate",
    "estimate",
    "estimate_params",
    "check_cost",
    "resolution_warnings",
    "small_deck",
    "announce",
    "time_limit",
    "deck_time_limit",
    "parse_time",
    "duration_text",
    "ENV_TIME",
    "ENV_DECK_TIME",
    "DEFAULT_MAX_TIME",
    "DEFAULT_MAX_DECK_TIME",
]
