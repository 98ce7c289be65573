!> The normal contact problem of a small grid under force control, solved exactly by an
!> active set on the dense influence matrix (Kalker's active-set iteration for the
!> normal problem, Kalker 1990, sect. 5.2; Kaiser eqs 17-23 with the force prescribed):
!> for a trial contact set I the equations A_II p_I = delta - h_I and dx dy sum(p_I) = Fn
!> are solved directly (Cholesky of A_II, which is symmetric positive definite), then
!> the elements of I with p <= 0 leave it, or, when there are none, the elements outside
!> with a negative deformed gap e = h + A p - delta join it, until neither happens.
!> On grids of a few hundred elements this costs a few Cholesky factors of the contact
!> set (about nc^3 / 6 multiply-adds each) where the projected CG (contact_normal) makes
!> 10-20 iterations of passes over the grid and products; the answer is the exact
!> solution of the discrete problem (to rounding), which CG approaches to its tolerance.
!> A start set (the elements with p > 0 of a start pressure, e.g. the previous case of a
!> creep-force table) changes the path, not the answer: the final set's equations fix p.
!> No convergence proof: after MAX_SETS trial sets the caller falls back to CG.
!> Used by contact_creep_table for grids of at most NORMAL_DENSE_MAX elements.
!> Implements Kaiser eqs 21-22 (the discrete normal problem, force control) by an active
!> set (docs/equations.md).
module contact_normal_dense
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NOT_FINITE
    use contact_normal, only: normal_residual
    implicit none
    private
    public :: normal_dense_force, NORMAL_DENSE_MAX, dense_is_cheaper, normal_dense_cache

    !> The Cholesky factor of the last trial set's A_II and its solution y1 = A_II^-1 1, kept by a
    !> caller from one solve to the next on the same grid and influence coefficients (a
    !> creep-force table's cases): a case whose trial set is the cached one (a table's next
    !> case starts from the previous case's final set) solves only A_II y2 = h_I with it.
    !> A_II depends on the set alone, not on h or Fn, so the result has the same bits as a
    !> fresh factor's.
    type :: normal_dense_cache
        integer :: m = 0                     ! elements of the cached set (0: none)
        integer, allocatable :: ic(:), jc(:) ! the set, column by column (set_list's order)
        real(dp), allocatable :: l(:, :)     ! (m, m) Cholesky factor of A_II, lower triangle
        real(dp), allocatable :: y1(:)       ! A_II^-1 1
    end type normal_dense_cache

    !> Grids of at most this many elements (the dense factor of a contact set of up to
    !> about a third of them stays below 1 MB).
    integer, parameter :: NORMAL_DENSE_MAX = 1024
    !> Trial contact sets before giving up (2-3 are typical on the 11 x 11 grid).
    integer, parameter :: MAX_SETS = 40
    !> An element outside the set joins it when its deformed gap is below -GAP_TOL times
    !> the deformation (delta - min h): a rounding-level negative gap is not a penetration.
    real(dp), parameter :: GAP_TOL = 1.0e-12_dp

contains

    !> Pressures p >= 0 (Pa) on the grid of the gap h (m) with the influence coefficients
    !> c (kernel zz, influence_field's circular layout on the (2 nx, 2 ny) grid, m/Pa), such
    !> that e = h + A p - approach is zero where p > 0 and >= 0 elsewhere and
    !> area_el sum(p) = fn (N). p in: a start (its elements with p > 0 the first trial set;
    !> none: the elements with h below a quarter of h's range, as contact_normal's start).
    !> iters: trial sets; resid: normal_residual of the result. info: STAT_OK;
    !> STAT_NOT_CONVERGED no final set after MAX_SETS (or a non-positive pivot, or fn <= 0):
    !> p is then zero and the caller solves otherwise; STAT_NOT_FINITE a non-finite h.
    !> cache (optional): the factor of the last trial set, kept by the caller for the next
    !> solve with the same c (normal_dense_cache); used when a trial set is the cached one,
    !> replaced by each factor made.
    subroutine normal_dense_force(c, h, area_el, fn, p, approach, iters, resid, info, cache)
        real(dp), intent(in) :: c(0:, 0:), h(:, :), area_el, fn
        real(dp), intent(inout) :: p(:, :)
        real(dp), intent(out) :: approach, resid
        integer, intent(out) :: iters, info
        type(normal_dense_cache), intent(inout), optional :: cache
        logical, allocatable :: act(:, :)
        real(dp), allocatable :: u(:, :), pi(:)
        integer, allocatable :: ic(:), jc(:)
        real(dp) :: hmin, delta, etol
        integer :: nx, ny, m, it, nout

        nx = size(h, 1)
        ny = size(h, 2)
        iters = 0
        approach = 0.0_dp
        resid = huge(1.0_dp)
        info = STAT_OK
        if (.not. all(abs(h) <= huge(1.0_dp))) then
            info = STAT_NOT_FINITE
            return
        end if
        if (.not. (fn > 0.0_dp)) then
            info = STAT_NOT_CONVERGED
            return
        end if
        allocate (act(nx, ny), u(nx, ny), ic(nx * ny), jc(nx * ny), pi(nx * ny))
        hmin = minval(h)
        if (any(p > 0.0_dp)) then
            act = p > 0.0_dp
        else
            act = h <= hmin + 0.25_dp * (maxval(h) - hmin)
        end if
        info = STAT_NOT_CONVERGED
        do it = 1, MAX_SETS
            iters = it
            call set_list(act, ic, jc, m)
            if (present(cache)) then
                call solve_set_cached(c, h, area_el, fn, ic(1:m), jc(1:m), pi(1:m), delta, info, cache)
            else
                call solve_set(c, h, area_el, fn, ic(1:m), jc(1:m), pi(1:m), delta, info)
            end if
            if (info /= STAT_OK) exit
            if (any(pi(1:m) <= 0.0_dp)) then
                call drop_nonpositive(act, ic(1:m), jc(1:m), pi(1:m))
                info = STAT_NOT_CONVERGED
                cycle
            end if
            p = 0.0_dp
            call scatter(ic(1:m), jc(1:m), pi(1:m), p)
            call apply_set(c, ic(1:m), jc(1:m), pi(1:m), u)
            etol = GAP_TOL * (delta - hmin)
            nout = count(.not. act .and. h + u - delta < -etol)
            if (nout > 0) then
                where (.not. act .and. h + u - delta < -etol) act = .true.
                info = STAT_NOT_CONVERGED
                cycle
            end if
            approach = delta
            resid = normal_residual(h + u - delta, p, u)
            exit
        end do
        if (info /= STAT_OK) p = 0.0_dp
    end subroutine normal_dense_force

    !> Whether the active set is likely the cheaper solve on an nx x ny grid (at most
    !> NORMAL_DENSE_MAX elements) from a start set of m0 elements: two Cholesky factors of
    !> about that size (m0^3 / 3 multiply-adds) against 15 CG iterations of one padded FFT
    !> product each (5 M log2 M + 10 M, M = 4 nx ny; contact_rolling's count). The 11 x 11
    !> case (m0 about 60) takes the active set; 25 x 25 (m0 about 280) keeps CG.
    pure logical function dense_is_cheaper(m0, nx, ny)
        integer, intent(in) :: m0, nx, ny
        real(dp) :: mm
        mm = 4.0_dp * nx * ny
        dense_is_cheaper = nx * ny <= NORMAL_DENSE_MAX .and. &
                           real(m0, dp)**3 / 3.0_dp <= 15.0_dp * (5.0_dp * mm * log(mm) / log(2.0_dp) + 10.0_dp * mm)
    end function dense_is_cheaper

    !> The elements of the set act as lists ic, jc (column by column), m of them.
    pure subroutine set_list(act, ic, jc, m)
        logical, intent(in) :: act(:, :)
        integer, intent(out) :: ic(:), jc(:), m
        integer :: i, j
        m = 0
        do j = 1, size(act, 2)
            do i = 1, size(act, 1)
                if (.not. act(i, j)) cycle
                m = m + 1
                ic(m) = i
                jc(m) = j
            end do
        end do
    end subroutine set_list

    !> The pressures pi on the set (ic, jc) and the approach delta from A_II pi = delta - h_I
    !> and area_el sum(pi) = fn: pi = delta y1 - y2 with A_II y1 = 1, A_II y2 = h_I.
    !> info: STAT_OK, or STAT_NOT_CONVERGED for an empty set or a non-positive pivot.
    pure subroutine solve_set(c, h, area_el, fn, ic, jc, pi, delta, info)
        real(dp), intent(in) :: c(0:, 0:), h(:, :), area_el, fn
        integer, intent(in) :: ic(:), jc(:)
        real(dp), intent(out) :: pi(:), delta
        integer, intent(out) :: info
        real(dp), allocatable :: a(:, :), y(:, :)
        integer :: m, l
        m = size(ic)
        delta = 0.0_dp
        pi = 0.0_dp
        info = STAT_NOT_CONVERGED
        if (m < 1) return
        allocate (a(m, m), y(m, 2))
        call gather_set(c, ic, jc, a)
        do l = 1, m
            y(l, 1) = 1.0_dp
            y(l, 2) = h(ic(l), jc(l))
        end do
        call cholesky_solve(a, y, info)
        if (info /= STAT_OK) return
        delta = (fn / area_el + sum(y(:, 2))) / sum(y(:, 1))
        pi = delta * y(:, 1) - y(:, 2)
    end subroutine solve_set

    !> solve_set with the factor of the set kept in cache: made (and kept) when the set is
    !> not the cached one, else only A_II y2 = h_I solved with it (y1 kept too). The same
    !> operations on the same numbers as solve_set: the same bits.
    pure subroutine solve_set_cached(c, h, area_el, fn, ic, jc, pi, delta, info, cache)
        real(dp), intent(in) :: c(0:, 0:), h(:, :), area_el, fn
        integer, intent(in) :: ic(:), jc(:)
        real(dp), intent(out) :: pi(:), delta
        integer, intent(out) :: info
        type(normal_dense_cache), intent(inout) :: cache
        real(dp), allocatable :: y(:, :)
        integer :: m, l
        logical :: same
        m = size(ic)
        delta = 0.0_dp
        pi = 0.0_dp
        info = STAT_NOT_CONVERGED
        if (m < 1) return
        same = cache%m == m
        if (same) same = all(cache%ic(1:m) == ic) .and. all(cache%jc(1:m) == jc)
        allocate (y(m, 2))
        do l = 1, m
            y(l, 1) = 1.0_dp
            y(l, 2) = h(ic(l), jc(l))
        end do
        if (same) then
            y(:, 1) = cache%y1(1:m)
            call cholesky_apply(cache%l(1:m, 1:m), y(:, 2:2))
        else
            cache%m = 0
            if (allocated(cache%l)) then
                if (size(cache%l, 1) < m) deallocate (cache%l, cache%ic, cache%jc, cache%y1)
            end if
            if (.not. allocated(cache%l)) allocate (cache%l(m, m), cache%ic(m), cache%jc(m), cache%y1(m))
            call gather_set(c, ic, jc, cache%l(1:m, 1:m))
            call cholesky_factor(cache%l(1:m, 1:m), info)
            if (info /= STAT_OK) return
            call cholesky_apply(cache%l(1:m, 1:m), y)
            cache%m = m
            cache%ic(1:m) = ic
            cache%jc(1:m) = jc
            cache%y1(1:m) = y(:, 1)
        end if
        info = STAT_OK
        delta = (fn / area_el + sum(y(:, 2))) / sum(y(:, 1))
        pi = delta * y(:, 1) - y(:, 2)
    end subroutine solve_set_cached

    !> The lower triangle of A_II for the set (ic, jc) from c's circular layout.
    pure subroutine gather_set(c, ic, jc, a)
        real(dp), intent(in) :: c(0:, 0:)
        integer, intent(in) :: ic(:), jc(:)
        real(dp), intent(out) :: a(:, :)
        integer :: m, k, l, nx2, ny2, di, dj
        m = size(ic)
        nx2 = size(c, 1)
        ny2 = size(c, 2)
        do l = 1, m
            do k = l, m
                di = ic(k) - ic(l)      ! modulo(., nx2) without a division
                if (di < 0) di = di + nx2
                dj = jc(k) - jc(l)
                if (dj < 0) dj = dj + ny2
                a(k, l) = c(di, dj)
            end do
        end do
    end subroutine gather_set

    !> a y = b for the two columns of y in place, a symmetric positive definite (its lower
    !> triangle given; overwritten by the Cholesky factor L, right-looking: column updates).
    !> info: STAT_OK or STAT_NOT_CONVERGED (a non-positive pivot).
    pure subroutine cholesky_solve(a, y, info)
        real(dp), intent(inout) :: a(:, :), y(:, :)
        integer, intent(out) :: info
        call cholesky_factor(a, info)
        if (info /= STAT_OK) return
        call cholesky_apply(a, y)
    end subroutine cholesky_solve

    !> The Cholesky factor L of a (symmetric positive definite, its lower triangle given)
    !> in place, right-looking (column updates). info: STAT_OK or STAT_NOT_CONVERGED (a
    !> non-positive pivot).
    pure subroutine cholesky_factor(a, info)
        real(dp), intent(inout) :: a(:, :)
        integer, intent(out) :: info
        integer :: m, k, j
        m = size(a, 1)
        info = STAT_NOT_CONVERGED
        do k = 1, m
            if (.not. (a(k, k) > 0.0_dp)) return
            a(k, k) = sqrt(a(k, k))
            a(k + 1:m, k) = a(k + 1:m, k) / a(k, k)
            do j = k + 1, m
                a(j:m, j) = a(j:m, j) - a(j:m, k) * a(j, k)
            end do
        end do
        info = STAT_OK
    end subroutine cholesky_factor

    !> L L^T x = y for the columns of y in place, L from cholesky_factor: L z = y (forward,
    !> by columns), then L^T x = z (backward, by rows of L^T); each column on its own.
    pure subroutine cholesky_apply(a, y)
        real(dp), intent(in) :: a(:, :)
        real(dp), intent(inout) :: y(:, :)
        integer :: m, k, c
        m = size(a, 1)
        do k = 1, m
            y(k, :) = y(k, :) / a(k, k)
            do c = 1, size(y, 2)
                y(k + 1:m, c) = y(k + 1:m, c) - a(k + 1:m, k) * y(k, c)
            end do
        end do
        do k = m, 1, -1
            do c = 1, size(y, 2)
                y(k, c) = (y(k, c) - dot_product(a(k + 1:m, k), y(k + 1:m, c))) / a(k, k)
            end do
        end do
    end subroutine cholesky_apply

    !> The elements of the set with p <= 0 taken out of act.
    pure subroutine drop_nonpositive(act, ic, jc, pi)
        logical, intent(inout) :: act(:, :)
        integer, intent(in) :: ic(:), jc(:)
        real(dp), intent(in) :: pi(:)
        integer :: k
        do k = 1, size(ic)
            if (pi(k) <= 0.0_dp) act(ic(k), jc(k)) = .false.
        end do
    end subroutine drop_nonpositive

    !> p(ic(k), jc(k)) = pi(k).
    pure subroutine scatter(ic, jc, pi, p)
        integer, intent(in) :: ic(:), jc(:)
        real(dp), intent(in) :: pi(:)
        real(dp), intent(inout) :: p(:, :)
        integer :: k
        do k = 1, size(ic)
            p(ic(k), jc(k)) = pi(k)
        end do
    end subroutine scatter

    !> u = A p on the whole grid for the pressures pi on the set (ic, jc), by columns of A
    !> (the offsets i - ic below zero wrap to the top of c's circular layout).
    pure subroutine apply_set(c, ic, jc, pi, u)
        real(dp), intent(in) :: c(0:, 0:)
        integer, intent(in) :: ic(:), jc(:)
        real(dp), intent(in) :: pi(:)
        real(dp), intent(out) :: u(:, :)
        integer :: k, j, nx, ny, nx2, ny2, dj, ii
        nx = size(u, 1)
        ny = size(u, 2)
        nx2 = size(c, 1)
        ny2 = size(c, 2)
        u = 0.0_dp
        do k = 1, size(ic)
            ii = ic(k)
            do j = 1, ny
                dj = j - jc(k)
                if (dj < 0) dj = dj + ny2
                u(ii:nx, j) = u(ii:nx, j) + c(0:nx - ii, dj) * pi(k)
                u(1:ii - 1, j) = u(1:ii - 1, j) + c(nx2 - ii + 1:nx2 - 1, dj) * pi(k)
            end do
        end do
    end subroutine apply_set

end module contact_normal_dense
