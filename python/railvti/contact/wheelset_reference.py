"""CONTACT's contact reference point of a loaded patch: the interpenetration's weighted centre.

CONTACT (module 1, planar contact D = 2: ``m_wr_locatecp``) does not take a patch's creepages
at the point of smallest gap but at a *contact reference point* found from the
interpenetration of the undeformed wheel and rail at the loaded position of the wheel:

1. Along the contact locus (for each lateral position y on the rail, the lowest point of
   the wheel's surface of revolution, at x_lc(y); railvti's lower silhouette,
   :mod:`railvti.contact.wheelset_pose`), the vertical gap g(y) between wheel and rail is
   taken at the loaded pose (the wheelset centre lowered by its sink). g < 0 is
   interpenetration.
2. Near the locus the gap along x is g(x, y) = g(y) + (x - x_lc)^2 / (2 R), R the nominal
   wheel radius. The weight of a lateral position is the integral of the squared
   interpenetration along x,

       w(y) = int (g(x, y))^2 dx over g < 0  =  (16/15) p^(5/2) sqrt(2 R),  p = -g(y) > 0,

   (CONTACT's default gap weighting; its linear weighting, p^(3/2), is not used).
3. Over the interpenetration region(s) of the patch:

       x_ref = sum w x_lc / sum w,   y_ref = sum w y / sum w,   delta_ref = sum w delta(y) / sum w,

   delta(y) the rail's inclination (contact angle) at y. The reference point P lies on the
   rail surface at y_ref (height of the rail there) and x_ref; its contact frame is rotated by
   the *weighted* angle delta_ref about the track x axis (not the rail's inclination at P):
   n = (0, -s sin delta_ref, cos delta_ref), s = +1 on the left, -1 on the right wheel,
   t_x = e_x, t_y = n x t_x.

CONTACT evaluates the creepages at the wheel's point Q = P - pen n (the approach ``pen``
below P, into the rail, where the undeformed wheel surface lies; n points into the wheel):
see :func:`railvti.contact.wheelset_kinematics.rigid_slip` with a loaded pose.

Regions: the lateral runs with g < 0 are given to the candidate patch whose point lies in
them (or the nearest one), so that a patch holding two areas joined by a low ridge (railvti's
rule; CONTACT combines areas closer than D_SEP) has one reference over both.

Sub-patches (CONTACT's ``combine_cpatches`` and IPLAN = 4): two neighbouring runs of one
patch whose distance d = sqrt(dy^2 + dz^2) (from the end of one run to the start of the
next, rail surface points in the track's y-z plane) exceeds D_COMB stay one patch but
interact elastically with the factor

    f = ((D_SEP - d) / (D_SEP - D_COMB))^0.8      (0 for d >= D_SEP)

in the normal problem; the cut between them lies at the midpoint y_sep of the gap, at
s = (y_sep - y_ref) / cos(delta_ref) on the patch's grid (its projection on the tangent plane).
docs/contact_decks.md gives the equations and the comparison with CONTACT's output.
Implements no equation of the paper (CONTACT's definitions, rigid geometry).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry import ContactPoint, WheelsetPose
from ..geometry.frames import SIDES, SIGN
from .normal import SubPatches
from .wheelset_pose import _silhouette_gap

#: Lateral sampling of the locus for the weighted centre, m (CONTACT samples at DS).
STEP = 1e-5
#: Exponent of the interpenetration p in the weight w(y) ~ p^(5/2) (squared gap along x).
WEIGHT_POWER = 2.5
#: Exponent of CONTACT's sub-patch interaction factor ((D_SEP - d) / (D_SEP - D_COMB))^0.8.
SUBPATCH_POWER = 0.8


@dataclass(frozen=True)
class Reference:
    """A patch's contact reference point and, when it holds areas further apart than
    D_COMB, its sub-patches (cuts in its grid's lateral coordinate, interaction factors)."""

    point: ContactPoint
    subpatches: SubPatches | None = None


def contact_references(
    seeds: list[ContactPoint], loaded: WheelsetPose, d_sep: float = 8e-3, d_comb: float = 4e-3
) -> list[Reference | None]:
    """CONTACT's reference points of one wheel's patches at the wheel's loaded pose.

    Parameters
    ----------
    seeds : list of ContactPoint
        The wheel's carrying candidate points (rigid pose; one per patch), all of one side.
    loaded : WheelsetPose
        The loaded pose of the (half) wheelset: the rigid pose lowered by the sink (and,
        with a load-controlled roll, rolled by the extra roll).
    d_sep, d_comb : float
        CONTACT's D_SEP and D_COMB, m (d_comb < d_sep): areas of a patch further apart than
        d_comb are sub-patches with the interaction factor of the module doc.

    Returns
    -------
    list of Reference or None
        Per seed, its reference point (on the rail, frame at the weighted contact angle,
        the seed's rigid pose, separation and flags) and sub-patches; None for a seed that
        does not interpenetrate at the loaded pose.
    """
    if not seeds:
        return []
    side = seeds[0].side
    k = SIDES.index(side)
    sg = SIGN[k]
    lay = loaded.layout
    gap, px, py, _ = _silhouette_gap(lay, k, loaded.y, loaded.roll, loaded.yaw)
    ok = np.isfinite(gap)
    order = np.argsort(py[ok])
    ys, gs, xs, ws = py[ok][order], gap[ok][order] + loaded.z, px[ok][order], lay.ws[ok][order]
    if not np.any(gs < 0.0):
        return [None] * len(seeds)
    # the interpenetration on a uniform lateral sampling (one sample beyond each end)
    inside = np.flatnonzero(gs < 0.0)
    lo, hi = ys[max(inside[0] - 1, 0)], ys[min(inside[-1] + 1, ys.size - 1)]
    yy = np.arange(lo, hi + STEP, STEP)
    gg = np.interp(yy, ys, gs)
    pen = np.where(gg < 0.0, -gg, 0.0)
    runs = _runs(pen > 0.0)
    owner = [_nearest(yy[a], yy[b - 1], [s.position[1] for s in seeds]) for a, b in runs]
    out: list[ContactPoint | None] = []
    for i, seed in enumerate(seeds):
        sel = np.zeros(yy.size, dtype=bool)
        for (a, b), o in zip(runs, owner):
            if o == i:
                sel[a:b] = True
        w = pen[sel] ** WEIGHT_POWER
        if w.sum() <= 0.0:
            out.append(None)
            continue
        y_sel = yy[sel]
        y_rail = sg * y_sel - lay.rail_offset
        delta = -np.arctan(lay.rail.slope(y_rail))
        y_ref = float(w @ y_sel / w.sum())
        x_ref = float(w @ np.interp(y_sel, ys, xs) / w.sum())
        d_ref = float(w @ delta / w.sum())
        point = _reference_point(seed, lay, sg, x_ref, y_ref, d_ref, float(np.interp(y_ref, ys, ws)))
        mine = [(yy[a], yy[b - 1]) for (a, b), o in zip(runs, owner) if o == i]
        out.append(Reference(point, _subpatches(mine, lay, sg, y_ref, d_ref, d_sep, d_comb)))
    return out


def _subpatches(
    runs: list[tuple[float, float]], lay, sg: float, y_ref: float, d_ref: float, d_sep: float, d_comb: float
) -> SubPatches | None:
    """CONTACT's sub-patches of a patch from its interpenetration runs [y0, y1] (track y,
    ascending): a cut between neighbours further apart than d_comb (see the module doc)."""
    cuts, factors = [], []
    for (_, y_end), (y_start, _) in zip(runs, runs[1:]):
        z_end, z_start = (-float(lay.rail.height(sg * v - lay.rail_offset)) for v in (y_end, y_start))
        d = float(np.hypot(y_start - y_end, z_start - z_end))
        if d <= d_comb:
            continue
        cuts.append((0.5 * (y_end + y_start) - y_ref) / np.cos(d_ref))
        factors.append((max(d_sep - d, 0.0) / (d_sep - d_comb)) ** SUBPATCH_POWER)
    return SubPatches(tuple(cuts), tuple(factors)) if cuts else None


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) of the runs of True in a boolean array."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    return list(zip(edges[0::2].tolist(), edges[1::2].tolist()))


