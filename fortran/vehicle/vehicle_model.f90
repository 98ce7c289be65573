!> The vehicle-track model as seen by the integrator: constant mass, damping and stiffness
!> matrices of the linear suspension and track (assembled in Python), a constant force
!> (gravity and spring preloads), scalar nonlinear suspension elements along a direction g
!> (regularised dry friction, bump stops) and the wheel-rail contact of each wheelset.
!> Implements no Kaiser equation: the coach's force balance below (docs/vehicle.md).
!>
!>   F(q, v) = f0 - K q - C v + sum_e (-g_e f_e(g_e.q, g_e.v)) + contact(q, v)
module vehicle_model
    use common_kinds, only: dp
    use vehicle_contact, only: nq_table, nwo, wheelset_contact
    implicit none
    private
    public :: vmodel, vehicle_pack, force_total, tangent, element_force, is_spin
    public :: el_friction, el_bump

    integer, parameter :: el_friction = 1   !< f = p1 tanh(gdot / p2) + p3 gdot
    integer, parameter :: el_bump = 2       !< f = p2 (|d| - p1) sign(d) for |d| > p1 (clearance p1)

    type :: vmodel
        integer :: nd = 0, ne = 0, nw = 0, ny = 0, cmodel = 1, fsn = 8
        integer :: bem = 0   !< vehicle_bem handle (cmodel 3)
        real(dp), allocatable :: m(:, :), c(:, :), k(:, :), f0(:)
        integer, allocatable :: etype(:)
        real(dp), allocatable :: eg(:, :), epar(:, :)
        !> 1-based DOF indices: iws (y, z, roll, yaw, x, beta) per wheelset, 0 for a DOF not
        !> modelled (held at zero: e.g. a wheelset without x or spin); itr (y, z, roll) of the
        !> track element, 0 = rigid ground.
        integer, allocatable :: iws(:, :), itr(:, :)
        real(dp), allocatable :: tab(:, :, :)
        real(dp) :: y0 = 0.0_dp, dy = 1.0_dp, r0 = 0.46_dp, v0 = 1.0_dp, gmod = 8.2e10_dp, mu = 0.3_dp
    end type vmodel

