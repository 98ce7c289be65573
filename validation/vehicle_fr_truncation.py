"""Model FR, centred running at 200 km/h: cost against error of the mode selection (issue 14
item 4), and the time step's order.

    .venv/bin/python validation/vehicle_fr_truncation.py            # all parts (~20 min, loaded)
    .venv/bin/python validation/vehicle_fr_truncation.py hertz      # mode grid, Hertz + Kalker
    .venv/bin/python validation/vehicle_fr_truncation.py timing     # 2 more timings per selection
    .venv/bin/python validation/vehicle_fr_truncation.py bem        # fewer selections, the BEM
    .venv/bin/python validation/vehicle_fr_truncation.py steps      # h .. h/32, with/without residual
    .venv/bin/python validation/vehicle_fr_truncation.py plot       # chart from the saved figures

Each selection (k_max harmonics, modes up to f_max) is run as ``scenarios.centred_running``
runs it: build_fr at the speed (with the residual flexibility of the truncated modes), the
steady state of ``static_equilibrium``, then ``simulate`` from it at the scenario's default
step (1 ms divided until h omega_max <= 2: the step comes with the selection). Measured:

- steady: the relative rim-rail angle change (camber) at each wheel of the steady state
  (``flexible_points.rim_rail_angle_change``; 0.1 s of running moves it by < 1e-13 mrad), mrad;
  with contact='bem' (after 0.01 s of running) also the pressure peak of
  every wheel's patch, MPa. The wheel loads Q of the steady state are the static load in every
  selection (the modes carry no weight): their error there is round-off, so Q is measured
  in the transient below.
- transient: the steady state with the leading wheelset kicked laterally (+0.05 m/s,
  ``KICK``), 0.3 s: max over time and the eight wheels of |camber - camber_ref| (mrad) and
  |Q - Q_ref| (kN), outputs every 1 ms. centred_running has no disturbance argument, so the
  script calls static_equilibrium and simulate itself (the scenario's own steps; checked
  against ``scenarios.centred_running`` for the default selection).
- cost: CPU time of this process per simulated second of the transient run, best of two
  (four with ``timing``; the machine's two cores are shared, so the wall time varies by 3x
  with the others' load; the wall time is printed beside it, and equals the CPU time on an
  unloaded core: the time loop is single-threaded). The build and the static solve are
  printed apart.

The errors are against the richest selection run (``REFERENCE``: k_max 6, f_max 3000 Hz, the
harmonics the residual flexibility covers). The step study runs the default selection's
transient at h, h/2, ... h/32 with tight Newton tolerances: successive differences must fall
by ~4 per halving (Newmark average acceleration, second order) once h omega_max is small.
Because the default step (h omega_max <= 2) is far from that, the mode grid is run twice:
at each selection's default step (what a user pays and gets) and all at the reference's step
0.1 ms (the truncation alone).

Writes validation/figures/vehicle_fr_truncation.png; the measured figures are kept in
/tmp/vehicle_fr_truncation.json (``--json PATH``) so that ``plot`` redraws without running.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.vehicle import systems
from railvti.vehicle import Coach, simulate, static_equilibrium
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.flexible_points import rim_rail_angle_change
from railvti.vehicle.params import speed_m_s
from railvti.vehicle.equilibrium import bem_state
from railvti.wheelset import Wheelset

FIG = Path(__file__).resolve().parent / "figures"
SPEED_KMH = 200.0
K_MAX = (0, 1, 2, 3)
F_MAX = (300.0, 500.0, 800.0, 1500.0, 3000.0)
REFERENCE = (6, 3000.0)
#: The BEM's grid (each point costs a slow static solve, ~25 s): fewer selections.
BEM_GRID = (
    (0, 300.0),
    (0, 800.0),
    (1, 300.0),
    (1, 800.0),
    (2, 300.0),
    (2, 800.0),
    (2, 3000.0),
    (3, 800.0),
    (3, 3000.0),
)
KICK = 0.05  # m/s, leading wheelset's lateral velocity at t = 0
T_TRANSIENT = 0.3  # s
T_STEADY = 0.1  # s
T_BEM = 0.01  # s of BEM running after its steady state
DEFAULT = (2, 800.0)
H_COMMON = 1e-4  # s: every selection at the reference's step (the truncation alone)
STEP_DIVISORS = (1, 2, 4, 8, 16, 32)


class _Setup:
    """The speed, the contact table and the FE wheelset, built once."""

    def __init__(self) -> None:
        self.v = speed_m_s(SPEED_KMH)
        self.table = scenarios.wheel_table()
        self.wheelset = Wheelset()

    def system(self, k_max: int, f_max: float, residual: bool = True):
        t0 = time.perf_counter()
        sy = build_fr(
            Coach(), self.table, self.v, wheelset=self.wheelset, k_max=k_max, f_max=f_max, residual=residual
        )[0]
        return sy, time.perf_counter() - t0


def _n_elastic(sy) -> int:
    """Elastic modal coordinates of one wheelset (the massless residual ones not counted)."""
    return int(np.count_nonzero(np.asarray(sy.modal.mass) > 0) // 4)


def _camber(sy, q: np.ndarray) -> np.ndarray:
    return rim_rail_angle_change(sy, q)


def _kicked(sy, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    qd = qd.copy()
    qd[sy.index("ws1_y")] += KICK
    return qd


def run_selection(
    S: _Setup,
    k_max: int,
    f_max: float,
    h: float | None = None,
    tol: float | None = None,
    rtol: float | None = None,
    repeats: int = 2,
    residual: bool = True,
) -> dict:
    """Steady state, 0.1 s of steady running and the 0.3 s transient of one selection (cost:
    the best of ``repeats`` transient runs)."""
    sy, t_build = S.system(k_max, f_max, residual)
    h = systems.default_step(sy) if h is None else h
    t0 = time.perf_counter()
    q, qd, _ = static_equilibrium(sy, S.v, "hertz-kalker", return_velocity=True)
    t_static = time.perf_counter() - t0
    steady = simulate(sy, S.v, T_STEADY, q0=q, v0=qd, h=h, progress=False)
    wall = cpu = np.inf
    for _ in range(repeats):  # the machine is shared: best of the repeats
        t0, c0 = time.perf_counter(), time.process_time()
        r = simulate(
            sy,
            S.v,
            T_TRANSIENT,
            q0=q,
            v0=_kicked(sy, q, qd),
            h=h,
            output_dt=1e-3,
            progress=False,
            tol=tol,
            rtol=rtol,
        )
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return {
        "k_max": k_max,
        "f_max": f_max,
        "h": h,
        "n_elastic": _n_elastic(sy),
        "f_top": sy.modal.max_frequency() / (2 * np.pi),
        "n_state": sy.n_state,
        "t_build": t_build,
        "t_static": t_static,
        "cost": cpu / T_TRANSIENT,
        "wall": wall / T_TRANSIENT,
        "substepped": int(r.stats["substepped_steps"]),
        "newton_per_step": r.stats["newton_iterations"] / max(r.stats["steps"], 1),
        "static_camber": _camber(sy, q).tolist(),
        "steady_camber": _camber(sy, steady.q[-1]).tolist(),
        "steady_Q": steady.Q[-1].tolist(),
        "t": r.t.tolist(),
        "camber": _camber(sy, r.q).tolist(),
        "Q": r.Q.tolist(),
        "y_ws1": r.y_ws1.tolist(),
    }


def _errors(run: dict, ref: dict) -> dict:
    """Errors of one run against the reference (same output times)."""
    n = min(len(run["t"]), len(ref["t"]))
    cam = np.abs(np.array(run["camber"])[:n] - np.array(ref["camber"])[:n])
    dq = np.abs(np.array(run["Q"])[:n] - np.array(ref["Q"])[:n])
    st = "static_camber" if "static_camber" in run and "static_camber" in ref else "steady_camber"
    return {
        "steady_camber": float(
            np.max(np.abs(np.array(run["steady_camber"]) - np.array(ref["steady_camber"])))
        ),
        "static_camber": float(np.max(np.abs(np.array(run[st]) - np.array(ref[st])))),
        "steady_Q": float(np.max(np.abs(np.array(run["steady_Q"]) - np.array(ref["steady_Q"])))),
        "camber": float(cam.max()),
        "Q": float(dq.max()),
    }


def hertz(S: _Setup, out: dict) -> None:
    print(
        f"centred running {SPEED_KMH:.0f} km/h, model FR, Hertz + Kalker: steady camber and the "
        f"transient after a {KICK} m/s lateral kick of the leading wheelset ({T_TRANSIENT} s)"
    )
    runs = {}
    for km, fm in [REFERENCE] + [(k, f) for k in K_MAX for f in F_MAX]:
        runs[f"{km}/{fm:g}"] = run_selection(S, km, fm)
        r = runs[f"{km}/{fm:g}"]
        print(
            f"  ran k_max {km} / {fm:.0f} Hz: {r['n_elastic']} modes per wheelset, h = "
            f"{r['h'] * 1e3:.3g} ms, {r['cost']:.2f} s CPU per simulated s",
            flush=True,
        )
    out["hertz"] = runs
    print(
        f"the same selections, all at the reference's step h = {H_COMMON * 1e3:g} ms (the truncation alone)"
    )
    fixed = {}
    for km, fm in [REFERENCE] + [(k, f) for k in K_MAX for f in F_MAX]:
        fixed[f"{km}/{fm:g}"] = run_selection(S, km, fm, h=H_COMMON, repeats=1)
    out["hertz_common"] = fixed
    # the scenario itself, default selection: the script's steps reproduce it
    c = scenarios.centred_running(
        speed_kmh=SPEED_KMH,
        variant="FR",
        duration=T_STEADY,
        k_max=DEFAULT[0],
        f_max=DEFAULT[1],
        progress=False,
    )
    d = runs[f"{DEFAULT[0]}/{DEFAULT[1]:g}"]
    out["scenario_check"] = {
        "camber": float(np.max(np.abs(c.rim_angle - np.array(d["steady_camber"])))),
        "Q": float(np.max(np.abs(c.Q - np.array(d["steady_Q"])))),
    }


def print_hertz(out: dict, part: str = "hertz") -> None:
    runs = out[part]
    if part != "hertz":
        print(f"\nall selections at h = {H_COMMON * 1e3:g} ms (the truncation alone):")
    ref = runs[f"{REFERENCE[0]}/{REFERENCE[1]:g}"]
    print(
        f"\nreference k_max {REFERENCE[0]} / {REFERENCE[1]:.0f} Hz: steady camber left/right, "
        "leading wheelset "
        + " / ".join(f"{1e3 * ref['steady_camber'][w][0]:+.4f}" for w in (0, 1))
        + " mrad; Q "
        + " / ".join(f"{ref['steady_Q'][w][0]:.1f}" for w in (0, 1))
        + " N"
    )
    sc = out.get("scenario_check")
    if sc and part == "hertz":
        print(
            f"scenarios.centred_running (default selection) against the script's steps: camber "
            f"{sc['camber']:.1e} rad, Q {sc['Q']:.1e} N"
        )
    print(
        f"{'k_max':>5s} {'f_max':>6s} {'modes':>5s} {'top Hz':>7s} {'h ms':>6s} {'build s':>7s} "
        f"{'static s':>8s} {'CPU s':>6s} {'wall s':>6s} {'Nwt/st':>6s} {'steady cam':>10s} "
        f"{'cam err':>8s} {'Q err':>7s}"
    )
    print(
        f"{'':>5s} {'Hz':>6s} {'/ws':>5s} {'':>7s} {'':>6s} {'':>7s} {'':>8s} {'/sim s':>6s} "
        f"{'/sim s':>6s} {'':>6s} {'err, mrad':>10s} {'mrad':>8s} {'kN':>7s}"
    )
    for _key, r in runs.items():
        e = _errors(r, ref)
        print(
            f"{r['k_max']:5d} {r['f_max']:6.0f} {r['n_elastic']:5d} {r['f_top']:7.0f} "
            f"{r['h'] * 1e3:6.3f} {r['t_build']:7.1f} {r['t_static']:8.2f} {r['cost']:6.2f} "
            f"{r['wall']:6.2f} "
            f"{r['newton_per_step']:6.2f} {e['static_camber'] * 1e3:10.2e} "
            f"{e['camber'] * 1e3:8.4f} {e['Q'] / 1e3:7.3f}"
            + ("  (reference)" if r is ref else "")
            + (f"  {r['substepped']} sub-stepped" if r["substepped"] else "")
        )
    drift = [
        np.abs(np.array(r["steady_camber"]) - np.array(r["static_camber"])).max()
        for r in runs.values()
        if "static_camber" in r
    ]
    if drift:
        print(
            f"(0.1 s of steady running moves the camber from the static solve by at most "
            f"{max(drift) * 1e3:.1e} mrad: the steady errors are the selections', not the run's)"
        )
    amp = np.ptp(np.array(ref["camber"]), axis=0).max() * 1e3
    qamp = np.ptp(np.array(ref["Q"]), axis=0).max() / 1e3
    print(
        f"(reference transient: camber range {amp:.3f} mrad, Q range {qamp:.2f} kN at the most excited wheel)"
    )


def bem(S: _Setup, out: dict) -> None:
    print(
        f"\ncentred running {SPEED_KMH:.0f} km/h, model FR, BEM 0.75 mm: steady state, then "
        f"{T_BEM} s of running"
    )
    runs = {}
    for km, fm in [REFERENCE] + list(BEM_GRID):
        sy, t_build = S.system(km, fm)
        h = systems.default_step(sy)
        with bem_state(sy) as st:
            t0 = time.perf_counter()
            # the defaults (1e-11, 60 iterations) stop early with the residual flexibility
            # (docs/vehicle_integrator.md, "What FR still needs"): more iterations here
            q, qd, _ = static_equilibrium(sy, S.v, "bem", bem=st, return_velocity=True, tol=1e-9, maxit=200)
            t_static = time.perf_counter() - t0
            t0, c0 = time.perf_counter(), time.process_time()
            r = simulate(sy, S.v, T_BEM, q0=q, v0=qd, h=h, contact="bem", bem=st, progress=False)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        pk = [[r.bem_patches[(w, s)].pressure.max() for w in range(4)] for s in (0, 1)]
        runs[f"{km}/{fm:g}"] = {
            "k_max": km,
            "f_max": fm,
            "h": h,
            "t_static": t_static,
            "cost": cpu / T_BEM,
            "wall": wall / T_BEM,
            "p_max": pk,
            "camber": _camber(sy, r.q[-1]).tolist(),
            "Q": r.Q[-1].tolist(),
        }
        print(
            f"  ran k_max {km} / {fm:.0f} Hz: static {t_static:.1f} s, {cpu / T_BEM:.0f} s CPU per "
            f"simulated s, p_max leading left/right {pk[0][0] / 1e6:.2f} / "
            f"{pk[1][0] / 1e6:.2f} MPa",
            flush=True,
        )
    out["bem"] = runs


def print_bem(out: dict) -> None:
    runs = out["bem"]
    ref = runs[f"{REFERENCE[0]}/{REFERENCE[1]:g}"]
    print(
        f"\n{'k_max':>5s} {'f_max':>6s} {'h ms':>6s} {'static s':>8s} {'CPU/s':>8s} "
        f"{'wall/s':>7s} {'p_max L/R, MPa':>16s} {'p err MPa':>9s} {'cam mrad':>9s} "
        f"{'cam err':>8s} {'Q err N':>8s}"
    )
    for r in runs.values():
        pe = np.abs(np.array(r["p_max"]) - np.array(ref["p_max"])).max()
        ce = np.abs(np.array(r["camber"]) - np.array(ref["camber"])).max()
        qe = np.abs(np.array(r["Q"]) - np.array(ref["Q"])).max()
        print(
            f"{r['k_max']:5d} {r['f_max']:6.0f} {r['h'] * 1e3:6.3f} {r['t_static']:8.1f} "
            f"{r['cost']:8.0f} {r['wall']:7.0f} "
            f"{r['p_max'][0][0] / 1e6:7.2f}/{r['p_max'][1][0] / 1e6:7.2f} "
            f"{pe / 1e6:9.3f} {r['camber'][0][0] * 1e3:+9.4f} {ce * 1e3:8.1e} {qe:8.1e}"
            + ("  (reference)" if r is ref else "")
        )


def steps(S: _Setup, out: dict) -> None:
    sy, _ = S.system(*DEFAULT)
    h0 = systems.default_step(sy)
    for residual, key in ((True, "steps"), (False, "steps_no_residual")):
        print(
            f"\ntime step, default selection k_max {DEFAULT[0]} / {DEFAULT[1]:.0f} Hz"
            + ("" if residual else " WITHOUT the residual flexibility")
            + f", the kicked transient ({T_TRANSIENT} s), Newton tol 1e-13 m, rtol 1e-9"
        )
        runs = []
        for m in STEP_DIVISORS:
            r = run_selection(S, *DEFAULT, h=h0 / m, tol=1e-13, rtol=1e-9, repeats=1, residual=residual)
            runs.append({k: r[k] for k in ("h", "cost", "substepped", "camber", "Q", "y_ws1", "t")})
            print(
                f"  ran h = {h0 / m * 1e3:.4g} ms ({r['cost']:.2f} s CPU per simulated s, "
                f"{r['substepped']} sub-stepped)",
                flush=True,
            )
        out[key] = runs


def timing(S: _Setup, out: dict) -> None:
    """More repeats of every selection's transient at its default step (the cost is the best
    CPU time of all its runs)."""
    print("\ntiming: two more runs of each selection at its default step", flush=True)
    for r in out["hertz"].values():
        again = run_selection(S, r["k_max"], r["f_max"], repeats=2)
        r["cost"] = min(r["cost"], again["cost"])
        r["static_camber"] = again["static_camber"]
        r["wall"] = min(r["wall"], again["wall"])


def print_steps(out: dict, key: str = "steps") -> None:
    runs = out[key]
    print("\n" + ("with" if key == "steps" else "WITHOUT") + " the residual flexibility:")
    print(
        f"{'h, ms':>8s} {'d camber, mrad':>15s} {'ratio':>6s} {'d Q, N':>9s} {'ratio':>6s} "
        f"{'d y_ws1, um':>12s} {'ratio':>6s} {'camber vs finest':>17s} {'Q vs finest':>12s}"
    )
    prev = None
    fin = runs[-1]
    for a, b in zip(runs[:-1], runs[1:]):
        d = [np.abs(np.array(a[k]) - np.array(b[k])).max() for k in ("camber", "Q", "y_ws1")]
        dref = np.abs(np.array(a["camber"]) - np.array(fin["camber"])).max()
        qref = np.abs(np.array(a["Q"]) - np.array(fin["Q"])).max()
        rat = ["" if prev is None else f"{p / x:6.2f}" for p, x in zip(prev or d, d)]
        print(
            f"{a['h'] * 1e3:8.4f} {d[0] * 1e3:15.3e} {rat[0]:>6s} {d[1]:9.3e} {rat[1]:>6s} "
            f"{d[2] * 1e6:12.3e} {rat[2]:>6s} {dref * 1e3:17.3e} {qref:12.3e}"
        )
        prev = d
    print(
        "(d: max over time and wheels of the change from h to h/2, mrad, N, um; ratio: the "
        "previous row's d over this one's, 4 for second order; vs finest: the error against "
        f"h = {fin['h'] * 1e3:.4g} ms, mrad and N)"
    )


def _curves(ax, rr: dict, rf: dict, key: str, scale: float, xkey: str, colors, bem: bool) -> None:
    """One curve per k_max: error of ``key`` against ``xkey`` ('cost' or 'n_elastic')."""
    from matplotlib.ticker import FormatStrFormatter, NullFormatter

    for i, km in enumerate(K_MAX):
        pts = sorted((r for r in rr.values() if r["k_max"] == km and r is not rf), key=lambda r: r["f_max"])
        if not pts:
            continue
        if bem:
            err = [np.abs(np.array(r[key]) - np.array(rf[key])).max() * scale for r in pts]
        else:
            err = [_errors(r, rf)[key] * scale for r in pts]
        x = [r[xkey] for r in pts]
        ax.loglog(x, err, "o-", color=colors[i], label=f"k_max = {km}", ms=4)
        for r, c, e in zip(pts, x, err):
            ax.annotate(
                f"{r['f_max']:.0f}",
                (c, e),
                textcoords="offset points",
                xytext=(3, 3),
                fontsize=6.5,
                color=colors[i],
            )
    xs = [r[xkey] for r in rr.values()]
    ticks = (
        (2, 3, 5, 10, 20, 30, 50, 80) if xkey == "n_elastic" else (0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500)
    )
    ax.set_xticks([t for t in ticks if 0.9 * min(xs) <= t <= 1.1 * max(xs)])
    ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, title="labels: f_max, Hz", title_fontsize=7)


def plot(out: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    ref_key = f"{REFERENCE[0]}/{REFERENCE[1]:g}"
    cost_label = "CPU time per simulated second, s"
    panels = [
        (
            "hertz",
            "camber",
            1e3,
            "cost",
            "transient: max |camber error|, mrad",
            "(a) each selection at its default step",
        ),
        (
            "hertz",
            "Q",
            1e-3,
            "cost",
            "transient: max |Q error|, kN",
            "(b) each selection at its default step",
        ),
        (
            "hertz",
            "static_camber",
            1e3,
            "cost",
            "steady: max |camber error|, mrad",
            "(c) steady state: camber 0.53 mrad, all within 0.06 %",
        ),
        (
            "hertz_common",
            "camber",
            1e3,
            "n_elastic",
            "transient: max |camber error|, mrad",
            f"(d) all at h = {H_COMMON * 1e3:g} ms: truncation alone",
        ),
        (
            "hertz_common",
            "Q",
            1e-3,
            "n_elastic",
            "transient: max |Q error|, kN",
            f"(e) all at h = {H_COMMON * 1e3:g} ms: truncation alone",
        ),
        (
            "bem",
            "p_max",
            1e-6,
            "cost",
            "BEM steady: max |pressure peak error|, MPa",
            "(f) BEM 0.75 mm, steady: p_max 672.2 MPa, all within 0.005 %",
        ),
    ]
    panels = [p for p in panels if p[0] in out]
    ncol = 3
    nrow = (len(panels) + ncol - 1) // ncol
    fig, axs = plt.subplots(nrow, ncol, figsize=(4.3 * ncol, 3.9 * nrow), squeeze=False)
    for ax, (part, key, sc, xkey, label, title) in zip(axs.ravel(), panels):
        rr = out[part]
        _curves(ax, rr, rr[ref_key], key, sc, xkey, colors, part == "bem")
        ax.set_xlabel(
            "elastic modal coordinates per wheelset"
            if xkey == "n_elastic"
            else cost_label + (" (BEM, 0.01 s runs)" if part == "bem" else "")
        )
        ax.set_ylabel(label, fontsize=8)
        ax.set_title(title, fontsize=8)
    for ax in axs.ravel()[len(panels) :]:
        ax.axis("off")
    fig.suptitle(
        f"Centred running {SPEED_KMH:.0f} km/h, model FR, Hertz + Kalker ((f): BEM "
        f"0.75 mm): error of the mode selection against k_max {REFERENCE[0]} / "
        f"{REFERENCE[1]:.0f} Hz\ntransient: {T_TRANSIENT:g} s after a {KICK} m/s "
        "lateral kick of the leading wheelset, max over time and the 8 wheels",
        fontsize=10,
    )
    fig.tight_layout()
    FIG.mkdir(exist_ok=True)
    path = FIG / "vehicle_fr_truncation.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def main(argv: list[str]) -> None:
    jpath = Path("/tmp/vehicle_fr_truncation.json")
    if "--json" in argv:
        i = argv.index("--json")
        jpath = Path(argv[i + 1])
        argv = argv[:i] + argv[i + 2 :]
    out = json.loads(jpath.read_text()) if jpath.exists() else {}
    parts = argv or ["hertz", "timing", "bem", "steps"]
    tasks = {"hertz": hertz, "timing": timing, "bem": bem, "steps": steps}
    S = _Setup() if any(p in tasks for p in parts) else None
    for p in parts:
        if p in tasks:
            tasks[p](S, out)
            jpath.write_text(json.dumps(out))
    if "hertz" in out:
        print_hertz(out)
    if "hertz_common" in out:
        print_hertz(out, "hertz_common")
    if "bem" in out:
        print_bem(out)
    for key in ("steps", "steps_no_residual"):
        if key in out:
            print_steps(out, key)
    if "hertz" in out:
        print(f"wrote {plot(out)}")


if __name__ == "__main__":
    main(sys.argv[1:])
