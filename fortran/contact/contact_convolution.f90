!> Discrete convolution u(i, j) = sum_kl C(i - k, j - l) q(k, l) of influence
!> coefficients with surface tractions on an nx x ny grid.
!>
!> The FFT form zero-pads to 2nx x 2ny so that the circular convolution equals
!> the linear one (Kaiser, sect. 4; Vollebregt 2014). FFTW plans and the
!> coefficient spectra are made once per grid (conv_init) and reused by every
!> product. conv_apply, conv_apply_buffer and conv_apply_pair prune the transforms to
!> the padding (issue 33): the x transforms run over the ny loaded columns only (r2c
!> forward, c2r inverse), the y transforms over all 2ny rows of the nx + 1 x
!> frequencies, in blocks of PBLOCK frequencies gathered into a small buffer in which
!> the forward transform, the spectral product and the inverse transform follow each
!> other in cache. The spectra are kept transposed: real for a point-symmetric field
!> (all four influence fields), complex otherwise. conv_apply_plain is the unpruned
!> 2-D product (one r2c of the padded grid, the product by the complex spectrum, one
!> c2r), the unit of the normal solver's benchmark; they agree to rounding. The direct
!> form (direct_apply) sums in O(N^2) and is
!> kept for small grids and as a reference. On small grids (N = nx ny <= DENSE_MAX)
!> conv_apply_dense multiplies by the dense N x N matrix of a kernel, made on first
!> use and kept in the plan: O(nq N) for nq non-zero sources, contiguous columns.
!> Implements Kaiser eq. 20, u_I = sum_J A_IJ q_J (role inferred: docs/equations.md).
module contact_convolution
    ! fftw3.f03 needs the whole of iso_c_binding
    use, intrinsic :: iso_c_binding
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_NO_MEMORY, STAT_FFTW_PLAN
    implicit none
    private
    public :: conv_plan, conv_init, conv_free, conv_apply, conv_apply_pair, direct_apply
    public :: conv_init_precond, conv_apply_buffer, conv_precond_buffer
    public :: conv_apply_dense, DENSE_MAX, conv_apply_plain

    include 'fftw3.f03'

    !> FFT state of one grid with nker coefficient spectra.
    type :: conv_plan
        integer :: nx = 0, ny = 0, mx = 0, my = 0, nker = 0
        type(c_ptr) :: fwd = c_null_ptr, bwd = c_null_ptr
        type(c_ptr) :: rmem = c_null_ptr, cmem = c_null_ptr, cmem2 = c_null_ptr
        real(c_double), pointer :: rbuf(:, :) => null()
        complex(c_double_complex), pointer :: cbuf(:, :) => null()
        complex(c_double_complex), pointer :: cbuf2(:, :) => null()
        ! kernel 1's spectrum (mx/2 + 1, my), for the plain product (conv_apply_plain)
        complex(dp), allocatable :: spec(:, :, :)
        ! Pruned product (conv_apply_buffer): x transforms of the ny loaded columns,
        ! y transforms of blocks of PBLOCK (and of the last nrem) x frequencies in wbuf
        ! (leading dimension my + WPAD).
        type(c_ptr) :: xf = c_null_ptr, xb = c_null_ptr
        type(c_ptr) :: yf = c_null_ptr, yb = c_null_ptr, yfr = c_null_ptr, ybr = c_null_ptr
        type(c_ptr) :: wmem = c_null_ptr, wmem2 = c_null_ptr
        complex(c_double_complex), pointer :: wbuf(:, :) => null(), wbuf2(:, :) => null()
        ! Every kernel's spectrum transposed, (my, mx/2 + 1): kernel k's is rspec(:, :, sidx(k))
        ! when real_spec(k) (a real spectrum: a point-symmetric field), else cspec(:, :, sidx(k)).
        logical, allocatable :: real_spec(:)
        integer, allocatable :: sidx(:)
        real(dp), allocatable :: rspec(:, :, :)
        complex(dp), allocatable :: cspec(:, :, :)
        ! Preconditioner M ~ A^-1 on the unpadded (periodic) nx x ny grid.
        logical :: has_prec = .false.
        type(c_ptr) :: pfwd = c_null_ptr, pbwd = c_null_ptr
        type(c_ptr) :: prmem = c_null_ptr, pcmem = c_null_ptr
        real(c_double), pointer :: prbuf(:, :) => null()
        complex(c_double_complex), pointer :: pcbuf(:, :) => null()
        real(dp), allocatable :: psym(:, :)
        ! Dense matrix of kernel dense_k (conv_apply_dense), (N, N), N = nx ny.
        integer :: dense_k = 0
        real(dp), allocatable :: dense(:, :)
    end type conv_plan

    !> Largest grid (elements) whose dense matrix conv_apply_dense makes (8 MB).
    integer, parameter :: DENSE_MAX = 1024
    !> x frequencies per block of the pruned product's y transforms: 16 rows of 2ny
    !> complex numbers (230 kB at 450 x 450) stay in cache from the forward transform
    !> to the inverse; measured 0.57-0.62 of a plain product at 450 and 500 with 12-24
    !> rows, more with 8.
    integer, parameter :: PBLOCK = 16
    !> Padding of wbuf's columns (complex numbers): with 2ny a power of two, unpadded columns
    !> fall into the same cache sets (measured 0.72 of a plain product at 256 x 256).
    integer, parameter :: WPAD = 4
    !> A coefficient field whose point reflection c(-i, -j) differs from it by at most this
    !> share of its largest modulus has its spectrum taken as real (the spectrum of its
    !> point-symmetric part). The influence fields are point-symmetric in exact arithmetic
    !> (A_zz, A_xx, A_yy even in x and y, A_xy odd in both); their computed values differ
    !> from their reflections by the rounding of the corner-function differences, up to
    !> 8e-13 of the largest at 450 x 450, 2e-13 at 128 x 128.
    real(dp), parameter :: SYM_SHARE = 1.0e-10_dp

