!> Explicit interfaces of every LAPACK, BLAS and ARPACK routine the kernels call, declared once.
!> Implements no equation. A kernel writes `use common_lapack, only: dgetrf, dgetrs`.
!> ARPACK's reverse-communication routines keep internal `save` state: they are not
!> reentrant, so never call them from two threads at once.
module common_lapack
    use common_kinds, only: dp
    implicit none
    private
    public :: dgetrf, dgetrs, dgetri, dgesv, zgesv
    public :: dposv, dpbtrf, dpbtrs, dsygvx, dsyevr
    public :: dsbmv, dlarnv
    public :: dsaupd, dseupd

    interface
        ! --- LU (general) ---
        subroutine dgetrf(m, n, a, lda, ipiv, info)
            import :: dp
            integer, intent(in) :: m, n, lda
            real(dp), intent(inout) :: a(lda, *)
            integer, intent(out) :: ipiv(*), info
        end subroutine dgetrf
        subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: dp
            character, intent(in) :: trans
            integer, intent(in) :: n, nrhs, lda, ldb
            real(dp), intent(in) :: a(lda, *)
            integer, intent(in) :: ipiv(*)
            real(dp), intent(inout) :: b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgetrs
        subroutine dgetri(n, a, lda, ipiv, work, lwork, info)
            import :: dp
            integer, intent(in) :: n, lda, lwork
            real(dp), intent(inout) :: a(lda, *), work(*)
            integer, intent(in) :: ipiv(*)
            integer, intent(out) :: info
        end subroutine dgetri
        subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: dp
            integer, intent(in) :: n, nrhs, lda, ldb
            real(dp), intent(inout) :: a(lda, *), b(ldb, *)
            integer, intent(out) :: ipiv(*), info
        end subroutine dgesv
        subroutine zgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: dp
            integer, intent(in) :: n, nrhs, lda, ldb
            complex(dp), intent(inout) :: a(lda, *), b(ldb, *)
            integer, intent(out) :: ipiv(*), info
        end subroutine zgesv

        ! --- Cholesky (dense and band) ---
        subroutine dposv(uplo, n, nrhs, a, lda, b, ldb, info)
            import :: dp
            character, intent(in) :: uplo
            integer, intent(in) :: n, nrhs, lda, ldb
            real(dp), intent(inout) :: a(lda, *), b(ldb, *)
            integer, intent(out) :: info
        end subroutine dposv
        subroutine dpbtrf(uplo, n, kd, ab, ldab, info)
            import :: dp
            character, intent(in) :: uplo
            integer, intent(in) :: n, kd, ldab
            real(dp), intent(inout) :: ab(ldab, *)
            integer, intent(out) :: info
        end subroutine dpbtrf
        subroutine dpbtrs(uplo, n, kd, nrhs, ab, ldab, b, ldb, info)
            import :: dp
            character, intent(in) :: uplo
            integer, intent(in) :: n, kd, nrhs, ldab, ldb
            real(dp), intent(in) :: ab(ldab, *)
            real(dp), intent(inout) :: b(ldb, *)
            integer, intent(out) :: info
        end subroutine dpbtrs

        ! --- symmetric eigenproblems ---
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

        ! --- BLAS ---
        subroutine dsbmv(uplo, n, k, alpha, a, lda, x, incx, beta, y, incy)
            import :: dp
            character, intent(in) :: uplo
            integer, intent(in) :: n, k, lda, incx, incy
            real(dp), intent(in) :: alpha, beta, a(lda, *), x(*)
            real(dp), intent(inout) :: y(*)
        end subroutine dsbmv

        ! --- random vector (LAPACK auxiliary) ---
        subroutine dlarnv(idist, iseed, n, x)
            import :: dp
            integer, intent(in) :: idist, n
            integer, intent(inout) :: iseed(4)
            real(dp), intent(out) :: x(*)
        end subroutine dlarnv

        ! --- ARPACK (symmetric, reverse communication) ---
        subroutine dsaupd(ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, ipntr, &
                          workd, workl, lworkl, info)
            import :: dp
            integer, intent(inout) :: ido, iparam(11), info
            character, intent(in) :: bmat
            character(len=2), intent(in) :: which
            integer, intent(in) :: n, nev, ncv, ldv, lworkl
            real(dp), intent(in) :: tol
            real(dp), intent(inout) :: resid(*), v(ldv, *), workd(*), workl(*)
            integer, intent(out) :: ipntr(11)
        end subroutine dsaupd
        subroutine dseupd(rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, tol, &
                          resid, ncv, v, ldv, iparam, ipntr, workd, workl, lworkl, info)
            import :: dp
            logical, intent(in) :: rvec
            character, intent(in) :: howmny, bmat
            character(len=2), intent(in) :: which
            logical, intent(inout) :: select(*)
            integer, intent(in) :: ldz, n, nev, ncv, ldv, lworkl
            real(dp), intent(out) :: d(*), z(ldz, *)
            real(dp), intent(in) :: sigma, tol
            real(dp), intent(inout) :: resid(*), v(ldv, *), workd(*), workl(*)
            integer, intent(inout) :: iparam(11), ipntr(11)
            integer, intent(out) :: info
        end subroutine dseupd
    end interface
end module common_lapack
