!> f2py shims for the shared numerical pieces of fortran/common (Anderson
!> mixing, small dense solves), so that tests can check them against numpy.
!> Plain arrays, explicit shapes, a status code `info` from common_status.
!> Implements no equation.

!> a^-1 of a general n x n matrix by LU (common_dense::dense_inverse).
!> info: STAT_OK, STAT_SINGULAR, STAT_LAPACK or STAT_BAD_ARGUMENT.
subroutine dense_inverse_c(n, a, ainv, info)
    use iso_c_binding, only: c_int, c_double
    use common_dense, only: dense_inverse
    implicit none
    integer(c_int), intent(in) :: n
    real(c_double), intent(in) :: a(n, n)
    real(c_double), intent(out) :: ainv(n, n)
    integer(c_int), intent(out) :: info
    integer :: stat
    ainv = a
    call dense_inverse(n, ainv, stat)
    info = stat
end subroutine dense_inverse_c

!> x = h^-1 b for a small symmetric positive definite h (common_dense::spd_solve_small;
!> the lower triangle of h is read). info: STAT_OK or STAT_NOT_POSITIVE_DEFINITE.
subroutine spd_solve_small_c(n, h, b, x, info)
    use iso_c_binding, only: c_int, c_double
    use common_dense, only: spd_solve_small
    implicit none
    integer(c_int), intent(in) :: n
    real(c_double), intent(in) :: h(n, n), b(n)
    real(c_double), intent(out) :: x(n)
    integer(c_int), intent(out) :: info
    real(c_double) :: hw(n, n)
    integer :: stat
    hw = h
    x = b
    call spd_solve_small(n, hw, x, stat)
    info = stat
end subroutine spd_solve_small_c

!> Anderson mixing (common_anderson, depth `depth`) of the affine fixed-point
!> map x = G x + b from x0, until ||G(x) - x|| <= tol ||G(x)|| or max_iter steps.
!> restart_at > 0: anderson_restart before the evaluation at that iteration.
!> xs(:, k + 1): the iterate evaluated at iteration k = 0..iters; x: the last one;
!> resid: its relative residual. info: STAT_OK or STAT_NOT_CONVERGED.
subroutine anderson_affine_c(n, g, b, x0, depth, max_iter, tol, restart_at, x, xs, iters, resid, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED
    use common_anderson, only: anderson_state, anderson_init, anderson_step, anderson_restart
    implicit none
    integer(c_int), intent(in) :: n, depth, max_iter, restart_at
    real(c_double), intent(in) :: g(n, n), b(n), x0(n), tol
    real(c_double), intent(out) :: x(n), xs(n, max_iter + 1), resid
    integer(c_int), intent(out) :: iters, info
    type(anderson_state) :: s
    real(c_double) :: gx(n)
    integer :: it
    xs = 0.0_c_double
    info = STAT_OK
    call anderson_init(s, x0, depth)
    it = 0
    do
        if (it == restart_at .and. it > 0) call anderson_restart(s)
        xs(:, it + 1) = s%x
        gx = matmul(g, s%x) + b
        resid = norm2(gx - s%x) / max(norm2(gx), tiny(1.0_c_double))
        if (resid <= tol) exit
        if (it >= max_iter) then
            info = STAT_NOT_CONVERGED
            exit
        end if
        call anderson_step(s, gx)
        it = it + 1
    end do
    iters = it
    x = s%x
end subroutine anderson_affine_c
