!> Wheel-rail contact forces of one rigid wheelset on its (rigid or elastic) track element,
!> from a precomputed per-wheel contact table (the usual MBS look-up-table approach).
!>
!> Table (left wheel; the right wheel is its mirror, read at (-u, -phi)): uniform in
!> u = Y + r_nom phi, the lateral position of the rolled wheel's lowest point (Y the
!> wheelset centre's lateral shift in the track frame, r_nom the nominal radius = the
!> centre's height above the rail top), and in the relative roll phi of wheel against
!> rail; two candidate points per wheel (slot 1 the tread side, slot 2 the flange side of a
!> split of the wheel profile), quantities
!>   1 g   vertical gap of the rolled wheel with its centre at nominal height, m
!>   2 l   lateral offset of the point from the wheelset centre (left wheel, track frame), m
!>   3 delta contact angle (rail normal from vertical, + towards the track centre), rad
!>   4 r   rolling radius (distance of the point from the axle), m
!>   5 a1, 6 b1  Hertz semi-axes (rolling, lateral) for a 1 N load, m N^(-1/3)
!>   7 kH  Hertz law N = kH * d^1.5 with d the normal approach, N m^(-1.5)
!>   8 c11, 9 c22, 10 c23  Kalker's linear creep coefficients at a1/b1,
!>   11 branch label of the slot's point along u within one roll row (a local minimum of
!>      the gap followed continuously),
!>   12 zarm  depth of the point below the wheelset centre (track frame), m,
!>   13 rlink 1 where the slot's point at this node and at the next roll row (same u) is
!>      the same local minimum, else 0 (pose_at never interpolates across a missing link),
!>   14 rzz   the rail's d2Z/dY2 under the point (track frame, Z up), 1/m.
!> Quasi-elastic contact: with Y = y_rel + r_nom phi_t and the centre's height
!> Z = z_rel - y_rel phi_t in the frame of the track element (rolled by phi_t about the
!> track centre at rail-top height), the vertical interference of a point is -(g + Z), its
!> normal approach that times cos(delta). The Hertz, Kalker and FASTSIM paths read the
!> table at (u, phi); the BEM paths (their gap fields exist on the zero-roll row only) use
!> the zero-roll row at u with the roll to first order (the point rotated about the centre,
!> the gap field tilted by phi about the point: vehicle_bem). Lever arms (l, zarm) about the
!> wheelset centre and (l + y_rel, r_nom - zarm) about the track's roll centre enter both
!> the relative velocities and the generalised forces (energy-consistent).
!> Creepages from the wheelset's velocities with the nominal rolling speed Omega0 = v0/r0
!> plus the spin perturbation rate betadot (no rotation angle: only the rate enters).
!> Forces on the wheel in track axes.
!> Implements Hertz's law, Kalker's linear theory with the Shen-Hedrick-Elkins saturation
!> (creep_kalker_she) and FASTSIM through contact_fastsim; no Kaiser equation.
module vehicle_contact
    use common_kinds, only: dp
    use contact_fastsim, only: fastsim_ellipse
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_OUTSIDE_TABLE
    use vehicle_bem, only: bem_patch, bem_scale, bem_linear, bem_lead
    use vehicle_strip, only: strip_geometry, strip_wheel, strip_props, nso, SO_N, SO_V, SO_DY, SO_DZ, &
                             SO_DPHI, SO_L, SO_ZA, SO_DELTA, SO_R, SO_X, SO_A, strip_lin, &
                             strip_linearise, strip_extrapolate, SO_DPSI, SO_XC
    implicit none
    private
    public :: nq_table, nwo, IO_ARM, wheelset_contact, creep_kalker_she, pose_table, pose_set, pose_at
    public :: CMODEL_HERTZ_KALKER, CMODEL_HERTZ_FASTSIM, CMODEL_BEM
    public :: SLIN_KEEP, SLIN_READ

    !> Contact models (wheelset_contact's `model`); Python's CONTACT_MODELS names them. The
    !> Newton tangent of a BEM run is CMODEL_BEM with wheelset_contact's flag `tangent`.
    integer, parameter :: CMODEL_HERTZ_KALKER = 1, CMODEL_HERTZ_FASTSIM = 2, CMODEL_BEM = 3
    !> Strip linearisation (wheelset_contact's slin, smode): evaluate and keep the wheels'
    !> strip outputs with their pose derivatives, or read them linearly at the pose.
    integer, parameter :: SLIN_KEEP = 1, SLIN_READ = 2

    integer, parameter :: nq_table = 14
    !> Table quantities: the branch label of each slot's point along u (table_at), the depth
    !> of the point below the centre, the link to the next roll row, the rail's d2Z/dY2
    !> (pose_at).
    integer, parameter :: IBRANCH = 11, IZARM = 12, IRLINK = 13, IRZZ = 14
    !> Gap difference over which two branches of one slot share its load, m (pose_at): a
    !> branch change of the lowest point keeps the forces continuous.
    real(dp), parameter :: SHARE_GAP = 2.0e-6_dp
    !> A branch's share below which the BEM's look-up drops it (table_at): its force then
    !> jumps by this fraction of the difference between the branches (~1e-3 N).
    real(dp), parameter :: SHARE_MIN = 1.0e-6_dp

    !> The contact table of a model: tab(nq_table, 2, ny, nr) over u = u0 + (i - 1) du and
    !> phi = p0 + (j - 1) dp, row j0 at phi = 0; r_nom the nominal radius (centre height).
    type :: pose_table
        integer :: ny = 0, nr = 0, j0 = 1
        real(dp) :: u0 = 0.0_dp, du = 1.0_dp, p0 = 0.0_dp, dp = 1.0_dp, rnom = 0.46_dp
        real(dp), allocatable :: tab(:, :, :, :)
    end type pose_table
    !> Outputs per wheel: 1 Q (vertical force on the wheel), 2 Y (lateral force on the wheel,
    !> track y), 3 Fx (longitudinal), 4 N tread, 5 N flange, 6 xi, 7 eta, 8 spin (1/m) of the
    !> point with the larger normal force, 9 Hertz potential energy (J), 10 its contact angle,
    !> 11 a, 12 b semi-axes of that point (m), 13 its centre of pressure along t_y from the
    !> point (m, BEM; 0 for the Hertz patch), 14 the moment of the wheel's contact stresses
    !> about its points along t_x (N m, sum Fn yc), 15 the spin moment about the normals (N m),
    !> 16 T gamma (N): the creep forces' work on the creepages, -(Fx xi + Fy eta) summed over
    !> the wheel's points (the energy index of wear models; spin not included, as usual), 17
    !> the tangential creep force |(Fx, Fy)| of the point with the larger normal force (N),
    !> 18 the contact's lateral arm on the wheel (m, wheel frame: unrolled by the relative roll;
    !> tread and flange weighted by their normal forces; 0 without contact): where the
    !> flexible rims' rows are evaluated (vehicle_modal%modal_follow).
    integer, parameter :: nwo = 18
    !> The row of the contact's lateral arm in the wheel outputs (the last, internal).
    integer, parameter :: IO_ARM = nwo
    !> One wheel's pose and velocities in the frame of its track element (wheel_at): sg 1 for
    !> the left wheel, -1 for the right; yr, phr the lateral shift and roll against the
    !> element, u = Y + r_nom phi the table's coordinate, zc the centre's height, pl = sg phr;
    !> ve the wheel's (y, z, roll) rates; qtw, vtw the element's pose and rates under the wheel;
    !> psi the wheelset's yaw against the rail under the wheel (an irregular rail's yaw off).
    type :: wheel_pose
        real(dp) :: sg, yr, phr, u, zc, pl, psi
        real(dp) :: ve(3), qtw(3), vtw(3)
    end type wheel_pose

