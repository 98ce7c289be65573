!> Axisymmetric solid elements with a circumferential Fourier harmonic k.
!>
!> Nine-node Lagrange quadrilaterals on the meridian section (r, y); per node
!> the amplitudes (U_r, U_y, U_theta) of the harmonic field (Kaiser, eq. 7)
!>     set A:  u_r = U_r cos k th,  u_y = U_y cos k th,  u_th =  U_th sin k th
!>     set B:  u_r = U_r sin k th,  u_y = U_y sin k th,  u_th = -U_th cos k th
!> Both sets give the same stiffness and mass, hence the double modes U_A, U_B
!> for k /= 0 (eqs 9-10). For k = 0 the same formulas with weight 2 pi hold the
!> axisymmetric (U_r, U_y) field and the torsional U_th field, uncoupled.
!> The matrices are the true 3-D energies of the field: the theta integral
!> (pi for k > 0, 2 pi for k = 0) is included.
!>
!> Local node order is tensor order: node (i, j), i, j = 1..3 along xi, eta,
!> has index (j - 1) * 3 + i and natural coordinates (i - 2, j - 2).
!> Element DOF order: node-major, (U_r, U_y, U_th) per node.
!> Implements Kaiser eqs 6-10 and, per element, the body-frame terms of eqs 1-5 (Coriolis,
!> centrifugal, prestress); the numbers 1-5 and 8 are inferred (docs/equations.md).
module wheelset_element
    use common_kinds, only: dp, pi
    use common_status, only: STAT_OK, STAT_BAD_ELEMENT
    implicit none
    private
    public :: axisym_element, axisym_prestress, axisym_geometric, NEN, NDOF_E, NGP

    integer, parameter :: NEN = 9           ! nodes per element
    integer, parameter :: NDOF_E = 3 * NEN  ! DOFs per element
    integer, parameter :: NGP = 9           ! Gauss points per element (3 x 3)

