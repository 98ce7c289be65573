!> The normal contact problem on a grid (Kaiser, eqs 17-23): find pressures
!> p >= 0 such that the deformed gap
!>     e = h + A p - delta                                        (eq. 21)
!> is zero where p > 0 and non-negative where p = 0, for an undeformed gap h,
!> the approach delta and the Boussinesq influence matrix A. Either delta is
!> prescribed, or the total force Fn = dx dy sum(p).
!>
!> Two solvers:
!>   normal_cg  projected conjugate gradients with FFT products
!>              (Polonsky & Keer, Wear 231, 1999, sect. 3); also resumable in
!>              slices of iterations (normal_cg_begin, normal_cg_steps), the
!>              iterate held by the caller;
!>   normal_gs  projected Gauss-Seidel, p_i <- max(0, p_i - e_i / A_ii)
!>              (eq. 23), with force scaling after each sweep when the
!>              force is prescribed; also resumable in slices of work
!>              (normal_gs_start, normal_gs_resume) so that a caller can
!>              show progress and stop between slices.
!> Both stop on the relative complementarity residual (normal_residual) and
!> accept a warm start in p.
!>
!> Sub-patches (optional lab, fac of the resumable solvers): a patch holding several
!> contact areas side by side may weaken the elastic interaction between them, as CONTACT
!> does (its planform IPLAN = 4, reduced interaction between sub-patches): grid column j
!> belongs to sub-patch lab(j), and the displacement that pressures in sub-patch b cause
!> in sub-patch a is scaled by fac(a, b), fac(a, a) = 1,
!>     u_I = sum_J fac(lab(I), lab(J)) A_IJ p_J.
!> For a symmetric fac with entries in [0, 1] this operator is f A + (1 - f) diag(A_aa)
!> for two sub-patches, symmetric positive definite: CG applies unchanged. Each product
!> then costs one FFT product per sub-patch; the preconditioner stays that of A.
!> Implements Kaiser eqs 17-23 (eq. 18 with piecewise-constant elements, not bilinear ones)
!> and Polonsky & Keer's projected CG (docs/equations.md).
module contact_normal
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, STAT_NOT_FINITE
    use contact_convolution, only: conv_plan, conv_apply, conv_apply_buffer, conv_precond_buffer, &
                                   conv_apply_dense, DENSE_MAX
    implicit none
    private
    public :: CONTROL_FORCE, CONTROL_APPROACH
    public :: normal_cg, normal_gs, normal_gs_start, normal_gs_resume, normal_residual
    public :: normal_cg_begin, normal_cg_steps, subpatches_valid, CG_RSTATE, CG_ISTATE

    integer, parameter :: CONTROL_FORCE = 1, CONTROL_APPROACH = 2
    !> Exact product every this many CG steps, against drift of the recurrence.
    integer, parameter :: REFRESH = 16
    !> Up to this many changed elements, u is corrected column by column
    !> (O(N) each) rather than by an FFT product (O(N log N)), on grids of at most
    !> DENSE_MAX elements; on larger ones up to column_limit(nx, ny).
    integer, parameter :: MAX_COLUMNS = 24
    !> Sizes of the scalar state of a resumable CG solve: rs = (gold, shift),
    !> is = (it, iters, nprod, conjugate, exact) (logicals as 0/1).
    integer, parameter :: CG_RSTATE = 2, CG_ISTATE = 5
    !> Share of an FFT product's operation count that column corrections may take
    !> (column_limit). Measured at 450 x 450, a column sum costs 1/150 of a plain product
    !> on an SSE2-era CPU and 1/83 on an AVX2 one (FFTW's kernels use the wider vectors,
    !> the build's loops do not), and the solvers' pruned product costs 0.6-0.7 of a plain
    !> one: a quarter of the count is then about one pruned product's time on the AVX2 CPU.
    real(dp), parameter :: COLUMN_SHARE = 0.25_dp
    !> Tolerances down to this one stop on the recurrence's u = A p without confirming it
    !> on an exact product: the recurrence drifts from A p by rounding only (a few eps |u|
    !> a step, at most REFRESH steps), 1e4 times below it (docs/normal_contact.md).
    real(dp), parameter :: CONFIRM_TOL = 1.0e-10_dp

contains

    !> Relative complementarity residual || v || / || delta - h ||, with
    !> v = e where p > 0 and v = min(e, 0) where p = 0, e = h + u - delta the
    !> deformed gap and u = A p; both norms over the elements in contact or
    !> interpenetrating. At the solution A p = delta - h there, so the
    !> denominator is the size of the deformation.
    pure real(dp) function normal_residual(e, p, u) result(res)
        real(dp), intent(in) :: e(:, :), p(:, :), u(:, :)
        real(dp) :: sv, sb
        sv = sum(e**2, mask=p > 0.0_dp) + sum(min(e, 0.0_dp)**2, mask=p <= 0.0_dp)
        sb = sum((u - e)**2, mask=p > 0.0_dp .or. e < 0.0_dp)
        if (sb > 0.0_dp) then
            res = sqrt(sv / sb)
        else
            res = 0.0_dp
        end if
    end function normal_residual

    !> Projected conjugate gradients (Polonsky & Keer 1999).
    !> info: STAT_OK converged; STAT_NOT_CONVERGED not converged in max_iter
    !> (or a breakdown: a non-positive curvature (r, t), all pressure projected
    !> away under force control); STAT_NO_CONTACT approach prescribed and below
    !> the smallest gap (p = 0 is the solution); STAT_NOT_FINITE a NaN in p.
    !>
    !> Each iteration makes one product A t and one preconditioner
    !> application, and a few fused passes over the grid; the products and
    !> the preconditioner read and write the FFT buffers in place. After the
    !> projection, u = A p is corrected column by column when few elements
    !> changed, by an exact product otherwise. A product is a sum of columns of A
    !> (O(nc N), nc elements in contact) when that takes fewer operations than the
    !> zero-padded FFT (columns_are_cheaper: small grids such as 11 x 11); the two
    !> agree to rounding.
    subroutine normal_cg(plan, kz, c, h, area_el, control, fn, approach, tol, max_iter, &
                         p, iters, nprod, resid, info)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, control, max_iter
        real(dp), intent(in) :: c(0:, 0:)     ! coefficients of kernel kz (influence_field layout)
        real(dp), intent(in) :: h(:, :), area_el, tol
        real(dp), intent(inout) :: fn, approach
        real(dp), intent(inout) :: p(:, :)
        integer, intent(out) :: iters, nprod, info
        real(dp), intent(out) :: resid
        real(dp), allocatable :: u(:, :), t(:, :)
        real(dp) :: rs(CG_RSTATE)
        integer :: is(CG_ISTATE)
        logical :: done

        allocate (u, t, mold=h)
        call normal_cg_begin(plan, kz, h, area_el, control, fn, approach, p, u, t, rs, is, &
                             resid, info, done, c)
        if (.not. done) call normal_cg_steps(plan, kz, c, h, area_el, control, fn, approach, tol, &
                                             max_iter, huge(1), p, u, t, rs, is, resid, info, done)
        iters = is(2)
        nprod = is(3)
    end subroutine normal_cg

    !> The start of a resumable projected CG solve (normal_cg = normal_cg_begin, then
    !> normal_cg_steps until done): the no-contact test, the initial pressure and
    !> u = A p, and the state (t, rs, is) of iteration 0. done: the solve has
    !> finished already (STAT_NO_CONTACT). c (optional): the coefficients of kernel kz
    !> (influence_field layout), for a product by columns on small grids (apply_a).
    subroutine normal_cg_begin(plan, kz, h, area_el, control, fn, approach, p, u, t, rs, is, &
                               resid, info, done, c, lab, fac)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, control
        real(dp), intent(in) :: h(:, :), area_el
        real(dp), intent(in), optional :: c(0:, 0:)
        integer, intent(in), optional :: lab(:)       ! sub-patch of each grid column
        real(dp), intent(in), optional :: fac(:, :)   ! interaction factors between sub-patches
        real(dp), intent(inout) :: fn, approach, p(:, :)
        real(dp), intent(out) :: u(:, :), t(:, :), rs(CG_RSTATE), resid
        integer, intent(out) :: is(CG_ISTATE), info
        logical, intent(out) :: done
        real(dp) :: scale
        integer :: nprod
        logical :: force

        info = STAT_OK
        resid = huge(1.0_dp)
        nprod = 0
        force = control == CONTROL_FORCE
        u = 0.0_dp
        t = 0.0_dp
        rs = [1.0_dp, approach]
        is = [0, 0, 0, 0, 1]
        done = no_contact(control, h, approach, p, fn, resid, info)
        if (done) return
        call initial_pressure(plan, kz, h, force, approach, p, u, nprod, c, lab, fac)
        if (force) then
            scale = fn / (area_el * sum(p))
            p = scale * p
            u = scale * u
        end if
        is(3) = nprod
    end subroutine normal_cg_begin

    !> Up to budget iterations of a resumable projected CG solve from the state
    !> (p, u = A p or its recurrence, t, rs, is) that normal_cg_begin or the previous
    !> call left; the numbers are those of one normal_cg call. done: finished, with
    !> fn or approach, resid and info final (info STAT_OK while not done).
    !> One iteration is seven passes over the grid: cg_contact_set (1), cg_gap (2),
    !> cg_precondition (3), cg_direction (4, with the product A t), cg_curvature (5),
    !> cg_project (6), cg_update (7, u = A p by columns or by an exact product).
    subroutine normal_cg_steps(plan, kz, c, h, area_el, control, fn, approach, tol, max_iter, &
                               budget, p, u, t, rs, is, resid, info, done, lab, fac)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, control, max_iter, budget
        real(dp), intent(in) :: c(0:, 0:)     ! coefficients of kernel kz (influence_field layout)
        real(dp), intent(in) :: h(:, :), area_el, tol
        real(dp), intent(inout) :: fn, approach
        real(dp), intent(inout) :: p(:, :), u(:, :), t(:, :), rs(CG_RSTATE), resid
        integer, intent(inout) :: is(CG_ISTATE)
        integer, intent(out) :: info
        logical, intent(out) :: done
        integer, intent(in), optional :: lab(:)       ! sub-patch of each grid column
        real(dp), intent(in), optional :: fac(:, :)   ! interaction factors between sub-patches
        real(dp), allocatable :: g(:, :), z(:, :)
        real(dp) :: shift, gg, gold, tau, rt, scale, zbar, beta, sv, sb, sg
        real(dp) :: sr, srt, st, sgt, psum
        real(dp), allocatable :: cd(:)
        integer, allocatable :: ci(:), cj(:)
        logical :: conjugate, exact, force, prec, have_set
        integer :: nc, nol, it, nd, iters, nprod, steps, mcol

        info = STAT_OK
        done = .false.
        force = control == CONTROL_FORCE
        prec = plan%has_prec
        allocate (g, z, mold=h)
        mcol = column_limit(size(h, 1), size(h, 2))
        allocate (ci(mcol), cj(mcol), cd(mcol))
        gold = rs(1)
        shift = rs(2)
        it = is(1)
        iters = is(2)
        nprod = is(3)
        conjugate = is(4) == 1
        exact = is(5) == 1
        steps = 0
        have_set = .false.
        do while (it <= max_iter)
            if (steps >= budget) exit
            steps = steps + 1
            ! pass 1: the contact set's size and, under force control, its mean gap
            ! (the approach is the Lagrange multiplier of the force constraint); after
            ! an update by recurrence, pass 7 has summed them already (the same sums)
            if (.not. have_set) call cg_contact_set(p, u, h, nc, sg)
            have_set = .false.
            if (force) shift = sg / max(nc, 1)

            ! pass 2: deformed gap g, residual sums (see normal_residual), and the
            ! preconditioner's input g restricted to the contact set
            call cg_gap(plan, prec, p, u, h, shift, g, z, sv, sb, sg)
            resid = 0.0_dp
            if (sb > 0.0_dp) resid = sqrt(sv / sb)
            if (resid <= tol) then
                if (exact .or. tol >= CONFIRM_TOL) then
                    done = .true.
                    exit
                end if
                ! a tolerance near rounding: confirm on an exact product before stopping
                call apply_op(plan, kz, p, u, nc, c, lab, fac)
                nprod = nprod + 1
                exact = .true.
                it = it + 1
                cycle
            end if
            if (it == max_iter) then
                info = STAT_NOT_CONVERGED
                done = .true.
                exit
            end if
            iters = it + 1

            ! pass 3: z = M g on the contact set (PK eqs 3.3-3.5), made mean-free
            ! under force control; gg = (g, z) uses sum(g) = sg on the set
            call cg_precondition(plan, prec, p, g, z, zbar, gg)
            if (force) then
                zbar = zbar / max(nc, 1)
                gg = gg - zbar * sg
            else
                zbar = 0.0_dp
            end if

            ! pass 4: conjugate direction t, written into the product's buffer, and r = A t
            beta = 0.0_dp
            if (conjugate) beta = gg / gold
            gold = gg
            call cg_direction(plan, kz, c, p, z, zbar, beta, nc, t, lab, fac)
            nprod = nprod + 1

            ! pass 5: step length tau = (g, t) / (r - rbar, t) with r = A t
            call cg_curvature(plan, p, t, g, sr, srt, st, sgt)
            rt = srt
            if (force) rt = srt - sr / max(nc, 1) * st
            if (rt <= 0.0_dp) then
                info = STAT_NOT_CONVERGED
                done = .true.
                exit
            end if
            tau = sgt / rt

            ! pass 6: step, projection on p >= 0 and re-entry of overlapping points
            ! (PK eqs 3.6-3.8)
            call cg_project(tau, t, g, p, nol, nd, ci, cj, cd, psum)
            conjugate = nol == 0

            scale = 1.0_dp
            if (force) then
                if (psum <= 0.0_dp) then
                    info = STAT_NOT_CONVERGED
                    done = .true.
                    exit
                end if
                scale = fn / (area_el * psum)
            end if

            ! pass 7: A p_new = scale (A p_old - tau A t + A d); by recurrence, also pass 1's
            ! sums for the next iteration
            exact = nd > mcol .or. mod(iters, REFRESH) == 0
            call cg_update(plan, kz, c, h, exact, tau, scale, nc + nd, nd, ci, cj, cd, p, u, nc, sg, &
                           lab, fac)
            have_set = .not. exact
            if (exact) nprod = nprod + 1
            it = it + 1
        end do
        if (it > max_iter) done = .true.

        rs = [gold, shift]
        is = [it, iters, nprod, merge(1, 0, conjugate), merge(1, 0, exact)]
        if (.not. done) return
        if (force) then
            approach = shift
        else
            fn = area_el * sum(p)
        end if
        if (info == STAT_OK .and. resid > tol) info = STAT_NOT_CONVERGED
        if (info == STAT_OK .and. any(p /= p)) info = STAT_NOT_FINITE
    end subroutine normal_cg_steps

    !> CG pass 1 (normal_cg_steps): the contact set's size nc and the sum sg of u + h over it.
    pure subroutine cg_contact_set(p, u, h, nc, sg)
        real(dp), intent(in) :: p(:, :), u(:, :), h(:, :)
        integer, intent(out) :: nc
        real(dp), intent(out) :: sg
        integer :: i, j
        nc = 0
        sg = 0.0_dp
        do j = 1, size(h, 2)
            do i = 1, size(h, 1)
                if (p(i, j) > 0.0_dp) then
                    nc = nc + 1
                    sg = sg + u(i, j) + h(i, j)
                end if
            end do
        end do
    end subroutine cg_contact_set

    !> CG pass 2 (normal_cg_steps): the deformed gap g = u + h - shift, the residual's sums
    !> sv, sb (normal_residual), the sum sg of g over the contact set, and g restricted to
    !> the set as the preconditioner's input (its buffer under prec, else z).
    subroutine cg_gap(plan, prec, p, u, h, shift, g, z, sv, sb, sg)
        type(conv_plan), intent(inout) :: plan
        logical, intent(in) :: prec
        real(dp), intent(in) :: p(:, :), u(:, :), h(:, :), shift
        real(dp), intent(inout) :: g(:, :), z(:, :)
        real(dp), intent(out) :: sv, sb, sg
        real(dp) :: gk
        integer :: i, j
        real(dp), pointer, contiguous :: pb(:, :)   ! (the buffer's descriptor held apart)
        sv = 0.0_dp
        sb = 0.0_dp
        sg = 0.0_dp
        pb => plan%prbuf
        do j = 1, size(h, 2)
            do i = 1, size(h, 1)
                gk = u(i, j) + h(i, j) - shift
                g(i, j) = gk
                if (p(i, j) > 0.0_dp) then
                    sv = sv + gk**2
                    sb = sb + (u(i, j) - gk)**2
                    sg = sg + gk
                else
                    if (gk < 0.0_dp) then
                        sv = sv + gk**2
                        sb = sb + (u(i, j) - gk)**2
                    end if
                    gk = 0.0_dp
                end if
                if (prec) then
                    pb(i, j) = gk
                else
                    z(i, j) = gk
                end if
            end do
        end do
    end subroutine cg_gap

    !> CG pass 3 (normal_cg_steps): z = M g on the contact set (PK eqs 3.3-3.5; z = g without
    !> a preconditioner), zero off it; zbar the sum of z and gg = (g, z) over the set.
    subroutine cg_precondition(plan, prec, p, g, z, zbar, gg)
        type(conv_plan), intent(inout) :: plan
        logical, intent(in) :: prec
        real(dp), intent(in) :: p(:, :), g(:, :)
        real(dp), intent(inout) :: z(:, :)
        real(dp), intent(out) :: zbar, gg
        real(dp) :: zk
        integer :: i, j
        real(dp), pointer, contiguous :: pb(:, :)   ! (the buffer's descriptor held apart)
        if (prec) call conv_precond_buffer(plan)
        zbar = 0.0_dp
        gg = 0.0_dp
        pb => plan%prbuf
        do j = 1, size(p, 2)
            do i = 1, size(p, 1)
                if (p(i, j) > 0.0_dp) then
                    zk = z(i, j)
                    if (prec) zk = pb(i, j)
                    z(i, j) = zk
                    zbar = zbar + zk
                    gg = gg + g(i, j) * zk
                else
                    z(i, j) = 0.0_dp
                end if
            end do
        end do
    end subroutine cg_precondition

    !> CG pass 4 (normal_cg_steps): the conjugate direction t = z - zbar + beta t on the
    !> contact set (0 off it), and r = A t in the product's buffer plan%rbuf (nc elements in
    !> contact; z is overwritten with sub-patches).
    subroutine cg_direction(plan, kz, c, p, z, zbar, beta, nc, t, lab, fac)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, nc
        real(dp), intent(in) :: c(0:, 0:), p(:, :), zbar, beta
        real(dp), intent(inout) :: z(:, :), t(:, :)
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)
        real(dp) :: tk
        integer :: i, j, nx, ny
        real(dp), pointer, contiguous :: rb(:, :)   ! (the buffer's descriptor held apart)
        nx = size(p, 1)
        ny = size(p, 2)
        rb => plan%rbuf
        do j = 1, ny
            do i = 1, nx
                tk = 0.0_dp
                if (p(i, j) > 0.0_dp) tk = z(i, j) - zbar + beta * t(i, j)
                t(i, j) = tk
                rb(i, j) = tk
            end do
        end do
        if (coupled(lab, fac)) then
            call apply_op(plan, kz, t, z, nc, c, lab, fac)
            plan%rbuf(1:nx, 1:ny) = z
        else if (columns_are_cheaper(nc, nx, ny)) then
            call conv_apply_dense(plan, kz, c, t, plan%rbuf(1:nx, 1:ny))
        else
            call conv_apply_buffer(plan, kz)
        end if
    end subroutine cg_direction

    !> CG pass 5 (normal_cg_steps): over the contact set, with r = A t in plan%rbuf, the sums
    !> sr of r, srt of r t, st of t and sgt of g t (the step length's terms).
    subroutine cg_curvature(plan, p, t, g, sr, srt, st, sgt)
        type(conv_plan), intent(in) :: plan
        real(dp), intent(in) :: p(:, :), t(:, :), g(:, :)
        real(dp), intent(out) :: sr, srt, st, sgt
        real(dp) :: rk
        integer :: i, j
        real(dp), pointer, contiguous :: rb(:, :)   ! (the buffer's descriptor held apart)
        sr = 0.0_dp
        srt = 0.0_dp
        st = 0.0_dp
        sgt = 0.0_dp
        rb => plan%rbuf
        do j = 1, size(p, 2)
            do i = 1, size(p, 1)
                if (p(i, j) > 0.0_dp) then
                    rk = rb(i, j)
                    sr = sr + rk
                    srt = srt + rk * t(i, j)
                    st = st + t(i, j)
                    sgt = sgt + g(i, j) * t(i, j)
                end if
            end do
        end do
    end subroutine cg_curvature

    !> CG pass 6 (normal_cg_steps): the step p - tau t on the contact set, the projection on
    !> p >= 0 and the re-entry of overlapping points (PK eqs 3.6-3.8); nol the points that
    !> re-entered, nd the changes d against the plain step, the first size(ci) of them kept
    !> (ci, cj, cd) for column corrections; psum the new sum of p.
    pure subroutine cg_project(tau, t, g, p, nol, nd, ci, cj, cd, psum)
        real(dp), intent(in) :: tau, t(:, :), g(:, :)
        real(dp), intent(inout) :: p(:, :)
        integer, intent(out) :: nol, nd
        integer, intent(inout) :: ci(:), cj(:)
        real(dp), intent(inout) :: cd(:)
        real(dp), intent(out) :: psum
        real(dp) :: pk, pn, dk
        integer :: i, j
        nol = 0
        nd = 0
        psum = 0.0_dp
        do j = 1, size(p, 2)
            do i = 1, size(p, 1)
                pk = p(i, j)
                if (pk > 0.0_dp) pk = pk - tau * t(i, j)
                pn = max(pk, 0.0_dp)
                if (pn <= 0.0_dp .and. g(i, j) < 0.0_dp) then
                    pn = -tau * g(i, j)
                    nol = nol + 1
                end if
                dk = pn - pk
                if (dk /= 0.0_dp) then
                    nd = nd + 1
                    if (nd <= size(ci)) then
                        ci(nd) = i
                        cj(nd) = j
                        cd(nd) = dk
                    end if
                end if
                p(i, j) = pn
                psum = psum + pn
            end do
        end do
    end subroutine cg_project

    !> CG pass 7 (normal_cg_steps): u = A p for the new p scaled by scale (force control),
    !> A p_new = scale (A p_old - tau A t + A d): an exact product of nnz elements when exact
    !> (d large, or every REFRESH steps against drift), else the recurrence with r = A t in
    !> plan%rbuf and the nd columns (ci, cj, cd) of A, in one pass with the scaling of p
    !> and u that also sums pass 1's nc and sg (cg_contact_set) for the new p and u.
    subroutine cg_update(plan, kz, c, h, exact, tau, scale, nnz, nd, ci, cj, cd, p, u, nc, sg, &
                         lab, fac)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, nnz, nd, ci(:), cj(:)
        real(dp), intent(in) :: c(0:, 0:), h(:, :), tau, scale, cd(:)
        logical, intent(in) :: exact
        real(dp), intent(inout) :: p(:, :), u(:, :)
        integer, intent(out) :: nc
        real(dp), intent(out) :: sg
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)
        real(dp) :: uk, pk
        integer :: i, j, m
        logical :: coupled_op
        nc = 0
        sg = 0.0_dp
        if (exact) then
            if (scale /= 1.0_dp) p = scale * p
            call apply_op(plan, kz, p, u, nnz, c, lab, fac)
            return
        end if
        coupled_op = coupled(lab, fac)
        if (coupled_op) then
            u = u - tau * plan%rbuf(1:size(u, 1), 1:size(u, 2))
            do m = 1, nd
                call add_column(c, ci(m), cj(m), cd(m), u, lab, fac)
            end do
        end if
        ! per grid column j: the step, the columns of A d, the scaling and pass 1's sums, in
        ! the order of the separate passes (the same numbers)
        do j = 1, size(u, 2)
            if (.not. coupled_op) then
                do i = 1, size(u, 1)
                    u(i, j) = u(i, j) - tau * plan%rbuf(i, j)
                end do
                call add_columns_at(c, j, nd, ci, cj, cd, u)
            end if
            do i = 1, size(u, 1)
                uk = scale * u(i, j)
                pk = scale * p(i, j)
                u(i, j) = uk
                p(i, j) = pk
                if (pk > 0.0_dp) then
                    nc = nc + 1
                    sg = sg + uk + h(i, j)
                end if
            end do
        end do
    end subroutine cg_update

    !> A cold start when p is all zero: p proportional to the interpenetration
    !> of the rigid surfaces, scaled to the best fit of A p = delta - h on it.
    !> On return u = A p (c, optional: kernel kz's coefficients, for apply_a).
    subroutine initial_pressure(plan, kz, h, force, approach, p, u, nprod, c, lab, fac)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz
        real(dp), intent(in) :: h(:, :), approach
        real(dp), intent(in), optional :: c(0:, 0:)
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)
        logical, intent(in) :: force
        real(dp), intent(inout) :: p(:, :)
        real(dp), intent(inout) :: u(:, :)
        integer, intent(inout) :: nprod
        real(dp) :: d, hmin, hmed, s
        if (any(p > 0.0_dp)) then
            p = max(p, 0.0_dp)
        else
            if (force) then
                ! interpenetrate the quarter of the grid with the smallest gaps
                hmin = minval(h)
                hmed = hmin + 0.25_dp * (maxval(h) - hmin)
                d = hmed
            else
                d = approach
            end if
            p = max(d - h, 0.0_dp)
            if (.not. any(p > 0.0_dp)) p = 1.0_dp
        end if
        call apply_op(plan, kz, p, u, count(p > 0.0_dp), c, lab, fac)
        nprod = nprod + 1
        if (.not. force) then
            s = sum(u * (approach - h), mask=p > 0.0_dp) / max(sum(u**2, mask=p > 0.0_dp), tiny(1.0_dp))
            if (s > 0.0_dp) then
                p = s * p
                u = s * u
            end if
        end if
    end subroutine initial_pressure

    !> A prescribed approach that does not close the smallest gap has the
    !> solution p = 0: set it with info = STAT_NO_CONTACT and return true.
    logical function no_contact(control, h, approach, p, fn, resid, info)
        integer, intent(in) :: control
        real(dp), intent(in) :: h(:, :), approach
        real(dp), intent(inout) :: p(:, :), fn, resid
        integer, intent(inout) :: info
        no_contact = control == CONTROL_APPROACH .and. all(h >= approach)
        if (.not. no_contact) return
        p = 0.0_dp
        fn = 0.0_dp
        resid = 0.0_dp
        info = STAT_NO_CONTACT
    end function no_contact

    !> The most changed elements whose columns correct u = A p after a CG projection
    !> (cg_update) before an exact product is cheaper: MAX_COLUMNS on grids of at most
    !> DENSE_MAX elements (the dense path, unchanged); on larger ones the columns whose
    !> sums (2 nx ny flops each, add_column) take COLUMN_SHARE of the zero-padded FFT
    !> product's count (that of columns_are_cheaper, 5 M log2 M + 10 M for M = 4 nx ny):
    !> 54 on 450 x 450, 49 on 225 x 225, 45 on 128 x 128. Results agree with exact
    !> products to rounding.
    pure integer function column_limit(nx, ny) result(mc)
        integer, intent(in) :: nx, ny
        real(dp) :: m
        mc = MAX_COLUMNS
        if (nx * ny <= DENSE_MAX) return
        m = 4.0_dp * nx * ny
        mc = max(MAX_COLUMNS, int(COLUMN_SHARE * (5.0_dp * m * log(m) / log(2.0_dp) + 10.0_dp * m) &
                                  / (2.0_dp * nx * ny)))
    end function column_limit

    !> Whether a product by columns of A (2 flops per source and target, nq sources
    !> on an nx x ny grid of at most DENSE_MAX elements, conv_apply_dense) takes fewer
    !> operations than the zero-padded FFT product:
    !> about 5 M log2 M + 10 M for the two real transforms of M = 4 nx ny points and
    !> the spectral product (the count of contact_rolling's direct_is_cheaper; by
    !> instruction counts the column sums win by more, so the choice is
    !> conservative: an 11 x 11 grid takes columns, 25 x 25 with 200 elements in
    !> contact and the vehicle's 48 x 80 grids the FFT).
    pure logical function columns_are_cheaper(nq, nx, ny)
        integer, intent(in) :: nq, nx, ny
        real(dp) :: m
        m = 4.0_dp * nx * ny
        columns_are_cheaper = nx * ny <= DENSE_MAX .and. &
                              2.0_dp * nq * nx * ny < 5.0_dp * m * log(m) / log(2.0_dp) + 10.0_dp * m
    end function columns_are_cheaper

    !> u = A q for kernel kz: by the columns of the dense matrix (conv_apply_dense) when
    !> q's nq non-zero elements make that cheaper (columns_are_cheaper), else by FFT.
    subroutine apply_a(plan, kz, c, q, u, nq)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, nq
        real(dp), intent(in) :: c(0:, 0:), q(:, :)
        real(dp), intent(out) :: u(:, :)
        if (columns_are_cheaper(nq, size(q, 1), size(q, 2))) then
            call conv_apply_dense(plan, kz, c, q, u)
        else
            call conv_apply(plan, kz, q, u)
        end if
    end subroutine apply_a

    !> Whether a sub-patch description is valid: nsub >= 1, every column's sub-patch in
    !> 1..nsub, fac (nsub x nsub) symmetric with ones on the diagonal and entries in [0, 1].
    pure logical function subpatches_valid(nsub, lab, fac) result(ok)
        integer, intent(in) :: nsub, lab(:)
        real(dp), intent(in) :: fac(:, :)
        integer :: a
        ok = nsub >= 1 .and. size(fac, 1) == nsub .and. size(fac, 2) == nsub
        if (.not. ok) return
        ok = all(lab >= 1 .and. lab <= nsub) .and. all(fac >= 0.0_dp .and. fac <= 1.0_dp) &
             .and. all(fac == transpose(fac))
        do a = 1, nsub
            ok = ok .and. fac(a, a) == 1.0_dp
        end do
    end function subpatches_valid

    !> Whether a sub-patch coupling is given and reduces any interaction (more than one
    !> sub-patch).
    pure logical function coupled(lab, fac)
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)
        coupled = .false.
        if (present(lab) .and. present(fac)) coupled = size(fac, 1) > 1
    end function coupled

    !> u = A q, or with a sub-patch coupling (lab, fac) u = sum_b fac(lab(:), b) A (q on
    !> sub-patch b): one product per sub-patch that holds load. c (optional): kernel kz's
    !> coefficients, for products by columns on small grids (apply_a); FFT without it.
    subroutine apply_op(plan, kz, q, u, nq, c, lab, fac)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, nq
        real(dp), intent(in) :: q(:, :)
        real(dp), intent(out) :: u(:, :)
        real(dp), intent(in), optional :: c(0:, 0:)
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)
        real(dp), allocatable :: w(:, :), v(:, :)
        integer :: b, j
        if (.not. coupled(lab, fac)) then
            if (present(c)) then
                call apply_a(plan, kz, c, q, u, nq)
            else
                call conv_apply(plan, kz, q, u)
            end if
            return
        end if
        allocate (w, v, mold=q)
        u = 0.0_dp
        do b = 1, size(fac, 1)
            do j = 1, size(q, 2)
                if (lab(j) == b) then
                    w(:, j) = q(:, j)
                else
                    w(:, j) = 0.0_dp
                end if
            end do
            if (.not. any(w /= 0.0_dp)) cycle
            if (present(c)) then
                call apply_a(plan, kz, c, w, v, count(w /= 0.0_dp))
            else
                call conv_apply(plan, kz, w, v)
            end if
            do j = 1, size(q, 2)
                u(:, j) = u(:, j) + fac(lab(j), b) * v(:, j)
            end do
        end do
    end subroutine apply_op

    !> u = u + dkl * A(:, (k, l)), the column of element (k, l); with a sub-patch coupling
    !> (lab, fac) its entries in column j scaled by fac(lab(j), lab(l)).
    pure subroutine add_column(c, k, l, dkl, u, lab, fac)
        real(dp), intent(in) :: c(0:, 0:), dkl
        integer, intent(in) :: k, l
        real(dp), intent(inout) :: u(:, :)
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)
        integer :: nx, ny, mx, my, j, jj
        real(dp) :: s
        logical :: cpl
        nx = size(u, 1)
        ny = size(u, 2)
        mx = 2 * nx
        my = 2 * ny
        cpl = coupled(lab, fac)
        s = dkl
        do j = 1, ny
            jj = modulo(j - l, my)
            if (cpl) s = dkl * fac(lab(j), lab(l))
            u(k:nx, j) = u(k:nx, j) + s * c(0:nx - k, jj)
            if (k > 1) u(1:k - 1, j) = u(1:k - 1, j) + s * c(mx + 1 - k:mx - 1, jj)
        end do
    end subroutine add_column

    !> u(:, j) = u(:, j) + sum_m cd(m) A((:, j), (ci(m), cj(m))): grid column j of the columns
    !> of A of nd elements (add_column's sums without sub-patches, in the same order per
    !> element, so the same numbers), while u(:, j) stays in cache. Element i of column m reads
    !> the coefficient at x offset i - ci(m), wrapped to i - ci(m) + 2 nx when negative; two
    !> columns are added per pass over u(:, j) (u + a + b is (u + a) + b: the same numbers).
    pure subroutine add_columns_at(c, j, nd, ci, cj, cd, u)
        real(dp), intent(in) :: c(0:, 0:), cd(:)
        integer, intent(in) :: j, nd, ci(:), cj(:)
        real(dp), intent(inout) :: u(:, :)
        integer :: nx, mx, my, ja, jb, ka, kb, m, i, oa, ob
        real(dp) :: da, db
        nx = size(u, 1)
        mx = 2 * nx
        my = 2 * size(u, 2)
        do m = 1, nd - 1, 2
            ka = ci(m)
            kb = ci(m + 1)
            ja = modulo(j - cj(m), my)
            jb = modulo(j - cj(m + 1), my)
            da = cd(m)
            db = cd(m + 1)
            ! offsets of element i: i - ka (+ mx below ka), i - kb (+ mx below kb)
            oa = mx - ka
            ob = mx - kb
            do i = 1, min(ka, kb) - 1
                u(i, j) = u(i, j) + da * c(i + oa, ja) + db * c(i + ob, jb)
            end do
            if (ka <= kb) then
                do i = ka, kb - 1
                    u(i, j) = u(i, j) + da * c(i - ka, ja) + db * c(i + ob, jb)
                end do
            else
                do i = kb, ka - 1
                    u(i, j) = u(i, j) + da * c(i + oa, ja) + db * c(i - kb, jb)
                end do
            end if
            do i = max(ka, kb), nx
                u(i, j) = u(i, j) + da * c(i - ka, ja) + db * c(i - kb, jb)
            end do
        end do
        if (mod(nd, 2) == 1) then
            ka = ci(nd)
            ja = modulo(j - cj(nd), my)
            u(ka:nx, j) = u(ka:nx, j) + cd(nd) * c(0:nx - ka, ja)
            if (ka > 1) u(1:ka - 1, j) = u(1:ka - 1, j) + cd(nd) * c(mx + 1 - ka:mx - 1, ja)
        end if
    end subroutine add_columns_at

    !> Projected Gauss-Seidel with prescribed approach or force, in one call.
    !> info as for normal_cg.
    subroutine normal_gs(plan, kz, c, h, area_el, control, fn, approach, omega, tol, &
                         max_iter, p, iters, resid, info)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, control, max_iter
        real(dp), intent(in) :: c(0:, 0:), h(:, :), area_el, omega, tol
        real(dp), intent(inout) :: fn, approach
        real(dp), intent(inout) :: p(:, :)
        integer, intent(out) :: iters, info
        real(dp), intent(out) :: resid
        real(dp), allocatable :: u(:, :)
        integer :: pos
        logical :: done

        allocate (u, mold=h)
        call normal_gs_start(plan, kz, c, h, area_el, control, fn, approach, p, u, iters, pos, &
                             resid, info, done)
        if (done) return
        call normal_gs_resume(c, h, area_el, control, fn, approach, omega, tol, max_iter, &
                              huge(1.0_dp), p, u, iters, pos, resid, info, done)
    end subroutine normal_gs

    !> Start of a resumable projected Gauss-Seidel solve: p = max(p, 0), u = A p, the
    !> initial residual (prescribed approach) or, from p = 0, the approach of a bed of
    !> springs (prescribed force). done (info = STAT_NO_CONTACT): the prescribed approach
    !> does not close the smallest gap. The solve goes on with normal_gs_resume.
    subroutine normal_gs_start(plan, kz, c, h, area_el, control, fn, approach, p, u, iters, &
                               pos, resid, info, done, lab, fac)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kz, control
        real(dp), intent(in) :: c(0:, 0:), h(:, :), area_el
        real(dp), intent(inout) :: fn, approach
        real(dp), intent(inout) :: p(:, :), u(:, :)
        integer, intent(out) :: iters, pos, info
        real(dp), intent(out) :: resid
        logical, intent(out) :: done
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)

        info = STAT_OK
        iters = 0
        pos = 0
        done = .false.
        p = max(p, 0.0_dp)
        call apply_op(plan, kz, p, u, count(p > 0.0_dp), lab=lab, fac=fac)
        if (control == CONTROL_APPROACH) then
            done = no_contact(control, h, approach, p, fn, resid, info)
            if (.not. done) resid = normal_residual(u + h - approach, p, u)
        else
            if (.not. any(p > 0.0_dp)) approach = rigid_estimate(c(0, 0), h, area_el, fn)
            resid = huge(1.0_dp)
        end if
    end subroutine normal_gs_start

    !> Projected Gauss-Seidel sweeps (eq. 23), resumable: u = A p is kept up to date
    !> column by column from the circular coefficient field c (influence_field layout),
    !> O(N) per changed element. With prescribed force, before every sweep p (and u) are
    !> scaled to the force and the approach set to the mean of u + h over the contact set,
    !> as Polonsky & Keer do in CG; the scaling corrects the smooth error mode that
    !> Gauss-Seidel damps slowest.
    !> The call returns (done false) once it has spent about budget units of work (one per
    !> element visited, nx ny per column correction), so that a caller can show progress
    !> and stop between calls; pos is the next element of the current sweep (0: before
    !> the next sweep), iters the sweeps begun. Any sequence of calls gives the same
    !> numbers as one call with an unbounded budget. On done, info as for normal_cg.
    subroutine normal_gs_resume(c, h, area_el, control, fn, approach, omega, tol, max_iter, &
                                budget, p, u, iters, pos, resid, info, done, lab, fac)
        real(dp), intent(in) :: c(0:, 0:), h(:, :), area_el, omega, tol, budget
        integer, intent(in) :: control, max_iter
        real(dp), intent(inout) :: fn, approach, p(:, :), u(:, :), resid
        integer, intent(inout) :: iters, pos
        integer, intent(out) :: info
        logical, intent(out) :: done
        integer, intent(in), optional :: lab(:)
        real(dp), intent(in), optional :: fac(:, :)
        integer :: nx, ny, k, l, m
        real(dp) :: c0, e, pnew, d, work, scale

        nx = size(h, 1)
        ny = size(h, 2)
        c0 = c(0, 0)
        info = STAT_OK
        done = .false.
        work = 0.0_dp
        do
            if (pos == 0) then          ! before a sweep: converged, or out of sweeps?
                if (control == CONTROL_FORCE) then
                    if (iters >= max_iter) exit
                    if (any(p > 0.0_dp)) then
                        scale = fn / (area_el * sum(p))
                        p = scale * p
                        u = scale * u
                        approach = sum(u + h, mask=p > 0.0_dp) / count(p > 0.0_dp)
                        resid = normal_residual(u + h - approach, p, u)
                        if (resid <= tol) exit
                    end if
                else if (resid <= tol .or. iters >= max_iter) then
                    exit
                end if
                iters = iters + 1
                pos = 1
            end if
            do m = pos, nx * ny
                if (work >= budget) then
                    pos = m
                    return
                end if
                k = mod(m - 1, nx) + 1
                l = (m - 1) / nx + 1
                work = work + 1.0_dp
                e = u(k, l) + h(k, l) - approach
                pnew = max(0.0_dp, p(k, l) - omega * e / c0)
                d = pnew - p(k, l)
                if (d == 0.0_dp) cycle
                p(k, l) = pnew
                call add_column(c, k, l, d, u, lab, fac)
                work = work + real(nx, dp) * real(ny, dp)
            end do
            pos = 0
            resid = normal_residual(u + h - approach, p, u)
        end do
        done = .true.
        if (control == CONTROL_APPROACH) fn = area_el * sum(p)
        if (resid > tol) info = STAT_NOT_CONVERGED
    end subroutine normal_gs_resume

    !> Approach at which a bed of independent springs of compliance c0 per
    !> element carries fn: sum(max(delta - h, 0)) area / c0 = fn. It lies below
    !> the elastic approach, since A's off-diagonal terms stiffen nothing.
    pure real(dp) function rigid_estimate(c0, h, area_el, fn) result(d)
        real(dp), intent(in) :: c0, h(:, :), area_el, fn
        real(dp) :: lo, hi, mid
        integer :: it
        lo = minval(h)
        hi = lo + fn * c0 / area_el
        do it = 1, 200
            mid = 0.5_dp * (lo + hi)
            if (sum(max(mid - h, 0.0_dp)) * area_el / c0 > fn) then
                hi = mid
            else
                lo = mid
            end if
        end do
        d = 0.5_dp * (lo + hi)
    end function rigid_estimate

end module contact_normal
