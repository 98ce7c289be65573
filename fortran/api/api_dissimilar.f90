!> f2py shim for the contact of dissimilar materials: plain arrays, explicit shapes,
!> integer info. Argument checks live in Python (railvti.contact.dissimilar).
!> Implements no equation (contact_coupling does: see docs/equations.md).

!> Cross coefficients (1/pi) I[X/r^2] (kernel 1) or (1/pi) I[Y/r^2] (kernel 2) for all
!> offsets (k, l), k = 1-nx..nx-1, l = 1-ny..ny-1, of an nx x ny grid (m); A_xz = -K/G c.
!> info: STAT_OK; STAT_BAD_ARGUMENT an unknown kernel.
subroutine cross_field_c(kernel, nx, ny, dx, dy, c, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    use contact_coupling, only: cross_field, CROSS_X, CROSS_Y
    implicit none
    integer(c_int), intent(in) :: kernel, nx, ny
    real(c_double), intent(in) :: dx, dy
    real(c_double), intent(out) :: c(2 * nx - 1, 2 * ny - 1)
    integer(c_int), intent(out) :: info
    info = STAT_OK
    c = 0.0_c_double
    if (kernel /= CROSS_X .and. kernel /= CROSS_Y) then
        info = STAT_BAD_ARGUMENT
        return
    end if
    call cross_field(kernel, nx, ny, dx, dy, c)
end subroutine cross_field_c

!> Cross products: un = A_zx tx + A_zy ty (gap increase, m) and (ux, uy) = A_xz p, A_yz p
!> (tangential displacement difference, m) for kg = K/G.
subroutine coupling_apply_c(nx, ny, dx, dy, kg, p, tx, ty, un, ux, uy)
    use iso_c_binding, only: c_int, c_double
    use contact_coupling, only: coupling_apply
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: nx, ny
    real(c_double), intent(in) :: dx, dy, kg, p(nx, ny), tx(nx, ny), ty(nx, ny)
    real(c_double), intent(out) :: un(nx, ny), ux(nx, ny), uy(nx, ny)
    call coupling_apply(nx, ny, dx, dy, kg, p, tx, ty, un, ux, uy)
end subroutine coupling_apply_c

!> Steady rolling of a dissimilar pair for a fixed pressure p (Pa): rolling_solve_c's
!> problem with the pressure's coupling as extra rigid slip (coupling_rolling_slip),
!> kg = K/G. The workspace holds the combined (G, nu). Arguments and info as
!> rolling_solve_c.
subroutine dissimilar_rolling_c(handle, nx, ny, p, x0, y0, xi, eta, phi, mu, speed, method, nblock, &
                                ninner, tol, max_iter, product, kg, tx, ty, status, sx, sy, iters, resid, &
                                info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_BAD_HANDLE
    use contact_plans, only: workspace, ws_get
    use contact_rolling, only: rolling_steady
    use contact_coupling, only: coupling_rolling_slip
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: handle, nx, ny, method, nblock, ninner, max_iter, product
    real(c_double), intent(in) :: p(nx, ny), x0, y0, xi, eta, phi, mu, speed, tol, kg
    real(c_double), intent(inout) :: tx(nx, ny), ty(nx, ny)
    integer(c_int), intent(out) :: status(nx, ny)
    real(c_double), intent(out) :: sx(nx, ny), sy(nx, ny)
    integer(c_int), intent(out) :: iters, info
    real(c_double), intent(out) :: resid
    type(workspace), pointer :: w
    integer, allocatable :: st(:, :)
    real(c_double), allocatable :: wex(:, :), wey(:, :)
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
    allocate (st(nx, ny), wex(nx, ny), wey(nx, ny))
    call coupling_rolling_slip(nx, ny, w%dx, w%dy, kg, p, wex, wey)
    call rolling_steady(w, p, x0, y0, xi, eta, phi, mu, speed, method, nblock, ninner, tol, max_iter, &
                        tx, ty, st, sx, sy, it, resid, stat, product=product, wex=wex, wey=wey)
    status = st
    iters = it
    info = stat
end subroutine dissimilar_rolling_c

!> One load step's tangential (shift) problem of a dissimilar pair (coupling_shift_step):
!> combined (g, nu), kg = K/G, pressure p (Pa), the previous step's displacement
!> difference (uoldx, uoldy) (m), rigid shift (wx, wy) (m). tx, ty: start in, Pa out;
!> (ux, uy): this step's displacement difference (m). info: coupling_shift_step's.
subroutine coupling_shift_c(nx, ny, dx, dy, g, nu, kg, mu, p, uoldx, uoldy, wx, wy, tol, max_iter, &
                            tx, ty, status, ux, uy, iters, change, info)
    use iso_c_binding, only: c_int, c_double
    use contact_coupling, only: coupling_shift_step
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: nx, ny, max_iter
    real(c_double), intent(in) :: dx, dy, g, nu, kg, mu, wx, wy, tol
    real(c_double), intent(in) :: p(nx, ny), uoldx(nx, ny), uoldy(nx, ny)
    real(c_double), intent(inout) :: tx(nx, ny), ty(nx, ny)
    integer(c_int), intent(out) :: status(nx, ny), iters, info
    real(c_double), intent(out) :: ux(nx, ny), uy(nx, ny), change
    integer, allocatable :: st(:, :)
    integer :: it, stat
    allocate (st(nx, ny))
    call coupling_shift_step(nx, ny, dx, dy, g, nu, kg, mu, p, uoldx, uoldy, wx, wy, tol, max_iter, &
                             tx, ty, st, ux, uy, it, change, stat)
    status = st
    iters = it
    info = stat
end subroutine coupling_shift_c