def _nearest(y0: float, y1: float, points: list[float]) -> int:
    """Index of the point inside [y0, y1], or else the nearest to it."""
    dist = [max(y0 - p, 0.0, p - y1) for p in points]
    return int(np.argmin(dist))


def _reference_point(
    seed: ContactPoint, lay, sg: float, x: float, y: float, delta: float, y_wheel: float
) -> ContactPoint:
    y_rail = sg * y - lay.rail_offset
    n = np.array([0.0, -sg * np.sin(delta), np.cos(delta)])
    tx = np.array([1.0, 0.0, 0.0])
    return ContactPoint(
        side=seed.side,
        separation=seed.separation,
        in_contact=seed.in_contact,
        position=np.array([x, y, lay.rail_top - float(lay.rail.height(y_rail))]),
        y_wheel=y_wheel,
        y_rail=float(y_rail),
        contact_angle=delta,
        rolling_radius=float(lay.wheelset.wheel_radius + lay.wheel.height(y_wheel)),
        normal=n,
        t_x=tx,
        t_y=np.cross(n, tx),
        flange_climb=seed.flange_climb,
        pose=seed.pose,
    )


def moved(a: ContactPoint, b: ContactPoint, tol_position: float, tol_angle: float) -> bool:
    """Whether two reference points differ by more than the tolerances (m, rad)."""
    return bool(
        np.linalg.norm(a.position - b.position) > tol_position
        or abs(a.contact_angle - b.contact_angle) > tol_angle
    )


__all__ = ["STEP", "WEIGHT_POWER", "SUBPATCH_POWER", "Reference", "contact_references", "moved"]
