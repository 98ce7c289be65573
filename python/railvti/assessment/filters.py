"""The standards' filters as analogue transfer functions and their digital forms.

Every filter is a chain of analogue sections ``b(s) / a(s)`` (coefficients in descending
powers of s, s in rad/s). :meth:`Filter.response` evaluates the analogue chain;
:meth:`Filter.sos` maps each section to a digital biquad by the bilinear transform,
pre-warped at the section's own corner frequency (so the digital filter matches the analogue
one exactly there and within 0.1 dB up to a tenth of the sampling rate, tests/
test_assessment_filters.py), and :meth:`Filter.apply` runs the sections over a signal from a
steady initial state (the first sample held since t = -infinity), so a constant offset does
not ring.

Sources of the constants (docs/assessment.md "Filters"):

* ISO 8041:2005 Table 3 (the weightings' parameters f1..f6, Q1..Q6, K; quoted in the
  Larson Davis HVM200 reference manual, Table 3.1, "source: ISO 8041") and ISO 2631-1:1997
  Annex A (the section forms: band limiting, acceleration-velocity transition, upward step).
* EN 12299:2009 Annex A (the ride-comfort weightings Wb, Wc, Wd, Wp: band limiting 0.4 /
  100 Hz, Q = 1/sqrt 2; Wb with f3 = f4 = 16 Hz, Q4 = 0.63, f5 = 2.5 Hz, Q5 = 0.8,
  f6 = 4 Hz, Q6 = 0.8, gain 0.4 at low frequency), as transcribed in comfpy
  (tobias-bettinger/comfpy, comfpy/filters.py, citing EN 12299:2009). EN 12299's Wc and Wd
  equal ISO 2631-1's (same parameters in ISO 8041 Table 3: cross-checked). Its Wb differs
  from ISO 2631-4's (Q4 0.63 / 0.55, Q5 0.8 / 0.9, Q6 0.8 / 0.95; both give 0.4 at low and
  1.024 at high frequency); Wp (no high-pass, f3 = f4 = 2 Hz, Q4 = 0.63) has only the
  comfpy transcription: not cross-checked.
* Sperling's weighting B(f) (Sperling 1941; in the continuous form
  B(f) = 0.588 sqrt((1.911 f^2 + (0.25 f^2)^2) / ((1 - 0.277 f^2)^2 + (1.563 f - 0.0368 f^3)^2)),
  f in Hz, vertical; lateral 1.25 times it), as used by comfpy (comfpy/filters.py, Bz, By)
  and janiex/SimulinkMatlab (Matlab/sperling.m: 0.737 = 1.25 x 0.588 lateral): it is the
  magnitude of the rational function of p = j f written in :func:`sperling`.
* EN 14363:2005 / UIC 518 (the assessment quantities' filters: Y, Q, Sigma Y low-pass 20 Hz;
  carbody accelerations band-pass 0.4-10 Hz; the instability criterion band-pass f0 +- 2 Hz;
  as tabulated by GENSYS, gensys.se/course/UIC518_tests.html). The standards fix the
  cut-offs; the filter family and order (Butterworth, 4 poles per edge: 24 dB/octave) are
  this module's choice, stated here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError


def _signal():
    """scipy.signal, imported on first use: ~0.8 s at start-up of every ``railvti run`` (the
    deck registry imports this module through railvti.vehicle.cases; issue 33)."""
    from scipy import signal

    return signal


__all__ = [
    "Section",
    "Filter",
    "iso_weighting",
    "WEIGHTINGS",
    "weighting",
    "sperling",
    "butterworth_lowpass",
    "butterworth_bandpass",
]

_TWO_PI = 2.0 * math.pi
_Q_BAND = 1.0 / math.sqrt(2.0)  # band-limiting Q1 = Q2 (ISO 8041 Table 3, EN 12299 Annex A)


@dataclass(frozen=True)
class Section:
    """One analogue section b(s) / a(s).

    Attributes
    ----------
    b, a : tuple of float
        Numerator and denominator coefficients in descending powers of s (s in rad/s).
    f_warp : float
        Frequency where the digital form matches the analogue one exactly, Hz.
    """

    b: tuple
    a: tuple
    f_warp: float

    def response(self, f: np.ndarray) -> np.ndarray:
        """The section's complex response at frequencies ``f`` (Hz)."""
        s = 1j * _TWO_PI * np.asarray(f, dtype=float)
        return np.polyval(self.b, s) / np.polyval(self.a, s)

    def digital(self, fs: float) -> tuple[np.ndarray, np.ndarray]:
        """(b, a) in z of the bilinear transform at sampling rate ``fs`` (Hz), pre-warped at
        ``f_warp``: s = 2 k (z - 1)/(z + 1) with k = pi f_warp / tan(pi f_warp / fs)."""
        k = math.pi * self.f_warp / math.tan(math.pi * self.f_warp / fs)
        return _signal().bilinear(np.asarray(self.b, float), np.asarray(self.a, float), fs=k)


