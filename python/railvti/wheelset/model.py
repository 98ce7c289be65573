"""The flexible rotating wheelset: modes per harmonic, the axle-fixed modal
model (Kaiser, eq. 11) and the gyroscopic frequency response."""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from .. import _checks
from .._native import core
from .._status import check
from ..errors import InputError
from .fe import HarmonicModes, check_harmonic, eq11_blocks, solve_harmonic
from .flexible import FlexibleWheelset, flexible_body
from .geometry import WheelsetGeometry
from .mesh import MeridianMesh

log = logging.getLogger(__name__)

_DIRECTIONS = ("lateral", "vertical", "longitudinal")


@dataclass(frozen=True)
class PrimarySuspension:
    """Primary suspension stiffness per axlebox, N/m (bogie frame fixed).

    Defaults: the Manchester Benchmarks passenger vehicle (Iwnicki, The
    Manchester Benchmarks for Rail Vehicle Simulation, VSD 30, 1998):
    longitudinal 31.391 MN/m, lateral 3.884 MN/m, vertical 1.22 MN/m.
    """

    longitudinal: float = 31.391e6
    lateral: float = 3.884e6
    vertical: float = 1.22e6

    def __post_init__(self) -> None:
        for name in ("longitudinal", "lateral", "vertical"):
            object.__setattr__(self, name, _checks.non_negative(name, getattr(self, name)))


@dataclass(frozen=True)
class ModeTable:
    """Eigenmodes of the non-rotating wheelset, one row per mode (pair).

    Attributes
    ----------
    k : ndarray of int (n,)
        Circumferential harmonic.
    freq_hz : ndarray (n,)
        Natural frequency, Hz.
    family : list of str
        'AB' a double mode (k > 0, U_A and U_B of eqs 9-10); 'A' the vertical
        and 'B' the longitudinal plane when the suspension tells them apart;
        '0' for k = 0.
    shapes : list of ndarray (nn, 3)
        Nodal amplitudes (U_r, U_y, U_theta), mass-normalised.
    mesh : MeridianMesh
        The meridian mesh the shapes live on.
    """

    k: np.ndarray
    freq_hz: np.ndarray
    family: list[str]
    shapes: list[np.ndarray]
    mesh: MeridianMesh

    def __len__(self) -> int:
        return int(self.k.size)

    def mirror_symmetry(self, i: int) -> float:
        """Symmetry of mode i about the mid-plane y = 0, in [-1, 1].

        +1: the mirror image of the field equals the field (u_r, u_theta even
        and u_y odd in y): for k = 1 the axle bows and the two wheels tilt in
        opposite senses; -1: antisymmetric (S-shaped axle, wheels tilting the
        same way). Computed as <u, P u> / <u, u> with P the mirror map.

        Raises
        ------
        InputError
            If i is out of range or the mesh is not mirror-symmetric.
        """
        if not 0 <= i < len(self):
            raise InputError(f"mode index {i} out of range 0..{len(self) - 1}")
        s = self.shapes[i]
        m = s[_mirror_index(self.mesh)] * np.array([1.0, -1.0, 1.0])
        return float(np.sum(s * m) / max(np.sum(s * s), 1e-300))

    def first(self, k: int, family: str | None = None, f_min: float = 1.0) -> float:
        """Lowest frequency (Hz) of harmonic k above f_min."""
        sel = [
            f
            for kk, f, fam in zip(self.k, self.freq_hz, self.family)
            if kk == k and f > f_min and (family is None or fam == family)
        ]
        if not sel:
            raise InputError(f"no mode of harmonic {k} above {f_min} Hz in the table")
        return float(min(sel))


def _mirror_index(mesh: MeridianMesh) -> np.ndarray:
    """Index of the node at (r, -y) for every node (r, y)."""
    x = mesh.nodes
    scale = max(float(np.abs(x).max()), 1e-30)
    key = {(round(r / scale, 9), round(y / scale, 9)): i for i, (r, y) in enumerate(x)}
    try:
        return np.array([key[(round(r / scale, 9), round(-y / scale, 9))] for r, y in x])
    except KeyError:
        raise InputError("the meridian mesh is not symmetric about y = 0") from None


