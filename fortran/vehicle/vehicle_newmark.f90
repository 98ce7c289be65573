!> Implicit time integration of M a = F(q, v) and the static equilibrium F(q, 0) = 0.
!> Implements Newmark/HHT-alpha and the Zienkiewicz-Xie estimate; no Kaiser equation.
!>
!> Newmark with HHT-alpha (Hilber, Hughes & Taylor 1977): alpha in [-1/3, 0],
!> beta = (1 - alpha)^2 / 4, gamma = 1/2 - alpha; alpha = 0 is the average acceleration
!> (trapezoidal) rule. Residual at t_{n+1}:  M a_{n+1} - (1 + alpha) F_{n+1} + alpha F_n = 0,
!> solved for q_{n+1} by Newton's method with the tangent of vehicle_model%tangent, refreshed
!> at the first iteration of each step and again when an iteration does not contract.
!> Local error estimate per step (Zienkiewicz & Xie 1991): e = h^2 |beta - 1/6| |a_{n+1} - a_n|.
module vehicle_newmark
    use common_kinds, only: dp
    use common_lapack, only: dgetrf, dgetrs
    use vehicle_contact, only: nwo
    use vehicle_model, only: vmodel, force_total, tangent, is_spin
    implicit none
    private
    public :: newmark_run, static_solve, initial_acceleration, too_big


