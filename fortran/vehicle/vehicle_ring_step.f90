!> The exact modal step of the ring track's modes with their moving rows (model RF/FF;
!> docs/vehicle_integrator.md, "The ring's moving rows"). A ring mode's generalised force
!> f_j(s) = phi_j(x(s)) . g(s) moves with the contact points x(s) = x_n + v0 s, far from linear
!> in s over a step of 1 ms at 300 km/h (83 mm of travel; sleeper bay 0.6 m). Over the m + 1
!> nodes s_k = k h / m it takes the rows at the nodes, phi_j(x_k), and the point forces linear
!> in time, g(s_k) = (1 - k/m) g_n + (k/m) g_{n+1}, and each mode (a 1 x 1 block, stepped
!> exactly) is integrated exactly for f piecewise linear between the nodes
!> (vehicle_modal_step%ring_weights: W_k, 2-vectors per mode and node):
!>   [Q; V]_{n+1} = A [Q; V]_n + sum_k W_k (1 - k/m) phi_j(x_k) . g_n + sum_k W_k (k/m) phi_j(x_k) . g_{n+1}.
!> The last sum is the end rows' part: Q_{n+1} - Qh = P phie_j . g_{n+1} with the effective rows
!> phie_j = sum_k Wq_k (k/m) phi_j(x_k) / P (P the step's own, the plain exact step's end
!> weight: phie = phi(x_{n+1}) for rows that do not move). Newton keeps the exact step's
!> residual and matrix (C = Phi P Phi^T): the residual gains (phie_j - phi_j(x_{n+1})) . g_{n+1}
!> (ring_step_force), its tangent does not (a modified Newton). The velocity inside Newton is
!> the exact step's, V = Vh + W (Q - Qh); the accepted one takes the end rows of the velocity,
!> Vh + sum_k Wv_k (k/m) phi_j(x_k) . g_{n+1} (ring_step_accept). g_n, g_{n+1}: the ring points'
!> forces recovered from the modal force over the ring's modes, phi(x)^T g = f + B V + K Q, by
!> least squares (24 points, hundreds of modes: exact), so that the carried state (q, v, f)
!> alone defines the step and a run's chunking cannot change it. Work per step: m + 1 row
!> evaluations and O(m nk np_ring); nothing over all modes. The ring's points carry the contact's
!> forces only (vehicle_newmark%state_force's gp; no point element or coupling on them).
!> Implements no Kaiser equation.
module vehicle_ring_step
    use common_kinds, only: dp
    use common_lapack, only: dposv
    use vehicle_modal, only: modal_part
    use vehicle_modal_step, only: modal_step
    use vehicle_ring, only: ring_rows_eval
    implicit none
    private
    public :: ring_step_begin, ring_step_force, ring_step_accept, ring_points_force, ring_step_flex
    public :: ring_step_predict

contains

    !> The known part (qh, vh) of the ring's modes for the step h ending at t1 from (q0, v0,
    !> f0) (modal coordinates and force, nm), the end rows of Q over P less the model's end rows,
    !> dphi = phie - phi(x_{n+1}), and those of V, phiv (3, nc, nk), and g_n. ok false when g_n
    !> cannot be recovered (the step is then the plain exact one).
    subroutine ring_step_begin(mp, ms, h, t1, q0, v0, f0, qh, vh, dphi, phiv, g, ok)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: h, t1, q0(mp%nm), v0(mp%nm), f0(mp%nm)
        real(dp), intent(inout) :: qh(mp%nm), vh(mp%nm)
        real(dp), intent(out) :: dphi(3, mp%rr%nc, mp%rr%nk), phiv(3, mp%rr%nc, mp%rr%nk)
        real(dp), intent(out) :: g(3, mp%rr%nc)   !< g_n
        logical, intent(out) :: ok
        real(dp) :: rows(3, mp%rr%nc, mp%rr%nk, 0:ms%nodes), ak, fk, o4(4)
        integer :: m, k, j, col, o, b0
        m = ms%nodes
        b0 = ring_block0(mp)
        do k = 0, m - 1
            call ring_rows_eval(mp%rr, t1 - real(m - k, dp) * (h / real(m, dp)), rows(:, :, :, k))
        end do
        call end_rows(mp, rows(:, :, :, m))    ! the model's, set at t1 (vehicle_modal%modal_ring_time)
        call ring_points_force(mp, rows(:, :, :, 0), q0, v0, f0, g, ok)
        if (.not. ok) return
        dphi = 0.0_dp
        phiv = 0.0_dp
        do j = 1, mp%rr%nk
            col = mp%rm0 + j
            o = mp%off(b0 + j - 1)
            o4 = ms%ea(4 * o + 1:4 * o + 4)
            qh(col) = o4(1) * q0(col) + o4(3) * v0(col)
            vh(col) = o4(2) * q0(col) + o4(4) * v0(col)
            do k = 0, m
                fk = real(k, dp) / real(m, dp)
                if (k < m) then
                    ak = sum(rows(:, :, j, k) * g) * (1.0_dp - fk)
                    qh(col) = qh(col) + ms%rwq(k, j) * ak
                    vh(col) = vh(col) + ms%rwv(k, j) * ak
                end if
                if (k > 0) then
                    dphi(:, :, j) = dphi(:, :, j) + (ms%rwq(k, j) * fk) * rows(:, :, j, k)
                    phiv(:, :, j) = phiv(:, :, j) + (ms%rwv(k, j) * fk) * rows(:, :, j, k)
                end if
            end do
            dphi(:, :, j) = dphi(:, :, j) / ms%ep(o + 1)
            ! Newton's velocity Vh + W (Q - Qh) = Vh + R phie . g_{n+1} is the exact step's,
            ! Vh + phiv . g_{n+1}, with (phiv - R phie) . g_{n+1} taken at g_n
            vh(col) = vh(col) + sum((phiv(:, :, j) - ms%er(o + 1) * dphi(:, :, j)) * g)
            dphi(:, :, j) = dphi(:, :, j) - rows(:, :, j, m)
        end do
    end subroutine ring_step_begin

    !> The block of the ring's first mode: mode j is the 1 x 1 block b0 + j - 1
    !> (vehicle_modal_step%ring_weights took the step only when every ring mode is one).
    pure integer function ring_block0(mp) result(b)
        type(modal_part), intent(in) :: mp
        b = findloc(mp%bs(1:mp%nb), mp%rm0 + 1, dim=1)
    end function ring_block0

    !> The ring points' forces g (3, nc) from the modal force f over the ring's modes at the
    !> rows (3, nc, nk): phi^T g = f + B V + K Q (mass-normalised modes), by least squares
    !> (the normal equations, Cholesky). ok false when they are singular or do not reproduce f
    !> to 1e-6 of its terms' size.
    subroutine ring_points_force(mp, rows, q, v, f, g, ok)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: rows(3 * mp%rr%nc, mp%rr%nk), q(mp%nm), v(mp%nm), f(mp%nm)
        real(dp), intent(out) :: g(3 * mp%rr%nc)
        logical, intent(out) :: ok
        real(dp) :: fn(mp%rr%nk), fs(mp%rr%nk), nrm(3 * mp%rr%nc, 3 * mp%rr%nc), res
        integer :: j, col, o, info, b0
        b0 = ring_block0(mp)
        do j = 1, mp%rr%nk
            col = mp%rm0 + j
            o = mp%off(b0 + j - 1)
            fn(j) = f(col) + mp%bb(o + 1) * v(col) + mp%kb(o + 1) * q(col)
            fs(j) = abs(f(col)) + abs(mp%bb(o + 1) * v(col)) + abs(mp%kb(o + 1) * q(col))
        end do
        nrm = matmul(rows, transpose(rows))
        g = matmul(rows, fn)
        call dposv('L', 3 * mp%rr%nc, 1, nrm, 3 * mp%rr%nc, g, 3 * mp%rr%nc, info)
        ok = info == 0
        if (.not. ok) return
        ! f + B V + K Q cancels: its rounding is eps |K Q| (the scale fs), far above eps |f_n|
        res = norm2(matmul(g, rows) - fn)
        ok = res <= 1.0e-6_dp * norm2(fs) .or. norm2(fs) == 0.0_dp
    end subroutine ring_points_force

    !> Newton's start for the ring's modes: the step's end with the point forces held at g_n
    !> over the step, q1 = Qh + P phie . g_n (the rows moving; the constant-acceleration
    !> predictor holds the modal force instead, whose rows stay where they were).
    pure subroutine ring_step_predict(mp, ms, qh, dphi, gn, q1)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: qh(mp%nm), dphi(3, mp%rr%nc, mp%rr%nk), gn(3, mp%rr%nc)
        real(dp), intent(inout) :: q1(mp%nm)
        real(dp) :: rows(3, mp%rr%nc, mp%rr%nk)
        integer :: j, b0
        b0 = ring_block0(mp)
        call end_rows(mp, rows)
        do j = 1, mp%rr%nk
            q1(mp%rm0 + j) = qh(mp%rm0 + j) + ms%ep(mp%off(b0 + j - 1) + 1) * sum((dphi(:, :, j) + rows(:, :, j)) * gn)
        end do
    end subroutine ring_step_predict

    !> The model's ring rows at the contact points (3, nc, nk), phi(x_{n+1}).
    pure subroutine end_rows(mp, rows)
        type(modal_part), intent(in) :: mp
        real(dp), intent(out) :: rows(3, mp%rr%nc, mp%rr%nk)
        integer :: i, k
        do i = 1, mp%nrl
            do k = 1, 2
                rows(:, 2 * (i - 1) + k, :) = mp%phi(mp%rlpt(:, k, i), mp%rm0 + 1:mp%rm0 + mp%rr%nk)
            end do
        end do
    end subroutine end_rows

    !> Add the end rows' part to Newton's residual r (nm) of the ring's modes at the point
    !> forces gp (np): dphi_j . g_{n+1} = (phie_j - phi_j(x_{n+1})) . g_{n+1}.
    pure subroutine ring_step_force(mp, dphi, gp, r)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: dphi(3, mp%rr%nc, mp%rr%nk), gp(mp%np)
        real(dp), intent(inout) :: r(mp%nm)
        real(dp) :: g(3, mp%rr%nc)
        integer :: i, k, j
        do i = 1, mp%nrl
            do k = 1, 2
                g(:, 2 * (i - 1) + k) = gp(mp%rlpt(:, k, i))
            end do
        end do
        do j = 1, mp%rr%nk
            r(mp%rm0 + j) = r(mp%rm0 + j) + sum(dphi(:, :, j) * g)
        end do
    end subroutine ring_step_force

    !> Add the end rows' part to Newton's condensed flexibility c (np x np, the points' motion
    !> per unit point force, Phi S^-1 Phi^T with S = P^-1 for the ring's modes): the ring's
    !> share is Phi(x_{n+1}) P phie^T, so c gains Phi(x_{n+1}) P (phie - Phi(x_{n+1}))^T at the
    !> ring's points (lin_solve's modal increments take phie^T likewise: ring_step_force).
    !> Work: (3 nc)^2 nk.
    pure subroutine ring_step_flex(mp, ms, dphi, c)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: dphi(3 * mp%rr%nc, mp%rr%nk)
        real(dp), intent(inout) :: c(mp%np, mp%np)
        real(dp) :: rows(3 * mp%rr%nc, mp%rr%nk), d(3 * mp%rr%nc, mp%rr%nk), dc(3 * mp%rr%nc, 3 * mp%rr%nc)
        integer :: pts(3 * mp%rr%nc), i, k, cc, j, b0
        b0 = ring_block0(mp)
        do i = 1, mp%nrl
            do k = 1, 2
                cc = 2 * (i - 1) + k
                pts(3 * cc - 2:3 * cc) = mp%rlpt(:, k, i)
            end do
        end do
        rows = mp%phi(pts, mp%rm0 + 1:mp%rm0 + mp%rr%nk)
        do j = 1, mp%rr%nk
            d(:, j) = ms%ep(mp%off(b0 + j - 1) + 1) * dphi(:, j)
        end do
        dc = matmul(rows, transpose(d))
        c(pts, pts) = c(pts, pts) + dc
    end subroutine ring_step_flex

    !> The accepted step's ring modes: from Newton's end (q1, its velocity vn and modal force
    !> f1 there) the point forces g_{n+1} (ring_points_force at the end rows, the model's), the
    !> velocity v1 = Vh + phiv . g_{n+1} (vh: Newton's, ring_step_begin's with g_n: v1 = vh +
    !> phiv . (g_{n+1} - g_n) + R phie . g_n), and the force and acceleration there,
    !> f1 = a1 = phi(x_{n+1}) . g - B v1 - K q1. ok false when g cannot be recovered.
    subroutine ring_step_accept(mp, ms, vh, dphi, phiv, gn, q1, vn, f1, v1, a1, ok)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: vh(mp%nm), dphi(3, mp%rr%nc, mp%rr%nk), phiv(3, mp%rr%nc, mp%rr%nk)
        real(dp), intent(in) :: gn(3, mp%rr%nc), q1(mp%nm), vn(mp%nm)
        real(dp), intent(inout) :: f1(mp%nm), v1(mp%nm), a1(mp%nm)
        logical, intent(out) :: ok
        real(dp) :: rows(3, mp%rr%nc, mp%rr%nk), g(3, mp%rr%nc)
        integer :: j, col, o, b0
        b0 = ring_block0(mp)
        call end_rows(mp, rows)
        call ring_points_force(mp, rows, q1, vn, f1, g, ok)
        if (.not. ok) return
        do j = 1, mp%rr%nk
            col = mp%rm0 + j
            o = mp%off(b0 + j - 1)
            v1(col) = vh(col) + sum(phiv(:, :, j) * (g - gn)) + ms%er(o + 1) * sum((dphi(:, :, j) + rows(:, :, j)) * gn)
            f1(col) = f1(col) + mp%bb(o + 1) * (vn(col) - v1(col))
            a1(col) = f1(col)
        end do
    end subroutine ring_step_accept

end module vehicle_ring_step