@dataclass(frozen=True)
class AxleFixedModel:
    """Linear model of the rotating wheelset in the axle-fixed frame (eq. 11).

    M Q'' + (G + D) Q' + K Q = Phi^T F with M = I. Coordinates: for each k,
    the modes of k (k = 0) or the pairs (Q_A block, then Q_B block, k > 0);
    azimuth 0 points from the axle to the contact points (downwards).

    Attributes
    ----------
    speed : float
        Running speed, m/s; omega = speed / r0 (rad/s).
    omega : float
        Angular speed of the wheelset, rad/s.
    k : ndarray of int (nq,)
        Harmonic of each coordinate.
    family : ndarray of str (nq,)
        '0', 'A' or 'B'.
    freq_hz : ndarray (nq,)
        Non-rotating natural frequency of each coordinate's mode, Hz.
    mass, gyro, damping, stiffness : ndarray (nq, nq)
        M, G (skew, Coriolis and frame rotation), D (modal damping), K
        (including the centrifugal softening and the anisotropic suspension).
    contact : ndarray (2, 3, nq)
        Shape functions at the right (0) and left (1) contact points at fixed
        azimuth 0: rows lateral (+y), vertical (upwards), longitudinal (m per
        unit Q).
    journal : ndarray (2, 3, nq)
        Same at the journal centres: the coupling to the bogie and to the
        wheelset's rigid-body coordinates of a vehicle model.
    """

    speed: float
    omega: float
    k: np.ndarray
    family: np.ndarray
    freq_hz: np.ndarray
    mass: np.ndarray
    gyro: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    contact: np.ndarray
    journal: np.ndarray

    @property
    def n(self) -> int:
        """Number of modal coordinates."""
        return int(self.k.size)

    def eigenfrequencies(self, k: int) -> np.ndarray:
        """Undamped natural frequencies (Hz, >= 0, ascending) of harmonic k in the axle-fixed frame."""
        sel = np.flatnonzero(self.k == k)
        if sel.size == 0:
            return np.zeros(0)
        kk = self.stiffness[np.ix_(sel, sel)]
        gg = self.gyro[np.ix_(sel, sel)]
        n = sel.size
        a = np.block([[np.zeros((n, n)), np.eye(n)], [-kk, -gg]])
        ev = np.linalg.eigvals(a)
        f = np.abs(ev.imag[ev.imag >= -1e-9]) / (2.0 * np.pi)
        return np.sort(f)[:n]