@dataclass(frozen=True)
class Filter:
    """A chain of analogue sections and its digital form.

    Attributes
    ----------
    name : str
        Short name ('Wb', 'sperling_vertical', 'lowpass_20Hz', ...).
    sections : tuple of Section
    gain : float
        Constant factor of the chain, 1.
    source : str
        The standard (and clause or table) its constants come from.

    Sections whose corner lies at or above 0.45 times the sampling rate are left out of the
    digital form (a band-limiting low-pass the sampled signal cannot carry anyway), and
    named by :meth:`dropped`.
    """

    name: str
    sections: tuple
    gain: float
    source: str

    def response(self, f) -> np.ndarray:
        """The analogue chain's complex response at ``f`` (Hz)."""
        f = np.asarray(f, dtype=float)
        h = np.full(f.shape, self.gain, dtype=complex)
        for sec in self.sections:
            h = h * sec.response(f)
        return h

    def _kept(self, fs: float) -> list:
        return [sec for sec in self.sections if sec.f_warp < 0.45 * fs]

    def dropped(self, fs: float) -> list:
        """The sections :meth:`sos` leaves out at sampling rate ``fs``: their corner
        frequencies, Hz (band-limiting low-passes above 0.45 fs)."""
        return [sec.f_warp for sec in self.sections if sec.f_warp >= 0.45 * fs]

    def sos(self, fs: float) -> np.ndarray:
        """Second-order sections (n, 6) of the digital filter at sampling rate ``fs`` (Hz)."""
        fs = _checks.positive("sampling rate", fs)
        rows = []
        for sec in self._kept(fs):
            bz, az = sec.digital(fs)
            rows.append(_signal().tf2sos(bz, az))
        if not rows:
            return np.array([[self.gain, 0.0, 0.0, 1.0, 0.0, 0.0]])
        sos = np.vstack(rows)
        sos[0, :3] *= self.gain
        return sos

    def digital_response(self, f, fs: float) -> np.ndarray:
        """The digital filter's complex response at ``f`` (Hz) for sampling rate ``fs``."""
        _, h = _signal().sosfreqz(self.sos(fs), worN=np.asarray(f, dtype=float), fs=fs)
        return h

    def apply(self, x: np.ndarray, fs: float) -> np.ndarray:
        """Filter ``x`` (along axis 0) at sampling rate ``fs`` (Hz), starting from the steady
        state of its first sample."""
        x = np.asarray(x, dtype=float)
        if x.shape[0] < 2:
            raise InputError(f"filter {self.name}: a signal of at least 2 samples is needed")
        if not np.all(np.isfinite(x)):
            raise InputError(f"filter {self.name}: the signal holds NaN or inf")
        sos = self.sos(fs)
        zi = _signal().sosfilt_zi(sos)  # (n, 2) for a unit step
        zi = zi.reshape(zi.shape + (1,) * (x.ndim - 1)) * x[0][None, None]
        y, _ = _signal().sosfilt(sos, x, axis=0, zi=zi)
        return y


