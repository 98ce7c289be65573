!> Steady rolling of viscoelastic bodies: the normal problem of a line (plane-strain)
!> contact, for a cylinder on a half-space or two cylinders, each body rigid, elastic or a
!> standard linear solid (SLS).
!>
!> A body's contact creep compliance (plane strain: (1 - nu^2)/E(t) = (1 - nu)/(2 G(t)),
!> Poisson's ratio held constant) is
!>     J(t) = J0 + (Jinf - J0) (1 - exp(-t/tc))
!> with the instantaneous (glassy) J0, the relaxed Jinf and the creep (retardation) time tc.
!> In steady rolling the surface particles move in -x at speed V, so a particle now at x
!> was at x + V s a time s ago, and the surface displacement is the hereditary integral
!>     u(x) = J0 ue(x) + (Jinf - J0) Int_0^inf (1/L) exp(-s/L) ue(x + s) ds,   L = V tc,
!> of the elastic field per unit compliance ue (a causal exponential filter along x).
!> For a uniform pressure on a strip of width d the plane-strain field is
!>     Ke(r) = -(2/pi) [Phi(r + d/2) - Phi(r - d/2)],   Phi(t) = t ln|t/l| - t,
!> r = x - xi the offset from the strip's centre and l the reference length: a surface
!> point at distance l from a line load does not move (the 2-D approach is defined only up
!> to this constant). Integrating by parts, the filtered field is exact in closed form:
!>     G(r) = Ke(r) - (2 L/pi) [M((r + d/2)/L) - M((r - d/2)/L)],
!>     M(z) = Int_0^inf exp(-v) ln|z + v| dv
!>          = ln z + exp(z) E1(z)          (z > 0)
!>          = -gamma                       (z = 0)
!>          = ln|z| - exp(z) Ei(-z)        (z < 0),
!> so the influence coefficients of the collocation (element centres) are exact for a
!> piecewise-constant pressure, with no truncation of the memory ahead of the grid.
!> The operator is a non-symmetric Toeplitz matrix A(i, j) = k(i - j); the normal problem
!> (p >= 0, gap h + A p - delta >= 0, complementary, sum p d = fn) is solved by an
!> active-set iteration with a dense LU solve on the contact set (visco_line_normal).
!> Implements docs/equations.md "Viscoelastic steady rolling" (eqs VE1-VE4).
module contact_viscoelastic
    use common_kinds, only: dp, pi
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_NOT_CONVERGED, STAT_SINGULAR, &
                             STAT_NOT_FINITE
    use common_lapack, only: dgesv
    implicit none
    private
    public :: visco_line_kernel, visco_line_normal, log_moment, expint_e1_scaled, expint_ei_scaled

    real(dp), parameter :: EULER_GAMMA = 0.577215664901532860606512090082402431_dp

