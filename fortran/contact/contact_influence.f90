!> Influence coefficients of the elastic half-space for uniform tractions on a
!> rectangular element, for quasi-identical bodies (both bodies with shear
!> modulus G and Poisson's ratio nu, so normal and tangential problems decouple).
!>
!> The coefficient A_ab(X, Y) is the difference of the surface displacements of
!> the two bodies in direction a at offset (X, Y) from the centre of an element
!> of size dx x dy that carries a unit traction in direction b (Kalker 1990,
!> sect. 1.5; Kaiser, eqs 14-16):
!>
!>   A_zz = (1 - nu)/(pi G) * I[1/r]                           (Boussinesq)
!>   A_xx = 1/(pi G) * ((1 - nu) I[1/r] + nu I[X^2/r^3])       (Cerruti)
!>   A_yy = 1/(pi G) * ((1 - nu) I[1/r] + nu I[Y^2/r^3])
!>   A_xy = A_yx = nu/(pi G) * I[X Y/r^3]
!>
!> where I[f] integrates f over the element. Each integral is a corner function
!> Phi with d2 Phi / dX dY = f, evaluated at the four corners:
!>   1/r     -> X ln(Y + r) + Y ln(X + r)
!>   X^2/r^3 -> Y ln(X + r)
!>   Y^2/r^3 -> X ln(Y + r)
!>   XY/r^3  -> -r
!> Implements Kaiser eqs 14-16 and 19 (Boussinesq-Cerruti), with piecewise-constant
!> elements in place of eq. 18's bilinear ones (docs/equations.md).
module contact_influence
    use common_kinds, only: dp, pi
    implicit none
    private
    public :: KERNEL_ZZ, KERNEL_XX, KERNEL_YY, KERNEL_XY
    public :: influence_coefficient, influence_field

    integer, parameter :: KERNEL_ZZ = 1, KERNEL_XX = 2, KERNEL_YY = 3, KERNEL_XY = 4

contains

    !> b * ln(a + sqrt(a^2 + b^2)), continuous at b = 0 and free of the
    !> cancellation in a + r for a < 0 (there a + r = b^2 / (r - a)).
    pure real(dp) function blog(a, b)
        real(dp), intent(in) :: a, b
        real(dp) :: r
        if (b == 0.0_dp) then
            blog = 0.0_dp
            return
        end if
        r = hypot(a, b)
        if (a > 0.0_dp) then
            blog = b * log(a + r)
        else
            blog = b * log(b * b / (r - a))
        end if
    end function blog

    pure real(dp) function corner(kernel, x, y)
        integer, intent(in) :: kernel
        real(dp), intent(in) :: x, y
        select case (kernel)
        case (1)      ! 1/r
            corner = blog(y, x) + blog(x, y)
        case (2)      ! X^2/r^3
            corner = blog(x, y)
        case (3)      ! Y^2/r^3
            corner = blog(y, x)
        case default  ! XY/r^3
            corner = -hypot(x, y)
        end select
    end function corner

    !> Integral of the elementary kernel over [X - dx/2, X + dx/2] x [Y - dy/2, Y + dy/2].
    pure real(dp) function element_integral(kernel, x, y, dx, dy)
        integer, intent(in) :: kernel
        real(dp), intent(in) :: x, y, dx, dy
        real(dp) :: xp, xm, yp, ym
        xp = x + 0.5_dp * dx
        xm = x - 0.5_dp * dx
        yp = y + 0.5_dp * dy
        ym = y - 0.5_dp * dy
        element_integral = corner(kernel, xp, yp) - corner(kernel, xp, ym) &
                         - corner(kernel, xm, yp) + corner(kernel, xm, ym)
    end function element_integral

    !> Influence coefficient A_kernel at offset (x, y) from an element's centre, m/Pa.
    pure real(dp) function influence_coefficient(kernel, x, y, dx, dy, g, nu) result(a)
        integer, intent(in) :: kernel
        real(dp), intent(in) :: x, y, dx, dy, g, nu
        select case (kernel)
        case (KERNEL_ZZ)
            a = (1.0_dp - nu) / (pi * g) * element_integral(1, x, y, dx, dy)
        case (KERNEL_XX)
            a = ((1.0_dp - nu) * element_integral(1, x, y, dx, dy) &
                 + nu * element_integral(2, x, y, dx, dy)) / (pi * g)
        case (KERNEL_YY)
            a = ((1.0_dp - nu) * element_integral(1, x, y, dx, dy) &
                 + nu * element_integral(3, x, y, dx, dy)) / (pi * g)
        case default
            a = nu / (pi * g) * element_integral(4, x, y, dx, dy)
        end select
    end function influence_coefficient

    !> Coefficients for all offsets of an nx x ny grid, in circular layout on the
    !> zero-padded 2nx x 2ny grid: offset (k, l) at index (mod(k, 2nx), mod(l, 2ny)).
    !> Index nx (offset +-nx) is never reached by a product and is set to zero.
    !> The corner function is evaluated once per corner of the offset lattice,
    !> X_m = (m - 1/2) dx, m = 1-nx..nx, and differenced (4x fewer logarithms).
    pure subroutine influence_field(kernel, nx, ny, dx, dy, g, nu, c)
        integer, intent(in) :: kernel, nx, ny
        real(dp), intent(in) :: dx, dy, g, nu
        real(dp), intent(out) :: c(0:2 * nx - 1, 0:2 * ny - 1)
        real(dp), allocatable :: phi(:, :)
        real(dp) :: x, y, w1, w2, f
        integer :: i, j, k, l, e2
        ! kernel = w1 * I[1/r] + w2 * I[e2] with e2 the second elementary kernel
        select case (kernel)
        case (KERNEL_ZZ)
            w1 = (1.0_dp - nu) / (pi * g); w2 = 0.0_dp; e2 = 2
        case (KERNEL_XX)
            w1 = (1.0_dp - nu) / (pi * g); w2 = nu / (pi * g); e2 = 2
        case (KERNEL_YY)
            w1 = (1.0_dp - nu) / (pi * g); w2 = nu / (pi * g); e2 = 3
        case default
            w1 = 0.0_dp; w2 = nu / (pi * g); e2 = 4
        end select
        allocate (phi(1 - nx:nx, 1 - ny:ny))
        do j = 1 - ny, ny
            y = (j - 0.5_dp) * dy
            do i = 1 - nx, nx
                x = (i - 0.5_dp) * dx
                f = 0.0_dp
                if (w1 /= 0.0_dp) f = w1 * corner(1, x, y)
                if (w2 /= 0.0_dp) f = f + w2 * corner(e2, x, y)
                phi(i, j) = f
            end do
        end do
        c = 0.0_dp
        do j = 0, 2 * ny - 1
            if (j == ny) cycle
            l = j
            if (j > ny) l = j - 2 * ny
            do i = 0, 2 * nx - 1
                if (i == nx) cycle
                k = i
                if (i > nx) k = i - 2 * nx
                ! offset (k, l): corners at lattice points k, k+1 and l, l+1
                c(i, j) = phi(k + 1, l + 1) - phi(k + 1, l) - phi(k, l + 1) + phi(k, l)
            end do
        end do
    end subroutine influence_field

end module contact_influence
