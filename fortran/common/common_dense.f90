!> Small dense linear algebra shared by the kernels: the inverse of a general
!> matrix by LAPACK's LU (dgetrf + dgetri) and the solve of a small symmetric
!> positive definite system by an in-line Cholesky factorization.
!> Implements no equation (standard LU and Cholesky factorizations; Golub & Van
!> Loan, Matrix Computations, 4th ed., algorithms 3.4.1 and 4.2.1).
module common_dense
    use common_kinds, only: dp
    use common_lapack, only: dgetrf, dgetri
    use common_status, only: STAT_OK, STAT_SINGULAR, STAT_LAPACK, STAT_NOT_POSITIVE_DEFINITE, &
                             STAT_BAD_ARGUMENT
    implicit none
    private
    public :: dense_inverse, spd_solve_small

contains

    !> a <- a^-1 for a general n x n matrix, by LU with partial pivoting
    !> (dgetrf) and dgetri. info: STAT_OK; STAT_SINGULAR when a pivot of the
    !> LU factors is exactly zero; STAT_LAPACK for an illegal-argument report;
    !> STAT_BAD_ARGUMENT for n < 1 or a smaller than n x n.
    subroutine dense_inverse(n, a, info)
        integer, intent(in) :: n
        real(dp), intent(inout) :: a(:, :)   ! (n, n): the matrix in, its inverse out
        integer, intent(out) :: info
        integer, allocatable :: ipiv(:)
        real(dp), allocatable :: work(:)
        integer :: lstat
        info = STAT_OK
        if (n < 1 .or. size(a, 1) < n .or. size(a, 2) < n) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        allocate (ipiv(n), work(64 * n))
        call dgetrf(n, n, a, size(a, 1), ipiv, lstat)
        if (lstat == 0) call dgetri(n, a, size(a, 1), ipiv, work, size(work), lstat)
        if (lstat > 0) then
            info = STAT_SINGULAR
        else if (lstat < 0) then
            info = STAT_LAPACK
        end if
    end subroutine dense_inverse

    !> Solve h x = b in place (b <- x) for a small symmetric positive definite
    !> h of order m, by the Cholesky factorization h = L L^T written into the
    !> lower triangle of h (the upper triangle is not read). In line rather
    !> than LAPACK: for the few-by-few systems of Anderson mixing a LAPACK call
    !> would wake OpenBLAS's threads at every iteration.
    !> info: STAT_OK, or STAT_NOT_POSITIVE_DEFINITE when a pivot is <= 0
    !> (h and b are then partly overwritten).
    pure subroutine spd_solve_small(m, h, b, info)
        integer, intent(in) :: m
        real(dp), intent(inout) :: h(:, :)   ! (m, m) at least: the matrix in, L in its lower triangle out
        real(dp), intent(inout) :: b(:)      ! (m) at least: right-hand side in, solution out
        integer, intent(out) :: info
        integer :: a, c
        info = STAT_OK
        do c = 1, m
            h(c, c) = h(c, c) - sum(h(c, 1:c - 1)**2)
            if (h(c, c) <= 0.0_dp) then
                info = STAT_NOT_POSITIVE_DEFINITE
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
    end subroutine spd_solve_small

end module common_dense
