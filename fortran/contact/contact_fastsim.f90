!> Kalker's simplified theory of rolling contact, FASTSIM (Kalker 1982,
!> "A fast algorithm for the simplified theory of rolling contact", Vehicle
!> System Dynamics 11, 1-13; Kalker 1990, "Three-dimensional elastic bodies
!> in rolling contact", sect. 3.3).
!>
!> Conventions (those of the linear theory, Kalker 1990 Table E.3):
!> rolling in +x, material particles move through the patch in -x from the
!> leading edge x = +a(y) to the trailing edge x = -a(y). Rigid slip per unit
!> rolled distance w = (xi - phi y, eta + phi x). The simplified theory puts
!> the surface displacement u = L tau with one flexibility per creepage
!> component: L1 = 8a/(3 C11 G) for xi, L2 = 8a/(3 C22 G) for eta and
!> L3 = pi a^2 / (4 C23 G sqrt(a b)) for phi. In adhesion du/dx = w, so
!>   dtau_x/dx = xi/L1 - phi y/L3,  dtau_y/dx = eta/L2 + phi x/L3,
!> integrated from tau = 0 at the leading edge; where the trial traction
!> leaves the Coulomb disc |tau| <= mu p it is scaled back onto it (slip).
!> In the linear limit this gives Fx = -G a b C11 xi and
!> Fy = -G a b C22 eta - G (ab)^1.5 C23 phi on an ellipse (exact; the
!> midpoint rule is exact for the linear x profiles and the L's were chosen
!> for these integrals).
!>
!> Slip s (per unit rolled distance, slip velocity = V s): the elastic part
!> of the step, s = L_eff (tau - tau_trial)/h, with Kalker's weighted
!> flexibility L_eff = (|xi| L1 + |eta| L2 + c |phi| L3)/sqrt(xi^2 + eta^2
!> + c^2 phi^2), c = sqrt(a b). It is antiparallel to tau by construction.
!> Implements FASTSIM (Kalker 1982) and the interpolation of Kalker's Table E.3
!> (kalker_interp); no Kaiser equation.
module contact_fastsim
    use common_kinds, only: dp, pi
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_NO_CONTACT
    implicit none
    private
    public :: fastsim_ellipse, fastsim_ellipse_fields, fastsim_strips, kalker_interp, kalker_ratio_in_table
    public :: flexibilities, shape_pressure, discrete_load

