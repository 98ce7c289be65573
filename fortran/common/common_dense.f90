!> Small dense linear algebra shared by the kernels: the inverse of a general
!> matrix by LAPACK's LU (dgetrf + dgetri), the solve of a small symmetric
!> positive definite system by an in-line Cholesky factorization, and an in-line
!> LU with partial pivoting in single precision for general systems of a few dozen unknowns
!> where an approximate solve serves (lu_factor_small, lu_solve_small: a chord iteration's
!> Jacobian; plain loops, so the same bits whatever BLAS kernel or threads).
!> Implements no equation (standard LU and Cholesky factorizations; Golub & Van
!> Loan, Matrix Computations, 4th ed., algorithms 3.4.1 and 4.2.1).
module common_dense
    use common_kinds, only: dp, sp
    use common_lapack, only: dgetrf, dgetri
    use common_status, only: STAT_OK, STAT_SINGULAR, STAT_LAPACK, STAT_NOT_POSITIVE_DEFINITE, &
                             STAT_BAD_ARGUMENT
    implicit none
    private
    public :: dense_inverse, spd_solve_small, lu_factor_small, lu_solve_small

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

    !> a = P L U in place (Golub & Van Loan alg. 3.4.1 with partial pivoting, row
    !> interchanges applied to whole rows): L unit lower (below the diagonal), U upper, piv
    !> the rows interchanged at each step. In panels of LU_PANEL = 4 columns (alg. 3.2.6's
    !> blocking, written out for 4): a panel is factored on its own columns, then the trailing
    !> columns take its 4 rank-one updates in one pass (each element loaded and stored once per panel,
    !> not once per column: the update is bound by those loads and stores).
    !> Single precision (twice the elements per SSE2 instruction): the factor of a chord
    !> iteration's Jacobian, whose steps are judged on residuals formed in double precision.
    !> info: STAT_OK, or STAT_SINGULAR for a zero or non-finite pivot.
    pure subroutine lu_factor_small(a, piv, info)
        real(sp), intent(inout) :: a(:, :)   ! (m, m)
        integer, intent(out) :: piv(:)       ! (m)
        integer, intent(out) :: info
        integer, parameter :: LU_PANEL = 4
        integer :: m, k, k0, k1, j, p, i
        real(sp) :: t, r, u1, u2, u3, u4
        m = size(a, 1)
        info = STAT_SINGULAR
        do k0 = 1, m, LU_PANEL
            k1 = min(m, k0 + LU_PANEL - 1)
            do k = k0, k1   ! the panel k0..k1, updated within itself only
                p = k - 1 + maxloc(abs(a(k:m, k)), 1)
                piv(k) = p
                if (.not. (abs(a(p, k)) > 0.0_sp .and. abs(a(p, k)) <= huge(1.0_sp))) return
                if (p /= k) then
                    do j = 1, m
                        t = a(k, j)
                        a(k, j) = a(p, j)
                        a(p, j) = t
                    end do
                end if
                r = 1.0_sp / a(k, k)
                a(k + 1:m, k) = a(k + 1:m, k) * r
                do j = k + 1, k1
                    a(k + 1:m, j) = a(k + 1:m, j) - a(k + 1:m, k) * a(k, j)
                end do
            end do
            ! the trailing columns (only after a full panel: a short one is the last)
            do j = k1 + 1, m
                ! the panel's rows of U in column j (unit lower triangular solve), then the
                ! panel's LU_PANEL rank-one updates below it at once
                u1 = a(k0, j)
                u2 = a(k0 + 1, j) - a(k0 + 1, k0) * u1
                u3 = a(k0 + 2, j) - a(k0 + 2, k0) * u1 - a(k0 + 2, k0 + 1) * u2
                u4 = a(k0 + 3, j) - a(k0 + 3, k0) * u1 - a(k0 + 3, k0 + 1) * u2 - a(k0 + 3, k0 + 2) * u3
                a(k0 + 1, j) = u2
                a(k0 + 2, j) = u3
                a(k0 + 3, j) = u4
                do i = k1 + 1, m
                    a(i, j) = a(i, j) - (a(i, k0) * u1 + a(i, k0 + 1) * u2 + a(i, k0 + 2) * u3 + a(i, k0 + 3) * u4)
                end do
            end do
        end do
        info = STAT_OK
    end subroutine lu_factor_small

    !> x from P L U x = b in place (b <- x), the factors of lu_factor_small (single precision).
    pure subroutine lu_solve_small(a, piv, b)
        real(sp), intent(in) :: a(:, :)
        integer, intent(in) :: piv(:)
        real(sp), intent(inout) :: b(:)
        integer :: m, k
        real(sp) :: t
        m = size(a, 1)
        do k = 1, m
            if (piv(k) /= k) then
                t = b(k)
                b(k) = b(piv(k))
                b(piv(k)) = t
            end if
        end do
        do k = 1, m - 1   ! L z = P b by columns
            b(k + 1:m) = b(k + 1:m) - a(k + 1:m, k) * b(k)
        end do
        do k = m, 1, -1   ! U x = z by columns
            b(k) = b(k) / a(k, k)
            b(1:k - 1) = b(1:k - 1) - a(1:k - 1, k) * b(k)
        end do
    end subroutine lu_solve_small

end module common_dense