def _band(f1: float, f2: float, q1: float = _Q_BAND, q2: float = _Q_BAND) -> list:
    """Band limiting (ISO 2631-1 A.2.1): second-order high-pass at f1 (none for f1 = 0) and
    low-pass at f2 (none for f2 = inf)."""
    out = []
    if f1 > 0.0:
        w1 = _TWO_PI * f1
        out.append(Section((1.0, 0.0, 0.0), (1.0, w1 / q1, w1 * w1), f1))
    if math.isfinite(f2):
        w2 = _TWO_PI * f2
        out.append(Section((0.0, 0.0, w2 * w2), (1.0, w2 / q2, w2 * w2), f2))
    return out


def iso_weighting(
    name: str,
    f1: float,
    f2: float,
    f3: float,
    f4: float,
    q4: float,
    f5: float,
    q5: float,
    f6: float,
    q6: float,
    k: float,
    source: str,
) -> Filter:
    """A weighting in the form of ISO 2631-1 Annex A / ISO 8041 Table 3:
    band limiting (f1, f2), acceleration-velocity transition
    Ht = (1 + s/w3) / (1 + s/(Q4 w4) + s^2/w4^2) (none for f4 = inf; numerator 1 for
    f3 = inf), upward step Hs = (s^2 + s w5/Q5 + w5^2) / (s^2 + s w6/Q6 + w6^2) (1 at high
    frequency; none for f5 = inf), times the gain ``k``. Frequencies in Hz."""
    secs = _band(f1, f2)
    if math.isfinite(f4):
        w4 = _TWO_PI * f4
        b1 = w4 * w4 / (_TWO_PI * f3) if math.isfinite(f3) else 0.0
        secs.append(Section((0.0, b1, w4 * w4), (1.0, w4 / q4, w4 * w4), f4))
    if math.isfinite(f5):
        w5, w6 = _TWO_PI * f5, _TWO_PI * f6
        secs.append(Section((1.0, w5 / q5, w5 * w5), (1.0, w6 / q6, w6 * w6), math.sqrt(f5 * f6)))
    return Filter(name=name, sections=tuple(secs), gain=float(k), source=source)


_INF = math.inf
_ISO8041 = "ISO 8041:2005 Table 3 (forms: ISO 2631-1:1997 Annex A)"
_EN12299 = "EN 12299:2009 Annex A (as transcribed in comfpy/filters.py)"

#: name -> (f1, f2, f3, f4, Q4, f5, Q5, f6, Q6, K (high-frequency gain of the step), source).
#: EN 12299's Wb is given there as a step normalised to 1 at low frequency times K = 0.4:
#: the same filter as K = 0.4 (4/2.5)^2 = 1.024 in this (ISO 8041) form.
WEIGHTINGS: dict[str, tuple] = {
    "Wb": (0.4, 100.0, 16.0, 16.0, 0.63, 2.5, 0.8, 4.0, 0.8, 0.4 * (4.0 / 2.5) ** 2, _EN12299 + ": vertical"),
    "Wc": (
        0.4,
        100.0,
        8.0,
        8.0,
        0.63,
        _INF,
        1.0,
        _INF,
        1.0,
        1.0,
        _EN12299 + " = " + _ISO8041 + ": seat back x",
    ),
    "Wd": (0.4, 100.0, 2.0, 2.0, 0.63, _INF, 1.0, _INF, 1.0, 1.0, _EN12299 + " = " + _ISO8041 + ": lateral"),
    "Wp": (0.0, 100.0, 2.0, 2.0, 0.63, _INF, 1.0, _INF, 1.0, 1.0, _EN12299 + ": not cross-checked"),
    "Wb_iso2631_4": (0.4, 100.0, 16.0, 16.0, 0.55, 2.5, 0.9, 4.0, 0.95, 1.024, _ISO8041 + ", ISO 2631-4 Wb"),
    "Wk_iso2631_1": (0.4, 100.0, 12.5, 12.5, 0.63, 2.37, 0.91, 3.35, 0.91, 1.0, _ISO8041 + ", ISO 2631-1 Wk"),
}


