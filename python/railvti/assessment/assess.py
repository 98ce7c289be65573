"""``assess(result)``: the standards' assessment quantities of one run as an
:class:`~railvti.assessment.table.Assessment` (docs/assessment.md lists each quantity, its
formula, filter, statistic and limit with the source)."""

from __future__ import annotations

import math

import numpy as np

from .. import _checks
from ..errors import InputError
from ..vehicle.params import Coach
from .comfort import n_mv, sperling_wz
from .filters import butterworth_bandpass, butterworth_lowpass
from .forces import (
    en14363_sum_y_limit,
    flange_climb_ratio,
    prudhomme_limit,
    q_limit,
    static_wheel_load,
    track_shifting_force,
    wheel_forces,
)
from .motions import point_acceleration
from .table import Assessment, Row
from .windows import percentile_abs, sampling_rate, sliding_mean, sliding_rms, time_window

__all__ = ["assess", "FORCE_FILTER_HZ", "CARBODY_BAND_HZ", "BOGIE_LOWPASS_HZ", "LIMIT_SOURCES"]

#: EN 14363 / UIC 518 filters (GENSYS's table of UIC 518 / EN 14363 assessment quantities,
#: gensys.se/course/UIC518_tests.html): forces low-pass 20 Hz, carbody 0.4-10 Hz.
FORCE_FILTER_HZ = 20.0
CARBODY_BAND_HZ = (0.4, 10.0)
#: Bogie frame lateral acceleration for its peak value: low-pass 10 Hz (UIC 515 / EN 14363).
BOGIE_LOWPASS_HZ = 10.0
_SIDE = ("left", "right")
_UNVERIFIED = " [quoted, unverified]"
#: The limits' sources (the table's footnotes).
LIMIT_SOURCES = {
    "yq": "EN 14363:2005 / UIC 518: (Y/Q)_2m,lim = 0.8 (curves R >= 250 m; 2 m sliding mean)",
    "nadal": "Nadal 1908: (tan g - mu)/(1 + mu tan g), the run's flange angle and friction",
    "prudhomme": "Prud'homme 1967: Sigma Y_2m <= 10 kN + P0/3 (UIC 518, EN 14363 alpha = 1)",
    "en14363_sy": "EN 14363:2005 (Sigma Y_2m)_lim = alpha (10 + 2 Q0/3) kN, alpha = {alpha:g}",
    "q": "EN 14363:2005 / UIC 518: Q_lim = 90 kN + Q0, capped by speed" + _UNVERIFIED,
    "bogie": "UIC 515 / EN 14363: bogie frame (y..+)_lim = 12 - m+/5 m/s^2 (m+ bogie mass, t)" + _UNVERIFIED,
    "bogie_rms": "EN 14363 instability: (s y..+)_lim = (12 - m+/5)/2 m/s^2, f0 +- 2 Hz, 100 m rms"
    + _UNVERIFIED,
    "sy_rms": "EN 14363 instability: (s Sigma Y)_lim = (Sigma Y_2m)_lim/2 (alpha = 1), f0 +- 2 Hz, 100 m"
    + _UNVERIFIED,
    "car_max": "EN 14363:2005 / UIC 518 ride characteristics: max 3.0 m/s^2 (0.4-10 Hz)" + _UNVERIFIED,
    "car_y_rms": "EN 14363:2005 / UIC 518 ride characteristics: lateral rms 0.5 m/s^2" + _UNVERIFIED,
    "car_z_rms": "EN 14363:2005 / UIC 518 ride characteristics: vertical rms 0.75 m/s^2" + _UNVERIFIED,
}


def _where(w: int, s: int | None = None) -> str:
    return f"ws{w + 1}" + (f" {_SIDE[s]}" if s is not None else "")


