!> Subsurface stresses of the elastic half-space z > 0 under piecewise-constant surface
!> tractions on a grid of rectangular elements: a pressure p (pressing into the body) and
!> shear tractions qx, qy (acting on the body's surface in +x, +y).
!>
!> The stress at (x, y, z) of a unit traction on the element [x1, x2] x [y1, y2] is a corner
!> sum Phi(X2, Y2) - Phi(X2, Y1) - Phi(X1, Y2) + Phi(X1, Y1) over the offsets X = x - xi,
!> Y = y - eta of the element's corners (X2 = x - x1 > X1 = x - x2). The corner functions
!> are Love's (1929) rectangle integrals of the Boussinesq potentials for the pressure
!> (Johnson 1985, sect. 3.2, with the kernels 1/rho and ln(rho + z)) and, for the shear
!> tractions, the same integrals of the Cerruti solution written with Love's potential
!> Omega = z ln(rho + z) - rho (Johnson 1985, sect. 3.2), reduced by the harmonicity of
!> Omega to closed forms (derivation and checks in docs/contact_subsurface.md). Terms that
!> depend on X only or on Y only cancel in the corner sum and are left out.
!> Sign convention: tensile stresses positive (a compressive sigma_zz is negative).
!> Component order (Voigt): xx, yy, zz, yz, xz, xy.
!> Implements docs/contact_subsurface.md eqs S1-S3 (Love 1929; Johnson 1985, sect. 3.2).
module contact_subsurface
    use common_kinds, only: dp, pi
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    implicit none
    private
    public :: corner_pressure, corner_shear_x, element_stress, subsurface_points
    public :: stress_invariants

contains

    !> ln(a + sqrt(a^2 + b2)) for b2 = b^2 + z^2 > 0, free of the cancellation at a < 0.
    pure real(dp) function lnplus(a, b2)
        real(dp), intent(in) :: a, b2
        real(dp) :: r
        r = sqrt(a * a + b2)
        if (a >= 0.0_dp) then
            lnplus = log(a + r)
        else
            lnplus = log(b2 / (r - a))
        end if
    end function lnplus

    !> Corner function of a unit pressure (eq. S1), times 2 pi.
    pure subroutine corner_pressure(x, y, z, nu, c)
        real(dp), intent(in) :: x, y, z, nu
        real(dp), intent(out) :: c(6)
        real(dp) :: r, fz, fxx, fyy, gxx, gyy, xz2, yz2
        xz2 = x * x + z * z
        yz2 = y * y + z * z
        r = sqrt(x * x + yz2)
        fz = -atan2(x * y, z * r)               ! d/dz of the integral of 1/rho
        fxx = -x * y / (r * xz2)                ! d2/dx2 of it (less a function of x)
        fyy = -x * y / (r * yz2)
        if (x == 0.0_dp .or. y == 0.0_dp) then
            gxx = 0.0_dp
            gyy = 0.0_dp
        else                                    ! d2/dx2 of the integral of ln(rho + z)
            gxx = atan2(x * y * (x * x + y * y), (r + z) * (x * x * r + z * y * y))
            gyy = atan2(x * y * (x * x + y * y), (r + z) * (y * y * r + z * x * x))
        end if
        c(1) = 2.0_dp * nu * fz - z * fxx - (1.0_dp - 2.0_dp * nu) * gxx
        c(2) = 2.0_dp * nu * fz - z * fyy - (1.0_dp - 2.0_dp * nu) * gyy
        c(3) = fz + z * (fxx + fyy)
        c(4) = z * z * x / (r * yz2)
        c(5) = z * z * y / (r * xz2)
        c(6) = -((1.0_dp - 2.0_dp * nu) * log(r + z) + z / r)
    end subroutine corner_pressure

    !> Corner function of a unit shear traction in +x (eq. S2), times 2 pi.
    pure subroutine corner_shear_x(x, y, z, nu, c)
        real(dp), intent(in) :: x, y, z, nu
        real(dp), intent(out) :: c(6)
        real(dp) :: r, fz, xz2, e010, e011, sy0, sy1
        xz2 = x * x + z * z
        r = sqrt(xz2 + y * y)
        fz = -atan2(x * y, z * r)
        e010 = -y / (r + z)                     ! d Omega / dy
        e011 = y / (r * (r + z))                ! d2 Omega / dy dz
        sy0 = lnplus(y, xz2)                    ! integral over y of 1/rho
        sy1 = -z * y / (r * xz2)                ! its z derivative (less a function of x)
        c(1) = -2.0_dp * nu * e010 + z * e011 + 2.0_dp * sy0 + z * sy1
        c(2) = 2.0_dp * nu * e010 - z * e011 + 2.0_dp * nu * sy0
        c(3) = -z * sy1
        c(4) = -z / r
        c(5) = fz + z * x * y / (r * xz2)
        c(6) = -(2.0_dp * nu + z / r) * x / (r + z) + lnplus(x, y * y + z * z)
    end subroutine corner_shear_x

    !> Stresses at offset (x, y) from an element's centre and depth z > 0 under a unit
    !> pressure (sp), unit qx (sx) and unit qy (sy) on the dx x dy element, per Pa.
    pure subroutine element_stress(x, y, z, dx, dy, nu, sp, sx, sy)
        real(dp), intent(in) :: x, y, z, dx, dy, nu
        real(dp), intent(out) :: sp(6), sx(6), sy(6)
        real(dp) :: xc(2), yc(2), cp(6), cx(6), cy(6), s
        integer :: i, j
        xc = [x - 0.5_dp * dx, x + 0.5_dp * dx]
        yc = [y - 0.5_dp * dy, y + 0.5_dp * dy]
        sp = 0.0_dp
        sx = 0.0_dp
        sy = 0.0_dp
        do j = 1, 2
            do i = 1, 2
                s = merge(1.0_dp, -1.0_dp, i == j)
                call corner_pressure(xc(i), yc(j), z, nu, cp)
                call corner_shear_x(xc(i), yc(j), z, nu, cx)
                call corner_shear_x(yc(j), xc(i), z, nu, cy)   ! qy: x and y exchanged
                sp = sp + s * cp
                sx = sx + s * cx
                sy = sy + s * [cy(2), cy(1), cy(3), cy(5), cy(4), cy(6)]
            end do
        end do
        sp = sp / (2.0_dp * pi)
        sx = sx / (2.0_dp * pi)
        sy = sy / (2.0_dp * pi)
    end subroutine element_stress

    !> Stresses sig(k, :) at the points (xp, yp, zp)(k) by direct summation over the loaded
    !> elements of the nx x ny grid (element (i, j) centred at x0 + (i-1) dx, y0 + (j-1) dy).
    !> Cost O(points x loaded elements). info: STAT_OK; STAT_BAD_ARGUMENT a depth zp <= 0,
    !> dx or dy <= 0 or nu outside (-1, 0.5) (ibad: the first bad point, 0 otherwise).
    subroutine subsurface_points(nx, ny, dx, dy, x0, y0, p, qx, qy, nu, npt, xp, yp, zp, &
                                 sig, info, ibad)
        integer, intent(in) :: nx, ny, npt
        real(dp), intent(in) :: dx, dy, x0, y0, nu
        real(dp), intent(in) :: p(nx, ny), qx(nx, ny), qy(nx, ny)
        real(dp), intent(in) :: xp(npt), yp(npt), zp(npt)
        real(dp), intent(out) :: sig(npt, 6)
        integer, intent(out) :: info, ibad
        integer, allocatable :: ie(:), je(:)
        integer :: i, j, k, m, nl
        real(dp) :: sp(6), sx(6), sy(6), acc(6)
        sig = 0.0_dp
        ibad = 0
        info = STAT_BAD_ARGUMENT
        if (.not. (dx > 0.0_dp .and. dy > 0.0_dp .and. nu > -1.0_dp .and. nu < 0.5_dp)) return
        do k = 1, npt
            if (.not. (zp(k) > 0.0_dp)) then
                ibad = k
                return
            end if
        end do
        info = STAT_OK
        ! the loaded elements, in a fixed order (results independent of the thread count)
        nl = count(p /= 0.0_dp .or. qx /= 0.0_dp .or. qy /= 0.0_dp)
        allocate (ie(nl), je(nl))
        m = 0
        do j = 1, ny
            do i = 1, nx
                if (p(i, j) /= 0.0_dp .or. qx(i, j) /= 0.0_dp .or. qy(i, j) /= 0.0_dp) then
                    m = m + 1
                    ie(m) = i
                    je(m) = j
                end if
            end do
        end do
        !$omp parallel do schedule(dynamic, 16) private(k, m, i, j, sp, sx, sy, acc)
        do k = 1, npt
            acc = 0.0_dp
            do m = 1, nl
                i = ie(m)
                j = je(m)
                call element_stress(xp(k) - (x0 + (i - 1) * dx), yp(k) - (y0 + (j - 1) * dy), &
                                    zp(k), dx, dy, nu, sp, sx, sy)
                acc = acc + p(i, j) * sp + qx(i, j) * sx + qy(i, j) * sy
            end do
            sig(k, :) = acc
        end do
        !$omp end parallel do
    end subroutine subsurface_points

    !> Principal stresses (descending), von Mises and Tresca (s1 - s3) equivalent stresses
    !> of n stress states sig(k, :) (Voigt order), by the invariants of the deviator and
    !> the trigonometric solution of its characteristic cubic (Smith 1961).
    pure subroutine stress_invariants(n, sig, prin, vm, tresca)
        integer, intent(in) :: n
        real(dp), intent(in) :: sig(n, 6)
        real(dp), intent(out) :: prin(n, 3), vm(n), tresca(n)
        real(dp) :: m, d(3), j2, j3, r, th, s
        integer :: k
        do k = 1, n
            m = (sig(k, 1) + sig(k, 2) + sig(k, 3)) / 3.0_dp
            d = sig(k, 1:3) - m
            j2 = 0.5_dp * sum(d * d) + sig(k, 4)**2 + sig(k, 5)**2 + sig(k, 6)**2
            j3 = d(1) * d(2) * d(3) + 2.0_dp * sig(k, 4) * sig(k, 5) * sig(k, 6) &
                 - d(1) * sig(k, 4)**2 - d(2) * sig(k, 5)**2 - d(3) * sig(k, 6)**2
            vm(k) = sqrt(3.0_dp * j2)
            if (j2 <= 0.0_dp) then
                prin(k, :) = m
                tresca(k) = 0.0_dp
                cycle
            end if
            r = 2.0_dp * sqrt(j2 / 3.0_dp)
            s = max(-1.0_dp, min(1.0_dp, 0.5_dp * j3 * (3.0_dp / j2)**1.5_dp))
            th = acos(s) / 3.0_dp
            prin(k, 1) = m + r * cos(th)
            prin(k, 3) = m + r * cos(th + 2.0_dp * pi / 3.0_dp)
            prin(k, 2) = 3.0_dp * m - prin(k, 1) - prin(k, 3)
            tresca(k) = prin(k, 1) - prin(k, 3)
        end do
    end subroutine stress_invariants

end module contact_subsurface