contains

    !> a = M^-1 F(q, v).
    subroutine initial_acceleration(md, q, v, a, info)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: q(md%nd), v(md%nd)
        real(dp), intent(out) :: a(md%nd)
        integer, intent(out) :: info
        real(dp) :: f(md%nd), wout(nwo, 2, md%nw), mm(md%nd, md%nd)
        integer :: ipiv(md%nd)
        call force_total(md, q, v, f, wout, info)
        a = 0.0_dp
        if (info /= 0) return
        mm = md%m
        call dgetrf(md%nd, md%nd, mm, md%nd, ipiv, info)
        if (info /= 0) then
            info = -1
            return
        end if
        a = f
        call dgetrs('N', md%nd, 1, mm, md%nd, ipiv, a, md%nd, info)
    end subroutine initial_acceleration

    !> One HHT step of size h from (q, v, a, fn = F(q, v)); on success the state is advanced.
    !> ok = .false. when Newton does not converge (the state is left unchanged). A trial
    !> iterate outside the table (3) or with a BEM patch at its grid edge or unconverged
    !> (5, 6) fails the step (to be retried with sub-steps) and is recorded in why.
    subroutine hht_step(md, h, alpha, tol, maxit, qmax, q, v, a, fn, wk, nit, njac, err, ok, why, info)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: h, alpha, tol, qmax
        integer, intent(in) :: maxit
        real(dp), intent(inout) :: q(md%nd), v(md%nd), a(md%nd), fn(md%nd)
        real(dp), intent(out) :: wk(nwo, 2, md%nw), err
        integer, intent(inout) :: nit, njac, why
        logical, intent(out) :: ok
        integer, intent(out) :: info
        real(dp) :: beta, gamma, cq, cv, f1(md%nd), r(md%nd), jac(md%nd, md%nd)
        real(dp) :: qt(md%nd), vt(md%nd), q1(md%nd), v1(md%nd), a1(md%nd), dq, dqold
        real(dp) :: dqv(md%nd), qtry(md%nd), rtry(md%nd), rn, rnt, sl
        real(dp) :: flast(md%nd), fkeep(md%nd), wlast(nwo, 2, md%nw), wkeep(nwo, 2, md%nw)
        integer :: ipiv(md%nd), it, lin, ls
        logical :: fresh
        beta = 0.25_dp * (1.0_dp - alpha)**2
        gamma = 0.5_dp - alpha
        cq = 1.0_dp / (beta * h * h)
        cv = gamma / (beta * h)
        ok = .false.
        err = 0.0_dp
        qt = q + h * v + h * h * (0.5_dp - beta) * a     ! predictor (the a_{n+1} = 0 part)
        vt = v + h * (1.0_dp - gamma) * a
        q1 = q + h * v + 0.5_dp * h * h * a               ! start: constant acceleration
        dqold = huge(1.0_dp)
        dq = huge(1.0_dp)
        fresh = .false.
        call residual(q1, r, rn, info)
        if (info /= 0) then
            if (soft(info)) info = 0    ! e.g. an iterate outside the table: a failed step, retried
            return
        end if
        fkeep = flast
        wkeep = wlast
        do it = 1, maxit
            if (.not. fresh) then
                a1 = cq * (q1 - qt)
                v1 = vt + gamma * h * a1
                call tangent(md, q1, v1, cv, 0, jac, info)
                if (soft(info)) info = 0
                if (info /= 0) return
                jac = cq * md%m - (1.0_dp + alpha) * jac
                call dgetrf(md%nd, md%nd, jac, md%nd, ipiv, lin)
                njac = njac + 1
                fresh = .true.
                if (lin /= 0) return
            end if
            dqv = r
            call dgetrs('N', md%nd, 1, jac, md%nd, ipiv, dqv, md%nd, lin)
            nit = nit + 1
            if (.not. (maxval(abs(dqv)) <= qmax)) return
            ! backtracking on the residual norm (contact closing/opening makes full steps cycle)
            sl = 1.0_dp
            do ls = 1, 6
                qtry = q1 + sl * dqv
                call residual(qtry, rtry, rnt, info)
                if (soft(info)) then
                    info = 0
                    rnt = huge(1.0_dp)
                end if
                if (info /= 0) return
                if (rnt < rn .or. ls == 6) exit
                sl = 0.5_dp * sl
            end do
            if (rnt == huge(1.0_dp)) return
            q1 = qtry
            r = rtry
            rn = rnt
            fkeep = flast
            wkeep = wlast
            dq = sl * maxval(abs(dqv))
            if (sl == 1.0_dp .and. dq <= tol) exit
            ! a damped step or a contraction worse than 1/2: refresh the tangent
            if (sl < 1.0_dp .or. dq > 0.5_dp * dqold) fresh = .false.
            dqold = dq
            dq = huge(1.0_dp)
        end do
        if (.not. (dq <= tol)) return
        a1 = cq * (q1 - qt)
        v1 = vt + gamma * h * a1
        f1 = fkeep      ! F(q1, v1) from the accepted residual: no extra (BEM) evaluation
        wk = wkeep
        if (too_big(md, q1, v1, qmax)) return
        err = h * h * abs(beta - 1.0_dp / 6.0_dp) * maxval(abs(a1 - a))
        q = q1
        v = v1
        a = a1
        fn = f1
        ok = .true.
    contains
        !> Residual -(M a - (1 + alpha) F(q, v) + alpha F_n) at the trial q and its 2-norm.
        subroutine residual(qq, rr, nrm, inf)
            real(dp), intent(in) :: qq(md%nd)
            real(dp), intent(out) :: rr(md%nd), nrm
            integer, intent(out) :: inf
            real(dp) :: aa(md%nd), vv(md%nd), ff(md%nd)
            aa = cq * (qq - qt)
            vv = vt + gamma * h * aa
            call force_total(md, qq, vv, ff, wlast, inf)
            flast = ff
            rr = -(matmul(md%m, aa) - (1.0_dp + alpha) * ff + alpha * fn)
            nrm = norm2(rr)
        end subroutine residual

        !> A failure of one trial state: recorded, the step fails softly.
        logical function soft(inf)
            integer, intent(in) :: inf
            soft = inf == 3 .or. inf == 5 .or. inf == 6
            if (soft) why = inf
        end function soft
    end subroutine hht_step

    !> Integrate nsteps steps of size h from (t, q, v, a), storing every nevery-th step.
    !> A step whose Newton iterations fail is retried as 2, 4, ... 2^maxsub sub-steps
    !> (contact closing or opening within the step); the output stays on the h grid.
    !> info: 0 ok, 2 Newton did not converge even at h / 2^maxsub, 3 a wheelset left the
    !> contact table, 4 non-finite state or |q| above qmax, 5 a BEM patch at its grid edge,
    !> 6 a BEM solver not converging (5 and 6 when they made the last sub-step fail); tfail
    !> the time of the failure.
    !> stats: 1 Newton iterations, 2 tangent evaluations, 3 max local error estimate
    !> (Zienkiewicz & Xie: h^2 |beta - 1/6| |a_{n+1} - a_n|, m or rad), 4 steps done,
    !> 5 steps that needed sub-steps, 6 smallest sub-step used (s).
    subroutine newmark_run(md, h, nsteps, nevery, alpha, tol, maxit, maxsub, qmax, t, q, v, a, &
                           nout, tout, qout, vout, wout, stats, info, tfail)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: h, alpha, tol, qmax
        integer, intent(in) :: nsteps, nevery, maxit, maxsub, nout
        real(dp), intent(inout) :: t, q(md%nd), v(md%nd), a(md%nd)
        real(dp), intent(out) :: tout(nout), qout(md%nd, nout), vout(md%nd, nout)
        real(dp), intent(out) :: wout(nwo, 2, md%nw, nout), stats(6)
        integer, intent(out) :: info
        real(dp), intent(out) :: tfail
        real(dp) :: fn(md%nd), wk(nwo, 2, md%nw), err, tl
        integer :: n, io, nit, njac, why
        logical :: ok
        stats = 0.0_dp
        stats(6) = h
        tout = 0.0_dp
        qout = 0.0_dp
        vout = 0.0_dp
        wout = 0.0_dp
        tfail = t
        io = 0
        nit = 0
        njac = 0
        why = 0
        call force_total(md, q, v, fn, wk, info)
        if (info /= 0) return
        do n = 1, nsteps
            tl = 0.0_dp
            why = 0
            call finish_rest(0)
            if (info /= 0 .or. .not. ok) then
                if (info == 0) info = 2
                if (info == 2 .and. (why == 5 .or. why == 6)) info = why
                if (info == 2 .and. near_edge()) info = 3
                if (too_big(md, q, v, qmax)) info = 4
                tfail = t + tl + h / 2**maxsub
                stats(1) = nit
                stats(2) = njac
                return
            end if
            t = t + h
            stats(4) = stats(4) + 1.0_dp
            if (mod(n, nevery) == 0 .and. io < nout) then
                io = io + 1
                tout(io) = t
                qout(:, io) = q
                vout(:, io) = v
                wout(:, :, :, io) = wk
            end if
        end do
        stats(1) = nit
        stats(2) = njac
    contains
        !> A wheelset within 0.5 mm of the table's end (flange climb or divergence).
        logical function near_edge()
            integer :: w
            real(dp) :: yr
            near_edge = .false.
            do w = 1, md%nw
                yr = q(md%iws(1, w))
                if (md%itr(1, w) > 0) yr = yr - q(md%itr(1, w))
                if (abs(yr) > -md%y0 - 5.0e-4_dp) near_edge = .true.
            end do
        end function near_edge

        !> Cover the rest of the step, h - tl, with sub-steps h / 2^lev, refining further on
        !> failure; sets ok.
        recursive subroutine finish_rest(lev)
            integer, intent(in) :: lev
            real(dp) :: hl
            if (lev > 0) stats(5) = stats(5) + 1.0_dp
            hl = h / 2**lev
            stats(6) = min(stats(6), hl)
            do while (tl < h - 0.5_dp * hl)
                call hht_step(md, hl, alpha, tol, maxit, qmax, q, v, a, fn, wk, nit, njac, &
                              err, ok, why, info)
                if (info /= 0) then
                    ok = .false.
                    return
                end if
                if (.not. ok) then
                    if (lev >= maxsub) return
                    call finish_rest(lev + 1)
                    return
                end if
                tl = tl + hl
                stats(3) = max(stats(3), err)
            end do
            ok = .true.
        end subroutine finish_rest
    end subroutine newmark_run

    !> A non-finite state, |q| above qmax or |v| above 1e6. The spin perturbations beta are
    !> only checked for being finite: no force depends on them, and at a steady spin rate
    !> (free rolling with a longitudinal creepage) they grow linearly in time.
    pure logical function too_big(md, q, v, qmax)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: q(md%nd), v(md%nd), qmax
        integer :: j
        too_big = any(.not. (abs(v) <= 1.0e6_dp))
        if (too_big) return
        do j = 1, md%nd
            if (is_spin(md, j)) then
                too_big = .not. (abs(q(j)) <= huge(1.0_dp))
            else
                too_big = .not. (abs(q(j)) <= qmax)
            end if
            if (too_big) return
        end do
    end function too_big

    !> Steady state of running on straight track: F(q, v) = 0 with v = 0 except the rates of
    !> the wheelsets' spin perturbations beta, which are unknowns in place of the angles
    !> (no force depends on beta; free rolling fixes betadot). Newton's method with step
    !> halving on the residual; the spin columns of the tangent are dF/dv.
    !> info: 0 ok, 2 not converged, 3 outside the contact table, -1 singular tangent.
    subroutine static_solve(md, q, v, tol, maxit, iters, resid, info)
        type(vmodel), intent(in) :: md
        real(dp), intent(inout) :: q(md%nd)
        real(dp), intent(out) :: v(md%nd)
        real(dp), intent(in) :: tol
        integer, intent(in) :: maxit
        integer, intent(out) :: iters, info
        real(dp), intent(out) :: resid
        real(dp) :: f(md%nd), ftry(md%nd), jac(md%nd, md%nd), jv(md%nd, md%nd), dq(md%nd)
        real(dp) :: wk(nwo, 2, md%nw), s, r0, r1
        logical :: spin(md%nd)
        integer :: ipiv(md%nd), it, lin, ls, j
        v = 0.0_dp
        iters = 0
        resid = 0.0_dp
        do j = 1, md%nd
            spin(j) = is_spin(md, j)
        end do
        call force_total(md, q, v, f, wk, info)
        if (info /= 0) return
        r0 = norm2(f)
        do it = 1, maxit
            iters = it
            call tangent(md, q, v, 0.0_dp, 0, jac, info)
            if (info /= 0) return
            if (any(spin)) then
                call tangent(md, q, v, 0.0_dp, 1, jv, info)
                if (info /= 0) return
                do j = 1, md%nd
                    if (.not. spin(j)) cycle
                    jac(:, j) = jv(:, j)
                    ! no creep force (friction 0, or wheels off the rails): the rate is free;
                    ! keep it (its equation F_j = 0 holds already)
                    if (all(jv(:, j) == 0.0_dp)) jac(j, j) = -1.0_dp
                end do
            end if
            jac = -jac
            call dgetrf(md%nd, md%nd, jac, md%nd, ipiv, lin)
            if (lin /= 0) then
                info = -1
                return
            end if
            dq = f
            call dgetrs('N', md%nd, 1, jac, md%nd, ipiv, dq, md%nd, lin)
            s = 1.0_dp
            do ls = 1, 30
                call force_total(md, merge(q, q + s * dq, spin), merge(v + s * dq, v, spin), ftry, &
                                 wk, info)
                if (info == 0) then
                    r1 = norm2(ftry)
                    if (r1 < r0 .or. ls == 30) exit
                end if
                s = 0.5_dp * s
            end do
            if (info /= 0) return
            q = merge(q, q + s * dq, spin)
            v = merge(v + s * dq, v, spin)
            f = ftry
            r0 = r1
            resid = maxval(abs(s * dq))
            if (resid <= tol) return
        end do
        info = 2
    end subroutine static_solve

end module vehicle_newmark
