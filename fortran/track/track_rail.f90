!> Rail modes per wave number on a reduced basis. K(kappa) = K0 + kappa K1 + kappa^2 K2 is
!> polynomial in kappa, so one basis W that holds the section modes (up to lam_max) and the
!> static responses to the load vectors at a few sample wave numbers represents the modes at
!> every kappa in between (reduced-basis / parametric model order reduction, as for
!> wave-finite-element dispersion curves). The dense solves are then done ns times on the full
!> section and nk times on the small reduced matrices.
!> Implements Kaiser eq. 13 per wave number (the modes of K(kappa)); the reduced basis is a
!> numerical device, not an equation of the paper.
module track_rail
    use common_kinds, only: dp
    use common_eigen, only: eig_sym_range, eig_std_range, chol_solve
    use common_status, only: STAT_OK, STAT_SIZE_MISMATCH, STAT_EIGEN_FAILED
    implicit none
    private
    public :: rail_reduced_basis, rail_wave_basis

contains

    !> Add v to the M-orthonormal set w(:, 1:r) (Gram-Schmidt twice), unless it is dependent.
    subroutine add_vector(n, m, v, rmax, r, w, mw)
        integer, intent(in) :: n, rmax
        real(dp), intent(in) :: m(n, n)
        real(dp), intent(inout) :: v(n)
        integer, intent(inout) :: r
        real(dp), intent(inout) :: w(n, rmax), mw(n, rmax)
        real(dp) :: mv(n), nrm0, nrm
        integer :: pass
        if (r >= rmax) return
        mv = matmul(m, v)
        nrm0 = sqrt(max(dot_product(v, mv), 0.0_dp))
        if (nrm0 <= 0) return
        do pass = 1, 2
            if (r > 0) then
                v = v - matmul(w(:, 1:r), matmul(transpose(mw(:, 1:r)), v))
            end if
        end do
        mv = matmul(m, v)
        nrm = sqrt(max(dot_product(v, mv), 0.0_dp))
        if (nrm < 1.0e-7_dp * nrm0) return
        r = r + 1
        w(:, r) = v / nrm
        mw(:, r) = mv / nrm
    end subroutine add_vector

    !> Reduced basis from ns sample wave numbers kap_s: section modes with
    !> lambda = omega^2 <= lam_max and the responses (K + shift M)^-1 f to the nf loads.
    !> On return w(:, 1:r) is M-orthonormal and kr_i = W^T K_i W, fr = W^T f; r = rmax
    !> means the basis filled up (vectors beyond rmax were dropped).
    !> info: STAT_OK, or the eigen-solver's / Cholesky's STAT_ code (common_eigen) at sample
    !> wave number kap_s(sample), with LAPACK's info in lapack_info (sample = 0 if ok).
    subroutine rail_reduced_basis(n, k0, k1, k2, m, nf, f, ns, kap_s, lam_max, rmax, r, w, &
                                  k0r, k1r, k2r, fr, info, sample, lapack_info)
        integer, intent(in) :: n, nf, ns, rmax
        real(dp), intent(in), dimension(n, n) :: k0, k1, k2, m
        real(dp), intent(in) :: f(n, nf), kap_s(ns), lam_max
        integer, intent(out) :: r, info, sample, lapack_info
        real(dp), intent(out) :: w(n, rmax), k0r(rmax, rmax), k1r(rmax, rmax), k2r(rmax, rmax)
        real(dp), intent(out) :: fr(rmax, nf)
        real(dp), allocatable :: a(:, :), b(:, :), x(:, :), lam(:), mw(:, :), rhs(:, :), v(:)
        real(dp) :: shift
        integer :: s, i, nev

        info = STAT_OK
        sample = 0
        lapack_info = 0
        r = 0
        w = 0; k0r = 0; k1r = 0; k2r = 0; fr = 0
        allocate (a(n, n), b(n, n), x(n, n), lam(n), mw(n, rmax), rhs(n, nf), v(n))
        shift = 1.0e-4_dp * lam_max      ! makes K(0) (rigid-body modes) invertible
        do s = 1, ns
            a = k0 + kap_s(s) * k1 + kap_s(s)**2 * k2
            b = m
            call eig_sym_range(n, a, b, -1.0e-3_dp * lam_max, lam_max, nev, lam, x, info, lapack_info)
            if (info /= STAT_OK) then
                sample = s
                return
            end if
            do i = 1, nev
                v = x(:, i)
                call add_vector(n, m, v, rmax, r, w, mw)
            end do
            a = k0 + kap_s(s) * k1 + kap_s(s)**2 * k2 + shift * m
            rhs = f
            call chol_solve(n, nf, a, rhs, info, lapack_info)
            if (info /= STAT_OK) then
                sample = s
                return
            end if
            do i = 1, nf
                v = rhs(:, i)
                call add_vector(n, m, v, rmax, r, w, mw)
            end do
        end do
        k0r(1:r, 1:r) = matmul(transpose(w(:, 1:r)), matmul(k0, w(:, 1:r)))
        k1r(1:r, 1:r) = matmul(transpose(w(:, 1:r)), matmul(k1, w(:, 1:r)))
        k2r(1:r, 1:r) = matmul(transpose(w(:, 1:r)), matmul(k2, w(:, 1:r)))
        fr(1:r, :) = matmul(transpose(w(:, 1:r)), f)
    end subroutine rail_reduced_basis

    !> Rail basis at each of nk wave numbers, in reduced coordinates: the modes with
    !> omega^2 <= lam_cut, then the residual static responses to the nf loads (the part
    !> the dropped modes carry), made K-diagonal by a small Ritz step. Columns are
    !> orthonormal (reduced M = I) and y^T K y = diag(om2).
    !> nm(k): number of basis vectors at kappa(k). info: STAT_OK; STAT_SIZE_MISMATCH (more
    !> than mmax vectors at kap(wave): enlarge mmax); the eigen-solver's or Cholesky's STAT_
    !> code (common_eigen) at kap(wave), with LAPACK's info in lapack_info. wave = 0 if ok.
    subroutine rail_wave_basis(r, k0r, k1r, k2r, nf, fr, nk, kap, lam_cut, mmax, nm, om2, y, info, &
                               wave, lapack_info)
        integer, intent(in) :: r, nf, nk, mmax
        real(dp), intent(in), dimension(r, r) :: k0r, k1r, k2r
        real(dp), intent(in) :: fr(r, nf), kap(nk), lam_cut
        integer, intent(out) :: nm(nk), info, wave, lapack_info
        real(dp), intent(out) :: om2(mmax, nk), y(r, mmax, nk)
        real(dp), allocatable :: a(:, :), kk(:, :), x(:, :), lam(:), z(:, :), q(:, :), sm(:, :)
        real(dp), allocatable :: sx(:, :), sl(:)
        real(dp) :: shift, nrm, nrm0
        integer :: ik, nev, i, j, nz, nsev

        info = STAT_OK
        wave = 0
        lapack_info = 0
        nm = 0; om2 = 0; y = 0
        allocate (a(r, r), kk(r, r), x(r, r), lam(r), z(r, nf), q(r, nf), sm(nf, nf), sx(nf, nf), sl(nf))
        shift = 1.0e-4_dp * lam_cut
        do ik = 1, nk
            kk = k0r + kap(ik) * k1r + kap(ik)**2 * k2r
            a = kk
            call eig_std_range(r, a, -1.0e-3_dp * lam_cut, lam_cut, nev, lam, x, info, lapack_info)
            if (info /= STAT_OK) then
                wave = ik
                return
            end if
            ! Residual attachment vectors: (K + shift)^-1 f minus its kept-mode part.
            a = kk
            do i = 1, r
                a(i, i) = a(i, i) + shift
            end do
            z = fr
            call chol_solve(r, nf, a, z, info, lapack_info)
            if (info /= STAT_OK) then
                wave = ik
                return
            end if
            if (nev > 0) z = z - matmul(x(:, 1:nev), matmul(transpose(x(:, 1:nev)), z))
            ! Orthonormalise (deflating dependent ones) against each other.
            nz = 0
            do i = 1, nf
                nrm0 = norm2(z(:, i))
                if (nrm0 <= 0) cycle
                do j = 1, 2
                    if (nz > 0) z(:, i) = z(:, i) - matmul(q(:, 1:nz), matmul(transpose(q(:, 1:nz)), z(:, i)))
                    if (nev > 0) z(:, i) = z(:, i) - matmul(x(:, 1:nev), matmul(transpose(x(:, 1:nev)), z(:, i)))
                end do
                nrm = norm2(z(:, i))
                if (nrm < 1.0e-8_dp * nrm0) cycle
                nz = nz + 1
                q(:, nz) = z(:, i) / nrm
            end do
            if (nev + nz > mmax) then
                info = STAT_SIZE_MISMATCH
                wave = ik
                return
            end if
            nm(ik) = nev + nz
            om2(1:nev, ik) = max(lam(1:nev), 0.0_dp)
            y(:, 1:nev, ik) = x(:, 1:nev)
            if (nz > 0) then
                sm(1:nz, 1:nz) = matmul(transpose(q(:, 1:nz)), matmul(kk, q(:, 1:nz)))
                call eig_std_range(nz, sm(1:nz, 1:nz), -huge(1.0_dp), huge(1.0_dp), nsev, sl, &
                                   sx(1:nz, 1:nz), info, lapack_info)
                if (info == STAT_OK .and. nsev /= nz) info = STAT_EIGEN_FAILED
                if (info /= STAT_OK) then
                    wave = ik
                    return
                end if
                om2(nev + 1:nev + nz, ik) = sl(1:nz)
                y(:, nev + 1:nev + nz, ik) = matmul(q(:, 1:nz), sx(1:nz, 1:nz))
            end if
        end do
    end subroutine rail_wave_basis

end module track_rail
