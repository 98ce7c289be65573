!> Steady rolling on a small contact set (at most SOP_MAX elements, the 11 x 11 creep case):
!> contact_rolling's row-implicit Gauss-Seidel with Anderson mixing on packed vectors,
!> the field read through the dense slip operator, finished by Newton's method once the
!> elements' statuses have settled (settled_newton). Same equations as the grid path
!> (contact_rolling::iterate_grid) and the same stopping test: the solutions agree to the
!> solver's tolerance (the small path's is the closer to the exact one).
!> Implements Kaiser eqs 26-29 on the packed contact set (the slip of eq. 29 through the dense slip operator).
module contact_rolling_small
    use common_kinds, only: dp, sp
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NOT_FINITE
    use common_dense, only: lu_factor_small, lu_solve_small
    use common_anderson, only: anderson_state, anderson_init, anderson_step, anderson_restart
    use contact_rolling_patch, only: ST_SLIP, AA_M, SOP_MAX, rolling_patch, project_on_disc, &
                                     residual_ok, pack_tractions
    use contact_rolling_element, only: element_solve_r, element_any, element_batch
    implicit none
    private
    public :: iterate_small, small_runs

    !> settled_newton: tried when the Jacobi residual is below NEWTON_RESID and the statuses
    !> are those of the previous iterate, at most NEWTON_TRIES times per solve, with at most
    !> NEWTON_STEPS steps on one Jacobian, each to cut the residual by NEWTON_RATE at least.
    real(dp), parameter :: NEWTON_RESID = 0.1_dp, NEWTON_RATE = 0.25_dp
    integer, parameter :: NEWTON_TRIES = 2, NEWTON_STEPS = 5