contains

    !> 1-D quadratic Lagrange functions and derivatives at s (nodes -1, 0, 1).
    pure subroutine lagrange3(s, l, dl)
        real(dp), intent(in) :: s
        real(dp), intent(out) :: l(3), dl(3)
        l = [0.5_dp * s * (s - 1.0_dp), 1.0_dp - s * s, 0.5_dp * s * (s + 1.0_dp)]
        dl = [s - 0.5_dp, -2.0_dp * s, s + 0.5_dp]
    end subroutine lagrange3

    !> Element matrices of harmonic k.
    !> xe(2, 9): nodal (r, y), m. e, nu, rho: Young's modulus (Pa), Poisson, density.
    !> ke, me: stiffness and mass. ce: Coriolis coupling (test set A, trial set B
    !> for k > 0; skew r-theta coupling for k = 0) without the factor 2 Omega.
    !> mc: mass of the in-plane (r, theta) motion, for the centrifugal softening.
    !> info: STAT_OK, STAT_BAD_ELEMENT (a non-positive Jacobian or radius: a distorted or
    !> inverted element).
    pure subroutine axisym_element(k, xe, e, nu, rho, ke, me, ce, mc, info)
        integer, intent(in) :: k
        real(dp), intent(in) :: xe(2, NEN), e, nu, rho
        real(dp), intent(out) :: ke(NDOF_E, NDOF_E), me(NDOF_E, NDOF_E)
        real(dp), intent(out) :: ce(NDOF_E, NDOF_E), mc(NDOF_E, NDOF_E)
        integer, intent(out) :: info
        real(dp) :: n(NEN), nr(NEN), ny(NEN)
        real(dp) :: r, w, wk, lam, mu, fk, ro, cs
        real(dp) :: b(6, NDOF_E), d(6, 6), db(6, NDOF_E)
        integer :: ig, jg, i, a, bb, ia, ib

        info = STAT_OK
        ke = 0.0_dp
        me = 0.0_dp
        ce = 0.0_dp
        mc = 0.0_dp
        wk = merge(2.0_dp * pi, pi, k == 0)
        fk = real(k, dp)
        lam = e * nu / ((1.0_dp + nu) * (1.0_dp - 2.0_dp * nu))
        mu = e / (2.0_dp * (1.0_dp + nu))
        d = 0.0_dp
        d(1:3, 1:3) = lam
        do i = 1, 3
            d(i, i) = lam + 2.0_dp * mu
            d(i + 3, i + 3) = mu
        end do
        ! Coriolis sign: test A / trial B is +; for k = 0 the coupling is skew.
        cs = merge(-1.0_dp, 1.0_dp, k == 0)

        do jg = 1, 3
            do ig = 1, 3
                call gauss_point(xe, (jg - 1) * 3 + ig, n, nr, ny, r, w, info)
                if (info /= STAT_OK) return
                w = w * wk
                ro = 1.0_dp / r
                ! strains (eps_r, eps_y, eps_th, gam_ry, gam_rth, gam_yth)
                b = 0.0_dp
                do a = 1, NEN
                    ia = 3 * (a - 1)
                    b(1, ia + 1) = nr(a)
                    b(2, ia + 2) = ny(a)
                    b(3, ia + 1) = n(a) * ro
                    b(3, ia + 3) = fk * n(a) * ro
                    b(4, ia + 1) = ny(a)
                    b(4, ia + 2) = nr(a)
                    b(5, ia + 1) = -fk * n(a) * ro
                    b(5, ia + 3) = nr(a) - n(a) * ro
                    b(6, ia + 2) = -fk * n(a) * ro
                    b(6, ia + 3) = ny(a)
                end do
                db = matmul(d, b)
                ke = ke + w * matmul(transpose(b), db)
                do bb = 1, NEN
                    ib = 3 * (bb - 1)
                    do a = 1, NEN
                        ia = 3 * (a - 1)
                        me(ia + 1, ib + 1) = me(ia + 1, ib + 1) + rho * w * n(a) * n(bb)
                        me(ia + 2, ib + 2) = me(ia + 2, ib + 2) + rho * w * n(a) * n(bb)
                        me(ia + 3, ib + 3) = me(ia + 3, ib + 3) + rho * w * n(a) * n(bb)
                        mc(ia + 1, ib + 1) = mc(ia + 1, ib + 1) + rho * w * n(a) * n(bb)
                        mc(ia + 3, ib + 3) = mc(ia + 3, ib + 3) + rho * w * n(a) * n(bb)
                        ce(ia + 3, ib + 1) = ce(ia + 3, ib + 1) + rho * w * n(a) * n(bb)
                        ce(ia + 1, ib + 3) = ce(ia + 1, ib + 3) + cs * rho * w * n(a) * n(bb)
                    end do
                end do
            end do
        end do
    end subroutine axisym_element

    !> Shape functions at Gauss point g (1..9): n, d/dr, d/dy, radius and
    !> weight * detJ * r (without the theta factor). info: STAT_OK, STAT_BAD_ELEMENT
    !> (det J <= 0 or r <= 0).
    pure subroutine gauss_point(xe, g, n, nr, ny, r, w, info)
        real(dp), intent(in) :: xe(2, NEN)
        integer, intent(in) :: g
        real(dp), intent(out) :: n(NEN), nr(NEN), ny(NEN), r, w
        integer, intent(out) :: info
        real(dp), parameter :: gp(3) = [-sqrt(0.6_dp), 0.0_dp, sqrt(0.6_dp)]
        real(dp), parameter :: gw(3) = [5.0_dp / 9.0_dp, 8.0_dp / 9.0_dp, 5.0_dp / 9.0_dp]
        real(dp) :: lx(3), dlx(3), ly(3), dly(3), dnx(NEN), dny(NEN), jac(2, 2), detj
        integer :: i, j, a, ig, jg
        info = STAT_OK
        ig = mod(g - 1, 3) + 1
        jg = (g - 1) / 3 + 1
        call lagrange3(gp(ig), lx, dlx)
        call lagrange3(gp(jg), ly, dly)
        do j = 1, 3
            do i = 1, 3
                a = (j - 1) * 3 + i
                n(a) = lx(i) * ly(j)
                dnx(a) = dlx(i) * ly(j)
                dny(a) = lx(i) * dly(j)
            end do
        end do
        jac(1, 1) = sum(dnx * xe(1, :))
        jac(1, 2) = sum(dnx * xe(2, :))
        jac(2, 1) = sum(dny * xe(1, :))
        jac(2, 2) = sum(dny * xe(2, :))
        detj = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
        r = sum(n * xe(1, :))
        nr = 0.0_dp
        ny = 0.0_dp
        w = 0.0_dp
        if (detj <= 0.0_dp .or. r <= 0.0_dp) then
            info = STAT_BAD_ELEMENT
            return
        end if
        nr = (jac(2, 2) * dnx - jac(1, 2) * dny) / detj
        ny = (-jac(2, 1) * dnx + jac(1, 1) * dny) / detj
        w = gw(ig) * gw(jg) * detj * r
    end subroutine gauss_point

    !> Centrifugal prestress of a k = 0 element: the consistent load of the
    !> body force rho r e_r (angular speed 1 rad/s) in fe, and, given the
    !> element's displacements ue, the stresses (sig_r, sig_y, sig_th, tau_ry)
    !> at its Gauss points in sig. info: STAT_OK, STAT_BAD_ELEMENT.
    pure subroutine axisym_prestress(xe, e, nu, rho, ue, fe, sig, info)
        real(dp), intent(in) :: xe(2, NEN), e, nu, rho, ue(NDOF_E)
        real(dp), intent(out) :: fe(NDOF_E), sig(4, NGP)
        integer, intent(out) :: info
        real(dp) :: n(NEN), nr(NEN), ny(NEN), r, w, lam, mu, ur(NEN), uy(NEN)
        real(dp) :: er, ey, et, gry
        integer :: g
        lam = e * nu / ((1.0_dp + nu) * (1.0_dp - 2.0_dp * nu))
        mu = e / (2.0_dp * (1.0_dp + nu))
        ur = ue(1::3)
        uy = ue(2::3)
        fe = 0.0_dp
        sig = 0.0_dp
        do g = 1, NGP
            call gauss_point(xe, g, n, nr, ny, r, w, info)
            if (info /= STAT_OK) return
            fe(1::3) = fe(1::3) + 2.0_dp * pi * w * rho * r * n
            er = sum(nr * ur)
            ey = sum(ny * uy)
            et = sum(n * ur) / r
            gry = sum(ny * ur) + sum(nr * uy)
            sig(1, g) = lam * (er + ey + et) + 2.0_dp * mu * er
            sig(2, g) = lam * (er + ey + et) + 2.0_dp * mu * ey
            sig(3, g) = lam * (er + ey + et) + 2.0_dp * mu * et
            sig(4, g) = mu * gry
        end do
    end subroutine axisym_prestress

    !> Geometric (stress) stiffness of harmonic k for the prestress sig(4, 9)
    !> (sig_r, sig_y, sig_th, tau_ry at the Gauss points): the theta-integral of
    !> sum_i grad(u_i) . S grad(u_i) with the physical cylindrical gradient.
    !> info: STAT_OK, STAT_BAD_ELEMENT.
    pure subroutine axisym_geometric(k, xe, sig, kg, info)
        integer, intent(in) :: k
        real(dp), intent(in) :: xe(2, NEN), sig(4, NGP)
        real(dp), intent(out) :: kg(NDOF_E, NDOF_E)
        integer, intent(out) :: info
        real(dp) :: n(NEN), nr(NEN), ny(NEN), r, w, wk, fk, s(3, 3)
        real(dp) :: gr(3, NDOF_E), gt(3, NDOF_E), gy(3, NDOF_E)
        integer :: g, a, ia
        kg = 0.0_dp
        wk = merge(2.0_dp * pi, pi, k == 0)
        fk = real(k, dp)
        do g = 1, NGP
            call gauss_point(xe, g, n, nr, ny, r, w, info)
            if (info /= STAT_OK) return
            ! rows: derivative direction (r, theta, y); one matrix per component
            gr = 0.0_dp
            gt = 0.0_dp
            gy = 0.0_dp
            do a = 1, NEN
                ia = 3 * (a - 1)
                gr(1, ia + 1) = nr(a)                  ! u_r
                gr(2, ia + 1) = -fk * n(a) / r
                gr(2, ia + 3) = -n(a) / r
                gr(3, ia + 1) = ny(a)
                gt(1, ia + 3) = nr(a)                  ! u_theta
                gt(2, ia + 3) = fk * n(a) / r
                gt(2, ia + 1) = n(a) / r
                gt(3, ia + 3) = ny(a)
                gy(1, ia + 2) = nr(a)                  ! u_y
                gy(2, ia + 2) = -fk * n(a) / r
                gy(3, ia + 2) = ny(a)
            end do
            s = 0.0_dp
            s(1, 1) = sig(1, g)
            s(2, 2) = sig(3, g)
            s(3, 3) = sig(2, g)
            s(1, 3) = sig(4, g)
            s(3, 1) = sig(4, g)
            kg = kg + wk * w * (matmul(transpose(gr), matmul(s, gr)) &
                                + matmul(transpose(gt), matmul(s, gt)) &
                                + matmul(transpose(gy), matmul(s, gy)))
        end do
    end subroutine axisym_geometric

end module wheelset_element
