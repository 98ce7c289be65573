!> Creep-force tables: the normal problem (force control) and steady rolling
!> for a table of cases on one grid, in one call, so that a table of small
!> cases (the 11 x 11 grids of vehicle codes' contact tables) pays no per-case
!> call overhead. Each case is the solve_rolling of the Python API: the normal
!> problem (on small grids, where dense_is_cheaper, solved exactly by the
!> active set of contact_normal_dense, which agrees with solve_rolling's projected CG
!> to CG's tolerance; elsewhere, or where the active set fails, projected CG from zero
!> pressure, contact_normal::normal_cg), then the steady rolling
!> solver from zero traction (contact_rolling::rolling_steady, method 'fftgs',
!> product chosen by operation count); the normal problem is solved again only
!> when a case's gap or normal force differs from the previous case's (the
!> pressure does not depend on the creepages for quasi-identical bodies), and the
!> rolling solver's fixed data of that pressure (contact set, in-row bases, dense slip
!> operator: rolling_steady's patch) are made once with it.
!> Implements no equation (normal_cg and rolling_steady do: docs/equations.md).
module contact_creep_table
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_GRID_EDGE, STAT_BAD_ARGUMENT, STAT_NOT_CONVERGED
    use contact_plans, only: workspace
    use contact_normal, only: normal_cg, CONTROL_FORCE
    use contact_normal_dense, only: normal_dense_force, dense_is_cheaper, normal_dense_cache
    use contact_rolling, only: rolling_steady, ROLL_FFTGS, rolling_patch, rolling_patch_reset
    implicit none
    private
    public :: creep_force_table

    !> Rows per FFT refresh and passes per run of the rolling solver (the Python defaults).
    integer, parameter :: NBLOCK = 16, NINNER = 1

contains

    !> The creep forces of ncase cases on the grid of workspace w (made with the
    !> tangential kernels). Case k has the gap gap(:, :, kgap(k)) (m), the normal force
    !> fn(k) (N) and the creepages creep(:, k) = (xi, eta, phi) (1, 1, 1/m); all share
    !> mu, the rolling speed (m/s) and the grid's origin x0, y0 (centre of element
    !> (1, 1), m). Out per case: fx, fy (N), mz about x = y = 0 (N m), frictional
    !> power (W), elements in contact, approach (m), normal iterations (trial contact sets
    !> of the dense active set, or CG iterations) and rolling
    !> sweeps; nfo_n: the normal solver's status (STAT_OK, STAT_NOT_CONVERGED,
    !> STAT_NOT_FINITE), or STAT_GRID_EDGE when the pressure reaches the grid's edge
    !> rows or columns (or the last two rows, which the slip stencil needs); nfo_t: the
    !> rolling solver's status, only where nfo_n is STAT_OK (elsewhere the tangential
    !> problem is not solved: forces zero). info: STAT_BAD_ARGUMENT for a kgap outside
    !> 1..size(gap, 3) or arrays of different lengths, else STAT_OK.
    !> A table in slices (the Python API's, between which Ctrl-C can stop it): p (Pa, nx x ny),
    !> appr_io (m) and itn_io hold on return the pressure, approach and normal iterations
    !> of the last case; with carry the first case continues that case's run (same gap and
    !> force, normal status STAT_OK) and takes them instead of solving its normal problem,
    !> so that the slices together make the normal solves of one call.
    subroutine creep_force_table(w, gap, kgap, fn, creep, mu, speed, x0, y0, tol_n, tol_t, max_iter_n, &
                           max_iter_t, carry, p, appr_io, itn_io, fx, fy, mz, power, ncontact, approach, iters_n, &
                           iters_t, nfo_n, nfo_t, info)
        type(workspace), intent(inout) :: w
        logical, intent(in) :: carry
        real(dp), intent(inout) :: p(:, :), appr_io
        integer, intent(inout) :: itn_io
        real(dp), intent(in) :: gap(:, :, :), fn(:), creep(:, :), mu, speed, x0, y0, tol_n, tol_t
        integer, intent(in) :: kgap(:), max_iter_n, max_iter_t
        real(dp), intent(out) :: fx(:), fy(:), mz(:), power(:), approach(:)
        integer, intent(out) :: ncontact(:), iters_n(:), iters_t(:), nfo_n(:), nfo_t(:), info
        real(dp), allocatable :: tx(:, :), ty(:, :), sx(:, :), sy(:, :)
        integer, allocatable :: st(:, :)
        type(rolling_patch) :: pa
        type(normal_dense_cache) :: ncache   ! the active set's last factor, case to case
        real(dp) :: da, fnk, appr, resid
        integer :: k, nx, ny, stat, itn, itt, nprod, stat_n, nc
        logical :: fresh

        nx = w%nx
        ny = w%ny
        da = w%dx * w%dy
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        power = 0.0_dp
        approach = 0.0_dp
        ncontact = 0
        iters_n = 0
        iters_t = 0
        nfo_n = STAT_OK
        nfo_t = STAT_OK
        info = STAT_OK
        if (any(kgap < 1) .or. any(kgap > size(gap, 3)) .or. size(fn) /= size(kgap) &
            .or. size(creep, 2) /= size(kgap)) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        allocate (tx(nx, ny), ty(nx, ny), sx(nx, ny), sy(nx, ny), st(nx, ny))
        stat_n = STAT_OK
        itn = itn_io
        nc = count(p > 0.0_dp)
        appr = appr_io
        do k = 1, size(kgap)
            fresh = k == 1 .and. .not. carry
            if (k > 1) fresh = kgap(k) /= kgap(k - 1) .or. fn(k) /= fn(k - 1)
            if (fresh) then
                ! the active set starts from the previous case's contact set (p holds its
                ! pressure; zero before the table's first case) when that case was solved:
                ! the final set fixes the answer, not the start
                if (stat_n /= STAT_OK) p = 0.0_dp
                fnk = fn(k)
                appr = 0.0_dp
                stat_n = STAT_NOT_CONVERGED
                if (dense_is_cheaper(start_size(gap(:, :, kgap(k))), nx, ny)) then
                    ! small grids: the exact active-set solve, CG where it finds no set
                    call normal_dense_force(w%c(:, :, 1), gap(:, :, kgap(k)), da, fnk, p, appr, itn, resid, &
                                            stat_n, cache=ncache)
                    if (stat_n == STAT_OK .and. resid > tol_n) stat_n = STAT_NOT_CONVERGED
                end if
                if (stat_n == STAT_NOT_CONVERGED) then
                    p = 0.0_dp
                    appr = 0.0_dp
                    w%plan%has_prec = .true.
                    call normal_cg(w%plan, 1, w%c(:, :, 1), gap(:, :, kgap(k)), da, CONTROL_FORCE, fnk, appr, &
                                   tol_n, max_iter_n, p, itn, nprod, resid, stat_n)
                end if
                if (stat_n == STAT_OK .and. touches_edge(p)) stat_n = STAT_GRID_EDGE
                nc = count(p > 0.0_dp)
                call rolling_patch_reset(pa)   ! a new pressure: the rolling solver's patch anew
            end if
            iters_n(k) = itn
            approach(k) = appr
            ncontact(k) = nc
            nfo_n(k) = stat_n
            if (stat_n /= STAT_OK) cycle
            tx = 0.0_dp
            ty = 0.0_dp
            call rolling_steady(w, p, x0, y0, creep(1, k), creep(2, k), creep(3, k), mu, speed, ROLL_FFTGS, &
                                NBLOCK, NINNER, tol_t, max_iter_t, tx, ty, st, sx, sy, itt, resid, stat, patch=pa)
            iters_t(k) = itt
            nfo_t(k) = stat
            call case_forces(tx, ty, sx, sy, x0, y0, w%dx, w%dy, fx(k), fy(k), mz(k), power(k))
        end do
        appr_io = appr
        itn_io = itn
    end subroutine creep_force_table

    !> The size of the active set's cold start (contact_normal_dense): the elements with h
    !> below a quarter of h's range. The choice of the normal solver depends on the case's
    !> gap alone (not on the previous case: the table's results do not depend on its order).
    pure integer function start_size(h)
        real(dp), intent(in) :: h(:, :)
        real(dp) :: hmin
        hmin = minval(h)
        start_size = count(h <= hmin + 0.25_dp * (maxval(h) - hmin))
    end function start_size

    !> Whether any pressure lies on the grid's edge rows or columns (the contact area
    !> would be cut by the grid; the Python API's GridTooSmallError).
    pure logical function touches_edge(p)
        real(dp), intent(in) :: p(:, :)
        integer :: nx, ny
        nx = size(p, 1)
        ny = size(p, 2)
        touches_edge = any(p(1, :) > 0.0_dp) .or. any(p(nx - 1:nx, :) > 0.0_dp) &
                       .or. any(p(:, 1) > 0.0_dp) .or. any(p(:, ny) > 0.0_dp)
    end function touches_edge

    !> Forces, spin moment about x = y = 0 and frictional power of the tractions t (Pa)
    !> with slip velocities s (m/s) on the grid with origin x0, y0 and steps dx, dy.
    pure subroutine case_forces(tx, ty, sx, sy, x0, y0, dx, dy, fx, fy, mz, power)
        real(dp), intent(in) :: tx(:, :), ty(:, :), sx(:, :), sy(:, :), x0, y0, dx, dy
        real(dp), intent(out) :: fx, fy, mz, power
        integer :: i, j
        real(dp) :: x, y
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        power = 0.0_dp
        do j = 1, size(tx, 2)
            y = y0 + (j - 1) * dy
            do i = 1, size(tx, 1)
                if (tx(i, j) == 0.0_dp .and. ty(i, j) == 0.0_dp) cycle
                x = x0 + (i - 1) * dx
                fx = fx + tx(i, j)
                fy = fy + ty(i, j)
                mz = mz + (x * ty(i, j) - y * tx(i, j))
                power = power + sqrt(tx(i, j)**2 + ty(i, j)**2) * sqrt(sx(i, j)**2 + sy(i, j)**2)
            end do
        end do
        fx = fx * dx * dy
        fy = fy * dx * dy
        mz = mz * dx * dy
        power = power * dx * dy
    end subroutine case_forces

end module contact_creep_table