contains

    !> One element of a strip: march the traction from xold to xnew (< xold)
    !> at lateral position y, bound it by the Coulomb disc of radius bound.
    pure subroutine step_element(tx, ty, xold, xnew, y, cx, cy, cs, leff, bound, sx, sy, slipping)
        real(dp), intent(inout) :: tx, ty        ! traction at xold on entry, at xnew on exit, Pa
        real(dp), intent(in) :: xold, xnew, y    ! m
        real(dp), intent(in) :: cx, cy, cs       ! xi/L1, eta/L2, phi/L3
        real(dp), intent(in) :: leff             ! flexibility for the slip, m/Pa
        real(dp), intent(in) :: bound            ! mu p, Pa
        real(dp), intent(out) :: sx, sy          ! slip per unit rolled distance
        logical, intent(out) :: slipping
        real(dp) :: h, ux, uy, t
        h = xold - xnew
        ! exact for the linear (spin: quadratic) adhesion profiles: x at mid-step
        ux = tx - (cx - cs * y) * h
        uy = ty - (cy + cs * 0.5_dp * (xold + xnew)) * h
        t = ux * ux + uy * uy       ! squared: no hypot call in the innermost loop
        if (t > bound * bound) then
            t = sqrt(t)
            if (t > 0.0_dp) then
                tx = ux * (bound / t)
                ty = uy * (bound / t)
            else
                tx = 0.0_dp
                ty = 0.0_dp
            end if
            sx = leff * (tx - ux) / h
            sy = leff * (ty - uy) / h
            slipping = .true.
        else
            tx = ux
            ty = uy
            sx = 0.0_dp
            sy = 0.0_dp
            slipping = .false.
        end if
    end subroutine step_element

    !> Flexibilities from the equivalent ellipse (a, b) and the coefficients.
    !> ok = .false. when an argument makes them undefined.
    pure subroutine flexibilities(a, b, g, c11, c22, c23, xi, eta, phi, cx, cy, cs, leff, ok)
        real(dp), intent(in) :: a, b, g, c11, c22, c23, xi, eta, phi
        real(dp), intent(out) :: cx, cy, cs, leff
        logical, intent(out) :: ok
        real(dp) :: l1, l2, l3, c, den
        cx = 0.0_dp
        cy = 0.0_dp
        cs = 0.0_dp
        leff = 0.0_dp
        ok = a > 0.0_dp .and. b > 0.0_dp .and. g > 0.0_dp .and. c11 > 0.0_dp &
             .and. c22 > 0.0_dp .and. c23 > 0.0_dp
        if (.not. ok) return
        l1 = 8.0_dp * a / (3.0_dp * c11 * g)
        l2 = 8.0_dp * a / (3.0_dp * c22 * g)
        l3 = pi * a * a / (4.0_dp * c23 * g * sqrt(a * b))
        cx = xi / l1
        cy = eta / l2
        cs = phi / l3
        c = sqrt(a * b)
        den = sqrt(xi * xi + eta * eta + (c * phi)**2)
        if (den > 0.0_dp) then
            leff = (abs(xi) * l1 + abs(eta) * l2 + c * abs(phi) * l3) / den
        else
            leff = l1
        end if
    end subroutine flexibilities

    !> Normal pressure at (x, y) of an elliptic patch, normalised by p0.
    !> kind 1: parabolic 1 - (x/a)^2 - (y/b)^2 (FASTSIM's usual choice);
    !> kind 2: Hertz, sqrt of the same.
    pure elemental function shape_pressure(kind, x, y, a, b) result(p)
        integer, intent(in) :: kind
        real(dp), intent(in) :: x, y, a, b
        real(dp) :: p
        p = max(0.0_dp, 1.0_dp - (x / a)**2 - (y / b)**2)
        if (kind == 2) p = sqrt(p)
    end function shape_pressure

    !> Creep forces and spin moment on an elliptic patch by FASTSIM with the
    !> parabolic pressure p = 2 fn/(pi a b) (1 - x^2/a^2 - y^2/b^2), rescaled
    !> so that its discrete sum equals fn. ny strips of equal width 2b/ny,
    !> nx equal elements per strip, tractions at element centres.
    !> fn <= 0, or a, b, g or a coefficient <= 0, or nx, ny < 1: zero forces.
    pure subroutine fastsim_ellipse(a, b, g, c11, c22, c23, mu, fn, xi, eta, phi, nx, ny, fx, fy, mz)
        real(dp), intent(in) :: a, b        ! semi-axes, m (a along rolling direction x)
        real(dp), intent(in) :: g           ! combined shear modulus, Pa
        real(dp), intent(in) :: c11, c22, c23  ! Kalker's creep coefficients for a/b and nu
        real(dp), intent(in) :: mu, fn      ! friction coefficient, normal force (N)
        real(dp), intent(in) :: xi, eta, phi   ! longitudinal, lateral creepage (-), spin (1/m)
        integer, intent(in) :: nx, ny       ! points along x per strip, number of strips
        real(dp), intent(out) :: fx, fy, mz ! creep forces (N) and spin moment (N m)
        real(dp) :: cx, cy, cs, leff, p0, dys, y, aj, dxj, xold, xnew, tx, ty, sx, sy, da
        integer :: i, j
        logical :: ok, slipping
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        if (fn <= 0.0_dp .or. nx < 1 .or. ny < 1) return
        call flexibilities(a, b, g, c11, c22, c23, xi, eta, phi, cx, cy, cs, leff, ok)
        if (.not. ok) return
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
            do i = 1, nx
                xnew = aj - (i - 0.5_dp) * dxj
                call step_element(tx, ty, xold, xnew, y, cx, cy, cs, leff, &
                                  max(mu, 0.0_dp) * p0 * shape_pressure(1, xnew, y, a, b), sx, sy, slipping)
                fx = fx + tx * da
                fy = fy + ty * da
                mz = mz + (xnew * ty - y * tx) * da
                xold = xnew
            end do
        end do
    end subroutine fastsim_ellipse

    !> Sum of shape_pressure(kind) dA over the strip grid of an ellipse.
    pure function discrete_load(kind, a, b, nx, ny) result(s)
        integer, intent(in) :: kind, nx, ny
        real(dp), intent(in) :: a, b
        real(dp) :: s, dys, y, aj, dxj
        integer :: i, j
        s = 0.0_dp
        dys = 2.0_dp * b / ny
        do j = 1, ny
            y = -b + (j - 0.5_dp) * dys
            aj = a * sqrt(max(0.0_dp, 1.0_dp - (y / b)**2))
            dxj = 2.0_dp * aj / nx
            do i = 1, nx
                s = s + shape_pressure(kind, aj - (i - 0.5_dp) * dxj, y, a, b) * dxj * dys
            end do
        end do
    end function discrete_load

    !> FASTSIM on an ellipse with the fields on the (nx, ny) strip grid:
    !> element (i, j) is centred at (x(i, j), y(j)), i = 1 at the leading edge.
    !> pkind 1 parabolic, 2 Hertz pressure (both scaled to sum to fn).
    !> info: STAT_OK; STAT_BAD_ARGUMENT a, b, g or a coefficient <= 0, fn <= 0,
    !> or pkind not 1 or 2.
    pure subroutine fastsim_ellipse_fields(a, b, g, c11, c22, c23, mu, fn, xi, eta, phi, nx, ny, pkind, &
                                           x, y, pn, tx, ty, sx, sy, slip, fx, fy, mz, info)
        real(dp), intent(in) :: a, b, g, c11, c22, c23, mu, fn, xi, eta, phi
        integer, intent(in) :: nx, ny, pkind
        real(dp), intent(out) :: x(nx, ny), y(ny)   ! element centres, m
        real(dp), intent(out) :: pn(nx, ny)         ! normal pressure, Pa
        real(dp), intent(out) :: tx(nx, ny), ty(nx, ny)  ! tangential traction on the body, Pa
        real(dp), intent(out) :: sx(nx, ny), sy(nx, ny)  ! slip per unit rolled distance
        integer, intent(out) :: slip(nx, ny)        ! 1 slip, 0 adhesion
        real(dp), intent(out) :: fx, fy, mz
        integer, intent(out) :: info
        real(dp) :: cx, cy, cs, leff, p0, dys, aj, dxj, xold, t1, t2, da
        integer :: i, j
        logical :: ok, slipping
        x = 0.0_dp
        y = 0.0_dp
        pn = 0.0_dp
        tx = 0.0_dp
        ty = 0.0_dp
        sx = 0.0_dp
        sy = 0.0_dp
        slip = 0
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        info = STAT_OK
        call flexibilities(a, b, g, c11, c22, c23, xi, eta, phi, cx, cy, cs, leff, ok)
        if (.not. ok .or. fn <= 0.0_dp .or. (pkind /= 1 .and. pkind /= 2)) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        p0 = fn / discrete_load(pkind, a, b, nx, ny)
        dys = 2.0_dp * b / ny
        do j = 1, ny
            y(j) = -b + (j - 0.5_dp) * dys
            aj = a * sqrt(max(0.0_dp, 1.0_dp - (y(j) / b)**2))
            dxj = 2.0_dp * aj / nx
            da = dxj * dys
            t1 = 0.0_dp
            t2 = 0.0_dp
            xold = aj
            do i = 1, nx
                x(i, j) = aj - (i - 0.5_dp) * dxj
                pn(i, j) = p0 * shape_pressure(pkind, x(i, j), y(j), a, b)
                call step_element(t1, t2, xold, x(i, j), y(j), cx, cy, cs, leff, &
                                  max(mu, 0.0_dp) * pn(i, j), sx(i, j), sy(i, j), slipping)
                tx(i, j) = t1
                ty(i, j) = t2
                if (slipping) slip(i, j) = 1
                fx = fx + t1 * da
                fy = fy + t2 * da
                mz = mz + (x(i, j) * t2 - y(j) * t1) * da
                xold = x(i, j)
            end do
        end do
    end subroutine fastsim_ellipse_fields

    !> Strip-wise FASTSIM on a grid with a given normal pressure p (e.g. from
    !> the BEM): each column j (constant y) is a strip; every run of elements
    !> with p > 0 is marched from its leading edge (largest x, element front
    !> face) with tau = 0 there. Element (i, j) is centred at
    !> (x0 + (i-1) dx, y0 + (j-1) dy).
    !> Flexibilities from the equivalent ellipse (ae, be) and c11..c23;
    !> lmode 1: the same L1, L2, L3 on every strip (Kalker);
    !> lmode 2: L scaled on each run by its half-length a_r, L_r = L k a_r with
    !> k = sum(a_r) / sum(a_r^2) (sums over runs), so the linear-theory
    !> longitudinal force of the equivalent ellipse is kept while short strips
    !> get stiffer (strip-theory idea, cf. Sichani et al. 2016, FaStrip).
    !> info: STAT_OK; STAT_BAD_ARGUMENT dx or dy <= 0, lmode not 1 or 2, or ae,
    !> be, g or a coefficient <= 0; STAT_NO_CONTACT no element with p > 0.
    pure subroutine fastsim_strips(nx, ny, dx, dy, x0, y0, p, g, c11, c22, c23, ae, be, mu, &
                                   xi, eta, phi, lmode, tx, ty, sx, sy, slip, fx, fy, mz, info)
        integer, intent(in) :: nx, ny, lmode
        real(dp), intent(in) :: dx, dy, x0, y0     ! element size and first centre, m
        real(dp), intent(in) :: p(nx, ny)          ! normal pressure, Pa
        real(dp), intent(in) :: g, c11, c22, c23, ae, be, mu, xi, eta, phi
        real(dp), intent(out) :: tx(nx, ny), ty(nx, ny), sx(nx, ny), sy(nx, ny)
        integer, intent(out) :: slip(nx, ny)
        real(dp), intent(out) :: fx, fy, mz
        integer, intent(out) :: info
        real(dp) :: cx, cy, cs, leff, y, xold, xi_c, t1, t2, da, sum1, sum2, k, ar, scale
        integer :: i, j, i_end, i_start
        logical :: ok, slipping
        tx = 0.0_dp
        ty = 0.0_dp
        sx = 0.0_dp
        sy = 0.0_dp
        slip = 0
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        info = STAT_OK
        call flexibilities(ae, be, g, c11, c22, c23, xi, eta, phi, cx, cy, cs, leff, ok)
        if (dx <= 0.0_dp .or. dy <= 0.0_dp .or. (lmode /= 1 .and. lmode /= 2) .or. .not. ok) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        if (.not. any(p > 0.0_dp)) then
            info = STAT_NO_CONTACT
            return
        end if
        ! lmode 2: k = sum(a_r) / sum(a_r^2) over all runs of contact
        k = 1.0_dp
        if (lmode == 2) then
            sum1 = 0.0_dp
            sum2 = 0.0_dp
            do j = 1, ny
                i = nx
                do while (i >= 1)
                    if (p(i, j) > 0.0_dp) then
                        i_start = i
                        do while (i >= 1)
                            if (.not. p(i, j) > 0.0_dp) exit
                            i = i - 1
                        end do
                        ar = 0.5_dp * dx * (i_start - i)
                        sum1 = sum1 + ar
                        sum2 = sum2 + ar * ar
                    else
                        i = i - 1
                    end if
                end do
            end do
            k = sum1 / sum2
        end if
        da = dx * dy
        do j = 1, ny
            y = y0 + (j - 1) * dy
            i = nx
            do while (i >= 1)
                if (.not. p(i, j) > 0.0_dp) then
                    i = i - 1
                    cycle
                end if
                ! a run of contact from i_start down to i_end
                i_start = i
                i_end = i
                do while (i_end > 1)
                    if (.not. p(i_end - 1, j) > 0.0_dp) exit
                    i_end = i_end - 1
                end do
                scale = 1.0_dp
                if (lmode == 2) scale = 1.0_dp / (k * 0.5_dp * dx * (i_start - i_end + 1))
                t1 = 0.0_dp
                t2 = 0.0_dp
                xold = x0 + (i_start - 1) * dx + 0.5_dp * dx
                do i = i_start, i_end, -1
                    xi_c = x0 + (i - 1) * dx
                    ! L -> L / scale: the rates c = creepage/L scale up, leff down
                    call step_element(t1, t2, xold, xi_c, y, cx * scale, cy * scale, cs * scale, &
                                      leff / scale, max(mu, 0.0_dp) * p(i, j), sx(i, j), sy(i, j), slipping)
                    tx(i, j) = t1
                    ty(i, j) = t2
                    if (slipping) slip(i, j) = 1
                    fx = fx + t1 * da
                    fy = fy + t2 * da
                    mz = mz + (xi_c * t2 - y * t1) * da
                    xold = xi_c
                end do
                i = i_end - 1
            end do
        end do
    end subroutine fastsim_strips

    !> Kalker's creep coefficients C11, C22, C23 for a/b and nu, interpolated in
    !> Kalker's Table E.3 (J.J. Kalker, "Three-dimensional elastic bodies in
    !> rolling contact", Kluwer 1990) as railvti.contact.kalker does (same values
    !> to rounding): monotone piecewise-cubic Hermite (PCHIP, Fritsch-Butland
    !> slopes, one-sided three-point end slopes) in log(a/b), linear in nu
    !> between the columns nu = 0, 0.25, 0.5.
    !> The table is the caller's: its one copy is python/railvti/data/kalker_table_e3.csv
    !> (with its source lines), read by railvti.contact.kalker.kalker_table and
    !> passed in here: ab(n) the tabulated a/b, ascending; tab(n, 9) the columns
    !> C11 (nu = 0, 0.25, 0.5), C22 (same), C23 (same).
    !> info: STAT_OK; STAT_BAD_ARGUMENT a/b outside [ab(1), ab(n)] (see
    !> kalker_ratio_in_table) or nu outside [0, 0.5] (c11 = c22 = c23 = 0).
    pure subroutine kalker_interp(ab, tab, a_over_b, nu, c11, c22, c23, info)
        real(dp), intent(in) :: ab(:), tab(:, :)
        real(dp), intent(in) :: a_over_b, nu
        real(dp), intent(out) :: c11, c22, c23
        integer, intent(out) :: info
        real(dp) :: t, v(9), w, lab(size(ab))
        integer :: m, k, n
        c11 = 0.0_dp
        c22 = 0.0_dp
        c23 = 0.0_dp
        info = STAT_OK
        n = size(ab)
        if (.not. kalker_ratio_in_table(ab, a_over_b) .or. .not. (nu >= 0.0_dp .and. nu <= 0.5_dp) &
            .or. n < 3 .or. size(tab, 1) /= n .or. size(tab, 2) /= 9) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        ! A scalar loop: gfortran -O3 would vectorize log(ab) with glibc's libmvec,
        ! whose vector log is not correctly rounded (1 ulp off for some nodes, and
        ! then the interpolated values differ from the Python ones in the last bit).
        !GCC$ novector
        do k = 1, n
            lab(k) = log(ab(k))
        end do
        t = min(max(log(a_over_b), lab(1)), lab(n))
        do k = 1, 9
            v(k) = pchip_eval(n, lab, tab(:, k), t)
        end do
        m = min(int(nu / 0.25_dp), 1)
        w = (nu - 0.25_dp * m) / 0.25_dp
        c11 = (1.0_dp - w) * v(1 + m) + w * v(2 + m)
        c22 = (1.0_dp - w) * v(4 + m) + w * v(5 + m)
        c23 = (1.0_dp - w) * v(7 + m) + w * v(8 + m)
    end subroutine kalker_interp

    !> True when a_over_b lies in the table's range [ab(1), ab(n)], with a
    !> relative tolerance of 1e-12 so that e.g. 1/(1/10) is accepted.
    pure logical function kalker_ratio_in_table(ab, a_over_b) result(inside)
        real(dp), intent(in) :: ab(:), a_over_b
        inside = size(ab) > 0
        if (.not. inside) return
        inside = a_over_b >= ab(1) * (1.0_dp - 1.0e-12_dp) .and. a_over_b <= ab(size(ab)) * (1.0_dp + 1.0e-12_dp)
    end function kalker_ratio_in_table

    !> Value at t (x(1) <= t <= x(n)) of the monotone piecewise-cubic Hermite
    !> interpolant of (x, y): slopes 0 at local extrema, weighted harmonic
    !> means of the secants elsewhere (Fritsch & Butland 1984), shape-preserving
    !> three-point slopes at the ends.
    pure function pchip_eval(n, x, y, t) result(f)
        integer, intent(in) :: n
        real(dp), intent(in) :: x(n), y(n), t
        real(dp) :: f, h(n - 1), del(n - 1), d(n), w1, w2, s, u
        integer :: k
        h = x(2:n) - x(1:n - 1)
        del = (y(2:n) - y(1:n - 1)) / h
        do k = 2, n - 1
            if (del(k - 1) * del(k) <= 0.0_dp) then
                d(k) = 0.0_dp
            else
                w1 = 2.0_dp * h(k) + h(k - 1)
                w2 = h(k) + 2.0_dp * h(k - 1)
                d(k) = (w1 + w2) / (w1 / del(k - 1) + w2 / del(k))
            end if
        end do
        d(1) = end_slope(h(1), h(2), del(1), del(2))
        d(n) = end_slope(h(n - 1), h(n - 2), del(n - 1), del(n - 2))
        k = 1
        do while (k < n - 1)
            if (t < x(k + 1)) exit
            k = k + 1
        end do
        s = t - x(k)
        u = s / h(k)
        ! cubic Hermite on [x(k), x(k+1)]
        f = y(k) * (1.0_dp + 2.0_dp * u) * (1.0_dp - u)**2 + y(k + 1) * u * u * (3.0_dp - 2.0_dp * u) &
            + d(k) * s * (1.0_dp - u)**2 - d(k + 1) * s * u * (1.0_dp - u)
    end function pchip_eval

    pure function end_slope(h0, h1, m0, m1) result(d)
        real(dp), intent(in) :: h0, h1, m0, m1
        real(dp) :: d
        d = ((2.0_dp * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        if (d * m0 <= 0.0_dp) then
            d = 0.0_dp
        else if (m0 * m1 <= 0.0_dp .and. abs(d) > 3.0_dp * abs(m0)) then
            d = 3.0_dp * m0
        end if
    end function end_slope

end module contact_fastsim
