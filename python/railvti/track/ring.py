"""The flexible ring track: 2.5-D FE rails on discrete sleepers, pads and ballast.

Model (see docs/track.md): each rail is the 60E1 section meshed with 6-node triangles, with
trigonometric functions along the ring of length L = n_sl * spacing (kappa = 2 pi k / L);
rails inclined 1:40 sit on rigid sleepers (lateral, vertical, roll) through pads spread over
the rail seat, sleepers on ballast springs and dampers. The rail is first reduced per wave
number (modes up to ``f_cut`` plus residual static responses to rail-head and foot loads),
then each cyclic group j of the ring is solved for its modes (track_ring.f90).
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _cache, _checks
from .._native import core
from .._status import Status, check, error
from ..errors import ConvergenceError, InputError
from .section import RailSection, arc_step_si, head_surface, rail_section, t6_shape

log = logging.getLogger(__name__)

#: Default parameters of a typical ballasted track, SI units. Sources:
#: rail steel and loss factor: Thompson, Railway Noise and Vibration (Elsevier 2009), ch. 3
#: (E = 210 GPa, rho = 7850 kg/m^3, eta_rail = 0.02); pads, sleeper and ballast: Knothe &
#: Grassie, Veh. Syst. Dyn. 22 (1993) 209-262, table of typical values (pad 100-350 MN/m,
#: half-sleeper 120-160 kg, ballast 50-100 MN/m per rail seat) and Thompson (2009) tables 3.1-3.3
#: (pad loss factor ~0.25 -> viscous c = eta k / omega at ~ 300 Hz; ballast loss factor ~1).
DEFAULTS: dict[str, float] = {
    "sleeper_spacing": 0.6,  # m
    "rail_young": 2.1e11,  # Pa
    "rail_poisson": 0.3,
    "rail_density": 7850.0,  # kg/m^3 (60.2 kg/m with A = 76.7 cm^2)
    "rail_loss_factor": 0.02,
    "rail_distance": 1.5,  # m between rail axes (1435 mm gauge + head width ~ 1.5 m)
    "cant": 1.0 / 40.0,  # rail inclination (tan)
    "pad_stiffness_vertical": 200e6,  # N/m per rail seat
    "pad_stiffness_lateral": 40e6,  # N/m per rail seat
    "pad_stiffness_longitudinal": 40e6,  # N/m per rail seat
    "pad_damping_vertical": 25e3,  # N s/m per rail seat (eta 0.25 at ~300 Hz)
    "pad_damping_lateral": 5e3,  # N s/m per rail seat
    "pad_damping_longitudinal": 5e3,  # N s/m per rail seat
    "pad_length": 0.15,  # m along the rail (seat width of a B70-type sleeper)
    "sleeper_mass": 280.0,  # kg, whole monoblock sleeper (2 x 140 kg)
    "sleeper_length": 2.6,  # m, for the roll inertia and ballast roll stiffness
    "ballast_stiffness_vertical": 160e6,  # N/m per sleeper (80 MN/m per rail seat)
    "ballast_stiffness_lateral": 40e6,  # N/m per sleeper
    "ballast_damping_vertical": 120e3,  # N s/m per sleeper
    "ballast_damping_lateral": 60e3,  # N s/m per sleeper
}

#: Numerical settings (not physics) and their defaults.
NUMERICS: dict[str, float] = {
    "f_max": 3000.0,  # Hz, highest frequency of interest
    "f_cut_factor": 2.0,  # rail modes kept per wave number up to f_cut_factor * f_max
    "kappa_max": 50.0,  # rad/m, highest rail wave number in the series
    "mesh_max_area": 2e-4,  # m^2, largest triangle of the section mesh
    "arc_step": 8e-3,  # m, spacing of outline points on arcs (arc_step_mm: deprecated mm)
    "n_samples": 12,  # sample wave numbers of the rail's reduced basis
}

_POSITIVE = [k for k in DEFAULTS if k not in ("cant",)]


@dataclass(frozen=True)
class TrackModes:
    """Track modes up to a frequency.

    Attributes
    ----------
    freq : ndarray
        Natural frequencies, Hz (ascending).
    damping_ratio : ndarray
        Modal damping ratio c / (2 omega) of the diagonal modal damping.
    group : ndarray
        Cyclic group j of each mode (0..n_sl/2): the sleeper-pattern wave number.
    """

    freq: np.ndarray
    damping_ratio: np.ndarray
    group: np.ndarray


def _foot_quadrature(sec: RailSection) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pad points on the foot underside: eta_p, weights, interpolation P (np, 3, ndof)."""
    g = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
    wg = np.array([5.0, 8.0, 5.0]) / 9.0
    ndof = 3 * sec.n_nodes
    etas, ws, rows = [], [], []
    for a, b, m in sec.foot_edges:
        ya, yb = sec.nodes[a, 0], sec.nodes[b, 0]
        for s, w in zip(g, wg):
            n = {a: s * (s - 1) / 2, b: s * (s + 1) / 2, m: 1 - s * s}
            etas.append(0.5 * (ya + yb) + 0.5 * s * (yb - ya))
            ws.append(w * abs(yb - ya) / 2)
            rows.append(n)
    p = np.zeros((len(etas), 3, ndof))
    for i, n in enumerate(rows):
        for node, v in n.items():
            for c in range(3):
                p[i, c, 3 * node + c] = v
    return np.array(etas), np.array(ws), p