def _forces(t, fs, q, y, speed, q0, alpha, nadal, k) -> tuple[list, np.ndarray]:
    """Rows of the force quantities; also the filtered Sigma Y (nt, nw)."""
    lp = butterworth_lowpass(FORCE_FILTER_HZ, source="EN 14363 force filter")
    qf, yf = lp.apply(q, fs), lp.apply(y, fs)
    yq = flange_climb_ratio(yf, qf)
    sy = track_shifting_force(yf)
    rows = []
    w2 = time_window(2.0, speed)
    long_enough = t[k][-1] - t[k][0] >= w2
    if long_enough:
        _, yq2 = sliding_mean(t[k], yq[k], w2, "Y/Q")
        _, sy2 = sliding_mean(t[k], sy[k], w2, "Sigma Y")
        s, w = np.unravel_index(int(np.argmax(yq2.max(axis=0))), yq2.shape[1:])
        rows.append(
            Row(
                "yq_2m",
                "(Y/Q)_2m max, 20 Hz, 2 m sliding mean",
                float(yq2.max()),
                "1",
                0.8,
                LIMIT_SOURCES["yq"],
                _where(w, s),
            )
        )
        ws = int(np.argmax(np.abs(sy2).max(axis=0)))
        sy2max = float(np.abs(sy2).max())
    else:
        note = f"run {t[k][-1] - t[k][0]:.3g} s < 2 m window {w2:.3g} s"
        rows.append(
            Row(
                "yq_2m",
                "(Y/Q)_2m max, 20 Hz, 2 m sliding mean",
                math.nan,
                "1",
                0.8,
                LIMIT_SOURCES["yq"],
                "",
                note,
            )
        )
        ws, sy2max = 0, math.nan
    s, w = np.unravel_index(int(np.argmax(yq[k].max(axis=0))), yq.shape[1:])
    rows.append(
        Row(
            "yq_max",
            "Y/Q max, 20 Hz, against Nadal",
            float(yq[k].max()),
            "1",
            nadal,
            LIMIT_SOURCES["nadal"] if math.isfinite(nadal) else "",
            _where(w, s),
        )
    )
    note = "" if long_enough else f"run < 2 m window {w2:.3g} s"
    rows.append(
        Row(
            "sum_y_2m_prudhomme",
            "|Sigma Y|_2m max, 20 Hz, 2 m sliding mean",
            sy2max,
            "N",
            prudhomme_limit(2.0 * q0),
            LIMIT_SOURCES["prudhomme"],
            _where(ws),
            note,
        )
    )
    rows.append(
        Row(
            "sum_y_2m_en14363",
            "|Sigma Y|_2m max against EN 14363",
            sy2max,
            "N",
            en14363_sum_y_limit(q0, alpha),
            LIMIT_SOURCES["en14363_sy"].format(alpha=alpha),
            _where(ws),
            note,
        )
    )
    p = np.array([[percentile_abs(qf[k, i, j]) for j in range(q.shape[2])] for i in range(2)])
    s, w = np.unravel_index(int(np.argmax(p)), p.shape)
    rows.append(
        Row(
            "q_max",
            "Q max, 20 Hz, 99.85 % percentile",
            float(p.max()),
            "N",
            q_limit(q0, speed),
            LIMIT_SOURCES["q"],
            _where(w, s),
        )
    )
    rows.append(
        Row(
            "q_dyn",
            "Q dynamic: Q 99.85 % - Q0",
            float(p.max()) - q0,
            "N",
            where=_where(w, s),
            note=f"Q0 = {q0 / 1e3:.2f} kN",
        )
    )
    return rows, sy


def _instability(t, fs, speed, sy, bogie_ay, f0, limits, k) -> list:
    """Rows of EN 14363's instability criterion: Sigma Y and the bogie frame's lateral
    acceleration band-passed at f0 +- 2 Hz, rms over 100 m sliding."""
    w100 = time_window(100.0, speed)
    sy_lim, b_lim = limits
    if f0 is None:
        x = sy[k, 0] - sy[k, 0].mean()
        spec = np.abs(np.fft.rfft(x * np.hanning(x.size)))
        fr = np.fft.rfftfreq(x.size, 1.0 / fs)
        ok = (fr >= 0.5) & (fr <= 20.0)
        f0 = float(fr[ok][np.argmax(spec[ok])]) if np.any(ok) else math.nan
    names = ("sum_y_rms", "bogie_ay_rms")
    labels = ("Sigma Y rms, f0 +- 2 Hz, 100 m sliding", "bogie frame y.. rms, f0 +- 2 Hz, 100 m")
    units, lims, srcs = ("N", "m/s^2"), (sy_lim / 2.0, b_lim / 2.0), ("sy_rms", "bogie_rms")
    span = t[k][-1] - t[k][0]
    if not math.isfinite(f0) or span < w100:
        note = f"run {span:.3g} s < 100 m window {w100:.3g} s" if span < w100 else "no f0 found"
        return [
            Row(n, lab, math.nan, u, lim, LIMIT_SOURCES[s], "", note)
            for n, lab, u, lim, s in zip(names, labels, units, lims, srcs)
        ]
    bp = butterworth_bandpass(max(f0 - 2.0, 0.1), f0 + 2.0, order=2)
    rows = []
    for n, lab, u, lim, s, sig in zip(names, labels, units, lims, srcs, (sy, bogie_ay)):
        _, r = sliding_rms(t[k], bp.apply(sig, fs)[k], w100, lab)
        j = int(np.argmax(r.max(axis=0)))
        where = _where(j) if n == "sum_y_rms" else f"bogie {j + 1}"
        rows.append(Row(n, lab, float(r.max()), u, lim, LIMIT_SOURCES[s], where, f"f0 = {f0:.2f} Hz"))
    return rows


