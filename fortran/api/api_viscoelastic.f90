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
    if (stat == STAT_OK) call visco_line_normal(n, d, h, k, fn, tol, max_iter, p, u, approach, &
                                                it, resid, stat)
    if (stat == STAT_OK) iters = it
    info = stat
end subroutine visco_line_solve_c
