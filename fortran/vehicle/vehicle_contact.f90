!> Wheel-rail contact forces of one rigid wheelset on its (rigid or elastic) track element,
!> from a precomputed per-wheel contact table (the usual MBS look-up-table approach).
!>
!> Table (left wheel; the right wheel is its mirror): uniform in the lateral displacement
!> y_r of the wheelset relative to the track, two candidate points per wheel (slot 1 the
!> tread side, slot 2 the flange side of a split of the wheel profile), quantities
!>   1 g   vertical gap at nominal height and zero roll, m
!>   2 l   lateral position of the point from the wheelset centre (left wheel), m
!>   3 delta contact angle (rail normal from vertical, + towards the track centre), rad
!>   4 r   rolling radius, m
!>   5 a1, 6 b1  Hertz semi-axes (rolling, lateral) for a 1 N load, m N^(-1/3)
!>   7 kH  Hertz law N = kH * d^1.5 with d the normal approach, N m^(-1.5)
!>   8 c11, 9 c22, 10 c23  Kalker's linear creep coefficients at a1/b1,
!>   11 branch label of the slot's point (a local minimum of the gap followed continuously
!>      in y; table_at never interpolates between two labels).
!> Quasi-elastic contact: the vertical interference of a point is
!> -(g + z_w - z_t + phi_w l - phi_t (l + y_rel)) (wheelset roll about its centre, track roll
!> about the track centre, the arms of the generalised forces),
!> its normal approach that times cos(delta). Creepages from the wheelset's velocities with
!> the nominal rolling speed Omega0 = v0/r0 plus the spin perturbation rate betadot (no
!> rotation angle: only the rate enters). Forces on the wheel in track axes.
!> Implements Hertz's law, Kalker's linear theory with the Shen-Hedrick-Elkins saturation
!> (creep_kalker_she) and FASTSIM through contact_fastsim; no Kaiser equation.
module vehicle_contact
    use common_kinds, only: dp
    use contact_fastsim, only: fastsim_ellipse
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_OUTSIDE_TABLE
    use vehicle_bem, only: bem_patch, bem_scale
    implicit none
    private
    public :: nq_table, nwo, wheelset_contact, creep_kalker_she
    public :: CMODEL_HERTZ_KALKER, CMODEL_FASTSIM, CMODEL_BEM, CMODEL_BEM_TANGENT

    !> Contact models (wheelset_contact's `model`); Python's CONTACT_MODELS names the first three.
    integer, parameter :: CMODEL_HERTZ_KALKER = 1, CMODEL_FASTSIM = 2, CMODEL_BEM = 3
    integer, parameter :: CMODEL_BEM_TANGENT = 4

    integer, parameter :: nq_table = 11
    !> Table quantity holding the branch label of each slot's point (see table_at).
    integer, parameter :: IBRANCH = 11
    !> Outputs per wheel: 1 Q (vertical force on the wheel), 2 Y (lateral force on the wheel,
    !> track y), 3 Fx (longitudinal), 4 N tread, 5 N flange, 6 xi, 7 eta, 8 spin (1/m) of the
    !> point with the larger normal force, 9 Hertz potential energy (J), 10 its contact angle,
    !> 11 a, 12 b semi-axes of that point (m), 13 its centre of pressure along t_y from the
    !> point (m, BEM; 0 for the Hertz patch), 14 the moment of the wheel's contact stresses
    !> about its points along t_x (N m, sum Fn yc), 15 the spin moment about the normals (N m).
    integer, parameter :: nwo = 15

contains

    !> The table at y, per slot: vals(:, k) = (1 - wa(k)) tab(:, k, ia(k)) + wa(k) tab(:, k, ib(k)).
    !> Within one branch (quantity IBRANCH equal at both nodes of the interval) that is the
    !> linear interpolation. Where the slot's point changes branch inside the interval (it
    !> jumps to another local minimum of the gap), fields and points of the two branches are
    !> never mixed: each side's branch is extrapolated linearly from its own two nodes (a
    !> single node when its neighbour is another branch) and the one with the smaller gap is
    !> taken, as the geometry does (the slot's point is the minimum of the two branches;
    !> their gaps cross inside the interval, so the choice and the gap are continuous).
    !> info STAT_OUTSIDE_TABLE when y is outside the table.
    pure subroutine table_at(ny, tab, y0, dy, y, vals, ia, ib, wa, info)
        integer, intent(in) :: ny
        real(dp), intent(in) :: tab(nq_table, 2, ny), y0, dy, y
        real(dp), intent(out) :: vals(nq_table, 2), wa(2)
        integer, intent(out) :: ia(2), ib(2), info
        real(dp) :: s, w, g1, g2, w1, w2
        integer :: i, k, a1, b1, a2, b2
        ia = 1
        ib = 1
        wa = 0.0_dp
        s = (y - y0) / dy
        if (.not. (s >= 0.0_dp .and. s <= real(ny - 1, dp))) then
            info = STAT_OUTSIDE_TABLE
            vals = 0.0_dp
            return
        end if
        info = STAT_OK
        i = min(int(s), ny - 2) + 1
        w = s - real(i - 1, dp)
        do k = 1, 2
            if (tab(IBRANCH, k, i) == tab(IBRANCH, k, i + 1)) then
                ia(k) = i
                ib(k) = i + 1
                wa(k) = w
            else
                call side(i, -1, 1.0_dp + w, a1, b1, w1)
                call side(i + 1, 1, w - 1.0_dp, a2, b2, w2)
                g1 = (1.0_dp - w1) * tab(1, k, a1) + w1 * tab(1, k, b1)
                g2 = (1.0_dp - w2) * tab(1, k, a2) + w2 * tab(1, k, b2)
                if (g1 <= g2) then
                    ia(k) = a1
                    ib(k) = b1
                    wa(k) = w1
                else
                    ia(k) = a2
                    ib(k) = b2
                    wa(k) = w2
                end if
            end if
            vals(:, k) = (1.0_dp - wa(k)) * tab(:, k, ia(k)) + wa(k) * tab(:, k, ib(k))
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
    !> model CMODEL_HERTZ_KALKER: Hertz + Kalker linear with SHE saturation; CMODEL_FASTSIM:
    !> Hertz + FASTSIM (contact_fastsim, fsn x fsn strips x points); CMODEL_BEM: the BEM
    !> normal and steady-rolling solvers of vehicle_bem (state `bem`, wheelset index iws) with
    !> the same approach and creepages (the Hertz semi-axes and energy are still reported in
    !> wout); CMODEL_BEM_TANGENT: Hertz + Kalker with the normal force and the creep forces
    !> scaled by their ratios BEM / Hertz-Kalker at the last BEM solve of each point (the
    !> Newton tangent of a BEM run).
    !> fw: generalised forces on the wheelset (y, z, roll, yaw, x, beta); ft: on the track element.
    !> info: STAT_OK, STAT_BAD_ARGUMENT (unknown model), STAT_OUTSIDE_TABLE, or from
    !> vehicle_bem%bem_patch (STAT_GRID_EDGE, STAT_CONTACT_NOT_CONVERGED, STAT_BAD_HANDLE).
    subroutine wheelset_contact(ny, tab, y0, dy, r0, v0, gmod, mu, model, fsn, bem, iws, qw, vw, qt, vt, &
                                fw, ft, wout, info)
        integer, intent(in) :: ny, model, fsn, bem, iws
        real(dp), intent(in) :: tab(nq_table, 2, ny), y0, dy, r0, v0, gmod, mu
        real(dp), intent(in) :: qw(6), vw(6), qt(3), vt(3)
        real(dp), intent(out) :: fw(6), ft(3), wout(nwo, 2)
        integer, intent(out) :: info
        real(dp) :: vals(nq_table, 2), sg, yr, zr, phr, dvy, dvz
        real(dp) :: gp, l, dlt, r, dv, dn, fn, a, b, cd, sd, xi, eta, spin, fx, fy, fyt, fzt
        real(dp) :: nbest, mz, fnh, fxk, fyk, rt(2), xc, yc, mtx, mty, mx, my, mzt
        real(dp) :: wa(2)
        integer :: w, k, stat, ia(2), ib(2)
        fw = 0.0_dp
        ft = 0.0_dp
        wout = 0.0_dp
        info = STAT_OK
        if (model < CMODEL_HERTZ_KALKER .or. model > CMODEL_BEM_TANGENT) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        yr = qw(1) - qt(1)
        zr = qw(2) - qt(2)
        phr = qw(3) - qt(3)
        do w = 1, 2
            sg = merge(1.0_dp, -1.0_dp, w == 1)
            call table_at(ny, tab, y0, dy, sg * yr, vals, ia, ib, wa, info)
            if (info /= STAT_OK) return
            nbest = -1.0_dp
            do k = 1, 2
                gp = vals(1, k)
                l = sg * vals(2, k)
                dlt = vals(3, k)
                r = vals(4, k)
                cd = cos(dlt)
                sd = sin(dlt)
                ! the wheel point moves with the wheelset's roll about its centre (arm l), the
                ! rail point with the track element's roll about the track centre (arm l + yr,
                ! the same arm as the generalised force ft(3) below: energy-consistent)
                dv = -(gp + zr + qw(3) * l - qt(3) * (l + yr))
                dn = dv * cd
                if (dn <= 0.0_dp) then
                    ! clear a BEM point's state (warm start, reported fields) when it opens
                    if (model == CMODEL_BEM) call bem_patch(bem, iws, w, k, ia(k), ib(k), wa(k), dn, &
                                                             phr, 0.0_dp, 0.0_dp, 0.0_dp, mu, v0, &
                                                             fn, fx, fy, mz, xc, yc, stat)
                    cycle
                end if
                fn = vals(7, k) * dn * sqrt(dn)
                mz = 0.0_dp
                xc = 0.0_dp
                yc = 0.0_dp
                a = vals(5, k) * fn**(1.0_dp / 3.0_dp)
                b = vals(6, k) * fn**(1.0_dp / 3.0_dp)
                ! relative velocity of the wheel's material point over the rail's
                dvy = (vw(1) + r * vw(3)) - vt(1)
                dvz = (vw(2) + vw(3) * l) - (vt(2) + vt(3) * (l + yr))
                ! longitudinal creepage: the material velocity of the wheel at the contact
                ! point (0, l, -r) from the axle centre, along x, is v0 + xdot - psidot l
                ! - (Omega0 + betadot) r (w x p with w = (., Omega0 + betadot, psidot));
                ! over the rail (at rest), divided by v0, with Omega0 = v0 / r0:
                xi = vw(5) / v0 + (1.0_dp - r / r0) - vw(4) * l / v0 - vw(6) * r / v0
                eta = (dvy * cd + sg * sd * dvz) / v0 - qw(4) / cd
                spin = (-sg * sd + cd * phr) / r0 + cd * vw(4) / v0
                if (model == CMODEL_BEM) then
                    fnh = fn
                    call bem_patch(bem, iws, w, k, ia(k), ib(k), wa(k), dn, phr, xi, eta, spin, mu, v0, &
                                   fn, fx, fy, mz, xc, yc, info)
                    if (info /= STAT_OK) return
                    if (fn <= 0.0_dp) cycle
                    ! calibration of the tangent's cheap model (4) against this solve
                    call creep_kalker_she(gmod, a, b, vals(8, k), vals(9, k), vals(10, k), mu, fnh, &
                                          xi, eta, spin, fxk, fyk)
                    rt(1) = min(max(fn / fnh, 0.5_dp), 2.0_dp)
                    rt(2) = 1.0_dp
                    if (hypot(fxk, fyk) > 0.05_dp * mu * fnh) &
                        rt(2) = min(max(hypot(fx, fy) / hypot(fxk, fyk), 0.5_dp), 2.0_dp)
                    call bem_scale(bem, iws, w, k, .true., rt)
                else if (model == CMODEL_BEM_TANGENT) then
                    ! Hertz + Kalker scaled to the last BEM solve of this point (Newton tangent)
                    call bem_scale(bem, iws, w, k, .false., rt)
                    fn = rt(1) * fn
                    call creep_kalker_she(gmod, a, b, vals(8, k), vals(9, k), vals(10, k), mu, fn, &
                                          xi, eta, spin, fx, fy)
                    fx = rt(2) * fx
                    fy = rt(2) * fy
                else if (model == CMODEL_HERTZ_KALKER) then
                    call creep_kalker_she(gmod, a, b, vals(8, k), vals(9, k), vals(10, k), mu, fn, &
                                          xi, eta, spin, fx, fy)
                else
                    call fastsim_ellipse(a, b, gmod, vals(8, k), vals(9, k), vals(10, k), mu, fn, &
                                         xi, eta, spin, fsn, fsn, fx, fy, mz)
                end if
                ! n = (0, -sg sin, cos), t_y = (0, cos, sg sin)
                fyt = fy * cd - sg * fn * sd
                fzt = fy * sg * sd + fn * cd
                ! moment about the point of the contact stresses (patch's centre of pressure
                ! and spin moment; the Hertz patch is centred on the point): Fn yc t_x
                ! - Fn xc t_y + mz n, in track axes
                mtx = fn * yc
                mty = -fn * xc
                mx = mtx
                my = mty * cd - mz * sg * sd
                mzt = mty * sg * sd + mz * cd
                fw(1) = fw(1) + fyt
                fw(2) = fw(2) + fzt
                fw(3) = fw(3) + l * fzt + r * fyt + mx
                fw(4) = fw(4) - l * fx + mzt
                ! Fx acts on x; its moment about the axle (y) at p = (0, l, -r) is
                ! (p x F)_y = p_z Fx - p_x Fz = -r Fx (it opposes the xi it comes from)
                fw(5) = fw(5) + fx
                fw(6) = fw(6) - r * fx + my
                ft(1) = ft(1) - fyt
                ft(2) = ft(2) - fzt
                ft(3) = ft(3) - (l + yr) * fzt - mx
                wout(1, w) = wout(1, w) + fzt
                wout(2, w) = wout(2, w) + fyt
                wout(3, w) = wout(3, w) + fx
                wout(3 + k, w) = fn
                wout(9, w) = wout(9, w) + 0.4_dp * vals(7, k) * dn * dn * sqrt(dn)
                wout(14, w) = wout(14, w) + mtx
                wout(15, w) = wout(15, w) + mz
                if (fn > nbest) then
                    nbest = fn
                    wout(6, w) = xi
                    wout(7, w) = eta
                    wout(8, w) = spin
                    wout(10, w) = dlt
                    wout(11, w) = a
                    wout(12, w) = b
                    wout(13, w) = yc
                end if
            end do
        end do
    end subroutine wheelset_contact

end module vehicle_contact