contains

    !> Copy the flat arrays of the shim into a vmodel.
    pure subroutine vehicle_pack(nd, ne, nw, ny, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                                 y0, dy, r0, v0, gmod, mu, cmodel, fsn, bem, md)
        integer, intent(in) :: nd, ne, nw, ny, cmodel, fsn, bem
        real(dp), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
        integer, intent(in) :: etype(ne), iws(6, nw), itr(3, nw)
        real(dp), intent(in) :: tab(nq_table, 2, ny), y0, dy, r0, v0, gmod, mu
        type(vmodel), intent(out) :: md
        md%nd = nd
        md%ne = ne
        md%nw = nw
        md%ny = ny
        md%cmodel = cmodel
        md%fsn = fsn
        md%bem = bem
        md%m = mm
        md%c = cc
        md%k = kk
        md%f0 = f0
        md%etype = etype
        md%eg = eg
        md%epar = epar
        md%iws = iws
        md%itr = itr
        md%tab = tab
        md%y0 = y0
        md%dy = dy
        md%r0 = r0
        md%v0 = v0
        md%gmod = gmod
        md%mu = mu
    end subroutine vehicle_pack

    !> Force and its derivatives (d f / d d, d f / d ddot) of one scalar element.
    pure subroutine element_force(etype, p, d, dd, f, kd, cd)
        integer, intent(in) :: etype
        real(dp), intent(in) :: p(4), d, dd
        real(dp), intent(out) :: f, kd, cd
        real(dp) :: t
        f = 0.0_dp
        kd = 0.0_dp
        cd = 0.0_dp
        select case (etype)
        case (el_friction)
            f = p(3) * dd
            cd = p(3)
            if (p(1) /= 0.0_dp .and. p(2) > 0.0_dp) then
                t = tanh(dd / p(2))
                f = f + p(1) * t
                cd = cd + p(1) * (1.0_dp - t * t) / p(2)
            end if
        case (el_bump)
            if (abs(d) > p(1)) then
                f = p(2) * (abs(d) - p(1)) * sign(1.0_dp, d)
                kd = p(2)
            end if
        end select
    end subroutine element_force

    !> Gather the local states of wheelset w.
    pure subroutine ws_state(md, w, q, v, qw, vw, qt, vt)
        type(vmodel), intent(in) :: md
        integer, intent(in) :: w
        real(dp), intent(in) :: q(:), v(:)
        real(dp), intent(out) :: qw(6), vw(6), qt(3), vt(3)
        integer :: j
        qw = 0.0_dp
        vw = 0.0_dp
        do j = 1, 6
            if (md%iws(j, w) > 0) then
                qw(j) = q(md%iws(j, w))
                vw(j) = v(md%iws(j, w))
            end if
        end do
        qt = 0.0_dp
        vt = 0.0_dp
        do j = 1, 3
            if (md%itr(j, w) > 0) then
                qt(j) = q(md%itr(j, w))
                vt(j) = v(md%itr(j, w))
            end if
        end do
    end subroutine ws_state

    !> Contact forces of wheelset w added into f. cheap: for a BEM run, the Hertz + Kalker
    !> model calibrated by the last BEM solves (the tangent: modified Newton).
    subroutine add_contact(md, w, q, v, f, wout, info, cheap)
        type(vmodel), intent(in) :: md
        integer, intent(in) :: w
        real(dp), intent(in) :: q(:), v(:)
        real(dp), intent(inout) :: f(:)
        real(dp), intent(out) :: wout(nwo, 2)
        integer, intent(out) :: info
        logical, intent(in), optional :: cheap
        real(dp) :: qw(6), vw(6), qt(3), vt(3), fw(6), ft(3)
        integer :: j, model
        model = md%cmodel
        if (present(cheap)) then
            if (cheap .and. model == 3) model = 4
        end if
        call ws_state(md, w, q, v, qw, vw, qt, vt)
        call wheelset_contact(md%ny, md%tab, md%y0, md%dy, md%r0, md%v0, md%gmod, md%mu, model, md%fsn, &
                              md%bem, w, qw, vw, qt, vt, fw, ft, wout, info)
        do j = 1, 6
            if (md%iws(j, w) > 0) f(md%iws(j, w)) = f(md%iws(j, w)) + fw(j)
        end do
        do j = 1, 3
            if (md%itr(j, w) > 0) f(md%itr(j, w)) = f(md%itr(j, w)) + ft(j)
        end do
    end subroutine add_contact

    !> Total force F(q, v); wout (nwo, 2, nw) the contact outputs per wheel. info 3: a
    !> wheelset left the contact table (derailment or a diverging solution); 5, 6 a BEM patch
    !> reached its grid edge / a BEM solver did not converge.
    subroutine force_total(md, q, v, f, wout, info)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: q(md%nd), v(md%nd)
        real(dp), intent(out) :: f(md%nd), wout(nwo, 2, md%nw)
        integer, intent(out) :: info
        real(dp) :: d, dd, fe, kd, cd
        integer :: e, w
        f = md%f0 - matmul(md%k, q) - matmul(md%c, v)
        do e = 1, md%ne
            d = dot_product(md%eg(:, e), q)
            dd = dot_product(md%eg(:, e), v)
            call element_force(md%etype(e), md%epar(:, e), d, dd, fe, kd, cd)
            f = f - md%eg(:, e) * fe
        end do
        info = 0
        do w = 1, md%nw
            call add_contact(md, w, q, v, f, wout(:, :, w), info)
            if (info /= 0) return
        end do
    end subroutine force_total

    !> Tangent dF/dq + cv dF/dv at (q, v): the linear part exactly, the elements analytically,
    !> the contact by forward differences over each wheelset's own DOFs (up to 6 + 3 track),
    !> perturbing q by eps and v by cv eps together. With cv = 0 (or a second call with
    !> dq = 0) the two parts separate: mode 0 -> dF/dq + cv dF/dv, mode 1 -> dF/dv only.
    !> With the BEM contact (cmodel 3) the contact part is that of Hertz + Kalker scaled to the
    !> last BEM solves (vehicle_contact model 4): modified Newton.
    subroutine tangent(md, q, v, cv, mode, jac, info)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: q(md%nd), v(md%nd), cv
        integer, intent(in) :: mode
        real(dp), intent(out) :: jac(md%nd, md%nd)
        integer, intent(out) :: info
        real(dp) :: d, dd, fe, kd, cd, s
        real(dp) :: f0w(md%nd), f1w(md%nd), qp(md%nd), vp(md%nd), wout(nwo, 2)
        integer :: e, w, j, jj, idx(9), n
        real(dp), parameter :: eps = 1.0e-8_dp
        if (mode == 0) then
            jac = -md%k - cv * md%c
        else
            jac = -md%c
        end if
        do e = 1, md%ne
            d = dot_product(md%eg(:, e), q)
            dd = dot_product(md%eg(:, e), v)
            call element_force(md%etype(e), md%epar(:, e), d, dd, fe, kd, cd)
            if (mode == 0) then
                s = kd + cv * cd
            else
                s = cd
            end if
            if (s /= 0.0_dp) then
                do j = 1, md%nd
                    if (md%eg(j, e) /= 0.0_dp) jac(:, j) = jac(:, j) - md%eg(:, e) * (s * md%eg(j, e))
                end do
            end if
        end do
        info = 0
        do w = 1, md%nw
            n = 0
            do j = 1, 6
                if (md%iws(j, w) > 0) then
                    n = n + 1
                    idx(n) = md%iws(j, w)
                end if
            end do
            do j = 1, 3
                if (md%itr(j, w) > 0) then
                    n = n + 1
                    idx(n) = md%itr(j, w)
                end if
            end do
            f0w = 0.0_dp
            call add_contact(md, w, q, v, f0w, wout, info, cheap=.true.)
            if (info /= 0) return
            do jj = 1, n
                j = idx(jj)
                qp = q
                vp = v
                if (mode == 0) then
                    qp(j) = q(j) + eps
                    vp(j) = v(j) + cv * eps
                else
                    vp(j) = v(j) + eps
                end if
                f1w = 0.0_dp
                call add_contact(md, w, qp, vp, f1w, wout, info, cheap=.true.)
                if (info /= 0) return
                jac(idx(1:n), j) = jac(idx(1:n), j) + (f1w(idx(1:n)) - f0w(idx(1:n))) / eps
            end do
        end do
    end subroutine tangent

    !> Whether DOF j is a wheelset spin perturbation beta (no stiffness: only its rate enters).
    pure logical function is_spin(md, j)
        type(vmodel), intent(in) :: md
        integer, intent(in) :: j
        is_spin = any(md%iws(6, :) == j)
    end function is_spin

end module vehicle_model