_NODE_L = np.array(
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]]
)  # T6 nodes, area coords


def _node_observation(sec: RailSection, node: int) -> np.ndarray:
    """Rows u_x, u_eta, u_zeta at a section node and its roll 1/2 (du_zeta/deta - du_eta/dzeta),
    the curl averaged over the elements that hold the node (a continuous recovered field)."""
    ndof = 3 * sec.n_nodes
    o = np.zeros((4, ndof))
    for c in range(3):
        o[c, 3 * node + c] = 1.0
    cnt = 0
    for el in sec.elements:
        hit = np.where(el == node)[0]
        if hit.size == 0:
            continue
        _, dn = t6_shape(_NODE_L[hit[0]][None, :])
        xy = sec.nodes[el]
        jac = dn[0].T @ xy  # (2 l, 2 yz)
        dxy = dn[0] @ np.linalg.inv(jac).T  # (6, 2)
        for a in range(6):
            o[3, 3 * el[a] + 2] += 0.5 * dxy[a, 0]
            o[3, 3 * el[a] + 1] -= 0.5 * dxy[a, 1]
        cnt += 1
    o[3] /= max(cnt, 1)
    return o


def _crown_observation(sec: RailSection) -> np.ndarray:
    """Rows: u_x, u_eta, u_zeta at the crown node and the roll 1/2 (du_zeta/deta - du_eta/dzeta)."""
    return _node_observation(sec, sec.crown_node)