def _points(p: dict, floor: float) -> tuple[dict, dict]:
    """The carbody floor points (centre, above each bogie centre) and the bogie frame points
    (above each wheelset): name -> (body, ref, point)."""
    a, aw = p["half_bogie_distance"], p["half_wheelbase"]
    hc, hb = p["carbody_cg_height"], p["bogie_cg_height"]
    car = {
        "floor above bogie 1": ("carbody", (0.0, 0.0, hc), (a, 0.0, floor)),
        "floor centre": ("carbody", (0.0, 0.0, hc), (0.0, 0.0, floor)),
        "floor above bogie 2": ("carbody", (0.0, 0.0, hc), (-a, 0.0, floor)),
    }
    bog = {}
    for i, xb in enumerate((a, -a)):
        for j, dx in enumerate((aw, -aw)):
            bog[f"bogie {i + 1} above ws{2 * i + j + 1}"] = (
                f"bogie{i + 1}",
                (xb, 0.0, hb),
                (xb + dx, 0.0, hb),
            )
    return car, bog


def _accelerations(result, fs, p, floor, k) -> tuple[list, dict, np.ndarray]:
    """Rows of the carbody and bogie frame accelerations; the carbody floor accelerations
    (name -> (a_y, a_z)) and the bogie frames' lateral ones (nt, 2) for the comfort and
    instability rows."""
    car, bog = _points(p, floor)
    acc_c = {n: point_acceleration(result, *spec) for n, spec in car.items()}
    acc_b = {n: point_acceleration(result, *spec) for n, spec in bog.items()}
    bp = butterworth_bandpass(*CARBODY_BAND_HZ, source="EN 14363 carbody filter")
    lp = butterworth_lowpass(BOGIE_LOWPASS_HZ, source="bogie frame filter")
    rows = []
    for comp, c, lim_max, src_rms, lim_rms in (
        ("y", 0, 3.0, "car_y_rms", 0.5),
        ("z", 1, 3.0, "car_z_rms", 0.75),
    ):
        f = {n: bp.apply(a[c], fs)[k] for n, a in acc_c.items()}
        peak = {n: percentile_abs(x) for n, x in f.items()}
        rms = {n: float(np.sqrt(np.mean(x**2))) for n, x in f.items()}
        npk, nrm = max(peak, key=peak.get), max(rms, key=rms.get)
        rows.append(
            Row(
                f"carbody_a{comp}_max",
                f"carbody {comp}.. max, 0.4-10 Hz, 99.85 %",
                peak[npk],
                "m/s^2",
                lim_max,
                LIMIT_SOURCES["car_max"],
                npk,
            )
        )
        rows.append(
            Row(
                f"carbody_a{comp}_rms",
                f"carbody {comp}.. rms, 0.4-10 Hz",
                rms[nrm],
                "m/s^2",
                lim_rms,
                LIMIT_SOURCES[src_rms],
                nrm,
            )
        )
    m_t = p["bogie_mass"] / 1e3
    for comp, c in (("y", 0), ("z", 1)):
        peak = {n: percentile_abs(lp.apply(a[c], fs)[k]) for n, a in acc_b.items()}
        n = max(peak, key=peak.get)
        lim = 12.0 - m_t / 5.0 if comp == "y" else math.nan
        rows.append(
            Row(
                f"bogie_a{comp}_max",
                f"bogie frame {comp}.. max, 10 Hz, 99.85 %",
                peak[n],
                "m/s^2",
                lim,
                LIMIT_SOURCES["bogie"] if comp == "y" else "",
                n,
            )
        )
    # the instability criterion's bogie frame signal: above each bogie's leading wheelset
    bogie_y = np.stack([acc_b[f"bogie {i} above ws{2 * i - 1}"][0] for i in (1, 2)], axis=1)
    return rows, acc_c, bogie_y