contains

    !> Plan the padded FFTs of an nx x ny grid and store the spectra of the
    !> coefficient fields c(:, :, k) (circular layout of influence_field).
    !> info: STAT_OK; STAT_BAD_ARGUMENT nx or ny < 1; STAT_NO_MEMORY FFTW could
    !> not allocate its buffers; STAT_FFTW_PLAN no plan.
    subroutine conv_init(plan, nx, ny, c, info)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: c(0:, 0:, :)
        integer, intent(out) :: info
        integer :: mxh

        info = STAT_OK
        call conv_free(plan)
        if (nx < 1 .or. ny < 1) then
            info = STAT_BAD_ARGUMENT
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
            info = STAT_NO_MEMORY
            return
        end if
        call c_f_pointer(plan%rmem, plan%rbuf, [plan%mx, plan%my])
        call c_f_pointer(plan%cmem, plan%cbuf, [mxh, plan%my])
        call c_f_pointer(plan%cmem2, plan%cbuf2, [mxh, plan%my])

        ! Fortran's column-major (mx, my) array is FFTW's row-major (my, mx).
        plan%fwd = fftw_plan_dft_r2c_2d(plan%my, plan%mx, plan%rbuf, plan%cbuf, FFTW_ESTIMATE)
        plan%bwd = fftw_plan_dft_c2r_2d(plan%my, plan%mx, plan%cbuf, plan%rbuf, FFTW_ESTIMATE)
        if (.not. (c_associated(plan%fwd) .and. c_associated(plan%bwd))) then
            info = STAT_FFTW_PLAN
            return
        end if

        call conv_init_pruned(plan, info)
        if (info == STAT_OK) call conv_spectra(plan, c)
    end subroutine conv_init

    !> The spectra of the coefficient fields c(:, :, k), by the plain forward transform, with
    !> FFTW's unnormalised inverse's 1/(mx my) folded in: kernel 1's as spec, every kernel's
    !> transposed as rspec (real, for a point-symmetric field: the spectrum of its
    !> point-symmetric part) or cspec.
    subroutine conv_spectra(plan, c)
        type(conv_plan), intent(inout) :: plan
        real(dp), intent(in) :: c(0:, 0:, :)
        integer :: k, mxh, nr, nc
        real(dp) :: s
        mxh = plan%mx / 2 + 1
        s = real(plan%mx * plan%my, dp)
        allocate (plan%real_spec(plan%nker), plan%sidx(plan%nker))
        nr = 0
        nc = 0
        do k = 1, plan%nker
            plan%real_spec(k) = point_symmetric(c(:, :, k))
            if (plan%real_spec(k)) then
                nr = nr + 1
                plan%sidx(k) = nr
            else
                nc = nc + 1
                plan%sidx(k) = nc
            end if
        end do
        allocate (plan%spec(mxh, plan%my, 1), plan%rspec(plan%my, mxh, nr), plan%cspec(plan%my, mxh, nc))
        do k = 1, plan%nker
            plan%rbuf = c(:, :, k)
            call fftw_execute_dft_r2c(plan%fwd, plan%rbuf, plan%cbuf)
            plan%cbuf = plan%cbuf / s
            if (k == 1) plan%spec(:, :, 1) = plan%cbuf
            if (plan%real_spec(k)) then
                plan%rspec(:, :, plan%sidx(k)) = transpose(real(plan%cbuf, dp))
            else
                plan%cspec(:, :, plan%sidx(k)) = transpose(plan%cbuf)
            end if
        end do
    end subroutine conv_spectra

    !> Whether c is point-symmetric, c(-i, -j) = c(i, j) (indices modulo the padded grid),
    !> to SYM_SHARE of its largest modulus: then its spectrum is real.
    pure logical function point_symmetric(c) result(sym)
        real(dp), intent(in) :: c(0:, 0:)
        integer :: i, j, mx, my
        real(dp) :: d, tol
        mx = size(c, 1)
        my = size(c, 2)
        tol = SYM_SHARE * maxval(abs(c))
        d = 0.0_dp
        do j = 0, my - 1
            do i = 0, mx - 1
                d = max(d, abs(c(i, j) - c(modulo(-i, mx), modulo(-j, my))))
            end do
        end do
        sym = d <= tol
    end function point_symmetric

    !> The pruned product's plans (conv_apply_buffer), after conv_init's buffers. info: STAT_OK; STAT_NO_MEMORY, STAT_FFTW_PLAN as conv_init.
    subroutine conv_init_pruned(plan, info)
        type(conv_plan), intent(inout) :: plan
        integer, intent(out) :: info
        integer(c_int) :: mx, my, mxh, ny, nrem, ldw
        info = STAT_OK
        mx = plan%mx
        my = plan%my
        ny = plan%ny
        mxh = mx / 2 + 1
        nrem = mod(mxh, PBLOCK)
        ldw = my + WPAD
        plan%wmem = fftw_alloc_complex(int(ldw, c_size_t) * PBLOCK)
        plan%wmem2 = fftw_alloc_complex(int(ldw, c_size_t) * PBLOCK)
        if (.not. (c_associated(plan%wmem) .and. c_associated(plan%wmem2))) then
            info = STAT_NO_MEMORY
            return
        end if
        call c_f_pointer(plan%wmem, plan%wbuf, [ldw, PBLOCK])
        call c_f_pointer(plan%wmem2, plan%wbuf2, [ldw, PBLOCK])
        plan%xf = fftw_plan_many_dft_r2c(1, [mx], ny, plan%rbuf, [mx], 1, mx, &
                                         plan%cbuf, [mxh], 1, mxh, FFTW_ESTIMATE)
        plan%xb = fftw_plan_many_dft_c2r(1, [mx], ny, plan%cbuf, [mxh], 1, mxh, &
                                         plan%rbuf, [mx], 1, mx, FFTW_ESTIMATE)
        plan%yf = fftw_plan_many_dft(1, [my], PBLOCK, plan%wbuf, [ldw], 1, ldw, &
                                     plan%wbuf, [ldw], 1, ldw, FFTW_FORWARD, FFTW_ESTIMATE)
        plan%yb = fftw_plan_many_dft(1, [my], PBLOCK, plan%wbuf, [ldw], 1, ldw, &
                                     plan%wbuf, [ldw], 1, ldw, FFTW_BACKWARD, FFTW_ESTIMATE)
        if (nrem > 0) then
            plan%yfr = fftw_plan_many_dft(1, [my], nrem, plan%wbuf, [ldw], 1, ldw, &
                                          plan%wbuf, [ldw], 1, ldw, FFTW_FORWARD, FFTW_ESTIMATE)
            plan%ybr = fftw_plan_many_dft(1, [my], nrem, plan%wbuf, [ldw], 1, ldw, &
                                          plan%wbuf, [ldw], 1, ldw, FFTW_BACKWARD, FFTW_ESTIMATE)
        end if
        if (.not. (c_associated(plan%xf) .and. c_associated(plan%xb) .and. c_associated(plan%yf) &
                   .and. c_associated(plan%yb) .and. (nrem == 0 .or. (c_associated(plan%yfr) &
                                                                        .and. c_associated(plan%ybr))))) then
            info = STAT_FFTW_PLAN
            return
        end if
    end subroutine conv_init_pruned

    subroutine conv_free(plan)
        type(conv_plan), intent(inout) :: plan
        call destroy_plan(plan%fwd)
        call destroy_plan(plan%bwd)
        call free_mem(plan%rmem)
        call free_mem(plan%cmem)
        call free_mem(plan%cmem2)
        nullify (plan%rbuf, plan%cbuf, plan%cbuf2)
        if (allocated(plan%spec)) deallocate (plan%spec)
        call destroy_plan(plan%xf)
        call destroy_plan(plan%xb)
        call destroy_plan(plan%yf)
        call destroy_plan(plan%yb)
        call destroy_plan(plan%yfr)
        call destroy_plan(plan%ybr)
        call free_mem(plan%wmem)
        call free_mem(plan%wmem2)
        nullify (plan%wbuf, plan%wbuf2)
        if (allocated(plan%real_spec)) deallocate (plan%real_spec)
        if (allocated(plan%sidx)) deallocate (plan%sidx)
        if (allocated(plan%rspec)) deallocate (plan%rspec)
        if (allocated(plan%cspec)) deallocate (plan%cspec)
        call destroy_plan(plan%pfwd)
        call destroy_plan(plan%pbwd)
        call free_mem(plan%prmem)
        call free_mem(plan%pcmem)
        nullify (plan%prbuf, plan%pcbuf)
        if (allocated(plan%psym)) deallocate (plan%psym)
        if (allocated(plan%dense)) deallocate (plan%dense)
        plan%dense_k = 0
        plan%has_prec = .false.
        plan%nx = 0
        plan%ny = 0
        plan%nker = 0
    end subroutine conv_free

    subroutine destroy_plan(p)
        type(c_ptr), intent(inout) :: p
        if (c_associated(p)) call fftw_destroy_plan(p)
        p = c_null_ptr
    end subroutine destroy_plan

    subroutine free_mem(p)
        type(c_ptr), intent(inout) :: p
        if (c_associated(p)) call fftw_free(p)
        p = c_null_ptr
    end subroutine free_mem

    !> u = C_k * q by zero-padded FFT, pruned to the padding (conv_apply_buffer).
    subroutine conv_apply(plan, k, q, u)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: k
        real(dp), intent(in) :: q(:, :)
        real(dp), intent(out) :: u(:, :)
        plan%rbuf(1:plan%nx, 1:plan%ny) = q
        call conv_apply_buffer(plan, k)
        u = plan%rbuf(1:plan%nx, 1:plan%ny)
    end subroutine conv_apply

    !> u = C_1 * q (kernel 1) by the plain zero-padded FFT product: one r2c transform of
    !> the 2nx x 2ny grid, the product by the complex spectrum, one c2r transform (the unit
    !> of bench_contact_normal's "FFT-product time", and the reference of the pruned one).
    subroutine conv_apply_plain(plan, q, u)
        type(conv_plan), intent(inout) :: plan
        real(dp), intent(in) :: q(:, :)
        real(dp), intent(out) :: u(:, :)
        plan%rbuf(1:plan%nx, 1:plan%ny) = q
        plan%rbuf(plan%nx + 1:, 1:plan%ny) = 0.0_dp
        plan%rbuf(:, plan%ny + 1:) = 0.0_dp
        call fftw_execute_dft_r2c(plan%fwd, plan%rbuf, plan%cbuf)
        plan%cbuf = plan%cbuf * plan%spec(:, :, 1)
        call fftw_execute_dft_c2r(plan%bwd, plan%cbuf, plan%rbuf)
        u = plan%rbuf(1:plan%nx, 1:plan%ny)
    end subroutine conv_apply_plain

    !> The product of conv_apply in place on the plan's buffer, for callers
    !> that fuse the copies into their own loops: on entry
    !> plan%rbuf(1:nx, 1:ny) holds q, on return it holds C_k * q (the padding
    !> rows are zeroed here; columns ny+1: of rbuf are neither read nor written).
    !> The x transforms run over the ny loaded columns, the y transforms with the
    !> spectral product in blocks of PBLOCK x frequencies (spectral_block).
    subroutine conv_apply_buffer(plan, k)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: k
        integer :: i0, mxh
        mxh = plan%mx / 2 + 1
        plan%rbuf(plan%nx + 1:, 1:plan%ny) = 0.0_dp
        call fftw_execute_dft_r2c(plan%xf, plan%rbuf, plan%cbuf)
        do i0 = 1, mxh, PBLOCK
            call spectral_block(plan, k, i0, min(PBLOCK, mxh - i0 + 1))
        end do
        call fftw_execute_dft_c2r(plan%xb, plan%cbuf, plan%rbuf)
    end subroutine conv_apply_buffer

    !> x frequencies i0 .. i0 + nb - 1 of a pruned product: their ny loaded columns of
    !> plan%cbuf gathered into wbuf (zero beyond), the forward y transforms, the product
    !> by kernel k's spectrum, the inverse y transforms, and the first ny rows (the grid's)
    !> scattered back into cbuf.
    subroutine spectral_block(plan, k, i0, nb)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: k, i0, nb
        integer :: b, j, ny, my, ks
        ny = plan%ny
        my = plan%my
        ks = plan%sidx(k)
        do j = 1, ny
            do b = 1, nb
                plan%wbuf(j, b) = plan%cbuf(i0 + b - 1, j)
            end do
        end do
        plan%wbuf(ny + 1:my, 1:nb) = (0.0_dp, 0.0_dp)
        call block_transforms(plan, nb, .true., .false.)
        if (plan%real_spec(k)) then
            do b = 1, nb
                plan%wbuf(1:my, b) = plan%wbuf(1:my, b) * plan%rspec(:, i0 + b - 1, ks)
            end do
        else
            do b = 1, nb
                plan%wbuf(1:my, b) = plan%wbuf(1:my, b) * plan%cspec(:, i0 + b - 1, ks)
            end do
        end if
        call block_transforms(plan, nb, .false., .false.)
        do j = 1, ny
            do b = 1, nb
                plan%cbuf(i0 + b - 1, j) = plan%wbuf(j, b)
            end do
        end do
    end subroutine spectral_block

    !> The 2x2 block product of the tangential problem,
    !>   ux = C_kxx * qx + C_kxy * qy,   uy = C_kxy * qx + C_kyy * qy,
    !> with two forward and two inverse transforms, pruned as conv_apply_buffer's
    !> (the y transforms and the spectral products in blocks, pair_block).
    subroutine conv_apply_pair(plan, kxx, kxy, kyy, qx, qy, ux, uy)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kxx, kxy, kyy
        real(dp), intent(in) :: qx(:, :), qy(:, :)
        real(dp), intent(out) :: ux(:, :), uy(:, :)
        integer :: nx, ny, i0, mxh
        nx = plan%nx
        ny = plan%ny
        mxh = plan%mx / 2 + 1
        ! the out-of-place r2c keeps its input: the padding rows stay zero for qy
        plan%rbuf(1:nx, 1:ny) = qx
        plan%rbuf(nx + 1:, 1:ny) = 0.0_dp
        call fftw_execute_dft_r2c(plan%xf, plan%rbuf, plan%cbuf)
        plan%rbuf(1:nx, 1:ny) = qy
        call fftw_execute_dft_r2c(plan%xf, plan%rbuf, plan%cbuf2)
        do i0 = 1, mxh, PBLOCK
            call pair_block(plan, kxx, kxy, kyy, i0, min(PBLOCK, mxh - i0 + 1))
        end do
        call fftw_execute_dft_c2r(plan%xb, plan%cbuf, plan%rbuf)
        ux = plan%rbuf(1:nx, 1:ny)
        call fftw_execute_dft_c2r(plan%xb, plan%cbuf2, plan%rbuf)
        uy = plan%rbuf(1:nx, 1:ny)
    end subroutine conv_apply_pair

    !> x frequencies i0 .. i0 + nb - 1 of conv_apply_pair: Qx (cbuf) and Qy (cbuf2)
    !> gathered into wbuf and wbuf2, transformed along y, Ux = Cxx Qx + Cxy Qy into wbuf and
    !> Uy = Cxy Qx + Cyy Qy into wbuf2, transformed back and scattered into cbuf and cbuf2
    !> (see spectral_block).
    subroutine pair_block(plan, kxx, kxy, kyy, i0, nb)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: kxx, kxy, kyy, i0, nb
        integer :: b, j, ny, my, ii, rxx, rxy, ryy
        complex(dp) :: sx, sy
        complex(dp) :: cxx(plan%my), cxy(plan%my), cyy(plan%my)
        ny = plan%ny
        my = plan%my
        do j = 1, ny
            do b = 1, nb
                plan%wbuf(j, b) = plan%cbuf(i0 + b - 1, j)
                plan%wbuf2(j, b) = plan%cbuf2(i0 + b - 1, j)
            end do
        end do
        plan%wbuf(ny + 1:my, 1:nb) = (0.0_dp, 0.0_dp)
        plan%wbuf2(ny + 1:my, 1:nb) = (0.0_dp, 0.0_dp)
        call block_transforms(plan, nb, .true., .true.)
        if (plan%real_spec(kxx) .and. plan%real_spec(kxy) .and. plan%real_spec(kyy)) then
            rxx = plan%sidx(kxx)
            rxy = plan%sidx(kxy)
            ryy = plan%sidx(kyy)
            do b = 1, nb
                ii = i0 + b - 1
                do j = 1, my
                    sx = plan%wbuf(j, b)
                    sy = plan%wbuf2(j, b)
                    plan%wbuf(j, b) = plan%rspec(j, ii, rxx) * sx + plan%rspec(j, ii, rxy) * sy
                    plan%wbuf2(j, b) = plan%rspec(j, ii, rxy) * sx + plan%rspec(j, ii, ryy) * sy
                end do
            end do
        else
            do b = 1, nb
                ii = i0 + b - 1
                call spectrum_column(plan, kxx, ii, cxx)
                call spectrum_column(plan, kxy, ii, cxy)
                call spectrum_column(plan, kyy, ii, cyy)
                do j = 1, my
                    sx = plan%wbuf(j, b)
                    sy = plan%wbuf2(j, b)
                    plan%wbuf(j, b) = cxx(j) * sx + cxy(j) * sy
                    plan%wbuf2(j, b) = cxy(j) * sx + cyy(j) * sy
                end do
            end do
        end if
        call block_transforms(plan, nb, .false., .true.)
        do j = 1, ny
            do b = 1, nb
                plan%cbuf(i0 + b - 1, j) = plan%wbuf(j, b)
                plan%cbuf2(i0 + b - 1, j) = plan%wbuf2(j, b)
            end do
        end do
    end subroutine pair_block

    !> The y transforms of a block of nb x frequencies in wbuf (and wbuf2 for a pair),
    !> forward or inverse, by the plans of PBLOCK or of the remainder.
    subroutine block_transforms(plan, nb, forward, pair)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: nb
        logical, intent(in) :: forward, pair
        type(c_ptr) :: yp
        if (forward) then
            yp = plan%yf
            if (nb /= PBLOCK) yp = plan%yfr
        else
            yp = plan%yb
            if (nb /= PBLOCK) yp = plan%ybr
        end if
        call fftw_execute_dft(yp, plan%wbuf, plan%wbuf)
        if (pair) call fftw_execute_dft(yp, plan%wbuf2, plan%wbuf2)
    end subroutine block_transforms

    !> Kernel k's spectrum at x frequency ii over all my y frequencies, as complex numbers.
    pure subroutine spectrum_column(plan, k, ii, col)
        type(conv_plan), intent(in) :: plan
        integer, intent(in) :: k, ii
        complex(dp), intent(out) :: col(:)
        if (plan%real_spec(k)) then
            col = cmplx(plan%rspec(:, ii, plan%sidx(k)), 0.0_dp, dp)
        else
            col = plan%cspec(:, ii, plan%sidx(k))
        end if
    end subroutine spectrum_column

    !> Set up the preconditioner z = M r, M ~ A^-1 of the Boussinesq operator:
    !> the half-space's symbol is A(k) = 2 (1 - nu) / (G |k|), so M(k) =
    !> G |k| / (2 (1 - nu)) with the discrete wave number
    !> |k|^2 = (2/dx sin(kx dx/2))^2 + (2/dy sin(ky dy/2))^2, applied by
    !> periodic FFT on the unpadded grid (a quarter of a product's cost).
    !> The mean (k = 0) gets the weight of the lowest non-zero wave number.
    !> info: STAT_OK; STAT_BAD_ARGUMENT plan not initialised (conv_init);
    !> STAT_NO_MEMORY, STAT_FFTW_PLAN as conv_init.
    subroutine conv_init_precond(plan, g, nu, dx, dy, info)
        type(conv_plan), intent(inout) :: plan
        real(dp), intent(in) :: g, nu, dx, dy
        integer, intent(out) :: info
        integer :: i, j, nxh, ii, jj
        real(dp) :: kx, ky, twopi
        info = STAT_OK
        if (plan%nx < 1) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        nxh = plan%nx / 2 + 1
        plan%prmem = fftw_alloc_real(int(plan%nx, c_size_t) * plan%ny)
        plan%pcmem = fftw_alloc_complex(int(nxh, c_size_t) * plan%ny)
        if (.not. (c_associated(plan%prmem) .and. c_associated(plan%pcmem))) then
            info = STAT_NO_MEMORY
            return
        end if
        call c_f_pointer(plan%prmem, plan%prbuf, [plan%nx, plan%ny])
        call c_f_pointer(plan%pcmem, plan%pcbuf, [nxh, plan%ny])
        plan%pfwd = fftw_plan_dft_r2c_2d(plan%ny, plan%nx, plan%prbuf, plan%pcbuf, FFTW_ESTIMATE)
        plan%pbwd = fftw_plan_dft_c2r_2d(plan%ny, plan%nx, plan%pcbuf, plan%prbuf, FFTW_ESTIMATE)
        if (.not. (c_associated(plan%pfwd) .and. c_associated(plan%pbwd))) then
            info = STAT_FFTW_PLAN
            return
        end if
        allocate (plan%psym(nxh, plan%ny))
        twopi = 2.0_dp * acos(-1.0_dp)
        do j = 1, plan%ny
            jj = j - 1
            if (jj > plan%ny / 2) jj = jj - plan%ny
            ky = twopi * jj / (plan%ny * dy)
            do i = 1, nxh
                ii = i - 1
                kx = twopi * ii / (plan%nx * dx)
                plan%psym(i, j) = g / (2.0_dp * (1.0_dp - nu)) * sqrt( &
                    (2.0_dp / dx * sin(0.5_dp * kx * dx))**2 + (2.0_dp / dy * sin(0.5_dp * ky * dy))**2)
            end do
        end do
        plan%psym(1, 1) = minval(plan%psym(2:, 1))
        if (plan%ny > 1) plan%psym(1, 1) = min(plan%psym(1, 1), plan%psym(1, 2))
        plan%psym = plan%psym / real(plan%nx * plan%ny, dp)
        plan%has_prec = .true.
    end subroutine conv_init_precond

    !> z = M r (see conv_init_precond) in place on plan%prbuf: r on entry, z on return.
    subroutine conv_precond_buffer(plan)
        type(conv_plan), intent(inout) :: plan
        call fftw_execute_dft_r2c(plan%pfwd, plan%prbuf, plan%pcbuf)
        plan%pcbuf = plan%pcbuf * plan%psym
        call fftw_execute_dft_c2r(plan%pbwd, plan%pcbuf, plan%prbuf)
    end subroutine conv_precond_buffer

    !> u = C_k * q by the columns of the dense matrix of kernel k for q's non-zero
    !> elements, O(nq N); the matrix is made from c (kernel k's coefficients,
    !> influence_field layout) on first use and kept in the plan. For grids of at
    !> most DENSE_MAX elements (larger ones: conv_apply). Agrees with conv_apply to
    !> rounding.
    subroutine conv_apply_dense(plan, k, c, q, u)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: k
        real(dp), intent(in) :: c(0:, 0:), q(:, :)
        real(dp), intent(out) :: u(:, :)
        real(dp) :: v(plan%nx * plan%ny)
        integer :: i, j, n, nx, ny
        nx = plan%nx
        ny = plan%ny
        if (plan%dense_k /= k) call make_dense(plan, k, c)
        v = 0.0_dp
        n = 0
        do j = 1, ny
            do i = 1, nx
                n = n + 1
                if (q(i, j) /= 0.0_dp) v = v + q(i, j) * plan%dense(:, n)
            end do
        end do
        u = reshape(v, [nx, ny])
    end subroutine conv_apply_dense

    !> The dense matrix of kernel k: dense(i + (j - 1) nx, k + (l - 1) nx) = C(i - k, j - l).
    subroutine make_dense(plan, k, c)
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: k
        real(dp), intent(in) :: c(0:, 0:)
        integer :: i, j, kk, l, nx, ny, mx, my
        nx = plan%nx
        ny = plan%ny
        mx = 2 * nx
        my = 2 * ny
        if (allocated(plan%dense)) deallocate (plan%dense)
        allocate (plan%dense(nx * ny, nx * ny))
        do l = 1, ny
            do kk = 1, nx
                do j = 1, ny
                    do i = 1, nx
                        plan%dense(i + (j - 1) * nx, kk + (l - 1) * nx) = c(modulo(i - kk, mx), modulo(j - l, my))
                    end do
                end do
            end do
        end do
        plan%dense_k = k
    end subroutine make_dense

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
