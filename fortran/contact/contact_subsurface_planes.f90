!> Subsurface stresses on whole planes z = const at the element centres of the grid, by
!> FFT convolution per depth: the corner functions of contact_subsurface evaluated once per
!> lattice corner ((2nx) x (2ny) per depth and load), differenced into the coefficients of
!> every offset, and convolved with the zero-padded tractions (as contact_convolution does
!> for the surface displacements). Cost per depth: 18 forward and 6 inverse FFTs of the
!> 2nx x 2ny grid, against nx ny x (loaded elements) element sums of the direct form.
!> Implements docs/contact_subsurface.md eqs S1-S3 and S4 (the convolution).
module contact_subsurface_planes
    ! fftw3.f03 needs the whole of iso_c_binding
    use, intrinsic :: iso_c_binding
    use common_kinds, only: dp, pi
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_NO_MEMORY, STAT_FFTW_PLAN
    use contact_subsurface, only: corner_pressure, corner_shear_x
    implicit none
    private
    public :: subsurface_planes

    include 'fftw3.f03'

contains

    !> Corner functions of load ld (1 pressure, 2 qx, 3 qy) at the lattice corners
    !> ((m - 1/2) dx, (n - 1/2) dy), m = 1-nx..nx, n = 1-ny..ny, depth z.
    subroutine corner_lattice(ld, nx, ny, dx, dy, z, nu, phi)
        integer, intent(in) :: ld, nx, ny
        real(dp), intent(in) :: dx, dy, z, nu
        real(dp), intent(out) :: phi(1 - nx:nx, 1 - ny:ny, 6)
        real(dp) :: x, y, c(6)
        integer :: m, n
        ! Serial: OpenMP threads here gave no gain on the shared 2-core machine (100 x 100
        ! elements x 30 depths: 0.34-0.55 s on two threads, 0.24 s on one, at load 2.2; a
        ! 41 x 41 grid ran 6x slower on two at load 11), and the FFTs are serial anyway
        do n = 1 - ny, ny
            y = (n - 0.5_dp) * dy
            do m = 1 - nx, nx
                x = (m - 0.5_dp) * dx
                select case (ld)
                case (1)
                    call corner_pressure(x, y, z, nu, c)
                case (2)
                    call corner_shear_x(x, y, z, nu, c)
                case default
                    call corner_shear_x(y, x, z, nu, c)
                    c = [c(2), c(1), c(3), c(5), c(4), c(6)]
                end select
                phi(m, n, :) = c
            end do
        end do
    end subroutine corner_lattice

    !> Coefficients of offset (k, l) in the circular layout of the padded grid.
    pure subroutine lattice_to_coefficients(nx, ny, phi, c)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: phi(1 - nx:nx, 1 - ny:ny)
        real(dp), intent(out) :: c(0:2 * nx - 1, 0:2 * ny - 1)
        integer :: i, j, k, l
        c = 0.0_dp
        do j = 0, 2 * ny - 1
            if (j == ny) cycle
            l = j
            if (j > ny) l = j - 2 * ny
            do i = 0, 2 * nx - 1
                if (i == nx) cycle
                k = i
                if (i > nx) k = i - 2 * nx
                c(i, j) = phi(k + 1, l + 1) - phi(k + 1, l) - phi(k, l + 1) + phi(k, l)
            end do
        end do
    end subroutine lattice_to_coefficients

    !> Stresses sig(i, j, iz, :) at the element centres (i, j) and depths z(iz) > 0 under
    !> the tractions p, qx, qy (Pa) of the nx x ny grid. info: STAT_OK; STAT_BAD_ARGUMENT
    !> a depth <= 0 (ibad: its index), dx, dy <= 0 or nu outside (-1, 0.5);
    !> STAT_NO_MEMORY; STAT_FFTW_PLAN.
    subroutine subsurface_planes(nx, ny, dx, dy, p, qx, qy, nu, nz, z, sig, info, ibad)
        integer, intent(in) :: nx, ny, nz
        real(dp), intent(in) :: dx, dy, nu, p(nx, ny), qx(nx, ny), qy(nx, ny), z(nz)
        real(dp), intent(out) :: sig(nx, ny, nz, 6)
        integer, intent(out) :: info, ibad
        type(c_ptr) :: rmem, cmem, fwd, bwd
        real(c_double), pointer :: rbuf(:, :)
        complex(c_double_complex), pointer :: cbuf(:, :)
        complex(dp), allocatable :: lspec(:, :, :), acc(:, :, :)
        real(dp), allocatable :: phi(:, :, :)
        integer :: mx, my, mxh, iz, ld, ic
        sig = 0.0_dp
        ibad = 0
        info = STAT_BAD_ARGUMENT
        if (.not. (dx > 0.0_dp .and. dy > 0.0_dp .and. nu > -1.0_dp .and. nu < 0.5_dp)) return
        do iz = 1, nz
            if (.not. (z(iz) > 0.0_dp)) then
                ibad = iz
                return
            end if
        end do
        mx = 2 * nx
        my = 2 * ny
        mxh = nx + 1
        fwd = c_null_ptr
        bwd = c_null_ptr
        rmem = fftw_alloc_real(int(mx, c_size_t) * my)
        cmem = fftw_alloc_complex(int(mxh, c_size_t) * my)
        info = STAT_NO_MEMORY
        if (c_associated(rmem) .and. c_associated(cmem)) then
            call c_f_pointer(rmem, rbuf, [mx, my])
            call c_f_pointer(cmem, cbuf, [mxh, my])
            ! Fortran's column-major (mx, my) array is FFTW's row-major (my, mx).
            fwd = fftw_plan_dft_r2c_2d(my, mx, rbuf, cbuf, FFTW_ESTIMATE)
            bwd = fftw_plan_dft_c2r_2d(my, mx, cbuf, rbuf, FFTW_ESTIMATE)
            info = STAT_FFTW_PLAN
            if (c_associated(fwd) .and. c_associated(bwd)) info = STAT_OK
        end if
        if (info == STAT_OK) then
            allocate (lspec(mxh, my, 3), acc(mxh, my, 6), phi(1 - nx:nx, 1 - ny:ny, 6))
            call load_spectrum(p, 1)
            call load_spectrum(qx, 2)
            call load_spectrum(qy, 3)
            do iz = 1, nz
                acc = (0.0_dp, 0.0_dp)
                do ld = 1, 3
                    if (all(lspec(:, :, ld) == (0.0_dp, 0.0_dp))) cycle
                    call corner_lattice(ld, nx, ny, dx, dy, z(iz), nu, phi)
                    do ic = 1, 6
                        call lattice_to_coefficients(nx, ny, phi(:, :, ic), rbuf)
                        call fftw_execute_dft_r2c(fwd, rbuf, cbuf)
                        acc(:, :, ic) = acc(:, :, ic) + cbuf * lspec(:, :, ld)
                    end do
                end do
                do ic = 1, 6
                    cbuf = acc(:, :, ic)
                    call fftw_execute_dft_c2r(bwd, cbuf, rbuf)
                    sig(:, :, iz, ic) = rbuf(1:nx, 1:ny) / (2.0_dp * pi * real(mx, dp) * real(my, dp))
                end do
            end do
        end if
        if (c_associated(fwd)) call fftw_destroy_plan(fwd)
        if (c_associated(bwd)) call fftw_destroy_plan(bwd)
        if (c_associated(rmem)) call fftw_free(rmem)
        if (c_associated(cmem)) call fftw_free(cmem)

    contains

        subroutine load_spectrum(q, k)
            real(dp), intent(in) :: q(nx, ny)
            integer, intent(in) :: k
            rbuf = 0.0_dp
            rbuf(1:nx, 1:ny) = q
            call fftw_execute_dft_r2c(fwd, rbuf, cbuf)
            lspec(:, :, k) = cbuf
        end subroutine load_spectrum

    end subroutine subsurface_planes

end module contact_subsurface_planes