def _comfort(t, acc_c, k, discard) -> list:
    """Sperling's Wz per direction and EN 12299's N_MV at the worst floor point."""
    rows = []
    for comp, c, direction in (("y", 0, "lateral"), ("z", 1, "vertical")):
        wz = {n: sperling_wz(t, a[c], direction, discard) for n, a in acc_c.items()}
        n = max(wz, key=wz.get)
        rows.append(Row(f"wz_{comp}", f"Sperling Wz {direction}", wz[n], "1", where=n))
    span = t[k][-1] - t[k][0]
    try:
        nm = {n: n_mv(t, None, a[0], a[1], discard) for n, a in acc_c.items()}
    except InputError:
        return rows + [
            Row(
                "n_mv",
                "EN 12299 N_MV (simplified), Wd / Wb",
                math.nan,
                "1",
                note=f"run {span:.3g} s < one 5 s block",
            )
        ]
    n = max(nm, key=lambda x: nm[x].value)
    note = f"indicative: {nm[n].blocks} x 5 s blocks, not 5 min" if nm[n].indicative else ""
    return rows + [Row("n_mv", "EN 12299 N_MV (simplified), Wd / Wb", nm[n].value, "1", where=n, note=note)]


def assess(
    result,
    *,
    coach: Coach | None = None,
    floor_height: float = 1.2,
    wheel_load: float | None = None,
    alpha: float = 0.85,
    f0: float | None = None,
    discard: float = 0.0,
) -> Assessment:
    """The standards' assessment quantities of a run (EN 14363, EN 12299, Sperling).

    Parameters
    ----------
    result : railvti.vehicle.SimulationResult
        A run kept in memory (a streamed run holds only its tail: InputError).
    coach : Coach, optional
        The coach's geometry and masses (bogie centres, wheelbase, heights, bogie mass);
        default the Manchester benchmark coach (railvti.vehicle.DEFAULTS).
    floor_height : float
        Carbody floor height above the rail top, m (the measuring points of EN 14363 and
        EN 12299 above the bogie centres and at mid-car; an assumption, the benchmark gives
        none).
    wheel_load : float, optional
        Static wheel load Q0, N; default the run's mean wheel load (:func:`static_wheel_load`).
    alpha : float
        EN 14363's factor of the Sigma Y limit (0.85 freight wagons, 1 passenger coaches: the
        latter is Prud'homme's limit, also in the table).
    f0 : float, optional
        Instability frequency for the f0 +- 2 Hz band-pass, Hz; default the spectral peak of
        the leading wheelset's Sigma Y in 0.5-20 Hz.
    discard : float
        Seconds at the start left out of every statistic (the initial disturbance), s.

    Returns
    -------
    Assessment
        One row per quantity (``str()`` is the one-screen table).

    Raises
    ------
    InputError
        No per-wheel outputs, NaN in the histories, uneven output times, a streamed run, or
        nothing left after ``discard``. Quantities whose window is longer than the run are
        rows marked 'n/a' with the reason.
    """
    if getattr(result, "streamed", ""):
        raise InputError(f"the run was streamed to {result.streamed}: assess its full history, not the tail")
    t, q, y = wheel_forces(result)
    for name in ("q", "v"):
        if not np.all(np.isfinite(getattr(result, name))):
            raise InputError(f"the run's {name} history holds NaN or inf")
    fs = sampling_rate(t, "the run")
    speed = _checks.positive("the run's speed", result.speed)
    k = t >= t[0] + _checks.non_negative("discard", discard)
    if np.count_nonzero(k) < 3:
        raise InputError(f"nothing left of the {t[-1] - t[0]:.3g} s run after discarding {discard:g} s")
    p = (coach or Coach()).params
    q0 = _checks.positive("wheel_load", wheel_load) if wheel_load is not None else static_wheel_load(q)
    nadal = (
        getattr(result, "nadal", math.nan)
        if math.isfinite(getattr(result, "flange_angle", math.nan))
        else math.nan
    )
    rows, sy = _forces(t, fs, q, y, speed, q0, alpha, nadal, k)
    acc_rows, acc_c, bogie_y = _accelerations(
        result, fs, p, _checks.positive("floor_height", floor_height), k
    )
    sy_lim = prudhomme_limit(2.0 * q0)
    rows += acc_rows
    rows += _instability(t, fs, speed, sy, bogie_y, f0, (sy_lim, 12.0 - p["bogie_mass"] / 5e3), k)
    rows += _comfort(t, acc_c, k, discard)
    title = (
        f"assessment: {speed * 3.6:.0f} km/h, contact {result.contact}, {t[-1] - t[0]:.3g} s "
        f"({speed * (t[-1] - t[0]):.0f} m), Q0 {q0 / 1e3:.2f} kN"
    )
    notes = (
        "accelerations: central differences of the velocities (relative error (2 pi f dt)^2/6)",
        "maxima of sliding means: over every output time (EN 14363 samples every 0.5 m)",
    )
    return Assessment(rows=tuple(rows), title=title, notes=notes)
