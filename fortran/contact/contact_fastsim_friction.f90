!> FASTSIM (Kalker 1982; contact_fastsim) with a friction law of contact_friction
!> (static/kinetic, falling with the slip velocity) and a slope reduction factor.
!>
!> Falling friction: where the trial traction u of an element leaves the disc
!> |t| <= mu_s p the element slips with t = -mu(V |s|) p e, the slip
!> s = L_eff (t - u) / h (contact_fastsim's slip per unit rolled distance, h the
!> element length) being lam e. That is the element problem s = s0 + k t with
!> k = L_eff / h, s0 = -k u, solved by friction_element_solve: the smallest-slip
!> solution, and the count of solutions when the element problem is not monotone
!> (k p V max|mu'| >= 1: a fine strip grid or a steep law). Rule RULE_CONTINUOUS takes
!> the solution nearest to the upstream element's slip (continuity along the strip).
!> Slope reduction (Polach 2005's k_A, k_S make the initial slope (k_A + k_S)/2 of
!> Kalker's): the flexibilities L1, L2, L3 are divided by kred (0 < kred <= 1), which
!> scales the creep stiffness of the linear limit by kred; kred = 1 and a constant law
!> give contact_fastsim's fastsim_ellipse.
!> Implements no Kaiser equation (FASTSIM: Kalker 1990 sect. 3.3).
module contact_fastsim_friction
    use common_kinds, only: dp
    use contact_fastsim, only: flexibilities, shape_pressure, discrete_load
    use contact_friction, only: friction_law, friction_element_solve, RULE_CONTINUOUS
    implicit none
    private
    public :: fastsim_friction_ellipse

contains

    !> Creep forces and spin moment on an elliptic patch (parabolic pressure scaled to
    !> sum to fn, ny strips of nx elements: as fastsim_ellipse) with the friction law
    !> law and the slope reduction kred. nmulti: elements whose element problem had more
    !> than one solution. fn <= 0, or a, b, g, a coefficient or kred <= 0, or nx, ny < 1:
    !> zero forces.
    pure subroutine fastsim_friction_ellipse(a, b, g, c11, c22, c23, law, kred, fn, xi, eta, phi, speed, &
                                             nx, ny, fx, fy, mz, nmulti)
        real(dp), intent(in) :: a, b, g, c11, c22, c23   ! semi-axes (m), shear modulus (Pa), Kalker's C
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: kred                     ! slope reduction factor (0, 1]
        real(dp), intent(in) :: fn, xi, eta, phi, speed  ! N, creepages (1, 1, 1/m), m/s
        integer, intent(in) :: nx, ny
        real(dp), intent(out) :: fx, fy, mz              ! N, N, N m
        integer, intent(out) :: nmulti
        real(dp) :: cx, cy, cs, leff, p0, dys, y, aj, dxj, xold, xnew, tx, ty, da, h, ux, uy, g0, k, lam, lprev
        integer :: i, j, st, nsol
        logical :: ok
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        nmulti = 0
        if (fn <= 0.0_dp .or. nx < 1 .or. ny < 1 .or. kred <= 0.0_dp) return
        call flexibilities(a, b, g, c11, c22, c23, xi, eta, phi, cx, cy, cs, leff, ok)
        if (.not. ok) return
        cx = cx * kred
        cy = cy * kred
        cs = cs * kred
        leff = leff / kred
        p0 = fn / discrete_load(1, a, b, nx, ny)
        dys = 2.0_dp * b / ny
        do j = 1, ny
            y = -b + (j - 0.5_dp) * dys
            aj = a * sqrt(max(0.0_dp, 1.0_dp - (y / b)**2))
            dxj = 2.0_dp * aj / nx
            da = dxj * dys
            tx = 0.0_dp
            ty = 0.0_dp
            xold = aj
            lprev = 0.0_dp
            do i = 1, nx
                xnew = aj - (i - 0.5_dp) * dxj
                h = xold - xnew
                ! trial (adhesion) traction, as contact_fastsim's step_element
                ux = tx - (cx - cs * y) * h
                uy = ty - (cy + cs * 0.5_dp * (xold + xnew)) * h
                g0 = max(law%mu_s, 0.0_dp) * p0 * shape_pressure(1, xnew, y, a, b)
                ! adhesion directly under a constant law (fastsim_ellipse's path); else the
                ! element problem, which also counts slip solutions beside adhesion
                if (law%mu_s == law%mu_k .and. ux * ux + uy * uy <= g0 * g0) then
                    tx = ux
                    ty = uy
                    lprev = 0.0_dp
                else
                    k = leff / h
                    if (law%rule == RULE_CONTINUOUS) then
                        call friction_element_solve(law, speed, -k * ux, -k * uy, k, k, g0, tx, ty, st, lam, nsol, &
                                                    lam_prev=lprev)
                    else
                        call friction_element_solve(law, speed, -k * ux, -k * uy, k, k, g0, tx, ty, st, lam, nsol)
                    end if
                    if (nsol > 1) nmulti = nmulti + 1
                    lprev = lam
                end if
                fx = fx + tx * da
                fy = fy + ty * da
                mz = mz + (xnew * ty - y * tx) * da
                xold = xnew
            end do
        end do
    end subroutine fastsim_friction_ellipse

end module contact_fastsim_friction
