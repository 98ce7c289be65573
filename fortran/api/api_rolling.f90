!> f2py shim for steady rolling contact: plain arrays, explicit shapes, integer info.
!> Argument checks live in Python (railvti.contact.rolling); the kernel
!> contact_rolling::rolling_steady takes the workspace itself, so Fortran
!> callers (time simulation) use it without this shim.
!> Implements no equation (contact_rolling does: see docs/equations.md).

!> Steady rolling on the grid of workspace `handle` (made with tangential /= 0)
!> for the pressure p (Pa). method: 1 row-implicit Gauss-Seidel ('gs'),
!> 2 the same with an FFT refresh every nblock rows and Anderson acceleration
!> ('fftgs'); ninner passes per row run. x0, y0: centre of element
!> [1, 1] (m); creepages xi, eta (1) and spin phi (1/m); speed (m/s).
!> tx, ty: warm start on entry, tractions (Pa) on exit. status: 0 exterior,
!> 1 adhesion, 2 slip. sx, sy: slip velocity (m/s). product: how u = A t is
!> formed, 0 the cheaper way, 1 FFT (the reference), 2 direct sums over the
!> contact box (contact_rolling's PRODUCT_*). info: rolling_steady's
!> status (STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, ...); STAT_BAD_HANDLE
!> no such workspace, or one of another grid size.
subroutine rolling_solve_c(handle, nx, ny, p, x0, y0, xi, eta, phi, mu, speed, method, nblock, &
                           ninner, tol, max_iter, product, tx, ty, status, sx, sy, iters, resid, &
                           info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_BAD_HANDLE
    use contact_plans, only: workspace, ws_get
    use contact_rolling, only: rolling_steady
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: handle, nx, ny, method, nblock, ninner, max_iter, product
    real(c_double), intent(in) :: p(nx, ny), x0, y0, xi, eta, phi, mu, speed, tol
    real(c_double), intent(inout) :: tx(nx, ny), ty(nx, ny)
    integer(c_int), intent(out) :: status(nx, ny)
    real(c_double), intent(out) :: sx(nx, ny), sy(nx, ny)
    integer(c_int), intent(out) :: iters, info
    real(c_double), intent(out) :: resid
    type(workspace), pointer :: w
    integer, allocatable :: st(:, :)
    integer :: it, stat

    iters = 0
    resid = 0.0_c_double
    status = 0
    sx = 0.0_c_double
    sy = 0.0_c_double
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) then
        info = STAT_BAD_HANDLE
        return
    end if
    allocate (st(nx, ny))
    call rolling_steady(w, p, x0, y0, xi, eta, phi, mu, speed, method, nblock, ninner, tol, max_iter, &
                        tx, ty, st, sx, sy, it, resid, stat, product=product)
    status = st
    iters = it
    info = stat
end subroutine rolling_solve_c

!> A creep-force table on the grid of workspace `handle` (made with tangential /= 0):
!> for each of the ncase cases the normal problem with the gap gap(:, :, kgap(k)) (m)
!> and the force fn(k) (N), solved again only when these differ from the previous
!> case's, then steady rolling with creep(:, k) = (xi, eta, phi) (1, 1, 1/m), each from
!> zero (contact_creep_table::creep_force_table). Per case: fx, fy (N), mz (N m, about x = y = 0),
!> power (W), ncontact, approach (m), iters_n (normal iterations), iters_t (sweeps),
!> nfo_n (normal status, STAT_GRID_EDGE if the pressure reaches the grid's edge),
!> nfo_t (rolling status, where nfo_n is STAT_OK). info: STAT_OK; STAT_BAD_HANDLE no
!> such workspace, one of another grid size or without the tangential kernels;
!> STAT_BAD_ARGUMENT a kgap outside 1..ngap. A table in slices: carry (0/1), pstate (Pa),
!> rstate(1) (approach, m) and istate(1) (normal iterations) as the kernel's carry, p,
!> appr_io, itn_io (the last case's normal solution out; with carry = 1 the first case
!> continues its run).
subroutine creep_force_table_c(handle, nx, ny, ngap, ncase, gap, kgap, fn, creep, mu, speed, x0, y0, &
                           tol_n, tol_t, max_iter_n, max_iter_t, carry, pstate, rstate, istate, fx, fy, mz, &
                           power, ncontact, approach, iters_n, iters_t, nfo_n, nfo_t, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_BAD_HANDLE
    use contact_plans, only: workspace, ws_get
    use contact_creep_table, only: creep_force_table
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: handle, nx, ny, ngap, ncase, max_iter_n, max_iter_t, carry
    real(c_double), intent(inout) :: pstate(nx, ny), rstate(1)
    integer(c_int), intent(inout) :: istate(1)
    real(c_double), intent(in) :: gap(nx, ny, ngap), fn(ncase), creep(3, ncase)
    integer(c_int), intent(in) :: kgap(ncase)
    real(c_double), intent(in) :: mu, speed, x0, y0, tol_n, tol_t
    real(c_double), intent(out) :: fx(ncase), fy(ncase), mz(ncase), power(ncase), approach(ncase)
    integer(c_int), intent(out) :: ncontact(ncase), iters_n(ncase), iters_t(ncase)
    integer(c_int), intent(out) :: nfo_n(ncase), nfo_t(ncase), info
    type(workspace), pointer :: w
    integer, allocatable :: kg(:), nc(:), itn(:), itt(:), sn(:), stt(:)
    integer :: stat, itn_io
    real(c_double) :: appr_io

    fx = 0.0_c_double
    fy = 0.0_c_double
    mz = 0.0_c_double
    power = 0.0_c_double
    approach = 0.0_c_double
    ncontact = 0
    iters_n = 0
    iters_t = 0
    nfo_n = 0
    nfo_t = 0
    w => ws_get(handle, nx, ny)
    info = STAT_BAD_HANDLE
    if (.not. associated(w)) return
    if (w%nker < 4) return
    allocate (kg(ncase), nc(ncase), itn(ncase), itt(ncase), sn(ncase), stt(ncase))
    kg = kgap
    appr_io = rstate(1)
    itn_io = istate(1)
    call creep_force_table(w, gap, kg, fn, creep, mu, speed, x0, y0, tol_n, tol_t, max_iter_n, max_iter_t, &
                           carry /= 0, pstate, appr_io, itn_io, fx, fy, mz, power, nc, approach, itn, itt, sn, stt, &
                           stat)
    rstate(1) = appr_io
    istate(1) = itn_io
    ncontact = nc
    iters_n = itn
    iters_t = itt
    nfo_n = sn
    nfo_t = stt
    info = stat
end subroutine creep_force_table_c
