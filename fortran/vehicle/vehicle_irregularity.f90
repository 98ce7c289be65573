!> Track irregularities as rail-position inputs under each wheel (docs/vehicle_irregularity.md).
!> Implements no Kaiser equation: the four EN 13848-1 channels (vertical level, alignment, cross
!> level, gauge; m along the track x, m) tabulated at nodes x_i with their slopes, read by cubic
!> Hermite interpolation (C1; zero outside the table), turned into the pose of a track element
!> of each wheel's own, as the ring's rail head is (vehicle_contact%wheelset_contact's rail):
!>
!>   T_y = alignment + sg gauge / 2,   T_z = vertical_level,   T_roll = cross_level / base
!>
!> (sg = +1 left wheel, -1 right; base the distance over which the cross level is measured,
!> 1.5 m for standard gauge), which moves the left rail head by (al + ga/2, vl + cl/2) and the
!> right by (al - ga/2, vl - cl/2) and rolls both by cl/base. Wheelset w's wheels are at
!> x_w(t) = x0 + v0 t + xw(w) (xw: its position in the coach, the leading wheelset ahead);
!> the pose's rates are v0 dT/dx (the rates of the rail under the moving contact) and the
!> rail's yaw dT_y/dx, which the contact subtracts from the wheelset's yaw: with both, the
!> creepages are those of the wheelset against the rail's own direction (eta = y'/v0 - psi
!> against a rail at rest, to first order). The inputs are an explicit function of time: the
!> time loop sets them once per (sub-)step at its end time (irr_time).
module vehicle_irregularity
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    implicit none
    private
    public :: irr_track, irr_set, irr_time, irr_inputs, NIRR

    !> Inputs per wheel: T_y, T_z, T_roll, their rates, the rail's yaw dT_y/dx.
    integer, parameter :: NIRR = 7

    !> The irregular track of a model (nw = 0: none).
    type :: irr_track
        integer :: n = 0, nw = 0
        real(dp), allocatable :: x(:), c(:, :), d(:, :)   !< nodes (n), channels and slopes (4, n)
        real(dp), allocatable :: xw(:)                    !< wheelset positions in the coach (nw)
        real(dp) :: x0 = 0.0_dp, v0 = 0.0_dp, base = 1.5_dp
        !> The inputs (NIRR, 2 wheels, nw) at the time set last (irr_time).
        real(dp), allocatable :: now(:, :, :)
    end type irr_track

contains

    !> Store an irregular track: n >= 2 strictly increasing finite nodes x, the channels c and
    !> their slopes d (4, n; rows vertical level, alignment, cross level, gauge), the wheelsets'
    !> positions xw (nw), the start x0, the speed v0 > 0 and the cross level's base > 0; the
    !> inputs are then at t = 0. info: STAT_OK, STAT_BAD_ARGUMENT (any of these violated).
    subroutine irr_set(n, x, c, d, nw, xw, x0, v0, base, ir, info)
        integer, intent(in) :: n, nw
        real(dp), intent(in) :: x(n), c(4, n), d(4, n), xw(nw), x0, v0, base
        type(irr_track), intent(out) :: ir
        integer, intent(out) :: info
        info = STAT_BAD_ARGUMENT
        if (n < 2 .or. nw < 1) return
        if (.not. (all(abs(x) <= huge(1.0_dp)) .and. all(abs(c) <= huge(1.0_dp)) .and. &
                   all(abs(d) <= huge(1.0_dp)) .and. all(abs(xw) <= huge(1.0_dp)) .and. &
                   abs(x0) <= huge(1.0_dp) .and. v0 > 0.0_dp .and. v0 <= huge(1.0_dp) .and. &
                   base > 0.0_dp .and. base <= huge(1.0_dp))) return
        if (any(x(2:n) <= x(1:n - 1))) return
        ir%n = n
        ir%nw = nw
        ir%x = x
        ir%c = c
        ir%d = d
        ir%xw = xw
        ir%x0 = x0
        ir%v0 = v0
        ir%base = base
        allocate (ir%now(NIRR, 2, nw))
        call irr_time(ir, 0.0_dp)
        info = STAT_OK
    end subroutine irr_set

    !> Set the inputs to time t (nothing without an irregular track).
    pure subroutine irr_time(ir, t)
        type(irr_track), intent(inout) :: ir
        real(dp), intent(in) :: t
        if (ir%nw == 0) return
        call irr_inputs(ir, t, ir%now)
    end subroutine irr_time

    !> The inputs at time t: u(:, k, w) for wheel k (1 left, 2 right) of wheelset w.
    pure subroutine irr_inputs(ir, t, u)
        type(irr_track), intent(in) :: ir
        real(dp), intent(in) :: t
        real(dp), intent(out) :: u(NIRR, 2, ir%nw)
        real(dp) :: c(4), dc(4), sg
        integer :: w, k
        do w = 1, ir%nw
            call channels_at(ir, ir%x0 + ir%v0 * t + ir%xw(w), c, dc)
            do k = 1, 2
                sg = merge(1.0_dp, -1.0_dp, k == 1)
                u(1, k, w) = c(2) + 0.5_dp * sg * c(4)
                u(2, k, w) = c(1)
                u(3, k, w) = c(3) / ir%base
                u(4, k, w) = ir%v0 * (dc(2) + 0.5_dp * sg * dc(4))
                u(5, k, w) = ir%v0 * dc(1)
                u(6, k, w) = ir%v0 * dc(3) / ir%base
                u(7, k, w) = dc(2) + 0.5_dp * sg * dc(4)
            end do
        end do
    end subroutine irr_inputs

    !> The channels c and their x-derivatives dc at x: the cubic Hermite interpolant of the
    !> nodes' values and slopes (zero outside [x(1), x(n)]).
    pure subroutine channels_at(ir, x, c, dc)
        type(irr_track), intent(in) :: ir
        real(dp), intent(in) :: x
        real(dp), intent(out) :: c(4), dc(4)
        real(dp) :: h, s, h00, h10, h01, h11, g00, g10, g01, g11
        integer :: lo, hi, mid
        c = 0.0_dp
        dc = 0.0_dp
        if (.not. (x >= ir%x(1) .and. x <= ir%x(ir%n))) return
        lo = 1
        hi = ir%n
        do while (hi - lo > 1)      ! x(lo) <= x <= x(hi)
            mid = (lo + hi) / 2
            if (ir%x(mid) <= x) then
                lo = mid
            else
                hi = mid
            end if
        end do
        h = ir%x(hi) - ir%x(lo)
        s = (x - ir%x(lo)) / h
        h00 = (1.0_dp + 2.0_dp * s) * (1.0_dp - s)**2
        h10 = s * (1.0_dp - s)**2
        h01 = s * s * (3.0_dp - 2.0_dp * s)
        h11 = s * s * (s - 1.0_dp)
        g00 = 6.0_dp * s * (s - 1.0_dp)
        g10 = (1.0_dp - s) * (1.0_dp - 3.0_dp * s)
        g01 = -g00
        g11 = s * (3.0_dp * s - 2.0_dp)
        c = h00 * ir%c(:, lo) + h * h10 * ir%d(:, lo) + h01 * ir%c(:, hi) + h * h11 * ir%d(:, hi)
        dc = (g00 * ir%c(:, lo) + g01 * ir%c(:, hi)) / h + g10 * ir%d(:, lo) + g11 * ir%d(:, hi)
    end subroutine channels_at

end module vehicle_irregularity
