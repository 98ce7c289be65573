!> Registry of contact workspaces: the influence coefficients, their FFT
!> spectra and FFTW plans of one grid and material, made once and reused by
!> every solve on that grid (warm starts in sweeps and time simulations).
!> Callers hold an integer handle. Not thread-safe: create and free from one
!> thread (FFTW planning is not reentrant).
!> Implements no equation.
module contact_plans
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_NO_MEMORY
    use contact_influence, only: influence_field, KERNEL_ZZ, KERNEL_XX, KERNEL_YY, KERNEL_XY
    use contact_convolution, only: conv_plan, conv_init, conv_free, conv_init_precond
    implicit none
    private
    public :: workspace, ws_create, ws_free, ws_get, MAX_WORKSPACES, ws_create_from

    integer, parameter :: MAX_WORKSPACES = 512

    !> One grid's state. c(:, :, k) holds kernel k's coefficients
    !> (1 zz; with tangential kernels also 2 xx, 3 yy, 4 xy).
    type :: workspace
        logical :: used = .false.
        integer :: nx = 0, ny = 0, nker = 0
        real(dp) :: dx = 0, dy = 0, g = 0, nu = 0
        real(dp), allocatable :: c(:, :, :)
        type(conv_plan) :: plan
    end type workspace

    type(workspace), target :: slots(MAX_WORKSPACES)

contains

    !> Make a workspace; handle in 1..MAX_WORKSPACES. info: STAT_OK;
    !> STAT_NO_MEMORY when all MAX_WORKSPACES slots are in use (the registry is
    !> a fixed pool) or FFTW could not allocate; otherwise conv_init's or
    !> conv_init_precond's status (STAT_FFTW_PLAN, ...).
    subroutine ws_create(nx, ny, dx, dy, g, nu, tangential, handle, info)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, g, nu
        logical, intent(in) :: tangential
        integer, intent(out) :: handle, info
        type(workspace), pointer :: w
        call ws_claim(nx, ny, dx, dy, g, nu, merge(4, 1, tangential), w, handle, info)
        if (handle == 0) return
        call influence_field(KERNEL_ZZ, nx, ny, dx, dy, g, nu, w%c(:, :, 1))
        if (tangential) then
            call influence_field(KERNEL_XX, nx, ny, dx, dy, g, nu, w%c(:, :, 2))
            call influence_field(KERNEL_YY, nx, ny, dx, dy, g, nu, w%c(:, :, 3))
            call influence_field(KERNEL_XY, nx, ny, dx, dy, g, nu, w%c(:, :, 4))
        end if
        call ws_plan(w, handle, info)
    end subroutine ws_create

    !> Make a workspace from given coefficient fields c(:, :, k), k = 1..4 (zz, xx, yy, xy;
    !> influence_field's layout), e.g. the filtered fields of viscoelastic rolling
    !> (contact_viscoelastic_grid); g, nu: the elastic half-space of the preconditioner
    !> (and of w%g, w%nu). info as ws_create.
    subroutine ws_create_from(nx, ny, dx, dy, c, g, nu, handle, info)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, c(0:, 0:, :), g, nu
        integer, intent(out) :: handle, info
        type(workspace), pointer :: w
        call ws_claim(nx, ny, dx, dy, g, nu, size(c, 3), w, handle, info)
        if (handle == 0) return
        w%c = c
        call ws_plan(w, handle, info)
    end subroutine ws_create_from

    !> A free slot (handle 0 and STAT_NO_MEMORY when none) with the grid's data and
    !> room for nker coefficient fields.
    subroutine ws_claim(nx, ny, dx, dy, g, nu, nker, w, handle, info)
        integer, intent(in) :: nx, ny, nker
        real(dp), intent(in) :: dx, dy, g, nu
        type(workspace), pointer, intent(out) :: w
        integer, intent(out) :: handle, info
        integer :: k
        handle = 0
        info = STAT_NO_MEMORY
        w => null()
        do k = 1, MAX_WORKSPACES
            if (.not. slots(k)%used) then
                handle = k
                exit
            end if
        end do
        if (handle == 0) return
        w => slots(handle)
        w%nx = nx
        w%ny = ny
        w%dx = dx
        w%dy = dy
        w%g = g
        w%nu = nu
        w%nker = nker
        allocate (w%c(0:2 * nx - 1, 0:2 * ny - 1, nker))
    end subroutine ws_claim

    !> The FFT plans and the preconditioner of a claimed slot; on failure the slot is
    !> released (handle 0).
    subroutine ws_plan(w, handle, info)
        type(workspace), pointer, intent(in) :: w
        integer, intent(inout) :: handle
        integer, intent(out) :: info
        call conv_init(w%plan, w%nx, w%ny, w%c, info)
        if (info == STAT_OK) call conv_init_precond(w%plan, w%g, w%nu, w%dx, w%dy, info)
        if (info /= STAT_OK) then
            call conv_free(w%plan)
            deallocate (w%c)
            handle = 0
            return
        end if
        w%used = .true.
    end subroutine ws_plan

    subroutine ws_free(handle)
        integer, intent(in) :: handle
        if (handle < 1 .or. handle > MAX_WORKSPACES) return
        if (.not. slots(handle)%used) return
        call conv_free(slots(handle)%plan)
        if (allocated(slots(handle)%c)) deallocate (slots(handle)%c)
        slots(handle)%used = .false.
    end subroutine ws_free

    !> Pointer to a live workspace, or null for a bad handle.
    function ws_get(handle, nx, ny) result(w)
        integer, intent(in) :: handle
        integer, intent(in), optional :: nx, ny   ! if given, the grid must have this size
        type(workspace), pointer :: w
        w => null()
        if (handle < 1 .or. handle > MAX_WORKSPACES) return
        if (.not. slots(handle)%used) return
        if (present(nx)) then
            if (slots(handle)%nx /= nx) return
        end if
        if (present(ny)) then
            if (slots(handle)%ny /= ny) return
        end if
        w => slots(handle)
    end function ws_get

end module contact_plans
