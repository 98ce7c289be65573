!> f2py shim for viscoelastic steady rolling (contact_viscoelastic): plain arrays,
!> explicit shapes, integer info. Argument checks live in railvti.contact.viscoelastic.
!> Implements no equation (contact_viscoelastic does: see docs/equations.md).

!> Influence coefficients k(m + n), m = -(n-1)..n-1 (m/Pa), of a plane-strain line
!> contact on n strips of width d for nb bodies with compliances j0, jinf (1/Pa) and
!> memory lengths vlen = V tc (m); ell the reference length (m). info: visco_line_kernel's.
subroutine visco_line_kernel_c(n, d, nb, j0, jinf, vlen, ell, k, info)
    use iso_c_binding, only: c_int, c_double
    use contact_viscoelastic, only: visco_line_kernel
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: n, nb
    real(c_double), intent(in) :: d, j0(nb), jinf(nb), vlen(nb), ell
    real(c_double), intent(out) :: k(2 * n - 1)
    integer(c_int), intent(out) :: info
    integer :: stat
    call visco_line_kernel(n, d, nb, j0, jinf, vlen, ell, k, stat)
    info = stat
end subroutine visco_line_kernel_c

!> The normal problem of the line contact with the gap h (m) and the force per length
!> fn (N/m): the kernel (visco_line_kernel), then the active-set solve
!> (visco_line_normal). p: warm start on entry (zero: none), pressure (Pa) on exit;
!> u = A p (m); approach (m). info: the first non-OK status of the two.
subroutine visco_line_solve_c(n, d, h, nb, j0, jinf, vlen, ell, fn, tol, max_iter, p, u, &
                              approach, iters, resid, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK
    use contact_viscoelastic, only: visco_line_kernel, visco_line_normal
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: n, nb, max_iter
    real(c_double), intent(in) :: d, h(n), j0(nb), jinf(nb), vlen(nb), ell, fn, tol
    real(c_double), intent(inout) :: p(n)
    real(c_double), intent(out) :: u(n), approach, resid
    integer(c_int), intent(out) :: iters, info
    real(c_double), allocatable :: k(:)
    integer :: stat, it
    allocate (k(2 * n - 1))
    u = 0.0_c_double
    approach = 0.0_c_double
    resid = 0.0_c_double
    iters = 0
    call visco_line_kernel(n, d, nb, j0, jinf, vlen, ell, k, stat)
    if (stat == STAT_OK) then
        call visco_line_normal(n, d, h, k, fn, tol, max_iter, p, u, approach, it, resid, stat)
        iters = it
    end if
    info = stat
end subroutine visco_line_solve_c

!> The 3-D grid's coefficient field c (circular layout on 2nx x 2ny, m/Pa) of nb bodies
!> (contact_viscoelastic_grid::visco_grid_coefficients). info: its status.
subroutine visco_grid_coefficients_c(nx, ny, dx, dy, nb, j0, jinf, vlen, c, info)
    use iso_c_binding, only: c_int, c_double
    use contact_viscoelastic_grid, only: visco_grid_coefficients
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: nx, ny, nb
    real(c_double), intent(in) :: dx, dy, j0(nb), jinf(nb), vlen(nb)
    real(c_double), intent(out) :: c(2 * nx, 2 * ny)
    integer(c_int), intent(out) :: info
    integer :: stat
    call visco_grid_coefficients(nx, ny, dx, dy, nb, j0, jinf, vlen, c, stat)
    info = stat
end subroutine visco_grid_coefficients_c

!> The normal problem of a point contact on the 3-D grid with the gap h (m) and the force fn
!> (N): the coefficient field, then the active-set solve with GMRES steps
!> (visco_grid_normal, preconditioned with the compliance sum(j0), or sum(jinf) if that
!> is 0). p: start set (p > 0; zero: all elements) on entry, pressure (Pa) on exit;
!> u = C * p (m); nprod: FFT products. info: the first non-OK status.
subroutine visco_grid_solve_c(nx, ny, dx, dy, h, nb, j0, jinf, vlen, fn, tol, max_iter, p, u, &
                              approach, iters, nprod, resid, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK
    use contact_viscoelastic_grid, only: visco_grid_coefficients, visco_grid_normal
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: nx, ny, nb, max_iter
    real(c_double), intent(in) :: dx, dy, h(nx, ny), j0(nb), jinf(nb), vlen(nb), fn, tol
    real(c_double), intent(inout) :: p(nx, ny)
    real(c_double), intent(out) :: u(nx, ny), approach, resid
    integer(c_int), intent(out) :: iters, nprod, info
    real(c_double), allocatable :: c(:, :)
    real(c_double) :: jprec
    integer :: stat, it, np
    allocate (c(2 * nx, 2 * ny))
    u = 0.0_c_double
    approach = 0.0_c_double
    resid = 0.0_c_double
    iters = 0
    nprod = 0
    jprec = sum(j0)
    if (.not. jprec > 0.0_c_double) jprec = sum(jinf)
    call visco_grid_coefficients(nx, ny, dx, dy, nb, j0, jinf, vlen, c, stat)
    if (stat == STAT_OK) then
        call visco_grid_normal(nx, ny, dx, dy, c, jprec, h, fn, tol, max_iter, p, u, approach, &
                               it, np, resid, stat)
        iters = it
        nprod = np
    end if
    info = stat
end subroutine visco_grid_solve_c

!> A contact workspace (contact_plans) holding the four viscoelastic coefficient fields of nb
!> bodies (contact_viscoelastic_grid::visco_grid_kernels: shear moduli g0, ginf (Pa; g0 = 0
!> rigid), Poisson's ratios nu, memory lengths vlen = V tc (m)), for rolling_solve_c.
!> Free it with contact_ws_free_c. info: the first non-OK status.
subroutine visco_ws_create_c(nx, ny, dx, dy, nb, g0, ginf, nu, vlen, handle, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    use contact_plans, only: ws_create_from
    use contact_viscoelastic_grid, only: visco_grid_kernels
    implicit none
    integer(c_int), intent(in) :: nx, ny, nb
    real(c_double), intent(in) :: dx, dy, g0(nb), ginf(nb), nu(nb), vlen(nb)
    integer(c_int), intent(out) :: handle, info
    real(c_double), allocatable :: c(:, :, :)
    real(c_double) :: j0
    integer :: stat, h, b
    handle = 0
    allocate (c(0:2 * nx - 1, 0:2 * ny - 1, 4))
    call visco_grid_kernels(nx, ny, dx, dy, nb, g0, ginf, nu, vlen, c, stat)
    j0 = 0.0_c_double
    do b = 1, nb
        if (g0(b) > 0.0_c_double) j0 = j0 + (1.0_c_double - nu(b)) / (2.0_c_double * g0(b))
    end do
    if (stat == STAT_OK .and. .not. j0 > 0.0_c_double) stat = STAT_BAD_ARGUMENT
    if (stat == STAT_OK) then
        call ws_create_from(nx, ny, dx, dy, c, 1.0_c_double / j0, 0.0_c_double, h, stat)
        handle = h
    end if
    info = stat
end subroutine visco_ws_create_c
