!> Steady-state rolling contact of quasi-identical bodies: the tangential
!> tractions for a given pressure, creepages and Coulomb friction (Kaiser,
!> eqs 24-29; Kalker 1990, ch. 2 and 5).
!>
!> Kinematics. The contact patch is fixed; material particles move through it
!> in -x at the rolling speed V, so the leading edge is at the largest x.
!> In units of V (creepage units) the slip of element I = (i, j) is
!>
!>   s_I = w_I + (u_I - u_I+) / dx,     I+ = (i + 1, j), the upstream element,
!>   w_x = xi - phi y_j,   w_y = eta + phi x_i,                 (eq. 29)
!>
!> the difference quotient being the material derivative of the displacement
!> difference u = A t over dt = dx / V. u_I+ is the displacement of the
!> particle one time step before, taken from the full field u = A t (it is
!> non-zero outside the contact area too). With this sign convention a
!> positive xi gives a negative Fx (Fx = -G a b C11 xi in the linear limit).
!>
!> Friction law per element in contact (p > 0), g = mu p:
!>   adhesion  s = 0,               |t| <= g                    (eq. 26)
!>   slip      t = -g s / |s|,      |t| = g                     (eq. 28)
!> The element's own traction enters its slip through the diagonal block
!> D = (A(0, 0) - A(+dx, 0)) / dx, which is diagonal (A_xy vanishes on the
!> x axis), so s = s0 + D t is affine in t and the element problem is solved
!> exactly on the Coulomb disc (element_solve): the adhesion traction
!> -D^-1 s0 if it lies in the disc, else the unique t = -g e with
!> s = lambda e, lambda > 0, found by a monotone Newton iteration on lambda.
!>
!> Iteration. Gauss-Seidel sweeps over the elements in contact, marching from
!> the leading edge (i = nx) backward so that the dominant upstream coupling
!> is resolved within one sweep. Every sweep starts from the exact field
!> u = A t (one FFT pair product); changes of t during the sweep update u only
!> inside a window of +-nwin elements around the changed element:
!>   - 'gs' (method 1): the window covers the whole contact area, i.e. plain
!>     Gauss-Seidel with exact element updates, O(N^2) per sweep;
!>   - 'fftgs' (method 2): a small window (default 4), the far field being
!>     refreshed by the FFT product once per sweep, O(N nwin^2 + N log N).
!> The residual is the relative change of a Jacobi step on the exact field,
!>   r = || F(t) - t ||_2 / || F(t) ||_2,
!> F being the element solutions: zero exactly at the solution.
module contact_rolling
    use kinds, only: dp
    use contact_plans, only: workspace
    use contact_convolution, only: conv_apply_pair
    implicit none
    private
    public :: rolling_steady, element_solve
    public :: ROLL_GS, ROLL_FFTGS, ST_EXTERIOR, ST_ADHESION, ST_SLIP

    integer, parameter :: ROLL_GS = 1, ROLL_FFTGS = 2
    integer, parameter :: ST_EXTERIOR = 0, ST_ADHESION = 1, ST_SLIP = 2
    integer, parameter :: KXX = 2, KYY = 3, KXY = 4

