!> Semi-analytical (2.5-D) finite elements of a prismatic elastic solid: a 2-D mesh of
!> 6-node triangles over the cross-section (eta lateral, zeta vertical), trigonometric
!> functions along the axis x. With u_eta, u_zeta ~ cos(kappa x) and u_x ~ sin(kappa x)
!> (or the sine partner) the strains split into a cos group (e_xx, e_ee, e_zz, g_ez) and a
!> sin group (g_xz, g_xe) that do not couple through an isotropic D, so the stiffness per
!> unit of (L/2) ring length is real symmetric:
!>     K(kappa) = K0 + kappa K1 + kappa^2 K2,  K_i from eps = (B0 + kappa B1) U
!> (Gavric 1995, J. Sound Vib. 185; Nilsson et al. 2009 for rails). Node DOFs (x, eta, zeta).
!> Implements Kaiser eq. 13 (the cos/sin field of one wave number).
module track_section
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_BAD_ELEMENT
    implicit none
    private
    public :: section_matrices

    ! Dunavant's 6-point rule, degree 4 (exact for the mass and K2 integrands).
    real(dp), parameter :: ga1 = 0.445948490915965_dp, gb1 = 0.108103018168070_dp
    real(dp), parameter :: ga2 = 0.091576213509771_dp, gb2 = 0.816847572980459_dp
    real(dp), parameter :: gw1 = 0.223381589678011_dp, gw2 = 0.109951743655322_dp

contains

    !> Shape functions n(6) of the 6-node triangle and derivatives dn(6, 2) w.r.t. (l1, l2).
    !> Node order: corners 1, 2, 3, mid-sides 12, 23, 31.
    pure subroutine t6_shape(l1, l2, n, dn)
        real(dp), intent(in) :: l1, l2
        real(dp), intent(out) :: n(6), dn(6, 2)
        real(dp) :: l3
        l3 = 1.0_dp - l1 - l2
        n = [l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), l3 * (2 * l3 - 1), 4 * l1 * l2, 4 * l2 * l3, &
             4 * l3 * l1]
        dn(:, 1) = [4 * l1 - 1, 0.0_dp, -(4 * l3 - 1), 4 * l2, -4 * l2, 4 * (l3 - l1)]
        dn(:, 2) = [0.0_dp, 4 * l2 - 1, -(4 * l3 - 1), 4 * l1, 4 * (l3 - l2), -4 * l1]
    end subroutine t6_shape

    !> Dense section matrices (ndof = 3 nn). xy(nn, 2) node coordinates (m), conn(ne, 6)
    !> 1-based node numbers, young (Pa), poisson, rho (kg/m^3).
    !> info: STAT_OK; STAT_BAD_ARGUMENT (a node number out of range); STAT_BAD_ELEMENT
    !> (element bad_element has det J <= 0). bad_element = 0 unless STAT_BAD_ELEMENT.
    subroutine section_matrices(nn, ne, xy, conn, young, poisson, rho, k0, k1, k2, m, info, &
                                bad_element)
        integer, intent(in) :: nn, ne
        real(dp), intent(in) :: xy(nn, 2), young, poisson, rho
        integer, intent(in) :: conn(ne, 6)
        real(dp), intent(out), dimension(3 * nn, 3 * nn) :: k0, k1, k2, m
        integer, intent(out) :: info, bad_element
        real(dp) :: gl(2, 6), gw(6), n(6), dn(6, 2), jac(2, 2), det, ji(2, 2), dxy(6, 2)
        real(dp) :: b0(6, 18), b1(6, 18), d(6, 6), lam, mu, w, db0(6, 18), db1(6, 18)
        real(dp) :: e0(18, 18), e1(18, 18), e2(18, 18), em(18, 18)
        integer :: e, g, a, dofs(18), i, c

        info = STAT_OK
        bad_element = 0
        k0 = 0; k1 = 0; k2 = 0; m = 0
        if (any(conn < 1) .or. any(conn > nn)) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        gl(:, 1) = [ga1, ga1]; gl(:, 2) = [ga1, gb1]; gl(:, 3) = [gb1, ga1]
        gl(:, 4) = [ga2, ga2]; gl(:, 5) = [ga2, gb2]; gl(:, 6) = [gb2, ga2]
        gw = [gw1, gw1, gw1, gw2, gw2, gw2]
        lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
        mu = young / (2 * (1 + poisson))
        d = 0
        d(1:3, 1:3) = lam
        do i = 1, 3
            d(i, i) = lam + 2 * mu
            d(i + 3, i + 3) = mu
        end do
        do e = 1, ne
            e0 = 0; e1 = 0; e2 = 0; em = 0
            do g = 1, 6
                call t6_shape(gl(1, g), gl(2, g), n, dn)
                jac = matmul(transpose(dn), xy(conn(e, :), :))   ! jac(l, c) = d x_c / d l_l
                det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
                if (det <= 0) then
                    info = STAT_BAD_ELEMENT
                    bad_element = e
                    return
                end if
                ji(1, 1) = jac(2, 2) / det; ji(2, 2) = jac(1, 1) / det
                ji(1, 2) = -jac(1, 2) / det; ji(2, 1) = -jac(2, 1) / det
                dxy = matmul(dn, transpose(ji))                  ! dN/d eta, dN/d zeta
                b0 = 0; b1 = 0
                do a = 1, 6
                    c = 3 * (a - 1)
                    b0(2, c + 2) = dxy(a, 1)
                    b0(3, c + 3) = dxy(a, 2)
                    b0(4, c + 2) = dxy(a, 2); b0(4, c + 3) = dxy(a, 1)
                    b0(5, c + 1) = dxy(a, 2)
                    b0(6, c + 1) = dxy(a, 1)
                    b1(1, c + 1) = n(a)
                    b1(5, c + 3) = -n(a)
                    b1(6, c + 2) = -n(a)
                end do
                w = 0.5_dp * det * gw(g)
                db0 = matmul(d, b0)
                db1 = matmul(d, b1)
                e0 = e0 + w * matmul(transpose(b0), db0)
                e1 = e1 + w * (matmul(transpose(b0), db1) + matmul(transpose(b1), db0))
                e2 = e2 + w * matmul(transpose(b1), db1)
                do a = 1, 6
                    do i = 1, 6
                        do c = 1, 3
                            em(3 * (a - 1) + c, 3 * (i - 1) + c) = em(3 * (a - 1) + c, 3 * (i - 1) + c) &
                                + w * rho * n(a) * n(i)
                        end do
                    end do
                end do
            end do
            do a = 1, 6
                dofs(3 * a - 2:3 * a) = 3 * (conn(e, a) - 1) + [1, 2, 3]
            end do
            k0(dofs, dofs) = k0(dofs, dofs) + e0
            k1(dofs, dofs) = k1(dofs, dofs) + e1
            k2(dofs, dofs) = k2(dofs, dofs) + e2
            m(dofs, dofs) = m(dofs, dofs) + em
        end do
    end subroutine section_matrices

end module track_section
