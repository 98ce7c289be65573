!> f2py shim for the friction laws (contact_friction), steady rolling with a friction
!> law, the FASTSIM variant with falling friction (contact_fastsim_friction) and
!> Polach's creep force: plain arrays, explicit shapes, integer info. Argument checks
!> live in Python (railvti.contact.friction). A law crosses as (kind, mu_s, mu_k, v_h):
!> kind 0 static/kinetic Coulomb, 1 linear, 2 rational, 3 exponential; v_h in m/s.
!> Implements no equation (contact_friction does: see docs/equations.md).

!> Friction coefficient mu(v) of a law at n slip velocities v (m/s).
subroutine friction_mu_c(n, kind, mu_s, mu_k, v_h, v, mu)
    use iso_c_binding, only: c_int, c_double
    use contact_friction, only: friction_law, friction_mu
    implicit none
    integer(c_int), intent(in) :: n, kind
    real(c_double), intent(in) :: mu_s, mu_k, v_h, v(n)
    real(c_double), intent(out) :: mu(n)
    type(friction_law) :: law
    integer :: k
    law = friction_law(kind, mu_s, mu_k, v_h)
    do k = 1, n
        mu(k) = friction_mu(law, v(k))
    end do
end subroutine friction_mu_c

!> n element problems s = s0 + diag(kx, ky) t with the bound mu(speed lam) bound0 / mu_s
!> (contact_friction::friction_element_solve). rule 0: the smallest slip; 1: the slip
!> nearest to lam_prev (creepage units).
subroutine friction_element_c(n, kind, mu_s, mu_k, v_h, rule, speed, s0x, s0y, kx, ky, bound0, lam_prev, &
                              tx, ty, stat, lam, nsol)
    use iso_c_binding, only: c_int, c_double
    use contact_friction, only: friction_law, friction_element_solve
    implicit none
    integer(c_int), intent(in) :: n, kind, rule
    real(c_double), intent(in) :: mu_s, mu_k, v_h, speed, kx, ky
    real(c_double), intent(in) :: s0x(n), s0y(n), bound0(n), lam_prev(n)
    real(c_double), intent(out) :: tx(n), ty(n), lam(n)
    integer(c_int), intent(out) :: stat(n), nsol(n)
    type(friction_law) :: law
    integer :: k, st, ns
    law = friction_law(kind, mu_s, mu_k, v_h)
    do k = 1, n
        if (rule == 1) then
            call friction_element_solve(law, speed, s0x(k), s0y(k), kx, ky, bound0(k), tx(k), ty(k), st, lam(k), &
                                        ns, lam_prev=lam_prev(k))
        else
            call friction_element_solve(law, speed, s0x(k), s0y(k), kx, ky, bound0(k), tx(k), ty(k), st, lam(k), ns)
        end if
        stat(k) = st
        nsol(k) = ns
    end do
end subroutine friction_element_c

!> Steady rolling (as api_rolling's rolling_solve_c) with the friction law (kind, mu_s,
!> mu_k, v_h) and the rule (0 the smallest slip, 1 the one continuous with the iterate)
!> where an element problem has several solutions. nmulti: elements whose final element
!> problem has several solutions.
subroutine rolling_friction_solve_c(handle, nx, ny, p, x0, y0, xi, eta, phi, kind, mu_s, mu_k, v_h, rule, speed, &
                                    method, nblock, ninner, tol, max_iter, product, tx, ty, status, sx, sy, &
                                    iters, resid, nmulti, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_BAD_HANDLE
    use contact_plans, only: workspace, ws_get
    use contact_rolling, only: rolling_steady
    use contact_friction, only: friction_law
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: handle, nx, ny, kind, rule, method, nblock, ninner, max_iter, product
    real(c_double), intent(in) :: p(nx, ny), x0, y0, xi, eta, phi, mu_s, mu_k, v_h, speed, tol
    real(c_double), intent(inout) :: tx(nx, ny), ty(nx, ny)
    integer(c_int), intent(out) :: status(nx, ny)
    real(c_double), intent(out) :: sx(nx, ny), sy(nx, ny)
    integer(c_int), intent(out) :: iters, nmulti, info
    real(c_double), intent(out) :: resid
    type(workspace), pointer :: w
    integer, allocatable :: st(:, :)
    integer :: it, stat, nm

    iters = 0
    nmulti = 0
    resid = 0.0_c_double
    status = 0
    sx = 0.0_c_double
    sy = 0.0_c_double
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) then
        info = STAT_BAD_HANDLE
        return
    end if
    allocate (st(nx, ny))
    call rolling_steady(w, p, x0, y0, xi, eta, phi, mu_s, speed, method, nblock, ninner, tol, max_iter, &
                        tx, ty, st, sx, sy, it, resid, stat, product=product, &
                        law=friction_law(kind, mu_s, mu_k, v_h, rule), nmulti=nm)
    status = st
    iters = it
    nmulti = nm
    info = stat
end subroutine rolling_friction_solve_c

!> FASTSIM with a friction law and the slope reduction kred on an ellipse, for n load
!> cases (contact_fastsim_friction::fastsim_friction_ellipse); rule as rolling_friction_solve_c
!> (continuous: with the slip of the upstream element of the strip).
subroutine fastsim_friction_c(n, a, b, g, c11, c22, c23, kind, mu_s, mu_k, v_h, rule, kred, fn, xi, eta, phi, speed, &
                              nx, ny, fx, fy, mz, nmulti)
    use iso_c_binding, only: c_int, c_double
    use contact_friction, only: friction_law
    use contact_fastsim_friction, only: fastsim_friction_ellipse
    implicit none
    integer(c_int), intent(in) :: n, kind, rule, nx, ny
    real(c_double), intent(in) :: a, b, g, c11, c22, c23, mu_s, mu_k, v_h, kred, speed
    real(c_double), intent(in) :: fn(n), xi(n), eta(n), phi(n)
    real(c_double), intent(out) :: fx(n), fy(n), mz(n)
    integer(c_int), intent(out) :: nmulti(n)
    type(friction_law) :: law
    integer :: k, nm
    law = friction_law(kind, mu_s, mu_k, v_h, rule)
    do k = 1, n
        call fastsim_friction_ellipse(a, b, g, c11, c22, c23, law, kred, fn(k), xi(k), eta(k), phi(k), speed, &
                                      nx, ny, fx(k), fy(k), mz(k), nm)
        nmulti(k) = nm
    end do
end subroutine fastsim_friction_c

!> Polach's creep force |F| (N) at n creepage magnitudes s (contact_friction::polach_force).
subroutine polach_force_c(n, q, a, b, g, c11, mu0, ca, cb, ka, ks, speed, s, f)
    use iso_c_binding, only: c_int, c_double
    use contact_friction, only: polach_force
    implicit none
    integer(c_int), intent(in) :: n
    real(c_double), intent(in) :: q, a, b, g, c11, mu0, ca, cb, ka, ks, speed, s(n)
    real(c_double), intent(out) :: f(n)
    f = polach_force(q, a, b, g, c11, mu0, ca, cb, ka, ks, speed, s)
end subroutine polach_force_c