contains

    !> Exact solution of one element's friction problem with s = s0 + diag(kx, ky) t.
    !> stat: ST_ADHESION (s = 0) or ST_SLIP (|t| = g, t opposite to s);
    !> lam = |s| (0 in adhesion).
    pure subroutine element_solve(s0x, s0y, kx, ky, g, tx, ty, stat, lam)
        real(dp), intent(in) :: s0x, s0y   ! slip with the element's own traction removed
        real(dp), intent(in) :: kx, ky     ! diagonal self-influence (> 0), 1/Pa
        real(dp), intent(in) :: g          ! traction bound mu p, Pa
        real(dp), intent(out) :: tx, ty
        integer, intent(out) :: stat
        real(dp), intent(out) :: lam
        real(dp) :: ax, ay, gx, gy, f, fp, dl, ex, ey, en, dx3, dy3
        integer :: it

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
            lam = hypot(s0x, s0y)
            return
        end if
        ! s = lam e and t = -g e  =>  e = (s0x / (lam + g kx), s0y / (lam + g ky)),
        ! |e| = 1 fixes lam. f(lam) = |e|^2 - 1 is convex and decreasing, and
        ! f >= 0 at lam = |s0| - g max(kx, ky), so Newton from there is monotone.
        gx = g * kx
        gy = g * ky
        lam = max(0.0_dp, hypot(s0x, s0y) - max(gx, gy))
        do it = 1, 100
            dx3 = 1.0_dp / (lam + gx)
            dy3 = 1.0_dp / (lam + gy)
            f = (s0x * dx3)**2 + (s0y * dy3)**2 - 1.0_dp
            fp = -2.0_dp * ((s0x * dx3)**2 * dx3 + (s0y * dy3)**2 * dy3)
            if (fp >= 0.0_dp) exit
            dl = -f / fp
            lam = max(lam + dl, 0.0_dp)
            if (abs(dl) <= 1.0e-15_dp * (lam + gx + gy)) exit
        end do
        ex = s0x / (lam + gx)
        ey = s0y / (lam + gy)
        en = hypot(ex, ey)
        if (en > 0.0_dp) then
            ex = ex / en
            ey = ey / en
        end if
        tx = -g * ex
        ty = -g * ey
    end subroutine element_solve

    !> Steady rolling: tangential tractions for the pressure p on the grid of
    !> workspace w (made with the tangential kernels).
    !>
    !> info: 0 converged, 1 not converged in max_iter sweeps (resid holds the
    !> residual), 2 no element in contact (t = 0), -1 workspace without the
    !> tangential kernels, -2 bad method, -3 bad window, -4 contact reaches
    !> the upstream grid edge i = nx (no upstream element), -5 non-finite values.
    subroutine rolling_steady(w, p, x0, y0, xi, eta, phi, mu, speed, method, nblock, ninner, tol, max_iter, &
                              tx, ty, status, sx, sy, iters, resid, info)
        type(workspace), intent(inout) :: w
        real(dp), intent(in) :: p(:, :)            ! pressure, Pa, (nx, ny)
        real(dp), intent(in) :: x0, y0             ! centre of element (1, 1), m
        real(dp), intent(in) :: xi, eta, phi       ! creepages (1, 1, 1/m)
        real(dp), intent(in) :: mu, speed          ! friction coefficient, rolling speed (m/s)
        integer, intent(in) :: method, max_iter
        integer, intent(in) :: nblock, ninner     ! rows per FFT refresh ('fftgs'), passes per row
        real(dp), intent(in) :: tol
        real(dp), intent(inout) :: tx(:, :), ty(:, :)   ! warm start in, tractions (Pa) out
        integer, intent(out) :: status(:, :)       ! 0 exterior, 1 adhesion, 2 slip
        real(dp), intent(out) :: sx(:, :), sy(:, :)     ! slip velocity, m/s
        integer, intent(out) :: iters
        real(dp), intent(out) :: resid
        integer, intent(out) :: info

        integer :: nx, ny, i, j, k, i1, i2, j1, j2, ib2, nbx, nby, nblk, jb, je, ipass, it, st
        real(dp) :: dx, dy, kx, ky, c0x, c0y, g, lam, s0x, s0y, ntx, nty, dtx, dty, r2, n2, x, y
        real(dp), allocatable :: ux(:, :), uy(:, :), dux(:, :), duy(:, :)
        real(dp), allocatable :: axx(:, :), ayy(:, :), axy(:, :), wx(:, :), wy(:, :), bound(:, :)
        integer, allocatable :: trail(:, :)
        logical, allocatable :: inc(:, :)

        nx = w%nx
        ny = w%ny
        dx = w%dx
        dy = w%dy
        iters = 0
        resid = 0.0_dp
        status = ST_EXTERIOR
        sx = 0.0_dp
        sy = 0.0_dp
        info = 0
        if (w%nker < 4) then
            info = -1
            return
        end if
        if (method /= ROLL_GS .and. method /= ROLL_FFTGS) then
            info = -2
            return
        end if
        if (nblock < 1 .or. ninner < 1) then
            info = -3
            return
        end if

        allocate (inc(nx, ny), bound(nx, ny))
        bound = mu * p
        inc = p > 0.0_dp
        where (.not. inc)
            tx = 0.0_dp
            ty = 0.0_dp
        end where
        if (.not. any(inc)) then
            info = 2
            return
        end if
        ! bounding box of the contact area plus the upstream row
        i1 = nx; i2 = 1; j1 = ny; j2 = 1
        do j = 1, ny
            do i = 1, nx
                if (inc(i, j)) then
                    i1 = min(i1, i); i2 = max(i2, i)
                    j1 = min(j1, j); j2 = max(j2, j)
                end if
            end do
        end do
        if (i2 >= nx) then
            info = -4
            return
        end if
        ib2 = i2 + 1
        nbx = ib2 - i1
        nby = j2 - j1
        ! rows per FFT refresh: all for plain GS, nblock for the blocked form
        nblk = nby + 1
        if (method == ROLL_FFTGS) nblk = min(nblock, nby + 1)

        ! cumulative coefficients along x, acum(k, l) = sum_{m <= k} c(m, l),
        ! for the field of a traction step over a run of a row (see module doc)
        allocate (axx(-nbx - 1:nbx + 1, -nby:nby), ayy(-nbx - 1:nbx + 1, -nby:nby), &
                  axy(-nbx - 1:nbx + 1, -nby:nby))
        call cumulative(w%c(:, :, KXX), axx)
        call cumulative(w%c(:, :, KYY), ayy)
        call cumulative(w%c(:, :, KXY), axy)
        c0x = w%c(0, 0, KXX)
        c0y = w%c(0, 0, KYY)

        ! trailing end of the contiguous run of contact elements through (i, j)
        allocate (trail(nx, ny))
        trail = 0
        do j = j1, j2
            do i = i1, i2
                if (.not. inc(i, j)) cycle
                if (i > 1) then
                    if (inc(i - 1, j)) then
                        trail(i, j) = trail(i - 1, j)
                        cycle
                    end if
                end if
                trail(i, j) = i
            end do
        end do

        allocate (wx(nx, ny), wy(nx, ny))
        do j = 1, ny
            y = y0 + (j - 1) * dy
            do i = 1, nx
                x = x0 + (i - 1) * dx
                wx(i, j) = xi - phi * y
                wy(i, j) = eta + phi * x
            end do
        end do

        ! warm start: on the Coulomb disc
        do j = 1, ny
            do i = 1, nx
                if (.not. inc(i, j)) cycle
                g = hypot(tx(i, j), ty(i, j))
                if (g > bound(i, j)) then
                    tx(i, j) = tx(i, j) * bound(i, j) / g
                    ty(i, j) = ty(i, j) * bound(i, j) / g
                end if
            end do
        end do

        allocate (ux(nx, ny), uy(nx, ny), dux(i1:ib2, j1:j2), duy(i1:ib2, j1:j2))
        it = 0
        do
            ! exact field and the Jacobi residual on it (pivot of a single element)
            call conv_apply_pair(w%plan, KXX, KXY, KYY, tx, ty, ux, uy)
            kx = (c0x - w%c(1, 0, KXX)) / dx
            ky = (c0y - w%c(1, 0, KYY)) / dx
            r2 = 0.0_dp
            n2 = 0.0_dp
            do j = j1, j2
                do i = i1, i2
                    if (.not. inc(i, j)) cycle
                    s0x = wx(i, j) + (ux(i, j) - ux(i + 1, j)) / dx - kx * tx(i, j)
                    s0y = wy(i, j) + (uy(i, j) - uy(i + 1, j)) / dx - ky * ty(i, j)
                    call element_solve(s0x, s0y, kx, ky, bound(i, j), ntx, nty, st, lam)
                    r2 = r2 + (ntx - tx(i, j))**2 + (nty - ty(i, j))**2
                    n2 = n2 + ntx**2 + nty**2
                end do
            end do
            if (r2 /= r2 .or. n2 /= n2 .or. r2 > huge(1.0_dp)) then
                info = -5
                resid = huge(1.0_dp)
                exit
            end if
            if (n2 > 0.0_dp) then
                resid = sqrt(r2 / n2)
            else
                resid = merge(0.0_dp, 1.0_dp, r2 == 0.0_dp)
            end if
            if (resid <= tol) exit
            if (it >= max_iter) then
                info = 1
                exit
            end if
            it = it + 1

            ! one sweep: rows in blocks of nblk, the field refreshed by FFT
            ! before each block; within a row march from the leading edge
            do jb = j1, j2, nblk
                je = min(j2, jb + nblk - 1)
                if (jb > j1) call conv_apply_pair(w%plan, KXX, KXY, KYY, tx, ty, ux, uy)
                dux = 0.0_dp
                duy = 0.0_dp
                do j = jb, je
                    do ipass = 1, ninner
                        do i = i2, i1, -1
                            if (.not. inc(i, j)) cycle
                            k = trail(i, j)
                            kx = (c0x - w%c(i + 1 - k, 0, KXX)) / dx
                            ky = (c0y - w%c(i + 1 - k, 0, KYY)) / dx
                            s0x = wx(i, j) + (ux(i, j) + dux(i, j) - ux(i + 1, j) - dux(i + 1, j)) / dx &
                                  - kx * tx(i, j)
                            s0y = wy(i, j) + (uy(i, j) + duy(i, j) - uy(i + 1, j) - duy(i + 1, j)) / dx &
                                  - ky * ty(i, j)
                            call element_solve(s0x, s0y, kx, ky, bound(i, j), ntx, nty, st, lam)
                            dtx = ntx - tx(i, j)
                            dty = nty - ty(i, j)
                            if (dtx == 0.0_dp .and. dty == 0.0_dp) cycle
                            ! step update: the change carried to the run's downstream elements
                            tx(k:i, j) = tx(k:i, j) + dtx
                            ty(k:i, j) = ty(k:i, j) + dty
                            call scatter_step(k, i, j, je, dtx, dty)
                        end do
                    end do
                end do
            end do
        end do
        iters = it

        ! slip of the final tractions on the exact field
        if (info >= 0) then
            call conv_apply_pair(w%plan, KXX, KXY, KYY, tx, ty, ux, uy)
            do j = j1, j2
                do i = i1, i2
                    if (.not. inc(i, j)) cycle
                    s0x = wx(i, j) + (ux(i, j) - ux(i + 1, j)) / dx
                    s0y = wy(i, j) + (uy(i, j) - uy(i + 1, j)) / dx
                    call element_solve(s0x - kx * tx(i, j), s0y - ky * ty(i, j), kx, ky, &
                                       bound(i, j), ntx, nty, st, lam)
                    status(i, j) = st
                    if (st == ST_SLIP) then
                        sx(i, j) = speed * s0x
                        sy(i, j) = speed * s0y
                    end if
                end do
            end do
        end if

    contains

        !> acum(k, l) = sum over m <= k of c(m, l), offsets beyond the grid zero.
        subroutine cumulative(cfull, acum)
            real(dp), intent(in) :: cfull(0:, 0:)
            real(dp), intent(out) :: acum(-nbx - 1:, -nby:)
            integer :: a, b
            real(dp) :: run
            do b = -nby, nby
                run = 0.0_dp
                do a = -nbx - 1, nbx + 1
                    if (abs(a) < nx .and. abs(b) < ny) run = run + cfull(modulo(a, 2 * nx), modulo(b, 2 * ny))
                    acum(a, b) = run
                end do
            end do
        end subroutine cumulative

        !> du += field of the traction step (ax, ay) on elements k..i of row l,
        !> at rows l..je of the block (the rows still to be processed).
        subroutine scatter_step(k, i, l, je, ax, ay)
            integer, intent(in) :: k, i, l, je
            real(dp), intent(in) :: ax, ay
            integer :: a, b
            real(dp) :: fxx, fyy, fxy
            do b = l, je
                do a = i1, ib2
                    fxx = axx(a - k, b - l) - axx(a - i - 1, b - l)
                    fyy = ayy(a - k, b - l) - ayy(a - i - 1, b - l)
                    fxy = axy(a - k, b - l) - axy(a - i - 1, b - l)
                    dux(a, b) = dux(a, b) + fxx * ax + fxy * ay
                    duy(a, b) = duy(a, b) + fxy * ax + fyy * ay
                end do
            end do
        end subroutine scatter_step

    end subroutine rolling_steady

end module contact_rolling
