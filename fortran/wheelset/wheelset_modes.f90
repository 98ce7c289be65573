!> Eigenmodes of one circumferential harmonic k of an axisymmetric body meshed
!> with nine-node meridian elements (wheelset_element): DOF numbering with the
!> regularity conditions on the axis, banded assembly, springs to the ground,
!> the lowest modes up to a frequency bound, and the modal Coriolis and
!> centrifugal matrices of the rotating body. Implements Kaiser eqs 6 and 8-10 (the modes of
!> harmonic k, double for k > 0), the modal matrices of the axle-fixed model (eq. 11) and the
!> modal terms of eqs 1-5 (Gamma, Mc, K_sigma); 1-5 and 8 numbered by inference (docs/equations.md).
module wheelset_modes
    use common_kinds, only: dp
    use common_lapack, only: dpbtrf, dpbtrs
    use wheelset_element, only: axisym_element, axisym_prestress, axisym_geometric, NEN, NDOF_E, NGP
    use common_eigen, only: eig_sym_range, eig_band_lowest
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_SIZE_MISMATCH, STAT_BAD_ELEMENT, &
                             STAT_NOT_CONVERGED, STAT_SINGULAR
    implicit none
    private
    public :: harmonic_modes

    !> Meshes with at most this many equations go to the dense LAPACK solver.
    integer, parameter :: DENSE_MAX = 600

