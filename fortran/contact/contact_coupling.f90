!> Normal-tangential coupling of two elastic bodies of dissimilar materials
!> (Kalker 1990, sect. 1.5, eq. 1.44; Johnson 1985, eqs 3.19 and 3.86).
!>
!> Body 1 (the wheel, the upper body) carries the tractions (p, tx, ty); body 2
!> (the rail) carries (p, -tx, -ty). With the combined constants
!>   1/G = (1/G1 + 1/G2) / 2,  nu/G = (nu1/G1 + nu2/G2) / 2,
!>   K = G/4 ((1 - 2 nu1)/G1 - (1 - 2 nu2)/G2)          (Kalker's difference parameter)
!> the displacement differences u = u(1) - u(2) (tangential) and the normal
!> displacement sum (the gap's increase, as in A_zz) are those of
!> contact_influence with (G, nu) plus the cross terms
!>   u_x += A_xz p,   u_y += A_yz p,   u_n += A_zx tx + A_zy ty,
!>   A_xz = -A_zx = -K/(pi G) I[X/r^2],   A_yz = -A_zy = -K/(pi G) I[Y/r^2],
!> I[f] the integral of f over the source element at offset (X, Y) (observation
!> minus source). Derivation (docs/contact_dissimilar.md): a point load P
!> pressing on a half-space moves its surface radially inwards by
!> (1 - 2 nu) P/(4 pi G r) (Boussinesq, Johnson eq. 3.19b), in both bodies, so the
!> difference is -K/(pi G) P X/r^2; by reciprocity (Betti) a tangential point
!> load Q on a half-space moves the surface ahead of it into the body by
!> (1 - 2 nu) Q X/(4 pi G r^2) (Cerruti, Johnson eq. 3.86c), which with Q on body 1
!> and -Q on body 2 opens the gap by K/(pi G) Q X/r^2. The full operator stays
!> symmetric (A_xz(X) = A_zx(-X)). K = beta (1 - nu), beta Dundurs' second
!> constant (Johnson eq. 5.4). K = 0 for identical materials.
!>
!> The corner functions (d2 Phi / dX dY = f):
!>   X/r^2 -> X atan(Y/X) + Y/2 ln(X^2 + Y^2)
!>   Y/r^2 -> Y atan(X/Y) + X/2 ln(X^2 + Y^2)
!>
!> Also here: the products of the cross terms by direct sums over the loaded
!> elements (coupling_apply), the rigid-slip field the pressure adds in steady
!> rolling (coupling_rolling_slip, with contact_rolling's upwind stencil) and the
!> tangential problem of one load step of a quasi-static loading history (shift
!> problem, coupling_shift_step: the slip is the increment of the tangential
!> displacement difference; Kalker 1990 sect. 5.2 transient theory with no rolling).
!> Implements Kalker 1990 eq. 1.44 (the combined constants and K) and the cross
!> influence coefficients A_xz, A_zx (Boussinesq-Cerruti of two bodies); no Kaiser equation.
module contact_coupling
    use common_kinds, only: dp, pi
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, STAT_NOT_FINITE
    use contact_influence, only: KERNEL_XX, KERNEL_YY, KERNEL_XY, influence_field
    use contact_rolling, only: element_solve, ST_EXTERIOR, WU0, WU1, WU2
    implicit none
    private
    public :: CROSS_X, CROSS_Y
    public :: cross_coefficient, cross_field, coupling_apply, coupling_rolling_slip, coupling_shift_step

    integer, parameter :: CROSS_X = 1, CROSS_Y = 2

contains

    !> Corner function of X/r^2 (kernel CROSS_X) or Y/r^2 (CROSS_Y); zero at the origin.
    pure real(dp) function cross_corner(kernel, x, y) result(f)
        integer, intent(in) :: kernel
        real(dp), intent(in) :: x, y
        real(dp) :: a, b, r2
        if (kernel == CROSS_X) then
            a = x
            b = y
        else
            a = y
            b = x
        end if
        r2 = x * x + y * y
        f = 0.0_dp
        if (a /= 0.0_dp) f = a * atan(b / a)
        if (b /= 0.0_dp) f = f + 0.5_dp * b * log(r2)
    end function cross_corner

    !> (1/pi) I[X/r^2] (CROSS_X) or (1/pi) I[Y/r^2] (CROSS_Y) over the element of size
    !> dx x dy whose centre lies at (-x, -y) from the observation point (offset (x, y) =
    !> observation minus source): the cross coefficient without its factor,
    !> A_xz = -K/G * this, m.
    pure real(dp) function cross_coefficient(kernel, x, y, dx, dy) result(c)
        integer, intent(in) :: kernel
        real(dp), intent(in) :: x, y, dx, dy
        real(dp) :: xp, xm, yp, ym
        xp = x + 0.5_dp * dx
        xm = x - 0.5_dp * dx
        yp = y + 0.5_dp * dy
        ym = y - 0.5_dp * dy
        c = (cross_corner(kernel, xp, yp) - cross_corner(kernel, xp, ym) &
             - cross_corner(kernel, xm, yp) + cross_corner(kernel, xm, ym)) / pi
    end function cross_coefficient

    !> cross_coefficient for every offset (k, l) = (i - i', j - j') of an nx x ny grid,
    !> c(k, l), k = 1-nx..nx-1, l = 1-ny..ny-1 (observation minus source).
    pure subroutine cross_field(kernel, nx, ny, dx, dy, c)
        integer, intent(in) :: kernel, nx, ny
        real(dp), intent(in) :: dx, dy
        real(dp), intent(out) :: c(1 - nx:nx - 1, 1 - ny:ny - 1)
        integer :: k, l
        do l = 1 - ny, ny - 1
            do k = 1 - nx, nx - 1
                c(k, l) = cross_coefficient(kernel, k * dx, l * dy, dx, dy)
            end do
        end do
    end subroutine cross_field

    !> Cross products by direct sums over the loaded elements:
    !> un = A_zx tx + A_zy ty (the gap's increase, m) and (ux, uy) = (A_xz p, A_yz p)
    !> (displacement difference, m), kg = K/G (1). O(N x loaded elements).
    subroutine coupling_apply(nx, ny, dx, dy, kg, p, tx, ty, un, ux, uy)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, kg
        real(dp), intent(in) :: p(nx, ny), tx(nx, ny), ty(nx, ny)
        real(dp), intent(out) :: un(nx, ny), ux(nx, ny), uy(nx, ny)
        real(dp), allocatable :: cx(:, :), cy(:, :)
        integer :: i, j, is, js
        un = 0.0_dp
        ux = 0.0_dp
        uy = 0.0_dp
        if (kg == 0.0_dp) return
        allocate (cx(1 - nx:nx - 1, 1 - ny:ny - 1), cy(1 - nx:nx - 1, 1 - ny:ny - 1))
        call cross_field(CROSS_X, nx, ny, dx, dy, cx)
        call cross_field(CROSS_Y, nx, ny, dx, dy, cy)
        do js = 1, ny
            do is = 1, nx
                if (p(is, js) == 0.0_dp .and. tx(is, js) == 0.0_dp .and. ty(is, js) == 0.0_dp) cycle
                do j = 1, ny
                    do i = 1, nx
                        un(i, j) = un(i, j) + kg * (cx(i - is, j - js) * tx(is, js) + cy(i - is, j - js) * ty(is, js))
                        ux(i, j) = ux(i, j) - kg * cx(i - is, j - js) * p(is, js)
                        uy(i, j) = uy(i, j) - kg * cy(i - is, j - js) * p(is, js)
                    end do
                end do
            end do
        end do
    end subroutine coupling_apply

    !> The rigid slip (creepage units) that the pressure adds in steady rolling:
    !> contact_rolling's three-point upwind difference (eq. 29) of u = A_xz p,
    !> A_yz p along x: w_I = (WU0 u_i + WU1 u_i+1 + WU2 u_i+2) / dx (zero in the
    !> last two rows, where no contact is allowed).
    subroutine coupling_rolling_slip(nx, ny, dx, dy, kg, p, wx, wy)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, kg, p(nx, ny)
        real(dp), intent(out) :: wx(nx, ny), wy(nx, ny)
        real(dp), allocatable :: z(:, :), un(:, :), ux(:, :), uy(:, :)
        integer :: i
        allocate (z(nx, ny), un(nx, ny), ux(nx, ny), uy(nx, ny))
        z = 0.0_dp
        call coupling_apply(nx, ny, dx, dy, kg, p, z, z, un, ux, uy)
        wx = 0.0_dp
        wy = 0.0_dp
        do i = 1, nx - 2
            wx(i, :) = (WU0 * ux(i, :) + WU1 * ux(i + 1, :) + WU2 * ux(i + 2, :)) / dx
            wy(i, :) = (WU0 * uy(i, :) + WU1 * uy(i + 1, :) + WU2 * uy(i + 2, :)) / dx
        end do
    end subroutine coupling_rolling_slip

    !> Tangential problem of one quasi-static load step (shift, no rolling), by
    !> point Gauss-Seidel with each element's problem solved exactly on its Coulomb
    !> disc (contact_rolling_element::element_solve). Slip (m) of element I in contact:
    !>   s_I = (A t)_I + (A_xz p)_I - uold_I + (wx, wy),
    !> A the Cerruti operator of the combined (g, nu), uold the previous step's
    !> tangential displacement difference (whole grid), (wx, wy) a rigid shift, m.
    !> Out: t (Pa), status (0 exterior, 1 adhesion, 2 slip), u = A t + A_xz p on
    !> the whole grid (the next step's uold), sweeps, the last sweep's largest
    !> traction change over mu max(p). info: STAT_OK, STAT_NOT_CONVERGED,
    !> STAT_NO_CONTACT, STAT_BAD_ARGUMENT (sizes, g <= 0), STAT_NOT_FINITE.
    subroutine coupling_shift_step(nx, ny, dx, dy, g, nu, kg, mu, p, uoldx, uoldy, wx, wy, tol, max_iter, &
                                   tx, ty, status, ux, uy, iters, change, info)
        integer, intent(in) :: nx, ny, max_iter
        real(dp), intent(in) :: dx, dy, g, nu, kg, mu, wx, wy, tol
        real(dp), intent(in) :: p(nx, ny), uoldx(nx, ny), uoldy(nx, ny)
        real(dp), intent(inout) :: tx(nx, ny), ty(nx, ny)   ! start in, tractions out
        integer, intent(out) :: status(nx, ny), iters
        real(dp), intent(out) :: ux(nx, ny), uy(nx, ny), change
        integer, intent(out) :: info
        real(dp), allocatable :: cxx(:, :), cyy(:, :), cxy(:, :), un(:, :), px(:, :), py(:, :), z(:, :)
        integer, allocatable :: ic(:), jc(:)
        real(dp) :: s0x, s0y, ntx, nty, lam, d, bnd
        integer :: n, nc, m, k, st

        iters = 0
        change = 0.0_dp
        status = ST_EXTERIOR
        ux = 0.0_dp
        uy = 0.0_dp
        info = STAT_OK
        if (nx < 1 .or. ny < 1 .or. g <= 0.0_dp .or. max_iter < 0) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        nc = count(p > 0.0_dp)
        where (p <= 0.0_dp)
            tx = 0.0_dp
            ty = 0.0_dp
        end where
        if (nc == 0) then
            info = STAT_NO_CONTACT
            return
        end if
        allocate (ic(nc), jc(nc))
        call contact_set(nx, ny, p, ic, jc)
        ! Cerruti coefficients by offset (circular layout of contact_influence)
        allocate (cxx(0:2 * nx - 1, 0:2 * ny - 1), cyy(0:2 * nx - 1, 0:2 * ny - 1), cxy(0:2 * nx - 1, 0:2 * ny - 1))
        call influence_field(KERNEL_XX, nx, ny, dx, dy, g, nu, cxx)
        call influence_field(KERNEL_YY, nx, ny, dx, dy, g, nu, cyy)
        call influence_field(KERNEL_XY, nx, ny, dx, dy, g, nu, cxy)
        ! the pressure's part, fixed in this step
        allocate (un(nx, ny), px(nx, ny), py(nx, ny), z(nx, ny))
        z = 0.0_dp
        call coupling_apply(nx, ny, dx, dy, kg, p, z, z, un, px, py)
        ! u = A t, kept up to date on the contact set through every change (the whole
        ! grid again after the sweeps: the next step's uold needs it everywhere)
        call tangential_field(nx, ny, cxx, cyy, cxy, nc, ic, jc, tx, ty, ux, uy)
        bnd = mu * maxval(p)
        do
            change = 0.0_dp
            do k = 1, nc
                n = ic(k)
                m = jc(k)
                s0x = ux(n, m) - cxx(0, 0) * tx(n, m) + px(n, m) - uoldx(n, m) + wx
                s0y = uy(n, m) - cyy(0, 0) * ty(n, m) + py(n, m) - uoldy(n, m) + wy
                call element_solve(s0x, s0y, cxx(0, 0), cyy(0, 0), mu * p(n, m), ntx, nty, st, lam)
                status(n, m) = st
                d = max(abs(ntx - tx(n, m)), abs(nty - ty(n, m)))
                change = max(change, d)
                if (d > 0.0_dp) then
                    call spread_on_set(nx, ny, cxx, cyy, cxy, nc, ic, jc, n, m, ntx - tx(n, m), nty - ty(n, m), ux, uy)
                    tx(n, m) = ntx
                    ty(n, m) = nty
                end if
            end do
            iters = iters + 1
            if (change /= change) then
                info = STAT_NOT_FINITE
                return
            end if
            if (bnd > 0.0_dp) change = change / bnd
            if (change <= tol) exit
            if (iters >= max_iter) then
                info = STAT_NOT_CONVERGED
                exit
            end if
        end do
        ! the state on the exact field of the final tractions
        call tangential_field(nx, ny, cxx, cyy, cxy, nc, ic, jc, tx, ty, ux, uy)
        ux = ux + px
        uy = uy + py
    end subroutine coupling_shift_step

    !> Elements with p > 0, column by column.
    subroutine contact_set(nx, ny, p, ic, jc)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: p(nx, ny)
        integer, intent(out) :: ic(:), jc(:)
        integer :: i, j, k
        k = 0
        do j = 1, ny
            do i = 1, nx
                if (p(i, j) > 0.0_dp) then
                    k = k + 1
                    ic(k) = i
                    jc(k) = j
                end if
            end do
        end do
    end subroutine contact_set

    !> Coefficient at offset (k, l) of a circular-layout field c (|k| < nx, |l| < ny).
    pure real(dp) function at_offset(c, nx, ny, k, l) result(a)
        integer, intent(in) :: nx, ny, k, l
        real(dp), intent(in) :: c(0:2 * nx - 1, 0:2 * ny - 1)
        a = c(modulo(k, 2 * nx), modulo(l, 2 * ny))
    end function at_offset

    !> u = A t over the whole grid from the tractions of the contact set (direct sums).
    subroutine tangential_field(nx, ny, cxx, cyy, cxy, nc, ic, jc, tx, ty, ux, uy)
        integer, intent(in) :: nx, ny, nc, ic(nc), jc(nc)
        real(dp), intent(in) :: cxx(0:2 * nx - 1, 0:2 * ny - 1), cyy(0:2 * nx - 1, 0:2 * ny - 1)
        real(dp), intent(in) :: cxy(0:2 * nx - 1, 0:2 * ny - 1), tx(nx, ny), ty(nx, ny)
        real(dp), intent(out) :: ux(nx, ny), uy(nx, ny)
        integer :: k
        ux = 0.0_dp
        uy = 0.0_dp
        do k = 1, nc
            call spread_change(nx, ny, cxx, cyy, cxy, ic(k), jc(k), tx(ic(k), jc(k)), ty(ic(k), jc(k)), ux, uy)
        end do
    end subroutine tangential_field

    !> Add the displacements of a traction (dtx, dty) on element (n, m) to u on the contact
    !> set only (what the sweeps read).
    subroutine spread_on_set(nx, ny, cxx, cyy, cxy, nc, ic, jc, n, m, dtx, dty, ux, uy)
        integer, intent(in) :: nx, ny, nc, ic(nc), jc(nc), n, m
        real(dp), intent(in) :: cxx(0:2 * nx - 1, 0:2 * ny - 1), cyy(0:2 * nx - 1, 0:2 * ny - 1)
        real(dp), intent(in) :: cxy(0:2 * nx - 1, 0:2 * ny - 1), dtx, dty
        real(dp), intent(inout) :: ux(nx, ny), uy(nx, ny)
        real(dp) :: axy
        integer :: k, i, j, ki, kj
        do k = 1, nc
            i = ic(k)
            j = jc(k)
            ki = modulo(i - n, 2 * nx)
            kj = modulo(j - m, 2 * ny)
            axy = cxy(ki, kj)
            ux(i, j) = ux(i, j) + cxx(ki, kj) * dtx + axy * dty
            uy(i, j) = uy(i, j) + axy * dtx + cyy(ki, kj) * dty
        end do
    end subroutine spread_on_set

    !> Add the displacements of a traction (dtx, dty) on element (n, m) to u (whole grid).
    subroutine spread_change(nx, ny, cxx, cyy, cxy, n, m, dtx, dty, ux, uy)
        integer, intent(in) :: nx, ny, n, m
        real(dp), intent(in) :: cxx(0:2 * nx - 1, 0:2 * ny - 1), cyy(0:2 * nx - 1, 0:2 * ny - 1)
        real(dp), intent(in) :: cxy(0:2 * nx - 1, 0:2 * ny - 1), dtx, dty
        real(dp), intent(inout) :: ux(nx, ny), uy(nx, ny)
        real(dp) :: axy
        integer :: i, j
        do j = 1, ny
            do i = 1, nx
                axy = at_offset(cxy, nx, ny, i - n, j - m)
                ux(i, j) = ux(i, j) + at_offset(cxx, nx, ny, i - n, j - m) * dtx + axy * dty
                uy(i, j) = uy(i, j) + axy * dtx + at_offset(cyy, nx, ny, i - n, j - m) * dty
            end do
        end do
    end subroutine spread_change

end module contact_coupling
