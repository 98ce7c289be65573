!> The element problem of steady rolling (Kaiser eqs 26 and 28): one element's traction
!> on its Coulomb disc given its slip with its own traction removed, exactly, and its
!> friction-law variant (contact_friction). Split from contact_rolling; the equations
!> are described there.
!> Implements Kaiser eqs 26-28 (element_solve, element_slip, element_any).
module contact_rolling_element
    use common_kinds, only: dp
    use contact_friction, only: friction_element_solve, RULE_CONTINUOUS
    use contact_rolling_patch, only: ST_ADHESION, ST_SLIP, SOP_MAX, rolling_patch
    implicit none
    private
    public :: element_solve, element_solve_r, element_slip, element_any, element_batch

contains

    !> Exact solution of one element's friction problem with s = s0 + diag(kx, ky) t
    !> (eqs 26 and 28). stat: ST_ADHESION (s = 0) or ST_SLIP (|t| = g, t opposite
    !> to s); lam = |s| (0 in adhesion).
    pure subroutine element_solve(s0x, s0y, kx, ky, g, tx, ty, stat, lam)
        real(dp), intent(in) :: s0x, s0y   ! slip with the element's own traction removed
        real(dp), intent(in) :: kx, ky     ! diagonal self-influence (> 0), 1/Pa
        real(dp), intent(in) :: g          ! traction bound mu p, Pa
        real(dp), intent(out) :: tx, ty
        integer, intent(out) :: stat
        real(dp), intent(out) :: lam
        real(dp) :: ax, ay, gx, gy, ex, ey, en

        ax = -s0x / kx
        ay = -s0y / ky
        if (ax * ax + ay * ay <= g * g) then
            tx = ax
            ty = ay
            stat = ST_ADHESION
            lam = 0.0_dp
            return
        end if
        stat = ST_SLIP
        if (g <= 0.0_dp) then
            tx = 0.0_dp
            ty = 0.0_dp
            lam = sqrt(s0x * s0x + s0y * s0y)
            return
        end if
        ! s = lam e and t = -g e  =>  e = (s0x / (lam + g kx), s0y / (lam + g ky)),
        ! |e| = 1 fixes lam. f(lam) = |e|^2 - 1 is convex and decreasing, so Newton
        ! converges from any start: at worst the first step overshoots below the
        ! root and the rest is monotone. The start |s0| - g k, k the mean of kx, ky
        ! weighted by s0's components, is exact for kx = ky and within a few per
        ! cent of the root otherwise: 2-3 steps (4-5 from |s0| - g max(kx, ky)).
        ! The convergence is quadratic, so a step below 1e-8 of the scale leaves an
        ! error of order 1e-16 after it.
        gx = g * kx
        gy = g * ky
        en = s0x * s0x + s0y * s0y
        lam = max(0.0_dp, sqrt(en) - (gx * s0x * s0x + gy * s0y * s0y) / en)
        call slip_root(s0x, s0y, gx, gy, 1.0e-8_dp, lam)
        ex = s0x / (lam + gx)
        ey = s0y / (lam + gy)
        en = sqrt(ex * ex + ey * ey)
        if (en > 0.0_dp) then
            ex = ex / en
            ey = ey / en
        end if
        tx = -g * ex
        ty = -g * ey
    end subroutine element_solve

    !> element_solve on the small path (iterate_small): the reciprocals rkx = 1 / kx,
    !> rky = 1 / ky given (a run's pivots, kept with its basis: no division in the adhesion
    !> test) and the slip solution by element_slip (its closer start and earlier stop: the
    !> same tractions to about 1e-11 relative). element_solve itself, which the grid path
    !> and contact_coupling use, is unchanged (their results stay main's to the bit).
    pure subroutine element_solve_r(s0x, s0y, kx, ky, rkx, rky, g, tx, ty, stat, lam)
        real(dp), intent(in) :: s0x, s0y, kx, ky, rkx, rky, g
        real(dp), intent(out) :: tx, ty, lam
        integer, intent(out) :: stat
        real(dp) :: ax, ay
        ax = -s0x * rkx
        ay = -s0y * rky
        if (ax * ax + ay * ay <= g * g) then
            tx = ax
            ty = ay
            stat = ST_ADHESION
            lam = 0.0_dp
            return
        end if
        call element_slip(s0x, s0y, kx, ky, g, tx, ty, lam)
        stat = ST_SLIP
    end subroutine element_solve_r

    !> Newton's iteration for the slip multiplier lam of element_solve and element_slip
    !> (eq. 28): f(lam) = |e|^2 - 1 with e = (s0x / (lam + gx), s0y / (lam + gy)), from the
    !> caller's start, stopped once a step is below tol of the scale lam + gx + gy.
    pure subroutine slip_root(s0x, s0y, gx, gy, tol, lam)
        real(dp), intent(in) :: s0x, s0y, gx, gy, tol
        real(dp), intent(inout) :: lam
        real(dp) :: f, fp, dl, dx3, dy3
        integer :: it
        do it = 1, 100
            dx3 = 1.0_dp / (lam + gx)
            dy3 = 1.0_dp / (lam + gy)
            f = (s0x * dx3)**2 + (s0y * dy3)**2 - 1.0_dp
            fp = -2.0_dp * ((s0x * dx3)**2 * dx3 + (s0y * dy3)**2 * dy3)
            if (fp >= 0.0_dp) exit
            dl = -f / fp
            lam = max(lam + dl, 0.0_dp)
            if (abs(dl) <= tol * (lam + gx + gy)) exit
        end do
    end subroutine slip_root

    !> The slip solution of element_solve (eq. 28), |t| = g with t opposite to s, when the
    !> adhesion traction lies outside the disc, for the small path: element_solve's Newton
    !> iteration from the second-order start below, stopped once a step is below 1e-6 of
    !> the scale (element_solve: 1e-8 from a first-order start), with one division per
    !> reciprocal pair (the element problems' divisions are a chain in the sweep: their
    !> latency, not their count of instructions, is what a sweep waits for).
    pure subroutine element_slip(s0x, s0y, kx, ky, g, tx, ty, lam)
        real(dp), intent(in) :: s0x, s0y, kx, ky, g
        real(dp), intent(out) :: tx, ty, lam
        real(dp) :: gx, gy, f, ex, ey, en, r, d

        if (g <= 0.0_dp) then
            tx = 0.0_dp
            ty = 0.0_dp
            lam = sqrt(s0x * s0x + s0y * s0y)
            return
        end if
        ! s = lam e and t = -g e  =>  e = (s0x / (lam + gx), s0y / (lam + gy)),
        ! |e| = 1 fixes lam. f(lam) = |e|^2 - 1 is convex and decreasing, so Newton
        ! converges from any start: at worst the first step overshoots below the
        ! root and the rest is monotone. The start: with mu = lam + c, c = (gx + gy) / 2,
        ! d = (gx - gy) / 2, the root's expansion in delta = d / |s0| to second order,
        ! mu = |s0| (1 - delta rho + 3/2 delta^2 (1 - rho^2)), rho = (s0x^2 - s0y^2) / |s0|^2
        ! (exact for kx = ky; the first-order term alone is the mean of kx, ky weighted by
        ! s0's components): 2-3 steps (about one more from the first-order start).
        ! The convergence is quadratic (error after a step about 3/2 dl^2 / (lam + g k)),
        ! so a step below 1e-6 of the scale leaves a relative error below about 1e-11.
        gx = g * kx
        gy = g * ky
        en = s0x * s0x + s0y * s0y
        r = sqrt(en)
        ex = 1.0_dp / r
        d = 0.5_dp * (gx - gy) * ex
        f = (s0x * s0x - s0y * s0y) * (ex * ex)
        lam = max(0.0_dp, r * (1.0_dp - d * f + 1.5_dp * d * d * (1.0_dp - f * f)) - 0.5_dp * (gx + gy))
        call slip_root_r(s0x, s0y, gx, gy, lam)
        ! e is parallel to (s0x (lam + gy), s0y (lam + gx)): (lam + gx)(lam + gy) > 0
        ex = s0x * (lam + gy)
        ey = s0y * (lam + gx)
        en = g / sqrt(ex * ex + ey * ey)
        tx = -ex * en
        ty = -ey * en
    end subroutine element_slip

    !> slip_root for the small path (element_slip, element_batch's sequential form): the
    !> two reciprocals 1 / (lam + gx), 1 / (lam + gy) of a step from one division of
    !> their product; stopped once a step is below 1e-6 of the scale lam + gx + gy.
    pure subroutine slip_root_r(s0x, s0y, gx, gy, lam)
        real(dp), intent(in) :: s0x, s0y, gx, gy
        real(dp), intent(inout) :: lam
        real(dp) :: f, fp, dl, dx3, dy3, a, b, r, ex2, ey2
        integer :: it
        do it = 1, 100
            a = lam + gx
            b = lam + gy
            r = 1.0_dp / (a * b)
            dx3 = b * r
            dy3 = a * r
            ex2 = (s0x * dx3)**2
            ey2 = (s0y * dy3)**2
            f = ex2 + ey2 - 1.0_dp
            fp = -2.0_dp * (ex2 * dx3 + ey2 * dy3)
            if (fp >= 0.0_dp) exit
            dl = -f / fp
            lam = max(lam + dl, 0.0_dp)
            if (abs(dl) <= 1.0e-6_dp * (lam + gx + gy)) exit
        end do
    end subroutine slip_root_r

    !> The element problem by the solve's friction law: element_solve (constant
    !> Coulomb: today's path, unchanged) or contact_friction's friction_element_solve;
    !> (scx, scy): the slip of the current iterate, for the rule RULE_CONTINUOUS.
    !> nsol_out (optional): the element problem's solutions (1 on today's path).
    pure subroutine element_any(pa, s0x, s0y, kx, ky, g, scx, scy, tx, ty, stat, lam, nsol_out)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: s0x, s0y, kx, ky, g, scx, scy
        real(dp), intent(out) :: tx, ty, lam
        integer, intent(out) :: stat
        integer, intent(out), optional :: nsol_out
        integer :: nsol
        nsol = 1
        if (pa%varlaw) then
            if (pa%law%rule == RULE_CONTINUOUS) then
                call friction_element_solve(pa%law, pa%speed, s0x, s0y, kx, ky, g, tx, ty, stat, lam, nsol, &
                                            lam_prev=sqrt(scx * scx + scy * scy))
            else
                call friction_element_solve(pa%law, pa%speed, s0x, s0y, kx, ky, g, tx, ty, stat, lam, nsol)
            end if
        else
            call element_solve(s0x, s0y, kx, ky, g, tx, ty, stat, lam)
        end if
        if (present(nsol_out)) nsol_out = nsol
    end subroutine element_any

    !> element_solve for many elements with the same pivots kx, ky (jacobi_small): the
    !> adhesion test for each (slip: its outcome), then element_solve's Newton iteration on the slipping ones
    !> side by side, without a branch per element and step (the steps go on until every
    !> one has met element_solve's test; one that had only refines), so that the divisions
    !> of different elements overlap. Agrees with element_solve to about 1e-11 relative.
    pure subroutine element_batch(s0x, s0y, kx, ky, g, tx, ty, slip)
        real(dp), intent(in) :: s0x(:), s0y(:), kx, ky, g(:)
        real(dp), intent(out) :: tx(:), ty(:)
        logical, intent(out) :: slip(:)   ! the element's status is ST_SLIP
        real(dp), dimension(SOP_MAX) :: sx, sy, gx, gy, lam   ! size(s0x) <= SOP_MAX
        logical :: ok(SOP_MAX)
        real(dp) :: ax, ay, en, r, d, rho, dx3, dy3, f, fp, dl, rkx, rky, a, b, ex2, ey2
        integer :: idx(SOP_MAX), k, m, ns, it
        ns = 0
        rkx = 1.0_dp / kx
        rky = 1.0_dp / ky
        do k = 1, size(s0x)
            ax = -s0x(k) * rkx
            ay = -s0y(k) * rky
            slip(k) = ax * ax + ay * ay > g(k) * g(k)
            if (.not. slip(k)) then
                tx(k) = ax
                ty(k) = ay
            else
                tx(k) = 0.0_dp       ! g <= 0: no traction
                ty(k) = 0.0_dp
                if (g(k) <= 0.0_dp) cycle
                ns = ns + 1
                idx(ns) = k
                sx(ns) = s0x(k)
                sy(ns) = s0y(k)
                gx(ns) = g(k) * kx
                gy(ns) = g(k) * ky
            end if
        end do
        if (ns == 0) return
        do m = 1, ns   ! element_slip's second-order start
            en = sx(m) * sx(m) + sy(m) * sy(m)
            r = sqrt(en)
            a = 1.0_dp / r
            d = 0.5_dp * (gx(m) - gy(m)) * a
            rho = (sx(m) * sx(m) - sy(m) * sy(m)) * (a * a)
            lam(m) = max(0.0_dp, r * (1.0_dp - d * rho + 1.5_dp * d * d * (1.0_dp - rho * rho)) &
                         - 0.5_dp * (gx(m) + gy(m)))
        end do
        do it = 1, 100   ! slip_root_r's steps side by side
            do m = 1, ns
                a = lam(m) + gx(m)
                b = lam(m) + gy(m)
                r = 1.0_dp / (a * b)
                dx3 = b * r
                dy3 = a * r
                ex2 = (sx(m) * dx3)**2
                ey2 = (sy(m) * dy3)**2
                f = ex2 + ey2 - 1.0_dp
                fp = -2.0_dp * (ex2 * dx3 + ey2 * dy3)
                dl = merge(-f / min(fp, -tiny(1.0_dp)), 0.0_dp, fp < 0.0_dp)
                lam(m) = max(lam(m) + dl, 0.0_dp)
                ok(m) = abs(dl) <= 1.0e-6_dp * (lam(m) + gx(m) + gy(m))
            end do
            if (all(ok(1:ns))) exit
        end do
        do m = 1, ns   ! e parallel to (sx (lam + gy), sy (lam + gx))
            dx3 = sx(m) * (lam(m) + gy(m))
            dy3 = sy(m) * (lam(m) + gx(m))
            en = g(idx(m)) / sqrt(dx3 * dx3 + dy3 * dy3)
            tx(idx(m)) = -dx3 * en
            ty(idx(m)) = -dy3 * en
        end do
    end subroutine element_batch

end module contact_rolling_element
