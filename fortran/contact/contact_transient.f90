!> Transient and shift tangential contact problems of quasi-identical bodies
!> (Kalker's transient theory: Kalker 1990, ch. 2.1 and 5.2; Kalker, "Transient
!> phenomena in two elastic cylinders rolling over each other with dry friction",
!> J. Appl. Mech. 37, 1970).
!>
!> Kinematics. Over one time step dt the slip (a distance, m) of the particle at
!> element I is the rigid slip plus the change of the displacement difference
!> u = A t of that particle:
!>   S_I = W_I dt + u_I(t) - u'_I(t - dt),                                (eq. T1)
!> u' the previous step's field at the same particle. In a shift problem (no
!> rolling) u'_I = u_I(t - dt). In rolling at speed V particles move through the
!> fixed patch in -x, so the particle now at x_i was at x_i + V dt: with V dt = k dx
!> restricted to a whole number k of elements (no interpolation),
!>   u'(i, j) = u_(t - dt)(i + k, j).
!> With the weight th (0 by default) the second-order form
!>   S = W dt + (1 + th) u(t) - (1 + 2 th) u'(t - dt) + th u''(t - 2 dt)   (eq. T2)
!> is used, u'' the field two steps back at the same particle (i + 2k). For
!> steady rolling with k = 1 and th = 1/3 it is contact_rolling's three-point
!> stencil times dx, so the transient approaches that solver's steady state.
!>
!> Element problem (Coulomb, eqs 26 and 28 of contact_rolling), g = mu p:
!>   adhesion  S = 0,  |t| <= g;      slip  t = -g S / |S|,  |t| = g.
!> With S = s0 + cs A t (cs = 1 + th, s0 the slip of zero traction), A symmetric
!> positive definite (quasi-identical bodies), this is the optimality condition of
!>   min  1/2 cs t.A t + t.s0   over  |t_I| <= g_I,                      (eq. T3)
!> S being the gradient. Solved by accelerated projected gradients (FISTA, Beck and
!> Teboulle 2009) with the gradient restart of O'Donoghue and Candes (2015): step
!> 1/L, L = cs lambda_max(A on the contact set) from a few power iterations; one
!> FFT pair product A t per iteration (conv_apply_pair), the gradient at the
!> extrapolated point formed from the last two products by linearity.
!> Convergence: the relative change of a Jacobi step on the exact field,
!> r = ||F(t) - t|| / ||F(t)||, F the exact element solutions (element_solve)
!> with the pivot cs A(0): zero exactly at the solution (as in contact_rolling).
!>
!> Callers may put any extra rigid slip into s0 (e.g. a normal-tangential coupling
!> term) and any per-element bound g (e.g. another friction law): the kernel
!> transient_tangential takes both as fields.
!>
!> Force control (transient_force): the rigid shift q (m, added to s0 everywhere) is
!> the unknown that carries the force F = da sum t. Each iteration projects onto the
!> discs and the affine set sum t = F / da at once (project_force: t_I = P_I(z_I - lam),
!> the multiplier lam (2) by Newton on the concave dual); lam / step is the shift q,
!> so one solve gives both (S = s0 + q + cs A t, eq. T3 with the force as a constraint).
!>
!> transient_run marches a sequence of steps: the normal problem re-solved when
!> the normal force changes (contact_normal::normal_cg), then the tangential step
!> with the history of the last one or two steps.
!> Implements eqs T1-T3 (docs/equations.md).
module contact_transient
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, &
                             STAT_BAD_HANDLE, STAT_GRID_EDGE, STAT_NOT_FINITE
    use contact_influence, only: KERNEL_XX, KERNEL_YY, KERNEL_XY, KERNEL_ZZ
    use contact_plans, only: workspace
    use contact_convolution, only: conv_apply_pair
    use contact_normal, only: normal_cg, CONTROL_FORCE
    use contact_rolling, only: element_solve, ST_EXTERIOR, ST_ADHESION, ST_SLIP
    implicit none
    private
    public :: transient_tangential, transient_force, transient_run
    public :: SHIFT_GIVEN, FORCE_GIVEN

    !> transient_run's tangential control: rigid shift increments or forces per step.
    integer, parameter :: SHIFT_GIVEN = 0, FORCE_GIVEN = 1
    !> Power iterations for lambda_max and the safety factor on it (the Rayleigh
    !> quotient is a lower bound; the top eigenvalue of the positive kernel is well
    !> separated, so 12 iterations give it to about 1e-4).
    integer, parameter :: NPOWER = 12
    real(dp), parameter :: LSAFE = 1.05_dp

