!> Steady-state rolling contact of quasi-identical bodies: the tangential
!> tractions for a given pressure, creepages and Coulomb friction (Kaiser,
!> eqs 24-29; Kalker 1990, ch. 2 and 5).
!>
!> Kinematics. The contact patch is fixed; material particles move through it
!> in -x at the rolling speed V, so the leading edge is at the largest x.
!> In units of V (creepage units) the slip of element I = (i, j) is
!>
!>   s_I = w_I + ((1 + th) u_i - (1 + 2 th) u_i+1 + th u_i+2) / dx,   (eq. 29)
!>   w_x = xi - phi y_j,   w_y = eta + phi x_i,
!>
!> the difference quotient being the material derivative of the displacement
!> difference u = A t over dt = dx / V, from the displacements of the
!> particle now and one and two time steps before (the upstream elements
!> i + 1, i + 2 of row j, taken from the full field u = A t, non-zero outside
!> the contact area too). With this sign convention a positive xi gives a
!> negative Fx (Fx = -G a b C11 xi in the linear limit).
!>
!> The three-point upwind stencil with weight th = THETA is the two-point
!> difference (ut_i - ut_i+1) / dx of the displacement extrapolated
!> downstream, ut_i = u_i + th (u_i - u_i+1) ~ u(x_i - th dx), so it takes
!> -du/dx at x_i + (1/2 - th) dx. th = 0 is Kalker's two-point difference
!> (first order: slip at x_i + dx/2, traction and bound at x_i), th = 1/2
!> the second-order backward difference (BDF2) at x_i. Against Carter's exact
!> 2-D profile (largest error in % of mu p0 over kappa = 0.05..0.99, 40
!> elements across, a 2-D prototype of this kernel): th = 0 7.4 % (stick zone
!> too long by about half an element), th = 1/2 4.9 % (too short, kappa -> 1),
!> th = 0.3..0.4 2.3-2.5 %. th = 1/3 is used: slip at x_i + dx/6.
!> In the solver ut = At t with At(d) = (1 + th) A(d) - th A(d + dx) replaces
!> u = A t (non-symmetric Toeplitz in x), and the two-point form is kept.
!>
!> Friction law per element in contact (p > 0), g = mu p:
!>   adhesion  s = 0,               |t| <= g                    (eq. 26)
!>   slip      t = -g s / |s|,      |t| = g                     (eq. 28)
!> The element's own traction enters its slip through the diagonal block
!> D = (At(0, 0) - At(+dx, 0)) / dx, which is diagonal (A_xy vanishes on the
!> x axis), so s = s0 + D t is affine in t and the element problem is solved
!> exactly on the Coulomb disc (element_solve): the adhesion traction
!> -D^-1 s0 if it lies in the disc, else the unique t = -g e with
!> s = lambda e, lambda > 0, found by a monotone Newton iteration on lambda.
!>
!> Iteration: row-implicit Gauss-Seidel. Point Gauss-Seidel on this system
!> diverges (spectral radius 115 for a 208-element Hertz patch): the element's
!> own pivot At(0) - At(+dx) is as large as its coupling to the downstream
!> neighbour, so fixing one element spoils the next. Sweeps therefore go
!> over the rows (lines along x, j ascending); within a contiguous run k..l
!> of a row the element updates use the in-row basis
!>   m_q = At_run^-1 C e_q,   (C e_q)_p = 1 for p <= q (downstream of q),
!> i.e. the tractions whose own-row (extrapolated) displacement ut is a unit
!> step ending at q:
!> they change the in-row slip at element q alone (and at the leading
!> element through the upstream displacement), so each run's linear part is
!> solved exactly in one pass, marching from the leading edge. The element
!> problem on the Coulomb disc is solved exactly with that pivot
!> (element_solve). The bases depend only on the run length (Toeplitz,
!> LAPACK LU inverse, cached per solve). The row-to-row coupling is
!> plain Gauss-Seidel: after each run its traction change updates the
!> displacements of the rows still to be processed in the current block;
!> before each block the whole field u = A t is refreshed by one FFT pair
!> product. Method 'gs' (1) uses one block (exact direct updates, O(N^2) per
!> sweep); 'fftgs' (2) blocks of nblock rows (O(N nblock nx) + one FFT per
!> block). Both accelerate the sweep map by Anderson mixing (depth AA_M), with a
!> safeguard that falls back to the plain sweep when the residual grows.
!> (With th = 1/3 the plain sweeps stagnate or diverge in partial slip, e.g.
!> residual 0.0065 after 500 sweeps on a 424-element Hertz patch with spin;
!> Anderson mixing converges in 19-40 sweeps in every case tried.)
!>
!> Convergence: the relative change of a Jacobi step on the exact field,
!>   r = || F(t) - t ||_2 / || F(t) ||_2,
!> F being the element solutions with a single-element pivot: zero exactly at
!> the solution. At exit every traction is put on its disc.
module contact_rolling
    use common_kinds, only: dp
    use common_lapack, only: dgetrf, dgetri
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, &
                             STAT_BAD_HANDLE, STAT_GRID_EDGE, STAT_NOT_FINITE, STAT_SINGULAR, STAT_LAPACK
    use contact_plans, only: workspace
    use contact_convolution, only: conv_apply_pair
    implicit none
    private
    public :: rolling_steady, element_solve
    public :: ROLL_GS, ROLL_FFTGS, ST_EXTERIOR, ST_ADHESION, ST_SLIP

    integer, parameter :: ROLL_GS = 1, ROLL_FFTGS = 2
    integer, parameter :: ST_EXTERIOR = 0, ST_ADHESION = 1, ST_SLIP = 2
    integer, parameter :: KXX = 2, KYY = 3, KXY = 4
    integer, parameter :: AA_M = 5   ! Anderson depth of method 'fftgs'
    !> Weight of the three-point upwind difference (module doc) and its stencil.
    real(dp), parameter :: THETA = 1.0_dp / 3.0_dp
    real(dp), parameter :: WU0 = 1.0_dp + THETA, WU1 = -(1.0_dp + 2.0_dp * THETA), WU2 = THETA

    !> In-row basis of a run of n elements (make_basis).
    type :: run_basis
        real(dp), allocatable :: mx(:, :), my(:, :), qx(:), qy(:)
    end type run_basis


