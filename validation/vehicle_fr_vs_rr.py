"""FR against RR side by side: centred running at 200 km/h (issue 14 item 6, the paper's
Figs 11-15).

    .venv/bin/python validation/vehicle_fr_vs_rr.py            # ~2 min (the FR BEM statics ~30-50 s)
    .venv/bin/python validation/vehicle_fr_vs_rr.py --replot   # tables and charts from the last run
    .venv/bin/python validation/vehicle_fr_vs_rr.py --model FF # FF (flexible wheelsets on the
                                                               # ring track) against RR instead
    .venv/bin/python validation/vehicle_fr_vs_rr.py --model RF # RF (rigid wheelsets, ring)

Both models on the same coach, S1002 / UIC60 1:40, 200 km/h; model FR at the default mode
selection of ``scenarios`` (k_max 2, f_max 800 Hz, with the truncated modes' residual
flexibility).

- Hertz + Kalker: ``scenarios.centred_running(speed_kmh=200, model=..., duration=1)``: Q and
  Y per wheel, the rim-rail angle at each wheel.
- BEM 0.75 mm: the steady state of ``static_equilibrium`` with more Newton iterations than
  its defaults (model FR with the residual converges only linearly there, so
  ``centred_running(model='FR', contact='bem')`` stops early: docs/vehicle_integrator.md,
  "What FR still needs"; RR gets the same settings), then 0.02 s of running with the BEM as
  ``centred_running`` does: the patch pressure, tractions and friction power density of the
  leading wheelset's two wheels, straight from the BEM (``SimulationResult.bem_patches``).

The rim-rail angle is the angle between the wheel's mid-plane and the rail's axis: the rail
inclination atan(1/40) = 24.99 mrad, plus the wheelset's roll against its track element
(sign: the tread's inner edge rising), plus in FR the rim's camber change
(``flexible_points.rim_camber_change``).

Writes validation/figures/vehicle_fr_vs_rr_wheels.png (Q, Y and the rim-rail angle at the
eight wheels), vehicle_fr_vs_rr_patches.png (the leading wheelset's patches) and
vehicle_fr_vs_rr_sections.png (the pressure along the patch's lateral centre line and the
friction power per unit width).
"""

from __future__ import annotations

import pickle
import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.vehicle import systems
from railvti.vehicle import simulate, static_equilibrium
from railvti.vehicle.flexible_points import rim_camber_change
from railvti.vehicle.params import speed_m_s
from railvti.vehicle.equilibrium import bem_state

FIG = Path(__file__).resolve().parent / "figures"
SPEED_KMH = 200.0
K_MAX, F_MAX = 2, 800.0  # scenarios' default selection for model FR
T_BEM = 0.02  # s of BEM running after the steady state
RAIL_ANGLE = float(np.arctan(1.0 / 40.0))
SIDES = ("left", "right")
#: The flexible model beside RR: FR (flexible wheelsets) or FF (also the ring track), --model.
FLEX = "FR"


def _flex_label() -> str:
    """The flexible model beside RR, with its wheelsets' mode selection where it has one."""
    return f"{FLEX} (k_max {K_MAX} / {F_MAX:.0f} Hz)" if FLEX in ("FR", "FF") else FLEX


def _system(model: str):
    if model in ("FR", "FF"):
        return scenarios.coach_system(model, speed_kmh=SPEED_KMH, k_max=K_MAX, f_max=F_MAX)
    if model == "RF":
        return scenarios.coach_system("RF", speed_kmh=SPEED_KMH)
    return scenarios.coach_system("RR")


def _relative_roll(sy, q: np.ndarray, t: float) -> np.ndarray:
    """(2, 4): each wheel's rigid rim-rail angle change, rad: the wheelset's roll against its
    track element (on the ring: against the rail head's roll under the wheel at time t),
    signed as rim_camber_change (the tread's inner edge rising): a roll about +x lifts
    the left wheel's outer edge (-roll) and the right wheel's inner edge (+roll)."""
    ws = np.array([q[sy.index(f"ws{i}_roll")] for i in (1, 2, 3, 4)])
    if getattr(sy, "ring", None) is not None:
        rail = sy.rail_deflection(np.array([t]), q[None])[0][2]  # (2 wheels, 4)
        rel = ws[None, :] - rail
    else:
        rel = (ws - np.array([q[sy.index(f"track{i}_roll")] for i in (1, 2, 3, 4)]))[None, :]
    return rel * np.array([-1.0, 1.0])[:, None]


