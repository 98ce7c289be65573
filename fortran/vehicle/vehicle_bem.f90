!> BEM contact at the wheels of the time simulation: the normal problem (contact_normal,
!> projected CG under approach control) and steady rolling (contact_rolling, 'fftgs') on a
!> fixed grid per candidate point, warm-started from the previous evaluation of the same
!> wheel and candidate point.
!>
!> Gap fields. For the left wheel (the right one is the mirror: the field read at -y with the
!> lateral grid index reversed) and each of the table's two candidate points, the undeformed
!> normal gap around the point, relative to the point (h = 0 there), is tabulated against the
!> lateral shift y of the wheelset on the contact table's y nodes (built in Python,
!> railvti.vehicle.bem). The grid (nx x ny, dx x dy) is centred on the point: x along the
!> rolling direction, y along the contact frame's t_y. The wheel's vertical interference at the
!> point enters as a uniform approach d (the same d as the Hertz path), so the field is
!> interpolated linearly in y within the point's branch (never across a jump of the point to
!> another local minimum: vehicle_contact%table_at picks the nodes and the weight) and solved
!> with delta = d.
!>
!> State. One bem_model per simulation behind an integer handle (registry like
!> contact_plans): the gap table, one contact workspace (FFT plans and influence spectra of
!> the grid, with the tangential kernels) shared by every patch, and per wheelset, wheel and
!> candidate point the last pressure, tractions and slip velocities (the warm starts and the
!> fields reported after a run). Not thread-safe.
!>
!> Windows. Each solve runs on the window of the grid around the point's rigid
!> interpenetration {h < dn} (its bounding box plus WIN_MARGIN elements a side, the sides
!> rounded up to multiples of WIN_QUANTUM, clipped to the grid), with a workspace of the
!> window's size made on first use and kept (bem_window switches this off). The contact area
!> lies inside {h < dn} (the normal displacement of a positive pressure is positive), and
!> the influence coefficients of an element pair depend on their offset only, so the
!> window's solution is the full grid's, to the solvers' tolerances, at the cost of FFTs of
!> the window (a tread patch's window is about a fifth of the 0.75 mm grid).
!> The window workspaces are made inside the time loop (the GIL released): two BEM runs in
!> threads of one process must not run at the same time (contact_plans' registry is not
!> thread-safe; the sweeps run one thread per process).
!> Implements no equation itself: it applies contact_normal (Kaiser eqs 17-23) and
!> contact_rolling (eqs 24-29) at every wheel.
module vehicle_bem
    use, intrinsic :: iso_fortran_env, only: int64
    use common_kinds, only: dp
    use contact_plans, only: workspace, ws_create, ws_free, ws_get
    use contact_normal, only: normal_cg, CONTROL_APPROACH
    use contact_rolling, only: rolling_steady, ROLL_FFTGS
    use common_status, only: STAT_OK, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, STAT_BAD_HANDLE, &
                             STAT_NO_MEMORY, STAT_FFTW_PLAN, STAT_GRID_EDGE, STAT_OUTSIDE_TABLE, &
                             STAT_CONTACT_NOT_CONVERGED
    implicit none
    private
    public :: bem_create, bem_free, bem_patch, bem_fields, bem_counts, bem_reset, bem_scale
    public :: bem_window
    public :: MAX_BEM, BEM_NCOUNT

    integer, parameter :: MAX_BEM = 16
    !> Gap-field entries at or above this mark elements off the point's part of the wheel, m.
    real(dp), parameter :: FAR = 0.5_dp
    !> Counters (bem_counts): 1 normal solves, 2 CG iterations, 3 rolling solves,
    !> 4 rolling sweeps, 5 patches found out of contact, 6 worst accepted normal residual,
    !> 7 worst accepted rolling residual, 8 wall seconds in normal solves, 9 in rolling
    !> solves, 10 in bem_patch as a whole (the solves, the gap field and the sums).
    integer, parameter :: BEM_NCOUNT = 10
    !> Free elements around the interpenetration in a solve window (steady rolling needs
    !> two free rows behind the patch, the edge test one more), and the step its sides are
    !> rounded up to (few distinct window sizes, so few workspaces).
    integer, parameter :: WIN_MARGIN = 3, WIN_QUANTUM = 4
    !> Window sizes (workspaces) kept per model; beyond it a solve uses the full grid.
    integer, parameter :: MAX_WIN = 48

    type :: bem_model
        logical :: used = .false.
        integer :: nx = 0, ny = 0, ntab = 0, nws = 0, ws = 0
        !> nblock: rows per FFT refresh of the rolling sweeps ('fftgs'): a window's rows all
        !> in one block (one field product per sweep; the in-block changes are summed directly)
        integer :: maxit_n = 200, maxit_t = 400, nblock = 64, ninner = 1
        real(dp) :: dx = 0, dy = 0, ytab0 = 0, dytab = 1, tol_n = 1e-8_dp, tol_t = 1e-6_dp
        real(dp) :: g = 0, nu = 0
        !> solves on windows (see the module doc); win(:, i) = (nx, ny, workspace) of the
        !> nwin window workspaces made so far
        logical :: window = .true.
        integer :: nwin = 0
        integer :: win(3, MAX_WIN) = 0
        real(dp), allocatable :: gap(:, :, :, :)          ! (nx, ny, 2 points, ntab), left wheel
        real(dp), allocatable :: p(:, :, :, :, :)         ! (nx, ny, point, wheel, wheelset)
        real(dp), allocatable :: tx(:, :, :, :, :), ty(:, :, :, :, :)
        real(dp), allocatable :: sx(:, :, :, :, :), sy(:, :, :, :, :)
        real(dp), allocatable :: h(:, :)
        !> BEM / Hertz-Kalker ratios of the normal force and the creep-force magnitude per
        !> (point, wheel, wheelset), from the last BEM solve: they calibrate the cheap model
        !> of the Newton tangent (vehicle_contact model 4).
        real(dp), allocatable :: ratio(:, :, :, :)
        integer, allocatable :: st(:, :)
        real(dp) :: counts(BEM_NCOUNT) = 0
    end type bem_model

    type(bem_model), target :: models(MAX_BEM)

contains

    !> Make a BEM contact state. gap: (nx, ny, 2, ntab) left-wheel gap fields on the table's
    !> y nodes ytab0 + (i - 1) dytab. g, nu: shear modulus and Poisson ratio.
    !> info: STAT_OK, STAT_BAD_ARGUMENT (sizes or steps), STAT_NO_MEMORY (no free slot),
    !> STAT_FFTW_PLAN (the contact workspace, FFT plans and spectra, could not be made).
    subroutine bem_create(nx, ny, dx, dy, ntab, ytab0, dytab, gap, nws, g, nu, tol_n, tol_t, &
                          maxit_n, maxit_t, handle, info)
        integer, intent(in) :: nx, ny, ntab, nws, maxit_n, maxit_t
        real(dp), intent(in) :: dx, dy, ytab0, dytab, gap(nx, ny, 2, ntab), g, nu, tol_n, tol_t
        integer, intent(out) :: handle, info
        type(bem_model), pointer :: m
        integer :: k, stat
        handle = 0
        info = STAT_BAD_ARGUMENT
        if (nx < 4 .or. ny < 4 .or. ntab < 2 .or. nws < 1 .or. dx <= 0 .or. dy <= 0 .or. dytab <= 0) return
        info = STAT_NO_MEMORY
        do k = 1, MAX_BEM
            if (.not. models(k)%used) then
                handle = k
                exit
            end if
        end do
        if (handle == 0) return
        m => models(handle)
        call ws_create(nx, ny, dx, dy, g, nu, .true., m%ws, stat)
        if (stat /= STAT_OK) then
            info = stat     ! STAT_NO_MEMORY (workspace pool full) or STAT_FFTW_PLAN
            handle = 0
            return
        end if
        m%nx = nx
        m%ny = ny
        m%dx = dx
        m%dy = dy
        m%ntab = ntab
        m%ytab0 = ytab0
        m%dytab = dytab
        m%nws = nws
        m%tol_n = tol_n
        m%tol_t = tol_t
        m%maxit_n = maxit_n
        m%maxit_t = maxit_t
        m%g = g
        m%nu = nu
        m%window = .true.
        m%nwin = 0
        m%win = 0
        m%gap = gap
        allocate (m%p(nx, ny, 2, 2, nws), source=0.0_dp)
        allocate (m%tx, m%ty, m%sx, m%sy, mold=m%p)
        allocate (m%h(nx, ny), m%st(nx, ny), m%ratio(2, 2, 2, nws))
        call reset(m)
        m%used = .true.
        info = STAT_OK
    end subroutine bem_create

    subroutine reset(m)
        type(bem_model), intent(inout) :: m
        m%p = 0.0_dp
        m%tx = 0.0_dp
        m%ty = 0.0_dp
        m%sx = 0.0_dp
        m%sy = 0.0_dp
        m%counts = 0.0_dp
        m%ratio = 1.0_dp
    end subroutine reset

    !> Clear the warm starts and counters.
    subroutine bem_reset(handle)
        integer, intent(in) :: handle
        if (.not. live(handle)) return
        call reset(models(handle))
    end subroutine bem_reset

    subroutine bem_free(handle)
        integer, intent(in) :: handle
        integer :: i
        if (.not. live(handle)) return
        call ws_free(models(handle)%ws)
        do i = 1, models(handle)%nwin
            call ws_free(models(handle)%win(3, i))
        end do
        models(handle)%nwin = 0
        deallocate (models(handle)%gap, models(handle)%p, models(handle)%tx, models(handle)%ty, &
                    models(handle)%sx, models(handle)%sy, models(handle)%h, models(handle)%st, &
                    models(handle)%ratio)
        models(handle)%used = .false.
    end subroutine bem_free

    logical function live(handle)
        integer, intent(in) :: handle
        live = .false.
        if (handle < 1 .or. handle > MAX_BEM) return
        live = models(handle)%used
    end function live

    !> Solve on windows around the interpenetration (on = .true., the default) or on the
    !> full grid (the reference of the window's test). info: STAT_OK or STAT_BAD_HANDLE.
    subroutine bem_window(handle, on, info)
        integer, intent(in) :: handle
        logical, intent(in) :: on
        integer, intent(out) :: info
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        models(handle)%window = on
        info = STAT_OK
    end subroutine bem_window

    !> Counters since creation or the last reset (see BEM_NCOUNT).
    subroutine bem_counts(handle, counts, info)
        integer, intent(in) :: handle
        real(dp), intent(out) :: counts(BEM_NCOUNT)
        integer, intent(out) :: info
        counts = 0.0_dp
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        counts = models(handle)%counts
        info = STAT_OK
    end subroutine bem_counts

    !> The last fields of wheelset iws, wheel iw (1 left, 2 right), candidate point k.
    !> info: STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT (sizes or indices).
    subroutine bem_fields(handle, iws, iw, k, nx, ny, p, tx, ty, sx, sy, info)
        integer, intent(in) :: handle, iws, iw, k, nx, ny
        real(dp), intent(out) :: p(nx, ny), tx(nx, ny), ty(nx, ny), sx(nx, ny), sy(nx, ny)
        integer, intent(out) :: info
        type(bem_model), pointer :: m
        p = 0.0_dp
        tx = 0.0_dp
        ty = 0.0_dp
        sx = 0.0_dp
        sy = 0.0_dp
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        m => models(handle)
        info = STAT_BAD_ARGUMENT
        if (nx /= m%nx .or. ny /= m%ny .or. iws < 1 .or. iws > m%nws .or. iw < 1 .or. iw > 2 &
            .or. k < 1 .or. k > 2) return
        p = m%p(:, :, k, iw, iws)
        tx = m%tx(:, :, k, iw, iws)
        ty = m%ty(:, :, k, iw, iws)
        sx = m%sx(:, :, k, iw, iws)
        sy = m%sy(:, :, k, iw, iws)
        info = STAT_OK
    end subroutine bem_fields

    !> Normal and tangential contact of one candidate point: wheelset iws, wheel iw (1 left,
    !> 2 right), point k, gap field (1 - wa) gap(ia) + wa gap(ib) of the left wheel's table
    !> nodes ia, ib (vehicle_contact%table_at: the same nodes and weight as the point's
    !> scalars, one branch only, wa outside [0, 1] where a branch is extrapolated), normal
    !> approach dn (m), relative roll phi of wheel against rail (rad: the field tilts by
    !> phi t, the normal component of the rotation e_x x t t_y, so that the roll moment of the
    !> pressure below derives from the same gap), creepages xi, eta (-), spin (1/m), friction
    !> mu, rolling speed (m/s). fn, fx, fy: forces on the wheel in the contact frame (N); mz:
    !> spin moment of the tractions about the normal through the point (N m); xc, yc: centre
    !> of pressure in the contact frame relative to the point (m), so that the moment of the
    !> contact stresses about the point is Fn yc t_x - Fn xc t_y + mz n.
    !> info: STAT_OK, STAT_OUTSIDE_TABLE (a node outside the table), STAT_GRID_EDGE (the patch
    !> reaches its grid's edge), STAT_CONTACT_NOT_CONVERGED (a solver did not converge),
    !> STAT_BAD_HANDLE.
    subroutine bem_patch(handle, iws, iw, k, ia, ib, wa, dn, phi, xi, eta, spin, mu, speed, &
                         fn, fx, fy, mz, xc, yc, info)
        integer, intent(in) :: handle, iws, iw, k, ia, ib
        real(dp), intent(in) :: wa, dn, phi, xi, eta, spin, mu, speed
        real(dp), intent(out) :: fn, fx, fy, mz, xc, yc
        integer, intent(out) :: info
        type(bem_model), pointer :: m
        type(workspace), pointer :: w
        real(dp) :: x0, y0
        integer :: nx, ny, j
        integer(int64) :: c0, c2
        fn = 0.0_dp
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        xc = 0.0_dp
        yc = 0.0_dp
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        m => models(handle)
        w => ws_get(m%ws, m%nx, m%ny)
        if (.not. associated(w)) return
        call system_clock(c0)
        nx = m%nx
        ny = m%ny
        if (min(ia, ib) < 1 .or. max(ia, ib) > m%ntab) then
            info = STAT_OUTSIDE_TABLE
            return
        end if
        info = STAT_OK
        if (iw == 1) then
            m%h = (1.0_dp - wa) * m%gap(:, :, k, ia) + wa * m%gap(:, :, k, ib)
            ! an element outside the point's part of the wheel at either node stays outside
            ! (an extrapolation must not pull the 1 m marker into the patch)
            where (max(m%gap(:, :, k, ia), m%gap(:, :, k, ib)) >= FAR) m%h = 1.0_dp
        else
            m%h = (1.0_dp - wa) * m%gap(:, ny:1:-1, k, ia) + wa * m%gap(:, ny:1:-1, k, ib)
            where (max(m%gap(:, ny:1:-1, k, ia), m%gap(:, ny:1:-1, k, ib)) >= FAR) m%h = 1.0_dp
        end if
        x0 = -0.5_dp * real(nx - 1, dp) * m%dx
        y0 = -0.5_dp * real(ny - 1, dp) * m%dy
        if (phi /= 0.0_dp) then
            do j = 1, ny
                where (m%h(:, j) < FAR) m%h(:, j) = m%h(:, j) + phi * (y0 + real(j - 1, dp) * m%dy)
            end do
        end if
        if (.not. (dn > minval(m%h))) then
            call open_patch()
            return
        end if
        call solve_point(m, w, k, iw, iws, dn, x0, y0, xi, eta, spin, mu, speed, fn, fx, fy, mz, &
                         xc, yc, info)
        if (info /= STAT_OK) return
        if (fn <= 0.0_dp) then
            call open_patch()
            return
        end if
        call patch_time()
    contains
        !> The patch's wall time into counter 10 (every return after c0 goes through it
        !> except the failures, which end the run).
        subroutine patch_time()
            call system_clock(c2)
            m%counts(10) = m%counts(10) + seconds(c0, c2)
        end subroutine patch_time

        subroutine open_patch()
            m%p(:, :, k, iw, iws) = 0.0_dp
            m%tx(:, :, k, iw, iws) = 0.0_dp
            m%ty(:, :, k, iw, iws) = 0.0_dp
            m%sx(:, :, k, iw, iws) = 0.0_dp
            m%sy(:, :, k, iw, iws) = 0.0_dp
            m%counts(5) = m%counts(5) + 1.0_dp
            call patch_time()
        end subroutine open_patch
    end subroutine bem_patch

    !> The normal and steady-rolling solves of one point on its window (module doc) with
    !> the gap m%h and approach dn, the point's fields (full grid) updated; the arguments as
    !> for bem_patch, x0, y0 the centre of the grid's element (1, 1). fn = 0 (info STAT_OK)
    !> when the normal solve finds no contact.
    subroutine solve_point(m, w, k, iw, iws, dn, x0, y0, xi, eta, spin, mu, speed, fn, fx, fy, &
                           mz, xc, yc, info)
        type(bem_model), intent(inout) :: m
        type(workspace), pointer, intent(in) :: w
        integer, intent(in) :: k, iw, iws
        real(dp), intent(in) :: dn, x0, y0, xi, eta, spin, mu, speed
        real(dp), intent(out) :: fn, fx, fy, mz, xc, yc
        integer, intent(out) :: info
        type(workspace), pointer :: ww
        real(dp), allocatable :: hw(:, :), pw(:, :), txw(:, :), tyw(:, :), sxw(:, :), syw(:, :)
        integer, allocatable :: stw(:, :)
        real(dp) :: appr, resid, da
        integer :: it, nprod, stat, nx, ny, i1, i2, j1, j2
        integer(int64) :: c1, c2
        fn = 0.0_dp
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        xc = 0.0_dp
        yc = 0.0_dp
        info = STAT_OK
        nx = m%nx
        ny = m%ny
        call patch_window(m, dn, i1, i2, j1, j2, ww)
        if (.not. associated(ww)) ww => w
        allocate (hw(i2 - i1 + 1, j2 - j1 + 1), stw(i2 - i1 + 1, j2 - j1 + 1))
        allocate (pw, txw, tyw, sxw, syw, mold=hw)
        hw = m%h(i1:i2, j1:j2)
        associate (p => m%p(:, :, k, iw, iws), tx => m%tx(:, :, k, iw, iws), &
                   ty => m%ty(:, :, k, iw, iws), sx => m%sx(:, :, k, iw, iws), &
                   sy => m%sy(:, :, k, iw, iws))
            pw = p(i1:i2, j1:j2)
            txw = tx(i1:i2, j1:j2)
            tyw = ty(i1:i2, j1:j2)
            appr = dn
            da = m%dx * m%dy
            call system_clock(c1)
            call normal_cg(ww%plan, 1, ww%c(:, :, 1), hw, da, CONTROL_APPROACH, fn, appr, m%tol_n, &
                           m%maxit_n, pw, it, nprod, resid, stat)
            call system_clock(c2)
            m%counts(8) = m%counts(8) + seconds(c1, c2)
            m%counts(1) = m%counts(1) + 1.0_dp
            m%counts(2) = m%counts(2) + real(it, dp)
            fn = 0.0_dp
            p = 0.0_dp
            if (stat == STAT_NO_CONTACT) return
            if (stat /= STAT_OK .or. .not. all(abs(pw) <= huge(1.0_dp))) then
                info = STAT_CONTACT_NOT_CONVERGED
                return
            end if
            p(i1:i2, j1:j2) = pw
            m%counts(6) = max(m%counts(6), resid)
            if (any(p(1, :) > 0.0_dp) .or. any(p(nx, :) > 0.0_dp) .or. any(p(:, 1) > 0.0_dp) &
                .or. any(p(:, ny) > 0.0_dp)) then
                info = STAT_GRID_EDGE
                return
            end if
            fn = da * sum(p)
            call pressure_centre(nx, ny, m%dx, m%dy, p, fn, xc, yc)
            m%counts(3) = m%counts(3) + 1.0_dp
            call system_clock(c1)
            call rolling_steady(ww, pw, x0 + real(i1 - 1, dp) * m%dx, y0 + real(j1 - 1, dp) * m%dy, &
                                xi, eta, spin, mu, speed, ROLL_FFTGS, m%nblock, m%ninner, m%tol_t, &
                                m%maxit_t, txw, tyw, stw, sxw, syw, it, resid, stat)
            call system_clock(c2)
            m%counts(9) = m%counts(9) + seconds(c1, c2)
            m%counts(4) = m%counts(4) + real(it, dp)
            tx = 0.0_dp
            ty = 0.0_dp
            sx = 0.0_dp
            sy = 0.0_dp
            if (stat == STAT_GRID_EDGE) then
                ! steady rolling needs two free rows behind the patch (contact_rolling)
                info = STAT_GRID_EDGE
                return
            end if
            if ((stat /= STAT_OK .and. stat /= STAT_NO_CONTACT) .or. .not. all(abs(txw) <= huge(1.0_dp)) &
                .or. .not. all(abs(tyw) <= huge(1.0_dp))) then
                info = STAT_CONTACT_NOT_CONVERGED
                return
            end if
            tx(i1:i2, j1:j2) = txw
            ty(i1:i2, j1:j2) = tyw
            sx(i1:i2, j1:j2) = sxw
            sy(i1:i2, j1:j2) = syw
            m%counts(7) = max(m%counts(7), resid)
            fx = da * sum(tx)
            fy = da * sum(ty)
            mz = spin_moment(nx, ny, m%dx, m%dy, tx, ty)
        end associate
    end subroutine solve_point

    !> The window (i1:i2, j1:j2) of a solve with approach dn on the gap m%h (module doc) and
    !> its workspace ww; the full grid, ww null, when windows are off, the window is the grid
    !> or no workspace of its size could be made (the registry or this model's list full).
    subroutine patch_window(m, dn, i1, i2, j1, j2, ww)
        type(bem_model), intent(inout) :: m
        real(dp), intent(in) :: dn
        integer, intent(out) :: i1, i2, j1, j2
        type(workspace), pointer, intent(out) :: ww
        integer :: i, j, lo(2), hi(2), nxw, nyw, hd, stat
        ww => null()
        i1 = 1
        i2 = m%nx
        j1 = 1
        j2 = m%ny
        if (.not. m%window) return
        lo = [m%nx, m%ny]
        hi = [1, 1]
        do j = 1, m%ny
            do i = 1, m%nx
                if (m%h(i, j) < dn) then
                    lo = min(lo, [i, j])
                    hi = max(hi, [i, j])
                end if
            end do
        end do
        call window_span(lo(1), hi(1), m%nx, i1, i2)
        call window_span(lo(2), hi(2), m%ny, j1, j2)
        nxw = i2 - i1 + 1
        nyw = j2 - j1 + 1
        if (nxw == m%nx .and. nyw == m%ny) return
        do i = 1, m%nwin
            if (m%win(1, i) == nxw .and. m%win(2, i) == nyw) then
                ww => ws_get(m%win(3, i), nxw, nyw)
                if (associated(ww)) return
            end if
        end do
        stat = STAT_NO_MEMORY
        if (m%nwin < MAX_WIN) call ws_create(nxw, nyw, m%dx, m%dy, m%g, m%nu, .true., hd, stat)
        if (stat == STAT_OK) then
            m%nwin = m%nwin + 1
            m%win(:, m%nwin) = [nxw, nyw, hd]
            ww => ws_get(hd, nxw, nyw)
        end if
        if (.not. associated(ww)) then
            i1 = 1
            i2 = m%nx
            j1 = 1
            j2 = m%ny
        end if
    end subroutine patch_window

    !> One side of a window: lo..hi widened by WIN_MARGIN, its length rounded up to a
    !> multiple of WIN_QUANTUM, inside 1..n (the whole side when that does not fit); the
    !> widened lo..hi stays inside a..b.
    pure subroutine window_span(lo, hi, n, a, b)
        integer, intent(in) :: lo, hi, n
        integer, intent(out) :: a, b
        integer :: len
        a = max(1, lo - WIN_MARGIN)
        b = min(n, hi + WIN_MARGIN)
        len = WIN_QUANTUM * ((b - a + WIN_QUANTUM) / WIN_QUANTUM)
        if (len >= n) then
            a = 1
            b = n
            return
        end if
        b = min(n, a + len - 1)
        a = b - len + 1
    end subroutine window_span

    !> Wall seconds between two system_clock counts (int64: microsecond or finer ticks).
    real(dp) function seconds(c1, c2)
        integer(int64), intent(in) :: c1, c2
        integer(int64) :: rate
        call system_clock(count_rate=rate)
        seconds = real(c2 - c1, dp) / real(rate, dp)
    end function seconds

    !> Centre of pressure (xc, yc) of p on the grid centred on the point (0 when fn = 0).
    pure subroutine pressure_centre(nx, ny, dx, dy, p, fn, xc, yc)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, p(nx, ny), fn
        real(dp), intent(out) :: xc, yc
        integer :: i, j
        xc = 0.0_dp
        yc = 0.0_dp
        if (fn <= 0.0_dp) return
        do j = 1, ny
            do i = 1, nx
                xc = xc + p(i, j) * (real(i, dp) - 0.5_dp * real(nx + 1, dp)) * dx
                yc = yc + p(i, j) * (real(j, dp) - 0.5_dp * real(ny + 1, dp)) * dy
            end do
        end do
        xc = xc * dx * dy / fn
        yc = yc * dx * dy / fn
    end subroutine pressure_centre

    !> Moment about the normal through the grid centre of the tractions (tx, ty), N m.
    pure function spin_moment(nx, ny, dx, dy, tx, ty) result(mz)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, tx(nx, ny), ty(nx, ny)
        real(dp) :: mz, x, y
        integer :: i, j
        mz = 0.0_dp
        do j = 1, ny
            y = (real(j, dp) - 0.5_dp * real(ny + 1, dp)) * dy
            do i = 1, nx
                x = (real(i, dp) - 0.5_dp * real(nx + 1, dp)) * dx
                mz = mz + x * ty(i, j) - y * tx(i, j)
            end do
        end do
        mz = mz * dx * dy
    end function spin_moment

    !> Get (set = .false.) or store (set = .true.) the calibration ratios (normal, tangential)
    !> of one point; a bad handle or index leaves r = 1.
    subroutine bem_scale(handle, iws, iw, k, set, r)
        integer, intent(in) :: handle, iws, iw, k
        logical, intent(in) :: set
        real(dp), intent(inout) :: r(2)
        if (.not. live(handle)) then
            if (.not. set) r = 1.0_dp
            return
        end if
        if (iws < 1 .or. iws > models(handle)%nws) return
        if (set) then
            models(handle)%ratio(:, k, iw, iws) = r
        else
            r = models(handle)%ratio(:, k, iw, iws)
        end if
    end subroutine bem_scale

end module vehicle_bem
