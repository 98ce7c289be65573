!> Steady rolling of viscoelastic bodies on the 3-D BEM grid: the normal problem of a
!> point contact (piecewise-constant pressure on nx x ny rectangles), each body rigid,
!> elastic or a standard linear solid (see contact_viscoelastic for the model).
!>
!> A body's displacement per unit compliance J = (1 - nu)/(2 G) is the Boussinesq field
!> ce = (1/pi) I[1/r] of each element (contact_influence, KERNEL_ZZ with G = 1, nu = 0);
!> steady rolling filters it along x with the creep function,
!>     cf(X, Y) = Int_0^inf (1/L) exp(-s/L) ce(X + s, Y) ds,         L = V tc,   (eq. VE9)
!> and the coefficient field of the pair is sum_b J0_b ce + (Jinf_b - J0_b) cf_b. The filter
!> runs backwards along each lateral offset Y over nodes at half an element (ce is smooth
!> between them: its kinks lie at X = +-dx/2), then geometrically spaced nodes beyond the
!> grid up to 50 L ahead (the memory left out weighs exp(-50)). On each interval the weight
!> exp(-(t - ta)/L)/L is mapped to a uniform one, t = ta - L ln(1 - v (1 - exp(-D/L))), and
!> integrated by 8-point Gauss-Legendre: accurate for L much smaller or larger than dx.
!> The field is translation-invariant, so products are FFT convolutions (contact_convolution)
!> with a non-symmetric kernel. The normal problem is solved by an active-set iteration whose
!> equality-constrained steps are two GMRES solves on the contact set (right-preconditioned
!> by the elastic half-space's inverse symbol with the instantaneous compliance).
!> Implements docs/equations.md eqs VE9-VE10.
module contact_viscoelastic_grid
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_NOT_CONVERGED, STAT_NOT_FINITE
    use contact_influence, only: influence_coefficient, KERNEL_ZZ, KERNEL_XX, KERNEL_YY, KERNEL_XY
    use contact_convolution, only: conv_plan, conv_init, conv_free, conv_apply, conv_init_precond, &
                                   conv_precond_buffer
    implicit none
    private
    public :: visco_grid_coefficients, visco_grid_normal, visco_grid_kernels

    !> GMRES restart length.
    integer, parameter :: RESTART = 40
    real(dp), parameter :: GAUSS_X(8) = [-0.960289856497536_dp, -0.796666477413627_dp, &
                                         -0.525532409916329_dp, -0.183434642495650_dp, &
                                         0.183434642495650_dp, 0.525532409916329_dp, &
                                         0.796666477413627_dp, 0.960289856497536_dp]
    real(dp), parameter :: GAUSS_W(8) = [0.101228536290376_dp, 0.222381034453374_dp, &
                                         0.313706645877887_dp, 0.362683783378362_dp, &
                                         0.362683783378362_dp, 0.313706645877887_dp, &
                                         0.222381034453374_dp, 0.101228536290376_dp]

contains

    !> Coefficient field c (influence_field's circular layout on 2nx x 2ny) of nb bodies
    !> with compliances j0, jinf (1/Pa) and memory lengths vlen = V tc (m; 0: relaxed).
    !> info: STAT_OK; STAT_BAD_ARGUMENT a size < 1, dx, dy <= 0, a compliance or vlen < 0.
    subroutine visco_grid_coefficients(nx, ny, dx, dy, nb, j0, jinf, vlen, c, info)
        integer, intent(in) :: nx, ny, nb
        real(dp), intent(in) :: dx, dy, j0(nb), jinf(nb), vlen(nb)
        real(dp), intent(out) :: c(0:2 * nx - 1, 0:2 * ny - 1)
        integer, intent(out) :: info
        real(dp), allocatable :: cf(:)
        real(dp) :: y, x, ce
        integer :: i, j, k, l, b

        c = 0.0_dp
        info = STAT_BAD_ARGUMENT
        if (nx < 1 .or. ny < 1 .or. .not. (dx > 0.0_dp .and. dy > 0.0_dp)) return
        if (any(.not. (j0 >= 0.0_dp)) .or. any(.not. (jinf >= 0.0_dp)) .or. &
            any(.not. (vlen >= 0.0_dp))) return
        info = STAT_OK
        allocate (cf(-(nx - 1):nx - 1))
        do j = 0, 2 * ny - 1
            if (j == ny) cycle
            l = j
            if (j > ny) l = j - 2 * ny
            y = l * dy
            do b = 1, nb
                if (jinf(b) /= j0(b) .and. vlen(b) > 0.0_dp) then
                    call filter_row(KERNEL_ZZ, 1.0_dp, 0.0_dp, nx, dx, dy, y, vlen(b), cf)
                else
                    cf = 0.0_dp
                end if
                do i = 0, 2 * nx - 1
                    if (i == nx) cycle
                    k = i
                    if (i > nx) k = i - 2 * nx
                    x = k * dx
                    ce = influence_coefficient(KERNEL_ZZ, x, y, dx, dy, 1.0_dp, 0.0_dp)
                    if (jinf(b) /= j0(b) .and. vlen(b) > 0.0_dp) then
                        c(i, j) = c(i, j) + j0(b) * ce + (jinf(b) - j0(b)) * cf(k)
                    else
                        c(i, j) = c(i, j) + jinf(b) * ce
                    end if
                end do
            end do
        end do
    end subroutine visco_grid_coefficients

    !> The four coefficient fields c(:, :, k) (k = 1 zz, 2 xx, 3 yy, 4 xy; influence_field's
    !> layout) of nb bodies with shear moduli g0 (instantaneous), ginf (relaxed), Poisson's
    !> ratios nu and memory lengths vlen = V tc: per body the one-body Boussinesq-Cerruti field
    !> of G0 (influence_coefficient with 2 G0) plus (G0/Ginf - 1) times its filter (eq. VE9),
    !> every kernel being proportional to the shear compliance. g0 = 0 marks a rigid body.
    !> Quasi-identical bodies (equal nu) decouple normal and tangential problems; otherwise the
    !> coupling is neglected (Kalker's approximation). info: STAT_OK; STAT_BAD_ARGUMENT.
    subroutine visco_grid_kernels(nx, ny, dx, dy, nb, g0, ginf, nu, vlen, c, info)
        integer, intent(in) :: nx, ny, nb
        real(dp), intent(in) :: dx, dy, g0(nb), ginf(nb), nu(nb), vlen(nb)
        real(dp), intent(out) :: c(0:2 * nx - 1, 0:2 * ny - 1, 4)
        integer, intent(out) :: info
        integer, parameter :: KERNELS(4) = [KERNEL_ZZ, KERNEL_XX, KERNEL_YY, KERNEL_XY]
        real(dp), allocatable :: cf(:)
        real(dp) :: y, extra
        integer :: i, j, k, l, b, kk
        logical :: visco

        c = 0.0_dp
        info = STAT_BAD_ARGUMENT
        if (nx < 1 .or. ny < 1 .or. .not. (dx > 0.0_dp .and. dy > 0.0_dp)) return
        if (any(.not. (g0 >= 0.0_dp)) .or. any(.not. (ginf > 0.0_dp .or. g0 == 0.0_dp)) .or. &
            any(.not. (vlen >= 0.0_dp))) return
        info = STAT_OK
        allocate (cf(-(nx - 1):nx - 1))
        do b = 1, nb
            if (g0(b) == 0.0_dp) cycle
            visco = ginf(b) /= g0(b) .and. vlen(b) > 0.0_dp
            extra = g0(b) / ginf(b) - 1.0_dp
            do kk = 1, 4
                do j = 0, 2 * ny - 1
                    if (j == ny) cycle
                    l = j
                    if (j > ny) l = j - 2 * ny
                    y = l * dy
                    if (visco) call filter_row(KERNELS(kk), 2.0_dp * g0(b), nu(b), nx, dx, dy, y, vlen(b), cf)
                    do i = 0, 2 * nx - 1
                        if (i == nx) cycle
                        k = i
                        if (i > nx) k = i - 2 * nx
                        if (visco) then
                            c(i, j, kk) = c(i, j, kk) + influence_coefficient(KERNELS(kk), k * dx, y, dx, dy, &
                                                                               2.0_dp * g0(b), nu(b)) + extra * cf(k)
                        else
                            c(i, j, kk) = c(i, j, kk) + (1.0_dp + extra) * influence_coefficient( &
                                          KERNELS(kk), k * dx, y, dx, dy, 2.0_dp * g0(b), nu(b))
                        end if
                    end do
                end do
            end do
        end do
    end subroutine visco_grid_kernels

    !> cf(k) = Int_0^inf (1/L) exp(-s/L) ce(k dx + s, y) ds, k = -(nx-1)..nx-1 (eq. VE9),
    !> by the backward recursion W(ta) = exp(-D/L) W(tb) + Int_ta^tb (1/L) exp(-(t-ta)/L) ce.
    subroutine filter_row(kernel, g, nu, nx, dx, dy, y, el, cf)
        integer, intent(in) :: kernel, nx
        real(dp), intent(in) :: g, nu, dx, dy, y, el
        real(dp), intent(out) :: cf(-(nx - 1):nx - 1)
        real(dp), allocatable :: t(:)
        real(dp) :: w, step, tmax
        integer :: m, nfine, nt, q

        ! nodes: half-element steps over the grid's offsets, then geometric growth
        nfine = 4 * (nx - 1)
        tmax = (nx - 1) * dx + 50.0_dp * el
        nt = nfine
        step = 0.5_dp * dx
        w = (nx - 1) * dx
        do while (w < tmax)
            step = 1.2_dp * step
            w = w + step
            nt = nt + 1
        end do
        allocate (t(0:nt))
        do m = 0, nfine
            t(m) = -(nx - 1) * dx + 0.5_dp * dx * m
        end do
        step = 0.5_dp * dx
        do m = nfine + 1, nt
            step = 1.2_dp * step
            t(m) = t(m - 1) + step
        end do
        w = influence_coefficient(kernel, t(nt), y, dx, dy, g, nu)
        do m = nt - 1, 0, -1
            w = exp(-(t(m + 1) - t(m)) / el) * w + segment(kernel, g, nu, t(m), t(m + 1), y, dx, dy, el)
            if (m <= nfine .and. mod(m, 2) == 0) then
                q = m / 2 - (nx - 1)
                cf(q) = w
            end if
        end do
    end subroutine filter_row

    !> Int_ta^tb (1/L) exp(-(t - ta)/L) ce(t, y) dt with the weight mapped to a uniform one.
    real(dp) function segment(kernel, g, nu, ta, tb, y, dx, dy, el) result(s)
        integer, intent(in) :: kernel
        real(dp), intent(in) :: g, nu, ta, tb, y, dx, dy, el
        real(dp) :: mass, v, t
        integer :: q
        mass = -exp_m1(-(tb - ta) / el)
        s = 0.0_dp
        do q = 1, 8
            v = 0.5_dp * (GAUSS_X(q) + 1.0_dp)
            t = min(tb, ta - el * log_1p(-v * mass))
            s = s + 0.5_dp * GAUSS_W(q) * influence_coefficient(kernel, t, y, dx, dy, g, nu)
        end do
        s = s * mass
    end function segment

    pure real(dp) function exp_m1(x)
        real(dp), intent(in) :: x
        if (abs(x) < 1.0e-5_dp) then
            exp_m1 = x + 0.5_dp * x * x + x**3 / 6.0_dp
        else
            exp_m1 = exp(x) - 1.0_dp
        end if
    end function exp_m1

    pure real(dp) function log_1p(x)
        real(dp), intent(in) :: x
        if (abs(x) < 1.0e-5_dp) then
            log_1p = x - 0.5_dp * x * x + x**3 / 3.0_dp
        else
            log_1p = log(1.0_dp + x)
        end if
    end function log_1p


    !> The normal problem on the grid with the coefficient field c (visco_grid_coefficients):
    !> p >= 0, e = h + C * p - delta >= 0, p e = 0, area_el sum(p) = fn. Active-set iteration
    !> (as in the line contact, contact_viscoelastic::visco_line_normal); on each set C two GMRES
    !> solves, C_CC p1 = 1 and C_CC ph = -h, give p = ph + delta p1 with delta from the force.
    !> The start set is {p > 0} of the given p, or all elements. jprec: the compliance of the
    !> preconditioner's elastic half-space (1/Pa), e.g. the sum of the instantaneous ones.
    !> resid as visco_line_normal. info: STAT_OK; STAT_NOT_CONVERGED max_iter set changes or
    !> a GMRES solve that stalled; STAT_NOT_FINITE a NaN; conv_init's status.
    subroutine visco_grid_normal(nx, ny, dx, dy, c, jprec, h, fn, tol, max_iter, p, u, approach, &
                                 iters, nprod, resid, info)
        integer, intent(in) :: nx, ny, max_iter
        real(dp), intent(in) :: dx, dy, c(0:2 * nx - 1, 0:2 * ny - 1), jprec, h(nx, ny), fn, tol
        real(dp), intent(inout) :: p(nx, ny)
        real(dp), intent(out) :: u(nx, ny), approach, resid
        integer, intent(out) :: iters, nprod, info
        type(conv_plan) :: plan
        real(dp), allocatable :: c3(:, :, :), p1(:, :), ph(:, :), e(:, :), b(:, :)
        logical :: in_c(nx, ny)
        real(dp) :: scale, area_el
        integer :: it, stat

        iters = 0
        nprod = 0
        resid = huge(1.0_dp)
        approach = 0.0_dp
        u = 0.0_dp
        info = STAT_BAD_ARGUMENT
        if (nx < 2 .or. ny < 2 .or. .not. fn > 0.0_dp .or. .not. jprec > 0.0_dp) return
        area_el = dx * dy
        allocate (c3(0:2 * nx - 1, 0:2 * ny - 1, 1), p1(nx, ny), ph(nx, ny), e(nx, ny), b(nx, ny))
        c3(:, :, 1) = c
        call conv_init(plan, nx, ny, c3, info)
        if (info == STAT_OK) call conv_init_precond(plan, 1.0_dp / jprec, 0.0_dp, dx, dy, info)
        if (info /= STAT_OK) then
            call conv_free(plan)
            return
        end if
        in_c = p > 0.0_dp
        if (.not. any(in_c)) in_c = .true.
        p1 = 0.0_dp
        ph = 0.0_dp
        info = STAT_NOT_CONVERGED
        do it = 1, max_iter
            iters = it
            b = merge(1.0_dp, 0.0_dp, in_c)
            call gmres_on_set(plan, in_c, b, p1, 0.1_dp * tol, 50 * RESTART, nprod, stat)
            if (stat == STAT_OK) then
                b = merge(-h, 0.0_dp, in_c)
                call gmres_on_set(plan, in_c, b, ph, 0.1_dp * tol, 50 * RESTART, nprod, stat)
            end if
            if (stat /= STAT_OK) exit
            approach = (fn / area_el - sum(ph, mask=in_c)) / sum(p1, mask=in_c)
            p = merge(ph + approach * p1, 0.0_dp, in_c)
            if (any(p < 0.0_dp)) then
                in_c = in_c .and. p >= 0.0_dp
                p = max(p, 0.0_dp)
                cycle
            end if
            call conv_apply(plan, 1, p, u)
            nprod = nprod + 1
            e = h + u - approach
            scale = maxval(abs(u)) + maxval(abs(h - approach), mask=in_c)
            resid = (maxval(abs(e), mask=in_c) + max(0.0_dp, -minval(e, mask=.not. in_c &
                                                                     .and. e < 0.0_dp))) / scale
            if (any(.not. in_c .and. e < -tol * scale)) then
                in_c = in_c .or. e < -tol * scale
                cycle
            end if
            info = STAT_OK
            if (.not. (resid <= 1.0_dp .and. all(abs(p) <= huge(1.0_dp)))) info = STAT_NOT_FINITE
            exit
        end do
        call conv_free(plan)
    end subroutine visco_grid_normal

    !> Right-preconditioned restarted GMRES for P_C A P_C x = b on the set in_c (x and b zero
    !> outside it), from the start x; stops at ||r|| <= rtol ||b|| or after maxit products.
    !> info: STAT_OK or STAT_NOT_CONVERGED.
    subroutine gmres_on_set(plan, in_c, b, x, rtol, maxit, nprod, info)
        type(conv_plan), intent(inout) :: plan
        logical, intent(in) :: in_c(:, :)
        real(dp), intent(in) :: b(:, :), rtol
        real(dp), intent(inout) :: x(:, :)
        integer, intent(in) :: maxit
        integer, intent(inout) :: nprod
        integer, intent(out) :: info
        real(dp), allocatable :: v(:, :, :), w(:, :), z(:, :)
        real(dp) :: hh(RESTART + 1, RESTART), g(RESTART + 1), cs(RESTART), sn(RESTART), y(RESTART)
        real(dp) :: bnorm, beta, tmp
        integer :: nx, ny, k, i, kk, used

        nx = size(b, 1)
        ny = size(b, 2)
        allocate (v(nx, ny, RESTART + 1), w(nx, ny), z(nx, ny))
        info = STAT_OK
        x = merge(x, 0.0_dp, in_c)
        bnorm = norm2(b)
        if (bnorm == 0.0_dp) then
            x = 0.0_dp
            return
        end if
        used = 0
        do while (used < maxit)
            call conv_apply(plan, 1, x, w)
            nprod = nprod + 1
            used = used + 1
            w = merge(b - w, 0.0_dp, in_c)
            beta = norm2(w)
            if (beta <= rtol * bnorm) return
            v(:, :, 1) = w / beta
            g = 0.0_dp
            g(1) = beta
            kk = 0
            do k = 1, RESTART
                kk = k
                call precondition(plan, in_c, v(:, :, k), z)
                call conv_apply(plan, 1, z, w)
                nprod = nprod + 1
                used = used + 1
                w = merge(w, 0.0_dp, in_c)
                do i = 1, k
                    hh(i, k) = sum(w * v(:, :, i))
                    w = w - hh(i, k) * v(:, :, i)
                end do
                hh(k + 1, k) = norm2(w)
                if (hh(k + 1, k) > 0.0_dp) v(:, :, k + 1) = w / hh(k + 1, k)
                do i = 1, k - 1
                    tmp = cs(i) * hh(i, k) + sn(i) * hh(i + 1, k)
                    hh(i + 1, k) = -sn(i) * hh(i, k) + cs(i) * hh(i + 1, k)
                    hh(i, k) = tmp
                end do
                tmp = hypot(hh(k, k), hh(k + 1, k))
                cs(k) = hh(k, k) / tmp
                sn(k) = hh(k + 1, k) / tmp
                hh(k, k) = tmp
                hh(k + 1, k) = 0.0_dp
                g(k + 1) = -sn(k) * g(k)
                g(k) = cs(k) * g(k)
                if (abs(g(k + 1)) <= rtol * bnorm .or. used >= maxit) exit
            end do
            ! y = H^-1 g (upper triangular), x = x + M V y
            do i = kk, 1, -1
                y(i) = (g(i) - sum(hh(i, i + 1:kk) * y(i + 1:kk))) / hh(i, i)
            end do
            w = 0.0_dp
            do i = 1, kk
                w = w + y(i) * v(:, :, i)
            end do
            call precondition(plan, in_c, w, z)
            x = x + z
            if (abs(g(kk + 1)) <= rtol * bnorm) return
        end do
        info = STAT_NOT_CONVERGED
    end subroutine gmres_on_set

    !> z = P_C M P_C r with M the elastic half-space's inverse symbol (conv_precond_buffer).
    subroutine precondition(plan, in_c, r, z)
        type(conv_plan), intent(inout) :: plan
        logical, intent(in) :: in_c(:, :)
        real(dp), intent(in) :: r(:, :)
        real(dp), intent(out) :: z(:, :)
        plan%prbuf = merge(r, 0.0_dp, in_c)
        call conv_precond_buffer(plan)
        z = merge(plan%prbuf, 0.0_dp, in_c)
    end subroutine precondition

end module contact_viscoelastic_grid