def hertz_runs() -> dict:
    out = {}
    for model in ("RR", FLEX):
        t0 = time.perf_counter()
        kw = {"k_max": K_MAX, "f_max": F_MAX} if model in ("FR", "FF") else {}
        c = scenarios.centred_running(speed_kmh=SPEED_KMH, variant=model, duration=1.0, progress=False, **kw)
        sy = _system(model)
        cam = c.rim_camber if c.rim_camber is not None else np.zeros((2, 4))
        out[model] = {
            "Q": c.Q,
            "Y": c.Y,
            "camber": cam,
            "rigid": _relative_roll(sy, c.run.q[-1], float(c.run.t[-1])),
            "wall": time.perf_counter() - t0,
        }
    return out


def bem_runs() -> dict:
    out = {}
    v = speed_m_s(SPEED_KMH)
    for model in ("RR", FLEX):
        sy = _system(model)
        h = systems.default_step(sy)
        t0 = time.perf_counter()
        with bem_state(sy) as st:
            q, qd, _ = static_equilibrium(sy, v, "bem", bem=st, return_velocity=True, tol=1e-9, maxit=200)
            t_static = time.perf_counter() - t0
            r = simulate(sy, v, T_BEM, q0=q, v0=qd, h=h, contact="bem", bem=st, progress=False)
        cam = rim_camber_change(sy, r.q[-1]) if model in ("FR", "FF") else np.zeros((2, 4))
        out[model] = {
            "Q": r.Q[-1],
            "Y": r.Y[-1],
            "camber": cam,
            "rigid": _relative_roll(sy, r.q[-1], float(r.t[-1])),
            "patches": [r.bem_patches[(0, w)] for w in (0, 1)],
            "t_static": t_static,
            "wall": time.perf_counter() - t0,
            "rtf": r.stats["real_time_factor"],
        }
    return out


def _angle(d: dict) -> np.ndarray:
    return RAIL_ANGLE + d["rigid"] + d["camber"]


def _two_maxima(p, wheel: int, field: str = "pressure") -> tuple[tuple[float, float], tuple[float, float]]:
    """The patch's two maxima across the track of a field ('pressure' or 'power_density'):
    (value, y) of the flange-side maximum and of the other (field-side), from the lateral
    profile of max over x of the field (its two largest local maxima)."""
    prof = getattr(p, field).max(axis=0)
    y = p.y[0]
    j = [
        k
        for k in range(1, prof.size - 1)
        if prof[k] > 0 and prof[k] >= prof[k - 1] and prof[k] >= prof[k + 1]
    ]
    j = sorted(sorted(j, key=lambda k: -prof[k])[:2], key=lambda k: y[k])
    if wheel == 1:
        j = j[::-1]  # the right wheel's flange side is +y
    flange, other = (j + j)[:2]
    return (prof[flange], y[flange]), (prof[other], y[other])


def _patch_row(p, wheel: int) -> dict:
    """Scalar figures of one BEM patch."""
    inside = p.pressure > 0
    k = np.unravel_index(np.argmax(p.pressure), p.pressure.shape)
    da = (p.x[1, 0] - p.x[0, 0]) * (p.y[0, 1] - p.y[0, 0])
    (pf, yf), (po, yo) = _two_maxima(p, wheel)
    (qf, zf), (qo, zo) = _two_maxima(p, wheel, "power_density")
    return {
        "fn": p.fn,
        "p_max": p.pressure.max(),
        "y_pmax": p.y[k],
        "x_pmax": p.x[k],
        "p_flange": pf,
        "y_flange": yf,
        "p_other": po,
        "y_other": yo,
        "y_centroid": float((p.pressure * p.y).sum() / p.pressure.sum()),
        "area": inside.sum() * da,
        "a": p.a,
        "b": p.b,
        "fx": p.fx,
        "fy": p.fy,
        "power": p.power,
        "pd_max": p.power_density.max(),
        "pd_flange": qf,
        "y_pd_flange": zf,
        "pd_other": qo,
        "y_pd_other": zo,
        "t_max": np.hypot(p.tx, p.ty).max(),
    }