contains

    !> Radial return of one element's traction onto the Coulomb disc
    !> |t| <= bound (the slip direction is kept).
    elemental subroutine project_on_disc(tx, ty, bound)
        real(dp), intent(inout) :: tx, ty
        real(dp), intent(in) :: bound
        real(dp) :: t
        t = hypot(tx, ty)
        if (t > bound) then
            tx = tx * bound / t
            ty = ty * bound / t
        end if
    end subroutine project_on_disc

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
    !> info: STAT_OK converged; STAT_NOT_CONVERGED after max_iter sweeps (resid
    !> holds the residual, the tractions the last iterate); STAT_NO_CONTACT no
    !> element with p > 0 (t = 0); STAT_BAD_HANDLE a workspace without the
    !> tangential kernels; STAT_BAD_ARGUMENT a bad method, or nblock or ninner < 1;
    !> STAT_GRID_EDGE the contact set reaches i = nx - 1 (fewer than two upstream
    !> elements); STAT_NOT_FINITE non-finite values (resid = huge); STAT_SINGULAR
    !> or STAT_LAPACK the LU inverse of a run basis failed.
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

        integer :: nx, ny, i, j, i1, i2, j1, j2, ib2, nbx, nby, nblk, jb, je, it, st
        real(dp) :: dx, dy, kx, ky, c0x, c0y, lam, s0x, s0y, ntx, nty, r2, n2, x, y
        real(dp), allocatable :: ux(:, :), uy(:, :), dux(:, :), duy(:, :)
        real(dp), allocatable :: axx(:, :), ayy(:, :), axy(:, :), wx(:, :), wy(:, :), bound(:, :)
        integer, allocatable :: trail(:, :)
        real(dp), allocatable :: tox(:), toy(:)
        type(run_basis), allocatable :: bases(:)
        integer :: stat, nc, naa, slot
        real(dp) :: rbest
        real(dp), allocatable :: xv(:), gv(:), fv(:), fold(:), gold(:), dfm(:, :), dgm(:, :)
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
        info = STAT_OK
        if (w%nker < 4) then
            info = STAT_BAD_HANDLE     ! a workspace made without the tangential kernels
            return
        end if
        if ((method /= ROLL_GS .and. method /= ROLL_FFTGS) .or. nblock < 1 .or. ninner < 1) then
            info = STAT_BAD_ARGUMENT
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
            info = STAT_NO_CONTACT
            return
        end if
        ! bounding box of the contact area plus the upstream row (ut there
        ! needs u one row further)
        i1 = nx; i2 = 1; j1 = ny; j2 = 1
        do j = 1, ny
            do i = 1, nx
                if (inc(i, j)) then
                    i1 = min(i1, i); i2 = max(i2, i)
                    j1 = min(j1, j); j2 = max(j2, j)
                end if
            end do
        end do
        if (i2 >= nx - 1) then
            info = STAT_GRID_EDGE
            return
        end if
        ib2 = i2 + 1
        nbx = ib2 - i1
        nby = j2 - j1
        ! rows per FFT refresh: all for plain GS, nblock for the blocked form
        nblk = nby + 1
        if (method == ROLL_FFTGS) nblk = min(nblock, nby + 1)

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

        ! coefficients At of ut = At t by offset (-nbx-1..nbx, -nby..nby),
        ! for the in-row bases and the cross-row updates
        allocate (axx(-nbx - 1:nbx + 1, -nby:nby), ayy(-nbx - 1:nbx + 1, -nby:nby), &
                  axy(-nbx - 1:nbx + 1, -nby:nby))
        call centred(w%c(:, :, KXX), axx)
        call centred(w%c(:, :, KYY), ayy)
        call centred(w%c(:, :, KXY), axy)
        ! in-row bases of every run length met (see module doc)
        allocate (bases(nbx))
        allocate (tox(nbx), toy(nbx))
        do j = j1, j2
            do i = i1, i2
                if (.not. inc(i, j)) cycle
                if (inc(i + 1, j)) cycle
                call make_basis(i - trail(i, j) + 1, stat)
                if (stat /= 0) then
                    info = merge(STAT_SINGULAR, STAT_LAPACK, stat > 0)
                    return
                end if
            end do
        end do
        c0x = w%c(0, 0, KXX)
        c0y = w%c(0, 0, KYY)

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
                call project_on_disc(tx(i, j), ty(i, j), bound(i, j))
            end do
        end do

        allocate (ux(nx, ny), uy(nx, ny), dux(i1:ib2, j1:j2), duy(i1:ib2, j1:j2))
        nc = count(inc)
        allocate (xv(2 * nc), gv(2 * nc), fv(2 * nc), fold(2 * nc), gold(2 * nc), &
                  dfm(2 * nc, AA_M), dgm(2 * nc, AA_M))
        xv = [pack(tx, inc), pack(ty, inc)]
        naa = 0
        slot = 0
        rbest = huge(1.0_dp)
        it = 0
        do
            ! exact field and the Jacobi residual on it (pivot of a single element)
            call conv_apply_pair(w%plan, KXX, KXY, KYY, tx, ty, ux, uy)
            kx = (WU0 * c0x + WU1 * w%c(1, 0, KXX) + WU2 * w%c(2, 0, KXX)) / dx
            ky = (WU0 * c0y + WU1 * w%c(1, 0, KYY) + WU2 * w%c(2, 0, KYY)) / dx
            r2 = 0.0_dp
            n2 = 0.0_dp
            do j = j1, j2
                do i = i1, i2
                    if (.not. inc(i, j)) cycle
                    s0x = wx(i, j) + updiff(ux, i, j) - kx * tx(i, j)
                    s0y = wy(i, j) + updiff(uy, i, j) - ky * ty(i, j)
                    call element_solve(s0x, s0y, kx, ky, bound(i, j), ntx, nty, st, lam)
                    r2 = r2 + (ntx - tx(i, j))**2 + (nty - ty(i, j))**2
                    n2 = n2 + ntx**2 + nty**2
                end do
            end do
            if (r2 /= r2 .or. n2 /= n2 .or. r2 > huge(1.0_dp)) then
                info = STAT_NOT_FINITE
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
                info = STAT_NOT_CONVERGED
                exit
            end if
            ! safeguard: an extrapolated iterate that raised the residual is
            ! replaced by the last plain sweep and the history dropped
            if (naa > 0 .and. resid > 2.0_dp * rbest) then
                call unpack_tractions(gold)
                xv = gold
                naa = 0
                slot = AA_M
                call conv_apply_pair(w%plan, KXX, KXY, KYY, tx, ty, ux, uy)
            end if
            rbest = min(rbest, resid)
            it = it + 1

            ! one sweep: rows in blocks of nblk, the field refreshed by FFT
            ! before each block; within a row march from the leading edge
            do jb = j1, j2, nblk
                je = min(j2, jb + nblk - 1)
                if (jb > j1) call conv_apply_pair(w%plan, KXX, KXY, KYY, tx, ty, ux, uy)
                dux = 0.0_dp
                duy = 0.0_dp
                do j = jb, je
                    ! runs of the row, leading (largest x) first
                    do i = i2, i1, -1
                        if (.not. inc(i, j)) cycle
                        if (inc(i + 1, j)) cycle
                        call solve_run(trail(i, j), i, j, je)
                    end do
                end do
            end do
            call anderson_step()
        end do
        iters = it

        ! the in-row updates move other elements of a run too: put every
        ! traction on its disc (a change of the order of the residual)
        do j = j1, j2
            do i = i1, i2
                if (.not. inc(i, j)) cycle
                call project_on_disc(tx(i, j), ty(i, j), bound(i, j))
            end do
        end do

        ! slip of the final tractions on the exact field
        if (info /= STAT_NOT_FINITE) then
            call conv_apply_pair(w%plan, KXX, KXY, KYY, tx, ty, ux, uy)
            do j = j1, j2
                do i = i1, i2
                    if (.not. inc(i, j)) cycle
                    s0x = wx(i, j) + updiff(ux, i, j)
                    s0y = wy(i, j) + updiff(uy, i, j)
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

        !> The upwind difference quotient of the field u at element (i, j):
        !> (ut_i - ut_i+1) / dx.
        pure real(dp) function updiff(u, i, j)
            real(dp), intent(in) :: u(:, :)
            integer, intent(in) :: i, j
            updiff = (WU0 * u(i, j) + WU1 * u(i + 1, j) + WU2 * u(i + 2, j)) / dx
        end function updiff

        !> At(offset) = (1 + th) c(offset) - th c(offset + (1, 0)) for offsets
        !> (-nbx-1..nbx, -nby..nby), c zero beyond the grid (cc(nbx + 1, :) unused).
        subroutine centred(cfull, cc)
            real(dp), intent(in) :: cfull(0:, 0:)
            real(dp), intent(out) :: cc(-nbx - 1:, -nby:)
            integer :: a, b
            cc = 0.0_dp
            do b = -nby, nby
                do a = -nbx - 1, nbx + 1
                    if (abs(a) < nx .and. abs(b) < ny) cc(a, b) = cfull(modulo(a, 2 * nx), modulo(b, 2 * ny))
                end do
            end do
            do a = -nbx - 1, nbx
                cc(a, :) = (1.0_dp + THETA) * cc(a, :) - THETA * cc(a + 1, :)
            end do
            cc(nbx + 1, :) = 0.0_dp
        end subroutine centred

        !> The in-row basis of a run of n elements, per component:
        !> m(:, q) = At_n^-1 C e_q (the tractions whose own-row displacement ut
        !> is 1 on elements 0..q of the run and 0 upstream of q), and
        !> ql(q) = the ut they give at the element upstream of the run.
        subroutine make_basis(n, stat)
            integer, intent(in) :: n
            integer, intent(out) :: stat
            integer :: comp, a, b
            integer, allocatable :: ipiv(:)
            real(dp), allocatable :: m(:, :), work(:)
            stat = 0
            if (allocated(bases(n)%mx)) return
            allocate (bases(n)%mx(n, n), bases(n)%my(n, n), bases(n)%qx(n), bases(n)%qy(n))
            allocate (m(n, n), ipiv(n), work(64 * n))
            do comp = 1, 2
                do b = 1, n
                    do a = 1, n
                        if (comp == 1) then
                            m(a, b) = axx(a - b, 0)
                        else
                            m(a, b) = ayy(a - b, 0)
                        end if
                    end do
                end do
                call dgetrf(n, n, m, n, ipiv, stat)
                if (stat /= 0) return
                call dgetri(n, m, n, ipiv, work, size(work), stat)
                if (stat /= 0) return
                ! C e_q = ones on elements 1..q (downstream of and at q): cumulative columns
                do b = 2, n
                    m(:, b) = m(:, b) + m(:, b - 1)
                end do
                if (comp == 1) then
                    bases(n)%mx = m
                    do b = 1, n
                        bases(n)%qx(b) = sum([(axx(n + 1 - a, 0) * m(a, b), a = 1, n)])
                    end do
                else
                    bases(n)%my = m
                    do b = 1, n
                        bases(n)%qy(b) = sum([(ayy(n + 1 - a, 0) * m(a, b), a = 1, n)])
                    end do
                end if
            end do
        end subroutine make_basis

        !> Anderson acceleration (depth AA_M) of the sweep map x -> G(x):
        !> x+ = G(x) - dG gamma, gamma minimising |f - dF gamma|, f = G(x) - x;
        !> then every traction back on its disc.
        subroutine anderson_step()
            real(dp) :: h(AA_M, AA_M), rhs(AA_M), gam(AA_M), reg
            integer :: mk, a, b, stat2
            gv = [pack(tx, inc), pack(ty, inc)]
            fv = gv - xv
            if (naa > 0 .or. slot > 0) then
                slot = mod(slot, AA_M) + 1
                dfm(:, slot) = fv - fold
                dgm(:, slot) = gv - gold
                naa = min(naa + 1, AA_M)
            else
                slot = 0
                naa = 0
            end if
            fold = fv
            gold = gv
            if (slot == 0) slot = AA_M   ! first call: the next difference goes to slot 1
            mk = naa
            xv = gv
            if (mk > 0) then
                do b = 1, mk
                    do a = 1, mk
                        h(a, b) = dot_product(dfm(:, a), dfm(:, b))
                    end do
                    rhs(b) = dot_product(dfm(:, b), fv)
                end do
                reg = 1.0e-10_dp * maxval([(h(a, a), a = 1, mk)])
                do a = 1, mk
                    h(a, a) = h(a, a) + reg
                end do
                gam(1:mk) = rhs(1:mk)
                ! tiny SPD system solved here: a LAPACK call would wake
                ! OpenBLAS threads every sweep
                call small_cholesky_solve(mk, h, gam, stat2)
                if (stat2 == 0 .and. all(gam(1:mk) == gam(1:mk))) then
                    do a = 1, mk
                        xv = xv - gam(a) * dgm(:, a)
                    end do
                end if
            end if
            call unpack_tractions(xv)
        end subroutine anderson_step

        !> Solve h x = b in place (b -> x) for a small SPD h (Cholesky, lower).
        pure subroutine small_cholesky_solve(m, h, b, stat)
            integer, intent(in) :: m
            real(dp), intent(inout) :: h(:, :), b(:)
            integer, intent(out) :: stat
            integer :: a, c
            stat = 0
            do c = 1, m
                h(c, c) = h(c, c) - sum(h(c, 1:c - 1)**2)
                if (h(c, c) <= 0.0_dp) then
                    stat = c
                    return
                end if
                h(c, c) = sqrt(h(c, c))
                do a = c + 1, m
                    h(a, c) = (h(a, c) - sum(h(a, 1:c - 1) * h(c, 1:c - 1))) / h(c, c)
                end do
            end do
            do a = 1, m
                b(a) = (b(a) - sum(h(a, 1:a - 1) * b(1:a - 1))) / h(a, a)
            end do
            do a = m, 1, -1
                b(a) = (b(a) - sum(h(a + 1:m, a) * b(a + 1:m))) / h(a, a)
            end do
        end subroutine small_cholesky_solve

        !> tx, ty from a packed vector, each traction put on its disc.
        subroutine unpack_tractions(v)
            real(dp), intent(in) :: v(:)
            integer :: a, b
            tx = unpack(v(1:nc), inc, 0.0_dp)
            ty = unpack(v(nc + 1:2 * nc), inc, 0.0_dp)
            do b = j1, j2
                do a = i1, i2
                    if (.not. inc(a, b)) cycle
                    call project_on_disc(tx(a, b), ty(a, b), bound(a, b))
                end do
            end do
        end subroutine unpack_tractions

        !> ninner passes over the run k..l of row jr with exact in-row updates,
        !> then the run's traction change carried to the rows jr..je of the block.
        subroutine solve_run(k, l, jr, je)
            integer, intent(in) :: k, l, jr, je
            integer :: n, q, ii, pass, a, b, st2
            real(dp) :: scx, scy, kxx, kyy, s0xx, s0yy, nx2, ny2, lm, dlx, dly, fx, fy
            n = l - k + 1
            associate (mx => bases(n)%mx, my => bases(n)%my, qx => bases(n)%qx, qy => bases(n)%qy)
                tox(1:n) = tx(k:l, jr)
                toy(1:n) = ty(k:l, jr)
                do pass = 1, ninner
                    do q = n, 1, -1
                        ii = k + q - 1
                        scx = wx(ii, jr) + updiff(ux, ii, jr) + (dux(ii, jr) - dux(ii + 1, jr)) / dx
                        scy = wy(ii, jr) + updiff(uy, ii, jr) + (duy(ii, jr) - duy(ii + 1, jr)) / dx
                        if (q == n) then
                            kxx = (1.0_dp - qx(q)) / (dx * mx(q, q))
                            kyy = (1.0_dp - qy(q)) / (dx * my(q, q))
                        else
                            kxx = 1.0_dp / (dx * mx(q, q))
                            kyy = 1.0_dp / (dx * my(q, q))
                        end if
                        s0xx = scx - kxx * tx(ii, jr)
                        s0yy = scy - kyy * ty(ii, jr)
                        call element_solve(s0xx, s0yy, kxx, kyy, bound(ii, jr), nx2, ny2, st2, lm)
                        dlx = (nx2 - tx(ii, jr)) / mx(q, q)
                        dly = (ny2 - ty(ii, jr)) / my(q, q)
                        if (dlx == 0.0_dp .and. dly == 0.0_dp) cycle
                        tx(k:l, jr) = tx(k:l, jr) + mx(:, q) * dlx
                        ty(k:l, jr) = ty(k:l, jr) + my(:, q) * dly
                        tx(ii, jr) = nx2
                        ty(ii, jr) = ny2
                        dux(k:ii, jr) = dux(k:ii, jr) + dlx
                        duy(k:ii, jr) = duy(k:ii, jr) + dly
                        dux(l + 1, jr) = dux(l + 1, jr) + qx(q) * dlx
                        duy(l + 1, jr) = duy(l + 1, jr) + qy(q) * dly
                    end do
                end do
            end associate
            ! the run's change seen by the rest of the block (its own row outside
            ! k..l+1 included; the xy coupling within a row vanishes)
            tox(1:n) = tx(k:l, jr) - tox(1:n)
            toy(1:n) = ty(k:l, jr) - toy(1:n)
            do b = jr, je
                do q = 1, n
                    fx = tox(q)
                    fy = toy(q)
                    if (fx == 0.0_dp .and. fy == 0.0_dp) cycle
                    ii = k + q - 1
                    if (b == jr) then
                        do a = i1, k - 1
                            dux(a, b) = dux(a, b) + axx(a - ii, 0) * fx
                            duy(a, b) = duy(a, b) + ayy(a - ii, 0) * fy
                        end do
                        do a = l + 2, ib2
                            dux(a, b) = dux(a, b) + axx(a - ii, 0) * fx
                            duy(a, b) = duy(a, b) + ayy(a - ii, 0) * fy
                        end do
                    else
                        do a = i1, ib2
                            dux(a, b) = dux(a, b) + axx(a - ii, b - jr) * fx + axy(a - ii, b - jr) * fy
                            duy(a, b) = duy(a, b) + axy(a - ii, b - jr) * fx + ayy(a - ii, b - jr) * fy
                        end do
                    end if
                end do
            end do
        end subroutine solve_run

    end subroutine rolling_steady

end module contact_rolling
