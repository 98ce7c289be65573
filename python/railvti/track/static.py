"""Direct static solve of the full 2.5-D FE ring track (every section DOF, same Fourier terms).

The reference for the modal form's static check: per cyclic group the sparse system of all
section DOFs of every rail wave number in the group, pads and sleepers, solved by SuperLU.
Costly (use small rings and coarse meshes); for validation only.
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
    kpad = np.array([p["pad_stiffness_longitudinal"], p["pad_stiffness_lateral"],
                     p["pad_stiffness_vertical"]]) / area
    ls = p["sleeper_length"]
    kb = np.array([p["ballast_stiffness_lateral"], p["ballast_stiffness_vertical"],
                   p["ballast_stiffness_vertical"] * ls * ls / 12])
    gx, gw = np.polynomial.legendre.leggauss(16)
    xi, w_xi = 0.5 * p["pad_length"] * gx, 0.5 * p["pad_length"] * gw
    pi_ = track._pad_interp                      # (np, 3, ndof)
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
                for fam in ((0,) if k == 0 else (1, 2)):
                    blocks.append((rho, k, fam, sgn, 2 * math.pi * k / L,
                                   1 / math.sqrt(L if k == 0 else L / 2)))
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
            e_track = {2: (0.0, 1.0), 1: (1.0, 0.0)}[comp]      # (y, z) of the unit load
            loc = np.array([0.0, e_track[0] * c_ + e_track[1] * s_, -e_track[0] * s_ + e_track[1] * c_])
            for c in (1, 2):
                t = _trig(b[2], c, b[4] * x) * b[5]
                f[i * ndof + 3 * cn + c] += sign[rho] * loc[c] * t
                if rho == 1:
                    out[i * ndof + 3 * cn + c] += loc[c] * t
        u = spla.spsolve(kg, f)
        total += float(out @ u)
    return total
