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
