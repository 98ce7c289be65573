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
module vehicle_modal
    use common_kinds, only: dp
    use common_lapack, only: dgetrf, dgetrs
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_SIZE_MISMATCH, STAT_SINGULAR
    implicit none
    private
    public :: modal_part, modal_factor, modal_create, modal_force, modal_point_tangent
    public :: modal_factorise, modal_solve, modal_points
    public :: PEL_LINEAR, PEL_HERTZ

    integer, parameter :: PEL_LINEAR = 1
    integer, parameter :: PEL_HERTZ = 2

    !> The constant modal part of a model (nm = 0: none; every loop below is then empty).
    type :: modal_part
        integer :: nm = 0, nb = 0, np = 0, npe = 0
        integer :: rows_version = 0                 !< increased whenever phi changes
        integer, allocatable :: bs(:), off(:)       !< block starts, packed offsets (nb + 1)
        real(dp), allocatable :: bb(:), kb(:)       !< packed blocks of B and K_m
        real(dp), allocatable :: phi(:, :)          !< (np, nm) attachment rows
        integer, allocatable :: ptype(:), prig(:), ppt(:)   !< per point element
        real(dp), allocatable :: ppar(:, :)         !< (4, npe) element parameters
    end type modal_part

    !> The factors of the modal step matrix S = cq I + ck (cb B + K_m), block by block, and the
    !> condensed flexibility C = Phi S^-1 Phi^T (np x np), valid for (cq, cb, ck, rows_version).
    type :: modal_factor
        real(dp) :: cq = -1.0_dp, cb = -1.0_dp, ck = -1.0_dp
        integer :: rows_version = -1
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
        mp%rows_version = 1
        info = STAT_OK
    end subroutine modal_create

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
        u = 0.0_dp
        do j = 1, mp%nm
            u = u + mp%phi(:, j) * qm(j)
        end do
    end subroutine modal_points

    !> Add the point elements' forces to fr (rigid, nd) and set the modal force
    !> fm = -B Q' - K_m Q + Phi^T g_p.
    pure subroutine modal_force(mp, nd, q, v, qm, vm, fr, fm)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: nd
        real(dp), intent(in) :: q(nd), v(nd), qm(mp%nm), vm(mp%nm)
        real(dp), intent(inout) :: fr(nd)
        real(dp), intent(out) :: fm(mp%nm)
        real(dp) :: u(mp%np), ud(mp%np), gp(mp%np), d, dd, f, kd, cd
        integer :: e, b, j, j0, s, r, p, o, ii, jj
        if (mp%nm == 0) return
        call modal_points(mp, qm, u)
        call modal_points(mp, vm, ud)
        gp = 0.0_dp
        do e = 1, mp%npe
            r = mp%prig(e)
            p = mp%ppt(e)
            d = u(p)
            dd = ud(p)
            if (r > 0) then
                d = d - q(r)
                dd = dd - v(r)
            end if
            call point_element(mp%ptype(e), mp%ppar(:, e), d, dd, f, kd, cd)
            gp(p) = gp(p) - f
            if (r > 0) fr(r) = fr(r) + f
        end do
        do j = 1, mp%nm
            fm(j) = dot_product(mp%phi(:, j), gp)
        end do
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

    !> The point elements' tangent d/dx + cv d/dx' (x = q or u) in four blocks: jrr (nd x nd,
    !> added), jru (nd x np), jpr (np x nd), jpu (np x np) of the forces on the rigid DOFs (r)
    !> and on the points (p).
    pure subroutine modal_point_tangent(mp, nd, q, v, qm, vm, cv, jrr, jru, jpr, jpu)
        type(modal_part), intent(in) :: mp
        integer, intent(in) :: nd
        real(dp), intent(in) :: q(nd), v(nd), qm(mp%nm), vm(mp%nm), cv
        real(dp), intent(inout) :: jrr(nd, nd)
        real(dp), intent(out) :: jru(nd, mp%np), jpr(mp%np, nd), jpu(mp%np, mp%np)
        real(dp) :: u(mp%np), ud(mp%np), d, dd, f, kd, cd, s
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
            d = u(p)
            dd = ud(p)
            if (r > 0) then
                d = d - q(r)
                dd = dd - v(r)
            end if
            call point_element(mp%ptype(e), mp%ppar(:, e), d, dd, f, kd, cd)
            s = kd + cv * cd
            jpu(p, p) = jpu(p, p) - s
            if (r > 0) then
                jpr(p, r) = jpr(p, r) + s
                jru(r, p) = jru(r, p) + s
                jrr(r, r) = jrr(r, r) - s
            end if
        end do
    end subroutine modal_point_tangent

    !> Factor S = cq I + ck (cb B + K_m) block by block and form C = Phi S^-1 Phi^T, unless
    !> mf already holds them for these coefficients and rows. Work: sum_b s_b^3 + nm np (s + np),
    !> linear in nm for bounded block sizes. info: STAT_OK or STAT_SINGULAR (a singular block).
    subroutine modal_factorise(mp, cq, cb, ck, mf, info)
        type(modal_part), intent(in) :: mp
        real(dp), intent(in) :: cq, cb, ck
        type(modal_factor), intent(inout) :: mf
        integer, intent(out) :: info
        integer :: b, j0, s, i, o, lin
        real(dp), allocatable :: x(:, :)
        info = STAT_OK
        if (mp%nm == 0) return
        if (mf%cq == cq .and. mf%cb == cb .and. mf%ck == ck .and. &
            mf%rows_version == mp%rows_version) return
        if (.not. allocated(mf%lu)) allocate (mf%lu(mp%off(mp%nb + 1)), mf%piv(mp%nm), &
                                              mf%c(mp%np, mp%np))
        mf%c = 0.0_dp
        mf%cq = -1.0_dp     ! invalid until complete
        do b = 1, mp%nb
            j0 = mp%bs(b)
            s = mp%bs(b + 1) - j0
            o = mp%off(b)
            mf%lu(o + 1:o + s * s) = ck * (cb * mp%bb(o + 1:o + s * s) + mp%kb(o + 1:o + s * s))
            do i = 1, s
                mf%lu(o + (i - 1) * s + i) = mf%lu(o + (i - 1) * s + i) + cq
            end do
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
            ! C += Phi_b S_b^-1 Phi_b^T
            x = transpose(mp%phi(:, j0:j0 + s - 1))
            call block_solve(mp, mf, b, s, mp%np, x)
            mf%c = mf%c + matmul(mp%phi(:, j0:j0 + s - 1), x)
        end do
        mf%cq = cq
        mf%cb = cb
        mf%ck = ck
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
