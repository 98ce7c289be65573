!> A curve under the running vehicle: the inputs that the track's plan and cant add to the
!> force balance, tabulated over the vehicle's position s along the track and read at each
!> step's time (s = x0 + v0 t). Implements no Kaiser equation: the moving-track-frame formulation of
!> docs/vehicle_curving.md, whose tables are made in Python (railvti.vehicle.curving):
!>
!>   F(q, v, t) += fext(s) ; an element's deflection d = g.q + doff(s), rate g.v + drate(s) ;
!>   the wheelset w's contact sees its track frame turn at v0 kappa_w(s) (yaw rate).
!>
!> fext holds the suspension's forces from the bodies' frames' offsets (-K q_geo - C q_geo'),
!> the frames' fictitious forces (centripetal, cant's gravity share, yaw and roll
!> accelerations) and the wheelsets' gyroscopic moment about the turning frame.
!> A model with flexible wheelsets (FR, FF) also gets point forces on its attachment points
!> (curve_points): the journal springs' share of the frames' offsets, k g.q_geo + c g.q_geo',
!> and the elastic modes' Coriolis coupling with the frame's yaw rate v0 kappa.
!> Linear interpolation between the table's nodes; before the first and after the last node
!> the end values hold.
module vehicle_curve
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_SIZE_MISMATCH
    implicit none
    private
    public :: curve_input, curve_set, curve_points, curve_clear, curve_time

    !> One run's curve tables and their values at the current time (curve_time). ns = 0: none
    !> (straight track; every reader skips it).
    !> np > 0: point forces gpt (np, ns) on a modal part's attachment points, now p (np).
    type :: curve_input
        integer :: ns = 0, np = 0
        real(dp) :: s0 = 0.0_dp, ds = 1.0_dp, x0 = 0.0_dp, v0 = 0.0_dp
        real(dp), allocatable :: fext(:, :), doff(:, :), drate(:, :), kap(:, :), gpt(:, :)
        real(dp), allocatable :: f(:), d(:), dd(:), k(:), p(:)
    end type curve_input

contains

    !> Store the tables (ns nodes from s0 by ds, m) of a run at speed v0 (m/s) starting at x0
    !> (m): fext (nd, ns) N or N m, doff / drate (ne, ns) m or rad (per second), kap (nw, ns)
    !> 1/m. info: STAT_OK, STAT_BAD_ARGUMENT (ns < 2, ds <= 0, v0 <= 0 or a value not finite),
    !> STAT_SIZE_MISMATCH (an array not of the given sizes). The current values are set at t = 0.
    subroutine curve_set(cv, nd, ne, nw, ns, s0, ds, x0, v0, fext, doff, drate, kap, info)
        type(curve_input), intent(inout) :: cv
        integer, intent(in) :: nd, ne, nw, ns
        real(dp), intent(in) :: s0, ds, x0, v0
        real(dp), intent(in) :: fext(:, :), doff(:, :), drate(:, :), kap(:, :)
        integer, intent(out) :: info
        call curve_clear(cv)
        info = STAT_SIZE_MISMATCH
        if (any(shape(fext) /= [nd, ns]) .or. any(shape(doff) /= [ne, ns]) .or. &
            any(shape(drate) /= [ne, ns]) .or. any(shape(kap) /= [nw, ns])) return
        info = STAT_BAD_ARGUMENT
        if (ns < 2 .or. .not. (ds > 0.0_dp) .or. .not. (v0 > 0.0_dp)) return
        if (.not. (all(abs(fext) <= huge(1.0_dp)) .and. all(abs(doff) <= huge(1.0_dp)) .and. &
                   all(abs(drate) <= huge(1.0_dp)) .and. all(abs(kap) <= huge(1.0_dp)) .and. &
                   abs(s0) <= huge(1.0_dp) .and. abs(x0) <= huge(1.0_dp))) return
        cv%ns = ns
        cv%s0 = s0
        cv%ds = ds
        cv%x0 = x0
        cv%v0 = v0
        cv%fext = fext
        cv%doff = doff
        cv%drate = drate
        cv%kap = kap
        allocate (cv%f(nd), cv%d(ne), cv%dd(ne), cv%k(nw))
        call curve_time(cv, 0.0_dp)
        info = STAT_OK
    end subroutine curve_set

    !> Add the point forces gpt (np, ns: the attachment points' N or N m on the nodes of the
    !> tables set last) to a curve; the current values are set at t = 0. info: STAT_OK,
    !> STAT_BAD_ARGUMENT (no curve set, np < 1 or a value not finite), STAT_SIZE_MISMATCH (gpt
    !> not (np, cv%ns)).
    subroutine curve_points(cv, np, gpt, info)
        type(curve_input), intent(inout) :: cv
        integer, intent(in) :: np
        real(dp), intent(in) :: gpt(:, :)
        integer, intent(out) :: info
        info = STAT_BAD_ARGUMENT
        if (cv%ns == 0 .or. np < 1) return
        if (.not. all(abs(gpt) <= huge(1.0_dp))) return
        info = STAT_SIZE_MISMATCH
        if (any(shape(gpt) /= [np, cv%ns])) return
        if (allocated(cv%gpt)) deallocate (cv%gpt, cv%p)
        cv%np = np
        cv%gpt = gpt
        allocate (cv%p(np))
        call curve_time(cv, 0.0_dp)
        info = STAT_OK
    end subroutine curve_points

    !> Drop a run's curve (straight track again).
    subroutine curve_clear(cv)
        type(curve_input), intent(inout) :: cv
        cv%ns = 0
        cv%np = 0
        if (allocated(cv%gpt)) deallocate (cv%gpt, cv%p)
        if (allocated(cv%fext)) deallocate (cv%fext, cv%doff, cv%drate, cv%kap)
        if (allocated(cv%f)) deallocate (cv%f, cv%d, cv%dd, cv%k)
    end subroutine curve_clear

    !> The tables' values at time t (s = x0 + v0 t), linearly interpolated; nothing without a
    !> curve.
    subroutine curve_time(cv, t)
        type(curve_input), intent(inout) :: cv
        real(dp), intent(in) :: t
        real(dp) :: u, w
        integer :: i
        if (cv%ns == 0) return
        u = (cv%x0 + cv%v0 * t - cv%s0) / cv%ds
        u = min(max(u, 0.0_dp), real(cv%ns - 1, dp))
        i = min(int(u) + 1, cv%ns - 1)
        w = u - real(i - 1, dp)
        cv%f = (1.0_dp - w) * cv%fext(:, i) + w * cv%fext(:, i + 1)
        cv%d = (1.0_dp - w) * cv%doff(:, i) + w * cv%doff(:, i + 1)
        cv%dd = (1.0_dp - w) * cv%drate(:, i) + w * cv%drate(:, i + 1)
        cv%k = (1.0_dp - w) * cv%kap(:, i) + w * cv%kap(:, i + 1)
        if (cv%np > 0) cv%p = (1.0_dp - w) * cv%gpt(:, i) + w * cv%gpt(:, i + 1)
    end subroutine curve_time

end module vehicle_curve
