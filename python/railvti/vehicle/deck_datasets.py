"""The datasets and scalars a deck case of type ``vehicle`` stores besides the run's own
(:meth:`railvti.vehicle.run_result.SimulationResult.case_data`; the layout in
railvti.vehicle.cases' docstring and docs/results.md): the modal coordinates and rim and rail
motion of variants FR, RF and FF, the contact patch, and the datasets a streamed history
derives block by block."""

from __future__ import annotations

import numpy as np

from .flexible import mode_labels
from .flexible_points import rail_head_roll, rim_camber_change, rim_deformation
from .model import WHEEL_OUTPUTS
from .run_result import WHEEL_SIDES

__all__ = ["modal_datasets", "stream_derived", "patch_datasets"]


def _fr_history(res, system, layouts, data: dict, stop: int | None = None) -> None:
    """Variant FR: the modal coordinates with their mode labels and the rims' deformation at
    the contact points (railvti.vehicle.flexible_points.rim_deformation, rim_camber_change,
    rail_head_roll on the ring, rim_rail_angle_change: the relative angle);
    ``stop``: the state's end of the wheelsets' coordinates (variant FF: the ring's follow)."""
    n = system.n
    stop = system.n_state if stop is None else stop
    nm = stop - n
    labels = list(mode_labels(system, layouts))[:nm]
    k = np.full(nm, -1)
    fam = np.full(nm, "residual", dtype=object)
    freq = np.full(nm, np.nan)
    units = ["m"] * nm  # residual coordinates: point displacements, m
    for lay in layouts:
        i = slice(lay.modes.start - n, lay.modes.stop - n)
        k[i], fam[i], freq[i] = lay.k, lay.family, lay.freq_hz
        units[i] = ["kg^0.5 m"] * (i.stop - i.start)  # mass-normalised (M = I)
    mode = {"axes": ["mode"], "mode_label": labels}
    data["mode_label"] = (np.array(labels, dtype=object), "text", {"axes": ["mode"]})
    data["mode_k"] = (
        k,
        "1",
        {**mode, "meaning": "circumferential harmonic (-1: residual flexibility's massless coordinate)"},
    )
    data["mode_family"] = (
        np.array([str(f) for f in fam], dtype=object),
        "text",
        {**mode, "meaning": "'0' (k = 0), 'A' or 'B' (k > 0), 'residual'"},
    )
    data["mode_frequency"] = (
        freq,
        "Hz",
        {**mode, "meaning": "free-free non-rotating natural frequency (NaN: residual)"},
    )
    data["modal_q"] = (
        res.q[:, n:stop],
        "kg^0.5 m or m (per column: column_units)",
        {"axes": ["t", "mode"], "mode_label": labels, "column_units": units},
    )
    per = {
        "axes": ["t", "component", "wheel", "wheelset"],
        "component": ["dy", "dz", "drx"],
        "wheel": WHEEL_SIDES,
        "wheelset": [f"ws{w + 1}" for w in range(4)],
        "column_units": ["m", "m", "rad"],
        "meaning": "rim deformation at the contact points (taping line), track axes",
    }
    data["rim_deformation"] = (rim_deformation(system, res.q), "m, m, rad (per component)", per)
    per_w = {
        "axes": ["t", "wheel", "wheelset"],
        "wheel": WHEEL_SIDES,
        "wheelset": [f"ws{w + 1}" for w in range(4)],
    }
    inner = (
        "+: the inner edge, towards the track centre, rises; -drx on the left wheel, +drx "
        "on the right, drx about the vehicle's x, y positive to the left"
    )
    camber = rim_camber_change(system, res.q)
    roll = rail_head_roll(system, res.q, res.t)
    data["rim_camber_change"] = (
        camber,
        "rad",
        {**per_w, "meaning": "elastic camber of the rim at the contact point (" + inner + ")"},
    )
    if getattr(system, "ring", None) is not None:
        data["rail_head_roll"] = (
            roll,
            "rad",
            {
                **per_w,
                "meaning": "elastic roll of the rail head "
                "under the wheel from the ring's modes (" + inner + ")",
            },
        )
    data["rim_rail_angle_change"] = (
        camber - roll,
        "rad",
        {
            **per_w,
            "meaning": "change of the rim-rail relative angle: rim_camber_change minus the "
            "rail head's roll under the wheel (rail_head_roll; 0 on the rigid "
            "track of model FR) (" + inner + ")",
        },
    )