contains

    !> rolling_steady's iteration on a small contact set (pa%sop made): the same
    !> row-implicit sweeps, Anderson mixing and residual as iterate_grid, on the
    !> packed tractions v = [tx(inc), ty(inc)] and their slips g = S v (the dense slip
    !> operator): no grid arrays inside the loop, the sweep's updates to the rows still
    !> to come as columns of S (sweep_small). Agrees with iterate_grid to rounding.
    subroutine iterate_small(pa, ninner, tol, max_iter, speed, tx, ty, status, sx, sy, iters, resid, info, nm)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: ninner, max_iter
        real(dp), intent(in) :: tol, speed
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        integer, intent(inout) :: status(:, :)
        real(dp), intent(inout) :: sx(:, :), sy(:, :)
        integer, intent(out) :: iters, info, nm
        real(dp), intent(out) :: resid
        type(anderson_state) :: aa
        ! fixed sizes (nc <= SOP_MAX): on the stack, where gfortran puts automatic arrays
        ! on the heap (a malloc and free per call, as much as a small problem's arithmetic)
        real(dp) :: vv(2 * SOP_MAX), gg(2 * SOP_MAX), nt(2 * SOP_MAX), r2, n2, rbest
        logical :: slip(SOP_MAX), slip_old(SOP_MAX), have_g, ok
        integer :: it, k, n, ntry, nstep

        info = STAT_OK
        resid = 0.0_dp
        nm = 0
        n = pa%nc
        associate (v => vv(1:2 * n), g => gg(1:2 * n))
        call pack_tractions(pa, tx, ty, v)
        call anderson_init(aa, v, AA_M)
        rbest = huge(1.0_dp)
        it = 0
        ntry = 0
        have_g = .false.
        slip_old(1:n) = .false.
        do
            if (.not. have_g) then
                call sop_apply(pa, v, g)
                call jacobi_small(pa, g, v, r2, n2, nt, slip)
            end if
            have_g = .false.
            if (.not. residual_ok(r2, n2, resid, info)) exit
            if (resid <= tol) exit
            if (it >= max_iter) then
                info = STAT_NOT_CONVERGED
                exit
            end if
            ! the statuses settled: Newton's method on the rest (the slip directions and the
            ! adhesion tractions), where a sweep would only shrink the error by a factor
            if (it > 0 .and. ntry < NEWTON_TRIES .and. .not. pa%varlaw .and. resid <= NEWTON_RESID) then
                if (all(slip(1:n) .eqv. slip_old(1:n))) then
                    ntry = ntry + 1
                    call settled_newton(pa, tol, resid, slip(1:n), nt(1:2 * n), v, g, r2, n2, nstep, ok)
                    it = it + nstep
                    if (ok) then
                        have_g = .true.   ! v, g, r2, n2 of the converged iterate
                        cycle
                    end if
                end if
            end if
            slip_old(1:n) = slip(1:n)
            if (aa%naa > 0 .and. resid > 2.0_dp * rbest) then
                call anderson_restart(aa)
                v = aa%x
                call project_packed(pa, v)
                call sop_apply(pa, v, g)
            end if
            rbest = min(rbest, resid)
            it = it + 1
            call sweep_small(pa, ninner, v, g)
            call anderson_step(aa, v)
            v = aa%x
            call project_packed(pa, v)
        end do
        iters = it
        call project_packed(pa, v)
        do k = 1, n
            tx(pa%ic(k), pa%jc(k)) = v(k)
            ty(pa%ic(k), pa%jc(k)) = v(n + k)
        end do
        if (info /= STAT_NOT_FINITE) then
            call sop_apply(pa, v, g)
            call final_small(pa, g, v, speed, status, sx, sy, nm)
        end if
        end associate
    end subroutine iterate_small

    !> g = S v: the slips of the packed tractions v by the dense slip operator.
    pure subroutine sop_apply(pa, v, g)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: v(:)
        real(dp), intent(out) :: g(:)
        integer :: k, m
        ! four columns per pass over g (g is loaded and stored a quarter as often)
        m = 2 * pa%nc
        g = 0.0_dp
        do k = 1, m - 3, 4
            if (v(k) == 0.0_dp .and. v(k + 1) == 0.0_dp .and. v(k + 2) == 0.0_dp .and. v(k + 3) == 0.0_dp) cycle
            g = g + v(k) * pa%sop(:, k) + v(k + 1) * pa%sop(:, k + 1) + v(k + 2) * pa%sop(:, k + 2) &
                + v(k + 3) * pa%sop(:, k + 3)
        end do
        do k = 4 * (m / 4) + 1, m
            if (v(k) /= 0.0_dp) g = g + v(k) * pa%sop(:, k)
        end do
    end subroutine sop_apply

    !> Every packed traction put on its Coulomb disc.
    pure subroutine project_packed(pa, v)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(inout) :: v(:)
        integer :: k
        do k = 1, pa%nc
            call project_on_disc(v(k), v(pa%nc + k), pa%bc(k))
        end do
    end subroutine project_packed

    !> jacobi_residual on packed vectors (g = S v, iterate_small); Coulomb's element
    !> problems all at once (element_batch). nt: the element solutions (packed), slip: their
    !> statuses are ST_SLIP.
    pure subroutine jacobi_small(pa, g, v, r2, n2, nt, slip)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: g(:), v(:)
        real(dp), intent(out) :: r2, n2
        real(dp), intent(inout) :: nt(:)
        logical, intent(inout) :: slip(:)
        real(dp) :: scx, scy, lam
        real(dp), dimension(SOP_MAX) :: ntx, nty, s0x, s0y   ! nc <= SOP_MAX (iterate_small)
        integer :: k, n, st
        n = pa%nc
        do k = 1, n
            s0x(k) = pa%wxc(k) + g(k)
            s0y(k) = pa%wyc(k) + g(n + k)
        end do
        if (pa%varlaw) then
            do k = 1, n
                scx = s0x(k)
                scy = s0y(k)
                call element_any(pa, scx - pa%kx * v(k), scy - pa%ky * v(n + k), pa%kx, pa%ky, pa%bc(k), &
                                 scx, scy, ntx(k), nty(k), st, lam)
                slip(k) = st == ST_SLIP
            end do
        else
            s0x(1:n) = s0x(1:n) - pa%kx * v(1:n)
            s0y(1:n) = s0y(1:n) - pa%ky * v(n + 1:2 * n)
            call element_batch(s0x(1:n), s0y(1:n), pa%kx, pa%ky, pa%bc, ntx(1:n), nty(1:n), slip(1:n))
        end if
        nt(1:n) = ntx(1:n)
        nt(n + 1:2 * n) = nty(1:n)
        r2 = 0.0_dp
        n2 = 0.0_dp
        do k = 1, n
            r2 = r2 + (ntx(k) - v(k))**2 + (nty(k) - v(n + k))**2
            n2 = n2 + ntx(k)**2 + nty(k)**2
        end do
    end subroutine jacobi_small

    !> Newton's method on the small path once the elements' statuses have settled (Kaiser
    !> eqs 26, 28 with the statuses fixed): unknowns the tractions of the elements in adhesion
    !> and the direction angle of those in slip (t = g e, |e| = 1), equations s = 0 in
    !> adhesion and s x e = 0 in slip (s = w + S t, eq. 29 through the slip operator). Its
    !> Jacobian is formed once, at the element solutions nt of the current iterate, and its LU
    !> factor (lu_factor_small, single precision) serves every step (the chord method: each
    !> step cuts the error by a factor of the order of the distance at which the Jacobian was
    !> formed, while the residuals are formed in double precision). A
    !> step is judged by the solver's own test, the Jacobi residual (jacobi_small) with the
    !> same statuses. ok: converged (resid <= tol): v, g = S v, r2, n2 those of the result;
    !> else (statuses changed, a step cut the residual by less than NEWTON_RATE, a singular
    !> Jacobian) v and g are left as they were. nstep: steps made.
    subroutine settled_newton(pa, tol, resid0, slip, nt, v, g, r2, n2, nstep, ok)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: tol, resid0
        logical, intent(in) :: slip(:)
        real(dp), intent(in) :: nt(:)
        real(dp), intent(inout) :: v(:), g(:), r2, n2
        integer, intent(out) :: nstep
        logical, intent(out) :: ok
        real(sp), allocatable :: jlu(:, :)
        real(sp) :: ds(2 * SOP_MAX)
        real(dp), dimension(2 * SOP_MAX) :: t, gt, ntt, d
        real(dp), dimension(SOP_MAX) :: ex, ey
        logical :: slt(SOP_MAX)
        integer :: col(SOP_MAX), piv(2 * SOP_MAX), n, m, k, c, step, info
        real(dp) :: en, sx, sy, r2t, n2t, rt, rprev
        n = pa%nc
        nstep = 0
        ok = .false.
        m = 0
        do k = 1, n
            col(k) = m + 1
            m = m + merge(1, 2, slip(k))
        end do
        ! the start: the element solutions, the slipping ones' directions exactly unit
        t(1:2 * n) = nt
        do k = 1, n
            if (.not. slip(k)) cycle
            en = sqrt(t(k)**2 + t(n + k)**2)
            if (.not. (en > 0.0_dp)) return
            ex(k) = t(k) / en
            ey(k) = t(n + k) / en
            t(k) = pa%bc(k) * ex(k)
            t(n + k) = pa%bc(k) * ey(k)
        end do
        call sop_apply(pa, t(1:2 * n), gt(1:2 * n))
        ! the Jacobian and its factor in single precision: the chord steps need an
        ! approximate J^-1 only (its relative error, ~1e-7 cond(J), adds that much to each
        ! step's contraction factor), and the LU takes half the instructions
        allocate (jlu(m, m))
        call newton_jacobian(pa, slip, col, t(1:2 * n), gt(1:2 * n), ex, ey, jlu)
        call lu_factor_small(jlu, piv(1:m), info)
        if (info /= STAT_OK) return
        rprev = resid0
        do step = 1, NEWTON_STEPS
            nstep = step
            do k = 1, n   ! -F: the slips in adhesion, s x e in slip
                sx = pa%wxc(k) + gt(k)
                sy = pa%wyc(k) + gt(n + k)
                c = col(k)
                if (slip(k)) then
                    d(c) = sy * ex(k) - sx * ey(k)
                else
                    d(c) = -sx
                    d(c + 1) = -sy
                end if
            end do
            ds(1:m) = real(d(1:m), sp)
            call lu_solve_small(jlu, piv(1:m), ds(1:m))
            d(1:m) = real(ds(1:m), dp)
            do k = 1, n
                c = col(k)
                if (slip(k)) then
                    ! e turned by the angle d(c), back on the unit circle (a second-order
                    ! retraction: Newton's quadratic convergence is kept)
                    en = 1.0_dp / sqrt(1.0_dp + d(c)**2)
                    sx = (ex(k) - d(c) * ey(k)) * en
                    ey(k) = (ey(k) + d(c) * ex(k)) * en
                    ex(k) = sx
                    t(k) = pa%bc(k) * ex(k)
                    t(n + k) = pa%bc(k) * ey(k)
                else
                    t(k) = t(k) + d(c)
                    t(n + k) = t(n + k) + d(c + 1)
                end if
            end do
            call sop_apply(pa, t(1:2 * n), gt(1:2 * n))
            call jacobi_small(pa, gt(1:2 * n), t(1:2 * n), r2t, n2t, ntt(1:2 * n), slt(1:n))
            if (r2t /= r2t .or. n2t /= n2t .or. r2t > huge(1.0_dp) .or. .not. (n2t > 0.0_dp)) return
            if (any(slt(1:n) .neqv. slip)) return
            rt = sqrt(r2t / n2t)
            if (rt <= tol) then
                v = t(1:2 * n)
                g = gt(1:2 * n)
                r2 = r2t
                n2 = n2t
                ok = .true.
                return
            end if
            if (rt > NEWTON_RATE * rprev) return
            rprev = rt
        end do
    end subroutine settled_newton

    !> settled_newton's Jacobian at the tractions t (slip directions e, slips w + gt): the
    !> column of an unknown is S's response to it (S e_x, S e_y for an adhesion traction,
    !> S dt/dtheta = S g (-e_y, e_x) for a slip angle), read by the equations' rows (s_x, s_y
    !> in adhesion, s x e in slip, whose own angle adds s . e).
    pure subroutine newton_jacobian(pa, slip, col, t, gt, ex, ey, jac)
        type(rolling_patch), intent(in) :: pa
        logical, intent(in) :: slip(:)
        integer, intent(in) :: col(:)
        real(dp), intent(in) :: t(:), gt(:), ex(:), ey(:)
        real(sp), intent(out) :: jac(:, :)    ! (m, m), single precision (settled_newton)
        real(dp) :: cv(2 * SOP_MAX)
        integer :: n, j, cc
        n = pa%nc
        do j = 1, n
            cc = col(j)
            if (slip(j)) then
                cv(1:2 * n) = pa%sop(:, j) * (-t(n + j)) + pa%sop(:, n + j) * t(j)
                call jacobian_rows(n, slip, col, ex, ey, cv(1:2 * n), jac(:, cc))
                jac(cc, cc) = real(cv(j) * ey(j) - cv(n + j) * ex(j) + (pa%wxc(j) + gt(j)) * ex(j) &
                                   + (pa%wyc(j) + gt(n + j)) * ey(j), sp)
            else
                call jacobian_rows(n, slip, col, ex, ey, pa%sop(:, j), jac(:, cc))
                call jacobian_rows(n, slip, col, ex, ey, pa%sop(:, n + j), jac(:, cc + 1))
            end if
        end do
    end subroutine newton_jacobian

    !> One column of newton_jacobian from S's response cv (2 n) to its unknown: the slips
    !> of the elements in adhesion, s x e of those in slip.
    pure subroutine jacobian_rows(n, slip, col, ex, ey, cv, jcol)
        integer, intent(in) :: n, col(:)
        logical, intent(in) :: slip(:)
        real(dp), intent(in) :: ex(:), ey(:), cv(:)
        real(sp), intent(out) :: jcol(:)
        integer :: k
        do k = 1, n
            if (slip(k)) then
                jcol(col(k)) = real(cv(k) * ey(k) - cv(n + k) * ex(k), sp)
            else
                jcol(col(k)) = real(cv(k), sp)
                jcol(col(k) + 1) = real(cv(n + k), sp)
            end if
        end do
    end subroutine jacobian_rows

    !> final_slip on packed vectors (g = S v): status and slip velocity (m/s) on the grid.
    subroutine final_small(pa, g, v, speed, status, sx, sy, nmulti)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: g(:), v(:), speed
        integer, intent(inout) :: status(:, :)
        real(dp), intent(inout) :: sx(:, :), sy(:, :)
        integer, intent(out) :: nmulti
        real(dp) :: scx, scy, ntx, nty, lam, rkx, rky
        integer :: k, n, i, j, st, nsol
        n = pa%nc
        nmulti = 0
        rkx = 1.0_dp / pa%kx
        rky = 1.0_dp / pa%ky
        do k = 1, n
            i = pa%ic(k)
            j = pa%jc(k)
            scx = pa%wxc(k) + g(k)
            scy = pa%wyc(k) + g(n + k)
            if (pa%varlaw) then
                call element_any(pa, scx - pa%kx * v(k), scy - pa%ky * v(n + k), pa%kx, pa%ky, pa%bc(k), &
                                 scx, scy, ntx, nty, st, lam, nsol_out=nsol)
                if (nsol > 1) nmulti = nmulti + 1
            else
                call element_solve_r(scx - pa%kx * v(k), scy - pa%ky * v(n + k), pa%kx, pa%ky, rkx, rky, &
                                     pa%bc(k), ntx, nty, st, lam)
            end if
            status(i, j) = st
            if (st == ST_SLIP) then
                sx(i, j) = speed * scx
                sy(i, j) = speed * scy
            end if
        end do
    end subroutine final_small

    !> One row-implicit sweep on packed vectors (sweep, on a small contact set): the
    !> runs in sweep order, each solved by run_small on the slips g = S v of the sweep's
    !> start plus dg, the slip changes of the runs solved before it in this sweep, to
    !> which its own traction change is then added as columns of S (the elements from
    !> pa%rrow on: every element a later run reads). v: the tractions, updated.
    pure subroutine sweep_small(pa, ninner, v, g)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: ninner
        real(dp), intent(inout) :: v(:)
        real(dp), intent(in) :: g(:)
        real(dp) :: dg(2 * SOP_MAX), tox(SOP_MAX), toy(SOP_MAX), fx, fy   ! nc <= SOP_MAX
        integer :: r, n, p0, nr, r0, q, kq
        n = pa%nc
        dg(1:2 * n) = 0.0_dp
        do r = 1, pa%nrun
            p0 = pa%rp0(r)
            nr = pa%rn(r)
            r0 = pa%rrow(r)
            tox(1:nr) = v(p0:p0 + nr - 1)
            toy(1:nr) = v(n + p0:n + p0 + nr - 1)
            call run_small(pa, p0, nr, ninner, v, g, dg)
            do q = 1, nr
                kq = p0 + q - 1
                fx = v(kq) - tox(q)
                fy = v(n + kq) - toy(q)
                if ((fx == 0.0_dp .and. fy == 0.0_dp) .or. r0 > n) cycle
                dg(r0:n) = dg(r0:n) + pa%sop(r0:n, kq) * fx + pa%sop(r0:n, n + kq) * fy
                dg(n + r0:2 * n) = dg(n + r0:2 * n) + pa%sop(n + r0:2 * n, kq) * fx &
                                   + pa%sop(n + r0:2 * n, n + kq) * fy
            end do
        end do
    end subroutine sweep_small

    !> run_passes on packed vectors: ninner passes over the run of nr elements from
    !> packed position p0, the slip of element q being g + dg (the rest of the contact
    !> set) plus the run's own in-row displacement change du (its elements and the one
    !> upstream, du(nr + 1)).
    pure subroutine run_small(pa, p0, nr, ninner, v, g, dg)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: p0, nr, ninner
        real(dp), intent(inout) :: v(:)
        real(dp), intent(in) :: g(:), dg(:)
        real(dp) :: dux(SOP_MAX + 1), duy(SOP_MAX + 1)   ! nr <= nc <= SOP_MAX
        real(dp) :: scx, scy, pivx, pivy, s0x, s0y, ntx, nty, lam, dlx, dly, dx, rdx
        integer :: n, q, pk, pass, st, pe
        n = pa%nc
        dx = pa%dx
        pe = p0 + nr - 1
        dux(1:nr + 1) = 0.0_dp
        duy(1:nr + 1) = 0.0_dp
        rdx = 1.0_dp / dx
        associate (bs => pa%bases(nr), mx => pa%bases(nr)%mx, my => pa%bases(nr)%my, qx => pa%bases(nr)%qx, &
                   qy => pa%bases(nr)%qy)
            do pass = 1, ninner
                do q = nr, 1, -1
                    pk = p0 + q - 1
                    scx = pa%wxc(pk) + g(pk) + dg(pk) + (dux(q) - dux(q + 1)) * rdx
                    scy = pa%wyc(pk) + g(n + pk) + dg(n + pk) + (duy(q) - duy(q + 1)) * rdx
                    pivx = bs%px(q)
                    pivy = bs%py(q)
                    s0x = scx - pivx * v(pk)
                    s0y = scy - pivy * v(n + pk)
                    if (pa%varlaw) then
                        call element_any(pa, s0x, s0y, pivx, pivy, pa%bc(pk), scx, scy, ntx, nty, st, lam)
                    else
                        call element_solve_r(s0x, s0y, pivx, pivy, bs%rpx(q), bs%rpy(q), pa%bc(pk), ntx, nty, st, lam)
                    end if
                    dlx = (ntx - v(pk)) * bs%rmx(q)
                    dly = (nty - v(n + pk)) * bs%rmy(q)
                    if (dlx == 0.0_dp .and. dly == 0.0_dp) cycle
                    v(p0:pe) = v(p0:pe) + mx(:, q) * dlx
                    v(n + p0:n + pe) = v(n + p0:n + pe) + my(:, q) * dly
                    v(pk) = ntx
                    v(n + pk) = nty
                    dux(1:q) = dux(1:q) + dlx
                    duy(1:q) = duy(1:q) + dly
                    dux(nr + 1) = dux(nr + 1) + qx(q) * dlx
                    duy(nr + 1) = duy(nr + 1) + qy(q) * dly
                end do
            end do
        end associate
    end subroutine run_small

    !> The small path's runs in sweep order (rows ascending, within a row from the
    !> leading edge), as packed positions, and the packed bound (patch_setup).
    subroutine small_runs(pa)
        type(rolling_patch), intent(inout) :: pa
        integer, allocatable :: pos(:, :)
        integer :: i, j, k
        allocate (pos(pa%nx, pa%ny), pa%bc(pa%nc), pa%wxc(pa%nc), pa%wyc(pa%nc))
        pos = 0
        do k = 1, pa%nc
            pos(pa%ic(k), pa%jc(k)) = k
            pa%bc(k) = pa%bound(pa%ic(k), pa%jc(k))
        end do
        pa%nrun = 0
        do j = pa%j1, pa%j2
            do i = pa%i2, pa%i1, -1
                if (pa%inc(i, j) .and. .not. pa%inc(i + 1, j)) pa%nrun = pa%nrun + 1
            end do
        end do
        allocate (pa%rp0(pa%nrun), pa%rn(pa%nrun), pa%rrow(pa%nrun))
        k = 0
        do j = pa%j1, pa%j2
            do i = pa%i2, pa%i1, -1
                if (.not. (pa%inc(i, j) .and. .not. pa%inc(i + 1, j))) cycle
                k = k + 1
                pa%rp0(k) = pos(pa%trail(i, j), j)
                pa%rn(k) = i - pa%trail(i, j) + 1
                ! a run that fills its row changes no other element of it: the next row's first
                pa%rrow(k) = pos(pa%rlo(j), j)
                if (pa%trail(i, j) == pa%rlo(j) .and. i == pa%rhi(j)) pa%rrow(k) = pa%rp0(k) + pa%rn(k)
            end do
        end do
    end subroutine small_runs

end module contact_rolling_small