contains

    !> One transient (or shift) tangential step: the tractions t with
    !> S = s0 + cs A t satisfying Coulomb's law on the elements of inc (eq. T3).
    !>
    !> info: STAT_OK; STAT_NOT_CONVERGED after max_iter iterations (the last
    !> iterate returned); STAT_NO_CONTACT no element in inc (t = 0);
    !> STAT_BAD_HANDLE a workspace without the tangential kernels;
    !> STAT_BAD_ARGUMENT cs <= 0; STAT_NOT_FINITE non-finite values.
    subroutine transient_tangential(w, inc, bound, s0x, s0y, cs, tol, max_iter, tx, ty, ux, uy, &
                                    status, slx, sly, iters, resid, info, force, da, q, lmax_io)
        type(workspace), intent(inout) :: w
        logical, intent(in) :: inc(:, :)            ! (nx, ny) elements in contact
        real(dp), intent(in) :: bound(:, :)         ! (nx, ny) traction bound g, Pa
        real(dp), intent(in) :: s0x(:, :), s0y(:, :)    ! slip of zero traction, m
        real(dp), intent(in) :: cs, tol             ! weight of u(t) in S (1 + th), tolerance
        integer, intent(in) :: max_iter
        real(dp), intent(inout) :: tx(:, :), ty(:, :)   ! warm start in, tractions (Pa) out
        real(dp), intent(out) :: ux(:, :), uy(:, :)     ! u = A t, whole grid, m
        integer, intent(out) :: status(:, :)        ! 0 exterior, 1 adhesion, 2 slip
        real(dp), intent(out) :: slx(:, :), sly(:, :)   ! slip S over the step (0 in adhesion), m
        integer, intent(out) :: iters, info
        real(dp), intent(out) :: resid
        real(dp), intent(in), optional :: force(2), da  ! force control: the force (N), element area (m^2)
        real(dp), intent(out), optional :: q(2)         ! force control: the rigid shift found, m
        !> lambda_max of A on this contact set (power_lmax): used if > 0, else computed and returned
        real(dp), intent(inout), optional :: lmax_io
        real(dp), allocatable :: px(:, :), py(:, :), apx(:, :), apy(:, :), nx_(:, :), ny_(:, :)
        real(dp) :: lmax, step, tk, tk1, beta, r2, n2, dot, kx, ky, lam(2), c(2), qq(2)
        integer :: it
        logical :: fc

        iters = 0
        resid = 0.0_dp
        info = STAT_OK
        fc = present(force) .and. present(da) .and. present(q)
        lam = 0.0_dp
        qq = 0.0_dp
        c = 0.0_dp
        if (fc) then
            q = 0.0_dp
            c = force / da
        end if
        status = ST_EXTERIOR
        slx = 0.0_dp
        sly = 0.0_dp
        ux = 0.0_dp
        uy = 0.0_dp
        if (w%nker < 4) then
            info = STAT_BAD_HANDLE
            return
        end if
        if (.not. (cs > 0.0_dp)) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        where (.not. inc)
            tx = 0.0_dp
            ty = 0.0_dp
        end where
        if (.not. any(inc)) then
            info = STAT_NO_CONTACT
            return
        end if
        if (fc) then
            call project_force(inc, bound, c, tx, ty, lam, info)
            if (info /= STAT_OK) return
        else
            call project_set(inc, bound, tx, ty)
        end if
        kx = cs * w%c(0, 0, KERNEL_XX)
        ky = cs * w%c(0, 0, KERNEL_YY)
        lmax = 0.0_dp
        if (present(lmax_io)) lmax = lmax_io
        if (.not. (lmax > 0.0_dp)) lmax = power_lmax(w, inc)
        if (present(lmax_io)) lmax_io = lmax
        lmax = cs * lmax
        step = 1.0_dp / lmax
        allocate (px, py, apx, apy, nx_, ny_, mold=tx)
        call conv_apply_pair(w%plan, KERNEL_XX, KERNEL_XY, KERNEL_YY, tx, ty, ux, uy)
        px = tx
        py = ty
        apx = ux
        apy = uy
        tk = 1.0_dp
        it = 0
        do
            call jacobi_residual(inc, bound, s0x, s0y, qq, cs, kx, ky, tx, ty, ux, uy, r2, n2)
            if (r2 /= r2 .or. n2 /= n2 .or. r2 > huge(1.0_dp)) then
                info = STAT_NOT_FINITE
                resid = huge(1.0_dp)
                exit
            end if
            resid = 0.0_dp
            if (n2 > 0.0_dp) then
                resid = sqrt(r2 / n2)
            else if (r2 > 0.0_dp) then
                resid = 1.0_dp
            end if
            if (resid <= tol) exit
            if (it >= max_iter) then
                info = STAT_NOT_CONVERGED
                exit
            end if
            it = it + 1
            tk1 = 0.5_dp * (1.0_dp + sqrt(1.0_dp + 4.0_dp * tk * tk))
            beta = (tk - 1.0_dp) / tk1
            call fista_step(inc, bound, s0x, s0y, cs, step, beta, .not. fc, tx, ty, px, py, ux, uy, apx, apy, &
                            nx_, ny_)
            if (fc) then
                ! the projection onto the discs and the force: its multiplier is the shift (step) q
                call project_force(inc, bound, c, nx_, ny_, lam, info)
                if (info /= STAT_OK) exit
                qq = lam / step
            end if
            dot = restart_dot(inc, beta, tx, ty, px, py, nx_, ny_)
            px = tx
            py = ty
            tx = nx_
            ty = ny_
            apx = ux
            apy = uy
            call conv_apply_pair(w%plan, KERNEL_XX, KERNEL_XY, KERNEL_YY, tx, ty, ux, uy)
            ! gradient restart: the momentum points uphill
            tk = merge(1.0_dp, tk1, dot > 0.0_dp)
        end do
        iters = it
        if (fc) q = qq
        if (info /= STAT_NOT_FINITE) call final_state(inc, bound, s0x, s0y, qq, cs, kx, ky, tx, ty, ux, uy, &
                                                     status, slx, sly)
    end subroutine transient_tangential

    !> One gradient step from the extrapolated point y = t + beta (t - tp) (field
    !> A y = u + beta (u - up) by linearity): tn = y - step grad f(y), grad f = s0 + cs A y,
    !> put on the discs when proj (else the caller projects: force control).
    pure subroutine fista_step(inc, bound, s0x, s0y, cs, step, beta, proj, tx, ty, px, py, ux, uy, apx, apy, &
                               tnx, tny)
        logical, intent(in) :: inc(:, :), proj
        real(dp), intent(in) :: bound(:, :), s0x(:, :), s0y(:, :), cs, step, beta
        real(dp), intent(in) :: tx(:, :), ty(:, :), px(:, :), py(:, :)
        real(dp), intent(in) :: ux(:, :), uy(:, :), apx(:, :), apy(:, :)
        real(dp), intent(out) :: tnx(:, :), tny(:, :)
        real(dp) :: gx, gy, ax, ay
        integer :: i, j
        tnx = 0.0_dp
        tny = 0.0_dp
        do j = 1, size(tx, 2)
            do i = 1, size(tx, 1)
                if (.not. inc(i, j)) cycle
                gx = s0x(i, j) + cs * (ux(i, j) + beta * (ux(i, j) - apx(i, j)))
                gy = s0y(i, j) + cs * (uy(i, j) + beta * (uy(i, j) - apy(i, j)))
                ax = tx(i, j) + beta * (tx(i, j) - px(i, j)) - step * gx
                ay = ty(i, j) + beta * (ty(i, j) - py(i, j)) - step * gy
                if (proj) call project_on_disc(ax, ay, bound(i, j))
                tnx(i, j) = ax
                tny(i, j) = ay
            end do
        end do
    end subroutine fista_step

    !> (y - tn).(tn - t) with y = t + beta (t - tp): positive when the momentum points
    !> uphill and is dropped (gradient restart, O'Donoghue and Candes 2015).
    pure real(dp) function restart_dot(inc, beta, tx, ty, px, py, tnx, tny) result(dot)
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: beta, tx(:, :), ty(:, :), px(:, :), py(:, :), tnx(:, :), tny(:, :)
        real(dp) :: yx, yy
        integer :: i, j
        dot = 0.0_dp
        do j = 1, size(tx, 2)
            do i = 1, size(tx, 1)
                if (.not. inc(i, j)) cycle
                yx = tx(i, j) + beta * (tx(i, j) - px(i, j))
                yy = ty(i, j) + beta * (ty(i, j) - py(i, j))
                dot = dot + (yx - tnx(i, j)) * (tnx(i, j) - tx(i, j)) + (yy - tny(i, j)) * (tny(i, j) - ty(i, j))
            end do
        end do
    end function restart_dot

    !> Projection of z onto the discs |t_I| <= g_I and the force sum_I t_I = c (Pa, per
    !> element area), in place: t_I = P_I(z_I - lam) with the multiplier lam (2) found by
    !> Newton's method on the concave dual D(lam) = sum_I [|t_I - z_I|^2 / 2 + lam.t_I]
    !> - lam.c (gradient sum t - c, Hessian -sum dP_I/dz), with backtracking; lam:
    !> warm start in. info: STAT_OK; STAT_NOT_CONVERGED when no lam reaches c (|c| at or
    !> beyond sum g: no traction field carries the force).
    pure subroutine project_force(inc, bound, c, zx, zy, lam, info)
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: bound(:, :), c(2)
        real(dp), intent(inout) :: zx(:, :), zy(:, :), lam(2)
        integer, intent(out) :: info
        real(dp) :: r(2), h(3), d(2), dv, dn, rn(2), hn(3), det, eps, gsum, st
        integer :: it, ib
        info = STAT_OK
        gsum = sum(bound, mask=inc)
        call disc_sum(inc, bound, zx, zy, c, lam, r, h, dv)
        do it = 1, 100
            if (norm2(r) <= 1.0e-13_dp * gsum) exit
            eps = 1.0e-12_dp * (h(1) + h(3)) + tiny(1.0_dp)
            det = (h(1) + eps) * (h(3) + eps) - h(2)**2
            d = [(h(3) + eps) * r(1) - h(2) * r(2), (h(1) + eps) * r(2) - h(2) * r(1)] / det
            st = 1.0_dp
            do ib = 1, 60
                call disc_sum(inc, bound, zx, zy, c, lam + st * d, rn, hn, dn)
                ! an ascent of D, or (near the maximum, where D's rounding hides the ascent) a
                ! smaller gradient
                if (dn > dv .or. norm2(rn) < norm2(r)) exit
                st = 0.5_dp * st
            end do
            lam = lam + st * d
            r = rn
            h = hn
            dv = dn
        end do
        if (norm2(r) > 1.0e-9_dp * gsum) info = STAT_NOT_CONVERGED
        call disc_apply(inc, bound, lam, zx, zy)
    end subroutine project_force

    !> For t_I = P_I(z_I - lam): r = sum t - c, the 2 x 2 sum of dP_I/dz as (h11, h12, h22),
    !> and the dual value dv (project_force).
    pure subroutine disc_sum(inc, bound, zx, zy, c, lam, r, h, dv)
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: bound(:, :), zx(:, :), zy(:, :), c(2), lam(2)
        real(dp), intent(out) :: r(2), h(3), dv
        real(dp) :: wx, wy, wn, tx, ty, f
        integer :: i, j
        r = -c
        h = 0.0_dp
        dv = -dot_product(lam, c)
        do j = 1, size(zx, 2)
            do i = 1, size(zx, 1)
                if (.not. inc(i, j)) cycle
                wx = zx(i, j) - lam(1)
                wy = zy(i, j) - lam(2)
                wn = sqrt(wx * wx + wy * wy)
                if (wn <= bound(i, j)) then
                    tx = wx
                    ty = wy
                    h(1) = h(1) + 1.0_dp
                    h(3) = h(3) + 1.0_dp
                else
                    f = bound(i, j) / wn
                    tx = f * wx
                    ty = f * wy
                    h(1) = h(1) + f * (1.0_dp - (wx / wn)**2)
                    h(2) = h(2) - f * (wx / wn) * (wy / wn)
                    h(3) = h(3) + f * (1.0_dp - (wy / wn)**2)
                end if
                r(1) = r(1) + tx
                r(2) = r(2) + ty
                dv = dv + 0.5_dp * ((tx - zx(i, j))**2 + (ty - zy(i, j))**2) + lam(1) * tx + lam(2) * ty
            end do
        end do
    end subroutine disc_sum

    !> z_I <- P_I(z_I - lam) on the contact set.
    pure subroutine disc_apply(inc, bound, lam, zx, zy)
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: bound(:, :), lam(2)
        real(dp), intent(inout) :: zx(:, :), zy(:, :)
        integer :: i, j
        do j = 1, size(zx, 2)
            do i = 1, size(zx, 1)
                if (.not. inc(i, j)) cycle
                zx(i, j) = zx(i, j) - lam(1)
                zy(i, j) = zy(i, j) - lam(2)
                call project_on_disc(zx(i, j), zy(i, j), bound(i, j))
            end do
        end do
    end subroutine disc_apply

    !> Radial return of one traction onto its disc |t| <= bound.
    elemental subroutine project_on_disc(tx, ty, bound)
        real(dp), intent(inout) :: tx, ty
        real(dp), intent(in) :: bound
        real(dp) :: t
        t = sqrt(tx * tx + ty * ty)
        if (t > bound) then
            if (t > 0.0_dp) then
                tx = tx * bound / t
                ty = ty * bound / t
            end if
        end if
    end subroutine project_on_disc

    !> Every traction of the contact set on its disc.
    pure subroutine project_set(inc, bound, tx, ty)
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: bound(:, :)
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        integer :: i, j
        do j = 1, size(tx, 2)
            do i = 1, size(tx, 1)
                if (inc(i, j)) call project_on_disc(tx(i, j), ty(i, j), bound(i, j))
            end do
        end do
    end subroutine project_set

    !> lambda_max of the tangential operator A restricted to the contact set, by
    !> NPOWER power iterations from the uniform field (the top eigenvector of the
    !> positive kernel is smooth and positive), times LSAFE.
    real(dp) function power_lmax(w, inc) result(lmax)
        type(workspace), intent(inout) :: w
        logical, intent(in) :: inc(:, :)
        real(dp), allocatable :: vx(:, :), vy(:, :), ax(:, :), ay(:, :)
        real(dp) :: rho, nrm
        integer :: k
        allocate (vx(size(inc, 1), size(inc, 2)), vy(size(inc, 1), size(inc, 2)), ax(size(inc, 1), size(inc, 2)), &
                  ay(size(inc, 1), size(inc, 2)))
        vx = merge(1.0_dp, 0.0_dp, inc)
        vy = vx
        nrm = sqrt(sum(vx**2 + vy**2))
        vx = vx / nrm
        vy = vy / nrm
        rho = 0.0_dp
        do k = 1, NPOWER
            call conv_apply_pair(w%plan, KERNEL_XX, KERNEL_XY, KERNEL_YY, vx, vy, ax, ay)
            where (.not. inc)
                ax = 0.0_dp
                ay = 0.0_dp
            end where
            rho = sum(vx * ax + vy * ay)
            nrm = sqrt(sum(ax**2 + ay**2))
            if (.not. (nrm > 0.0_dp)) exit
            vx = ax / nrm
            vy = ay / nrm
        end do
        lmax = LSAFE * max(rho, w%c(0, 0, KERNEL_XX), w%c(0, 0, KERNEL_YY))
    end function power_lmax

    !> Squared norms of the Jacobi step F(t) - t and of F(t) over the contact
    !> set, F the element solutions with the pivot (kx, ky) = cs A(0) on the exact
    !> field u = A t (the convergence measure, module doc).
    pure subroutine jacobi_residual(inc, bound, s0x, s0y, q, cs, kx, ky, tx, ty, ux, uy, r2, n2)
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: bound(:, :), s0x(:, :), s0y(:, :), q(2), cs, kx, ky
        real(dp), intent(in) :: tx(:, :), ty(:, :), ux(:, :), uy(:, :)
        real(dp), intent(out) :: r2, n2
        real(dp) :: ax, ay, ntx, nty, lam
        integer :: i, j, st
        r2 = 0.0_dp
        n2 = 0.0_dp
        do j = 1, size(tx, 2)
            do i = 1, size(tx, 1)
                if (.not. inc(i, j)) cycle
                ax = s0x(i, j) + q(1) + cs * ux(i, j) - kx * tx(i, j)
                ay = s0y(i, j) + q(2) + cs * uy(i, j) - ky * ty(i, j)
                call element_solve(ax, ay, kx, ky, bound(i, j), ntx, nty, st, lam)
                r2 = r2 + (ntx - tx(i, j))**2 + (nty - ty(i, j))**2
                n2 = n2 + ntx**2 + nty**2
            end do
        end do
    end subroutine jacobi_residual

    !> Status and slip S (m over the step; 0 in adhesion) of every element in
    !> contact for the tractions t on the exact field u = A t.
    pure subroutine final_state(inc, bound, s0x, s0y, q, cs, kx, ky, tx, ty, ux, uy, status, slx, sly)
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: bound(:, :), s0x(:, :), s0y(:, :), q(2), cs, kx, ky
        real(dp), intent(in) :: tx(:, :), ty(:, :), ux(:, :), uy(:, :)
        integer, intent(inout) :: status(:, :)
        real(dp), intent(inout) :: slx(:, :), sly(:, :)
        real(dp) :: sx, sy, ntx, nty, lam
        integer :: i, j, st
        do j = 1, size(tx, 2)
            do i = 1, size(tx, 1)
                if (.not. inc(i, j)) cycle
                sx = s0x(i, j) + q(1) + cs * ux(i, j)
                sy = s0y(i, j) + q(2) + cs * uy(i, j)
                call element_solve(sx - kx * tx(i, j), sy - ky * ty(i, j), kx, ky, bound(i, j), ntx, nty, st, lam)
                status(i, j) = st
                if (st == ST_SLIP) then
                    slx(i, j) = sx
                    sly(i, j) = sy
                end if
            end do
        end do
    end subroutine final_state

    !> The tangential step under force control: the rigid shift q (m, added to s0
    !> everywhere) such that da sum t = target (both components), as the multiplier of
    !> the force in the projection (module doc). info: as transient_tangential;
    !> STAT_NOT_CONVERGED also when the force cannot be carried (|target| >= da sum g).
    subroutine transient_force(w, inc, bound, s0x, s0y, cs, target, da, tol, max_iter, tx, ty, ux, uy, &
                               status, slx, sly, q, iters, resid, info, lmax_io)
        type(workspace), intent(inout) :: w
        logical, intent(in) :: inc(:, :)
        real(dp), intent(in) :: bound(:, :), s0x(:, :), s0y(:, :), cs, target(2), da, tol
        integer, intent(in) :: max_iter
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        real(dp), intent(out) :: ux(:, :), uy(:, :), slx(:, :), sly(:, :), q(2), resid
        integer, intent(out) :: status(:, :), iters, info
        real(dp), intent(inout), optional :: lmax_io
        call transient_tangential(w, inc, bound, s0x, s0y, cs, tol, max_iter, tx, ty, ux, uy, status, slx, sly, &
                                  iters, resid, info, force=target, da=da, q=q, lmax_io=lmax_io)
    end subroutine transient_force

    !> March nt steps (module doc): per step n the normal problem for the gap h and
    !> the force fn(n) (re-solved when fn changes; with pgiven the pressure fn(n) h
    !> instead, h then the pressure per newton, 1/m^2), then the tangential step with the
    !> history. kshift: elements the material moves per step (V dt = kshift dx; 0 for
    !> a shift problem); th: the weight of eq. T2 (0: eq. T1); dist: rolled distance
    !> per step, m, scaling the creepages creep(:, n) = (xi, eta, phi) into the rigid
    !> slip dist (xi - phi y, eta + phi x); control: SHIFT_GIVEN (load(:, n) the rigid
    !> shift increment, m, added to the rigid slip) or FORCE_GIVEN (load(:, n) the
    !> tangential force, N, the shift found: transient_force). Per step: fx, fy (N),
    !> fno (N), q (the shift increment, m), ncon, nslip, iters, resids, infos (each
    !> step's status). Fields of the steps with keep(n) /= 0, in order, into ktx, kty
    !> (Pa), kst (status), ksx, ksy (slip, m), kp (pressure, Pa).
    !> info: STAT_OK; the first hard failure (STAT_GRID_EDGE: the pressure on the
    !> grid's edge, or the history reaching beyond the leading edge x = x_max;
    !> the normal solver's failure; STAT_NOT_FINITE), the march stopped there;
    !> STAT_NOT_CONVERGED if some step did not converge (the march goes on);
    !> STAT_BAD_ARGUMENT bad kshift, th, control or sizes; STAT_BAD_HANDLE no tangential kernels.
    subroutine transient_run(w, h, pgiven, fn, kshift, th, mu, x0, y0, dist, creep, control, load, tol, max_iter, &
                             tol_n, max_iter_n, keep, fx, fy, fno, q, ncon, nslip, iters, resids, infos, &
                             ktx, kty, kst, ksx, ksy, kp, info)
        type(workspace), intent(inout) :: w
        real(dp), intent(in) :: h(:, :), fn(:), th, mu, x0, y0, dist, creep(:, :), load(:, :), tol, tol_n
        logical, intent(in) :: pgiven
        integer, intent(in) :: kshift, control, max_iter, max_iter_n, keep(:)
        real(dp), intent(out) :: fx(:), fy(:), fno(:), q(:, :), resids(:)
        integer, intent(out) :: ncon(:), nslip(:), iters(:), infos(:), info
        real(dp), intent(out) :: ktx(:, :, :), kty(:, :, :), ksx(:, :, :), ksy(:, :, :), kp(:, :, :)
        integer, intent(out) :: kst(:, :, :)
        real(dp), allocatable :: p(:, :), bound(:, :), tx(:, :), ty(:, :), ux(:, :), uy(:, :), u1x(:, :), &
                                 u1y(:, :), u2x(:, :), u2y(:, :), s0x(:, :), s0y(:, :), slx(:, :), sly(:, :)
        integer, allocatable :: st(:, :)
        logical, allocatable :: inc(:, :)
        real(dp) :: da, fnk, appr, resn, lmax
        integer :: n, nt, kk, itn, nprod, stat

        nt = size(fn)
        fx = 0.0_dp; fy = 0.0_dp; fno = 0.0_dp; q = 0.0_dp; resids = 0.0_dp
        ncon = 0; nslip = 0; iters = 0; infos = STAT_OK
        ktx = 0.0_dp; kty = 0.0_dp; ksx = 0.0_dp; ksy = 0.0_dp; kp = 0.0_dp; kst = ST_EXTERIOR
        info = STAT_OK
        if (w%nker < 4) then
            info = STAT_BAD_HANDLE
            return
        end if
        if (kshift < 0 .or. th < 0.0_dp .or. th > 1.0_dp .or. (control /= SHIFT_GIVEN .and. control /= FORCE_GIVEN) &
            .or. size(creep, 2) /= nt .or. size(load, 2) /= nt .or. size(keep) /= nt) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        allocate (p, bound, tx, ty, ux, uy, u1x, u1y, u2x, u2y, s0x, s0y, slx, sly, mold=h)
        allocate (st(size(h, 1), size(h, 2)), inc(size(h, 1), size(h, 2)))
        p = 0.0_dp; tx = 0.0_dp; ty = 0.0_dp
        u1x = 0.0_dp; u1y = 0.0_dp; u2x = 0.0_dp; u2y = 0.0_dp
        da = w%dx * w%dy
        kk = 0
        lmax = 0.0_dp
        inc = .false.
        do n = 1, nt
            if (n == 1 .or. fn(n) /= fn(max(n - 1, 1))) then
                fnk = fn(n)
                appr = 0.0_dp
                stat = STAT_OK
                if (pgiven) then
                    p = max(fnk * h, 0.0_dp)
                else
                    call normal_cg(w%plan, KERNEL_ZZ, w%c(:, :, KERNEL_ZZ), h, da, CONTROL_FORCE, fnk, appr, &
                                   tol_n, max_iter_n, p, itn, nprod, resn, stat)
                end if
                if (stat == STAT_OK .and. .not. patch_fits(p, kshift, th)) stat = STAT_GRID_EDGE
                if (stat /= STAT_OK) then
                    infos(n) = stat
                    info = stat
                    return
                end if
                ! lambda_max depends on the contact set only: kept while the set stays
                if (any(inc .neqv. (p > 0.0_dp))) lmax = 0.0_dp
                inc = p > 0.0_dp
                bound = mu * p
            end if
            call history_slip(w, u1x, u1y, u2x, u2y, kshift, th, x0, y0, dist, creep(:, n), s0x, s0y)
            if (control == SHIFT_GIVEN) then
                q(:, n) = load(:, n)
                call transient_tangential(w, inc, bound, s0x + load(1, n), s0y + load(2, n), 1.0_dp + th, tol, &
                                          max_iter, tx, ty, ux, uy, st, slx, sly, iters(n), resids(n), stat, &
                                          lmax_io=lmax)
            else
                call transient_force(w, inc, bound, s0x, s0y, 1.0_dp + th, load(:, n), da, tol, max_iter, &
                                     tx, ty, ux, uy, st, slx, sly, q(:, n), iters(n), resids(n), stat, lmax)
            end if
            infos(n) = stat
            fx(n) = da * sum(tx)
            fy(n) = da * sum(ty)
            fno(n) = da * sum(p)
            ncon(n) = count(inc)
            nslip(n) = count(st == ST_SLIP)
            if (stat == STAT_NO_CONTACT .or. stat == STAT_NOT_CONVERGED) then
                if (stat == STAT_NOT_CONVERGED) info = STAT_NOT_CONVERGED
            else if (stat /= STAT_OK) then
                info = stat
                return
            end if
            if (keep(n) /= 0 .and. kk < size(ktx, 3)) then
                kk = kk + 1
                ktx(:, :, kk) = tx; kty(:, :, kk) = ty; kst(:, :, kk) = st
                ksx(:, :, kk) = slx; ksy(:, :, kk) = sly; kp(:, :, kk) = p
            end if
            u2x = u1x; u2y = u1y
            u1x = ux; u1y = uy
        end do
    end subroutine transient_run

    !> Whether the pressure p stays off the grid's edges and the history of a rolling
    !> step (kshift elements per step, two steps back for th > 0) stays on the grid
    !> upstream of the contact set (x_max side).
    pure logical function patch_fits(p, kshift, th)
        real(dp), intent(in) :: p(:, :), th
        integer, intent(in) :: kshift
        integer :: nx, ny, i, reach
        nx = size(p, 1)
        ny = size(p, 2)
        patch_fits = .not. (any(p(1, :) > 0.0_dp) .or. any(p(nx, :) > 0.0_dp) &
                            .or. any(p(:, 1) > 0.0_dp) .or. any(p(:, ny) > 0.0_dp))
        if (.not. patch_fits .or. kshift == 0) return
        reach = kshift
        if (th > 0.0_dp) reach = 2 * kshift
        do i = nx, 1, -1
            if (any(p(i, :) > 0.0_dp)) exit
        end do
        patch_fits = i + reach <= nx
    end function patch_fits

    !> The slip of zero traction of a step, m (eq. T2 without the cs A t term):
    !> s0 = dist (xi - phi y, eta + phi x) - (1 + 2 th) u'(i + k) + th u''(i + 2 k),
    !> u' = u1 and u'' = u2 the fields one and two steps back (zero beyond the grid:
    !> patch_fits keeps the contact set clear of that).
    pure subroutine history_slip(w, u1x, u1y, u2x, u2y, kshift, th, x0, y0, dist, creep, s0x, s0y)
        type(workspace), intent(in) :: w
        real(dp), intent(in) :: u1x(:, :), u1y(:, :), u2x(:, :), u2y(:, :), th, x0, y0, dist, creep(3)
        integer, intent(in) :: kshift
        real(dp), intent(out) :: s0x(:, :), s0y(:, :)
        integer :: i, j, nx
        real(dp) :: x, y
        nx = size(s0x, 1)
        do j = 1, size(s0x, 2)
            y = y0 + (j - 1) * w%dy
            do i = 1, nx
                x = x0 + (i - 1) * w%dx
                s0x(i, j) = dist * (creep(1) - creep(3) * y)
                s0y(i, j) = dist * (creep(2) + creep(3) * x)
                if (i + kshift <= nx) then
                    s0x(i, j) = s0x(i, j) - (1.0_dp + 2.0_dp * th) * u1x(i + kshift, j)
                    s0y(i, j) = s0y(i, j) - (1.0_dp + 2.0_dp * th) * u1y(i + kshift, j)
                end if
                if (th > 0.0_dp .and. i + 2 * kshift <= nx) then
                    s0x(i, j) = s0x(i, j) + th * u2x(i + 2 * kshift, j)
                    s0y(i, j) = s0y(i, j) + th * u2y(i + 2 * kshift, j)
                end if
            end do
        end do
    end subroutine history_slip

end module contact_transient