def print_tables(hz: dict, bm: dict) -> None:
    print(f"centred running {SPEED_KMH:.0f} km/h; {_flex_label()}, with the residual")
    for name, d in (("Hertz + Kalker, 1 s", hz), (f"BEM 0.75 mm, {T_BEM} s", bm)):
        print(f"\n{name}: per wheelset (1 leading) left / right")
        for model in ("RR", FLEX):
            x = d[model]
            a = _angle(x)
            print(
                f"  {model} Q, kN:             "
                + "  ".join(f"{x['Q'][0, i] / 1e3:8.3f}/{x['Q'][1, i] / 1e3:8.3f}" for i in range(4))
            )
            print(
                f"  {model} Y, N:              "
                + "  ".join(f"{x['Y'][0, i]:8.1f}/{x['Y'][1, i]:8.1f}" for i in range(4))
            )
            print(
                f"  {model} rim-rail angle, mrad: "
                + "  ".join(f"{a[0, i] * 1e3:7.3f}/{a[1, i] * 1e3:7.3f}" for i in range(4))
            )
            print(
                f"  {model}   of it rigid roll, mrad: "
                + "  ".join(f"{x['rigid'][0, i] * 1e3:+.1e}/{x['rigid'][1, i] * 1e3:+.1e}" for i in range(4))
                + f"; camber change {x['camber'].min() * 1e3:+.4f}..{x['camber'].max() * 1e3:+.4f}"
            )
        dq = np.abs(d[FLEX]["Q"] - d["RR"]["Q"]).max()
        print(f"  max |Q_{FLEX} - Q_RR| = {dq:.2e} N")
    print(
        f"\nBEM timing: RR static {bm['RR']['t_static']:.1f} s, {FLEX} static {bm[FLEX]['t_static']:.1f} s; "
        f"RTF of the {T_BEM} s run RR {bm['RR']['rtf']:.0f}, {FLEX} {bm[FLEX]['rtf']:.0f}"
    )
    rows = {m: [_patch_row(p, w) for w, p in enumerate(bm[m]["patches"])] for m in ("RR", FLEX)}
    print(
        "\nBEM patches, leading wheelset (contact frame: x rolling + forward, y track lateral + left; "
        "flange side: left wheel -y, right wheel +y)"
    )
    print(
        f"{'':24s} "
        + " ".join(f"{m + ' ' + s:>10s}" for s in SIDES for m in ("RR", FLEX))
        + f" {FLEX + '/RR-1 L':>10s} {FLEX + '/RR-1 R':>10s}"
    )
    for key, sc, unit in (
        ("fn", 1e-3, "kN"),
        ("p_max", 1e-6, "MPa"),
        ("y_pmax", 1e3, "mm"),
        ("p_flange", 1e-6, "MPa"),
        ("y_flange", 1e3, "mm"),
        ("p_other", 1e-6, "MPa"),
        ("y_other", 1e3, "mm"),
        ("y_centroid", 1e3, "mm"),
        ("a", 1e3, "mm"),
        ("b", 1e3, "mm"),
        ("area", 1e6, "mm^2"),
        ("fx", 1.0, "N"),
        ("fy", 1.0, "N"),
        ("t_max", 1e-6, "MPa"),
        ("power", 1.0, "W"),
        ("pd_max", 1e-6, "W/mm^2"),
        ("pd_flange", 1e-6, "W/mm^2"),
        ("y_pd_flange", 1e3, "mm"),
        ("pd_other", 1e-6, "W/mm^2"),
        ("y_pd_other", 1e3, "mm"),
    ):
        vals = [rows[m][w][key] for w in (0, 1) for m in ("RR", FLEX)]
        rel = [
            rows[FLEX][w][key] / rows["RR"][w][key] - 1 if not key.startswith("y_") else float("nan")
            for w in (0, 1)
        ]
        print(
            f"{key + ', ' + unit:>24s} "
            + " ".join(f"{v * sc:10.3f}" for v in vals)
            + " "
            + " ".join(f"{100 * r:+9.1f}%" if np.isfinite(r) else f"{'':>10s}" for r in rel)
        )
    a_rr, a_fr = _angle(hz["RR"])[:, 0], _angle(hz[FLEX])[:, 0]
    b_rr, b_fr = _angle(bm["RR"])[:, 0], _angle(bm[FLEX])[:, 0]
    l_rr, l_fr = rows["RR"][0], rows[FLEX][0]
    print("\nthe paper's findings for centred running beside ours (leading wheelset, left wheel)")
    print(
        f"  camber: paper 25 -> ~26 mrad; ours Hertz+Kalker {a_rr[0] * 1e3:.2f} -> {a_fr[0] * 1e3:.2f}"
        f" mrad, BEM {b_rr[0] * 1e3:.2f} -> {b_fr[0] * 1e3:.2f} mrad"
    )
    print(
        f"  left pressure maximum shrinks: ours, the flange-side maximum of the patch (the left one "
        f"in the left wheel's chart) {l_rr['p_flange'] / 1e6:.1f} -> {l_fr['p_flange'] / 1e6:.1f} MPa "
        f"({100 * (l_fr['p_flange'] / l_rr['p_flange'] - 1):+.1f} %), the other maximum "
        f"{l_rr['p_other'] / 1e6:.1f} -> {l_fr['p_other'] / 1e6:.1f} MPa; the patch's maximum "
        f"{l_rr['p_max'] / 1e6:.1f} -> {l_fr['p_max'] / 1e6:.1f} MPa "
        f"({100 * (l_fr['p_max'] / l_rr['p_max'] - 1):+.1f} %)"
    )
    print(
        f"  friction power changes: ours {l_rr['power']:.2f} -> {l_fr['power']:.2f} W "
        f"({100 * (l_fr['power'] / l_rr['power'] - 1):+.1f} %), peak density "
        f"{l_rr['pd_max'] / 1e6:.3f} -> {l_fr['pd_max'] / 1e6:.3f} W/mm^2"
    )
    for w, side in enumerate(SIDES):
        a, b = rows["RR"][w], rows[FLEX][w]
        print(
            f"  friction power density maxima, {side} wheel (paper RR 13 / 7, FF 4 / 5 W/mm^2, "
            f"flange / field side): RR {a['pd_flange'] / 1e6:.2f} / {a['pd_other'] / 1e6:.2f}, "
            f"{FLEX} {b['pd_flange'] / 1e6:.2f} / {b['pd_other'] / 1e6:.2f} W/mm^2 "
            f"({100 * (b['pd_flange'] / a['pd_flange'] - 1):+.0f} % / "
            f"{100 * (b['pd_other'] / a['pd_other'] - 1):+.0f} %; paper -69 % / -29 %)"
        )