contains

    !> exp(x) E1(x) for x > 0: the power series of E1 for x <= 2, a continued fraction
    !> (evaluated backwards at fixed depth) above.
    pure real(dp) function expint_e1_scaled(x) result(f)
        real(dp), intent(in) :: x
        real(dp) :: term, s
        integer :: k
        if (x <= 2.0_dp) then
            ! E1(x) = -gamma - ln x - sum_k (-x)^k / (k k!)
            s = 0.0_dp
            term = 1.0_dp
            do k = 1, 60
                term = -term * x / k
                s = s + term / k
                if (abs(term) < 1.0e-18_dp * abs(s)) exit
            end do
            f = exp(x) * (-EULER_GAMMA - log(x) - s)
        else
            ! exp(x) E1(x) = 1/(x + 1 - 1/(x + 3 - 4/(x + 5 - 9/(x + 7 - ...))))
            s = x + 2.0_dp * 120 + 1.0_dp
            do k = 120, 1, -1
                s = x + 2.0_dp * (k - 1) + 1.0_dp - real(k, dp)**2 / s
            end do
            f = 1.0_dp / s
        end if
    end function expint_e1_scaled

    !> exp(-b) Ei(b) for b > 0: the power series Ei(b) = gamma + ln b + sum b^k/(k k!)
    !> (positive terms, no cancellation) up to b = 40, the asymptotic series above.
    pure real(dp) function expint_ei_scaled(b) result(f)
        real(dp), intent(in) :: b
        real(dp) :: term, s, t
        integer :: k
        if (b <= 40.0_dp) then
            s = 0.0_dp
            term = 1.0_dp
            do k = 1, 400
                term = term * b / k
                s = s + term / k
                if (term / k < 1.0e-17_dp * s) exit
            end do
            f = exp(-b) * (EULER_GAMMA + log(b) + s)
        else
            ! exp(-b) Ei(b) ~ (1/b) sum_k k!/b^k, stopped at the smallest term
            s = 1.0_dp
            t = 1.0_dp
            do k = 1, 60
                if (k / b >= 1.0_dp) exit
                t = t * k / b
                s = s + t
                if (t < 1.0e-17_dp) exit
            end do
            f = s / b
        end if
    end function expint_ei_scaled

    !> M(z) = Int_0^inf exp(-v) ln|z + v| dv (eq. VE3).
    pure real(dp) function log_moment(z) result(m)
        real(dp), intent(in) :: z
        if (z > 0.0_dp) then
            m = log(z) + expint_e1_scaled(z)
        else if (z < 0.0_dp) then
            m = log(-z) - expint_ei_scaled(-z)
        else
            m = -EULER_GAMMA
        end if
    end function log_moment

    !> t ln|t/l| - t, continuous at t = 0.
    pure real(dp) function phi_log(t, ell) result(f)
        real(dp), intent(in) :: t, ell
        if (t == 0.0_dp) then
            f = 0.0_dp
        else
            f = t * log(abs(t) / ell) - t
        end if
    end function phi_log

    !> Influence coefficients k(m), m = -(n-1)..n-1, of a line contact on n strips of
    !> width d, for nb bodies (m/Pa per Pa of strip pressure, i.e. displacement per
    !> pressure): k(m) = sum_b [J0_b Ke(m d) + (Jinf_b - J0_b) G_b(m d)] (eqs VE1-VE3).
    !> vlen(b) = V tc_b, m: 0 gives the relaxed response Jinf_b; a body with
    !> J0_b = Jinf_b is elastic. info: STAT_OK; STAT_BAD_ARGUMENT n < 1, d <= 0, ell <= 0,
    !> a compliance < 0 or vlen < 0.
    pure subroutine visco_line_kernel(n, d, nb, j0, jinf, vlen, ell, k, info)
        integer, intent(in) :: n, nb
        real(dp), intent(in) :: d, j0(nb), jinf(nb), vlen(nb), ell
        real(dp), intent(out) :: k(-(n - 1):n - 1)
        integer, intent(out) :: info
        real(dp) :: r, ke, g, el
        integer :: m, b

        k = 0.0_dp
        info = STAT_BAD_ARGUMENT
        if (n < 1 .or. .not. d > 0.0_dp .or. .not. ell > 0.0_dp) return
        if (any(.not. (j0 >= 0.0_dp)) .or. any(.not. (jinf >= 0.0_dp)) .or. &
            any(.not. (vlen >= 0.0_dp))) return
        info = STAT_OK
        do m = -(n - 1), n - 1
            r = m * d
            ke = -(2.0_dp / pi) * (phi_log(r + 0.5_dp * d, ell) - phi_log(r - 0.5_dp * d, ell))
            do b = 1, nb
                if (jinf(b) == j0(b) .or. vlen(b) == 0.0_dp) then
                    k(m) = k(m) + jinf(b) * ke
                else
                    el = vlen(b)
                    g = ke - (2.0_dp * el / pi) * (log_moment((r + 0.5_dp * d) / el) &
                                                   - log_moment((r - 0.5_dp * d) / el))
                    k(m) = k(m) + j0(b) * ke + (jinf(b) - j0(b)) * g
                end if
            end do
        end do
    end subroutine visco_line_kernel

    !> The normal problem of a line contact with the (non-symmetric) Toeplitz operator
    !> A(i, j) = k(i - j): p >= 0, e = h + A p - delta >= 0, p e = 0, d sum(p) = fn.
    !> Active-set iteration (as Kalker's NORM): solve A_CC p_C - delta = -h_C, d sum p_C = fn
    !> on the set C by LU, drop the elements with p < 0; when none is negative, add the
    !> elements outside C that interpenetrate (e < -tol |delta - h| scale); stop when neither
    !> changes C. Starts from C = {p > 0} of the given p, or all elements if p = 0.
    !> resid: the relative complementarity residual max|e_C| + max(-e_out, 0) over the scale
    !> of h + A p. info: STAT_OK; STAT_NOT_CONVERGED after max_iter set changes;
    !> STAT_SINGULAR a singular system; STAT_NOT_FINITE a NaN; STAT_BAD_ARGUMENT n < 2 or fn <= 0.
    subroutine visco_line_normal(n, d, h, k, fn, tol, max_iter, p, u, approach, iters, resid, info)
        integer, intent(in) :: n, max_iter
        real(dp), intent(in) :: d, h(n), k(-(n - 1):n - 1), fn, tol
        real(dp), intent(inout) :: p(n)
        real(dp), intent(out) :: u(n), approach, resid
        integer, intent(out) :: iters, info
        logical :: in_c(n), changed
        real(dp) :: e(n), scale
        integer :: it

        iters = 0
        resid = huge(1.0_dp)
        approach = 0.0_dp
        u = 0.0_dp
        info = STAT_BAD_ARGUMENT
        if (n < 2 .or. .not. fn > 0.0_dp .or. .not. d > 0.0_dp) return
        in_c = p > 0.0_dp
        if (.not. any(in_c)) in_c = .true.
        info = STAT_NOT_CONVERGED
        do it = 1, max_iter
            iters = it
            call solve_on_set(n, d, h, k, fn, in_c, p, approach, info)
            if (info /= STAT_OK) return
            if (any(p < 0.0_dp)) then
                in_c = in_c .and. p >= 0.0_dp
                where (.not. in_c) p = 0.0_dp
                info = STAT_NOT_CONVERGED
                cycle
            end if
            call toeplitz_apply(n, k, p, u)
            e = h + u - approach
            scale = maxval(abs(u)) + maxval(abs(h - approach), mask=in_c)
            changed = .false.
            if (any(.not. in_c .and. e < -tol * scale)) then
                changed = .true.
                in_c = in_c .or. e < -tol * scale
            end if
            resid = (maxval(abs(e), mask=in_c) + max(0.0_dp, -minval(e, mask=.not. in_c &
                                                                     .and. e < 0.0_dp))) / scale
            if (.not. changed) then
                info = STAT_OK
                if (.not. (resid <= 1.0_dp .and. all(p <= huge(1.0_dp)))) info = STAT_NOT_FINITE
                return
            end if
            info = STAT_NOT_CONVERGED
        end do
    end subroutine visco_line_normal

    !> u = A p with A(i, j) = k(i - j) (O(n nc), nc the non-zero pressures).
    pure subroutine toeplitz_apply(n, k, p, u)
        integer, intent(in) :: n
        real(dp), intent(in) :: k(-(n - 1):n - 1), p(n)
        real(dp), intent(out) :: u(n)
        integer :: i, j
        u = 0.0_dp
        do j = 1, n
            if (p(j) == 0.0_dp) cycle
            do i = 1, n
                u(i) = u(i) + k(i - j) * p(j)
            end do
        end do
    end subroutine toeplitz_apply

    !> The equality-constrained solve on the set in_c: [A_CC, -1; d 1^T, 0] [p_C; delta]
    !> = [-h_C; fn]; p = 0 outside the set.
    subroutine solve_on_set(n, d, h, k, fn, in_c, p, approach, info)
        integer, intent(in) :: n
        real(dp), intent(in) :: d, h(n), k(-(n - 1):n - 1), fn
        logical, intent(in) :: in_c(n)
        real(dp), intent(inout) :: p(n)
        real(dp), intent(out) :: approach
        integer, intent(out) :: info
        real(dp), allocatable :: a(:, :), rhs(:, :)
        integer, allocatable :: idx(:), ipiv(:)
        integer :: nc, i, j, lapack_info

        nc = count(in_c)
        idx = pack([(i, i=1, n)], in_c)
        allocate (a(nc + 1, nc + 1), rhs(nc + 1, 1), ipiv(nc + 1))
        do j = 1, nc
            do i = 1, nc
                a(i, j) = k(idx(i) - idx(j))
            end do
            a(nc + 1, j) = d
            a(j, nc + 1) = -1.0_dp
            rhs(j, 1) = -h(idx(j))
        end do
        a(nc + 1, nc + 1) = 0.0_dp
        rhs(nc + 1, 1) = fn
        call dgesv(nc + 1, 1, a, nc + 1, ipiv, rhs, nc + 1, lapack_info)
        if (lapack_info /= 0) then
            info = STAT_SINGULAR
            return
        end if
        p = 0.0_dp
        p(idx) = rhs(1:nc, 1)
        approach = rhs(nc + 1, 1)
        info = STAT_OK
    end subroutine solve_on_set

end module contact_viscoelastic
