!> The fixed data of one steady-rolling solve (contact_rolling): the rolling_patch and
!> in-row run_basis types, the method and status constants, and the operations on a
!> patch that both iterations use (the disc projection of eq. 26/28's bound, packing the
!> contact set's tractions, the convergence test). Split from contact_rolling; the
!> algorithm and the equations are described there.
!> Implements Kaiser eq. 27 (the bound g = mu p, project_on_disc) and none other.
module contact_rolling_patch
    use common_kinds, only: dp
    use common_status, only: STAT_NOT_FINITE
    use contact_friction, only: friction_law
    implicit none
    private
    public :: rolling_patch, run_basis, rolling_patch_reset, project_on_disc, residual_ok
    public :: pack_tractions, unpack_tractions
    public :: ROLL_GS, ROLL_FFTGS, ST_EXTERIOR, ST_ADHESION, ST_SLIP, AA_M, SOP_MAX
    public :: PRODUCT_AUTO, PRODUCT_FFT, PRODUCT_DIRECT, THETA, WU0, WU1, WU2

    integer, parameter :: ROLL_GS = 1, ROLL_FFTGS = 2
    integer, parameter :: ST_EXTERIOR = 0, ST_ADHESION = 1, ST_SLIP = 2
    integer, parameter :: AA_M = 5   ! Anderson depth of both methods
    !> How the field u = A t is formed: the cheaper way by a count of operations
    !> (direct_is_cheaper), always by FFT (the reference), or always directly.
    integer, parameter :: PRODUCT_AUTO = 0, PRODUCT_FFT = 1, PRODUCT_DIRECT = 2
    !> Weight of the three-point upwind difference (module doc) and its stencil.
    real(dp), parameter :: THETA = 1.0_dp / 3.0_dp
    real(dp), parameter :: WU0 = 1.0_dp + THETA, WU1 = -(1.0_dp + 2.0_dp * THETA), WU2 = THETA
    !> Largest contact set whose dense slip operator direct products use: its matrix
    !> (at most 313 KB) stays in cache; a larger one streams from memory on every
    !> product and loses to box_apply (25 x 25 grid, 210 in contact: 6 % slower).
    integer, parameter :: SOP_MAX = 100

    !> In-row basis of a run of n elements (make_basis).
    type :: run_basis
        real(dp), allocatable :: mx(:, :), my(:, :), qx(:), qy(:)
        !> per element of the run: the pivots of its element problem (px, py), their
        !> reciprocals (rpx, rpy) and 1 / m(q, q) (rmx, rmy), for the small path's passes
        real(dp), allocatable :: px(:), py(:), rpx(:), rpy(:), rmx(:), rmy(:)
    end type run_basis

    !> The fixed data of one solve (patch_setup): the contact set and its
    !> bounding box, the rigid slip, the coefficients At by offset and the
    !> in-row bases. Only the tractions and displacement fields change.
    type :: rolling_patch
        integer :: nx = 0, ny = 0                 ! grid size
        real(dp) :: dx = 0.0_dp                   ! element length along x (rolling), m
        integer :: i1 = 0, i2 = 0, j1 = 0, j2 = 0 ! bounding box of the contact set
        integer :: ib2 = 0                        ! i2 + 1: the upstream row the slip needs
        integer :: nbx = 0, nby = 0               ! offsets spanned by the box
        integer :: nc = 0                         ! elements in contact
        logical :: direct = .false.               ! u = A t by direct sums over the box (box_apply)
        integer, allocatable :: ic(:), jc(:)      ! (nc) the contact set, column by column
        real(dp) :: kx = 0.0_dp, ky = 0.0_dp      ! single-element pivots (At(0) - At(dx)) / dx, 1/Pa
        logical, allocatable :: inc(:, :)         ! (nx, ny) element in contact, p > 0
        integer, allocatable :: trail(:, :)       ! (nx, ny) trailing end of the run through (i, j)
        integer, allocatable :: rlo(:), rhi(:)    ! (j1:j2) first and last element in contact of row j
        real(dp), allocatable :: bound(:, :)      ! (nx, ny) traction bound mu p, Pa
        real(dp), allocatable :: wx(:, :), wy(:, :)   ! (nx, ny) rigid slip, creepage units
        !> At by offset (-nbx-1..nbx+1, -nby..nby), for the bases and the cross-row updates
        real(dp), allocatable :: axx(:, :), ayy(:, :), axy(:, :)
        !> A itself by offset, same bounds (direct products only)
        real(dp), allocatable :: rxx(:, :), ryy(:, :), rxy(:, :)
        !> (2 nc, 2 nc) dense slip operator of the contact set (direct products, nc <= SOP_MAX)
        real(dp), allocatable :: sop(:, :)
        type(run_basis), allocatable :: bases(:)  ! by run length 1..nbx
        !> the small path (pa%sop made): the runs in sweep order (rows j ascending, within
        !> a row from the leading edge), as packed positions: first element rp0, length rn,
        !> first element whose slip the run's change must update rrow (its row's first, or
        !> the next row's when the run fills its row); the rigid slip and the bound packed
        integer :: nrun = 0
        integer, allocatable :: rp0(:), rn(:), rrow(:)
        real(dp), allocatable :: wxc(:), wyc(:), bc(:)
        !> the geometry (everything but the rigid slip) is set: a caller's patch
        !> (rolling_steady's patch) is reused for the next solve of the same pressure
        logical :: ready = .false.
        integer :: prod = -1                      ! the product choice it was made for
        !> a slip-velocity-dependent or static/kinetic friction law (contact_friction):
        !> bound holds mu_s p and the element problems go to friction_element_solve
        logical :: varlaw = .false.
        type(friction_law) :: law
        real(dp) :: speed = 0.0_dp                ! rolling speed, m/s
    end type rolling_patch


contains

    !> Radial return of one element's traction onto the Coulomb disc
    !> |t| <= bound (the slip direction is kept).
    elemental subroutine project_on_disc(tx, ty, bound)
        real(dp), intent(inout) :: tx, ty
        real(dp), intent(in) :: bound
        real(dp) :: t
        t = sqrt(tx * tx + ty * ty)    ! tractions and slips are far from over/underflow
        if (t > bound) then
            tx = tx * bound / t
            ty = ty * bound / t
        end if
    end subroutine project_on_disc

    !> A kept patch (rolling_steady's patch) marked stale after the pressure or mu changed:
    !> the next solve makes it anew, or, when its contact set (p > 0) and product are
    !> those of the stale patch, only sets the new traction bound (the contact set, bases
    !> and slip operator depend on nothing else; the caller keeps the workspace and the
    !> grid origin, as contact_creep_table does).
    subroutine rolling_patch_reset(pa)
        type(rolling_patch), intent(inout) :: pa
        pa%ready = .false.
    end subroutine rolling_patch_reset

    !> The relative residual sqrt(r2 / n2) (jacobi_residual's squares) into resid; false
    !> (info STAT_NOT_FINITE, resid huge) when the squares are not finite.
    logical function residual_ok(r2, n2, resid, info)
        real(dp), intent(in) :: r2, n2
        real(dp), intent(out) :: resid
        integer, intent(inout) :: info
        residual_ok = .not. (r2 /= r2 .or. n2 /= n2 .or. r2 > huge(1.0_dp))
        if (.not. residual_ok) then
            info = STAT_NOT_FINITE
            resid = huge(1.0_dp)
        else if (n2 > 0.0_dp) then
            resid = sqrt(r2 / n2)
        else
            resid = merge(0.0_dp, 1.0_dp, r2 == 0.0_dp)
        end if
    end function residual_ok

    !> The tractions of the contact set packed as [tx(inc), ty(inc)] (pack's order).
    subroutine pack_tractions(pa, tx, ty, v)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: tx(:, :), ty(:, :)
        real(dp), intent(out) :: v(:)
        integer :: k
        do k = 1, pa%nc
            v(k) = tx(pa%ic(k), pa%jc(k))
            v(pa%nc + k) = ty(pa%ic(k), pa%jc(k))
        end do
    end subroutine pack_tractions

    !> tx, ty on the contact set from a vector packed as [tx(inc), ty(inc)], each
    !> traction put on its disc (outside the set they stay zero: patch_setup).
    subroutine unpack_tractions(pa, v, tx, ty)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: v(:)
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        integer :: k, i, j
        do k = 1, pa%nc
            i = pa%ic(k)
            j = pa%jc(k)
            tx(i, j) = v(k)
            ty(i, j) = v(pa%nc + k)
            call project_on_disc(tx(i, j), ty(i, j), pa%bound(i, j))
        end do
    end subroutine unpack_tractions

end module contact_rolling_patch