def section_fe(
    sec: RailSection, young: float, poisson: float, density: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Section matrices K0, K1, K2, M of the 2.5-D FE (Fortran track_section).

    Raises
    ------
    InputError
        A node number out of range, or an element with a non-positive Jacobian.
    """
    k0, k1, k2, m, info, bad = core.track_section_matrices_c(
        np.asfortranarray(sec.nodes),
        np.asfortranarray(sec.elements + 1, dtype=np.int32),
        young,
        poisson,
        density,
    )
    where = f" (element {bad - 1}, 0-based)" if info == Status.BAD_ELEMENT else ""
    check(info, f"section mesh rejected by the FE assembly{where}")
    return k0, k1, k2, m


class RingTrack:
    """Ballasted ring track of ``n_sleepers`` sleeper bays with 2.5-D FE rails.

    Parameters
    ----------
    n_sleepers : int
        Number of sleepers on the ring (>= 2); ring length L = n_sleepers * sleeper_spacing.
    section : RailSection, optional
        The meshed rail section (default: 60E1 with ``mesh_max_area``).
    **params
        Any key of :data:`DEFAULTS` (track physics, SI units) or :data:`NUMERICS` (SI:
        ``arc_step`` in m; ``arc_step_mm``, the same in mm, is deprecated).

    Raises
    ------
    InputError
        Unknown key, negative stiffness/mass/damping, spacing <= 0, n_sleepers < 2;
        ``arc_step`` above 0.05 m (a mm value: the message says so), or given twice.
    """

    def __init__(self, n_sleepers: int, section: RailSection | None = None, **params: Any) -> None:
        self.n_sleepers = _checks.positive_int("n_sleepers", n_sleepers, minimum=2)
        params = dict(params)
        arc_step_mm = params.pop("arc_step_mm", None)
        unknown = set(params) - set(DEFAULTS) - set(NUMERICS)
        if unknown:
            raise InputError(f"unknown track parameter(s): {sorted(unknown)}")
        p = {**DEFAULTS, **NUMERICS, **params}
        p["arc_step"] = arc_step_si(params.get("arc_step"), arc_step_mm, NUMERICS["arc_step"])
        for k in DEFAULTS:
            p[k] = _checks.finite(k, p[k])
        for k in _POSITIVE:
            if k.startswith(("pad_damping", "ballast_damping")) or k == "rail_loss_factor":
                p[k] = _checks.non_negative(k, p[k])
            else:
                p[k] = _checks.positive(k, p[k])
        if not 0.0 <= p["rail_poisson"] < 0.5:
            raise InputError(f"rail_poisson must lie in [0, 0.5), got {p['rail_poisson']}")
        if abs(p["cant"]) > 0.2:
            raise InputError(f"cant must be a small inclination |tan| <= 0.2, got {p['cant']}")
        for k in ("f_max", "f_cut_factor", "kappa_max", "mesh_max_area"):
            p[k] = _checks.positive(k, p[k])
        if p["f_cut_factor"] < 1.0:
            raise InputError(f"f_cut_factor must be >= 1, got {p['f_cut_factor']}")
        p["n_samples"] = _checks.positive_int("n_samples", p["n_samples"], minimum=2)
        self.params = p
        self.length = self.n_sleepers * p["sleeper_spacing"]
        t0 = time.perf_counter()
        self.section = (
            section if section is not None else rail_section(p["mesh_max_area"], arc_step=p["arc_step"])
        )
        # the eigen-solves' outputs on disk (railvti._cache): a later process replays them
        sec = self.section
        mesh = (sec.nodes, sec.elements, sec.outline, sec.crown_node, sec.foot_edges)
        rec = _cache.Recorder("ring", self.n_sleepers, tuple(sorted(p.items())), mesh)
        self._build_rail(rec)
        t1 = time.perf_counter()
        self._build_groups(rec)
        rec.finish()
        self.build_time = (t1 - t0, time.perf_counter() - t1)
        log.info(
            "ring track n_sl=%d: %d modes, rail %.2f s, groups %.2f s",
            self.n_sleepers,
            self.lam.size,
            *self.build_time,
        )

    # ------------------------------------------------------------------ build
    def _build_rail(self, rec: _cache.Recorder) -> None:
        p, sec = self.params, self.section
        k0, k1, k2, m = section_fe(sec, p["rail_young"], p["rail_poisson"], p["rail_density"])
        self._fe = (k0, k1, k2, m)
        ndof = k0.shape[0]
        self.eta_p, self.w_p, self._pad_interp = _foot_quadrature(sec)
        self._obs = _crown_observation(sec)
        self.head = head_surface(sec)
        self._head_nodes = np.unique(self.head.edges)
        self._head_obs = np.vstack([_node_observation(sec, int(i)) for i in self._head_nodes])
        cn = sec.crown_node
        f = np.zeros((ndof, 4), order="F")
        f[3 * cn + 1, 0] = 1.0  # crown lateral force
        f[3 * cn + 2, 1] = 1.0  # crown vertical force
        f[:, 2] = self._pad_interp[:, 2, :].T @ self.w_p  # uniform pad pressure
        f[:, 3] = self._pad_interp[:, 1, :].T @ self.w_p  # uniform pad shear
        f /= np.linalg.norm(f, axis=0)
        f_cut = p["f_cut_factor"] * p["f_max"]
        lam_cut = (2 * math.pi * f_cut) ** 2
        kmax = p["kappa_max"]
        ns = int(p["n_samples"])
        kap_s = kmax * np.linspace(0.0, 1.0, ns) ** 1.5  # denser where modes change fastest
        rmax = int(min(ndof, 40 * ns))
        r, w, k0r, k1r, k2r, fr, info, s, linfo = rec.call(
            "track_reduced_basis_c", core.track_reduced_basis_c, k0, k1, k2, m, f, kap_s, 2.25 * lam_cut, rmax
        )
        if info != Status.OK:
            raise error(
                info,
                f"rail reduced basis at sample wave number {kap_s[s - 1]:.4g} rad/m (LAPACK info {linfo})",
            )
        if r >= rmax:
            log.warning("rail reduced basis full (%d vectors): later vectors were dropped", r)
        w, k0r, k1r, k2r, fr = w[:, :r], k0r[:r, :r], k1r[:r, :r], k2r[:r, :r], fr[:r]
        self._rom = (w, k0r, k1r, k2r, fr)
        n_k = int(math.floor(kmax * self.length / (2 * math.pi)))
        self.k_max = n_k
        kap = 2 * math.pi * np.arange(n_k + 1) / self.length
        mmax = min(60, r)
        while True:
            nm, om2, y, info, ik, linfo = rec.call(
                "track_wave_basis_c",
                core.track_wave_basis_c,
                np.asfortranarray(k0r),
                np.asfortranarray(k1r),
                np.asfortranarray(k2r),
                np.asfortranarray(fr),
                kap,
                lam_cut,
                mmax,
            )
            if info != Status.SIZE_MISMATCH or mmax >= r:
                break
            mmax = min(2 * mmax, r)  # more basis vectors at one wave number than mmax
        if info != Status.OK:
            raise error(info, f"rail wave basis at wave number {kap[ik - 1]:.4g} rad/m (LAPACK info {linfo})")
        pw = np.einsum("pcn,nr->pcr", self._pad_interp, w)
        ow = self._obs @ w
        hw = self._head_obs @ w
        self._rail = []  # per k: (kappa, om2, pad traces (np,3,nm), obs (4,nm), y)
        self._rail_head = []  # per k: head-node observations (4 nh, nm)
        for k in range(n_k + 1):
            yk = y[:, : nm[k], k]
            norm = 1.0 / math.sqrt(self.length if k == 0 else 0.5 * self.length)
            self._rail.append(
                (
                    kap[k],
                    om2[: nm[k], k].copy(),
                    np.einsum("pcr,rm->pcm", pw, yk) * norm,
                    (ow @ yk) * norm,
                    yk * norm,
                )
            )
            self._rail_head.append((hw @ yk) * norm)

    def _build_groups(self, rec: _cache.Recorder) -> None:
        p, n = self.params, self.n_sleepers
        cant = math.atan(p["cant"])
        y0 = np.array([-0.5, 0.5]) * p["rail_distance"]
        beta = np.array([-cant, cant])
        foot_w = self.w_p.sum()
        area = p["pad_length"] * foot_w
        kpad = (
            np.array(
                [p["pad_stiffness_longitudinal"], p["pad_stiffness_lateral"], p["pad_stiffness_vertical"]]
            )
            / area
        )
        cpad = (
            np.array([p["pad_damping_longitudinal"], p["pad_damping_lateral"], p["pad_damping_vertical"]])
            / area
        )
        ls = p["sleeper_length"]
        ms = np.array([p["sleeper_mass"], p["sleeper_mass"], p["sleeper_mass"] * ls * ls / 12])
        kb = np.array(
            [
                p["ballast_stiffness_lateral"],
                p["ballast_stiffness_vertical"],
                p["ballast_stiffness_vertical"] * ls * ls / 12,
            ]
        )
        cb = np.array(
            [
                p["ballast_damping_lateral"],
                p["ballast_damping_vertical"],
                p["ballast_damping_vertical"] * ls * ls / 12,
            ]
        )
        gx, gw = np.polynomial.legendre.leggauss(16)
        xi, w_xi = 0.5 * p["pad_length"] * gx, 0.5 * p["pad_length"] * gw
        self._geom = (y0, beta)
        bpos, mpos, vpos = [0], [0], [0]
        kap_l, fam_l, rail_l, obs_l, lam_l, cm_l, grp_l, v_l = [], [], [], [], [], [], [], []
        head_l = []
        for j in range(n // 2 + 1):
            kap, fam, sgn, rail, om2, tr, obs, head = [], [], [], [], [], [], [], []
            for rho in (1, 2):
                for k, (kp, o2, trk, obk, _) in enumerate(self._rail):
                    km = k % n
                    if km != j and km != (n - j) % n:
                        continue
                    s = 1 if km == j else -1
                    for f in (0,) if k == 0 else (1, 2):
                        for i in range(o2.size):
                            kap.append(kp)
                            fam.append(f)
                            sgn.append(s)
                            rail.append(rho)
                            om2.append(o2[i])
                            tr.append(trk[:, :, i])
                            obs.append(obk[:, i])
                            head.append(self._rail_head[k][:, i])
            nb = len(kap)
            nsd = 6 if (j != 0 and 2 * j != n) else 3
            ntot = nb + nsd
            lam, v, cm, info, linfo = rec.call(
                "track_group_modes_c",
                core.track_group_modes_c,
                np.array(om2),
                np.array(kap),
                np.array(fam, np.int32),
                np.array(sgn, np.int32),
                np.array(rail, np.int32),
                np.asfortranarray(np.stack(tr, axis=2)),
                self.eta_p,
                self.w_p,
                xi,
                w_xi,
                kpad,
                cpad,
                y0,
                beta,
                ms,
                kb,
                cb,
                n,
                j,
                p["rail_loss_factor"],
                ntot,
            )
            check(info, f"ring group {j}: eigen-solver (LAPACK info {linfo})")
            if lam.min() <= 0:
                raise ConvergenceError(f"ring group {j}: non-positive eigenvalue {lam.min():.3g}")
            kap_l += kap
            fam_l += fam
            rail_l += rail
            obs_l += obs
            head_l += head
            lam_l.append(lam)
            cm_l.append(cm)
            grp_l.append(np.full(ntot, j))
            v_l.append(v.ravel(order="F"))
            bpos.append(bpos[-1] + nb)
            mpos.append(mpos[-1] + ntot)
            vpos.append(vpos[-1] + ntot * ntot)
        self.kap = np.array(kap_l)
        self.fam = np.array(fam_l, np.int32)
        self.rail = np.array(rail_l, np.int32)
        self.obs = np.asfortranarray(np.array(obs_l).T)
        # head-node observations: (node of self._head_nodes, row x/eta/zeta/roll, basis function)
        self._head_basis = np.array(head_l).T.reshape(self._head_nodes.size, 4, -1)
        self.lam = np.concatenate(lam_l)
        self.cmod = np.concatenate(cm_l)
        self.group = np.concatenate(grp_l)
        self.vflat = np.concatenate(v_l)
        self.bpos = np.array(bpos, np.int32)
        self.mpos = np.array(mpos, np.int32)
        self.vpos = np.array(vpos, np.int32)

    # -------------------------------------------------------------- interface
    @property
    def n_modes(self) -> int:
        """Number of modes of the modal form (all groups, including the quasi-static ones)."""
        return int(self.lam.size)

    def head_shapes(self, x: float, rail: int, s: float | None = None) -> np.ndarray:
        """Rail-head values of every mode at position x on a rail.

        Parameters
        ----------
        x : float
            Position along the ring, m (sleeper s sits at x = s * spacing).
        rail : int
            1 (left, y < 0) or 2 (right, y > 0); the ring's y points to the right.
        s : float, optional
            Lateral position of the point on the head's running surface, m, in the rail's own
            section frame: eta from the rail's axis, along the ring's +y tilted by the rail's
            cant (so towards the track centre on rail 1, away from it on rail 2). The point
            is on the surface of the section mesh (:attr:`head`, its height and slope from
            ``head.point(s)``); its values are the section field interpolated along the
            surface edge (quadratic), the roll from the nodal averages of the curl. Default:
            the crown node (s = 0 gives the same values).

        Returns
        -------
        ndarray (4, n_modes)
            Rows: longitudinal, lateral (y), vertical (z) displacement, m, and roll rotation
            about x, rad, in the track frame, per unit modal coordinate.

        Raises
        ------
        InputError
            x not finite, rail not 1 or 2, s off the head surface.
        """
        return self._eval(x, rail, s, dx=False)

    def head_shapes_dx(self, x: float, rail: int, s: float | None = None) -> np.ndarray:
        """Derivative along x of :meth:`head_shapes`, per m: the convective rows.

        A contact point moving at speed v0 along the ring sees the rail head's velocity
        ``head_shapes(x_c) @ dq/dt + v0 * head_shapes_dx(x_c) @ q``. Exact (the
        trigonometric functions differentiated), same arguments and rows as
        :meth:`head_shapes`.
        """
        return self._eval(x, rail, s, dx=True)

    def contact_rows(
        self, x: np.ndarray, rail: np.ndarray, s: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Head shapes and their x-derivatives at several contact points (one time step).

        Parameters
        ----------
        x : array_like (n,)
            Contact points' positions along the ring, m (taken modulo the ring length).
        rail : array_like of int (n,)
            Rail of each point, 1 (left) or 2 (right).
        s : array_like (n,), optional
            Lateral positions on the head surface, m (see :meth:`head_shapes`); default the
            crown for all.

        Returns
        -------
        shapes, shapes_dx : ndarray (n, 4, n_modes)
            :meth:`head_shapes` and :meth:`head_shapes_dx` of each point (track frame).
        """
        xs = _checks.finite_array("x", x, ndim=1)
        rails = np.asarray(rail).reshape(-1)
        if rails.shape != xs.shape:
            raise InputError(f"rail must have the shape of x {xs.shape}, got {rails.shape}")
        if s is None:
            ss: list[float | None] = [None] * xs.size
        else:
            sa = _checks.finite_array("s", s, ndim=1)
            if sa.shape != xs.shape:
                raise InputError(f"s must have the shape of x {xs.shape}, got {sa.shape}")
            ss = [float(v) for v in sa]
        xs = np.mod(xs, self.length)
        shapes = np.empty((xs.size, 4, self.n_modes))
        dx = np.empty_like(shapes)
        for i, (xi, ri, si) in enumerate(zip(xs, rails, ss)):
            shapes[i] = self._eval(float(xi), int(ri), si, dx=False)
            dx[i] = self._eval(float(xi), int(ri), si, dx=True)
        return shapes, dx

    def _eval(self, x: float, rail: int, s: float | None, dx: bool) -> np.ndarray:
        x = _checks.finite("x", x)
        if rail not in (1, 2):
            raise InputError(f"rail must be 1 or 2, got {rail!r}")
        if s is None:
            obs = self.obs
        else:
            nodes, wts = self.head.weights(s)
            idx = np.searchsorted(self._head_nodes, nodes)
            obs = np.asfortranarray(np.tensordot(wts, self._head_basis[idx], axes=1))
        fam = self.fam
        if dx:
            # d/dx of family 1 (sin for u_x, cos else) is -kappa times family 2's function
            # (-cos, sin), and d/dx of family 2 is +kappa times family 1's; k = 0 is constant.
            factor = np.where(fam == 1, -self.kap, np.where(fam == 2, self.kap, 0.0))
            obs = np.asfortranarray(obs * factor[None, :])
            fam = np.where(fam == 1, 2, np.where(fam == 2, 1, fam)).astype(np.int32)
        psi = core.track_eval_x_c(
            self.bpos, self.mpos, self.vpos, self.kap, fam, self.rail, obs, self.vflat, self.n_modes, x, rail
        )
        b = self._geom[1][rail - 1]
        c, sn = math.cos(b), math.sin(b)
        out = np.empty_like(psi)
        out[0] = psi[0]
        out[1] = c * psi[1] - sn * psi[2]
        out[2] = sn * psi[1] + c * psi[2]
        out[3] = psi[3]
        return out

    def generalized_forces(self, x: float, rail: int, force: np.ndarray) -> np.ndarray:
        """Modal forces of a force/moment (Fx, Fy, Fz N, Mx N m) on the rail head at x."""
        f = _checks.finite_array("force", force, shape=(4,))
        return f @ self.head_shapes(x, rail)

    def _pattern(self, x: float, direction: str) -> tuple[np.ndarray, np.ndarray]:
        patterns = {
            "vertical": (2, (1.0, 1.0)),
            "lateral": (1, (-1.0, 1.0)),  # outward on both rails (opposite)
            "vertical_opposite": (2, (-1.0, 1.0)),
            "lateral_inphase": (1, (1.0, 1.0)),
        }
        if direction not in patterns:
            raise InputError(f"direction must be one of {sorted(patterns)}, got {direction!r}")
        comp, sign = patterns[direction]
        h1, h2 = self.head_shapes(x, 1), self.head_shapes(x, 2)
        q = sign[0] * h1[comp] + sign[1] * h2[comp]
        return h2[comp], q

    def _position(self, position: str | float) -> float:
        a = self.params["sleeper_spacing"]
        if position == "midspan":
            return 0.5 * a
        if position == "sleeper":
            return 0.0
        if isinstance(position, str):
            raise InputError(f"position must be 'midspan', 'sleeper' or a number, got {position!r}")
        return _checks.finite("position", position)

    def receptance(
        self, freqs: np.ndarray, direction: str = "vertical", position: str | float = "midspan"
    ) -> np.ndarray:
        """Rail-head receptance of the right rail, m/N.

        Parameters
        ----------
        freqs : array_like
            Frequencies, Hz (>= 0).
        direction : {'vertical', 'lateral', 'vertical_opposite', 'lateral_inphase'}
            'vertical': unit vertical forces in phase on both rails, vertical displacement.
            'lateral': unit lateral forces in opposite directions (outward) on the two rails,
            lateral displacement. The other two swap the phase (used to fit TrackElement).
        position : {'midspan', 'sleeper'} or float
            Load and response position x, m.

        Returns
        -------
        ndarray of complex
            Displacement of the right rail's crown per unit force.
        """
        f = _checks.finite_array("freqs", freqs, ndim=1)
        if np.any(f < 0):
            raise InputError("freqs must be >= 0")
        out, q = self._pattern(self._position(position), direction)
        hr, hi = core.track_frf_c(self.lam, self.cmod, out * q, f)
        return hr + 1j * hi

    def head_receptance(self, freqs: np.ndarray, x: float, rail: int) -> np.ndarray:
        """Point receptance matrix of one rail's head at x, in the track frame.

        Parameters
        ----------
        freqs : array_like
            Frequencies, Hz (>= 0).
        x : float
            Load and response position along the ring, m.
        rail : int
            1 (left, y < 0) or 2 (right, y > 0); y points to the right (docs/track.md).

        Returns
        -------
        ndarray of complex, shape (nf, 4, 4)
            ``H[f, i, j]``: response i (u_x, u_y, u_z in m, roll about x in rad) to a unit
            load j (F_x, F_y, F_z in N, M_x in N m) at the same point of the same rail.
        """
        f = _checks.finite_array("freqs", freqs, ndim=1)
        if np.any(f < 0):
            raise InputError("freqs must be >= 0")
        h = self.head_shapes(x, rail)
        out = np.empty((f.size, 4, 4), complex)
        for i in range(4):
            for j in range(i, 4):
                hr, hi = core.track_frf_c(self.lam, self.cmod, h[i] * h[j], f)
                out[:, i, j] = out[:, j, i] = hr + 1j * hi
        return out

    def static_modal(self, direction: str = "vertical", position: str | float = "midspan") -> float:
        """Static deflection per unit load from the modal sum (all modes), m/N."""
        out, q = self._pattern(self._position(position), direction)
        return float(np.sum(out * q / self.lam))

    def modes(self, f_max: float | None = None) -> TrackModes:
        """Natural frequencies up to ``f_max`` (Hz; default the model's f_max)."""
        fm = self.params["f_max"] if f_max is None else _checks.positive("f_max", f_max)
        om = np.sqrt(self.lam)
        sel = np.where(om <= 2 * math.pi * fm)[0]
        sel = sel[np.argsort(om[sel])]
        return TrackModes(
            freq=om[sel] / (2 * math.pi), damping_ratio=self.cmod[sel] / (2 * om[sel]), group=self.group[sel]
        )


__all__ = ["DEFAULTS", "NUMERICS", "TrackModes", "section_fe", "RingTrack"]