contains

    !> Equation numbers of the nodal amplitudes (U_r, U_y, U_th) for harmonic k.
    !> Regularity on the axis (r = 0): k = 0: U_r = U_th = 0; k = 1: U_y = 0 and
    !> U_th = -U_r (a rigid translation; sgn = -1 on the shared equation);
    !> k >= 2: all zero. fixed(3, nn) /= 0 clamps a component.
    !> eq(c, i) = 0 for a removed component.
    pure subroutine dof_map(nn, xn, k, fixed, eq, sgn, neq)
        integer, intent(in) :: nn, k
        real(dp), intent(in) :: xn(2, nn)
        integer, intent(in) :: fixed(3, nn)
        integer, intent(out) :: eq(3, nn), neq
        real(dp), intent(out) :: sgn(3, nn)
        real(dp) :: tol
        integer :: i, c
        tol = 1.0e-9_dp * max(maxval(abs(xn(1, :))), 1.0e-30_dp)
        neq = 0
        sgn = 1.0_dp
        eq = 0
        do i = 1, nn
            if (xn(1, i) <= tol) then
                select case (k)
                case (0)
                    if (fixed(2, i) == 0) then
                        neq = neq + 1
                        eq(2, i) = neq
                    end if
                case (1)
                    if (fixed(1, i) == 0 .and. fixed(3, i) == 0) then
                        neq = neq + 1
                        eq(1, i) = neq
                        eq(3, i) = neq
                        sgn(3, i) = -1.0_dp
                    end if
                end select
            else
                do c = 1, 3
                    if (fixed(c, i) == 0) then
                        neq = neq + 1
                        eq(c, i) = neq
                    end if
                end do
            end if
        end do
    end subroutine dof_map

    !> Half-bandwidth of the assembled matrices.
    pure integer function band_width(nn, ne, conn, eq) result(kd)
        integer, intent(in) :: nn, ne, conn(NEN, ne), eq(3, nn)
        integer :: e, lo, hi, a, c, q
        kd = 0
        do e = 1, ne
            lo = huge(1)
            hi = 0
            do a = 1, NEN
                do c = 1, 3
                    q = eq(c, conn(a, e))
                    if (q > 0) then
                        lo = min(lo, q)
                        hi = max(hi, q)
                    end if
                end do
            end do
            if (hi > 0) kd = max(kd, hi - lo)
        end do
    end function band_width

    !> Stiffness and mass in upper band storage (kd + 1, neq).
    !> info: STAT_OK, STAT_BAD_ELEMENT (element bad_element has a non-positive Jacobian).
    subroutine assemble_band(nn, ne, xn, conn, k, e_mod, nu, rho, eq, sgn, neq, kd, kb, mb, info, &
                             bad_element)
        integer, intent(in) :: nn, ne, k, conn(NEN, ne), eq(3, nn), neq, kd
        real(dp), intent(in) :: xn(2, nn), e_mod, nu, rho, sgn(3, nn)
        real(dp), intent(out) :: kb(kd + 1, neq), mb(kd + 1, neq)
        integer, intent(out) :: info, bad_element
        real(dp) :: ke(NDOF_E, NDOF_E), me(NDOF_E, NDOF_E), ce(NDOF_E, NDOF_E), mc(NDOF_E, NDOF_E)
        real(dp) :: xe(2, NEN), s(NDOF_E)
        integer :: g(NDOF_E), e, a, c, i, j, gi, gj
        kb = 0.0_dp
        mb = 0.0_dp
        bad_element = 0
        do e = 1, ne
            xe = xn(:, conn(:, e))
            call axisym_element(k, xe, e_mod, nu, rho, ke, me, ce, mc, info)
            if (info /= STAT_OK) then
                bad_element = e
                return
            end if
            do a = 1, NEN
                do c = 1, 3
                    g(3 * (a - 1) + c) = eq(c, conn(a, e))
                    s(3 * (a - 1) + c) = sgn(c, conn(a, e))
                end do
            end do
            do j = 1, NDOF_E
                gj = g(j)
                if (gj == 0) cycle
                do i = 1, NDOF_E
                    gi = g(i)
                    if (gi == 0 .or. gi > gj) cycle
                    kb(kd + 1 + gi - gj, gj) = kb(kd + 1 + gi - gj, gj) + s(i) * s(j) * ke(i, j)
                    mb(kd + 1 + gi - gj, gj) = mb(kd + 1 + gi - gj, gj) + s(i) * s(j) * me(i, j)
                end do
            end do
        end do
    end subroutine assemble_band

    !> Modes of harmonic k with lambda = omega^2 <= lam_max (at most nmax).
    !> fixed(3, nn): clamped components. Springs to the ground: nspr of them,
    !> on component spr_comp (1 r, 2 y, 3 th) of node spr_node, stiffness spr_k
    !> (N/m; for k = 1 on an axis node component 1 is the transverse translation).
    !> Out: nm modes, lam(1:nm) ascending, phi(3, nn, 1:nm) nodal amplitudes
    !> normalised to unit modal mass; gam(nm, nm) = Phi^T C Phi (Coriolis, to be
    !> multiplied by 2 Omega) and mcq = Phi^T Mc Phi (centrifugal softening,
    !> to be multiplied by Omega^2). neq: equations, kd: half-bandwidth.
    !> info: STAT_OK; STAT_BAD_ARGUMENT (k < 0, nmax < 1, lam_max <= 0, or fewer than two
    !> free DOFs left); STAT_SIZE_MISMATCH (nn < 9, ne < 1, a node number of conn or of a
    !> spring out of range, a spring component not 1..3); STAT_BAD_ELEMENT (element
    !> bad_element is inverted or has r <= 0); STAT_SINGULAR (the k = 0 system of the
    !> centrifugal prestress could not be factorised); STAT_NOT_CONVERGED (the eigen-solver
    !> stopped before all wanted modes converged: nm modes kept); or the eigen-solver's code
    !> (STAT_NOT_POSITIVE_DEFINITE: K - sigma M or M is not; STAT_EIGEN_FAILED, STAT_LAPACK),
    !> with the LAPACK/ARPACK info in solver_info.
    subroutine harmonic_modes(nn, ne, xn, conn, k, e_mod, nu, rho, fixed, nspr, spr_node, &
                              spr_comp, spr_k, lam_max, nmax, nm, lam, phi, gam, mcq, kgq, neq, kd, &
                              info, bad_element, solver_info)
        integer, intent(in) :: nn, ne, k, conn(NEN, ne), fixed(3, nn), nspr, nmax
        integer, intent(in) :: spr_node(nspr), spr_comp(nspr)
        real(dp), intent(in) :: xn(2, nn), e_mod, nu, rho, spr_k(nspr), lam_max
        integer, intent(out) :: nm, neq, kd, info, bad_element, solver_info
        real(dp), intent(out) :: lam(nmax), phi(3, nn, nmax), gam(nmax, nmax), mcq(nmax, nmax)
        real(dp), intent(out) :: kgq(nmax, nmax)
        integer :: eq(3, nn), i, j, q, nev, ncv, nconv, stat
        real(dp) :: sgn(3, nn), sigma
        real(dp), allocatable :: kb(:, :), mb(:, :), kf(:, :), mf(:, :), w(:), z(:, :)

        nm = 0
        lam = 0.0_dp
        phi = 0.0_dp
        gam = 0.0_dp
        mcq = 0.0_dp
        kgq = 0.0_dp
        neq = 0
        kd = 0
        info = STAT_OK
        bad_element = 0
        solver_info = 0
        if (nmax < 1 .or. k < 0 .or. lam_max <= 0.0_dp) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        if (nn < NEN .or. ne < 1) then
            info = STAT_SIZE_MISMATCH
            return
        end if
        if (minval(conn) < 1 .or. maxval(conn) > nn) then
            info = STAT_SIZE_MISMATCH
            return
        end if
        call dof_map(nn, xn, k, fixed, eq, sgn, neq)
        if (neq < 2) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        kd = band_width(nn, ne, conn, eq)
        allocate (kb(kd + 1, neq), mb(kd + 1, neq))
        call assemble_band(nn, ne, xn, conn, k, e_mod, nu, rho, eq, sgn, neq, kd, kb, mb, info, &
                           bad_element)
        if (info /= STAT_OK) return
        do i = 1, nspr
            if (spr_node(i) < 1 .or. spr_node(i) > nn .or. spr_comp(i) < 1 .or. spr_comp(i) > 3) then
                info = STAT_SIZE_MISMATCH
                return
            end if
            q = eq(spr_comp(i), spr_node(i))
            if (q > 0) kb(kd + 1, q) = kb(kd + 1, q) + spr_k(i)
        end do

        if (neq <= DENSE_MAX) then
            allocate (kf(neq, neq), mf(neq, neq), w(neq), z(neq, neq))
            kf = 0.0_dp
            mf = 0.0_dp
            do j = 1, neq
                do i = max(1, j - kd), j
                    kf(i, j) = kb(kd + 1 + i - j, j)
                    mf(i, j) = mb(kd + 1 + i - j, j)
                end do
            end do
            call eig_sym_range(neq, kf, mf, -1.0e-3_dp * lam_max, lam_max, nconv, w, z, info, &
                               solver_info)
            if (info /= STAT_OK) return
            nm = min(nconv, nmax)
            lam(1:nm) = w(1:nm)
            call expand(z(:, 1:nm))
        else
            ! Shift below the spectrum (rigid modes sit at 0), then grow the
            ! number of wanted modes until one lies above lam_max.
            sigma = -1.0e-3_dp * lam_max
            nev = min(nmax, neq - 2, 24)
            do
                ncv = min(neq, max(2 * nev + 1, nev + 24))
                allocate (w(nev), z(neq, nev))
                call eig_band_lowest(neq, kd, kb, mb, sigma, nev, ncv, 1.0e-10_dp, 3000, w, z, &
                                     nconv, stat, solver_info)
                if (stat /= STAT_OK .and. stat /= STAT_NOT_CONVERGED) then
                    info = stat
                    return
                end if
                if (nconv < nev) then
                    info = STAT_NOT_CONVERGED
                    call keep_below_max()
                    return
                end if
                if (w(nev) > lam_max .or. nev >= min(nmax, neq - 2)) exit
                nev = min(2 * nev, nmax, neq - 2)
                deallocate (w, z)
            end do
            call keep_below_max()
        end if
        ! The band matrices and the eigenvector work arrays are done with:
        ! free them before modal_extra assembles the k = 0 prestress system.
        deallocate (kb, mb)
        if (allocated(kf)) deallocate (kf, mf)
        if (allocated(z)) deallocate (z, w)
        call modal_extra(nn, ne, xn, conn, k, e_mod, nu, rho, nm, phi(:, :, 1:nm), &
                         gam(1:nm, 1:nm), mcq(1:nm, 1:nm), kgq(1:nm, 1:nm), info, bad_element)

    contains

        !> Keep the converged modes with lambda <= lam_max (at most nmax).
        subroutine keep_below_max()
            integer :: ii
            nm = 0
            do ii = 1, nconv
                if (w(ii) <= lam_max) nm = ii
            end do
            nm = min(nm, nmax)
            lam(1:nm) = w(1:nm)
            call expand(z(:, 1:nm))
        end subroutine keep_below_max

        subroutine expand(zz)
            real(dp), intent(in) :: zz(:, :)
            integer :: m, c, ii
            do m = 1, size(zz, 2)
                do ii = 1, nn
                    do c = 1, 3
                        if (eq(c, ii) > 0) phi(c, ii, m) = sgn(c, ii) * zz(eq(c, ii), m)
                    end do
                end do
            end do
        end subroutine expand

    end subroutine harmonic_modes

    !> Modal Coriolis (gam), in-plane mass (mcq) and centrifugal geometric
    !> stiffness (kgq, per (rad/s)^2) matrices, element by element.
    !> info: STAT_OK, STAT_BAD_ELEMENT (element bad_element), STAT_SINGULAR (prestress).
    subroutine modal_extra(nn, ne, xn, conn, k, e_mod, nu, rho, nm, phi, gam, mcq, kgq, info, &
                           bad_element)
        integer, intent(in) :: nn, ne, conn(NEN, ne), k, nm
        real(dp), intent(in) :: xn(2, nn), e_mod, nu, rho, phi(3, nn, nm)
        real(dp), intent(out) :: gam(nm, nm), mcq(nm, nm), kgq(nm, nm)
        integer, intent(out) :: info, bad_element
        real(dp) :: ke(NDOF_E, NDOF_E), me(NDOF_E, NDOF_E), ce(NDOF_E, NDOF_E), mc(NDOF_E, NDOF_E)
        real(dp) :: kg(NDOF_E, NDOF_E)
        real(dp) :: pe(NDOF_E, nm)
        real(dp), allocatable :: sig(:, :, :)
        integer :: e, a
        gam = 0.0_dp
        mcq = 0.0_dp
        kgq = 0.0_dp
        info = STAT_OK
        bad_element = 0
        if (nm < 1) return
        allocate (sig(4, NGP, ne))
        call centrifugal_prestress(nn, ne, xn, conn, e_mod, nu, rho, sig, info, bad_element)
        if (info /= STAT_OK) return
        do e = 1, ne
            call axisym_element(k, xn(:, conn(:, e)), e_mod, nu, rho, ke, me, ce, mc, info)
            if (info /= STAT_OK) then
                bad_element = e
                return
            end if
            do a = 1, NEN
                pe(3 * a - 2:3 * a, :) = phi(:, conn(a, e), :)
            end do
            gam = gam + matmul(transpose(pe), matmul(ce, pe))
            mcq = mcq + matmul(transpose(pe), matmul(mc, pe))
            call axisym_geometric(k, xn(:, conn(:, e)), sig(:, :, e), kg, info)
            if (info /= STAT_OK) then
                bad_element = e
                return
            end if
            kgq = kgq + matmul(transpose(pe), matmul(kg, pe))
        end do
    end subroutine modal_extra

    !> Stresses (sig_r, sig_y, sig_th, tau_ry) at the Gauss points of every
    !> element due to rotation at 1 rad/s about the axis (scale by Omega^2).
    !> The body is free: the load is self-equilibrated, and a tiny mass shift
    !> (K + eps M) removes the axial and spin rigid modes without loading them.
    !> info: STAT_OK, STAT_BAD_ELEMENT (element bad_element inverted), STAT_SINGULAR (the
    !> banded factorisation of K + eps M failed).
    subroutine centrifugal_prestress(nn, ne, xn, conn, e_mod, nu, rho, sig, info, bad_element)
        integer, intent(in) :: nn, ne, conn(NEN, ne)
        real(dp), intent(in) :: xn(2, nn), e_mod, nu, rho
        real(dp), intent(out) :: sig(4, NGP, ne)
        integer, intent(out) :: info, bad_element
        integer :: eq(3, nn), fixed(3, nn), neq, kd, e, a, c, q, stat
        real(dp) :: sgn(3, nn), fe(NDOF_E), ue(NDOF_E), eps
        real(dp), allocatable :: kb(:, :), mb(:, :), f(:)
        sig = 0.0_dp
        fixed = 0
        call dof_map(nn, xn, 0, fixed, eq, sgn, neq)
        kd = band_width(nn, ne, conn, eq)
        allocate (kb(kd + 1, neq), mb(kd + 1, neq), f(neq))
        call assemble_band(nn, ne, xn, conn, 0, e_mod, nu, rho, eq, sgn, neq, kd, kb, mb, info, &
                           bad_element)
        if (info /= STAT_OK) return
        eps = 1.0e-9_dp * maxval(kb(kd + 1, :)) / maxval(mb(kd + 1, :))
        kb = kb + eps * mb
        f = 0.0_dp
        ue = 0.0_dp
        do e = 1, ne
            call axisym_prestress(xn(:, conn(:, e)), e_mod, nu, rho, ue, fe, sig(:, :, e), stat)
            do a = 1, NEN
                do c = 1, 3
                    q = eq(c, conn(a, e))
                    if (q > 0) f(q) = f(q) + sgn(c, conn(a, e)) * fe(3 * (a - 1) + c)
                end do
            end do
        end do
        call dpbtrf('U', neq, kd, kb, kd + 1, stat)
        if (stat /= 0) then
            info = STAT_SINGULAR
            return
        end if
        call dpbtrs('U', neq, kd, 1, kb, kd + 1, f, neq, stat)
        do e = 1, ne
            do a = 1, NEN
                do c = 1, 3
                    q = eq(c, conn(a, e))
                    ue(3 * (a - 1) + c) = 0.0_dp
                    if (q > 0) ue(3 * (a - 1) + c) = sgn(c, conn(a, e)) * f(q)
                end do
            end do
            call axisym_prestress(xn(:, conn(:, e)), e_mod, nu, rho, ue, fe, sig(:, :, e), stat)
        end do
    end subroutine centrifugal_prestress

end module wheelset_modes
