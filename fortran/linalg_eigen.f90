!> Generalized symmetric eigenproblems K x = lambda M x (K symmetric, M
!> symmetric positive definite), as met by every FE model in railvti.
module linalg_eigen
    use kinds, only: dp
    implicit none
    private
    public :: eig_sym_range

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
    end interface

contains

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