contains

    !> The table at y for the BEM, per slot k and member: point c = 2 (k - 1) + member (the
    !> BEM's point, vehicle_bem NPT) with vals(:, c) = (1 - wa(c)) tab(:, k, ia(c)) + wa(c)
    !> tab(:, k, ib(c)) and load share wt(c) (0: the member is not used). Within one branch
    !> (quantity IBRANCH equal at both nodes of the interval) that is the linear interpolation,
    !> one member of share 1. Where the slot's point changes branch inside the interval (it
    !> jumps to another local minimum of the gap), fields and points of the two branches are
    !> never mixed: each side's branch is extrapolated linearly from its own two nodes (a
    !> single node when its neighbour is another branch), and the two share the slot's load by
    !> the softmin of pose_at (SHARE_GAP, weighted by each side's presence 1 - w, w), so that
    !> the forces stay continuous where the lowest point jumps: a hard switch is a jump of the
    !> creepages and the contact frame at the point (1.7 kN of Fx on a tread jump at 420 km/h)
    !> on which Newton's method cannot converge at any step size. Shares below SHARE_MIN are
    !> dropped (the other member's raised to 1). A branch keeps its member (the parity of its
    !> label), so that its BEM point keeps its own warm starts. info STAT_OUTSIDE_TABLE when y
    !> is outside the table.
    pure subroutine table_at(ny, tab, y0, dy, y, vals, ia, ib, wa, wt, info)
        integer, intent(in) :: ny
        real(dp), intent(in) :: tab(nq_table, 2, ny), y0, dy, y
        real(dp), intent(out) :: vals(nq_table, 4), wa(4), wt(4)
        integer, intent(out) :: ia(4), ib(4), info
        real(dp) :: s, w, g1, g2, w1, w2, e1, e2, gmin, s1
        integer :: i, k, a1, b1, a2, b2, c1, c2
        ia = 1
        ib = 1
        wa = 0.0_dp
        wt = 0.0_dp
        vals = 0.0_dp
        s = (y - y0) / dy
        if (.not. (s >= 0.0_dp .and. s <= real(ny - 1, dp))) then
            info = STAT_OUTSIDE_TABLE
            return
        end if
        info = STAT_OK
        i = min(int(s), ny - 2) + 1
        w = s - real(i - 1, dp)
        do k = 1, 2
            c1 = 2 * (k - 1) + 1 + modulo(nint(tab(IBRANCH, k, i)), 2)
            c2 = 4 * k - 1 - c1                  ! the slot's other point
            if (tab(IBRANCH, k, i) == tab(IBRANCH, k, i + 1)) then
                ia(c1) = i
                ib(c1) = i + 1
                wa(c1) = w
                wt(c1) = 1.0_dp
                cycle
            end if
            call side(i, -1, 1.0_dp + w, a1, b1, w1)
            call side(i + 1, 1, w - 1.0_dp, a2, b2, w2)
            g1 = (1.0_dp - w1) * tab(1, k, a1) + w1 * tab(1, k, b1)
            g2 = (1.0_dp - w2) * tab(1, k, a2) + w2 * tab(1, k, b2)
            gmin = min(g1, g2)
            e1 = (1.0_dp - w) * exp(-(g1 - gmin) / SHARE_GAP)
            e2 = w * exp(-(g2 - gmin) / SHARE_GAP)
            if (e1 + e2 > 0.0_dp) then
                s1 = e1 / (e1 + e2)
            else
                s1 = merge(1.0_dp, 0.0_dp, g1 <= g2)
            end if
            if (s1 < SHARE_MIN) s1 = 0.0_dp
            if (s1 > 1.0_dp - SHARE_MIN) s1 = 1.0_dp
            ia([c1, c2]) = [a1, a2]
            ib([c1, c2]) = [b1, b2]
            wa([c1, c2]) = [w1, w2]
            wt([c1, c2]) = [s1, 1.0_dp - s1]
        end do
        do c1 = 1, 4
            if (wt(c1) > 0.0_dp) vals(:, c1) = (1.0_dp - wa(c1)) * tab(:, (c1 + 1) / 2, ia(c1)) &
                                                + wa(c1) * tab(:, (c1 + 1) / 2, ib(c1))
        end do
    contains
        !> Node j's branch at weight we between (na, nb): extrapolated from j and its
        !> neighbour j + dir when that lies on the same branch, else node j alone.
        pure subroutine side(j, dir, we, na, nb, wo)
            integer, intent(in) :: j, dir
            real(dp), intent(in) :: we
            integer, intent(out) :: na, nb
            real(dp), intent(out) :: wo
            integer :: jn
            jn = j + dir
            na = j
            nb = j
            wo = 0.0_dp
            if (jn < 1 .or. jn > ny) return
            if (tab(IBRANCH, k, jn) /= tab(IBRANCH, k, j)) return
            ! value = v_j + e (v_j - v_jn), e the distance from j away from jn in steps
            if (dir < 0) then
                na = jn
                nb = j
                wo = we
            else
                na = j
                nb = jn
                wo = we
            end if
        end subroutine side
    end subroutine table_at

    !> Store a table: info STAT_BAD_ARGUMENT for fewer than 2 nodes in u, steps <= 0, an even
    !> number of roll rows or rows not symmetric about phi = 0, or a non-finite entry.
    pure subroutine pose_set(nq, ny, nr, tab, u0, du, p0, dph, rnom, ct, info)
        integer, intent(in) :: nq, ny, nr
        real(dp), intent(in) :: tab(nq, 2, ny, nr), u0, du, p0, dph, rnom
        type(pose_table), intent(out) :: ct
        integer, intent(out) :: info
        info = STAT_BAD_ARGUMENT
        if (nq /= nq_table .or. ny < 2 .or. nr < 1 .or. mod(nr, 2) /= 1) return
        if (.not. (du > 0.0_dp .and. dph > 0.0_dp .and. rnom > 0.0_dp)) return
        if (abs(p0 + 0.5_dp * real(nr - 1, dp) * dph) > 1.0e-9_dp * dph) return
        if (.not. all(abs(tab) <= huge(1.0_dp))) return
        ct%ny = ny
        ct%nr = nr
        ct%j0 = (nr + 1) / 2
        ct%u0 = u0
        ct%du = du
        ct%p0 = p0
        ct%dp = dph
        ct%rnom = rnom
        ct%tab = tab
        info = STAT_OK
    end subroutine pose_set

    !> The table at (u, phi), per slot: a bilinear blend of the cell's four nodes in which
    !> each node's gap is first carried to (u, phi) along its own wheel point (the point
    !> rotated rigidly about the wheelset centre by phi - phi_node, the centre moved to
    !> Y = u - r_nom phi, the rail's slope tan(delta) under it: exact in the rotation, first
    !> order in the rail's second derivative), so the blend is exact for a point that does not move
    !> on the wheel. Branches: the four nodes fall into groups joined by the cell's edges
    !> that keep one branch (equal labels along u, links along phi); each group is blended
    !> alone (weights renormalised) and the group with the smallest gap is the slot's point
    !> (the geometry's choice: the lowest local minimum). Fields and points of two branches
    !> are never mixed, and on a cell edge only that edge's nodes count, so the look-up is
    !> continuous across cells. A single row (nr = 1) gives the roll by the same carry.
    !> info STAT_OUTSIDE_TABLE outside the table.
    pure subroutine pose_at(ct, u, phi, vals, wt, grad, info)
        type(pose_table), intent(in) :: ct
        real(dp), intent(in) :: u, phi
        real(dp), intent(out) :: vals(nq_table, 2, 2), wt(2, 2)    ! (., member, slot)
        real(dp), intent(out) :: grad(2, 2, 2)                     ! (d/du d/dphi, member, slot)
        integer, intent(out) :: info
        real(dp) :: su, sp, wu, wp, w(4), wsum, v(nq_table), gg(4), pres(4), e
        real(dp) :: gd(2, 4), hv(4), hs(2, 4), t(nq_table)
        integer :: i, j, k, c, g, grp(4), ci(4), cj(4), nc, m, order(4), cn
        vals = 0.0_dp
        wt = 0.0_dp
        grad = 0.0_dp
        su = (u - ct%u0) / ct%du
        if (.not. (su >= 0.0_dp .and. su <= real(ct%ny - 1, dp))) then
            info = STAT_OUTSIDE_TABLE
            return
        end if
        sp = 0.0_dp
        if (ct%nr > 1) then
            sp = (phi - ct%p0) / ct%dp
            if (.not. (sp >= 0.0_dp .and. sp <= real(ct%nr - 1, dp))) then
                info = STAT_OUTSIDE_TABLE
                return
            end if
        end if
        info = STAT_OK
        i = min(int(su), ct%ny - 2) + 1
        wu = su - real(i - 1, dp)
        j = min(int(sp), max(ct%nr - 2, 0)) + 1
        wp = sp - real(j - 1, dp)
        ! corners 1 (i, j), 2 (i+1, j), 3 (i, j+1), 4 (i+1, j+1); a single row has two
        ci = [i, i + 1, i, i + 1]
        cj = [j, j, j + 1, j + 1]
        w = [(1.0_dp - wu) * (1.0_dp - wp), wu * (1.0_dp - wp), (1.0_dp - wu) * wp, wu * wp]
        nc = merge(2, 4, ct%nr == 1)
        do k = 1, 2
            call corner_groups(ct, k, nc, ci, cj, grp)
            ! each group's blend: gap gg and presence pres (its bilinear weight)
            gg = huge(1.0_dp)
            pres = 0.0_dp
            gd = 0.0_dp
            do g = 1, nc
                wsum = sum(w(1:nc), mask=grp(1:nc) == g)
                if (.not. (wsum > 0.0_dp)) cycle
                pres(g) = wsum
                ! the group's gap by cubic Hermite interpolation over the cell from the node
                ! values and their exact slopes (C1 across cells: the forces' gradient is
                ! continuous); a corner of another branch is stood in for by the nearest
                ! corner of this group carried to it along its wheel point
                do c = 1, nc
                    if (grp(c) == g) then
                        t = ct%tab(:, k, ci(c), cj(c))
                        hv(c) = t(1)
                        hs(1, c) = -tan(t(3))
                        hs(2, c) = t(2) + (ct%rnom - t(IZARM)) * tan(t(3))
                    else
                        cn = nearest_member(c, g, nc, grp)
                        call carried_gap(ct%rnom, ct%tab(:, k, ci(cn), cj(cn)), &
                                         real(ci(c) - ci(cn), dp) * ct%du, &
                                         real(cj(c) - cj(cn), dp) * ct%dp, hv(c), hs(:, c))
                    end if
                end do
                call hermite_gap(ct, k, ci(1:2), phi, hv, hs, wu, wp, gg(g), gd(:, g))
            end do
            ! the two lowest groups become the slot's members
            order = [1, 2, 3, 4]
            do m = 1, 2
                do g = m + 1, 4
                    if (gg(order(g)) < gg(order(m))) order([m, g]) = order([g, m])
                end do
            end do
            do m = 1, 2
                g = order(m)
                if (.not. (pres(g) > 0.0_dp)) cycle
                v = 0.0_dp
                do c = 1, nc
                    if (grp(c) == g) v = v + w(c) * ct%tab(:, k, ci(c), cj(c))
                end do
                vals(:, m, k) = v / pres(g)
                vals(1, m, k) = gg(g)
                grad(:, m, k) = gd(:, g)
            end do
            ! load share of two branches with nearly equal gaps: softmin over SHARE_GAP
            ! weighted by each group's presence, so a branch enters and leaves the slot
            ! continuously (a cell edge has only its own nodes' groups: presence 0)
            wt(1, k) = 1.0_dp
            if (pres(order(2)) > 0.0_dp) then
                e = pres(order(2)) * exp(-(gg(order(2)) - gg(order(1))) / SHARE_GAP)
                wt(1, k) = pres(order(1)) / (pres(order(1)) + e)
                wt(2, k) = 1.0_dp - wt(1, k)
            end if
        end do
    end subroutine pose_at

    !> Cubic Hermite interpolation over the cell of the corner gaps hv with their slopes
    !> hs (d/du, d/dphi): bicubic with zero cross derivatives (a single row: cubic in u,
    !> then the roll by the carry of the u-interpolated point). The slopes are the exact
    !> dg/du = -tan(delta), dg/dphi = l + (r_nom - za) tan(delta) of the minimum (its
    !> envelope: the slopes at a fixed wheel point). Returns g and its gradient gdv.
    pure subroutine hermite_gap(ct, k, ci, phi, hv, hs, a, b, gv, gdv)
        type(pose_table), intent(in) :: ct
        integer, intent(in) :: k, ci(2)              ! the slot, the cell's corners along u
        real(dp), intent(in) :: phi, hv(4), hs(2, 4), a, b
        real(dp), intent(out) :: gv, gdv(2)
        real(dp) :: h0(2), h1(2), d0(2), d1(2), e0(2), e1(2), f0(2), f1(2), tt(nq_table)
        real(dp) :: cu, cp
        integer :: ia, ib, cc
        h0 = [2 * a**3 - 3 * a**2 + 1, -2 * a**3 + 3 * a**2]
        h1 = [a**3 - 2 * a**2 + a, a**3 - a**2] * ct%du
        d0 = [6 * a**2 - 6 * a, -6 * a**2 + 6 * a] / ct%du
        d1 = [3 * a**2 - 4 * a + 1, 3 * a**2 - 2 * a]
        e0 = [1.0_dp, 0.0_dp]
        e1 = 0.0_dp
        f0 = 0.0_dp
        f1 = 0.0_dp
        if (ct%nr > 1) then
            e0 = [2 * b**3 - 3 * b**2 + 1, -2 * b**3 + 3 * b**2]
            e1 = [b**3 - 2 * b**2 + b, b**3 - b**2] * ct%dp
            f0 = [6 * b**2 - 6 * b, -6 * b**2 + 6 * b] / ct%dp
            f1 = [3 * b**2 - 4 * b + 1, 3 * b**2 - 2 * b]
        end if
        gv = 0.0_dp
        gdv = 0.0_dp
        do ib = 1, merge(1, 2, ct%nr == 1)
            do ia = 1, 2
                cc = ia + 2 * (ib - 1)
                gv = gv + hv(cc) * h0(ia) * e0(ib) + hs(1, cc) * h1(ia) * e0(ib) &
                     + hs(2, cc) * h0(ia) * e1(ib)
                gdv(1) = gdv(1) + hv(cc) * d0(ia) * e0(ib) + hs(1, cc) * d1(ia) * e0(ib) &
                         + hs(2, cc) * d0(ia) * e1(ib)
                gdv(2) = gdv(2) + hv(cc) * h0(ia) * f0(ib) + hs(1, cc) * h1(ia) * f0(ib) &
                         + hs(2, cc) * h0(ia) * f1(ib)
            end do
        end do
        if (ct%nr == 1) then
            cu = gv
            cp = gdv(1)
            tt = (1.0_dp - a) * ct%tab(:, k, ci(1), 1) + a * ct%tab(:, k, ci(2), 1)
            tt(1) = cu
            call carried_gap(ct%rnom, tt, 0.0_dp, phi, gv, gdv)
            gdv(1) = cp + (gdv(1) + tan(tt(3)))
        end if
    end subroutine hermite_gap

    !> The corner of group gq nearest to corner c (along u first, then along phi), among the
    !> nc corners of group labels grp.
    pure integer function nearest_member(c, gq, nc, grp)
        integer, intent(in) :: c, gq, nc, grp(4)
        integer, parameter :: pref(3, 4) = reshape([2, 3, 4, 1, 4, 3, 4, 1, 2, 3, 2, 1], [3, 4])
        integer :: q
        nearest_member = c
        do q = 1, 3
            if (pref(q, c) <= nc) then
                if (grp(pref(q, c)) == gq) then
                    nearest_member = pref(q, c)
                    return
                end if
            end if
        end do
    end function nearest_member

    !> The gap gc of a node's wheel point (quantities t) carried by du along u and dph in
    !> roll, and its derivatives gd (d/du, d/dphi).
    pure subroutine carried_gap(rnom, t, du, dph, gc, gd)
        real(dp), intent(in) :: rnom, t(nq_table), du, dph
        real(dp), intent(out) :: gc, gd(2)
        real(dp) :: l, za, l1, za1, dy, slope
        l = t(2)
        za = t(IZARM)
        l1 = l * cos(dph) + za * sin(dph)
        za1 = za * cos(dph) - l * sin(dph)
        dy = du - rnom * dph + l1 - l
        gc = t(1) + (za - za1) - tan(t(3)) * dy - 0.5_dp * t(IRZZ) * dy * dy
        slope = tan(t(3)) + t(IRZZ) * dy
        gd(1) = -slope
        gd(2) = l1 - slope * (za1 - rnom)
    end subroutine carried_gap

    !> Group labels of the corners joined by the cell's one-branch edges, for slot kk
    !> (pose_at: n corners ci, cj).
    !> The edges' claims need not be transitive (a point that slides along one row but
    !> jumps along the other): edges join corners in the order of the smallest movement of
    !> the point (|l| difference), and an edge is skipped when its join would put the two
    !> ends of an edge that keeps no branch into one group.
    pure subroutine corner_groups(ct, kk, n, ci, cj, gr)
        type(pose_table), intent(in) :: ct
        integer, intent(in) :: kk, n, ci(4), cj(4)   ! the cell's corners (pose_at)
        integer, intent(out) :: gr(4)
        integer, parameter :: ea(4) = [1, 3, 1, 2], eb(4) = [2, 4, 3, 4]
        logical :: e(4), used(4)
        real(dp) :: dist(4)
        integer :: it, m, q, old(4), ga, gb
        associate (t => ct%tab)
            e = .false.
            e(1) = t(IBRANCH, kk, ci(1), cj(1)) == t(IBRANCH, kk, ci(2), cj(2))
            if (n == 4) then
                e(2) = t(IBRANCH, kk, ci(3), cj(3)) == t(IBRANCH, kk, ci(4), cj(4))
                e(3) = t(IRLINK, kk, ci(1), cj(1)) > 0.5_dp
                e(4) = t(IRLINK, kk, ci(2), cj(2)) > 0.5_dp
            end if
            ! only the cell's own edges: with two corners (a single roll row) edges 2-4 name
            ! corners outside the table (reading them was out of bounds: an occasional crash)
            dist = huge(1.0_dp)
            do q = 1, merge(4, 1, n == 4)
                dist(q) = abs(t(2, kk, ci(ea(q)), cj(ea(q))) - t(2, kk, ci(eb(q)), cj(eb(q))))
            end do
        end associate
        gr = [1, 2, 3, 4]
        used = .not. e
        do it = 1, 4
            q = minloc(dist, dim=1, mask=.not. used)
            if (q == 0) exit
            used(q) = .true.
            old = gr
            ga = gr(ea(q))
            gb = gr(eb(q))
            m = min(ga, gb)
            where (gr == ga .or. gr == gb) gr = m
            do m = 1, 4
                if (.not. e(m) .and. (m <= 1 .or. n == 4)) then
                    if (gr(ea(m)) == gr(eb(m))) then
                        gr = old
                        exit
                    end if
                end if
            end do
        end do
    end subroutine corner_groups

    !> Kalker's linear creep forces with the Shen-Hedrick-Elkins (1983) saturation of the
    !> resultant: F' = mu N (u - u^2/3 + u^3/27), u = F/(mu N), capped at mu N for u >= 3.
    pure subroutine creep_kalker_she(g, a, b, c11, c22, c23, mu, fn, xi, eta, phi, fx, fy)
        real(dp), intent(in) :: g, a, b, c11, c22, c23, mu, fn, xi, eta, phi
        real(dp), intent(out) :: fx, fy
        real(dp) :: ab, f, u, fs
        ab = a * b
        fx = -g * ab * c11 * xi
        fy = -g * ab * c22 * eta - g * ab * sqrt(ab) * c23 * phi
        f = hypot(fx, fy)
        if (f <= 0.0_dp) return
        if (mu * fn <= 0.0_dp) then
            fx = 0.0_dp
            fy = 0.0_dp
            return
        end if
        u = f / (mu * fn)
        if (u < 3.0_dp) then
            fs = mu * fn * (u - u * u / 3.0_dp + u**3 / 27.0_dp)
        else
            fs = mu * fn
        end if
        fx = fx * fs / f
        fy = fy * fs / f
    end subroutine creep_kalker_she

    !> Contact forces of one wheelset.
    !> qw, vw: wheelset (y, z, roll, yaw, x, beta) and rates (x longitudinal relative to the
    !> nominal position moving at v0, beta the spin perturbation about the axle on top of the
    !> nominal rolling v0/r0; only vw(5:6) enter); qt, vt: track element (y, z, roll) and rates.
    !> model CMODEL_HERTZ_KALKER: Hertz + Kalker linear with SHE saturation; CMODEL_HERTZ_FASTSIM:
    !> Hertz + FASTSIM (contact_fastsim, fsn x fsn strips x points); CMODEL_BEM: the BEM
    !> normal and steady-rolling solvers of vehicle_bem (state `bem`, wheelset index iws) with
    !> the same approach and creepages (the Hertz semi-axes and energy are still reported in
    !> wout; point_bem). With CMODEL_BEM and tangent (optional, default false), the Newton
    !> tangent of a BEM run instead (point_bem_tangent): Hertz + Kalker with the normal force
    !> and the creep forces scaled by their ratios BEM / Hertz-Kalker at the last BEM solve of
    !> each point, or where the point has one the linear model of its BEM patch
    !> (vehicle_bem%bem_linear: the Jacobian from differences of its own solves).
    !> fw: generalised forces on the wheelset (y, z, roll, yaw, x, beta); ft: on the track element.
    !> info: STAT_OK, STAT_BAD_ARGUMENT (unknown model), STAT_OUTSIDE_TABLE, or from
    !> vehicle_bem%bem_patch (STAT_GRID_EDGE, STAT_CONTACT_NOT_CONVERGED, STAT_BAD_HANDLE).
    !> Flexible wheel rims (model FR, optional rim, rarm, frim, all three or none): rim(:, w)
    !> = (dy, dz, drx, dy', dz', drx') of wheel w (1 left, 2 right): the elastic displacement
    !> (track y, z) of the rim's reference point at (0, sg rarm(1, w), -rarm(2, w)) from the wheelset
    !> centre and the rim's rotation about x (camber). To first order the wheel is moved
    !> rigidly: rotated by drx about the centre and translated by (dy - rarm(2, w) drx,
    !> dz - sg rarm(1, w) drx), so that its reference point moves by (dy, dz). Each wheel is then
    !> evaluated at its own pose (Y, Z, roll) + that motion, velocities likewise; frim(:, w)
    !> the generalised forces on (dy, dz, drx): (F_y, F_z, M_x - rarm(2, w) F_y - sg rarm(1, w) F_z)
    !> of that wheel's forces and moment about the centre (the moment about the reference
    !> point): the same arms as the pose change (energy-consistent). rim = 0 gives fw, ft,
    !> wout exactly (bit for bit) as without.
    !> Strip contact (optional st, switched on, models CMODEL_HERTZ_KALKER and CMODEL_HERTZ_FASTSIM):
    !> each wheel's normal forces are -grad V of the strip potential (vehicle_strip) over the
    !> pose, and each slot's creep forces act at its load-weighted point with the Hertz
    !> ellipse and Kalker's coefficients of its mean curvature ratio; the table only bounds
    !> the wheelset's lateral range (STAT_OUTSIDE_TABLE as before). With slin and smode
    !> SLIN_KEEP each wheel's strip outputs are kept with their derivatives over its pose;
    !> SLIN_READ reads them linearly at the pose instead of evaluating the strips (the Newton
    !> tangent's perturbations: first order, like its forward differences).
    !> Ring track (model RF, optional rail, frail, both or none): rail(:, w) = (y, z, roll and
    !> their rates) of a track element of its own under wheel w, added to qt, vt for that
    !> wheel (the rail head's motion under the wheel expressed as an element's pose); frail(:,
    !> w) the generalised forces on it (wheel w's share of ft). rail = 0 gives fw, ft, wout as
    !> without. The same arguments carry an irregular track's rail positions under the wheels
    !> (vehicle_irregularity: RR, FR too), with ryaw(w) (optional) the rail's yaw under wheel w,
    !> subtracted from the wheelset's yaw qw(4) where the contact reads it (the creepage and
    !> the strip's yaw); ryaw = 0 gives the same numbers as without.
    !> Curve (optional frame_yaw_rate, rad/s): the yaw rate v0 kappa of the wheelset's track
    !> frame, added to its own in the creepages (wheel_points); absent or 0: straight track.
    !> Per wheel: its pose (wheel_at), its candidate points from the strips (strip_points),
    !> the zero-roll row (bem_points) or the table (pose_at), then their forces (wheel_points).
    subroutine wheelset_contact(ct, r0, v0, gmod, mu, model, fsn, bem, iws, qw, vw, qt, vt, &
                                fw, ft, wout, info, rim, rarm, frim, st, slin, smode, rail, frail, &
                                tangent, frame_yaw_rate, ryaw)
        type(pose_table), intent(in) :: ct
        integer, intent(in) :: model, fsn, bem, iws
        real(dp), intent(in) :: r0, v0, gmod, mu
        real(dp), intent(in) :: qw(6), vw(6), qt(3), vt(3)
        real(dp), intent(out) :: fw(6), ft(3), wout(nwo, 2)
        integer, intent(out) :: info
        real(dp), intent(in), optional :: rim(6, 2), rarm(2, 2)
        real(dp), intent(out), optional :: frim(3, 2)
        type(strip_geometry), intent(in), optional :: st
        type(strip_lin), intent(inout), optional :: slin(2)
        integer, intent(in), optional :: smode
        real(dp), intent(in), optional :: rail(6, 2)
        real(dp), intent(out), optional :: frail(3, 2)
        logical, intent(in), optional :: tangent
        real(dp), intent(in), optional :: frame_yaw_rate, ryaw(2)
        real(dp) :: vals(nq_table, 4), wt(4), grd(2, 4), wa(4), so(nso, 2), fwl(3), ftl(3), yf
        integer :: w, ia(4), ib(4)
        logical :: flex, strip, ring, tng
        type(wheel_pose) :: wp
        flex = present(rim) .and. present(rarm) .and. present(frim)
        strip = .false.
        if (present(st)) strip = st%on .and. (model == CMODEL_HERTZ_KALKER .or. model == CMODEL_HERTZ_FASTSIM)
        tng = .false.
        if (present(tangent)) tng = tangent .and. model == CMODEL_BEM
        yf = 0.0_dp
        if (present(frame_yaw_rate)) yf = frame_yaw_rate
        if (flex) frim = 0.0_dp
        ring = present(rail) .and. present(frail)
        if (ring) frail = 0.0_dp
        fw = 0.0_dp
        ft = 0.0_dp
        wout = 0.0_dp
        info = STAT_OK
        if (model < CMODEL_HERTZ_KALKER .or. model > CMODEL_BEM) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        ia = 1
        ib = 1
        wa = 0.0_dp
        do w = 1, 2
            call wheel_at(ct%rnom, w, qw, vw, qt, vt, flex, ring, wp, rim, rarm, rail)
            wp%psi = qw(4)
            if (present(ryaw)) wp%psi = qw(4) - ryaw(w)
            ftl = ft
            fwl = fw(1:3)
            if (strip) then
                call strip_points(ct, st, w, wp%psi, wp, so, vals, wt, info, slin, smode)
            else if (model == CMODEL_BEM) then
                call bem_points(ct, bem, iws, w, .not. tng, wp, vals, wt, grd, ia, ib, wa, info)
            else
                call pose_at(ct, wp%sg * wp%u, wp%pl, vals, wt, grd, info)
            end if
            if (info /= STAT_OK) return
            call wheel_points(ct%rnom, r0, v0, gmod, mu, model, tng, fsn, bem, iws, w, qw, vw, yf, wp, &
                              strip, so, vals, wt, grd, ia, ib, wa, fw, ft, wout(:, w), info)
            if (info /= STAT_OK) return
            if (flex) then
                fwl = fw(1:3) - fwl
                frim(1, w) = fwl(1)
                frim(2, w) = fwl(2)
                frim(3, w) = fwl(3) - rarm(2, w) * fwl(1) - wp%sg * rarm(1, w) * fwl(2)
            end if
            if (ring) frail(:, w) = ft - ftl
        end do
    end subroutine wheelset_contact

    !> Wheel w's pose and velocities in the frame of its track element (wheelset_contact): the
    !> element qt, vt, plus under a ring track (ring) the rail head's motion rail(:, w); the
    !> wheel the rigid wheelset's, moved by its rim's deformation rim(:, w) (flex). u = Y +
    !> r_nom phr with Y = yr + r_nom qtw(3), the centre's height zc (the element is rolled by
    !> qtw(3) about the track centre at rail-top height).
    pure subroutine wheel_at(rnom, w, qw, vw, qt, vt, flex, ring, wp, rim, rarm, rail)
        real(dp), intent(in) :: rnom, qw(6), vw(6), qt(3), vt(3)
        integer, intent(in) :: w
        logical, intent(in) :: flex, ring
        type(wheel_pose), intent(out) :: wp
        real(dp), intent(in), optional :: rim(6, 2), rarm(2, 2), rail(6, 2)
        real(dp) :: zr, ty, tz
        wp%sg = merge(1.0_dp, -1.0_dp, w == 1)
        wp%qtw = qt
        wp%vtw = vt
        if (ring) then
            ! this wheel's own track element: the rail head's motion under it (model RF)
            wp%qtw = qt + rail(1:3, w)
            wp%vtw = vt + rail(4:6, w)
        end if
        wp%yr = qw(1) - wp%qtw(1)
        zr = qw(2) - wp%qtw(2)
        wp%phr = qw(3) - wp%qtw(3)
        wp%u = wp%yr + rnom * qw(3)
        wp%zc = zr - wp%yr * wp%qtw(3)
        wp%ve = vw(1:3)
        if (flex) then
            ! this wheel's pose: the rigid wheelset's moved by the rim's deformation
            ty = rim(1, w) - rarm(2, w) * rim(3, w)
            tz = rim(2, w) - wp%sg * rarm(1, w) * rim(3, w)
            wp%yr = qw(1) + ty - wp%qtw(1)
            zr = qw(2) + tz - wp%qtw(2)
            wp%phr = qw(3) + rim(3, w) - wp%qtw(3)
            wp%u = wp%yr + rnom * (qw(3) + rim(3, w))
            wp%zc = zr - wp%yr * wp%qtw(3)
            wp%ve(1) = vw(1) + rim(4, w) - rarm(2, w) * rim(6, w)
            wp%ve(2) = vw(2) + rim(5, w) - wp%sg * rarm(1, w) * rim(6, w)
            wp%ve(3) = vw(3) + rim(6, w)
        end if
        wp%pl = wp%sg * wp%phr
    end subroutine wheel_at

    !> The strip contact's points of wheel w (wheelset_contact, strip): its strip outputs so at
    !> the pose (evaluated, kept with their derivatives in slin(w) under smode SLIN_KEEP, or
    !> read linearly from it under SLIN_READ) and one point per slot (candidates 1 and 3) with
    !> the Hertz ellipse and Kalker's coefficients of its mean curvature ratio. The table only
    !> bounds the lateral range: info STAT_OUTSIDE_TABLE outside it.
    pure subroutine strip_points(ct, st, w, yaw, wp, so, vals, wt, info, slin, smode)
        type(pose_table), intent(in) :: ct
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: w
        real(dp), intent(in) :: yaw
        type(wheel_pose), intent(in) :: wp
        real(dp), intent(out) :: so(nso, 2), vals(nq_table, 4), wt(4)
        integer, intent(inout) :: info
        type(strip_lin), intent(inout), optional :: slin(2)
        integer, intent(in), optional :: smode
        real(dp) :: su, pose(4), pr(5)
        integer :: k, c, lm
        su = (wp%sg * wp%u - ct%u0) / ct%du
        if (.not. (su >= 0.0_dp .and. su <= real(ct%ny - 1, dp))) then
            info = STAT_OUTSIDE_TABLE
            return
        end if
        ! the centre's lateral position in the element's frame: Y = u - r_nom phr
        ! and the yaw against the rail (mirrored for the right wheel; x is not)
        pose = [wp%sg * (wp%yr + ct%rnom * wp%qtw(3)), wp%zc, wp%pl, wp%sg * yaw]
        lm = 0
        if (present(slin) .and. present(smode)) lm = smode
        if (lm == SLIN_READ) then
            call strip_extrapolate(slin(w), pose, so)
        else if (lm == SLIN_KEEP) then
            call strip_linearise(st, pose, slin(w))
            so = slin(w)%so
        else
            call strip_wheel(st, pose(1), pose(2), pose(3), so, pose(4))
        end if
        wt = [1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp]
        vals = 0.0_dp
        do k = 1, 2
            c = 2 * k - 1
            call strip_props(st, so(SO_X, k), so(SO_A, k), pr)
            vals(2, c) = so(SO_L, k)
            vals(3, c) = so(SO_DELTA, k)
            vals(4, c) = so(SO_R, k)
            vals(5:6, c) = pr(1:2)
            vals(8:10, c) = pr(3:5)
            vals(IZARM, c) = so(SO_ZA, k)
        end do
    end subroutine strip_points

    !> The BEM's points of wheel w (wheelset_contact, CMODEL_BEM): the zero-roll row at u
    !> (table_at: members, nodes ia, ib, weights wa and shares wt), the point rotated about the
    !> centre by the roll to first order (the BEM's gap field is tilted by phr about the point
    !> in vehicle_bem), grd the gap's gradient (d/du, d/dphi). lead: tell the BEM which member
    !> of each slot has the larger share (the point its fields are reported of).
    subroutine bem_points(ct, bem, iws, w, lead, wp, vals, wt, grd, ia, ib, wa, info)
        type(pose_table), intent(in) :: ct
        integer, intent(in) :: bem, iws, w
        logical, intent(in) :: lead
        type(wheel_pose), intent(in) :: wp
        real(dp), intent(out) :: vals(nq_table, 4), wt(4), grd(2, 4), wa(4)
        integer, intent(out) :: ia(4), ib(4), info
        real(dp) :: za
        integer :: k, c
        call table_at(ct%ny, ct%tab(:, :, :, ct%j0), ct%u0, ct%du, wp%sg * wp%u, vals, ia, ib, wa, &
                      wt, info)
        if (info == STAT_OK .and. ct%nr > 1 .and. abs(wp%pl) > abs(ct%p0)) info = STAT_OUTSIDE_TABLE
        if (info /= STAT_OK) return
        if (lead) then
            do k = 1, 2
                c = 2 * k - 1
                if (wt(c + 1) > wt(c)) c = c + 1
                call bem_lead(bem, iws, w, c)
            end do
        end if
        do c = 1, 4
            if (.not. (wt(c) > 0.0_dp)) cycle
            za = vals(IZARM, c)
            grd(1, c) = -tan(vals(3, c))
            grd(2, c) = vals(2, c) + (ct%rnom - za) * tan(vals(3, c))
            vals(1, c) = vals(1, c) + grd(2, c) * wp%pl
            vals(IZARM, c) = za - vals(2, c) * wp%pl
            vals(2, c) = vals(2, c) + za * wp%pl
        end do
    end subroutine bem_points

    !> The forces of wheel w's candidate points c (slot k = (c + 1) / 2, its member 1 or 2 with
    !> load share wt(c); quantities vals(:, c), gap gradient grd(:, c), strip outputs so(:, k)
    !> under strip) added to fw, ft and to the wheel's outputs wo (wheelset_contact's wout(:, w)).
    !> Each point: its approach and Hertz force, its creepages from the relative velocities,
    !> its creep forces by the contact model (creep_kalker_she, fastsim_ellipse, point_bem or,
    !> under tangent, point_bem_tangent), then the generalised forces with the arms of the
    !> relative velocities (energy-consistent).
    subroutine wheel_points(rnom, r0, v0, gmod, mu, model, tangent, fsn, bem, iws, w, qw, vw, yf, wp, &
                            strip, so, vals, wt, grd, ia, ib, wa, fw, ft, wo, info)
        real(dp), intent(in) :: rnom, r0, v0, gmod, mu, qw(6), vw(6), yf
        integer, intent(in) :: model, fsn, bem, iws, w, ia(4), ib(4)
        logical, intent(in) :: tangent, strip
        type(wheel_pose), intent(in) :: wp
        real(dp), intent(in) :: so(nso, 2), vals(nq_table, 4), wt(4), grd(2, 4), wa(4)
        real(dp), intent(inout) :: fw(6), ft(3), wo(nwo)
        integer, intent(inout) :: info
        real(dp) :: fyn, fzn, mwn, mtn, mpn, fnsum, nbest, sg, gp, l, za, dlt, r, cd, sd, dv, dn
        real(dp) :: fn, a, b, xcp, dvy, dvz, xi, eta, spin, fx, fy, mz, xc, yc, fyt, fzt
        real(dp) :: mtx, mty, mx, my, mzt
        integer :: k, c, stat
        sg = wp%sg
        nbest = -1.0_dp
        fnsum = 0.0_dp
        do c = 1, 4
            k = (c + 1) / 2
            if (.not. (wt(c) > 0.0_dp)) cycle
            gp = vals(1, c)
            l = sg * vals(2, c)
            za = vals(IZARM, c)
            dlt = vals(3, c)
            r = vals(4, c)
            cd = cos(dlt)
            sd = sin(dlt)
            dv = -(gp + wp%zc)
            dn = dv * cd
            if (strip) dn = so(SO_N, k)
            if (dn <= 0.0_dp) then
                ! clear a BEM point's state (warm start, reported fields) when it opens
                if (model == CMODEL_BEM .and. .not. tangent) &
                    call bem_patch(bem, iws, w, c, ia(c), ib(c), wa(c), dn, wp%phr, 0.0_dp, 0.0_dp, &
                                   0.0_dp, mu, v0, fn, fx, fy, mz, xc, yc, stat)
                cycle
            end if
            if (strip) then
                fn = so(SO_N, k)
            else
                fn = vals(7, c) * dn * sqrt(dn)
            end if
            mz = 0.0_dp
            xc = 0.0_dp
            yc = 0.0_dp
            a = vals(5, c) * fn**(1.0_dp / 3.0_dp)
            b = vals(6, c) * fn**(1.0_dp / 3.0_dp)
            ! the strip's contact lies xcp ahead of the axle under yaw (the table's at 0)
            xcp = 0.0_dp
            if (strip) xcp = so(SO_XC, k)
            ! relative velocity of the wheel's material point (arms l, za about the
            ! wheelset centre) over the rail's (arms l + yr, r_nom - za about the track's
            ! roll centre): the arms of the generalised forces below (energy-consistent)
            dvy = (wp%ve(1) + za * wp%ve(3) + xcp * vw(4)) - (wp%vtw(1) - (rnom - za) * wp%vtw(3))
            dvz = (wp%ve(2) + wp%ve(3) * l - xcp * vw(6)) - (wp%vtw(2) + wp%vtw(3) * (l + wp%yr))
            ! longitudinal creepage: the material velocity of the wheel at the contact
            ! point (0, l, -r) from the axle centre, along x, is v0 + xdot - psidot l
            ! - (Omega0 + betadot) r (w x p with w = (., Omega0 + betadot, psidot));
            ! over the rail (at rest), divided by v0, with Omega0 = v0 / r0. In a curve the
            ! wheelset's track frame turns at yf = v0 kappa (wheelset_contact's frame_yaw_rate):
            ! its absolute yaw rate psidot + yf enters xi (-kappa l: the inner wheel's shorter
            ! path) and the spin; in the lateral slip the frame's turn cancels against the
            ! rail's turned tangent at the point (docs/vehicle_curving.md)
            xi = vw(5) / v0 + (1.0_dp - r / r0) - (vw(4) + yf) * l / v0 - vw(6) * r / v0
            eta = (dvy * cd + sg * sd * dvz) / v0 - wp%psi / cd
            spin = (-sg * sd + cd * wp%phr) / r0 + cd * (vw(4) + yf) / v0
            if (model == CMODEL_BEM .and. tangent) then
                call point_bem_tangent(bem, iws, w, c, ia(c), wa(c), dn, wp%phr, xi, eta, spin, gmod, &
                                       a, b, vals(7:10, c), mu, fn, fx, fy, mz, xc, yc)
            else if (model == CMODEL_BEM) then
                call point_bem(bem, iws, w, c, ia(c), ib(c), wa(c), dn, wp%phr, xi, eta, spin, mu, v0, &
                               gmod, a, b, vals(8:10, c), fn, fx, fy, mz, xc, yc, info)
                if (info /= STAT_OK) return
                if (fn <= 0.0_dp) cycle
            else if (model == CMODEL_HERTZ_KALKER) then
                call creep_kalker_she(gmod, a, b, vals(8, c), vals(9, c), vals(10, c), mu, fn, &
                                      xi, eta, spin, fx, fy)
            else
                call fastsim_ellipse(a, b, gmod, vals(8, c), vals(9, c), vals(10, c), mu, fn, &
                                     xi, eta, spin, fsn, fsn, fx, fy, mz)
            end if
            ! a member's share of its slot's load (pose_at)
            fn = wt(c) * fn
            fx = wt(c) * fx
            fy = wt(c) * fy
            mz = wt(c) * mz
            call normal_forces(strip, so(:, k), grd(:, c), sg, rnom, wp%yr, wp%qtw(3), fn * cd, &
                               fyn, fzn, mwn, mtn, mpn)
            ! the creep forces along t_y = (0, cos, sg sin) with the geometric arms
            fyt = fy * cd
            fzt = fy * sg * sd
            ! moment about the point of the contact stresses (patch's centre of pressure
            ! and spin moment; the Hertz patch is centred on the point): Fn yc t_x
            ! - Fn xc t_y + mz n, in track axes
            mtx = fn * yc
            mty = -fn * xc
            mx = mtx
            my = mty * cd - mz * sg * sd
            mzt = mty * sg * sd + mz * cd
            fw(1) = fw(1) + fyt + fyn
            fw(2) = fw(2) + fzt + fzn
            fw(3) = fw(3) + l * fzt + za * fyt + mx + mwn
            fw(4) = fw(4) - l * fx + xcp * fyt + mzt + mpn
            ! Fx acts on x; its moment about the axle (y) at p = (0, l, -r) is
            ! (p x F)_y = p_z Fx - p_x Fz = -r Fx (it opposes the xi it comes from)
            fw(5) = fw(5) + fx
            fw(6) = fw(6) - r * fx - xcp * fzt + my
            ft(1) = ft(1) - fyt - fyn
            ft(2) = ft(2) - fzt - fzn
            ft(3) = ft(3) - (l + wp%yr) * fzt + (rnom - za) * fyt - mx + mtn
            wo(1) = wo(1) + fzt + fzn
            wo(2) = wo(2) + fyt + fyn + fzn * wp%qtw(3)      ! track axes
            wo(3) = wo(3) + fx
            wo(3 + k) = wo(3 + k) + fn
            if (strip) then
                wo(9) = wo(9) + so(SO_V, k)
            else
                wo(9) = wo(9) + wt(c) * 0.4_dp * vals(7, c) * dn * dn * sqrt(dn)
            end if
            wo(14) = wo(14) + mtx
            wo(15) = wo(15) + mz
            ! the point's arm in the wheel's frame: (l, -za) rotated back by the roll pl
            wo(IO_ARM) = wo(IO_ARM) + fn * (cos(wp%pl) * sg * l - sin(wp%pl) * za)
            wo(16) = wo(16) - (fx * xi + fy * eta)
            fnsum = fnsum + fn
            if (fn > nbest) then
                nbest = fn
                wo(6) = xi
                wo(7) = eta
                wo(8) = spin
                wo(10) = dlt
                wo(11) = a
                wo(12) = b
                wo(13) = yc
                wo(17) = hypot(fx, fy)
            end if
        end do
        if (fnsum > 0.0_dp) wo(IO_ARM) = wo(IO_ARM) / fnsum
    end subroutine wheel_points

    !> The generalised components of one point's normal force (wheel_points): fyn, fzn on the
    !> wheelset's y, z, mwn on its roll, mtn on the track element's roll, mpn on the yaw.
    !> From the gradient of the gap the approach came from (-dV/dq of the Hertz potential:
    !> conservative), the left wheel's table read at (sg u, sg phr): g_u = -tan(delta), g_phi
    !> = l + (r_nom - za) tan(delta) to first order (grd), with the track's frame terms of zc,
    !> and fzn = fnc the normal force's vertical part; or under strip -grad V of the strip
    !> potential (sok: the slot's strip outputs) over Y = yr + r_nom qt3, zc = zr - yr qt3,
    !> phr (the right wheel's V read mirrored).
    pure subroutine normal_forces(strip, sok, grd, sg, rnom, yr, qt3, fnc, fyn, fzn, mwn, mtn, mpn)
        logical, intent(in) :: strip
        real(dp), intent(in) :: sok(nso), grd(2), sg, rnom, yr, qt3, fnc
        real(dp), intent(out) :: fyn, fzn, mwn, mtn, mpn
        real(dp) :: gy, gz, gph
        if (strip) then
            gy = sg * sok(SO_DY)
            gz = sok(SO_DZ)
            gph = sg * sok(SO_DPHI)
            fzn = -gz
            fyn = -(gy - gz * qt3)
            mwn = -gph
            mtn = -(gy * rnom - gz * yr - gph)
            ! the yaw moment of the normal forces: -dV/dpsi
            mpn = -sg * sok(SO_DPSI)
        else
            fzn = fnc
            fyn = fzn * (sg * grd(1) - qt3)
            mwn = fzn * sg * (grd(1) * rnom + grd(2))
            mtn = -fzn * (sg * grd(2) + yr)
            mpn = 0.0_dp
        end if
    end subroutine normal_forces

    !> CMODEL_BEM at one point (wheel_points): the BEM's normal and steady-rolling solve of
    !> the patch (vehicle_bem%bem_patch; fn in: the Hertz force, out: the BEM's), then the
    !> calibration of the Newton tangent's cheap model (point_bem_tangent) against this solve:
    !> the ratios BEM / Hertz-Kalker of the normal force and of the creep force (bem_scale).
    subroutine point_bem(bem, iws, w, c, ia, ib, wa, dn, phr, xi, eta, spin, mu, v0, gmod, a, b, &
                         ck, fn, fx, fy, mz, xc, yc, info)
        integer, intent(in) :: bem, iws, w, c, ia, ib
        real(dp), intent(in) :: wa, dn, phr, xi, eta, spin, mu, v0, gmod, a, b, ck(3)
        real(dp), intent(inout) :: fn
        real(dp), intent(out) :: fx, fy, mz, xc, yc
        integer, intent(out) :: info
        real(dp) :: fnh, fxk, fyk, rt(2)
        fnh = fn
        call bem_patch(bem, iws, w, c, ia, ib, wa, dn, phr, xi, eta, spin, mu, v0, &
                       fn, fx, fy, mz, xc, yc, info)
        if (info /= STAT_OK) return
        if (fn <= 0.0_dp) return
        call creep_kalker_she(gmod, a, b, ck(1), ck(2), ck(3), mu, fnh, xi, eta, spin, fxk, fyk)
        rt(1) = min(max(fn / fnh, 0.5_dp), 2.0_dp)
        rt(2) = 1.0_dp
        if (hypot(fxk, fyk) > 0.05_dp * mu * fnh) &
            rt(2) = min(max(hypot(fx, fy) / hypot(fxk, fyk), 0.5_dp), 2.0_dp)
        call bem_scale(bem, iws, w, c, .true., rt)
    end subroutine point_bem

    !> The Newton tangent of a BEM run at one point (wheel_points, CMODEL_BEM with tangent): the
    !> patch's linear model from differences of its own solves (vehicle_bem%bem_linear), else
    !> Hertz (kc(1) = kH) + Kalker (kc(2:4)) scaled to the last BEM solve of this point.
    subroutine point_bem_tangent(bem, iws, w, c, ia, wa, dn, phr, xi, eta, spin, gmod, a, b, kc, mu, &
                                 fn, fx, fy, mz, xc, yc)
        integer, intent(in) :: bem, iws, w, c, ia
        real(dp), intent(in) :: wa, dn, phr, xi, eta, spin, gmod, a, b, kc(4), mu
        real(dp), intent(inout) :: fn, fx, fy, mz, xc, yc
        real(dp) :: rt(2)
        logical :: lin
        call bem_linear(bem, iws, w, c, ia, wa, dn, phr, xi, eta, spin, fn, fx, fy, mz, xc, yc, lin)
        if (lin) return
        fn = kc(1) * dn * sqrt(dn)
        call bem_scale(bem, iws, w, c, .false., rt)
        fn = rt(1) * fn
        call creep_kalker_she(gmod, a, b, kc(2), kc(3), kc(4), mu, fn, xi, eta, spin, fx, fy)
        fx = rt(2) * fx
        fy = rt(2) * fy
    end subroutine point_bem_tangent

end module vehicle_contact
