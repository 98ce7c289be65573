!> The exact step of the modal blocks (docs/vehicle_integrator.md, "Exact modal step"): each
!> block with mass, Q'' + B Q' + K Q = f(t) (M = I, f = Phi^T g the point forces' generalised
!> forces), is integrated exactly over a step of size h for the force linear in time between
!> its end values (the trapezoidal rule's interpolation order):
!>   [Q; V]_{n+1} = A [Q; V]_n + B0 f_n + B1 f_{n+1},   A = exp(h F),
!>   B1 = int_0^h exp((h - s) F) G s/h ds,  B0 = int_0^h exp((h - s) F) G ds - B1,
!>   F = [0 I; -K -B], G = [0; I],
!> all from one matrix exponential of the augmented 4s x 4s system per block and step size
!> (Pade, scaling and squaring; Van Loan's block form). With P, R the upper and lower halves of
!> B1 the step reads Q1 = Qh + P f1, V1 = Vh + R f1 (Qh, Vh: the known part), so that Newton
!> sees the block through P as it sees the trapezoidal block through S^-1 = (4/h^2 + 2 B/h +
!> K)^-1: the block's residual is f1 - P^-1 (Q1 - Qh), its velocity V1 = Vh + W (Q1 - Qh),
!> W = R P^-1. Stability: a force linear in time is Newmark's beta = 1/6 for what the points
!> couple to the block: stable while sqrt(k_c) h <= sqrt(12) for a coupling stiffness k_c per
!> unit modal mass (the block's own K and B are exact at any h). The force held at its mean
!> (B0 = B1) would be stable for any coupling stiffness, but is not for a point damper on a
!> mode beyond h omega = pi, and delayed the quasi-static part of the modes (FR hunting at 1 ms:
!> the amplitude 18 % low; docs/vehicle_integrator.md).
!> Massless blocks (and blocks whose P is singular) keep the trapezoidal rule. Work per step:
!> sum over blocks of s^2; per step size sum of (4 s)^3.
!> Implements no Kaiser equation.
module vehicle_modal_step
    use common_kinds, only: dp
    use common_lapack, only: dgesv
    use vehicle_modal, only: modal_part
    implicit none
    private
    public :: modal_step, modal_step_make, modal_step_begin, modal_step_velocity
    public :: modal_step_residual, modal_step_accel, modal_step_matrices, expm_pade, modal_step_cvp
    public :: modal_step_slot, block_step

    !> The exact step's matrices of every block for the step size h (h < 0: none yet).
    !> ex(b): block b is stepped exactly; packed at 4 off(b) (A, 2s x 2s) and off(b) (P, R,
    !> P^-1, W, s x s) as vehicle_modal's blocks.
    !> The key: h and the blocks it was made for (bb, kb, mass), so that a cache kept in the
    !> model across calls is never stale (the matrices are a function of these alone: cached or
    !> made afresh, the same bits).
    type :: modal_step
        real(dp) :: h = -1.0_dp
        logical, allocatable :: ex(:)
        real(dp), allocatable :: ea(:), ep(:), er(:), epi(:), ew(:), ep0(:), er0(:)
        real(dp), allocatable :: kbb(:), kkb(:), kmass(:)
        !> The ring's moving rows (vehicle_ring_step), nodes > 0: the weights of the m + 1 =
        !> nodes + 1 nodes s_k = k h / m of each ring mode j (the block's Q and V rows, rwq, rwv
        !> (0:m, nk)) in [Q; V]_{n+1} = A [Q; V]_n + sum_k W_k f(s_k) for f piecewise linear
        !> between the nodes (ring_weights); nodes = 0: none (also when a ring mode is not a
        !> 1 x 1 block stepped exactly).
        integer :: nodes = 0, knodes = 0   !< knodes: the nodes asked for (the key)
        real(dp), allocatable :: rwq(:, :), rwv(:, :)
    end type modal_step

contains

    !> The matrices of the step h for every block (nothing when ms already holds them).
    subroutine modal_step_make(mp, h, ms, nodes)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: h
        type(modal_step), intent(inout) :: ms
        integer, intent(in) :: nodes
        integer :: b, s, o, j0
        if (holds(mp, h, nodes, ms)) return
        if (allocated(ms%ex)) then
            if (size(ms%ex) /= mp%nb .or. size(ms%ep) /= mp%off(mp%nb + 1)) ms = modal_step()
        end if
        if (.not. allocated(ms%ex)) then
            allocate (ms%ex(mp%nb), ms%ea(4 * mp%off(mp%nb + 1)))
            allocate (ms%ep(mp%off(mp%nb + 1)), ms%er(mp%off(mp%nb + 1)), ms%epi(mp%off(mp%nb + 1)), &
                      ms%ew(mp%off(mp%nb + 1)), ms%ep0(mp%off(mp%nb + 1)), ms%er0(mp%off(mp%nb + 1)))
        end if
        ms%ea = 0.0_dp
        ms%ep = 0.0_dp
        ms%er = 0.0_dp
        ms%epi = 0.0_dp
        ms%ew = 0.0_dp
        ms%ep0 = 0.0_dp
        ms%er0 = 0.0_dp
        do b = 1, mp%nb
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            o = mp%off(b)
            ms%ex(b) = all(mp%mass(j0:j0 + s - 1) == 1.0_dp)
            if (ms%ex(b)) call block_step(s, h, mp%bb(o + 1:o + s * s), mp%kb(o + 1:o + s * s), &
                                          ms%ea(4 * o + 1:4 * o + 4 * s * s), ms%ep(o + 1:o + s * s), &
                                          ms%er(o + 1:o + s * s), ms%epi(o + 1:o + s * s), &
                                          ms%ew(o + 1:o + s * s), ms%ep0(o + 1:o + s * s), &
                                          ms%er0(o + 1:o + s * s), ms%ex(b))
        end do
        ms%h = h
        ms%kbb = mp%bb
        ms%kkb = mp%kb
        ms%kmass = mp%mass
        ms%nodes = 0
        ms%knodes = merge(nodes, 0, mp%nrl > 0)
        if (nodes > 0 .and. mp%nrl > 0) call ring_weights(mp, h, nodes, ms)
    end subroutine modal_step_make

    !> The node weights of the ring's modes for the step h with m nodes (ms%rwq, rwv): the
    !> sub-step h / m's exact step of each mode (A_s, B0_s, B1_s: block_step) chained,
    !> W_k = A_s^(m-1-k) B0_s [k < m] + A_s^(m-k) B1_s [k > 0]: exact for a force piecewise
    !> linear between the nodes. ms%nodes stays 0 when a ring mode is not a 1 x 1 exact block.
    subroutine ring_weights(mp, h, m, ms)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: h
        integer, intent(in) :: m
        type(modal_step), intent(inout) :: ms
        real(dp) :: a(2, 2), p(1, 1), r(1, 1), pinv(1, 1), w(1, 1), p0(1, 1), r0(1, 1), ap(2, 2, 0:m)
        integer :: j, b, col, k, o
        logical :: ok
        if (allocated(ms%rwq)) deallocate (ms%rwq, ms%rwv)
        allocate (ms%rwq(0:m, mp%rr%nk), ms%rwv(0:m, mp%rr%nk))
        b = 1
        do j = 1, mp%rr%nk
            col = mp%rm0 + j
            do while (b < mp%nb .and. mp%bs(b) < col)
                b = b + 1
            end do
            if (mp%bs(b) /= col .or. mp%bs(b + 1) /= col + 1) return
            if (.not. ms%ex(b)) return
            o = mp%off(b)
            call block_step(1, h / m, mp%bb(o + 1:o + 1), mp%kb(o + 1:o + 1), a, p, r, pinv, w, p0, r0, ok)
            if (.not. ok) return
            ap(:, :, 0) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 2])
            do k = 1, m
                ap(:, :, k) = matmul(a, ap(:, :, k - 1))
            end do
            ms%rwq(:, j) = 0.0_dp
            ms%rwv(:, j) = 0.0_dp
            do k = 0, m
                if (k < m) then
                    ms%rwq(k, j) = ap(1, 1, m - 1 - k) * p0(1, 1) + ap(1, 2, m - 1 - k) * r0(1, 1)
                    ms%rwv(k, j) = ap(2, 1, m - 1 - k) * p0(1, 1) + ap(2, 2, m - 1 - k) * r0(1, 1)
                end if
                if (k > 0) then
                    ms%rwq(k, j) = ms%rwq(k, j) + ap(1, 1, m - k) * p(1, 1) + ap(1, 2, m - k) * r(1, 1)
                    ms%rwv(k, j) = ms%rwv(k, j) + ap(2, 1, m - k) * p(1, 1) + ap(2, 2, m - k) * r(1, 1)
                end if
            end do
        end do
        ms%nodes = m
    end subroutine ring_weights

    !> Whether ms holds the step h of mp's blocks (and the ring's nodes: asked for, kept).
    pure logical function holds(mp, h, nodes, ms)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: h
        integer, intent(in) :: nodes
        type(modal_step), intent(in) :: ms
        holds = ms%h == h .and. allocated(ms%kmass)
        if (holds) holds = ms%knodes == merge(nodes, 0, mp%nrl > 0)
        if (.not. holds) return
        holds = size(ms%kmass) == mp%nm .and. size(ms%kbb) == size(mp%bb)
        if (holds) holds = all(ms%kbb == mp%bb) .and. all(ms%kkb == mp%kb) .and. all(ms%kmass == mp%mass)
    end function holds

    !> The slot of a cache (a run and its sub-steps: a few step sizes) for the step h: the one
    !> holding it, else the next in turn (next, advanced), which modal_step_make then fills.
    integer function modal_step_slot(mp, h, nodes, cache, next) result(i)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: h
        integer, intent(in) :: nodes
        type(modal_step), intent(in) :: cache(:)
        integer, intent(inout) :: next
        do i = 1, size(cache)
            if (holds(mp, h, nodes, cache(i))) return
        end do
        next = mod(next, size(cache)) + 1
        i = next
    end function modal_step_slot

    !> One block's A, P, R (B1), P0, R0 (B0), P^-1 and W = R P^-1 for the step h; ok false
    !> when P is singular
    !> (h omega near 2 pi k for an undamped mode: the block then keeps the trapezoidal rule).
    !> Scaled state (c Q, V), c ~ sqrt(|K|), so that the exponential's argument is balanced.
    subroutine block_step(s, h, bb, kb, a, p, r, pinv, w, p0, r0, ok)
        integer, intent(in) :: s
        real(dp), intent(in) :: h, bb(s, s), kb(s, s)
        real(dp), intent(out) :: a(2 * s, 2 * s), p(s, s), r(s, s), pinv(s, s), w(s, s), p0(s, s), r0(s, s)
        logical, intent(out) :: ok
        real(dp) :: x(4 * s, 4 * s), e(4 * s, 4 * s), c, lu(s, s)
        integer :: i, ipiv(s), info
        c = max(sqrt(maxval(sum(abs(kb), dim=1))), 1.0_dp / h)
        x = 0.0_dp
        do i = 1, s
            x(i, s + i) = h * c
            x(s + i, 2 * s + i) = 1.0_dp       ! G (the force enters V'), unscaled by h
            x(2 * s + i, 3 * s + i) = 1.0_dp   ! the force's change over the step
        end do
        x(s + 1:2 * s, 1:s) = -h * kb / c
        x(s + 1:2 * s, s + 1:2 * s) = -h * bb
        call expm_pade(4 * s, x, e, info)
        ok = info == 0
        if (.not. ok) return
        ! A = D^-1 E11 D, D = diag(c I, I); Gamma = h D^-1 E12
        a = e(1:2 * s, 1:2 * s)
        a(1:s, s + 1:2 * s) = a(1:s, s + 1:2 * s) / c
        a(s + 1:2 * s, 1:s) = a(s + 1:2 * s, 1:s) * c
        ! z1 = A z0 + h E12 f0 + h E13 (f1 - f0): B1 = h E13, B0 = h (E12 - E13)
        p = h * e(1:s, 3 * s + 1:4 * s) / c
        r = h * e(s + 1:2 * s, 3 * s + 1:4 * s)
        p0 = h * e(1:s, 2 * s + 1:3 * s) / c - p
        r0 = h * e(s + 1:2 * s, 2 * s + 1:3 * s) - r
        lu = p
        pinv = 0.0_dp
        do i = 1, s
            pinv(i, i) = 1.0_dp
        end do
        call dgesv(s, s, lu, s, ipiv, pinv, s, info)
        ok = info == 0 .and. all(abs(pinv) <= huge(1.0_dp))
        ! P's condition: a block whose end position hardly responds to the force is not taken
        if (ok) ok = maxval(sum(abs(p), dim=1)) * maxval(sum(abs(pinv), dim=1)) < 1.0e12_dp
        if (.not. ok) return
        w = matmul(r, pinv)
    end subroutine block_step

    !> exp(x) (n x n) by the (6, 6) Pade approximant with scaling and squaring (Moler & Van
    !> Loan 2003, method 3): |x / 2^j|_1 <= 1/2, relative error below 1e-16 there.
    !> info: 0, or LAPACK's dgesv info (a singular denominator: never for |x| <= 1/2).
    subroutine expm_pade(n, x, e, info)
        integer, intent(in) :: n
        real(dp), intent(in) :: x(n, n)
        real(dp), intent(out) :: e(n, n)
        integer, intent(out) :: info
        real(dp), parameter :: c(0:6) = [1.0_dp, 0.5_dp, 5.0_dp / 44.0_dp, 1.0_dp / 66.0_dp, &
                                          1.0_dp / 792.0_dp, 1.0_dp / 15840.0_dp, 1.0_dp / 665280.0_dp]
        real(dp) :: xs(n, n), xk(n, n), num(n, n), den(n, n), nrm
        integer :: j, k, i, ipiv(n)
        nrm = maxval(sum(abs(x), dim=1))
        j = 0
        if (nrm > 0.5_dp) j = max(0, ceiling(log(nrm / 0.5_dp) / log(2.0_dp)))
        xs = x / 2.0_dp**j
        num = 0.0_dp
        den = 0.0_dp
        do i = 1, n
            num(i, i) = 1.0_dp
            den(i, i) = 1.0_dp
        end do
        xk = num
        do k = 1, 6
            xk = matmul(xk, xs)
            num = num + c(k) * xk
            den = den + (-1.0_dp)**k * c(k) * xk
        end do
        call dgesv(n, n, den, n, ipiv, num, n, info)
        if (info /= 0) return
        e = num
        do k = 1, j
            e = matmul(e, e)
        end do
    end subroutine expm_pade

    !> The known part of the step from (q0, v0, a0) (modal coordinates; a0 the acceleration
    !> of the modal equation at t_n, so that f_n = a0 + B v0 + K q0): Qh = A11 q0 + A12 v0 +
    !> P0 f_n, Vh = A21 q0 + A22 v0 + R0 f_n (P0, R0: the halves of B0). Entries of blocks not
    !> stepped exactly are left as they are.
    pure subroutine modal_step_begin(mp, ms, q0, v0, a0, qh, vh)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: q0(mp%nm), v0(mp%nm), a0(mp%nm)
        real(dp), intent(inout) :: qh(mp%nm), vh(mp%nm)
        real(dp), allocatable :: fn(:), z(:)
        real(dp) :: fn1
        integer :: b, s, o, j0, j1
        do b = 1, mp%nb
            if (.not. ms%ex(b)) cycle
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            j1 = j0 + s - 1
            o = mp%off(b)
            if (s == 1) then    ! a mode on its own (the ring's): no temporaries
                fn1 = a0(j0) + mp%bb(o + 1) * v0(j0) + mp%kb(o + 1) * q0(j0)
                qh(j0) = ms%ea(4 * o + 1) * q0(j0) + ms%ea(4 * o + 3) * v0(j0) + ms%ep0(o + 1) * fn1
                vh(j0) = ms%ea(4 * o + 2) * q0(j0) + ms%ea(4 * o + 4) * v0(j0) + ms%er0(o + 1) * fn1
                cycle
            end if
            fn = a0(j0:j1) + matmul(reshape(mp%bb(o + 1:o + s * s), [s, s]), v0(j0:j1)) &
                 + matmul(reshape(mp%kb(o + 1:o + s * s), [s, s]), q0(j0:j1))
            z = matmul(reshape(ms%ea(4 * o + 1:4 * o + 4 * s * s), [2 * s, 2 * s]), [q0(j0:j1), v0(j0:j1)])
            qh(j0:j1) = z(1:s) + matmul(reshape(ms%ep0(o + 1:o + s * s), [s, s]), fn)
            vh(j0:j1) = z(s + 1:2 * s) + matmul(reshape(ms%er0(o + 1:o + s * s), [s, s]), fn)
        end do
    end subroutine modal_step_begin

    !> The end velocity of the exact blocks at the trial end q1: v1 = Vh + W (q1 - Qh).
    pure subroutine modal_step_velocity(mp, ms, qh, vh, q1, v1)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: qh(mp%nm), vh(mp%nm), q1(mp%nm)
        real(dp), intent(inout) :: v1(mp%nm)
        integer :: b, s, o, j0, j1
        do b = 1, mp%nb
            if (.not. ms%ex(b)) cycle
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            j1 = j0 + s - 1
            o = mp%off(b)
            if (s == 1) then
                v1(j0) = vh(j0) + ms%ew(o + 1) * (q1(j0) - qh(j0))
                cycle
            end if
            v1(j0:j1) = vh(j0:j1) + matmul(reshape(ms%ew(o + 1:o + s * s), [s, s]), q1(j0:j1) - qh(j0:j1))
        end do
    end subroutine modal_step_velocity

    !> The exact blocks' rows of Newton's residual at the trial end (q1, v1) with the modal
    !> force fm = -B v1 - K q1 + Phi^T g there: r = fm + B v1 + K q1 - P^-1 (q1 - Qh), the
    !> force at the end less the one the step implies (the trapezoidal rows' counterpart).
    pure subroutine modal_step_residual(mp, ms, qh, q1, v1, fm, r)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: qh(mp%nm), q1(mp%nm), v1(mp%nm), fm(mp%nm)
        real(dp), intent(inout) :: r(mp%nm)
        integer :: b, s, o, j0, j1
        do b = 1, mp%nb
            if (.not. ms%ex(b)) cycle
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            j1 = j0 + s - 1
            o = mp%off(b)
            if (s == 1) then
                r(j0) = fm(j0) + mp%bb(o + 1) * v1(j0) + mp%kb(o + 1) * q1(j0) - ms%epi(o + 1) * (q1(j0) - qh(j0))
                cycle
            end if
            r(j0:j1) = fm(j0:j1) + matmul(reshape(mp%bb(o + 1:o + s * s), [s, s]), v1(j0:j1)) &
                       + matmul(reshape(mp%kb(o + 1:o + s * s), [s, s]), q1(j0:j1)) &
                       - matmul(reshape(ms%epi(o + 1:o + s * s), [s, s]), q1(j0:j1) - qh(j0:j1))
        end do
    end subroutine modal_step_residual

    !> The exact blocks' acceleration at the accepted end: a1 = f1 - B v1 - K q1 with the end
    !> force the step implies, f1 = P^-1 (q1 - Qh) (the next step's f_n, modal_step_begin).
    pure subroutine modal_step_accel(mp, ms, qh, q1, v1, a1)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: qh(mp%nm), q1(mp%nm), v1(mp%nm)
        real(dp), intent(inout) :: a1(mp%nm)
        integer :: b, s, o, j0, j1
        do b = 1, mp%nb
            if (.not. ms%ex(b)) cycle
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            j1 = j0 + s - 1
            o = mp%off(b)
            if (s == 1) then
                a1(j0) = ms%epi(o + 1) * (q1(j0) - qh(j0)) - mp%bb(o + 1) * v1(j0) - mp%kb(o + 1) * q1(j0)
                cycle
            end if
            a1(j0:j1) = matmul(reshape(ms%epi(o + 1:o + s * s), [s, s]), q1(j0:j1) - qh(j0:j1)) &
                        - matmul(reshape(mp%bb(o + 1:o + s * s), [s, s]), v1(j0:j1)) &
                        - matmul(reshape(mp%kb(o + 1:o + s * s), [s, s]), q1(j0:j1))
        end do
    end subroutine modal_step_accel

    !> The packed block matrices S for vehicle_modal%modal_factorise (sx): P^-1 for the exact
    !> blocks, cq diag(mass) + cb B + K (the trapezoidal rule's) for the others.
    pure subroutine modal_step_matrices(mp, ms, cq, cb, sx)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: cq, cb
        real(dp), intent(out) :: sx(mp%off(mp%nb + 1))
        integer :: b, s, o, j0, i
        do b = 1, mp%nb
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            o = mp%off(b)
            if (ms%ex(b)) then
                sx(o + 1:o + s * s) = ms%epi(o + 1:o + s * s)
            else
                sx(o + 1:o + s * s) = cb * mp%bb(o + 1:o + s * s) + mp%kb(o + 1:o + s * s)
                do i = 1, s
                    sx(o + (i - 1) * s + i) = sx(o + (i - 1) * s + i) + cq * mp%mass(j0 + i - 1)
                end do
            end if
        end do
    end subroutine modal_step_matrices

    !> The points' own dv/dx for Newton's tangent: point p's velocity responds to a force on
    !> the points as Phi R Phi^T and its displacement as C = Phi S^-1 Phi^T; the ratio of their
    !> diagonals, cvp(p) = (cv (C_pp - E_pp) + Er_pp) / C_pp with E, Er the exact blocks' parts
    !> Phi P Phi^T, Phi R Phi^T (the trapezoidal blocks' velocity is cv times their
    !> displacement; 3/h for a slow exact mode, 1/h for a stiff one). cv where C_pp = 0.
    !> c: the condensed flexibility of the same step (modal_factor%c). Work: sum_b s^2 np_b.
    pure subroutine modal_step_cvp(mp, ms, c, cv, cvp)
        type(modal_part), intent(in) :: mp
        type(modal_step), intent(in) :: ms
        real(dp), intent(in) :: c(mp%np, mp%np), cv
        real(dp), intent(out) :: cvp(mp%np)
        real(dp) :: e(mp%np), er(mp%np)
        integer :: b, s, o, j0, lo, hi, p
        e = 0.0_dp
        er = 0.0_dp
        do b = 1, mp%nb
            if (.not. ms%ex(b)) cycle
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            o = mp%off(b)
            lo = minval(mp%rlo(j0:j0 + s - 1))
            hi = maxval(mp%rhi(j0:j0 + s - 1))
            if (hi < lo) cycle
            do p = lo, hi
                associate (row => mp%phi(p, j0:j0 + s - 1))
                    e(p) = e(p) + dot_product(row, matmul(reshape(ms%ep(o + 1:o + s * s), [s, s]), row))
                    er(p) = er(p) + dot_product(row, matmul(reshape(ms%er(o + 1:o + s * s), [s, s]), row))
                end associate
            end do
        end do
        do p = 1, mp%np
            cvp(p) = cv
            if (c(p, p) > 0.0_dp) cvp(p) = (cv * (c(p, p) - e(p)) + er(p)) / c(p, p)
        end do
    end subroutine modal_step_cvp

end module vehicle_modal_step
