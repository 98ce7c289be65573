!> Modal blocks: flexible bodies in the time integration as modal coordinates coupled to the
!> rest of the model only through attachment points (docs/vehicle_integrator.md).
!> Implements no Kaiser equation: the storage and the condensation of the modal part of the
!> step matrix onto the points (a Schur complement; see vehicle_newmark for its use).
!>
!> nm modal coordinates Q (mass-normalised: M = I) obey
!>   Q'' + B Q' + K_m Q = Phi^T g_p(q, v, u, u'),    u = Phi Q   (np attachment points)
!> with B (damping + gyroscopic) and K_m constant and block-diagonal in nb small dense blocks,
!> stored packed: block b covers modes bs(b) .. bs(b+1) - 1, its s x s entries (column-major)
!> at bb / kb(off(b) + 1 : off(b) + s*s). Phi (np x nm) is dense over the points only. Nothing
!> of size nm x nm is ever formed: memory and work are linear in nm for a fixed np.
!>
!> Point elements join a rigid DOF r (0: the ground) and a point p: d = u_p - q_r,
!> dd = u'_p - v_r; the force f(d, dd) acts as +f on q_r and -f on u_p (so -Phi_p^T f on Q).
!>   PEL_LINEAR: f = p1 d + p2 dd + p3                 (spring, damper, preload)
!>   PEL_HERTZ:  f = p1 max(d - p2, 0)^1.5 + p3 dd [d > p2]   (one-sided Hertz-like contact)
!>
!> Hook for rows that are not constant (moving loads on a ring track, contact-point-dependent
!> shape rows): whoever changes phi must increase rows_version; modal_factor then rebuilds the
!> condensed flexibility C = Phi S^-1 Phi^T. A Phi that depends on q also adds the chain-rule
!> term (dPhi/dq Q) to the point tangent: not needed (nor done) for constant rows.
!>
!> Massless coordinates (modal_set_mass, mass(j) = 0): Q_j'' drops out of its equation, which
!> becomes the algebraic K_m Q = Phi^T g_p (with B = 0). A block of them with K_m =
!> diag(1/lambda) and rows Phi_r = V (R = V diag(lambda) V^T) is a point compliance: Phi_r Q_r =
!> R g_p, the residual flexibility of truncated modes (static correction); in the condensed
!> step matrix it adds R / ck to C (docs/vehicle_integrator.md, "Residual flexibility").
module vehicle_modal
    use common_kinds, only: dp
    use common_lapack, only: dgetrf, dgetrs
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_SIZE_MISMATCH, STAT_SINGULAR
    use vehicle_ring, only: ring_rows, ring_rows_create, ring_rows_eval, ring_residual_set, &
                            ring_residual_eval
    implicit none
    private
    public :: modal_part, modal_factor, modal_create, modal_force, modal_point_tangent
    public :: modal_factorise, modal_solve, modal_points, modal_rows_t, modal_set_mass
    public :: PEL_LINEAR, PEL_HERTZ, LC_SPLIT, LC_GYRO
    public :: modal_couple, modal_coupling_force, modal_coupling_tangent, modal_rim_wheelset
    public :: modal_euler, modal_ring, modal_ring_time, modal_rail_wheelset, modal_ring_residual
    public :: modal_follow_set, modal_follow, modal_follow_reset

    integer, parameter :: PEL_LINEAR = 1
    integer, parameter :: PEL_HERTZ = 2
    !> Linear couplings of a point p with a combination g.q of rigid DOFs (modal_couple):
    !> LC_SPLIT (a spring/damper whose rigid-rigid part is already in the model's K, C, f0:
    !>   the journal springs of a flexible wheelset): g_p += k (g.q - u_p) + c (g.v - u'_p) + f0,
    !>   g_r += g (k u_p + c u'_p);
    !> LC_GYRO (a skew velocity coupling, the Coriolis terms between the rigid wheelset's
    !>   roll/yaw rates and its elastic modes): g_p += k g.v, g_r -= g k u'_p.
    integer, parameter :: LC_SPLIT = 1
    integer, parameter :: LC_GYRO = 2

    !> The constant modal part of a model (nm = 0: none; every loop below is then empty).
    type :: modal_part
        integer :: nm = 0, nb = 0, np = 0, npe = 0
        integer :: rows_version = 0                 !< increased whenever phi changes
        !> each column's nonzero rows lie in rlo(j) .. rhi(j) (rows_changed; rhi < rlo: none):
        !> a body's modes have rows only at its own points, so Phi Q and Phi^T g cost nnz
        integer, allocatable :: rlo(:), rhi(:)
        integer, allocatable :: bs(:), off(:)       !< block starts, packed offsets (nb + 1)
        real(dp), allocatable :: bb(:), kb(:)       !< packed blocks of B and K_m
        real(dp), allocatable :: phi(:, :)          !< (np, nm) attachment rows
        real(dp), allocatable :: mass(:)            !< (nm) modal masses: 1, or 0 (massless)
        integer, allocatable :: ptype(:), prig(:), ppt(:)   !< per point element
        real(dp), allocatable :: ppar(:, :)         !< (4, npe) element parameters
        !> linear couplings (LC_*): kind, point, rigid direction g (nd, nlc), (k, c, f0)
        integer :: nlc = 0
        integer, allocatable :: lkind(:), lpt(:)
        real(dp), allocatable :: lg(:, :), lpar(:, :)
        !> flexible wheel rims (model FR): wheelset index, the points of (dy, dz, drx) of each
        !> wheel (3, 2 [left, right], nfr) and the rim reference point's arms (lateral, depth)
        integer :: nfr = 0
        integer, allocatable :: frw(:), frpt(:, :, :)
        real(dp), allocatable :: frarm(:, :)
        !> Eulerian term of the rims (modal_euler): the points e whose displacement is
        !> dPhi/dtheta Q of each rim point (3, 2, nfr; 0: none) and the spin Omega (nfr):
        !> the rim material's velocity at the contact point is u'_p + Omega u_e.
        integer, allocatable :: frept(:, :, :)
        real(dp), allocatable :: fromega(:)
        !> Rows that follow the contact point along the wheel profile (modal_follow_set,
        !> Kaiser eq. 3): fsc (2, nfr) each wheel's current s (0: the taping line; the rims'
        !> lateral arm is frarm(1) + fsc). The rim rows (y, z, rx) and their d/dtheta on s = fs0
        !> + (i - 1) fds, ftab, fetab (3, fnq, fns, 2 wheels) over the modes fm0(i) + 1 ..
        !> fm0(i) + fnq of wheelset i; the residual over the 12 points fpt(:, i) (rims y, z,
        !> rx left, right; journals x, y, z left, right) on s = rs0 + (i - 1) rds: the rims'
        !> self blocks rcc (3, 3, rns, 2), left-right rcx (3, 3, rns [left], rns [right]),
        !> rim-journals rcj (3, 6, rns, 2), journals rjj (6, 6); its coordinates fr0(i) + 1 ..
        !> + 12 get the rows L fpost (L L^T = R; stiffness fpost^2 I, constant).
        integer :: fnq = 0, fns = 0, rns = 0
        real(dp) :: fs0 = 0.0_dp, fds = 1.0_dp, rs0 = 0.0_dp, rds = 1.0_dp, fpost = 1.0_dp
        integer, allocatable :: fm0(:), fr0(:), fpt(:, :)
        real(dp), allocatable :: fsc(:, :), ftab(:, :, :, :), fetab(:, :, :, :)
        real(dp), allocatable :: rcc(:, :, :, :), rcx(:, :, :, :), rcj(:, :, :, :), rjj(:, :)
        !> The ring track under the wheels (model RF, modal_ring): wheelset index and the points
        !> of the pose (y, z, roll) of a track element under each wheel (3, 2 [left, right],
        !> nrl), whose rows over the ring's modes rm0 + 1 .. rm0 + rr%nk depend on time
        !> (modal_ring_time, at x_c = x0 + v0 t); their generalised forces are the contact's.
        integer :: nrl = 0, rm0 = 0
        integer, allocatable :: rlw(:), rlpt(:, :, :)
        type(ring_rows) :: rr
    end type modal_part

    !> The factors of the modal step matrix S = cq I + ck (cb B + K_m), block by block, and the
    !> condensed flexibility C = Phi S^-1 Phi^T (np x np), valid for (cq, cb, ck, rows_version).
    type :: modal_factor
        real(dp) :: cq = -1.0_dp, cb = -1.0_dp, ck = -1.0_dp
        integer :: rows_version = -1
        logical :: given = .false.      !< S given by the caller (sx: vehicle_modal_step)
        real(dp), allocatable :: lu(:), c(:, :)
        integer, allocatable :: piv(:)
    end type modal_factor

contains

    !> Check and store a modal part for a model of nd rigid DOFs. info: STAT_OK;
    !> STAT_SIZE_MISMATCH (block starts not 1 < ... < nm + 1, packed length not the sum of
    !> the squared block sizes); STAT_BAD_ARGUMENT (nm, nb or np < 1, a non-finite matrix or
    !> parameter, an element with an unknown kind, a rigid DOF outside 0..nd or a point outside
    !> 1..np, a Hertz element with p1 < 0).
    subroutine modal_create(nd, nm, nb, np, npe, nbk, bs, bb, kb, phi, ptype, prig, ppt, ppar, &
                            mp, info)
        integer, intent(in) :: nd, nm, nb, np, npe, nbk
        integer, intent(in) :: bs(nb + 1), ptype(npe), prig(npe), ppt(npe)
        real(dp), intent(in) :: bb(nbk), kb(nbk), phi(np, nm), ppar(4, npe)
        type(modal_part), intent(out) :: mp
        integer, intent(out) :: info
        integer :: b, s, tot
        info = STAT_BAD_ARGUMENT
        if (nm < 1 .or. nb < 1 .or. np < 1 .or. npe < 0) return
        info = STAT_SIZE_MISMATCH
        if (bs(1) /= 1 .or. bs(nb + 1) /= nm + 1) return
        tot = 0
        do b = 1, nb
            s = bs(b + 1) - bs(b)
            if (s < 1) return
            tot = tot + s * s
        end do
        if (tot /= nbk) return
        info = STAT_BAD_ARGUMENT
        if (.not. (all(abs(bb) <= huge(1.0_dp)) .and. all(abs(kb) <= huge(1.0_dp)) &
                   .and. all(abs(phi) <= huge(1.0_dp)) .and. all(abs(ppar) <= huge(1.0_dp)))) return
        if (any(ptype /= PEL_LINEAR .and. ptype /= PEL_HERTZ) .or. any(prig < 0) &
            .or. any(prig > nd) .or. any(ppt < 1) .or. any(ppt > np)) return
        if (any(ptype == PEL_HERTZ .and. ppar(1, :) < 0.0_dp)) return
        mp%nm = nm
        mp%nb = nb
        mp%np = np
        mp%npe = npe
        mp%bs = bs
        allocate (mp%off(nb + 1))
        mp%off(1) = 0
        do b = 1, nb
            s = bs(b + 1) - bs(b)
            mp%off(b + 1) = mp%off(b) + s * s
        end do
        mp%bb = bb
        mp%kb = kb
        mp%phi = phi
        mp%ptype = ptype
        mp%prig = prig
        mp%ppt = ppt
        mp%ppar = ppar
        allocate (mp%mass(nm))
        mp%mass = 1.0_dp
        mp%rows_version = 0
        call rows_changed(mp)
        info = STAT_OK
    end subroutine modal_create

    !> After phi changed: a new rows_version (the cached factors are stale) and the range of
    !> nonzero rows of the columns j0..j1 that changed (default: all; the others keep theirs).
    !> Work: np per column, one product with those columns.
    pure subroutine rows_changed(mp, j0, j1)
        type(modal_part), intent(inout) :: mp
        integer, intent(in), optional :: j0, j1
        mp%rows_version = mp%rows_version + 1
        if (.not. allocated(mp%rlo)) then     ! the first time: every column
            allocate (mp%rlo(mp%nm), mp%rhi(mp%nm))
            call column_ranges(mp, 1, mp%nm)
        else if (present(j0) .and. present(j1)) then
            call column_ranges(mp, j0, j1)
        else
            call column_ranges(mp, 1, mp%nm)
        end if
    end subroutine rows_changed

    !> rlo(j), rhi(j): the first and last nonzero row of column j of phi, j = j0..j1.
    pure subroutine column_ranges(mp, j0, j1)
        type(modal_part), intent(inout) :: mp
        integer, intent(in) :: j0, j1
        integer :: j, i
        do j = j0, j1
            mp%rlo(j) = mp%np + 1
            mp%rhi(j) = 0
            do i = 1, mp%np
                if (mp%phi(i, j) /= 0.0_dp) then
                    mp%rlo(j) = i
                    exit
                end if
            end do
            do i = mp%np, mp%rlo(j), -1
                if (mp%phi(i, j) /= 0.0_dp) then
                    mp%rhi(j) = i
                    exit
                end if
            end do
        end do
    end subroutine column_ranges

    !> f(j) = Phi(:, j) . g over the modes (the generalised forces of point forces g).
    pure subroutine modal_rows_t(mp, g, f)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: g(mp%np)
        real(dp), intent(out) :: f(mp%nm)
        integer :: j
        do j = 1, mp%nm
            f(j) = dot_product(mp%phi(mp%rlo(j):mp%rhi(j), j), g(mp%rlo(j):mp%rhi(j)))
        end do
    end subroutine modal_rows_t

    !> Set the modal masses (1: a mass-normalised mode, 0: a massless coordinate, an algebraic
    !> equation). info: STAT_OK; STAT_SIZE_MISMATCH (nm not the part's); STAT_BAD_ARGUMENT
    !> (an entry other than 0 or 1).
    subroutine modal_set_mass(mp, nm, mass, info)
        type(modal_part), intent(inout) :: mp
        integer, intent(in) :: nm
        real(dp), intent(in) :: mass(nm)
        integer, intent(out) :: info
        info = STAT_SIZE_MISMATCH
        if (nm /= mp%nm .or. nm < 1) return
        info = STAT_BAD_ARGUMENT
        if (any(mass /= 0.0_dp .and. mass /= 1.0_dp)) return
        mp%mass = mass
        call rows_changed(mp)      ! the cached factors are stale
        info = STAT_OK
    end subroutine modal_set_mass

    !> Add linear couplings and flexible-rim wheelsets to a modal part (replacing any it had).
    !> info: STAT_OK; STAT_BAD_ARGUMENT (no modal part, an unknown kind, a point outside 1..np,
    !> a wheelset outside 1..nw or twice, non-finite entries, arms <= 0).
    subroutine modal_couple(mp, nd, nw, nlc, lkind, lpt, lg, lpar, nfr, frw, frpt, frarm, info)
        type(modal_part), intent(inout) :: mp
        integer, intent(in) :: nd, nw, nlc, nfr
        integer, intent(in) :: lkind(nlc), lpt(nlc), frw(nfr), frpt(3, 2, nfr)
        real(dp), intent(in) :: lg(nd, nlc), lpar(3, nlc), frarm(2, nfr)
        integer, intent(out) :: info
        integer :: i
        info = STAT_BAD_ARGUMENT
        if (mp%nm == 0 .or. nlc < 0 .or. nfr < 0) return
        if (any(lkind /= LC_SPLIT .and. lkind /= LC_GYRO) .or. any(lpt < 1) .or. any(lpt > mp%np)) return
        if (any(frw < 1) .or. any(frw > nw) .or. any(frpt < 1) .or. any(frpt > mp%np)) return
        do i = 2, nfr
            if (any(frw(1:i - 1) == frw(i))) return
        end do
        if (.not. (all(abs(lg) <= huge(1.0_dp)) .and. all(abs(lpar) <= huge(1.0_dp)) &
                   .and. all(frarm > 0.0_dp) .and. all(frarm <= huge(1.0_dp)))) return
        mp%nlc = nlc
        mp%lkind = lkind
        mp%lpt = lpt
        mp%lg = lg
        mp%lpar = lpar
        mp%nfr = nfr
        mp%frw = frw
        mp%frpt = frpt
        mp%frarm = frarm
        allocate (mp%frept(3, 2, nfr), mp%fromega(nfr), mp%fsc(2, nfr))
        mp%frept = 0
        mp%fromega = 0.0_dp
        mp%fsc = 0.0_dp
        mp%fns = 0
        info = STAT_OK
    end subroutine modal_couple

    !> Set the Eulerian term of the flexible rims (after modal_couple): the rim material's
    !> velocity at the (fixed) contact point is dW/dt + Omega dW/dtheta = u'_p + Omega u_e,
    !> with point e carrying the rows dPhi/dtheta of rim point p (ept(:, w, i), 0: no term).
    !> info: STAT_OK; STAT_SIZE_MISMATCH (nfr not the part's); STAT_BAD_ARGUMENT (a point
    !> outside 0..np, a non-finite Omega).
    subroutine modal_euler(mp, nfr, ept, omega, info)
        type(modal_part), intent(inout) :: mp
        integer, intent(in) :: nfr
        integer, intent(in) :: ept(3, 2, nfr)
        real(dp), intent(in) :: omega(nfr)
        integer, intent(out) :: info
        info = STAT_SIZE_MISMATCH
        if (nfr /= mp%nfr .or. nfr < 1) return
        info = STAT_BAD_ARGUMENT
        if (any(ept < 0) .or. any(ept > mp%np) .or. .not. all(abs(omega) <= huge(1.0_dp))) return
        mp%frept = ept
        mp%fromega = omega
        info = STAT_OK
    end subroutine modal_euler

    !> Make the rims' rows follow the contact point (after modal_couple and modal_euler): the
    !> tables of vehicle_modal's fields f* and r* (see modal_part); the rows are set at the
    !> taping line (s = 0). info: STAT_OK; STAT_SIZE_MISMATCH (nfr not the part's);
    !> STAT_BAD_ARGUMENT (fewer than 2 grid points, steps <= 0, s = 0 outside a grid, modes or
    !> points outside the part, non-finite entries).
    subroutine modal_follow_set(mp, nfr, nq, ns, s0, ds, tab, etab, nrs, rs0, rds, rcc, rcx, rcj, &
                                rjj, m0, r0, pt, post, info)
        type(modal_part), intent(inout) :: mp
        integer, intent(in) :: nfr, nq, ns, nrs, m0(nfr), r0(nfr), pt(12, nfr)
        real(dp), intent(in) :: s0, ds, tab(3, nq, ns, 2), etab(3, nq, ns, 2), rs0, rds
        real(dp), intent(in) :: rcc(3, 3, nrs, 2), rcx(3, 3, nrs, nrs), rcj(3, 6, nrs, 2), rjj(6, 6)
        real(dp), intent(in) :: post
        integer, intent(out) :: info
        info = STAT_SIZE_MISMATCH
        if (nfr /= mp%nfr .or. nfr < 1) return
        info = STAT_BAD_ARGUMENT
        if (ns < 2 .or. nrs < 2 .or. nq < 1 .or. .not. (ds > 0.0_dp .and. rds > 0.0_dp)) return
        if (s0 > 0.0_dp .or. s0 + (ns - 1) * ds < 0.0_dp) return
        if (rs0 > 0.0_dp .or. rs0 + (nrs - 1) * rds < 0.0_dp) return
        if (any(m0 < 0) .or. any(m0 + nq > mp%nm) .or. any(r0 + 12 > mp%nm)) return
        if (any(pt < 1) .or. any(pt > mp%np)) return
        if (.not. (all(abs(tab) <= huge(1.0_dp)) .and. all(abs(etab) <= huge(1.0_dp)) .and. &
                   all(abs(rcc) <= huge(1.0_dp)) .and. all(abs(rcx) <= huge(1.0_dp)) .and. &
                   all(abs(rcj) <= huge(1.0_dp)) .and. all(abs(rjj) <= huge(1.0_dp)) .and. &
                   abs(post) <= huge(1.0_dp))) return
        mp%fnq = nq
        mp%fns = ns
        mp%fs0 = s0
        mp%fds = ds
        mp%ftab = tab
        mp%fetab = etab
        mp%rns = nrs
        mp%rs0 = rs0
        mp%rds = rds
        mp%rcc = rcc
        mp%rcx = rcx
        mp%rcj = rcj
        mp%rjj = rjj
        mp%fm0 = m0
        mp%fr0 = r0
        mp%fpt = pt
        mp%fpost = post
        call modal_follow_reset(mp)
        info = STAT_OK
    end subroutine modal_follow_set

    !> Rows at the taping line (s = 0) of every wheel: what the statics, the force shims and
    !> the linear analysis see. No following rows: nothing.
    subroutine modal_follow_reset(mp)
        type(modal_part), intent(inout) :: mp
        real(dp) :: s(2, max(mp%nfr, 1))
        if (mp%nfr == 0) return
        if (mp%fns == 0) return
        s = 0.0_dp
        call modal_follow(mp, s)
    end subroutine modal_follow_reset

    !> Set the rims' rows, Eulerian rows, residual rows and arms at the contact points' s(w, i)
    !> (wheel w of flexible wheelset i, m along the wheel profile from the taping line, clipped
    !> to the tables): linear interpolation in the tables, the residual R (12 x 12) assembled
    !> from its blocks (the left-right block bilinear) and its rows L fpost, L L^T = R. The
    !> cached factors become stale (rows_version). Work per wheelset: 6 nq + 12^3 / 6.
    subroutine modal_follow(mp, s)
        type(modal_part), intent(inout) :: mp
        real(dp), intent(in) :: s(2, mp%nfr)
        real(dp) :: w(2), v(2), r(12, 12), l(12, 12), x
        integer :: i, k, j, ia(2), ib(2), c0
        if (mp%fns == 0) return
        do i = 1, mp%nfr
            c0 = mp%fm0(i)
            do k = 1, 2
                x = min(max(s(k, i), mp%fs0), mp%fs0 + (mp%fns - 1) * mp%fds)
                mp%fsc(k, i) = x
                call grid_cell(mp%fs0, mp%fds, mp%fns, x, ia(k), w(k))
                mp%phi(mp%frpt(:, k, i), c0 + 1:c0 + mp%fnq) = (1.0_dp - w(k)) * mp%ftab(:, :, ia(k), k) &
                                                              + w(k) * mp%ftab(:, :, ia(k) + 1, k)
                do j = 1, 3
                    if (mp%frept(j, k, i) > 0) mp%phi(mp%frept(j, k, i), c0 + 1:c0 + mp%fnq) = &
                        (1.0_dp - w(k)) * mp%fetab(j, :, ia(k), k) + w(k) * mp%fetab(j, :, ia(k) + 1, k)
                end do
                x = min(max(x, mp%rs0), mp%rs0 + (mp%rns - 1) * mp%rds)
                call grid_cell(mp%rs0, mp%rds, mp%rns, x, ib(k), v(k))
            end do
            if (mp%fr0(i) < 0) cycle
            r = 0.0_dp
            do k = 1, 2
                r(3 * k - 2:3 * k, 3 * k - 2:3 * k) = (1.0_dp - v(k)) * mp%rcc(:, :, ib(k), k) &
                                                      + v(k) * mp%rcc(:, :, ib(k) + 1, k)
                r(3 * k - 2:3 * k, 7:12) = (1.0_dp - v(k)) * mp%rcj(:, :, ib(k), k) &
                                           + v(k) * mp%rcj(:, :, ib(k) + 1, k)
                r(7:12, 3 * k - 2:3 * k) = transpose(r(3 * k - 2:3 * k, 7:12))
            end do
            r(1:3, 4:6) = (1.0_dp - v(1)) * ((1.0_dp - v(2)) * mp%rcx(:, :, ib(1), ib(2)) &
                                             + v(2) * mp%rcx(:, :, ib(1), ib(2) + 1)) &
                          + v(1) * ((1.0_dp - v(2)) * mp%rcx(:, :, ib(1) + 1, ib(2)) &
                                    + v(2) * mp%rcx(:, :, ib(1) + 1, ib(2) + 1))
            r(4:6, 1:3) = transpose(r(1:3, 4:6))
            r(7:12, 7:12) = mp%rjj
            call cholesky(12, r, l)
            mp%phi(mp%fpt(:, i), mp%fr0(i) + 1:mp%fr0(i) + 12) = mp%fpost * l
        end do
        call rows_changed(mp)
    end subroutine modal_follow

    !> The cell i (1-based, 1..n - 1) of x on the grid x0 + (i - 1) dx and the weight w of
    !> node i + 1 (x inside the grid).
    pure subroutine grid_cell(x0, dx, n, x, i, w)
        real(dp), intent(in) :: x0, dx, x
        integer, intent(in) :: n
        integer, intent(out) :: i
        real(dp), intent(out) :: w
        real(dp) :: t
        t = (x - x0) / dx
        i = min(max(int(t), 0), n - 2) + 1
        w = min(max(t - real(i - 1, dp), 0.0_dp), 1.0_dp)
    end subroutine grid_cell

    !> Cholesky factor L (lower) of a symmetric n x n matrix; a non-positive pivot gives a zero
    !> column (a compliance with no stiffness behind it is dropped, as vehicle_ring's chol3).
    pure subroutine cholesky(n, a, l)
        integer, intent(in) :: n
        real(dp), intent(in) :: a(n, n)
        real(dp), intent(out) :: l(n, n)
        real(dp) :: d
        integer :: i, j
        l = 0.0_dp
        do j = 1, n
            d = a(j, j) - sum(l(j, 1:j - 1)**2)
            if (.not. (d > 1.0e-14_dp * abs(a(j, j)))) cycle
            l(j, j) = sqrt(d)
            do i = j + 1, n
                l(i, j) = (a(i, j) - sum(l(i, 1:j - 1) * l(j, 1:j - 1))) / l(j, j)
            end do
        end do
    end subroutine cholesky

    !> Put wheelsets on the ring track (after modal_create): wheelset rlw(i) has the points
    !> rlpt(:, k, i) (y, z, roll of a track element under wheel k), rows over the modes rm0 + 1
    !> .. rm0 + nk evaluated by vehicle_ring (contact point c = 2 (i - 1) + k); the rows are
    !> set at t = 0. info: STAT_OK; STAT_BAD_ARGUMENT (no modal part, a wheelset outside 1..nw
    !> or twice, a point outside 1..np, ring modes outside 1..nm, nc not 2 nrl) or from
    !> vehicle_ring%ring_rows_create.
    subroutine modal_ring(mp, nw, nrl, rlw, rlpt, rm0, ng, nbt, nk, nvk, bpos, kpos, voff, kap, &
                          fam, rail, obs, vk, crho, cx0, ctr, v0, length, info)
        type(modal_part), intent(inout) :: mp
        integer, intent(in) :: nw, nrl, rm0, ng, nbt, nk, nvk
        integer, intent(in) :: rlw(nrl), rlpt(3, 2, nrl), bpos(ng + 1), kpos(ng + 1), voff(ng + 1)
        integer, intent(in) :: fam(nbt), rail(nbt), crho(2 * nrl)
        real(dp), intent(in) :: kap(nbt), obs(4, nbt), vk(nvk), cx0(2 * nrl), ctr(3, 4, 2 * nrl)
        real(dp), intent(in) :: v0, length
        integer, intent(out) :: info
        integer :: i
        info = STAT_BAD_ARGUMENT
        if (mp%nm == 0 .or. nrl < 1) return
        if (any(rlw < 1) .or. any(rlw > nw) .or. any(rlpt < 1) .or. any(rlpt > mp%np)) return
        if (rm0 < 0 .or. rm0 + nk > mp%nm) return
        do i = 2, nrl
            if (any(rlw(1:i - 1) == rlw(i))) return
        end do
        call ring_rows_create(ng, nbt, nk, nvk, 2 * nrl, bpos, kpos, voff, kap, fam, rail, obs, vk, &
                              crho, cx0, ctr, v0, length, mp%rr, info)
        if (info /= STAT_OK) return
        mp%nrl = nrl
        mp%rlw = rlw
        mp%rlpt = rlpt
        mp%rm0 = rm0
        call modal_ring_time(mp, 0.0_dp)
    end subroutine modal_ring

    !> Add the truncated ring modes' residual flexibility at the contact points (after
    !> modal_ring): the coordinates rm0 + nk + 3 (c - 1) + 1..3 of contact point c (a massless
    !> block with K = I each, modal_set_mass) get the rows L(x_c) of vehicle_ring's table.
    !> info: STAT_OK; STAT_BAD_ARGUMENT (no ring, the coordinates beyond nm) or from
    !> vehicle_ring%ring_residual_set.
    subroutine modal_ring_residual(mp, nrx, bay, rtab, rpost, info)
        type(modal_part), intent(inout) :: mp
        integer, intent(in) :: nrx
        real(dp), intent(in) :: bay, rtab(3, 3, nrx, 2), rpost(3, 3, 2)
        integer, intent(out) :: info
        info = STAT_BAD_ARGUMENT
        if (mp%nrl == 0) return
        if (mp%rm0 + mp%rr%nk + 3 * mp%rr%nc > mp%nm) return
        call ring_residual_set(mp%rr, nrx, bay, rtab, rpost, info)
        if (info /= STAT_OK) return
        call modal_ring_time(mp, 0.0_dp)
    end subroutine modal_ring_residual

    !> Set the ring rows of the wheels' points to their values at time t (contact points at
    !> x0 + v0 t), and the residual rows if any; the cached factors become stale
    !> (rows_version). No ring: nothing.
    subroutine modal_ring_time(mp, t)
        type(modal_part), intent(inout) :: mp
        real(dp), intent(in) :: t
        real(dp), allocatable :: rows(:, :, :), lres(:, :, :)
        integer :: i, k, c, j0
        if (mp%nrl == 0) return
        allocate (rows(3, mp%rr%nc, mp%rr%nk), lres(3, 3, mp%rr%nc))
        call ring_rows_eval(mp%rr, t, rows)
        if (mp%rr%nrx > 0) call ring_residual_eval(mp%rr, t, lres)
        do i = 1, mp%nrl
            do k = 1, 2
                c = 2 * (i - 1) + k
                mp%phi(mp%rlpt(:, k, i), mp%rm0 + 1:mp%rm0 + mp%rr%nk) = rows(:, c, :)
                if (mp%rr%nrx > 0) then
                    j0 = mp%rm0 + mp%rr%nk + 3 * (c - 1)
                    mp%phi(mp%rlpt(:, k, i), j0 + 1:j0 + 3) = lres(:, :, c)
                end if
            end do
        end do
        ! only the ring's columns moved (its modes, then its residual coordinates)
        call rows_changed(mp, mp%rm0 + 1, mp%rm0 + mp%rr%nk + merge(3 * mp%rr%nc, 0, mp%rr%nrx > 0))
    end subroutine modal_ring_time

    !> The index in 1..nrl of wheelset w on the ring track, 0 for one on track elements.
    pure integer function modal_rail_wheelset(mp, w) result(i)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: w
        do i = 1, mp%nrl
            if (mp%rlw(i) == w) return
        end do
        i = 0
    end function modal_rail_wheelset

    !> The index in 1..nfr of wheelset w's flexible rims, 0 for a rigid wheelset.
    pure integer function modal_rim_wheelset(mp, w) result(i)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: w
        do i = 1, mp%nfr
            if (mp%frw(i) == w) return
        end do
        i = 0
    end function modal_rim_wheelset

    !> The linear couplings' forces: added to fr (rigid, nd) and gp (points, np).
    pure subroutine modal_coupling_force(mp, nd, q, v, u, ud, fr, gp)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: nd
        real(dp), intent(in) :: q(nd), v(nd), u(mp%np), ud(mp%np)
        real(dp), intent(inout) :: fr(nd), gp(mp%np)
        integer :: e, p
        do e = 1, mp%nlc
            p = mp%lpt(e)
            associate (g => mp%lg(:, e), k => mp%lpar(1, e), c => mp%lpar(2, e))
                if (mp%lkind(e) == LC_SPLIT) then
                    gp(p) = gp(p) + k * (dot_product(g, q) - u(p)) + c * (dot_product(g, v) - ud(p)) &
                            + mp%lpar(3, e)
                    fr = fr + g * (k * u(p) + c * ud(p))
                else
                    gp(p) = gp(p) + k * dot_product(g, v)
                    fr = fr - g * (k * ud(p))
                end if
            end associate
        end do
    end subroutine modal_coupling_force

    !> The linear couplings' tangent d/dx + cv d/dx' added to jru, jpr, jpu; cvp (optional,
    !> np): the points' own dv/dx in place of cv in their columns (the exact modal step,
    !> vehicle_modal_step%modal_step_cvp).
    pure subroutine modal_coupling_tangent(mp, nd, cv, jru, jpr, jpu, cvp)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: nd
        real(dp), intent(in) :: cv
        real(dp), intent(inout) :: jru(nd, mp%np), jpr(mp%np, nd), jpu(mp%np, mp%np)
        real(dp), intent(in), optional :: cvp(:)
        integer :: e, p
        real(dp) :: s, sp, cu
        do e = 1, mp%nlc
            p = mp%lpt(e)
            cu = cv
            if (present(cvp)) cu = cvp(p)
            if (mp%lkind(e) == LC_SPLIT) then
                s = mp%lpar(1, e) + cv * mp%lpar(2, e)
                sp = mp%lpar(1, e) + cu * mp%lpar(2, e)
                jru(:, p) = jru(:, p) + sp * mp%lg(:, e)
                jpr(p, :) = jpr(p, :) + s * mp%lg(:, e)
                jpu(p, p) = jpu(p, p) - sp
            else
                jru(:, p) = jru(:, p) - cu * mp%lpar(1, e) * mp%lg(:, e)
                jpr(p, :) = jpr(p, :) + cv * mp%lpar(1, e) * mp%lg(:, e)
            end if
        end do
    end subroutine modal_coupling_tangent

    !> Force and its derivatives (df/dd, df/ddd) of one point element.
    pure subroutine point_element(kind, p, d, dd, f, kd, cd)
        integer, intent(in) :: kind
        real(dp), intent(in) :: p(4), d, dd
        real(dp), intent(out) :: f, kd, cd
        real(dp) :: pen
        f = 0.0_dp
        kd = 0.0_dp
        cd = 0.0_dp
        select case (kind)
        case (PEL_LINEAR)
            f = p(1) * d + p(2) * dd + p(3)
            kd = p(1)
            cd = p(2)
        case (PEL_HERTZ)
            pen = d - p(2)
            if (pen > 0.0_dp) then
                f = p(1) * pen * sqrt(pen) + p(3) * dd
                kd = 1.5_dp * p(1) * sqrt(pen)
                cd = p(3)
            end if
        end select
    end subroutine point_element

    !> Point coordinates u = Phi Q (and likewise velocities).
    pure subroutine modal_points(mp, qm, u)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: qm(mp%nm)
        real(dp), intent(out) :: u(mp%np)
        integer :: j
        integer :: lo, hi
        u = 0.0_dp
        do j = 1, mp%nm
            lo = mp%rlo(j)
            hi = mp%rhi(j)
            u(lo:hi) = u(lo:hi) + mp%phi(lo:hi, j) * qm(j)
        end do
    end subroutine modal_points

    !> Add the point elements' forces to fr (rigid, nd) and set the modal force
    !> fm = -B Q' - K_m Q + Phi^T g_p.
    !> gext (optional): further point forces (the wheel-rail contact on flexible rims).
    pure subroutine modal_force(mp, nd, q, v, qm, vm, fr, fm, gext)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: nd
        real(dp), intent(in) :: q(nd), v(nd), qm(mp%nm), vm(mp%nm)
        real(dp), intent(inout) :: fr(nd)
        real(dp), intent(out) :: fm(mp%nm)
        real(dp), intent(in), optional :: gext(mp%np)
        real(dp) :: u(mp%np), ud(mp%np), gp(mp%np), d, dd, f, kd, cd
        integer :: e, b, j0, s, r, p, o, ii, jj
        if (mp%nm == 0) return
        call modal_points(mp, qm, u)
        call modal_points(mp, vm, ud)
        gp = 0.0_dp
        if (present(gext)) gp = gext
        if (mp%nlc > 0) call modal_coupling_force(mp, nd, q, v, u, ud, fr, gp)
        do e = 1, mp%npe
            r = mp%prig(e)
            p = mp%ppt(e)
            call element_deflection(mp, e, q, v, u, ud, d, dd)
            call point_element(mp%ptype(e), mp%ppar(:, e), d, dd, f, kd, cd)
            gp(p) = gp(p) - f
            if (r > 0) fr(r) = fr(r) + f
        end do
        call modal_rows_t(mp, gp, fm)
        do b = 1, mp%nb
            j0 = mp%bs(b) - 1
            s = mp%bs(b + 1) - mp%bs(b)
            o = mp%off(b)
            do jj = 1, s
                do ii = 1, s
                    fm(j0 + ii) = fm(j0 + ii) - mp%bb(o + (jj - 1) * s + ii) * vm(j0 + jj) &
                                  - mp%kb(o + (jj - 1) * s + ii) * qm(j0 + jj)
                end do
            end do
        end do
    end subroutine modal_force

    !> Deflection d = u_p - q_r of point element e and its rate (q_r = 0 for an element
    !> grounded, prig = 0).
    pure subroutine element_deflection(mp, e, q, v, u, ud, d, dd)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: e
        real(dp), intent(in) :: q(:), v(:), u(:), ud(:)
        real(dp), intent(out) :: d, dd
        d = u(mp%ppt(e))
        dd = ud(mp%ppt(e))
        if (mp%prig(e) > 0) then
            d = d - q(mp%prig(e))
            dd = dd - v(mp%prig(e))
        end if
    end subroutine element_deflection

    !> The point elements' tangent d/dx + cv d/dx' (x = q or u) in four blocks: jrr (nd x nd,
    !> added), jru (nd x np), jpr (np x nd), jpu (np x np) of the forces on the rigid DOFs (r)
    !> and on the points (p). cvp (optional, np): the points' own dv/dx in their columns.
    pure subroutine modal_point_tangent(mp, nd, q, v, qm, vm, cv, jrr, jru, jpr, jpu, cvp)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: nd
        real(dp), intent(in) :: q(nd), v(nd), qm(mp%nm), vm(mp%nm), cv
        real(dp), intent(inout) :: jrr(nd, nd)
        real(dp), intent(out) :: jru(nd, mp%np), jpr(mp%np, nd), jpu(mp%np, mp%np)
        real(dp), intent(in), optional :: cvp(:)
        real(dp) :: u(mp%np), ud(mp%np), d, dd, f, kd, cd, s, sp
        integer :: e, r, p
        jru = 0.0_dp
        jpr = 0.0_dp
        jpu = 0.0_dp
        if (mp%nm == 0) return
        call modal_points(mp, qm, u)
        call modal_points(mp, vm, ud)
        do e = 1, mp%npe
            r = mp%prig(e)
            p = mp%ppt(e)
            call element_deflection(mp, e, q, v, u, ud, d, dd)
            call point_element(mp%ptype(e), mp%ppar(:, e), d, dd, f, kd, cd)
            s = kd + cv * cd
            sp = s
            if (present(cvp)) sp = kd + cvp(p) * cd
            jpu(p, p) = jpu(p, p) - sp
            if (r > 0) then
                jpr(p, r) = jpr(p, r) + s
                jru(r, p) = jru(r, p) + sp
                jrr(r, r) = jrr(r, r) - s
            end if
        end do
        if (mp%nlc > 0) call modal_coupling_tangent(mp, nd, cv, jru, jpr, jpu, cvp)
    end subroutine modal_point_tangent

    !> Factor S = cq diag(mass) + ck (cb B + K_m) block by block and form C = Phi S^-1 Phi^T, unless
    !> mf already holds them for these coefficients and rows. Work: sum_b s_b^3 + nm np (s + np),
    !> linear in nm for bounded block sizes. info: STAT_OK or STAT_SINGULAR (a singular block).
    !> sx (optional): the packed blocks of S given instead (the exact modal step's, a function
    !> of the step size cq stands for: vehicle_modal_step%modal_step_matrices).
    subroutine modal_factorise(mp, cq, cb, ck, mf, info, sx)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: cq, cb, ck
        type(modal_factor), intent(inout) :: mf
        integer, intent(out) :: info
        real(dp), intent(in), optional :: sx(:)
        integer :: b, j0, s, i, o, lin, lo, hi
        real(dp), allocatable :: x(:, :)
        info = STAT_OK
        if (mp%nm == 0) return
        if (mf%cq == cq .and. mf%cb == cb .and. mf%ck == ck .and. &
            mf%rows_version == mp%rows_version .and. (mf%given .eqv. present(sx))) return
        if (.not. allocated(mf%lu)) allocate (mf%lu(mp%off(mp%nb + 1)), mf%piv(mp%nm), &
                                              mf%c(mp%np, mp%np))
        mf%c = 0.0_dp
        mf%cq = -1.0_dp     ! invalid until complete
        do b = 1, mp%nb
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            o = mp%off(b)
            if (present(sx)) then
                mf%lu(o + 1:o + s * s) = sx(o + 1:o + s * s)
            else
                mf%lu(o + 1:o + s * s) = ck * (cb * mp%bb(o + 1:o + s * s) + mp%kb(o + 1:o + s * s))
                do i = 1, s
                    mf%lu(o + (i - 1) * s + i) = mf%lu(o + (i - 1) * s + i) + cq * mp%mass(j0 + i - 1)
                end do
            end if
            if (s == 1) then
                lin = merge(1, 0, mf%lu(o + 1) == 0.0_dp)
                mf%piv(j0) = 1
            else
                call dgetrf(s, s, mf%lu(o + 1), s, mf%piv(j0), lin)
            end if
            if (lin /= 0) then
                info = STAT_SINGULAR
                return
            end if
            ! C += Phi_b S_b^-1 Phi_b^T over the block's rows lo..hi
            lo = minval(mp%rlo(j0:j0 + s - 1))
            hi = maxval(mp%rhi(j0:j0 + s - 1))
            if (hi < lo) cycle
            x = transpose(mp%phi(lo:hi, j0:j0 + s - 1))
            call block_solve(mp, mf, b, s, hi - lo + 1, x)
            mf%c(lo:hi, lo:hi) = mf%c(lo:hi, lo:hi) + matmul(mp%phi(lo:hi, j0:j0 + s - 1), x)
        end do
        mf%cq = cq
        mf%cb = cb
        mf%ck = ck
        mf%given = present(sx)
        mf%rows_version = mp%rows_version
    end subroutine modal_factorise

    !> x <- S_b^-1 x for block b of size s (x: s x nrhs), from the factors in mf.
    subroutine block_solve(mp, mf, b, s, nrhs, x)
        type(modal_part), intent(in) :: mp
        type(modal_factor), intent(in) :: mf
        integer, intent(in) :: b, s, nrhs
        real(dp), intent(inout) :: x(s, nrhs)
        integer :: lin
        if (s == 1) then
            x = x / mf%lu(mp%off(b) + 1)
        else
            call dgetrs('N', s, nrhs, mf%lu(mp%off(b) + 1), s, mf%piv(mp%bs(b)), x, s, lin)
        end if
    end subroutine block_solve

    !> y <- S^-1 y over all blocks (y: nm), from the factors in mf.
    subroutine modal_solve(mp, mf, y)
        type(modal_part), intent(in) :: mp
        type(modal_factor), intent(in) :: mf
        real(dp), intent(inout) :: y(mp%nm)
        integer :: b, j0, s
        do b = 1, mp%nb
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            if (s == 1) then
                y(j0) = y(j0) / mf%lu(mp%off(b) + 1)
            else
                call block_solve(mp, mf, b, s, 1, y(j0:j0 + s - 1))
            end if
        end do
    end subroutine modal_solve

end module vehicle_modal