def weighting(name: str) -> Filter:
    """A comfort weighting by name: EN 12299's 'Wb', 'Wc', 'Wd', 'Wp'; ISO 2631's
    'Wb_iso2631_4', 'Wk_iso2631_1' (:data:`WEIGHTINGS`)."""
    if name not in WEIGHTINGS:
        raise InputError(f"unknown weighting {name!r}; one of {sorted(WEIGHTINGS)}")
    *p, source = WEIGHTINGS[name]
    return iso_weighting(name, *p, source=source)


#: Sperling's B(f) = 0.588 |(1.3824 p + 0.25 p^2) / (1 + 1.563 p + 0.277 p^2 + 0.0368 p^3)|,
#: p = j f (f in Hz): |1.3824 j f - 0.25 f^2|^2 = 1.911 f^2 + (0.25 f^2)^2 (1.3824^2 = 1.911).
_SPERLING_NUM = (0.25, math.sqrt(1.911), 0.0)
_SPERLING_DEN = (0.0368, 0.277, 1.563, 1.0)
_SPERLING_SOURCE = (
    "Sperling's weighting B(f) (continuous form: comfpy/filters.py Bz, By; "
    "janiex/SimulinkMatlab sperling.m), lateral = 1.25 x vertical"
)


def sperling(direction: str) -> Filter:
    """Sperling's frequency weighting B(f) as a filter: 'vertical' (factor 0.588) or
    'lateral' (1.25 x 0.588), acting on acceleration."""
    factor = {"vertical": 0.588, "lateral": 1.25 * 0.588}.get(direction)
    if factor is None:
        raise InputError(f"Sperling direction must be 'vertical' or 'lateral', got {direction!r}")
    # p = s / (2 pi): a polynomial c_k p^k becomes c_k (2 pi)^-k s^k
    b = tuple(c / _TWO_PI ** (2 - i) for i, c in enumerate(_SPERLING_NUM))
    a = tuple(c / _TWO_PI ** (3 - i) for i, c in enumerate(_SPERLING_DEN))
    return Filter(
        name=f"sperling_{direction}",
        sections=(Section(b, a, 5.0),),
        gain=factor,
        source=_SPERLING_SOURCE,
    )


def _butter_sections(order: int, fc: float, btype: str) -> list:
    """Analogue Butterworth of ``order`` at ``fc`` (Hz) as second-order sections."""
    z, p, k = _signal().butter(order, _TWO_PI * fc, btype=btype, analog=True, output="zpk")
    out = []
    pairs = _signal().zpk2sos(z, p, k, analog=True)
    for row in pairs:
        out.append(Section(tuple(row[:3]), tuple(row[3:]), fc))
    return out


def butterworth_lowpass(fc: float, order: int = 4, source: str = "") -> Filter:
    """Butterworth low-pass at ``fc`` (Hz), ``order`` poles (4: 24 dB/octave)."""
    fc = _checks.positive("cut-off frequency", fc)
    return Filter(
        name=f"lowpass_{fc:g}Hz",
        sections=tuple(_butter_sections(order, fc, "lowpass")),
        gain=1.0,
        source=source or f"Butterworth low-pass {fc:g} Hz, {order} poles",
    )


def butterworth_bandpass(f_lo: float, f_hi: float, order: int = 4, source: str = "") -> Filter:
    """Band-pass: Butterworth high-pass at ``f_lo`` then low-pass at ``f_hi`` (Hz), ``order``
    poles each."""
    f_lo = _checks.positive("lower cut-off frequency", f_lo)
    if not f_hi > f_lo:
        raise InputError(f"band-pass: upper cut-off {f_hi!r} Hz must exceed the lower {f_lo!r} Hz")
    return Filter(
        name=f"bandpass_{f_lo:g}_{f_hi:g}Hz",
        sections=tuple(_butter_sections(order, f_lo, "highpass") + _butter_sections(order, f_hi, "lowpass")),
        gain=1.0,
        source=source or f"Butterworth band-pass {f_lo:g}-{f_hi:g} Hz, {order} poles per edge",
    )