def _crop(patches) -> tuple[slice, slice]:
    """Index ranges covering every patch's contact area, with a margin of 2 elements."""
    inside = np.zeros_like(patches[0].pressure, dtype=bool)
    for p in patches:
        inside |= p.pressure > 0
    i, j = np.nonzero(inside.any(axis=1))[0], np.nonzero(inside.any(axis=0))[0]
    n0, n1 = inside.shape
    return (slice(max(i[0] - 2, 0), min(i[-1] + 3, n0)), slice(max(j[0] - 2, 0), min(j[-1] + 3, n1)))


def plot_wheels(hz: dict, bm: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(13.5, 4.0))
    xs = np.arange(8)
    labels = [f"ws{i + 1} {s[0].upper()}" for i in range(4) for s in SIDES]
    style = {
        ("RR", "hk"): ("s", "C0", "RR, Hertz + Kalker"),
        (FLEX, "hk"): ("o", "C3", f"{FLEX}, Hertz + Kalker"),
        ("RR", "bem"): ("s", "C2", "RR, BEM"),
        (FLEX, "bem"): ("o", "C1", f"{FLEX}, BEM"),
    }
    for (model, c), (mk, col, lab) in style.items():
        d = (hz if c == "hk" else bm)[model]
        off = (-0.15 if c == "hk" else 0.15) + (-0.05 if model == "RR" else 0.05)
        for a, val, sc in ((ax[0], d["Q"], 1e-3), (ax[1], d["Y"], 1.0), (ax[2], _angle(d), 1e3)):
            a.plot(
                xs + off,
                val.T.ravel() * sc,
                mk,
                color=col,
                label=lab,
                ms=6,
                mfc="none" if model == "RR" else col,
            )
    ax[0].set_ylabel("Q (vertical wheel force), kN")
    ax[1].set_ylabel("Y (lateral wheel force, track y + left), N")
    ax[2].set_ylabel("rim-rail angle, mrad")
    ax[2].axhline(
        RAIL_ANGLE * 1e3,
        color="0.5",
        lw=0.8,
        ls="--",
        label=f"rail inclination 1:40 ({RAIL_ANGLE * 1e3:.2f} mrad)",
    )
    dq = max(np.abs(hz[FLEX]["Q"] - hz["RR"]["Q"]).max(), np.abs(bm[FLEX]["Q"] - bm["RR"]["Q"]).max())
    q0 = float(np.mean(hz["RR"]["Q"])) / 1e3
    ax[0].set_ylim(q0 - 1.0, q0 + 1.0)  # sub-newton differences are not drawn as signal
    ax[0].ticklabel_format(axis="y", useOffset=False)
    ax[0].set_title(f"Q: {FLEX} - RR within {dq:.2g} N", fontsize=9)
    ax[1].set_title("Y: lateral wheel force per wheel", fontsize=9)
    ax[2].set_title("rim-rail angle: rail 1:40 + roll + rim camber", fontsize=9)
    for a in ax:
        a.set_xticks(xs)
        a.set_xticklabels(labels, fontsize=7, rotation=45)
        a.grid(alpha=0.3)
    ax[2].legend(fontsize=7, loc="center right")
    fig.suptitle(
        f"Centred running {SPEED_KMH:.0f} km/h, models RR and {_flex_label()}, "
        "Hertz + Kalker and BEM 0.75 mm: the eight wheels (L left, R right)",
        fontsize=10,
    )
    fig.tight_layout()
    path = FIG / f"vehicle_{FLEX.lower()}_vs_rr_wheels.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def plot_patches(bm: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pats = [(m, w, bm[m]["patches"][w]) for w in (0, 1) for m in ("RR", FLEX)]
    si, sj = _crop([p for _, _, p in pats])
    fields = (
        ("pressure", lambda p: p.pressure / 1e6, "pressure, MPa"),
        ("traction", lambda p: np.hypot(p.tx, p.ty) / 1e6, "|traction|, MPa (arrows: direction)"),
        ("power", lambda p: p.power_density / 1e6, "friction power density, W/mm^2"),
    )
    vmax = [max(f(p)[si, sj].max() for _, _, p in pats) for _, f, _ in fields]
    fig, ax = plt.subplots(4, 3, figsize=(12.0, 7.6), sharex=True, sharey=True, layout="constrained")
    for r, (m, w, p) in enumerate(pats):
        x, y = p.x[si, sj] * 1e3, p.y[si, sj] * 1e3
        for c, (name, f, _lab) in enumerate(fields):
            a = ax[r, c]
            val = np.ma.masked_where(p.pressure[si, sj] <= 0, f(p)[si, sj])
            a.pcolormesh(y, x, val, shading="nearest", cmap="viridis", vmin=0, vmax=vmax[c])
            if name == "traction":
                k = (slice(None, None, 3), slice(None, None, 3))
                out = p.pressure[si, sj][k] <= 0
                a.quiver(
                    y[k],
                    x[k],
                    np.ma.masked_where(out, p.ty[si, sj][k]),
                    np.ma.masked_where(out, p.tx[si, sj][k]),
                    color="w",
                    width=0.003,
                )
            a.set_aspect("equal")
            a.set_title(
                f"{m}, {SIDES[w]} wheel: max {f(p).max():.3g}"
                + (f", total {p.power:.1f} W" if name == "power" else ""),
                fontsize=8,
            )
            if r == 3:
                a.set_xlabel("y (track lateral, + left), mm", fontsize=8)
            if c == 0:
                a.set_ylabel("x, mm", fontsize=8)
    for c in range(3):
        fig.colorbar(ax[0, c].collections[0], ax=ax[:, c], location="bottom", shrink=0.8, label=fields[c][2])
    fig.suptitle(
        f"Centred running {SPEED_KMH:.0f} km/h, BEM 0.75 mm: the leading wheelset's "
        f"patches, RR against {_flex_label()}\none colour scale per "
        "column; x rolling (+ forward), flange side: left wheel -y, right wheel +y",
        fontsize=10,
    )
    path = FIG / f"vehicle_{FLEX.lower()}_vs_rr_patches.png"
    fig.savefig(path, dpi=85)
    plt.close(fig)
    return path


