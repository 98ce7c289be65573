"""Reference static solutions of the ring track, for the tests (not part of the package).

``static_direct``: direct static solve of the full 2.5-D FE ring track (every section DOF,
same Fourier terms): per cyclic group the sparse system of all section DOFs of every rail
wave number in the group, pads and sleepers, solved by SuperLU. It checks the modal
reduction (reduced rail basis, residual attachments, group eigenproblems) against the
unreduced system of the same discretisation. Costly: small rings and coarse meshes only.

``beam_on_sleepers_static``: an independent model of the same track, a Timoshenko (or
Euler-Bernoulli) beam on the same ring of discrete pads, sleepers and ballast, by finite
elements along x in physical space (no Fourier series, no cross-section mesh).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def _fg(fam: int, sgn: int, c: int, kx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if fam == 1:
        return (np.sin(kx), sgn * np.cos(kx)) if c == 0 else (np.cos(kx), -sgn * np.sin(kx))
    if fam == 2:
        return (-np.cos(kx), sgn * np.sin(kx)) if c == 0 else (np.sin(kx), sgn * np.cos(kx))
    return np.ones_like(kx), np.zeros_like(kx)


def _trig(fam: int, c: int, kx: float) -> float:
    if fam == 1:
        return math.sin(kx) if c == 0 else math.cos(kx)
    if fam == 2:
        return -math.cos(kx) if c == 0 else math.sin(kx)
    return 1.0


def static_direct(track, direction: str = "vertical", position="midspan") -> float:
    """Static crown deflection of the right rail per unit load, m/N, by a direct sparse solve.

    Same load pattern as :meth:`RingTrack.receptance` at zero frequency.
    """
    p, n = track.params, track.n_sleepers
    x = track._position(position)
    k0, k1, k2, _ = track._fe
    ndof = k0.shape[0]
    cn = track.section.crown_node
    y0, beta = track._geom
    comp, sign = (2, (1.0, 1.0)) if direction == "vertical" else (1, (-1.0, 1.0))
    foot_w = track.w_p.sum()
    area = p["pad_length"] * foot_w
    kpad = (
        np.array([p["pad_stiffness_longitudinal"], p["pad_stiffness_lateral"], p["pad_stiffness_vertical"]])
        / area
    )
    ls = p["sleeper_length"]
    kb = np.array(
        [
            p["ballast_stiffness_lateral"],
            p["ballast_stiffness_vertical"],
            p["ballast_stiffness_vertical"] * ls * ls / 12,
        ]
    )
    gx, gw = np.polynomial.legendre.leggauss(16)
    xi, w_xi = 0.5 * p["pad_length"] * gx, 0.5 * p["pad_length"] * gw
    pi_ = track._pad_interp  # (np, 3, ndof)
    pc = [sp.csr_matrix(pi_[:, c, :].T * track.w_p) @ sp.csr_matrix(pi_[:, c, :]) for c in range(3)]
    # sleeper motion -> rail-local at pad points, per rail: rs[rho][c] (np, 3)
    rs = []
    for rho in range(2):
        c_, s_ = math.cos(beta[rho]), math.sin(beta[rho])
        yp = y0[rho] + track.eta_p * c_
        zp = track.eta_p * s_
        r = np.zeros((3, track.eta_p.size, 3))
        r[1] = np.column_stack([np.full_like(yp, c_), np.full_like(yp, s_), -zp * c_ + yp * s_])
        r[2] = np.column_stack([np.full_like(yp, -s_), np.full_like(yp, c_), zp * s_ + yp * c_])
        rs.append(r)
    prs = [[pi_[:, c, :].T @ (track.w_p[:, None] * rs[rho][c]) for c in range(3)] for rho in range(2)]
    total = 0.0
    kmax = track.k_max
    L = track.length
    for j in range(n // 2 + 1):
        use_g = j != 0 and 2 * j != n
        sj = 0.5 * n if use_g else float(n)
        ca = 1.0 / math.sqrt(sj)
        blocks = []
        for rho in range(2):
            for k in range(kmax + 1):
                km = k % n
                if km != j and km != (n - j) % n:
                    continue
                sgn = 1 if km == j else -1
                for fam in (0,) if k == 0 else (1, 2):
                    blocks.append(
                        (rho, k, fam, sgn, 2 * math.pi * k / L, 1 / math.sqrt(L if k == 0 else L / 2))
                    )
        nbk = len(blocks)
        nsd = 6 if use_g else 3
        fg = [[_fg(b[2], b[3], c, b[4] * xi) for c in range(3)] for b in blocks]
        rows = [[None] * (nbk + 1) for _ in range(nbk + 1)]
        for i, bi in enumerate(blocks):
            kap = bi[4]
            rows[i][i] = sp.csr_matrix(k0 + kap * k1 + kap * kap * k2)
            for jj, bj in enumerate(blocks):
                if bi[0] != bj[0]:
                    continue
                acc = None
                for c in range(3):
                    fi, gi = fg[i][c]
                    fj, gj = fg[jj][c]
                    xcoef = np.sum(w_xi * (fi * fj + (gi * gj if use_g else 0)))
                    term = (sj * kpad[c] * xcoef * bi[5] * bj[5]) * pc[c]
                    acc = term if acc is None else acc + term
                rows[i][jj] = acc if rows[i][jj] is None else rows[i][jj] + acc
            # rail-sleeper
            col = np.zeros((ndof, nsd))
            for c in range(3):
                fi, gi = fg[i][c]
                col[:, :3] -= sj * ca * kpad[c] * np.sum(w_xi * fi) * bi[5] * prs[bi[0]][c]
                if use_g:
                    col[:, 3:] -= sj * ca * kpad[c] * np.sum(w_xi * gi) * bi[5] * prs[bi[0]][c]
            rows[i][nbk] = sp.csr_matrix(col)
            rows[nbk][i] = sp.csr_matrix(col.T)
        ss = np.zeros((3, 3))
        for rho in range(2):
            for c in range(3):
                ss += kpad[c] * w_xi.sum() * (rs[rho][c].T * track.w_p) @ rs[rho][c]
        ss += np.diag(kb)
        sl = np.zeros((nsd, nsd))
        sl[:3, :3] = ss
        if use_g:
            sl[3:, 3:] = ss
        rows[nbk][nbk] = sp.csr_matrix(sl)
        kg = sp.bmat(rows, format="csc")
        f = np.zeros(kg.shape[0])
        out = np.zeros(kg.shape[0])
        for i, b in enumerate(blocks):
            rho = b[0]
            c_, s_ = math.cos(beta[rho]), math.sin(beta[rho])
            # track-frame unit vector of the load component -> rail-local (eta, zeta)
            e_track = {2: (0.0, 1.0), 1: (1.0, 0.0)}[comp]  # (y, z) of the unit load
            loc = np.array([0.0, e_track[0] * c_ + e_track[1] * s_, -e_track[0] * s_ + e_track[1] * c_])
            for c in (1, 2):
                t = _trig(b[2], c, b[4] * x) * b[5]
                f[i * ndof + 3 * cn + c] += sign[rho] * loc[c] * t
                if rho == 1:
                    out[i * ndof + 3 * cn + c] += loc[c] * t
        u = spla.spsolve(kg, f)
        total += float(out @ u)
    return total


def beam_on_sleepers_static(
    n_sleepers: int,
    spacing: float,
    young: float,
    poisson: float,
    area: float,
    iy: float,
    centroid_height: float,
    pad_length: float,
    k_pad_vertical: float,
    k_pad_longitudinal: float,
    k_ballast_seat: float,
    x_load: float,
    shear_coefficient: float | None = None,
    elements_per_pad: int = 10,
) -> float:
    """Static vertical deflection per unit vertical load of a beam on discrete supports, m/N.

    One rail of a ring of ``n_sleepers`` bays (length n_sleepers * spacing, ends joined) as a
    beam with axial (u), deflection (w) and section-rotation (theta) fields, linear elements
    with one-point shear integration (no locking). At each sleeper x_s = s * spacing a pad of
    length ``pad_length`` (N/m per rail seat spread uniformly over it) ties the rail to a
    rigid sleeper: vertically between w and the sleeper's w_s, longitudinally between the
    foot's axial displacement u + centroid_height * theta and the (longitudinally fixed)
    sleeper. The sleeper sits on ``k_ballast_seat`` (N/m, the ballast per rail seat: a
    symmetric in-phase load on both rails does not roll the sleeper).

    Parameters
    ----------
    n_sleepers, spacing : int, float
        Number of bays and sleeper spacing, m.
    young, poisson : float
        Rail E (Pa) and Poisson ratio (for G).
    area, iy, centroid_height : float
        Section area m^2, second moment about the horizontal axis m^4, centroid above the
        foot's underside m.
    pad_length : float
        Pad length along the rail, m (a multiple of spacing / elements gives exact edges).
    k_pad_vertical, k_pad_longitudinal, k_ballast_seat : float
        Pad vertical and longitudinal stiffness per rail seat, ballast per rail seat, N/m.
    x_load : float
        Load and response position, m (a node: a multiple of pad_length / elements_per_pad).
    shear_coefficient : float or None
        Timoshenko shear coefficient; None: Euler-Bernoulli (shear rigid).
    elements_per_pad : int
        Elements over the pad length (the element size h = pad_length / elements_per_pad).
    """
    h = pad_length / elements_per_pad
    per_bay = int(round(spacing / h))
    if abs(per_bay * h - spacing) > 1e-9 * spacing:
        raise ValueError("spacing must be a multiple of pad_length / elements_per_pad")
    nn = n_sleepers * per_bay  # beam nodes (periodic)
    ndof = 3 * nn + n_sleepers  # (u, w, theta) per node + w_s per sleeper
    ea, ei = young * area, young * iy
    if shear_coefficient is None:  # Euler-Bernoulli as the shear-rigid limit (penalty)
        kga = 1e6 * ei / (spacing * h)
    else:
        kga = shear_coefficient * young / (2 * (1 + poisson)) * area
    rows, cols, vals = [], [], []

    def add(dofs, k):
        for i, di in enumerate(dofs):
            for j, dj in enumerate(dofs):
                rows.append(di)
                cols.append(dj)
                vals.append(k[i, j])

    half_pad = 0.5 * pad_length / h
    kz, kx = k_pad_vertical / pad_length, k_pad_longitudinal / pad_length  # per length
    lin = h / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])  # int N_i N_j dx
    for e in range(nn):
        a_, b_ = e, (e + 1) % nn
        u, w, t = [3 * a_, 3 * b_], [3 * a_ + 1, 3 * b_ + 1], [3 * a_ + 2, 3 * b_ + 2]
        add(u, ea / h * np.array([[1.0, -1.0], [-1.0, 1.0]]))
        add(t, ei / h * np.array([[1.0, -1.0], [-1.0, 1.0]]))
        bs = np.array([-1 / h, -0.5, 1 / h, -0.5])  # w' - theta at mid-element
        add([w[0], t[0], w[1], t[1]], kga * h * np.outer(bs, bs))
        # pad over [x_s - lp/2, x_s + lp/2]: element mid-point within half a pad of a sleeper
        mid = (e + 0.5) % per_bay
        d = min(mid, per_bay - mid)
        if d < half_pad:
            s = int(round((e + 0.5 - mid) / per_bay + (mid > per_bay / 2))) % n_sleepers
            ws = 3 * nn + s
            # vertical: kz (w - w_s)^2; longitudinal: kx (u + c theta)^2
            col = lin.sum(1, keepdims=True)  # int N_i dx
            add([w[0], w[1], ws], kz * np.block([[lin, -col], [-col.T, np.array([[h]])]]))
            c = centroid_height
            add([u[0], u[1], t[0], t[1]], kx * np.block([[lin, c * lin], [c * lin, c * c * lin]]))
    for s in range(n_sleepers):
        add([3 * nn + s], np.array([[k_ballast_seat]]))
    k = sp.csc_matrix((vals, (rows, cols)), shape=(ndof, ndof))
    i_load = int(round(x_load / h)) % nn
    if abs(i_load * h - x_load % (nn * h)) > 1e-9:
        raise ValueError("x_load must sit on a node")
    f = np.zeros(ndof)
    f[3 * i_load + 1] = 1.0
    return float(spla.spsolve(k, f)[3 * i_load + 1])


def _trap(y: np.ndarray, x: np.ndarray) -> float:
    """Trapezoidal rule (np.trapezoid is numpy >= 2 only)."""
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def _width_at(poly: np.ndarray, z: float) -> float:
    """Width of a closed polygon at height z: the sum of its chords there."""
    y0, y1 = poly[:-1, 1], poly[1:, 1]
    cross = (y0 - z) * (y1 - z) < 0
    t = (z - y0[cross]) / (y1[cross] - y0[cross])
    xs = np.sort(poly[:-1, 0][cross] + t * (poly[1:, 0][cross] - poly[:-1, 0][cross]))
    return float(np.sum(xs[1::2] - xs[0::2]))


def jourawski_shear_coefficient(outline: np.ndarray, n: int = 4001) -> float:
    """Shear coefficient of a section in vertical bending from Jourawski's shear stress.

    tau(z) = V Q(z) / (I t(z)) (Q the first moment of the part above z, t the width at z);
    the coefficient that gives the same shear energy is kappa = I^2 / (A int Q^2 / t dz).
    Geometry only (the outline), no finite elements.

    Parameters
    ----------
    outline : ndarray (n, 2)
        Closed polygon (eta, zeta), m, last point = first, or without the repeated point.
    n : int
        Integration points over the height.
    """
    poly = np.asarray(outline, float)
    if np.linalg.norm(poly[0] - poly[-1]) > 0:
        poly = np.vstack([poly, poly[:1]])
    zlo, zhi = poly[:, 1].min(), poly[:, 1].max()
    z = np.linspace(zlo, zhi, n)[1:-1]
    t = np.array([_width_at(poly, zz) for zz in z])
    area = _trap(t, z)
    zc = _trap(t * z, z) / area
    iy = _trap(t * (z - zc) ** 2, z)
    g = (z - zc) * t
    q = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(z))])
    q = q[-1] - q  # int_z^top (z' - zc) t dz'
    return float(iy**2 / (area * _trap(q**2 / t, z)))
