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
!> y and the vehicle's, and the map onto the pose of a track element under that wheel). Work
!> per point: 4 sum_g nb_g (nk_g + 1), linear in the kept modes; nothing over all modes.
module vehicle_ring
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_SIZE_MISMATCH
    implicit none
    private
    public :: ring_rows, ring_rows_create, ring_rows_eval, ring_residual_set, ring_residual_eval

    !> The kept modes' data and the contact points (nc = 2 per wheelset: left, right).
    type :: ring_rows
        integer :: ng = 0, nbt = 0, nk = 0, nc = 0
        integer, allocatable :: bpos(:), kpos(:), voff(:)   !< (ng + 1)
        integer, allocatable :: n1(:)                       !< (ng) rail-1 functions first
        integer, allocatable :: fam(:), rail(:), kn(:)      !< (nbt); kn: kap = 2 pi kn / length
        real(dp), allocatable :: kap(:), obs(:, :), vk(:)   !< (nbt), (4, nbt), packed
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
    end type ring_rows

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
        allocate (rr%n1(ng))
        do g = 1, ng     ! each point needs only its rail's half of a group
            rr%n1(g) = count(rail(bpos(g) + 1:bpos(g + 1)) == 1)
            if (any(rail(bpos(g) + 1:bpos(g) + rr%n1(g)) /= 1)) return
        end do
        rr%ng = ng
        rr%nbt = nbt
        rr%nk = nk
        rr%nc = nc
        rr%bpos = bpos
        rr%kpos = kpos
        rr%voff = voff
        rr%fam = fam
        rr%rail = rail
        rr%kap = kap
        rr%kn = nint(kap * length / (8.0_dp * atan(1.0_dp)))
        rr%obs = obs
        rr%vk = vk
        rr%crho = crho
        rr%cx0 = cx0
        rr%ctr = ctr
        rr%v0 = v0
        rr%length = length
        info = STAT_OK
    end subroutine ring_rows_create

    !> The rows of every contact point at time t: rows(i, c, r), i = 1..3 the point's three
    !> components (ctr), r = 1..nk the kept modes.
    pure subroutine ring_rows_eval(rr, t, rows)
        type(ring_rows), intent(in) :: rr
        real(dp), intent(in) :: t
        real(dp), intent(out) :: rows(3, rr%nc, rr%nk)
        real(dp) :: psi(4, rr%nk), tb(4, rr%nbt), x, th
        real(dp), allocatable :: sn(:), cs(:)
        integer :: c, g, b, nb, nk, kk, i0, i1
        allocate (sn(0:maxval(rr%kn)), cs(0:maxval(rr%kn)))
        do c = 1, rr%nc
            x = modulo(rr%cx0(c) + rr%v0 * t, rr%length)
            ! the trig factors of track_ring%trig_at, one sin and cos per wave number
            th = 8.0_dp * atan(1.0_dp) * x / rr%length
            do kk = 0, ubound(sn, 1)
                sn(kk) = sin(kk * th)
                cs(kk) = cos(kk * th)
            end do
            do g = 1, rr%ng
                nb = rr%bpos(g + 1) - rr%bpos(g)
                nk = rr%kpos(g + 1) - rr%kpos(g)
                if (rr%crho(c) == 1) then
                    i0 = 1
                    i1 = rr%n1(g)
                else
                    i0 = rr%n1(g) + 1
                    i1 = nb
                end if
                do b = rr%bpos(g) + i0, rr%bpos(g) + i1
                    kk = rr%kn(b)
                    if (rr%fam(b) == 1) then             ! sin for u_x, cos for the others
                        tb(1, b) = rr%obs(1, b) * sn(kk)
                        tb(2:4, b) = rr%obs(2:4, b) * cs(kk)
                    else if (rr%fam(b) == 2) then        ! -cos for u_x, sin for the others
                        tb(1, b) = -rr%obs(1, b) * cs(kk)
                        tb(2:4, b) = rr%obs(2:4, b) * sn(kk)
                    else                                 ! k = 0: constant
                        tb(:, b) = rr%obs(:, b)
                    end if
                end do
                call group_rows(nb, nk, i0, i1, tb(:, rr%bpos(g) + 1:rr%bpos(g + 1)), &
                                rr%vk(rr%voff(g) + 1:rr%voff(g + 1)), psi(:, rr%kpos(g) + 1:rr%kpos(g + 1)))
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

    !> One group's kept modes at a point on the rail of basis functions i0..i1:
    !> psi = tb(:, i0:i1) V(i0:i1, :).
    pure subroutine group_rows(nb, nk, i0, i1, tb, v, psi)
        integer, intent(in) :: nb, nk, i0, i1
        real(dp), intent(in) :: tb(4, nb), v(nb, nk)
        real(dp), intent(out) :: psi(4, nk)
        psi = matmul(tb(:, i0:i1), v(i0:i1, :))
    end subroutine group_rows

end module vehicle_ring