def plot_sections(bm: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11.0, 7.0), sharex=True)
    for w in (0, 1):
        for m, ls in (("RR", "--"), (FLEX, "-")):
            p = bm[m]["patches"][w]
            i0 = int(np.argmin(np.abs(p.x[:, 0])))
            y = p.y[0] * 1e3
            dx = p.x[1, 0] - p.x[0, 0]
            ax[0, w].plot(y, p.pressure[i0] / 1e6, ls, label=f"{m} (x = {p.x[i0, 0] * 1e3:+.2f} mm)")
            # W per mm of width: the density integrated along x
            ax[1, w].plot(y, p.power_density.sum(axis=0) * dx / 1e3, ls, label=f"{m} (total {p.power:.1f} W)")
        ax[0, w].set_title(f"{SIDES[w]} wheel: pressure along the patch's lateral centre line", fontsize=9)
        ax[1, w].set_title(f"{SIDES[w]} wheel: friction power per unit width", fontsize=9)
        ax[0, w].set_ylabel("pressure, MPa")
        ax[1, w].set_ylabel("friction power, W/mm")
        ax[1, w].set_xlabel("y (track lateral, + left), mm; flange side " + ("-y" if w == 0 else "+y"))
        for a in ax[:, w]:
            a.grid(alpha=0.3)
            a.legend(fontsize=8)
    pats = [bm[m]["patches"][w] for m in ("RR", FLEX) for w in (0, 1)]
    _, sj = _crop(pats)
    y = pats[0].y[0] * 1e3
    ax[1, 0].set_xlim(y[sj.start], y[sj.stop - 1])
    fig.suptitle(
        f"Centred running {SPEED_KMH:.0f} km/h, BEM 0.75 mm, leading wheelset: RR against {_flex_label()}",
        fontsize=10,
    )
    fig.tight_layout()
    path = FIG / f"vehicle_{FLEX.lower()}_vs_rr_sections.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def main(argv: list[str]) -> None:
    global FLEX
    if "--model" in argv:
        FLEX = argv[argv.index("--model") + 1]
        if FLEX not in ("FR", "FF", "RF"):
            raise SystemExit(f"--model: FR, FF or RF, not {FLEX}")
    cache = Path(f"/tmp/vehicle_{FLEX.lower()}_vs_rr.pkl")
    if "--replot" in argv and cache.exists():
        hz, bm = pickle.loads(cache.read_bytes())
    else:
        hz = hertz_runs()
        bm = bem_runs()
        cache.write_bytes(pickle.dumps((hz, bm)))
    print_tables(hz, bm)
    FIG.mkdir(exist_ok=True)
    for f in (plot_wheels(hz, bm), plot_patches(bm), plot_sections(bm)):
        print(f"wrote {f}")


if __name__ == "__main__":
    main(sys.argv[1:])