class Wheelset:
    """A flexible wheelset of axisymmetric finite elements.

    Parameters
    ----------
    geometry : WheelsetGeometry, optional
        Dimensions, material and mesh sizes; default: the passenger wheelset.
    suspension : PrimarySuspension, optional
        Primary suspension per axlebox (for ``support='suspension'`` and the FRF).
    **geometry_kw
        Fields of :class:`WheelsetGeometry` to change, m (e.g. ``web_thickness_rim=0.02``).

    Examples
    --------
    >>> ws = Wheelset()
    >>> table = ws.modes(k_max=2, f_max=500.0)
    >>> h = ws.frf(np.linspace(50, 800, 400), speed=300 / 3.6)
    """

    def __init__(
        self,
        geometry: WheelsetGeometry | None = None,
        suspension: PrimarySuspension | None = None,
        **geometry_kw: float,
    ) -> None:
        if geometry is not None and geometry_kw:
            raise InputError("give either geometry or keyword dimensions, not both")
        self.geometry = geometry if geometry is not None else WheelsetGeometry(**geometry_kw)
        self.suspension = suspension if suspension is not None else PrimarySuspension()
        self.mesh = self.geometry.mesh()
        g = self.geometry
        self._journal_nodes = (
            self.mesh.node_at(0.0, 0.5 * g.journal_spacing),
            self.mesh.node_at(0.0, -0.5 * g.journal_spacing),
        )
        self._contact_nodes = (
            self.mesh.node_at(g.wheel_radius, g.contact_y),
            self.mesh.node_at(g.wheel_radius, -g.contact_y),
        )
        self._cache: dict[tuple, HarmonicModes] = {}
        self._scaled: dict[float, "Wheelset"] = {}

    def stiffness_scaled(self, scale: float) -> "Wheelset":
        """This wheelset with Young's modulus times ``scale`` (> 0; every elastic frequency
        times sqrt(scale), the masses unchanged): itself for 1, else a copy kept for the next
        call (the stiff-limit checks of issue 30)."""
        scale = _checks.positive("wheelset_stiffness_scale", scale)
        if scale == 1.0:
            return self
        if scale not in self._scaled:
            g = replace(self.geometry, young=self.geometry.young * scale)
            self._scaled[scale] = Wheelset(geometry=g, suspension=self.suspension)
        return self._scaled[scale]

    # ----------------------------------------------------------------- modes
    def harmonic(
        self, k: int, f_max: float, support: str = "free", transverse: str = "vertical"
    ) -> HarmonicModes:
        """Modes of one harmonic k up to f_max (Hz).

        Parameters
        ----------
        k : int
            Circumferential harmonic, >= 0.
        f_max : float
            Highest frequency, Hz.
        support : {'free', 'suspension'}
            Free-free, or the journals on the primary suspension (bogie fixed).
        transverse : {'vertical', 'longitudinal'}
            Which primary stiffness acts on k = 1 (an axisymmetric model takes
            one transverse stiffness at a time).
        """
        k = check_harmonic(k)
        f_max = _checks.positive("f_max", f_max)
        if support not in ("free", "suspension"):
            raise InputError(f"support must be 'free' or 'suspension', got {support!r}")
        if transverse not in ("vertical", "longitudinal"):
            raise InputError(f"transverse must be 'vertical' or 'longitudinal', got {transverse!r}")
        key = (k, f_max, support, transverse if k == 1 else "")
        if key not in self._cache:
            springs: tuple = ()
            if support == "suspension":
                s = self.suspension
                if k == 0:
                    springs = tuple((n, 1, s.lateral) for n in self._journal_nodes)
                elif k == 1:
                    kt = s.vertical if transverse == "vertical" else s.longitudinal
                    springs = tuple((n, 0, kt) for n in self._journal_nodes)
            g = self.geometry
            self._cache[key] = solve_harmonic(
                self.mesh, k, g.young, g.poisson, g.density, f_max, springs=springs
            )
        return self._cache[key]

    def modes(self, k_max: int, f_max: float, support: str = "free") -> ModeTable:
        """Modes of harmonics 0..k_max up to f_max (Hz), as a table.

        Parameters
        ----------
        k_max : int
            Highest circumferential harmonic, >= 0.
        f_max : float
            Highest frequency, Hz.
        support : {'free', 'suspension'}
            Free-free, or journals on the primary suspension.

        Returns
        -------
        ModeTable
            Rows sorted by k then frequency; double modes (k > 0) listed once.
        """
        k_max = check_harmonic(k_max, "k_max")
        ks, fs, fams, shapes = [], [], [], []
        for k in range(k_max + 1):
            if k == 1 and support == "suspension":
                runs = [
                    ("A", self.harmonic(1, f_max, support, "vertical")),
                    ("B", self.harmonic(1, f_max, support, "longitudinal")),
                ]
            else:
                runs = [("0" if k == 0 else "AB", self.harmonic(k, f_max, support))]
            for fam, h in runs:
                for f, s in zip(h.freq_hz, h.shapes):
                    ks.append(k)
                    fs.append(f)
                    fams.append(fam)
                    shapes.append(s)
        return ModeTable(
            k=np.array(ks, dtype=int), freq_hz=np.array(fs), family=fams, shapes=shapes, mesh=self.mesh
        )

    # ----------------------------------------------------- axle-fixed model
    def axle_fixed(
        self,
        speed: float,
        k_max: int = 6,
        f_max: float = 3000.0,
        damping_ratio: float = 0.005,
        centrifugal: bool = True,
    ) -> AxleFixedModel:
        """The axle-fixed modal model (eq. 11) at a running speed, in its bogie.

        Basis: per k the modes with the journals on the primary suspension
        (vertical stiffness for both transverse directions); the difference of
        the longitudinal stiffness is added on the Q_B block at k = 1 (the
        journal centres are on the axis, so the spring is constant in this
        frame). The spin mode (rigid rotation, k = 0) is left out: the rolling
        speed is prescribed.

        Parameters
        ----------
        speed : float
            Running speed, m/s (>= 0). omega = speed / r0.
        k_max : int
            Highest harmonic kept.
        f_max : float
            Highest mode frequency kept, Hz.
        damping_ratio : float
            Modal damping ratio of every mode.
        centrifugal : bool
            Keep the centrifugal terms: spin softening -omega^2 Mc and the
            geometric stiffness of the centrifugal prestress +omega^2 K_sigma.

        Returns
        -------
        AxleFixedModel
        """
        speed = _checks.non_negative("speed", speed)
        zeta = _checks.non_negative("damping_ratio", damping_ratio)
        k_max = check_harmonic(k_max, "k_max")
        om = speed / self.geometry.wheel_radius
        blocks_g, blocks_kk, blocks_d, fam, kq, fq, cont, jour = [], [], [], [], [], [], [], []
        dk = self.suspension.longitudinal - self.suspension.vertical
        for k in range(k_max + 1):
            h = self.harmonic(k, f_max, "suspension", "vertical")
            keep = np.ones(h.freq_hz.size, dtype=bool)
            if k == 0:
                theta_frac = np.array([np.sum(s[:, 2] ** 2) / np.sum(s**2) for s in h.shapes])
                keep = ~((h.freq_hz < 0.5) & (theta_frac > 0.9))
            lam = h.lam[keep]
            gam = h.coriolis[np.ix_(keep, keep)]
            mc = h.inplane_mass[np.ix_(keep, keep)] if centrifugal else np.zeros_like(gam)
            if centrifugal:
                mc = mc - h.prestress_stiffness[np.ix_(keep, keep)]
            shp = h.shapes[keep]
            n = lam.size
            if n == 0:
                continue
            gk, kd, dmp = eq11_blocks(lam, gam, mc, k, om, zeta)
            blocks_g.append(gk)
            blocks_d.append(dmp)
            if k == 0:
                blocks_kk.append(kd)
                fam += ["0"] * n
                kq += [0] * n
                fq += list(h.freq_hz[keep])
                c = np.zeros((2, 3, n))
                j = np.zeros((2, 3, n))
                for side in range(2):
                    s = shp[:, self._contact_nodes[side], :]
                    c[side] = [s[:, 1], -s[:, 0], s[:, 2]]
                    sj = shp[:, self._journal_nodes[side], :]
                    j[side] = [sj[:, 1], np.zeros(n), np.zeros(n)]
            else:
                kb = kd.copy()
                if k == 1:
                    for nj in self._journal_nodes:
                        pj = shp[:, nj, 0]
                        kb = kb + dk * np.outer(pj, pj)
                blocks_kk.append(np.block([[kd, np.zeros((n, n))], [np.zeros((n, n)), kb]]))
                fam += ["A"] * n + ["B"] * n
                kq += [k] * (2 * n)
                fq += list(h.freq_hz[keep]) * 2
                c = np.zeros((2, 3, 2 * n))
                j = np.zeros((2, 3, 2 * n))
                for side in range(2):
                    s = shp[:, self._contact_nodes[side], :]
                    # azimuth 0: set A gives (phi_r, phi_y, 0), set B (0, 0, -phi_th)
                    c[side, 0, :n] = s[:, 1]
                    c[side, 1, :n] = -s[:, 0]
                    c[side, 2, n:] = -s[:, 2]
                    sj = shp[:, self._journal_nodes[side], :]
                    if k == 1:
                        j[side, 1, :n] = -sj[:, 0]
                        j[side, 2, n:] = sj[:, 0]
            cont.append(c)
            jour.append(j)
        from scipy.linalg import block_diag

        return AxleFixedModel(
            speed=speed,
            omega=om,
            k=np.array(kq),
            family=np.array(fam),
            freq_hz=np.array(fq),
            mass=np.eye(len(kq)),
            gyro=block_diag(*blocks_g),
            damping=block_diag(*blocks_d),
            stiffness=block_diag(*blocks_kk),
            contact=np.concatenate(cont, axis=2),
            journal=np.concatenate(jour, axis=2),
        )

    def flexible_body(
        self,
        speed: float,
        k_max: int = 2,
        f_max: float = 800.0,
        damping_ratio: float = 0.005,
        centrifugal: bool = True,
        residual_s: tuple[float, float] = (0.0, 0.0),
        ds: float = 1e-3,
        residual: bool = True,
        residual_k_max: int | None = None,
    ) -> "FlexibleWheelset":
        """The free-free elastic wheelset in the axle-fixed frame, for a vehicle model.

        Elastic modes of the free wheelset (no suspension: the vehicle attaches the journal
        springs to its moving bogie frame through the journal rows), rigid-body modes removed
        (k = 0 axial translation and spin, k = 1 transverse translations and tilts), as
        Q_A/Q_B pairs with constant matrices (eq. 11), contact rows along the rim edge, the
        rigid-elastic Coriolis coupling, the polar moment and the residual flexibility of the
        truncated modes (docs/wheelset_flexible.md).

        Parameters
        ----------
        speed : float
            Running speed, m/s (>= 0); Omega = speed / r0.
        k_max : int
            Highest harmonic kept. Default 2 and f_max 800 Hz (15 coordinates) from
            validation/wheelset_truncation.py: every FRF peak below 600 Hz at 300 km/h within
            0.02 % of the f_max 5 kHz / k_max 6 model, the static deflection exact through
            the residual flexibility (kept modes alone: 16 % camber error).
        f_max : float
            Highest free-free mode frequency kept, Hz (> 0).
        damping_ratio : float
            Modal damping ratio of every elastic mode.
        centrifugal : bool
            Keep the centrifugal softening and prestress terms of K.
        residual_s : (float, float)
            Wheel-profile coordinates (right, left) of the contact points at which the
            residual flexibility is computed, m.
        ds : float
            Step of the contact-row tables over the wheel-profile coordinate, m.
        residual : bool
            Compute the residual flexibility (static FE solves of harmonics
            0..residual_k_max).
        residual_k_max : int, optional
            Highest harmonic whose truncated modes enter the residual flexibility; default
            max(k_max, 6). Higher harmonics (the rim's local deformation under the contact
            load) are left to the contact model.

        Returns
        -------
        FlexibleWheelset

        Raises
        ------
        InputError
            A negative speed, f_max <= 0, a bad k_max, s outside the rim edge.
        """
        return flexible_body(
            self,
            speed,
            k_max=k_max,
            f_max=f_max,
            damping_ratio=damping_ratio,
            centrifugal=centrifugal,
            residual_s=residual_s,
            ds=ds,
            residual=residual,
            residual_k_max=residual_k_max,
        )

    def frf(
        self,
        freqs: np.ndarray,
        speed: float,
        input: str = "lateral",
        output: str = "lateral",
        k_max: int = 6,
        f_max: float = 3000.0,
        damping_ratio: float = 0.005,
        model: AxleFixedModel | None = None,
    ) -> np.ndarray:
        """Point receptance at the right contact point of the wheelset in its bogie.

        Parameters
        ----------
        freqs : array_like
            Frequencies, Hz (>= 0).
        speed : float
            Running speed, m/s.
        input, output : {'lateral', 'vertical', 'longitudinal'}
            Force and displacement directions at the contact point.
        k_max, f_max, damping_ratio
            Modal basis and damping, as :meth:`axle_fixed`.
        model : AxleFixedModel, optional
            A model already built at this speed (then k_max, f_max, damping are ignored).

        Returns
        -------
        ndarray of complex (nf,)
            Receptance, m/N.

        Raises
        ------
        InputError
            A bad direction, a negative or non-finite frequency or speed.
        ConvergenceError
            The dynamic matrix is singular at a frequency (named in the message).
        """
        for name, v in (("input", input), ("output", output)):
            if v not in _DIRECTIONS:
                raise InputError(f"{name} must be one of {_DIRECTIONS}, got {v!r}")
        f = _checks.finite_array("freqs", freqs, ndim=1)
        if np.any(f < 0):
            raise InputError("freqs must be >= 0")
        m = model if model is not None else self.axle_fixed(speed, k_max, f_max, damping_ratio)
        fin = np.asfortranarray(m.contact[0, _DIRECTIONS.index(input)][:, None])
        fout = np.asfortranarray(m.contact[0, _DIRECTIONS.index(output)][:, None])
        h, info, idx = core.wheelset_frf_c(
            np.asfortranarray(m.mass),
            np.asfortranarray(m.gyro + m.damping),
            np.asfortranarray(m.stiffness),
            fin,
            fout,
            np.asfortranarray(2.0 * np.pi * f),
        )
        where = f" at {f[idx - 1]} Hz (undamped rigid mode?)" if idx > 0 else ""
        check(info, f"wheelset FRF: dynamic matrix{where}")
        return h[0, 0, :].copy()


__all__ = ["PrimarySuspension", "ModeTable", "AxleFixedModel", "Wheelset"]
