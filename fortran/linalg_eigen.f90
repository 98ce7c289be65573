!> Generalized symmetric eigenproblems K x = lambda M x (K symmetric, M
!> symmetric positive definite), as met by every FE model in railvti.
module linalg_eigen
    use kinds, only: dp
    implicit none
    private
    public :: eig_sym_range, eig_std_range, chol_solve

    interface
        subroutine dsygvx(itype, jobz, range, uplo, n, a, lda, b, ldb, vl, vu, il, iu, &
                          abstol, m, w, z, ldz, work, lwork, iwork, ifail, info)
            import :: dp
            integer, intent(in) :: itype, n, lda, ldb, il, iu, ldz, lwork
            character, intent(in) :: jobz, range, uplo
            real(dp), intent(inout) :: a(lda, *), b(ldb, *)
            real(dp), intent(in) :: vl, vu, abstol
            integer, intent(out) :: m, iwork(*), ifail(*), info
            real(dp), intent(out) :: w(*), z(ldz, *), work(*)
        end subroutine dsygvx
        subroutine dsyevr(jobz, range, uplo, n, a, lda, vl, vu, il, iu, abstol, m, w, z, ldz, &
                          isuppz, work, lwork, iwork, liwork, info)
            import :: dp
            character, intent(in) :: jobz, range, uplo
            integer, intent(in) :: n, lda, il, iu, ldz, lwork, liwork
            real(dp), intent(inout) :: a(lda, *)
            real(dp), intent(in) :: vl, vu, abstol
            integer, intent(out) :: m, isuppz(*), iwork(*), info
            real(dp), intent(out) :: w(*), z(ldz, *), work(*)
        end subroutine dsyevr
        subroutine dposv(uplo, n, nrhs, a, lda, b, ldb, info)
            import :: dp
            character, intent(in) :: uplo
            integer, intent(in) :: n, nrhs, lda, ldb
            real(dp), intent(inout) :: a(lda, *), b(ldb, *)
            integer, intent(out) :: info
        end subroutine dposv
    end interface

contains

    !> Standard symmetric eigenproblem A x = lambda x: all pairs with lambda in (lam_lo, lam_hi]
    !> by LAPACK dsyevr (MRRR). a is overwritten; x(:, 1:nev) orthonormal, lam ascending.
    subroutine eig_std_range(n, a, lam_lo, lam_hi, nev, lam, x, info)
        integer, intent(in) :: n
        real(dp), intent(inout) :: a(n, n)
        real(dp), intent(in) :: lam_lo, lam_hi
        integer, intent(out) :: nev, info
        real(dp), intent(out) :: lam(n), x(n, n)
        real(dp), allocatable :: work(:)
        integer, allocatable :: iwork(:), isuppz(:)
        real(dp) :: wq(1)
        integer :: iq(1), lwork, liwork

        allocate (isuppz(2 * n))
        call dsyevr('V', 'V', 'U', n, a, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, lam, x, n, &
                    isuppz, wq, -1, iq, -1, info)
        if (info /= 0) return
        lwork = max(int(wq(1)), 26 * n)
        liwork = max(iq(1), 10 * n)
        allocate (work(lwork), iwork(liwork))
        call dsyevr('V', 'V', 'U', n, a, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, lam, x, n, &
                    isuppz, work, lwork, iwork, liwork, info)
    end subroutine eig_std_range

    !> Solve A X = B for symmetric positive definite A (Cholesky, LAPACK dposv).
    !> a is overwritten by its factor, b by the solution. info > 0: A not positive definite.
    subroutine chol_solve(n, nrhs, a, b, info)
        integer, intent(in) :: n, nrhs
        real(dp), intent(inout) :: a(n, n), b(n, nrhs)
        integer, intent(out) :: info
        call dposv('U', n, nrhs, a, n, b, n, info)
    end subroutine chol_solve

    !> All eigenpairs with lambda in (lam_lo, lam_hi] by LAPACK dsygvx.
    !> k and m are overwritten. On return nev pairs sit in lam(1:nev) (ascending)
    !> and x(:, 1:nev), M-normalised (x^T M x = 1). x must have n columns.
    !> info: 0 ok, <0 bad argument of dsygvx, >0 M not positive definite or
    !> eigenvectors that failed to converge (dsygvx's code).
    subroutine eig_sym_range(n, k, m, lam_lo, lam_hi, nev, lam, x, info)
        integer, intent(in) :: n
        real(dp), intent(inout) :: k(n, n), m(n, n)
        real(dp), intent(in) :: lam_lo, lam_hi
        integer, intent(out) :: nev, info
        real(dp), intent(out) :: lam(n), x(n, n)
        real(dp), allocatable :: work(:)
        integer, allocatable :: iwork(:), ifail(:)
        real(dp) :: wq(1)
        integer :: lwork

        allocate (iwork(5 * n), ifail(n))
        call dsygvx(1, 'V', 'V', 'U', n, k, n, m, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, &
                    lam, x, n, wq, -1, iwork, ifail, info)
        if (info /= 0) return
        lwork = max(int(wq(1)), 8 * n)
        allocate (work(lwork))
        call dsygvx(1, 'V', 'V', 'U', n, k, n, m, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, &
                    lam, x, n, work, lwork, iwork, ifail, info)
    end subroutine eig_sym_range

end module linalg_eigen
