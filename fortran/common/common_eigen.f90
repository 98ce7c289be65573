!> Generalized symmetric eigenproblems K x = lambda M x (K symmetric, M
!> symmetric positive definite), as met by every FE model in railvti. Implements no equation
!> (LAPACK dsyevr/dsygvx/dposv and ARPACK shift-invert mode 3, Lehoucq et al. 1998).
!>
!> Every routine returns info = STAT_OK or a STAT_ code of common_status, and the raw
!> LAPACK/ARPACK info in a separate argument (lapack_info, arpack_info) for the message.
module common_eigen
    use common_kinds, only: dp
    use common_lapack, only: dsygvx, dsyevr, dposv, dpbtrf, dpbtrs, dsbmv, dsaupd, dseupd, dlarnv
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_NOT_CONVERGED, STAT_LAPACK, &
                             STAT_EIGEN_FAILED, STAT_NOT_POSITIVE_DEFINITE
    implicit none
    private
    public :: eig_sym_range, eig_std_range, chol_solve, eig_band_lowest


contains

    !> Standard symmetric eigenproblem A x = lambda x: all pairs with lambda in (lam_lo, lam_hi]
    !> by LAPACK dsyevr (MRRR). a is overwritten; x(:, 1:nev) orthonormal, lam ascending.
    !> info: STAT_OK, STAT_LAPACK (an illegal argument) or STAT_EIGEN_FAILED (dsyevr's
    !> internal error); lapack_info: dsyevr's info.
    subroutine eig_std_range(n, a, lam_lo, lam_hi, nev, lam, x, info, lapack_info)
        integer, intent(in) :: n
        real(dp), intent(inout) :: a(n, n)
        real(dp), intent(in) :: lam_lo, lam_hi
        integer, intent(out) :: nev, info, lapack_info
        real(dp), intent(out) :: lam(n), x(n, n)
        real(dp), allocatable :: work(:)
        integer, allocatable :: iwork(:), isuppz(:)
        real(dp) :: wq(1)
        integer :: iq(1), lwork, liwork

        allocate (isuppz(2 * n))
        call dsyevr('V', 'V', 'U', n, a, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, lam, x, n, &
                    isuppz, wq, -1, iq, -1, lapack_info)
        if (lapack_info == 0) then
            lwork = max(int(wq(1)), 26 * n)
            liwork = max(iq(1), 10 * n)
            allocate (work(lwork), iwork(liwork))
            call dsyevr('V', 'V', 'U', n, a, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, lam, x, n, &
                        isuppz, work, lwork, iwork, liwork, lapack_info)
        end if
        if (lapack_info < 0) then
            info = STAT_LAPACK
        else if (lapack_info > 0) then
            info = STAT_EIGEN_FAILED
        else
            info = STAT_OK
        end if
    end subroutine eig_std_range

    !> Solve A X = B for symmetric positive definite A (Cholesky, LAPACK dposv).
    !> a is overwritten by its factor, b by the solution. info: STAT_OK,
    !> STAT_NOT_POSITIVE_DEFINITE or STAT_LAPACK (an illegal argument); lapack_info: dposv's.
    subroutine chol_solve(n, nrhs, a, b, info, lapack_info)
        integer, intent(in) :: n, nrhs
        real(dp), intent(inout) :: a(n, n), b(n, nrhs)
        integer, intent(out) :: info, lapack_info
        call dposv('U', n, nrhs, a, n, b, n, lapack_info)
        if (lapack_info > 0) then
            info = STAT_NOT_POSITIVE_DEFINITE
        else if (lapack_info < 0) then
            info = STAT_LAPACK
        else
            info = STAT_OK
        end if
    end subroutine chol_solve

    !> All eigenpairs with lambda in (lam_lo, lam_hi] by LAPACK dsygvx.
    !> k and m are overwritten. On return nev pairs sit in lam(1:nev) (ascending)
    !> and x(:, 1:nev), M-normalised (x^T M x = 1). x must have n columns.
    !> info: STAT_OK; STAT_LAPACK (an illegal argument of dsygvx); STAT_EIGEN_FAILED
    !> (eigenvectors that failed to converge); STAT_NOT_POSITIVE_DEFINITE (M is not).
    !> lapack_info: dsygvx's info.
    subroutine eig_sym_range(n, k, m, lam_lo, lam_hi, nev, lam, x, info, lapack_info)
        integer, intent(in) :: n
        real(dp), intent(inout) :: k(n, n), m(n, n)
        real(dp), intent(in) :: lam_lo, lam_hi
        integer, intent(out) :: nev, info, lapack_info
        real(dp), intent(out) :: lam(n), x(n, n)
        real(dp), allocatable :: work(:)
        integer, allocatable :: iwork(:), ifail(:)
        real(dp) :: wq(1)
        integer :: lwork

        allocate (iwork(5 * n), ifail(n))
        call dsygvx(1, 'V', 'V', 'U', n, k, n, m, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, &
                    lam, x, n, wq, -1, iwork, ifail, lapack_info)
        if (lapack_info == 0) then
            lwork = max(int(wq(1)), 8 * n)
            allocate (work(lwork))
            call dsygvx(1, 'V', 'V', 'U', n, k, n, m, n, lam_lo, lam_hi, 0, 0, 0.0_dp, nev, &
                        lam, x, n, work, lwork, iwork, ifail, lapack_info)
        end if
        if (lapack_info < 0) then
            info = STAT_LAPACK
        else if (lapack_info > n) then
            info = STAT_NOT_POSITIVE_DEFINITE     ! dsygvx: the order-(info - n) minor of M
        else if (lapack_info > 0) then
            info = STAT_EIGEN_FAILED              ! dsygvx: info eigenvectors did not converge
        else
            info = STAT_OK
        end if
    end subroutine eig_sym_range

    !> The nev lowest eigenpairs of K x = lambda M x, K and M symmetric banded
    !> (upper band storage: a(kd + 1 + i - j, j) = A(i, j), max(1, j - kd) <= i <= j),
    !> by ARPACK's shift-invert mode (dsaupd mode 3) around sigma < lambda_min,
    !> with a banded Cholesky factorisation (dpbtrf) of K - sigma M.
    !> ARPACK is not reentrant: call from one thread at a time.
    !> On return nconv pairs sit in lam(1:nconv) (ascending) and x(:, 1:nconv),
    !> M-normalised. info: STAT_OK; STAT_BAD_ARGUMENT (bad sizes);
    !> STAT_NOT_POSITIVE_DEFINITE (K - sigma M is not: sigma not below the spectrum;
    !> arpack_info = dpbtrf's info); STAT_NOT_CONVERGED (dsaupd stopped early, info 1:
    !> maxit reached, or 3: no shifts could be applied; nconv tells how many converged);
    !> STAT_EIGEN_FAILED (dsaupd or dseupd reported an error, or nothing converged).
    !> arpack_info: the ARPACK (dsaupd, else dseupd) info behind a failure, else 0.
    subroutine eig_band_lowest(n, kd, kb, mb, sigma, nev, ncv, tol, maxit, lam, x, nconv, info, &
                               arpack_info)
        integer, intent(in) :: n, kd, nev, ncv, maxit
        real(dp), intent(in) :: kb(kd + 1, n), mb(kd + 1, n), sigma, tol
        real(dp), intent(out) :: lam(nev), x(n, nev)
        integer, intent(out) :: nconv, info, arpack_info
        real(dp), allocatable :: ab(:, :), resid(:), v(:, :), workd(:), workl(:), d(:), z(:, :)
        logical, allocatable :: sel(:)
        integer :: ido, iparam(11), ipntr(11), lworkl, stat, i, j, nc, ainfo, iseed(4)
        integer, allocatable :: idx(:)
        character(len=1), parameter :: bmat = 'G'
        character(len=2), parameter :: which = 'LM'

        nconv = 0
        lam = 0.0_dp
        x = 0.0_dp
        info = STAT_OK
        arpack_info = 0
        if (n < 2 .or. kd < 0 .or. nev < 1 .or. nev >= n .or. ncv <= nev .or. ncv > n) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        allocate (ab(kd + 1, n))
        ab = kb - sigma * mb
        call dpbtrf('U', n, kd, ab, kd + 1, stat)
        if (stat /= 0) then
            info = STAT_NOT_POSITIVE_DEFINITE
            arpack_info = stat
            return
        end if
        lworkl = ncv * (ncv + 8)
        allocate (resid(n), v(n, ncv), workd(3 * n), workl(lworkl))
        iparam = 0
        iparam(1) = 1
        iparam(3) = maxit
        iparam(7) = 3
        ido = 0
        ! The start vector given (info = 1), the one ARPACK's dgetv0 draws on its first call in a
        ! process (dlarnv, uniform on (-1, 1), seed 1, 3, 5, 7): left to ARPACK, its seed carries
        ! over from call to call, so a solve's last bits would depend on the solves before it.
        iseed = [1, 3, 5, 7]
        call dlarnv(2, iseed, n, resid)
        ainfo = 1
        do
            call dsaupd(ido, bmat, n, which, nev, tol, resid, ncv, v, n, iparam, ipntr, &
                        workd, workl, lworkl, ainfo)
            select case (ido)
            case (-1)
                call dsbmv('U', n, kd, 1.0_dp, mb, kd + 1, workd(ipntr(1)), 1, 0.0_dp, &
                           workd(ipntr(2)), 1)
                call dpbtrs('U', n, kd, 1, ab, kd + 1, workd(ipntr(2)), n, stat)
            case (1)
                workd(ipntr(2):ipntr(2) + n - 1) = workd(ipntr(3):ipntr(3) + n - 1)
                call dpbtrs('U', n, kd, 1, ab, kd + 1, workd(ipntr(2)), n, stat)
            case (2)
                call dsbmv('U', n, kd, 1.0_dp, mb, kd + 1, workd(ipntr(1)), 1, 0.0_dp, &
                           workd(ipntr(2)), 1)
            case default
                exit
            end select
        end do
        if (ainfo < 0) then
            info = STAT_EIGEN_FAILED
            arpack_info = ainfo
            return
        end if
        nc = iparam(5)
        if (nc < 1) then
            info = STAT_EIGEN_FAILED
            arpack_info = ainfo
            return
        end if
        allocate (sel(ncv), d(nev), z(n, nev))
        call dseupd(.true., 'A', sel, d, z, n, sigma, bmat, n, which, nev, tol, resid, ncv, &
                    v, n, iparam, ipntr, workd, workl, lworkl, stat)
        if (stat /= 0) then
            info = STAT_EIGEN_FAILED
            arpack_info = stat
            return
        end if
        nc = min(nc, nev)
        ! dseupd returns ascending values; sort anyway to be safe.
        allocate (idx(nc))
        idx = [(i, i = 1, nc)]
        do i = 2, nc
            j = i
            do while (j > 1)
                if (d(idx(j - 1)) <= d(idx(j))) exit
                idx(j - 1:j) = idx([j, j - 1])
                j = j - 1
            end do
        end do
        do i = 1, nc
            lam(i) = d(idx(i))
            x(:, i) = z(:, idx(i))
        end do
        nconv = nc
        if (ainfo /= 0) then
            info = STAT_NOT_CONVERGED     ! dsaupd info 1 (maxit) or 3 (no shifts)
            arpack_info = ainfo
        end if
    end subroutine eig_band_lowest

end module common_eigen