def _ring_history(res, system, data: dict, prefix: str = "") -> None:
    """Variant RF: the ring's modal coordinates with their labels and the rail's motion under
    each wheel (RingSystem.rail_deflection; the crown's vertical displacement beside it);
    the mode datasets' names get ``prefix`` (variant FF: 'ring_', beside the wheelsets')."""
    ring = system.ring
    n0 = system.n_state - ring.n_modes - ring.n_residual
    labels = list(system.state_names[n0:])
    mb = system.modal
    nm = ring.n_modes
    om = np.sqrt([float(mb.stiffness[i][0, 0]) for i in range(nm)])
    freq = np.concatenate([om / (2 * np.pi), np.full(ring.n_residual, np.nan)])
    zeta = np.concatenate(
        [[float(mb.damping[i][0, 0]) / (2 * o) for i, o in enumerate(om)], np.full(ring.n_residual, np.nan)]
    )
    group = np.array([int(n.split("_")[1][1:]) if n.startswith("ring_g") else -1 for n in labels])
    units = ["kg^0.5 m"] * nm + [("rad" if n.endswith("_r") else "m") for n in labels[nm:]]
    mode = {"axes": ["mode"], "mode_label": labels}
    data[prefix + "mode_label"] = (np.array(labels, dtype=object), "text", {"axes": ["mode"]})
    data[prefix + "mode_group"] = (
        group,
        "1",
        {
            **mode,
            "meaning": "cyclic group j of the ring mode (its "
            "sleeper-pattern wave number; -1: a residual "
            "flexibility coordinate)",
        },
    )
    data[prefix + "mode_frequency"] = (
        freq,
        "Hz",
        {**mode, "meaning": "natural frequency of the ring mode (NaN: residual)"},
    )
    data[prefix + "mode_damping_ratio"] = (
        zeta,
        "1",
        {**mode, "meaning": "modal damping ratio (NaN: residual)"},
    )
    data[prefix + "modal_q"] = (
        res.q[:, n0:],
        "kg^0.5 m, m or rad (per column: column_units)",
        {
            "axes": ["t", "mode"],
            "mode_label": labels,
            "column_units": units,
            "meaning": "ring modes (mass-normalised), then per wheel the residual "
            "flexibility's coordinates (y, z, roll of the element pose)",
        },
    )
    rail = system.rail_deflection(res.t, res.q)  # (nt, 3, 2, nw)
    nw = rail.shape[-1]
    per = {
        "axes": ["t", "component", "wheel", "wheelset"],
        "component": ["y", "z", "roll"],
        "wheel": WHEEL_SIDES,
        "wheelset": [f"ws{w + 1}" for w in range(nw)],
        "column_units": ["m", "m", "rad"],
        "meaning": "rail head's motion under each wheel: the pose (y, z, roll; vehicle frame, y "
        "to the left) of the track element under the wheel, from the ring's modes",
    }
    data["rail_deflection"] = (rail, "m, m, rad (per component)", per)
    half = 0.5 * ring.rail_distance
    crown = rail[:, 1] + np.array([half, -half])[:, None] * rail[:, 2]
    data["rail_crown_z"] = (
        crown,
        "m",
        {
            "axes": ["t", "wheel", "wheelset"],
            "wheel": WHEEL_SIDES,
            "wheelset": [f"ws{w + 1}" for w in range(nw)],
            "meaning": "vertical displacement of the rail crown under each wheel (+ up)",
        },
    )


def modal_datasets(res, sy, layouts: list, fr: dict, ring: dict, data: dict, scalars: dict) -> None:
    """The modal datasets of a run (variant FR: the wheelsets'; RF: the ring's; FF: both, the
    ring's prefixed 'ring_') from the system ``sy`` the run used and its FR ``layouts``
    (nothing is rebuilt to label them)."""
    if fr:
        stop = sy.n_state - (sy.ring.n_modes + sy.ring.n_residual if ring else 0)
        _fr_history(res, sy, layouts, data, stop=stop)
    if ring:
        _ring_history(res, sy, data, prefix="ring_" if fr else "")
        scalars["n_ring_modes"] = (int(sy.ring.n_modes), "1")


def stream_derived() -> dict:
    """The full-length datasets of :meth:`SimulationResult.case_data` computed from each block
    of a streamed history (railvti.runner.stream), so that a streamed case stores what an
    in-memory one does."""

    def col(src: str, name: str):
        return lambda b, a: b[src][:, list(a["q"]["dof_names"]).index(name)]

    def ws_y(b, a):
        names = list(a["q"]["dof_names"])
        return b["q"][:, [names.index(f"ws{w + 1}_y") for w in range(b["wheel"].shape[-1])]]

    out = {"y_ws1": col("q", "ws1_y"), "vy_ws1": col("v", "ws1_y"), "ws_y": ws_y}
    out.update({f"wheel_{n}": (lambda b, a, i=i: b["wheel"][:, i]) for i, n in enumerate(WHEEL_OUTPUTS)})
    return out


def patch_datasets(pt, data: dict, scalars: dict) -> None:
    """The leading wheelset's right contact patch (FASTSIM on the Hertz ellipse, or the BEM
    fields with contact='bem')."""
    for name, unit in (
        ("x", "m"),
        ("y", "m"),
        ("pressure", "Pa"),
        ("tx", "Pa"),
        ("ty", "Pa"),
        ("power_density", "W/m^2"),
    ):
        data[f"patch_{name}"] = (
            np.asarray(getattr(pt, name)),
            unit,
            {
                "axes": ["x (rolling)", "y (lateral, contact frame)"],
                "wheel": "right wheel of the leading wheelset",
            },
        )
    scalars["patch_power"] = (float(pt.power), "W")
    scalars["patch_a"] = (float(pt.a), "m")
    scalars["patch_b"] = (float(pt.b), "m")
