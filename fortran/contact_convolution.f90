!> Discrete convolution u(i, j) = sum_kl C(i - k, j - l) q(k, l) of influence
!> coefficients with surface tractions on an nx x ny grid.
!>
!> The FFT form zero-pads to 2nx x 2ny so that the circular convolution equals
!> the linear one (Kaiser, sect. 4; Vollebregt 2014). FFTW plans and the
!> coefficient spectra are made once per grid (conv_init) and reused by every
!> product (conv_apply). The direct form (direct_apply) sums in O(N^2) and is
!> kept for small grids and as a reference.
module contact_convolution
    ! fftw3.f03 needs the whole of iso_c_binding
    use, intrinsic :: iso_c_binding
    use kinds, only: dp
    implicit none
    private
    public :: conv_plan, conv_init, conv_free, conv_apply, conv_apply_pair, direct_apply

    include 'fftw3.f03'

    !> FFT state of one grid with nker coefficient spectra.
    type :: conv_plan
        integer :: nx = 0, ny = 0, mx = 0, my = 0, nker = 0
        type(c_ptr) :: fwd = c_null_ptr, bwd = c_null_ptr
        type(c_ptr) :: rmem = c_null_ptr, cmem = c_null_ptr, cmem2 = c_null_ptr
        real(c_double), pointer :: rbuf(:, :) => null()
        complex(c_double_complex), pointer :: cbuf(:, :) => null()
        complex(c_double_complex), pointer :: cbuf2(:, :) => null()
        complex(dp), allocatable :: spec(:, :, :)
    end type conv_plan

