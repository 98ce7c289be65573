"""Standard spectra of track irregularities and a generator of tracks that follow them.

Every PSD here is **one-sided in the spatial angular frequency** Omega (rad/m, Omega = 2 pi /
wavelength): the variance of a channel is the integral of S(Omega) over Omega from 0 to
infinity, S in m^2/(rad/m) (for the ERRI cross level before conversion: rad^2/(rad/m)). To get
a PSD per cycle/m, multiply by 2 pi (and evaluate at Omega = 2 pi f). The channels are those of
:class:`railvti.track.TrackIrregularity` (EN 13848-1): vertical level (mean of the rails'
heights), alignment (mean of their lateral positions), cross level (left rail height minus
right rail height) and gauge deviation, all in m.

**ERRI B176 low and high** (ORE B176, "Bogies with steered or steering wheelsets", Report 1,
Utrecht 1989; the "low / high irregularity" spectra used by ERRI, given e.g. by Claus &
Schiehlen, Vehicle System Dynamics 29 suppl., 1998, and in the review of Haigermoser et al.,
Vehicle System Dynamics 53(7), 2015; also called the German (high-speed) spectra)::

    S_v = A_v Omega_c^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2))
    S_a = A_a Omega_c^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2))
    S_c = (A_v / b^2) Omega_c^2 Omega^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2) (Omega^2 + Omega_s^2))
    S_g = A_g Omega_c^2 Omega^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2) (Omega^2 + Omega_s^2))

Omega_c = 0.8246 rad/m, Omega_r = 0.0206 rad/m, Omega_s = 0.4380 rad/m, b = 0.75 m (half the
distance between the rails' centres); A_v = 4.032e-7 / 1.080e-6, A_a = 2.119e-7 / 6.125e-7,
A_g = 5.32e-8 / 1.032e-7 m rad (low / high). S_c is the PSD of the cross-level *angle*
(z_left - z_right) / (2 b); this module returns the cross level as a height difference in m,
so its PSD is (2 b)^2 S_c = 4 A_v Omega_c^2 Omega^2 / (...): at short wavelengths, where the
two rails are independent, it tends to 4 S_v, as the difference of two independent rails must.

**FRA track classes 1-6** (US Federal Railroad Administration; Hamid, Rasmussen, Baluja and
Yang, *Analytical descriptions of track geometry variations*, FRA final report, 1976-1981;
in SI units as tabulated by Garg & Dukkipati, *Dynamics of Railway Vehicle Systems*, Academic
Press 1984, and Zhai, *Vehicle-Track Coupled Dynamics*, Springer 2020)::

    S_v = k A_v Omega_c^2 / (Omega^2 (Omega^2 + Omega_c^2))
    S_a = k A_a Omega_c^2 / (Omega^2 (Omega^2 + Omega_c^2))
    S_c = S_g = 4 k A_v Omega_c^2 / ((Omega^2 + Omega_c^2) (Omega^2 + Omega_s^2))

k = 0.25, Omega_c = 0.8245 rad/m; A_v, A_a (cm^2 rad/m) and Omega_s (rad/m) per class in
:data:`FRA_TABLE` (class 1 the roughest, 6 the smoothest). The table's published unit gives S
in cm^2/(rad/m); this module converts once (1 cm^2 = 1e-4 m^2). The cross level is the height
difference (S_c tends to 4 S_v at short wavelengths, as above).

The generator (:func:`generate`) draws each channel as FFT-filtered Gaussian white noise on a
periodic grid: the Fourier coefficient of every harmonic Omega_k = 2 pi k / (n dx) inside the
wavelength band is complex Gaussian with E|c_k|^2 matching S(Omega_k) dOmega, every other
harmonic is zero. So the track is a stationary Gaussian sample of the spectrum, band-limited
exactly; the four channels are independent (the standards give no cross spectra), each from
its own stream of ``numpy.random.SeedSequence(seed)``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from types import MappingProxyType

import numpy as np

from .. import _checks
from ..errors import InputError
from .irregularity import CHANNELS, TrackIrregularity

__all__ = [
    "ERRI_B176",
    "ERRI_OMEGA_C",
    "ERRI_OMEGA_R",
    "ERRI_OMEGA_S",
    "ERRI_HALF_GAUGE",
    "FRA_K",
    "FRA_OMEGA_C",
    "FRA_TABLE",
    "MAX_SAMPLES",
    "MIN_SAMPLES_PER_WAVELENGTH",
    "SPECTRA",
    "band_variance",
    "generate",
    "psd",
]

#: ERRI B176: Omega_c, Omega_r, Omega_s (rad/m) and b (m), the same for low and high.
ERRI_OMEGA_C = 0.8246
ERRI_OMEGA_R = 0.0206
ERRI_OMEGA_S = 0.4380
ERRI_HALF_GAUGE = 0.75
#: ERRI B176 level -> (A_v, A_a, A_g), m rad.
ERRI_B176 = MappingProxyType({"low": (4.032e-7, 2.119e-7, 5.32e-8), "high": (1.080e-6, 6.125e-7, 1.032e-7)})

#: FRA: the factor k and Omega_c (rad/m), the same for all classes.
FRA_K = 0.25
FRA_OMEGA_C = 0.8245
#: FRA class -> (A_v cm^2 rad/m, A_a cm^2 rad/m, Omega_s rad/m), as published (Garg &
#: Dukkipati 1984; Zhai 2020). Converted to m^2 once, in :func:`psd`.
FRA_TABLE = MappingProxyType(
    {
        1: (1.2107, 3.3634, 0.6046),
        2: (1.0181, 1.2107, 0.9308),
        3: (0.6816, 0.4128, 0.8520),
        4: (0.5376, 0.3027, 1.1312),
        5: (0.2095, 0.0762, 0.8209),
        6: (0.0339, 0.0339, 0.4380),
    }
)
_CM2 = 1.0e-4  # m^2 per cm^2

#: The spectra :func:`generate` and :func:`psd` know.
SPECTRA = ("erri-b176-low", "erri-b176-high", *(f"fra-{c}" for c in range(1, 7)))

#: The shortest wavelength of a band holds at least this many samples (dx): at 2 (Nyquist) a
#: wave is a zigzag of two points, and a model that interpolates linearly between samples
#: loses a fifth of a 4-sample wave's amplitude already (the band's short end stays honest).
MIN_SAMPLES_PER_WAVELENGTH = 4

#: Most samples of a generated track (per channel): 2,500 km at dx = 0.25 m, 400 MB for x and
#: the four channels; a longer request is a typo (length in mm, dx in km), refused before work.
MAX_SAMPLES = 10_000_000


def _spectrum_name(spectrum: object) -> str:
    if not isinstance(spectrum, str) or spectrum.strip().lower() not in SPECTRA:
        raise InputError(f"spectrum: unknown {spectrum!r}; valid: {', '.join(SPECTRA)}")
    return spectrum.strip().lower()


def _channel_name(channel: object) -> str:
    if channel not in CHANNELS:
        raise InputError(f"channel: unknown channel {channel!r}; valid: {', '.join(CHANNELS)}")
    return str(channel)


def _erri(level: str, channel: str, w2: np.ndarray) -> np.ndarray:
    a_v, a_a, a_g = ERRI_B176[level]
    wc2, wr2, ws2 = ERRI_OMEGA_C**2, ERRI_OMEGA_R**2, ERRI_OMEGA_S**2
    base = wc2 / ((w2 + wr2) * (w2 + wc2))
    if channel == "vertical_level":
        return a_v * base
    if channel == "alignment":
        return a_a * base
    high_pass = w2 / (w2 + ws2)
    if channel == "cross_level":  # the angle's PSD A_v / b^2 ... times (2 b)^2: a height, m
        return (2.0 * ERRI_HALF_GAUGE) ** 2 * (a_v / ERRI_HALF_GAUGE**2) * base * high_pass
    return a_g * base * high_pass


def _fra(cls: int, channel: str, w2: np.ndarray) -> np.ndarray:
    a_v, a_a, omega_s = FRA_TABLE[cls]
    wc2 = FRA_OMEGA_C**2
    if channel == "vertical_level":
        return FRA_K * a_v * _CM2 * wc2 / (w2 * (w2 + wc2))
    if channel == "alignment":
        return FRA_K * a_a * _CM2 * wc2 / (w2 * (w2 + wc2))
    return 4.0 * FRA_K * a_v * _CM2 * wc2 / ((w2 + wc2) * (w2 + omega_s**2))  # cross level, gauge


def psd(spectrum: str, channel: str, omega: np.ndarray | float) -> np.ndarray:
    """One-sided PSD of a channel of a standard spectrum.

    Parameters
    ----------
    spectrum : str
        One of :data:`SPECTRA`.
    channel : str
        One of :data:`railvti.track.CHANNELS`.
    omega : array_like
        Spatial angular frequency Omega = 2 pi / wavelength, rad/m, > 0.

    Returns
    -------
    ndarray
        S(Omega), m^2/(rad/m), one-sided: the channel's variance is its integral over
        Omega > 0. The cross level is the left rail's height minus the right one's, m.
    """
    name = _spectrum_name(spectrum)
    channel = _channel_name(channel)
    w = _checks.finite_array("omega", omega)
    if np.any(w <= 0.0):
        raise InputError("omega: spatial angular frequencies must be > 0 (rad/m)")
    w2 = np.asarray(w, dtype=np.float64) ** 2
    if name.startswith("erri"):
        return _erri(name.rsplit("-", 1)[1], channel, w2)
    return _fra(int(name.rsplit("-", 1)[1]), channel, w2)


def _band(band: object, length: float, dx: float) -> tuple[float, float]:
    """The wavelength band (shortest, longest), m, checked against what dx and length sample."""
    if isinstance(band, (str, bytes)) or not isinstance(band, Sequence | np.ndarray) or len(band) != 2:
        raise InputError(f"band: a pair (shortest, longest) of wavelengths in m, got {band!r}")
    lo = _checks.positive("band: shortest wavelength", band[0])
    hi = _checks.positive("band: longest wavelength", band[1])
    if lo >= hi:
        raise InputError(f"band: shortest wavelength {lo:g} m must be below the longest, {hi:g} m")
    need = MIN_SAMPLES_PER_WAVELENGTH * dx
    if lo < need * (1.0 - 1e-12):
        raise InputError(
            f"band: shortest wavelength {lo:g} m is below {MIN_SAMPLES_PER_WAVELENGTH} dx = {need:g} m "
            f"(dx = {dx:g} m samples it too coarsely; lower dx or raise the band's short end)"
        )
    if hi > length * (1.0 + 1e-12):
        raise InputError(
            f"band: longest wavelength {hi:g} m exceeds the track length {length:g} m "
            "(a track holds no wave longer than itself; lengthen it or lower the band's long end)"
        )
    return lo, hi


def band_variance(spectrum: str, channel: str, band: tuple[float, float] = (3.0, 70.0)) -> float:
    """Variance of a channel within a wavelength band: the integral of :func:`psd` over it.

    Parameters
    ----------
    spectrum, channel : str
        As in :func:`psd`.
    band : (float, float)
        Shortest and longest wavelength, m.

    Returns
    -------
    float
        m^2 (its square root is the channel's rms in the band). Trapezoids on 4001 points
        evenly spaced in log Omega (relative error below 1e-7 for these spectra).
    """
    lo, hi = _band(band, math.inf, 0.0)
    u = np.linspace(math.log(2 * math.pi / hi), math.log(2 * math.pi / lo), 4001)
    w = np.exp(u)
    f = psd(spectrum, channel, w) * w
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(u)))


def generate(
    spectrum: str,
    length: float,
    *,
    seed: int,
    band: tuple[float, float] = (3.0, 70.0),
    dx: float = 0.25,
    x0: float = 0.0,
) -> TrackIrregularity:
    """A track whose four channels are Gaussian samples of a standard spectrum.

    Parameters
    ----------
    spectrum : str
        One of :data:`SPECTRA` ("erri-b176-low", "erri-b176-high", "fra-1" .. "fra-6").
    length : float
        Track length, m: the samples run from x0 to x0 + floor(length / dx) dx.
    seed : int
        Seed (>= 0) of ``numpy.random.SeedSequence``: the same seed and arguments give the same
        track, bit for bit (with the same numpy); each channel draws from its own child stream.
    band : (float, float)
        Shortest and longest wavelength, m (default 3-70 m, EN 13848's D1 and D2 ranges). The
        shortest must be >= 4 dx, the longest <= length. No power is put outside the band.
    dx : float
        Sample spacing, m.
    x0 : float
        Position of the first sample, m.

    Returns
    -------
    TrackIrregularity
        The channels in m at x; ``source`` names the spectrum, seed, band and dx.

    Notes
    -----
    The grid of n samples is treated as one period n dx: the harmonics Omega_k = 2 pi k /
    (n dx) with wavelengths inside the band get complex Gaussian Fourier coefficients,
    E|c_k|^2 = (n / 2)^2 2 S(Omega_k) dOmega (dOmega = 2 pi / (n dx)), so each harmonic adds
    S(Omega_k) dOmega to the variance on average; the others are zero. An inverse real FFT gives
    the channel. The track is periodic with period n dx (its end joins its start smoothly), and
    a shorter track with the same seed is not the start of a longer one.
    """
    name = _spectrum_name(spectrum)
    length = _checks.positive("length", length)
    dx = _checks.positive("dx", dx)
    x0 = _checks.finite("x0", x0)
    seed = _checks.positive_int("seed", seed, minimum=0)
    lo, hi = _band(band, length, dx)
    if length / dx >= MAX_SAMPLES:
        raise InputError(
            f"length: {length:g} m at dx = {dx:g} m gives {length / dx:.3g} samples, more than "
            f"{MAX_SAMPLES:.0e}; shorten the track or raise dx"
        )
    n = int(math.floor(length / dx * (1.0 + 1e-12))) + 1
    domega = 2.0 * math.pi / (n * dx)
    omega = domega * np.arange(n // 2 + 1)
    inside = (omega >= 2.0 * math.pi / hi * (1.0 - 1e-12)) & (omega <= 2.0 * math.pi / lo * (1.0 + 1e-12))
    inside[0] = False
    m = int(np.count_nonzero(inside))
    if m == 0:
        raise InputError(
            f"band: no harmonic of the {n * dx:g} m period between {lo:g} and {hi:g} m; widen the band or "
            "lengthen the track"
        )
    streams = np.random.SeedSequence(seed).spawn(len(CHANNELS))
    channels = []
    for ch, stream in zip(CHANNELS, streams, strict=True):
        rng = np.random.default_rng(stream)
        amp = 0.5 * n * np.sqrt(psd(name, ch, omega[inside]) * domega)
        coef = np.zeros(n // 2 + 1, dtype=np.complex128)
        coef[inside] = amp * (rng.standard_normal(m) + 1j * rng.standard_normal(m))
        channels.append(np.fft.irfft(coef, n))
    x = x0 + dx * np.arange(n)
    source = f"{name}, seed {seed}, band {lo:g}-{hi:g} m, dx {dx:g} m"
    return TrackIrregularity(x, *channels, source=source)
