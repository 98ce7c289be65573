!> The vehicle-track model as seen by the integrator: constant mass, damping and stiffness
!> matrices of the linear suspension and track (assembled in Python), a constant force
!> (gravity and spring preloads), scalar nonlinear suspension elements along a direction g
!> (regularised dry friction, bump stops) and the wheel-rail contact of each wheelset.
!> Implements no Kaiser equation: the coach's force balance below (docs/vehicle.md).
!>
!>   F(q, v) = f0 - K q - C v + sum_e (-g_e f_e(g_e.q, g_e.v)) + contact(q, v)
!>
!> Models live in a registry (like contact_plans and vehicle_bem): vehicle_create copies
!> the arrays once and returns an integer handle, vehicle_get gives the model to the
!> integrator on every later call, vehicle_free releases it. The per-call conditions (speed,
!> contact model, BEM state) travel separately in a vsettings value. Not thread-safe.
module vehicle_model
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT, STAT_BAD_HANDLE, STAT_SIZE_MISMATCH, &
                             STAT_NO_MEMORY
    use vehicle_contact, only: nq_table, nwo, wheelset_contact, CMODEL_HERTZ_KALKER, CMODEL_BEM, &
                               pose_table, pose_set, SLIN_KEEP, SLIN_READ
    use vehicle_strip, only: strip_geometry, strip_set, strip_lin
    use vehicle_bem, only: bem_record, bem_solve_recorded
    use vehicle_curve, only: curve_input, curve_set, curve_points, curve_clear, curve_time
    use vehicle_modal_step, only: modal_step
    use vehicle_modal, only: modal_part, modal_create, modal_couple, modal_rim_wheelset, modal_set_mass, &
                             modal_euler, modal_ring, modal_ring_time, modal_rail_wheelset, &
                             modal_ring_residual, modal_follow_set, modal_follow, &
                             modal_follow_reset
    use vehicle_irregularity, only: irr_track, irr_set, irr_time, irr_inputs, NIRR
    implicit none
    private
    public :: vmodel, vsettings, vehicle_create, vehicle_free, vehicle_get, vehicle_call
    public :: vehicle_attach_modal, vehicle_attach_couplings, vehicle_attach_mass, vehicle_attach_euler
    public :: vehicle_attach_follow, vehicle_follow_rows
    public :: vehicle_attach_strip, vehicle_attach_ring, vehicle_ring_time, vehicle_ring_residual
    public :: vehicle_attach_curve, vehicle_attach_curve_points
    public :: MAX_VEHICLE
    public :: force_total, tangent, element_force, is_spin, TANGENT_QV, TANGENT_V
    public :: el_friction, el_bump
    public :: add_contact, wheelset_coords
    public :: vehicle_attach_irregularity, vehicle_irregularity_inputs, model_time

    integer, parameter :: el_friction = 1   !< f = p1 tanh(gdot / p2) + p3 gdot
    integer, parameter :: el_bump = 2       !< f = p2 (|d| - p1) sign(d) for |d| > p1 (clearance p1)
    integer, parameter :: el_none = 0       !< no force (a placeholder keeps the arrays non-empty)
    integer, parameter :: MAX_VEHICLE = 64
    integer, parameter :: TANGENT_QV = 0    !< tangent mode: dF/dq + cv dF/dv
    integer, parameter :: TANGENT_V = 1     !< tangent mode: dF/dv
    !> Step sizes whose exact modal step matrices a model keeps (a run's h and its sub-steps).
    integer, parameter :: MSC_SLOTS = 4

    !> One assembled system: what does not change from call to call.
    type :: vmodel
        logical :: used = .false.
        integer :: nd = 0, ne = 0, nw = 0
        real(dp), allocatable :: m(:, :), c(:, :), k(:, :), f0(:)
        integer, allocatable :: etype(:)
        real(dp), allocatable :: eg(:, :), epar(:, :)
        !> 1-based DOF indices: iws (y, z, roll, yaw, x, beta) per wheelset, 0 for a DOF not
        !> modelled (held at zero: e.g. a wheelset without x or spin); itr (y, z, roll) of the
        !> track element, 0 = rigid ground.
        integer, allocatable :: iws(:, :), itr(:, :)
        !> Spin (polar) inertia I_y of each wheelset's rotating parts, kg m^2 (0: no
        !> gyroscopic term): add_gyroscopic.
        real(dp), allocatable :: ispin(:)
        !> The per-wheel contact table over (u, relative roll) (vehicle_contact).
        type(pose_table) :: ct
        !> The strip contact (vehicle_strip; off: the table's points).
        type(strip_geometry) :: st
        real(dp) :: r0 = 0.46_dp, gmod = 8.2e10_dp, mu = 0.3_dp
        !> Modal blocks coupled through points (vehicle_modal; nm = 0: none). The integrator's
        !> state is (q(1:nd), Q(1:nm)).
        type(modal_part) :: mp
        !> The time loop's iteration matrix kept from the end of the last run call
        !> (vehicle_newmark%newmark_run, strip contact): its LU factors (kma(:, :, 1)), for the
        !> rigid model the matrix itself (kma(:, :, 2), Broyden's update), for modal blocks the
        !> point elements' tangent blocks (kmjpr, kmjpu), and the key of the state and settings
        !> it continues from; kmkey not allocated: none kept.
        real(dp), allocatable :: kma(:, :, :), kmkey(:), kmjpr(:, :), kmjpu(:, :)
        integer, allocatable :: kmpiv(:)
        !> the steps the kept matrix has served since it was made (vehicle_newmark's refresh rule)
        integer :: kmage = 0
        !> A curve under the current run (vehicle_curve; cv%ns = 0: straight track), read at
        !> each step's time like the ring's rows.
        type(curve_input) :: cv
        !> The exact modal step's block matrices for the last step sizes (vehicle_modal_step,
        !> vehicle_newmark SCHEME_EXACT), kept from call to call: a function of h and the blocks.
        type(modal_step) :: msc(MSC_SLOTS)
        integer :: mscnext = 0
        !> The irregular track's rail inputs under the wheels (vehicle_irregularity; nw = 0: none).
        type(irr_track) :: irr
    end type vmodel

    !> The conditions of one call: forward speed v0 (m/s), contact model (vehicle_contact
    !> CMODEL_*), FASTSIM strips and points per strip, and the vehicle_bem handle of a BEM run.
    type :: vsettings
        real(dp) :: v0 = 1.0_dp
        integer :: cmodel = 1, fsn = 8, bem = 0
    end type vsettings

    type(vmodel), target :: models(MAX_VEHICLE)

contains

    !> Store a model; handle in 1..MAX_VEHICLE. info: STAT_OK, STAT_SIZE_MISMATCH (a table
    !> with other than nq_table quantities), STAT_BAD_ARGUMENT (no DOF, wheelset or element,
    !> a table of fewer than 2 nodes or step <= 0, a DOF index out of range, a wheelset
    !> without its y, z or roll DOF, an unknown element kind), STAT_NO_MEMORY (no free slot).
    subroutine vehicle_create(nd, ne, nw, ny, nr, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                              y0, dy, p0, dph, rnom, r0, gmod, mu, ispin, handle, info)
        integer, intent(in) :: nd, ne, nw, ny, nr, nq
        real(dp), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
        real(dp), intent(in) :: ispin(nw)
        integer, intent(in) :: etype(ne), iws(6, nw), itr(3, nw)
        real(dp), intent(in) :: tab(nq, 2, ny, nr), y0, dy, p0, dph, rnom, r0, gmod, mu
        integer, intent(out) :: handle, info
        type(vmodel), pointer :: md
        type(pose_table) :: ct
        integer :: k
        handle = 0
        info = STAT_SIZE_MISMATCH
        if (nq /= nq_table) return
        call pose_set(nq, ny, nr, tab, y0, dy, p0, dph, rnom, ct, info)
        if (info /= STAT_OK) return
        info = STAT_BAD_ARGUMENT
        if (nd < 1 .or. ne < 1 .or. nw < 1) return
        if (any(iws < 0) .or. any(iws > nd) .or. any(iws(1:3, :) == 0) .or. any(itr < 0) &
            .or. any(itr > nd) .or. any(etype /= el_friction .and. etype /= el_bump .and. etype /= el_none) &
            .or. any(.not. (ispin >= 0.0_dp))) return
        info = STAT_NO_MEMORY
        do k = 1, MAX_VEHICLE
            if (.not. models(k)%used) then
                handle = k
                exit
            end if
        end do
        if (handle == 0) return
        md => models(handle)
        md%nd = nd
        md%ne = ne
        md%nw = nw
        md%m = mm
        md%c = cc
        md%k = kk
        md%f0 = f0
        md%etype = etype
        md%eg = eg
        md%epar = epar
        md%iws = iws
        md%itr = itr
        md%ispin = ispin
        md%ct = ct
        md%st = strip_geometry()
        md%irr = irr_track()
        if (allocated(md%kmkey)) deallocate (md%kmkey)
        md%r0 = r0
        md%gmod = gmod
        md%mu = mu
        md%used = .true.
        info = STAT_OK
    end subroutine vehicle_create

    !> Switch a model's contact to the strip potential (vehicle_strip%strip_set's arrays).
    !> info: STAT_BAD_HANDLE, or strip_set's STAT_BAD_ARGUMENT.
    subroutine vehicle_attach_strip(handle, nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, &
                                    offset, top, nf, fx0, fdx, fv, fm, info)
        integer, intent(in) :: handle, nw, nr, nf
        real(dp), intent(in) :: ws(7, nw), ds, rnom, ry0, rdy, rz(nr), rm(nr), rk(nr), rk1(nr)
        real(dp), intent(in) :: offset, top, fx0, fdx, fv(nf, 6), fm(nf, 6)
        integer, intent(out) :: info
        info = STAT_BAD_HANDLE
        if (handle < 1 .or. handle > MAX_VEHICLE) return
        if (.not. models(handle)%used) return
        call strip_set(nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, top, nf, fx0, fdx, &
                       fv, fm, models(handle)%st, info)
        if (allocated(models(handle)%kmkey)) deallocate (models(handle)%kmkey)
    end subroutine vehicle_attach_strip

    !> Release a model (a handle not in use is ignored).
    subroutine vehicle_free(handle)
        integer, intent(in) :: handle
        if (.not. associated(vehicle_get(handle))) return
        deallocate (models(handle)%m, models(handle)%c, models(handle)%k, models(handle)%f0, &
                    models(handle)%etype, models(handle)%eg, models(handle)%epar, &
                    models(handle)%iws, models(handle)%itr, models(handle)%ct%tab, &
                    models(handle)%ispin)
        models(handle)%mp = modal_part()
        models(handle)%msc = modal_step()
        models(handle)%st = strip_geometry()
        models(handle)%irr = irr_track()
        if (allocated(models(handle)%kmkey)) deallocate (models(handle)%kmkey)
        models(handle)%used = .false.
    end subroutine vehicle_free

    !> The model behind a handle; null for a handle not in use.
    function vehicle_get(handle) result(md)
        integer, intent(in) :: handle
        type(vmodel), pointer :: md
        md => null()
        if (handle < 1 .or. handle > MAX_VEHICLE) return
        if (models(handle)%used) md => models(handle)
    end function vehicle_get

    !> Attach modal blocks and point elements to a model (replacing any it had); see
    !> vehicle_modal%modal_create for the arguments and info, and STAT_BAD_HANDLE.
    subroutine vehicle_attach_modal(handle, nm, nb, np, npe, nbk, bs, bb, kb, phi, ptype, prig, ppt, &
                                    ppar, info)
        integer, intent(in) :: handle, nm, nb, np, npe, nbk
        integer, intent(in) :: bs(nb + 1), ptype(npe), prig(npe), ppt(npe)
        real(dp), intent(in) :: bb(nbk), kb(nbk), phi(np, nm), ppar(4, npe)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        type(modal_part) :: mp
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        call modal_create(md%nd, nm, nb, np, npe, nbk, bs, bb, kb, phi, ptype, prig, ppt, ppar, mp, info)
        if (info == STAT_OK) md%mp = mp
    end subroutine vehicle_attach_modal

    !> Attach linear couplings and flexible-rim wheelsets to a model's modal part; see
    !> vehicle_modal%modal_couple for the arguments and info, and STAT_BAD_HANDLE.
    subroutine vehicle_attach_couplings(handle, nd, nlc, lkind, lpt, lg, lpar, nfr, frw, frpt, &
                                        frarm, info)
        integer, intent(in) :: handle, nd, nlc, nfr
        integer, intent(in) :: lkind(nlc), lpt(nlc), frw(nfr), frpt(3, 2, nfr)
        real(dp), intent(in) :: lg(nd, nlc), lpar(3, nlc), frarm(2, nfr)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        info = STAT_SIZE_MISMATCH
        if (nd /= md%nd) return
        call modal_couple(md%mp, md%nd, md%nw, nlc, lkind, lpt, lg, lpar, nfr, frw, frpt, frarm, info)
    end subroutine vehicle_attach_couplings

    !> Set the modal masses of a model's modal part (1 or 0: massless coordinates); see
    !> vehicle_modal%modal_set_mass for info, and STAT_BAD_HANDLE.
    subroutine vehicle_attach_mass(handle, nm, mass, info)
        integer, intent(in) :: handle, nm
        real(dp), intent(in) :: mass(nm)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        call modal_set_mass(md%mp, nm, mass, info)
    end subroutine vehicle_attach_mass

    !> Set the Eulerian term of a model's flexible rims; see vehicle_modal%modal_euler for the
    !> arguments and info, and STAT_BAD_HANDLE.
    subroutine vehicle_attach_euler(handle, nfr, ept, omega, info)
        integer, intent(in) :: handle, nfr
        integer, intent(in) :: ept(3, 2, nfr)
        real(dp), intent(in) :: omega(nfr)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        call modal_euler(md%mp, nfr, ept, omega, info)
    end subroutine vehicle_attach_euler

    !> Make a model's flexible rims follow the contact point; see vehicle_modal%modal_follow_set
    !> for the arguments and info, and STAT_BAD_HANDLE.
    subroutine vehicle_attach_follow(handle, nfr, nq, ns, s0, ds, tab, etab, nrs, rs0, rds, rcc, &
                                     rcx, rcj, rjj, m0, r0, pt, post, info)
        integer, intent(in) :: handle, nfr, nq, ns, nrs, m0(nfr), r0(nfr), pt(12, nfr)
        real(dp), intent(in) :: s0, ds, tab(3, nq, ns, 2), etab(3, nq, ns, 2), rs0, rds
        real(dp), intent(in) :: rcc(3, 3, nrs, 2), rcx(3, 3, nrs, nrs), rcj(3, 6, nrs, 2), rjj(6, 6)
        real(dp), intent(in) :: post
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        call modal_follow_set(md%mp, nfr, nq, ns, s0, ds, tab, etab, nrs, rs0, rds, rcc, rcx, rcj, &
                              rjj, m0, r0, pt, post, info)
    end subroutine vehicle_attach_follow

    !> The modal rows phi (np x nm) with the rims' contact points at s(w, i) (m from the taping
    !> line), as a time step sets them (vehicle_modal%modal_follow); the model keeps the
    !> taping line's. info: STAT_OK; STAT_BAD_HANDLE; STAT_SIZE_MISMATCH (nfr, np, nm not the
    !> model's); STAT_BAD_ARGUMENT (no rows that follow the contact point).
    subroutine vehicle_follow_rows(handle, nfr, s, np, nm, phi, info)
        integer, intent(in) :: handle, nfr, np, nm
        real(dp), intent(in) :: s(2, nfr)
        real(dp), intent(out) :: phi(np, nm)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        phi = 0.0_dp
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        info = STAT_SIZE_MISMATCH
        if (nfr /= md%mp%nfr .or. np /= md%mp%np .or. nm /= md%mp%nm) return
        info = STAT_BAD_ARGUMENT
        if (md%mp%fns == 0) return
        call modal_follow(md%mp, s)
        phi = md%mp%phi
        call modal_follow_reset(md%mp)
        info = STAT_OK
    end subroutine vehicle_follow_rows

    !> Put a model's wheelsets on the ring track (model RF); see vehicle_modal%modal_ring for
    !> the arguments and info, and STAT_BAD_HANDLE.
    subroutine vehicle_attach_ring(handle, nrl, rlw, rlpt, rm0, ng, nbt, nk, nvk, bpos, kpos, &
                                   voff, kap, fam, rail, obs, vk, crho, cx0, ctr, v0, length, info)
        integer, intent(in) :: handle, nrl, rm0, ng, nbt, nk, nvk
        integer, intent(in) :: rlw(nrl), rlpt(3, 2, nrl), bpos(ng + 1), kpos(ng + 1), voff(ng + 1)
        integer, intent(in) :: fam(nbt), rail(nbt), crho(2 * nrl)
        real(dp), intent(in) :: kap(nbt), obs(4, nbt), vk(nvk), cx0(2 * nrl), ctr(3, 4, 2 * nrl)
        real(dp), intent(in) :: v0, length
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        call modal_ring(md%mp, md%nw, nrl, rlw, rlpt, rm0, ng, nbt, nk, nvk, bpos, kpos, voff, kap, &
                        fam, rail, obs, vk, crho, cx0, ctr, v0, length, info)
    end subroutine vehicle_attach_ring

    !> Add the ring's residual flexibility at the contact points; see
    !> vehicle_modal%modal_ring_residual for the arguments and info, and STAT_BAD_HANDLE.
    subroutine vehicle_ring_residual(handle, nrx, bay, rtab, rpost, info)
        integer, intent(in) :: handle, nrx
        real(dp), intent(in) :: bay, rtab(3, 3, nrx, 2), rpost(3, 3, 2)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        call modal_ring_residual(md%mp, nrx, bay, rtab, rpost, info)
    end subroutine vehicle_ring_residual

    !> Set the ring rows of a model to time t (the wheels' contact points at x0 + v0 t): what the
    !> next force, tangent or static call sees. info: STAT_OK, STAT_BAD_HANDLE.
    subroutine vehicle_ring_time(handle, t, info)
        integer, intent(in) :: handle
        real(dp), intent(in) :: t
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        call modal_ring_time(md%mp, t)
        info = STAT_OK
    end subroutine vehicle_ring_time

    !> Put a model on an irregular track (vehicle_irregularity%irr_set's arguments, nw the
    !> model's wheelsets), or take it off (n = 0), at t = 0. info: STAT_OK, STAT_BAD_HANDLE,
    !> STAT_SIZE_MISMATCH (nw not the model's), irr_set's STAT_BAD_ARGUMENT.
    subroutine vehicle_attach_irregularity(handle, n, x, c, d, nw, xw, x0, v0, base, info)
        integer, intent(in) :: handle, n, nw
        real(dp), intent(in) :: x(n), c(4, n), d(4, n), xw(nw), x0, v0, base
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        type(irr_track) :: ir
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        info = STAT_SIZE_MISMATCH
        if (nw /= md%nw) return
        if (allocated(md%kmkey)) deallocate (md%kmkey)   ! a kept matrix belongs to the old track
        if (n == 0) then
            md%irr = irr_track()
            info = STAT_OK
            return
        end if
        call irr_set(n, x, c, d, nw, xw, x0, v0, base, ir, info)
        if (info == STAT_OK) md%irr = ir
    end subroutine vehicle_attach_irregularity

    !> The irregular track's inputs u (NIRR, 2, nw) under the wheels at time t (zero without
    !> one), as the time loop sets them. info: STAT_OK, STAT_BAD_HANDLE, STAT_SIZE_MISMATCH.
    subroutine vehicle_irregularity_inputs(handle, t, nw, u, info)
        integer, intent(in) :: handle, nw
        real(dp), intent(in) :: t
        real(dp), intent(out) :: u(NIRR, 2, nw)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        u = 0.0_dp
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        info = STAT_SIZE_MISMATCH
        if (nw /= md%nw) return
        if (md%irr%nw > 0) call irr_inputs(md%irr, t, u)
        info = STAT_OK
    end subroutine vehicle_irregularity_inputs

    !> Set what depends on time to time t: the ring rows (model RF) when ring, and the
    !> irregular track's inputs.
    subroutine model_time(md, t, ring)
        type(vmodel), intent(inout) :: md
        real(dp), intent(in) :: t
        logical, intent(in) :: ring
        if (ring) call modal_ring_time(md%mp, t)
        call irr_time(md%irr, t)
        call curve_time(md%cv, t)
    end subroutine model_time

    !> The model behind a handle for one call with the settings rs and arrays of nd DOFs, nw
    !> wheelsets and nwo outputs per wheel (nd: rigid plus modal DOFs, md%nd + md%mp%nm).
    !> info: STAT_OK; STAT_BAD_HANDLE (no such model);
    !> STAT_SIZE_MISMATCH (nd, nw or nwo not the model's); STAT_BAD_ARGUMENT (speed <= 0, an
    !> unknown contact model, CMODEL_BEM without a BEM handle, or a speed other than the
    !> attached curve's). md is null unless STAT_OK.
    subroutine vehicle_call(handle, nd, nw, nwo_in, rs, md, info)
        integer, intent(in) :: handle, nd, nw, nwo_in
        type(vsettings), intent(in) :: rs
        type(vmodel), pointer, intent(out) :: md
        integer, intent(out) :: info
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        info = STAT_SIZE_MISMATCH
        if (nd /= md%nd + md%mp%nm .or. nw /= md%nw .or. nwo_in /= nwo) then
            md => null()
            return
        end if
        info = STAT_BAD_ARGUMENT
        if (.not. (rs%v0 > 0.0_dp) .or. rs%cmodel < CMODEL_HERTZ_KALKER .or. &
            rs%cmodel > CMODEL_BEM .or. rs%fsn < 1 .or. (rs%cmodel == CMODEL_BEM .and. rs%bem <= 0) .or. &
            (md%cv%ns > 0 .and. abs(rs%v0 - md%cv%v0) > 1.0e-12_dp * md%cv%v0)) then
            md => null()
            return
        end if
        info = STAT_OK
    end subroutine vehicle_call

    !> Element e's deflection g.q and rate g.v, plus a curve's offsets of its bodies' frames
    !> (vehicle_curve).
    pure subroutine element_deflection(md, e, q, v, d, dd)
        type(vmodel), intent(in) :: md
        integer, intent(in) :: e
        real(dp), intent(in) :: q(:), v(:)
        real(dp), intent(out) :: d, dd
        d = dot_product(md%eg(:, e), q(1:md%nd))
        dd = dot_product(md%eg(:, e), v(1:md%nd))
        if (md%cv%ns > 0) then
            d = d + md%cv%d(e)
            dd = dd + md%cv%dd(e)
        end if
    end subroutine element_deflection

    !> Attach a curve's tables to a model for the runs that follow (ns = 0 drops it); see
    !> vehicle_curve%curve_set for the arguments and info, and STAT_BAD_HANDLE. t sets the
    !> current values (the statics' time).
    subroutine vehicle_attach_curve(handle, nd, ne, nw, ns, s0, ds, x0, v0, fext, doff, drate, kap, info)
        integer, intent(in) :: handle, nd, ne, nw, ns
        real(dp), intent(in) :: s0, ds, x0, v0
        real(dp), intent(in) :: fext(:, :), doff(:, :), drate(:, :), kap(:, :)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        if (ns == 0) then
            call curve_clear(md%cv)
            info = STAT_OK
            return
        end if
        info = STAT_SIZE_MISMATCH
        if (nd /= md%nd .or. ne /= md%ne .or. nw /= md%nw) return
        call curve_set(md%cv, nd, ne, nw, ns, s0, ds, x0, v0, fext, doff, drate, kap, info)
    end subroutine vehicle_attach_curve

    !> Add a curve's point forces gpt (np, ns) on the modal part's attachment points to the
    !> curve attached last (vehicle_curve%curve_points: flexible wheelsets, FR and FF). info:
    !> STAT_OK; STAT_BAD_HANDLE; STAT_SIZE_MISMATCH (np not the model's points, ns not the
    !> curve's nodes); STAT_BAD_ARGUMENT (no curve attached, a value not finite).
    subroutine vehicle_attach_curve_points(handle, np, ns, gpt, info)
        integer, intent(in) :: handle, np, ns
        real(dp), intent(in) :: gpt(:, :)
        integer, intent(out) :: info
        type(vmodel), pointer :: md
        md => vehicle_get(handle)
        info = STAT_BAD_HANDLE
        if (.not. associated(md)) return
        info = STAT_BAD_ARGUMENT
        if (md%cv%ns == 0) return
        info = STAT_SIZE_MISMATCH
        if (np /= md%mp%np .or. ns /= md%cv%ns) return
        call curve_points(md%cv, np, gpt, info)
    end subroutine vehicle_attach_curve_points

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

    !> Contact forces of wheelset w added into f. cheap: for a BEM run, each patch's linear
    !> model, or Hertz + Kalker calibrated by the last BEM solves (the tangent: modified Newton).
    !> With the attachment points' coordinates u, ud (model FR: u, ud, gp all present) a
    !> wheelset with flexible rims (vehicle_modal%modal_rim_wheelset) is evaluated on its
    !> deformed rims and the generalised forces on the rim points are added into gp.
    !> frictionless (optional, .true.): the contact with mu = 0, its normal (conservative)
    !> part only (vehicle_newmark's energy-conserving step). On an irregular track
    !> (md%irr, vehicle_irregularity) each wheel's rail element moves by the inputs set for
    !> the current time (model_time), on top of the ring's rail head (model RF).
    subroutine add_contact(md, rs, w, q, v, f, wout, info, cheap, u, ud, gp, slin, smode, frictionless)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        integer, intent(in) :: w
        real(dp), intent(in) :: q(:), v(:)
        real(dp), intent(inout) :: f(:)
        real(dp), intent(out) :: wout(nwo, 2)
        integer, intent(out) :: info
        logical, intent(in), optional :: cheap
        real(dp), intent(in), optional :: u(:), ud(:)
        real(dp), intent(inout), optional :: gp(:)
        type(strip_lin), intent(inout), optional :: slin(2)
        integer, intent(in), optional :: smode
        logical, intent(in), optional :: frictionless
        real(dp) :: qw(6), vw(6), qt(3), vt(3), fw(6), ft(3), rim(6, 2), frim(3, 2)
        real(dp) :: rail(6, 2), frail(3, 2), mu, arm(2, 2), ryaw(2), yf
        integer :: j, k, model, ir, il
        logical :: tng, onrail
        model = rs%cmodel
        mu = md%mu
        if (present(frictionless)) then
            if (frictionless) mu = 0.0_dp
        end if
        tng = .false.
        if (present(cheap)) tng = cheap
        call ws_state(md, w, q, v, qw, vw, qt, vt)
        yf = 0.0_dp          ! a curve's: the wheelset's track frame turns at v0 kappa
        if (md%cv%ns > 0) yf = rs%v0 * md%cv%k(w)
        ir = 0
        il = 0
        if (present(u) .and. present(ud) .and. present(gp)) then
            ir = modal_rim_wheelset(md%mp, w)
            il = modal_rail_wheelset(md%mp, w)
        end if
        if (ir > 0) then
            do k = 1, 2
                ! the rim point's arms: at the contact point's s when the rows follow it
                arm(1, k) = md%mp%frarm(1, ir) + md%mp%fsc(k, ir)
                arm(2, k) = md%mp%frarm(2, ir)
                rim(1:3, k) = u(md%mp%frpt(:, k, ir))
                rim(4:6, k) = ud(md%mp%frpt(:, k, ir))
                do j = 1, 3     ! Eulerian term: + Omega dW/dtheta
                    if (md%mp%frept(j, k, ir) > 0) rim(3 + j, k) = rim(3 + j, k) &
                        + md%mp%fromega(ir) * u(md%mp%frept(j, k, ir))
                end do
            end do
        end if
        if (il > 0) then
            ! the rail heads under the wheels (model RF): their material velocity Phi(x_c) Q'
            do k = 1, 2
                rail(1:3, k) = u(md%mp%rlpt(:, k, il))
                rail(4:6, k) = ud(md%mp%rlpt(:, k, il))
            end do
        end if
        ryaw = 0.0_dp
        onrail = il > 0
        if (md%irr%nw > 0) then
            ! the irregular track's rails under the wheels (vehicle_irregularity), at the time set
            if (il > 0) then
                rail = rail + md%irr%now(1:6, :, w)
            else
                rail = md%irr%now(1:6, :, w)
            end if
            ryaw = md%irr%now(7, :, w)
            onrail = .true.
        end if
        if (ir > 0 .and. onrail) then
            call wheelset_contact(md%ct, md%r0, rs%v0, md%gmod, mu, model, &
                                  rs%fsn, rs%bem, w, qw, vw, qt, vt, fw, ft, wout, info, &
                                  rim=rim, rarm=arm, frim=frim, st=md%st, &
                                  slin=slin, smode=smode, rail=rail, frail=frail, tangent=tng, &
                                  ryaw=ryaw, frame_yaw_rate=yf)
        else if (ir > 0) then
            call wheelset_contact(md%ct, md%r0, rs%v0, md%gmod, mu, model, &
                                  rs%fsn, rs%bem, w, qw, vw, qt, vt, fw, ft, wout, info, &
                                  rim=rim, rarm=arm, frim=frim, st=md%st, &
                                  slin=slin, smode=smode, tangent=tng, frame_yaw_rate=yf)
        else if (onrail) then
            call wheelset_contact(md%ct, md%r0, rs%v0, md%gmod, mu, model, &
                                  rs%fsn, rs%bem, w, qw, vw, qt, vt, fw, ft, wout, info, st=md%st, &
                                  slin=slin, smode=smode, rail=rail, frail=frail, tangent=tng, &
                                  ryaw=ryaw, frame_yaw_rate=yf)
        else
            call wheelset_contact(md%ct, md%r0, rs%v0, md%gmod, mu, model, &
                                  rs%fsn, rs%bem, w, qw, vw, qt, vt, fw, ft, wout, info, st=md%st, &
                                  slin=slin, smode=smode, tangent=tng, frame_yaw_rate=yf)
        end if
        do k = 1, 2
            if (ir > 0) gp(md%mp%frpt(:, k, ir)) = gp(md%mp%frpt(:, k, ir)) + frim(:, k)
            if (il > 0) gp(md%mp%rlpt(:, k, il)) = gp(md%mp%rlpt(:, k, il)) + frail(:, k)
        end do
        do j = 1, 6
            if (md%iws(j, w) > 0) f(md%iws(j, w)) = f(md%iws(j, w)) + fw(j)
        end do
        do j = 1, 3
            if (md%itr(j, w) > 0) f(md%itr(j, w)) = f(md%itr(j, w)) + ft(j)
        end do
    end subroutine add_contact

    !> The wheelsets' gyroscopic moments: the spin Omega = v0 / r0 about +y has the angular
    !> momentum H = I_y Omega (e_y - yaw e_x + roll e_z) (small rotations), and dH/dt = M gives
    !> the forces roll +I_y Omega yaw', yaw -I_y Omega roll' (docs/wheelset_flexible.md,
    !> "Equations for the integrator": the same skew term as the FE wheelset's rigid part).
    !> Added to f (at the rates v), or its rate derivative times cv to jac.
    pure subroutine add_gyroscopic(md, rs, v, cv, f, jac)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: v(md%nd), cv
        real(dp), intent(inout), optional :: f(md%nd), jac(md%nd, md%nd)
        real(dp) :: h
        integer :: w, ir, iy
        do w = 1, md%nw
            h = md%ispin(w) * rs%v0 / md%r0
            ir = md%iws(3, w)
            iy = md%iws(4, w)
            if (h == 0.0_dp .or. iy == 0) cycle
            if (present(f)) then
                f(ir) = f(ir) + h * v(iy)
                f(iy) = f(iy) - h * v(ir)
            end if
            if (present(jac)) then
                jac(ir, iy) = jac(ir, iy) + cv * h
                jac(iy, ir) = jac(iy, ir) - cv * h
            end if
        end do
    end subroutine add_gyroscopic

    !> Total force F(q, v); wout (nwo, 2, nw) the contact outputs per wheel. info:
    !> STAT_OUTSIDE_TABLE a wheelset left the contact table (derailment or a diverging
    !> solution); STAT_GRID_EDGE, STAT_CONTACT_NOT_CONVERGED a BEM patch reached its grid edge
    !> / a BEM solver did not converge (see vehicle_contact%wheelset_contact).
    !> u, ud, gp (optional, model FR): see add_contact.
    subroutine force_total(md, rs, q, v, f, wout, info, u, ud, gp)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: q(md%nd), v(md%nd)
        real(dp), intent(out) :: f(md%nd), wout(nwo, 2, md%nw)
        integer, intent(out) :: info
        real(dp), intent(in), optional :: u(:), ud(:)
        real(dp), intent(inout), optional :: gp(:)
        real(dp) :: d, dd, fe, kd, cd, fs(md%nd)
        real(dp), allocatable :: gs(:)
        integer :: e, w
        f = md%f0 - matmul(md%k, q) - matmul(md%c, v)
        if (md%cv%ns > 0) then
            f = f + md%cv%f
            if (md%cv%np > 0 .and. present(gp)) gp = gp + md%cv%p
        end if
        call add_gyroscopic(md, rs, v, 1.0_dp, f=f)
        do e = 1, md%ne
            call element_deflection(md, e, q, v, d, dd)
            call element_force(md%etype(e), md%epar(:, e), d, dd, fe, kd, cd)
            f = f - md%eg(:, e) * fe
        end do
        info = STAT_OK
        if (rs%cmodel == CMODEL_BEM) then
            ! the BEM patches of all wheels solved together (vehicle_bem, Threads): a pass
            ! that records them (its forces, on scratch fs, gs, are dropped), the solves, then
            ! the pass below reads them back
            fs = 0.0_dp
            if (present(gp)) gs = gp
            call bem_record(rs%bem)
            do w = 1, md%nw
                call add_contact(md, rs, w, q, v, fs, wout(:, :, w), info, u=u, ud=ud, gp=gs)
                if (info /= STAT_OK) exit
            end do
            call bem_solve_recorded(rs%bem)
            if (info /= STAT_OK) return
        end if
        do w = 1, md%nw
            call add_contact(md, rs, w, q, v, f, wout(:, :, w), info, u=u, ud=ud, gp=gp)
            if (info /= STAT_OK) return
        end do
    end subroutine force_total

    !> Tangent dF/dq + cv dF/dv at (q, v): the linear part exactly, the elements analytically,
    !> the contact by forward differences over each wheelset's own DOFs (up to 6 + 3 track),
    !> perturbing q by eps and v by cv eps together. With cv = 0 (or a second call with
    !> dq = 0) the two parts separate: mode TANGENT_QV -> dF/dq + cv dF/dv, TANGENT_V -> dF/dv.
    !> With the BEM contact (CMODEL_BEM) the contact part is that of each patch's linear model
    !> (vehicle_bem%bem_linear; else Hertz + Kalker scaled to the last BEM solves):
    !> add_contact's cheap, wheelset_contact's tangent; modified Newton.
    !> Model FR (u, ud at the attachment points and jru, jpr, jpu all present): the contact of
    !> a wheelset with flexible rims at the deformed rims, and its chain-rule blocks added to
    !> jru (nd x np), jpr (np x nd), jpu (np x np) by the same differences over the wheelset's
    !> DOFs and its six rim points (u by eps, ud by cv eps).
    subroutine tangent(md, rs, q, v, cv, mode, jac, info, u, ud, jru, jpr, jpu, cvp)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: q(md%nd), v(md%nd), cv
        integer, intent(in) :: mode
        real(dp), intent(out) :: jac(md%nd, md%nd)
        integer, intent(out) :: info
        real(dp), intent(in), optional :: u(:), ud(:)
        real(dp), intent(inout), optional :: jru(:, :), jpr(:, :), jpu(:, :)
        real(dp), intent(in), optional :: cvp(:)     !< the points' own dv/dx (contact_tangent)
        real(dp) :: d, dd, fe, kd, cd, s
        integer :: e, j
        if (mode == TANGENT_QV) then
            jac = -md%k - cv * md%c
            call add_gyroscopic(md, rs, v, cv, jac=jac)
        else
            jac = -md%c
            call add_gyroscopic(md, rs, v, 1.0_dp, jac=jac)
        end if
        do e = 1, md%ne
            call element_deflection(md, e, q, v, d, dd)
            call element_force(md%etype(e), md%epar(:, e), d, dd, fe, kd, cd)
            if (mode == TANGENT_QV) then
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
        if (present(u) .and. present(ud) .and. present(jru) .and. present(jpr) .and. present(jpu)) then
            call contact_tangent(md, rs, q, v, cv, mode, jac, info, u, ud, jru, jpr, jpu, cvp)
        else
            call contact_tangent(md, rs, q, v, cv, mode, jac, info)
        end if
    end subroutine tangent

    !> The contact part of tangent (added into jac; model FR: the rim blocks too). cvp
    !> (optional, np): the velocity perturbation of the point columns per unit displacement in
    !> place of cv (the exact modal step's dv/dx of the points, vehicle_modal_step).
    subroutine contact_tangent(md, rs, q, v, cv, mode, jac, info, u, ud, jru, jpr, jpu, cvp)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: q(md%nd), v(md%nd), cv
        integer, intent(in) :: mode
        real(dp), intent(inout) :: jac(md%nd, md%nd)
        integer, intent(out) :: info
        real(dp), intent(in), optional :: u(:), ud(:)
        real(dp), intent(inout), optional :: jru(:, :), jpr(:, :), jpu(:, :)
        real(dp), intent(in), optional :: cvp(:)
        real(dp) :: f0w(md%nd), f1w(md%nd), qp(md%nd), vp(md%nd), wout(nwo, 2), cvj
        type(strip_lin) :: sl(2)
        real(dp), allocatable :: g0(:), g1(:), up(:), udp(:)
        integer :: w, j, jj, idx(9), n, ir, pts(12), npt, cols(18), nc
        logical :: flex
        real(dp), parameter :: eps = 1.0e-8_dp
        flex = present(u)
        if (flex) then
            allocate (g0(md%mp%np), g1(md%mp%np))
            up = u
            udp = ud
        end if
        info = STAT_OK
        do w = 1, md%nw
            ir = 0
            if (flex) ir = modal_rim_wheelset(md%mp, w)
            call wheelset_coords(md, w, 6, idx, n, pts, npt)
            if (.not. flex) npt = 0
            f0w = 0.0_dp
            if (npt > 0) then
                g0 = 0.0_dp
                call add_contact(md, rs, w, q, v, f0w, wout, info, cheap=.true., u=u, ud=ud, gp=g0, &
                                 slin=sl, smode=SLIN_KEEP)
            else
                call add_contact(md, rs, w, q, v, f0w, wout, info, cheap=.true., slin=sl, smode=SLIN_KEEP)
            end if
            if (info /= STAT_OK) return
            do jj = 1, n
                j = idx(jj)
                call perturbed(q, v, j, mode, cv, eps, qp, vp)
                f1w = 0.0_dp
                if (npt > 0) then
                    g1 = 0.0_dp
                    call add_contact(md, rs, w, qp, vp, f1w, wout, info, cheap=.true., u=u, ud=ud, &
                                     gp=g1, slin=sl, smode=SLIN_READ)
                    jpr(pts(1:npt), j) = jpr(pts(1:npt), j) + (g1(pts(1:npt)) - g0(pts(1:npt))) / eps
                else
                    call add_contact(md, rs, w, qp, vp, f1w, wout, info, cheap=.true., slin=sl, &
                                     smode=SLIN_READ)
                end if
                if (info /= STAT_OK) return
                jac(idx(1:n), j) = jac(idx(1:n), j) + (f1w(idx(1:n)) - f0w(idx(1:n))) / eps
            end do
            if (npt == 0) cycle
            ! the rim and rail points' columns, and the rims' Eulerian points'
            cols(1:npt) = pts(1:npt)
            nc = npt
            do jj = 1, 6
                if (ir == 0) exit
                j = md%mp%frept(mod(jj - 1, 3) + 1, (jj - 1) / 3 + 1, ir)
                if (j > 0) then
                    nc = nc + 1
                    cols(nc) = j
                end if
            end do
            do jj = 1, nc
                j = cols(jj)
                cvj = cv
                if (present(cvp)) cvj = cvp(j)
                call perturbed(u, ud, j, mode, cvj, eps, up, udp)
                f1w = 0.0_dp
                g1 = 0.0_dp
                call add_contact(md, rs, w, q, v, f1w, wout, info, cheap=.true., u=up, ud=udp, gp=g1, &
                                 slin=sl, smode=SLIN_READ)
                if (info /= STAT_OK) return
                jru(idx(1:n), j) = jru(idx(1:n), j) + (f1w(idx(1:n)) - f0w(idx(1:n))) / eps
                jpu(pts(1:npt), j) = jpu(pts(1:npt), j) + (g1(pts(1:npt)) - g0(pts(1:npt))) / eps
            end do
        end do
    end subroutine contact_tangent

    !> The state (x, xd) with coordinate j perturbed for a forward difference of tangent's
    !> mode: TANGENT_QV moves x_j by eps and xd_j by cv eps together, TANGENT_V xd_j by eps.
    pure subroutine perturbed(x, xd, j, mode, cv, eps, xp, xdp)
        real(dp), intent(in) :: x(:), xd(:), cv, eps
        integer, intent(in) :: j, mode
        real(dp), intent(out) :: xp(:), xdp(:)
        xp = x
        xdp = xd
        if (mode == TANGENT_QV) then
            xp(j) = x(j) + eps
            xdp(j) = xd(j) + cv * eps
        else
            xdp(j) = xd(j) + eps
        end if
    end subroutine perturbed

    !> Whether DOF j is a wheelset spin perturbation beta (no stiffness: only its rate enters).
    pure logical function is_spin(md, j)
        type(vmodel), intent(in) :: md
        integer, intent(in) :: j
        is_spin = any(md%iws(6, :) == j)
    end function is_spin

    !> The state coordinates wheelset w's contact depends on: idx(1:nr) its first nwdof DOFs
    !> (y, z, roll, yaw, x and, with nwdof = 6, the spin angle) and its track element's,
    !> pts(1:npt) its rims' and rails' attachment points (models FR, RF; none without modes).
    pure subroutine wheelset_coords(md, w, nwdof, idx, nr, pts, npt)
        type(vmodel), intent(in) :: md
        integer, intent(in) :: w, nwdof
        integer, intent(out) :: idx(9), nr, pts(12), npt
        integer :: j, ir, il
        nr = 0
        do j = 1, nwdof
            if (md%iws(j, w) > 0) then
                nr = nr + 1
                idx(nr) = md%iws(j, w)
            end if
        end do
        do j = 1, 3
            if (md%itr(j, w) > 0) then
                nr = nr + 1
                idx(nr) = md%itr(j, w)
            end if
        end do
        npt = 0
        if (md%mp%nm == 0) return
        ir = modal_rim_wheelset(md%mp, w)
        il = modal_rail_wheelset(md%mp, w)
        if (ir > 0) then
            pts(1:6) = reshape(md%mp%frpt(:, :, ir), [6])
            npt = 6
        end if
        if (il > 0) then
            pts(npt + 1:npt + 6) = reshape(md%mp%rlpt(:, :, il), [6])
            npt = npt + 6
        end if
    end subroutine wheelset_coords

end module vehicle_model