contains

    !> Plan the padded FFTs of an nx x ny grid and store the spectra of the
    !> coefficient fields c(:, :, k) (circular layout of influence_field).
    subroutine conv_init(plan, nx, ny, c, info)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: c(0:, 0:, :)
        integer, intent(out) :: info
        integer :: k, mxh

        info = 0
        call conv_free(plan)
        if (nx < 1 .or. ny < 1) then
            info = -2
            return
        end if
        plan%nx = nx
        plan%ny = ny
        plan%mx = 2 * nx
        plan%my = 2 * ny
        plan%nker = size(c, 3)
        mxh = plan%mx / 2 + 1

        plan%rmem = fftw_alloc_real(int(plan%mx, c_size_t) * plan%my)
        plan%cmem = fftw_alloc_complex(int(mxh, c_size_t) * plan%my)
        plan%cmem2 = fftw_alloc_complex(int(mxh, c_size_t) * plan%my)
        if (.not. (c_associated(plan%rmem) .and. c_associated(plan%cmem) &
                   .and. c_associated(plan%cmem2))) then
            info = -100
            return
        end if
        call c_f_pointer(plan%rmem, plan%rbuf, [plan%mx, plan%my])
        call c_f_pointer(plan%cmem, plan%cbuf, [mxh, plan%my])
        call c_f_pointer(plan%cmem2, plan%cbuf2, [mxh, plan%my])

        ! Fortran's column-major (mx, my) array is FFTW's row-major (my, mx).
        plan%fwd = fftw_plan_dft_r2c_2d(plan%my, plan%mx, plan%rbuf, plan%cbuf, FFTW_ESTIMATE)
        plan%bwd = fftw_plan_dft_c2r_2d(plan%my, plan%mx, plan%cbuf, plan%rbuf, FFTW_ESTIMATE)
        if (.not. (c_associated(plan%fwd) .and. c_associated(plan%bwd))) then
            info = -101
            return
        end if

        allocate (plan%spec(mxh, plan%my, plan%nker))
        do k = 1, plan%nker
            plan%rbuf = c(:, :, k)
            call fftw_execute_dft_r2c(plan%fwd, plan%rbuf, plan%cbuf)
            ! FFTW's inverse is unnormalised: fold 1/(mx my) into the spectrum.
            plan%spec(:, :, k) = plan%cbuf / real(plan%mx * plan%my, dp)
        end do
    end subroutine conv_init

    subroutine conv_free(plan)
        type(conv_plan), intent(inout) :: plan
        if (c_associated(plan%fwd)) call fftw_destroy_plan(plan%fwd)
        if (c_associated(plan%bwd)) call fftw_destroy_plan(plan%bwd)
        if (c_associated(plan%rmem)) call fftw_free(plan%rmem)
        if (c_associated(plan%cmem)) call fftw_free(plan%cmem)
        if (c_associated(plan%cmem2)) call fftw_free(plan%cmem2)
        plan%fwd = c_null_ptr
        plan%bwd = c_null_ptr
        plan%rmem = c_null_ptr
        plan%cmem = c_null_ptr
        plan%cmem2 = c_null_ptr
        nullify (plan%rbuf, plan%cbuf, plan%cbuf2)
        if (allocated(plan%spec)) deallocate (plan%spec)
        plan%nx = 0
        plan%ny = 0
        plan%nker = 0
    end subroutine conv_free

    !> u = C_k * q by zero-padded FFT (one forward and one inverse transform).
    subroutine conv_apply(plan, k, q, u)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: k
        real(dp), intent(in) :: q(:, :)
        real(dp), intent(out) :: u(:, :)
        integer :: nx, ny
        nx = plan%nx
        ny = plan%ny
        plan%rbuf = 0.0_dp
        plan%rbuf(1:nx, 1:ny) = q
        call fftw_execute_dft_r2c(plan%fwd, plan%rbuf, plan%cbuf)
        plan%cbuf = plan%cbuf * plan%spec(:, :, k)
        call fftw_execute_dft_c2r(plan%bwd, plan%cbuf, plan%rbuf)
        u = plan%rbuf(1:nx, 1:ny)
    end subroutine conv_apply

    !> The 2x2 block product of the tangential problem,
    !>   ux = C_kxx * qx + C_kxy * qy,   uy = C_kxy * qx + C_kyy * qy,
    !> with two forward and two inverse transforms.
    subroutine conv_apply_pair(plan, kxx, kxy, kyy, qx, qy, ux, uy)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kxx, kxy, kyy
        real(dp), intent(in) :: qx(:, :), qy(:, :)
        real(dp), intent(out) :: ux(:, :), uy(:, :)
        integer :: nx, ny, i, j
        complex(dp) :: sx, sy
        nx = plan%nx
        ny = plan%ny
        plan%rbuf = 0.0_dp
        plan%rbuf(1:nx, 1:ny) = qx
        call fftw_execute_dft_r2c(plan%fwd, plan%rbuf, plan%cbuf2)
        plan%rbuf = 0.0_dp
        plan%rbuf(1:nx, 1:ny) = qy
        call fftw_execute_dft_r2c(plan%fwd, plan%rbuf, plan%cbuf)
        ! cbuf2 = Qx, cbuf = Qy; form Uy first so Qy can be overwritten for Ux.
        do j = 1, plan%my
            do i = 1, plan%mx / 2 + 1
                sx = plan%cbuf2(i, j)
                sy = plan%cbuf(i, j)
                plan%cbuf2(i, j) = plan%spec(i, j, kxy) * sx + plan%spec(i, j, kyy) * sy
                plan%cbuf(i, j) = plan%spec(i, j, kxx) * sx + plan%spec(i, j, kxy) * sy
            end do
        end do
        call fftw_execute_dft_c2r(plan%bwd, plan%cbuf, plan%rbuf)
        ux = plan%rbuf(1:nx, 1:ny)
        call fftw_execute_dft_c2r(plan%bwd, plan%cbuf2, plan%rbuf)
        uy = plan%rbuf(1:nx, 1:ny)
    end subroutine conv_apply_pair

    !> u = C * q by direct summation over the non-zero entries of q, O(N Nq).
    pure subroutine direct_apply(nx, ny, c, q, u)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: c(0:2 * nx - 1, 0:2 * ny - 1)
        real(dp), intent(in) :: q(nx, ny)
        real(dp), intent(out) :: u(nx, ny)
        integer :: i, j, k, l, ii, jj
        u = 0.0_dp
        do l = 1, ny
            do k = 1, nx
                if (q(k, l) == 0.0_dp) cycle
                do j = 1, ny
                    jj = modulo(j - l, 2 * ny)
                    do i = 1, nx
                        ii = modulo(i - k, 2 * nx)
                        u(i, j) = u(i, j) + c(ii, jj) * q(k, l)
                    end do
                end do
            end do
        end do
    end subroutine direct_apply

end module contact_convolution
