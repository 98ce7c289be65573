!> The ring track's rows under the moving wheels (model RF): the rail-head motion of the kept
!> ring modes at each wheel's contact point x_c = x0 + v0 t (mod the ring length), refreshed
!> once per time step. Implements Kaiser sect. 3 (the moving contact on the ring with
!> neglected curvature): the observation rows of the modal form at x_c (track_ring's basis
!> functions, the same sums as track_ring%ring_eval_x restricted to the kept modes, with one
!> sine and cosine per wave number k: kap = 2 pi k / length).
!>
!> Kept modes of group g: their eigenvector entries over the group's rail basis functions,
!> vk(voff(g) + 1 : voff(g) + nb_g * nk_g), column-major (nb_g x nk_g). A contact point c on
!> rail crho(c) gets psi(1:4, r) = sum_b obs(:, b) trig(fam_b, :, kap_b x) V(b, r) (rail-local
!> x, eta, zeta, roll) and its rows ctr(:, :, c) psi (the cant, the mirror between the ring's
!> y and the vehicle's, and the map onto the pose of a track element under that wheel).
!> The sum is folded once per wave number (ring_rows_fold): a group's basis functions of one
!> rail share few wave numbers (9 for ~126 functions: the cross-section's degrees of freedom),
!> so psi = sum_k [sin(k th) S_k + cos(k th) C_k] with S_k, C_k (4 x nk_g) summed at creation.
!> Work per point: 8 sum_g nw_g nk_g for nw_g wave numbers (was 4 nb_g nk_g per rail half),
!> linear in the kept modes; nothing over all modes.
module vehicle_ring
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_SIZE_MISMATCH
    implicit none
    private
    public :: ring_rows, ring_rows_create, ring_rows_eval, ring_residual_set, ring_residual_eval

    !> The kept modes' data and the contact points (nc = 2 per wheelset: left, right).
    type :: ring_rows
        integer :: ng = 0, nk = 0, nc = 0, kmax = 0         !< kmax: the largest wave number
        integer, allocatable :: kpos(:)                     !< (ng + 1) the groups' kept modes
        integer, allocatable :: crho(:)                     !< (nc) rail 1 or 2
        real(dp), allocatable :: cx0(:), ctr(:, :, :)       !< (nc), (3, 4, nc)
        real(dp) :: v0 = 0.0_dp, length = 0.0_dp
        !> Residual flexibility of the truncated modes at a contact point (ring_residual_set):
        !> the compliance R (3 x 3, over the point's three components) at nrx positions over
        !> one sleeper bay of length bay, per rail (3, 3, nrx, 2); nrx = 0: none. The residual
        !> coordinates' rows are L(x) P with L L^T = R(x) and P (3, 3, 2 rails) a constant
        !> change of coordinates (identity, or the unit-mass coordinates of a residual with
        !> inertia: docs/vehicle.md "Residual inertia of the ring").
        integer :: nrx = 0
        real(dp) :: bay = 0.0_dp
        real(dp), allocatable :: rtab(:, :, :, :), rpost(:, :, :)
        !> The sums folded per wave number (ring_rows_fold): slot s = 2 (g - 1) + rail holds the
        !> wave numbers wk(wpos(s) + 1 : wpos(s + 1)); entry j's S_k and C_k are the columns
        !> wcoef(:, coff(j) + 1 : coff(j) + nk_g) and the next nk_g.
        integer, allocatable :: wpos(:), wk(:), coff(:)
        real(dp), allocatable :: wcoef(:, :)
    end type ring_rows

    !> The basis functions as ring_rows_create receives them, for the fold only: group
    !> offsets bpos, voff (ng + 1), rail 1's count per group n1 (ng), family, wave number
    !> (kap = 2 pi kn / length) and observation (4) per function (nbt), and the kept modes'
    !> eigenvector entries vk, packed per group (nb_g x nk_g, column-major).
    type :: ring_basis
        integer, allocatable :: bpos(:), voff(:), n1(:), fam(:), kn(:)
        real(dp), allocatable :: obs(:, :), vk(:)
    end type ring_basis

contains

    !> Store the ring rows. info: STAT_OK; STAT_SIZE_MISMATCH (bpos, kpos, voff not starting at
    !> 0 and non-decreasing to nbt, nk, nvk; a group with kept modes and no basis function);
    !> STAT_BAD_ARGUMENT (nk, nc < 1, a rail not 1 or 2, a group's basis functions not those of
    !> rail 1 first, length <= 0, non-finite entries).
    subroutine ring_rows_create(ng, nbt, nk, nvk, nc, bpos, kpos, voff, kap, fam, rail, obs, vk, &
                                crho, cx0, ctr, v0, length, rr, info)
        integer, intent(in) :: ng, nbt, nk, nvk, nc
        integer, intent(in) :: bpos(ng + 1), kpos(ng + 1), voff(ng + 1), fam(nbt), rail(nbt), crho(nc)
        real(dp), intent(in) :: kap(nbt), obs(4, nbt), vk(nvk), cx0(nc), ctr(3, 4, nc), v0, length
        type(ring_rows), intent(out) :: rr
        integer, intent(out) :: info
        type(ring_basis) :: rb
        integer :: g
        info = STAT_BAD_ARGUMENT
        if (ng < 1 .or. nk < 1 .or. nc < 1 .or. .not. (length > 0.0_dp)) return
        if (any(rail < 1) .or. any(rail > 2) .or. any(crho < 1) .or. any(crho > 2)) return
        if (any(fam < 0) .or. any(fam > 2) .or. any(kap < 0.0_dp)) return
        if (.not. (all(abs(kap) <= huge(1.0_dp)) .and. all(abs(obs) <= huge(1.0_dp)) .and. &
                   all(abs(vk) <= huge(1.0_dp)) .and. all(abs(cx0) <= huge(1.0_dp)) .and. &
                   all(abs(ctr) <= huge(1.0_dp)) .and. abs(v0) <= huge(1.0_dp))) return
        info = STAT_SIZE_MISMATCH
        if (bpos(1) /= 0 .or. kpos(1) /= 0 .or. voff(1) /= 0) return
        if (bpos(ng + 1) /= nbt .or. kpos(ng + 1) /= nk .or. voff(ng + 1) /= nvk) return
        do g = 1, ng
            if (bpos(g + 1) < bpos(g) .or. kpos(g + 1) < kpos(g)) return
            if (voff(g + 1) - voff(g) /= (bpos(g + 1) - bpos(g)) * (kpos(g + 1) - kpos(g))) return
        end do
        info = STAT_BAD_ARGUMENT
        allocate (rb%n1(ng))
        do g = 1, ng     ! each point needs only its rail's half of a group
            rb%n1(g) = count(rail(bpos(g) + 1:bpos(g + 1)) == 1)
            if (any(rail(bpos(g) + 1:bpos(g) + rb%n1(g)) /= 1)) return
        end do
        rb%bpos = bpos
        rb%voff = voff
        rb%fam = fam
        rb%kn = nint(kap * length / (8.0_dp * atan(1.0_dp)))
        rb%obs = obs
        rb%vk = vk
        rr%ng = ng
        rr%nk = nk
        rr%nc = nc
        rr%kpos = kpos
        rr%crho = crho
        rr%cx0 = cx0
        rr%ctr = ctr
        rr%v0 = v0
        rr%length = length
        call ring_rows_fold(rb, rr)
        info = STAT_OK
    end subroutine ring_rows_create

    !> Fold each group's basis functions of each rail per wave number k: S_k and C_k, the
    !> coefficients of sin(k th) and cos(k th) in psi (ring_rows_eval; fam 1: sin for u_x, cos
    !> for the others; fam 2: -cos for u_x, sin for the others; fam 0, k = 0: constant).
    subroutine ring_rows_fold(rb, rr)
        type(ring_basis), intent(in) :: rb
        type(ring_rows), intent(inout) :: rr
        integer :: g, rho, b, bl, nb, nk, i0, i1, j, s, nw, ncol, kk
        integer, allocatable :: seen(:)
        real(dp), allocatable :: vrow(:)
        allocate (seen(0:maxval(rb%kn)), rr%wpos(2 * rr%ng + 1))
        ! the wave numbers of each slot, and the columns they need
        rr%wpos(1) = 0
        nw = 0
        ncol = 0
        do g = 1, rr%ng
            nk = rr%kpos(g + 1) - rr%kpos(g)
            do rho = 1, 2
                call half_range(rb, g, rho, i0, i1)
                seen = 0
                do b = rb%bpos(g) + i0, rb%bpos(g) + i1
                    seen(wave_of(rb, b)) = 1
                end do
                nw = nw + sum(seen)
                ncol = ncol + 2 * nk * sum(seen)
                rr%wpos(2 * (g - 1) + rho + 1) = nw
            end do
        end do
        allocate (rr%wk(nw), rr%coff(nw), rr%wcoef(4, ncol))
        rr%wcoef = 0.0_dp
        j = 0
        ncol = 0
        do g = 1, rr%ng
            nb = rb%bpos(g + 1) - rb%bpos(g)
            nk = rr%kpos(g + 1) - rr%kpos(g)
            allocate (vrow(nk))
            do rho = 1, 2
                call half_range(rb, g, rho, i0, i1)
                seen = 0
                do b = rb%bpos(g) + i0, rb%bpos(g) + i1
                    kk = wave_of(rb, b)
                    if (seen(kk) == 0) then     ! a new wave number: its columns
                        j = j + 1
                        seen(kk) = j
                        rr%wk(j) = kk
                        rr%coff(j) = ncol
                        ncol = ncol + 2 * nk
                    end if
                    s = rr%coff(seen(kk))
                    bl = b - rb%bpos(g)
                    vrow = rb%vk(rb%voff(g) + bl:rb%voff(g) + nb * nk:nb)   ! V(bl, :)
                    select case (rb%fam(b))
                    case (1)
                        call add_outer(rr%wcoef(1:1, s + 1:s + nk), rb%obs(1:1, b), vrow)
                        call add_outer(rr%wcoef(2:4, s + nk + 1:s + 2 * nk), rb%obs(2:4, b), vrow)
                    case (2)
                        call add_outer(rr%wcoef(1:1, s + nk + 1:s + 2 * nk), -rb%obs(1:1, b), vrow)
                        call add_outer(rr%wcoef(2:4, s + 1:s + nk), rb%obs(2:4, b), vrow)
                    case default
                        call add_outer(rr%wcoef(:, s + nk + 1:s + 2 * nk), rb%obs(:, b), vrow)
                    end select
                end do
            end do
            deallocate (vrow)
        end do
        rr%kmax = maxval(rr%wk)
    end subroutine ring_rows_fold

    !> The wave number whose sine and cosine multiply basis function b (0: a constant).
    pure integer function wave_of(rb, b) result(kk)
        type(ring_basis), intent(in) :: rb
        integer, intent(in) :: b
        kk = merge(0, rb%kn(b), rb%fam(b) == 0)
    end function wave_of

    !> a <- a + x y^T.
    pure subroutine add_outer(a, x, y)
        real(dp), intent(inout) :: a(:, :)
        real(dp), intent(in) :: x(:), y(:)
        integer :: k
        do k = 1, size(y)
            a(:, k) = a(:, k) + x * y(k)
        end do
    end subroutine add_outer

    !> The group-local range i0..i1 of group g's basis functions on rail rho (rail 1's first).
    pure subroutine half_range(rb, g, rho, i0, i1)
        type(ring_basis), intent(in) :: rb
        integer, intent(in) :: g, rho
        integer, intent(out) :: i0, i1
        if (rho == 1) then
            i0 = 1
            i1 = rb%n1(g)
        else
            i0 = rb%n1(g) + 1
            i1 = rb%bpos(g + 1) - rb%bpos(g)
        end if
    end subroutine half_range

    !> The rows of every contact point at time t: rows(i, c, r), i = 1..3 the point's three
    !> components (ctr), r = 1..nk the kept modes.
    pure subroutine ring_rows_eval(rr, t, rows)
        type(ring_rows), intent(in) :: rr
        real(dp), intent(in) :: t
        real(dp), intent(out) :: rows(3, rr%nc, rr%nk)
        real(dp) :: psi(4, rr%nk), x, th, s1, c1
        real(dp) :: sn(0:rr%kmax), cs(0:rr%kmax)
        integer :: c, g, j, k0, nk, s, o, kk
        do c = 1, rr%nc
            x = modulo(rr%cx0(c) + rr%v0 * t, rr%length)
            ! the trig factors of track_ring%trig_at, one sin and cos per wave number, by the
            ! angle-addition recurrence from sin(th), cos(th) (2 sines for kmax + 1 = 191 wave
            ! numbers at n_sl 40: was 5 % of FF's step; drift ~kmax eps, ~2e-14)
            th = 8.0_dp * atan(1.0_dp) * x / rr%length
            s1 = sin(th)
            c1 = cos(th)
            sn(0) = 0.0_dp
            cs(0) = 1.0_dp
            do kk = 1, rr%kmax
                sn(kk) = sn(kk - 1) * c1 + cs(kk - 1) * s1
                cs(kk) = cs(kk - 1) * c1 - sn(kk - 1) * s1
            end do
            psi = 0.0_dp
            do g = 1, rr%ng
                k0 = rr%kpos(g)
                nk = rr%kpos(g + 1) - k0
                s = 2 * (g - 1) + rr%crho(c)
                do j = rr%wpos(s) + 1, rr%wpos(s + 1)
                    o = rr%coff(j)
                    kk = rr%wk(j)
                    psi(:, k0 + 1:k0 + nk) = psi(:, k0 + 1:k0 + nk) + sn(kk) * rr%wcoef(:, o + 1:o + nk) &
                                             + cs(kk) * rr%wcoef(:, o + nk + 1:o + 2 * nk)
                end do
            end do
            rows(:, c, :) = matmul(rr%ctr(:, :, c), psi)
        end do
    end subroutine ring_rows_eval

    !> Set the residual compliance table (after ring_rows_create). info: STAT_OK;
    !> STAT_BAD_ARGUMENT (nrx < 2, bay <= 0, non-finite entries).
    subroutine ring_residual_set(rr, nrx, bay, rtab, rpost, info)
        type(ring_rows), intent(inout) :: rr
        integer, intent(in) :: nrx
        real(dp), intent(in) :: bay, rtab(3, 3, nrx, 2), rpost(3, 3, 2)
        integer, intent(out) :: info
        info = STAT_BAD_ARGUMENT
        if (nrx < 2 .or. .not. (bay > 0.0_dp) .or. .not. all(abs(rtab) <= huge(1.0_dp))) return
        if (.not. all(abs(rpost) <= huge(1.0_dp))) return
        rr%nrx = nrx
        rr%bay = bay
        rr%rtab = rtab
        rr%rpost = rpost
        info = STAT_OK
    end subroutine ring_residual_set

    !> The residual rows of every contact point at time t: L P with L (3 x 3, lower) the
    !> Cholesky factor of R(x_c), R interpolated linearly (periodic over the bay) in the table,
    !> and P the rail's rpost. A coordinate z with stiffness P^T P and rows L P is the
    !> point compliance u = R g (vehicle_modal, massless).
    pure subroutine ring_residual_eval(rr, t, lres)
        type(ring_rows), intent(in) :: rr
        real(dp), intent(in) :: t
        real(dp), intent(out) :: lres(3, 3, rr%nc)
        real(dp) :: x, s, w, r(3, 3), l(3, 3)
        integer :: c, i0, i1, rho
        do c = 1, rr%nc
            x = modulo(rr%cx0(c) + rr%v0 * t, rr%length)
            s = modulo(x, rr%bay) / rr%bay * rr%nrx
            i0 = min(int(s), rr%nrx - 1)
            w = s - i0
            i1 = mod(i0 + 1, rr%nrx)
            rho = rr%crho(c)
            r = (1.0_dp - w) * rr%rtab(:, :, i0 + 1, rho) + w * rr%rtab(:, :, i1 + 1, rho)
            call chol3(r, l)
            lres(:, :, c) = matmul(l, rr%rpost(:, :, rho))
        end do
    end subroutine ring_residual_eval

    !> Cholesky factor of a symmetric 3 x 3 matrix (non-positive pivots give zero columns: a
    !> compliance with no stiffness behind it is dropped rather than made imaginary).
    pure subroutine chol3(a, l)
        real(dp), intent(in) :: a(3, 3)
        real(dp), intent(out) :: l(3, 3)
        real(dp) :: d
        integer :: j, i
        l = 0.0_dp
        do j = 1, 3
            d = a(j, j) - sum(l(j, 1:j - 1)**2)
            if (.not. (d > 0.0_dp)) cycle
            l(j, j) = sqrt(d)
            do i = j + 1, 3
                l(i, j) = (a(i, j) - sum(l(i, 1:j - 1) * l(j, 1:j - 1))) / l(j, j)
            end do
        end do
    end subroutine chol3

end module vehicle_ring
