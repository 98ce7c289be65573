!> Implicit time integration of M a = F(q, v) and the static equilibrium F(q, 0) = 0.
!> Implements Newmark/HHT-alpha, the Zienkiewicz-Xie estimate and the energy-conserving midpoint
!> rule with Gonzalez's discrete gradient (Gonzalez 1996); no Kaiser equation.
!>
!> Newmark with HHT-alpha (Hilber, Hughes & Taylor 1977): alpha in [-1/3, 0],
!> beta = (1 - alpha)^2 / 4, gamma = 1/2 - alpha; alpha = 0 is the average acceleration
!> (trapezoidal) rule. Residual at t_{n+1}:  M a_{n+1} - (1 + alpha) F_{n+1} + alpha F_n = 0,
!> solved for q_{n+1} by Newton's method with the tangent of vehicle_model%tangent, refreshed
!> at the first iteration of each step and again when an iteration does not contract, and
!> Broyden's update in between (Kelley 1995, sec. 7.3). With the strip contact the matrix is
!> kept from step to step instead, carrying Broyden's update (keeps_matrix, broyden_matrix).
!> Local error estimate per step (Zienkiewicz & Xie 1991): e = h^2 |beta - 1/6| |a_{n+1} - a_n|.
!> Option SCHEME_ENERGY (hht_options%scheme): the midpoint rule M (v1 - v0) / h = F(x_m, v_m) +
!> F_dg, (x1 - x0) / h = (v0 + v1) / 2, with the discrete gradient F_dg of the contact potential
!> and the bump stops: an undamped frictionless run keeps its energy to the Newton tolerance
!> (energy_residual; docs/vehicle.md, "Energy-conserving integrator").
!>
!> Layers: newmark_run (the steps and the output) -> cover_step (one output step, cut into
!> 2^lev sub-steps when a step fails, or from the start while a wheel is in flange contact with
!> hht_options%flev > 0: flange_level) -> hht_step (one step: predictor, Newton, acceptance)
!> -> newton_iterate (tangent, solve, line_search) -> residual.
!>
!> The state is x = (q(1:nd), Q(1:nm)): the rigid DOFs of vehicle_model and the modal
!> coordinates of its modal blocks (vehicle_modal; nm = 0 for a rigid model). The modal rows
!> never enter a dense matrix: Newton's linear system is condensed onto the rigid DOFs and the
!> np attachment points (step_matrix, lin_solve; docs/vehicle_integrator.md), so a step costs
!> O(nd^3 + np^3 + nm (np + s)) for blocks of size s. With nm = 0 the arithmetic is exactly
!> that of the dense rigid integrator.
module vehicle_newmark
    use common_kinds, only: dp
    use common_lapack, only: dgetrf, dgetrs
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_SINGULAR, STAT_OUTSIDE_TABLE, &
                             STAT_GRID_EDGE, STAT_CONTACT_NOT_CONVERGED, STAT_MOTION_TOO_LARGE
    use vehicle_contact, only: nwo, IO_ARM, CMODEL_HERTZ_KALKER, CMODEL_HERTZ_FASTSIM
    use vehicle_model, only: vmodel, vsettings, force_total, tangent, is_spin, TANGENT_QV, TANGENT_V, &
                             add_contact, element_force, el_bump, wheelset_coords, model_time
    use vehicle_modal, only: modal_factor, modal_force, modal_point_tangent, modal_factorise, &
                             modal_solve, modal_points, modal_rows_t, modal_follow, &
                             modal_follow_reset
    use vehicle_modal_step, only: modal_step, modal_step_make, modal_step_begin, modal_step_velocity, &
                                  modal_step_residual, modal_step_accel, modal_step_matrices, &
                                  modal_step_cvp, modal_step_slot
    use vehicle_ring_step, only: ring_step_begin, ring_step_force, ring_step_accept, ring_step_flex, &
                                 ring_step_predict
    implicit none
    private
    public :: newmark_run, static_solve, state_force, hht_options, NSTATS, SCHEME_HHT, SCHEME_ENERGY
    public :: SCHEME_EXACT

    !> Time-stepping schemes (hht_options%scheme): HHT-alpha / Newmark (the default), and the
    !> energy-conserving midpoint rule with the discrete gradient of the contact potential
    !> (energy_residual; alpha is then 0), and the trapezoidal rule (alpha 0) with the modal
    !> blocks that have mass stepped exactly (vehicle_modal_step; the rigid DOFs and massless
    !> blocks as SCHEME_HHT).
    integer, parameter :: SCHEME_HHT = 0, SCHEME_ENERGY = 1, SCHEME_EXACT = 2
    !> The wheel output holding the contact's potential energy (vehicle_contact, J).
    integer, parameter :: IO_ENERGY = 9
    !> The wheel output holding the flange point's normal force (vehicle_contact, N).
    integer, parameter :: IO_NFLANGE = 5
    !> Length (m, rad) below which the discrete gradient's bracket fades out (contact_correction).
    real(dp), parameter :: DG_FLOOR = 1.0e-9_dp

    !> Length of newmark_run's stats.
    integer, parameter :: NSTATS = 10
    !> A full Newton correction at most this large (m, rad; and within the correction
    !> tolerance) is taken without a residual decrease: the residual is at its round-off
    !> there. Capped so that a run with the correction test switched off (a huge tol) keeps
    !> its line search (the defaults, 1e-9 and 1e-8, are below it).
    real(dp), parameter :: LS_SMALL = 1.0e-8_dp
    !> The ring track's stopping test from Newton's contraction (newton_iterate): taken when the
    !> observed contraction theta is below THETA_MAX and the correction at most LAG_MAX tol
    !> (the contact outputs of the accepted state, from the iterate before it, lag it by no more).
    real(dp), parameter :: THETA_MAX = 0.5_dp, LAG_MAX = 10.0_dp
    !> A kept matrix with modal blocks is renewed after a step of REFRESH_ITS or more Newton
    !> iterations once it has served REFRESH_AGE steps (refresh_due).
    integer, parameter :: REFRESH_ITS = 5, REFRESH_AGE = 10

    !> Settings of a run: HHT alpha, Newton tolerance on the correction (m, rad) and iteration
    !> limit, the deepest sub-step level (h / 2^maxsub), the bound on |q| (m, rad) and the
    !> Newton tolerance on the residual, max |r| (N, N m); the scheme (SCHEME_*).
    type :: hht_options
        real(dp) :: alpha = 0.0_dp, tol = 1.0e-9_dp, qmax = 1.0_dp
        integer :: maxit = 20, maxsub = 6
        real(dp) :: rtol = huge(1.0_dp)
        integer :: scheme = SCHEME_HHT
        !> SCHEME_EXACT on the ring track: the ring modes' moving rows at nodes + 1 nodes a
        !> step (vehicle_ring_step); 0: the rows at the step's ends only
        integer :: nodes = 0
        !> SCHEME_EXACT: a step that starts with a wheel in flange contact is taken as 2^flev
        !> sub-steps (flange_level); 0: never
        integer :: flev = 0
    end type hht_options

    !> Newton's linear system: the LU factors of the condensed step matrix (nd + np), and the
    !> point elements' tangent blocks needed to recover the modal increments.
    !> b: the rigid matrix before factoring (kept matrices: Broyden's update, newton_iterate).
    type :: newton_lin
        real(dp), allocatable :: a(:, :), jpr(:, :), jpu(:, :), b(:, :)
        integer, allocatable :: ipiv(:)
    end type newton_lin

    !> The state at the current time: q, v, a, F(q, v) and the contact outputs there (over
    !> the rigid and modal DOFs), and the modal factors of the last step size. keep: the
    !> iteration matrix is kept from step to step (keeps_matrix); nl its factors, made for
    !> the step size nlh (0: none).
    type :: hht_state
        real(dp), allocatable :: q(:), v(:), a(:), f(:), w(:, :, :)
        type(modal_factor) :: mf
        logical :: keep = .false.
        type(newton_lin) :: nl
        real(dp) :: nlh = 0.0_dp
        !> steps the kept matrix has served since it was made (refresh_due)
        integer :: kage = 0
        !> the exact modal step's matrices (SCHEME_EXACT) for the last step sizes: the model's
        !> cache (vmodel%msc) during a call
        type(modal_step), allocatable :: ms(:)
        integer :: msnext = 0
    end type hht_state

    !> Counters of a run, and `why`: the soft failure (STAT_OUTSIDE_TABLE, STAT_GRID_EDGE,
    !> STAT_CONTACT_NOT_CONVERGED) of the last trial state that had one in the current step.
    type :: hht_tally
        integer :: nit = 0, njac = 0, why = STAT_OK
        real(dp) :: maxerr = 0.0_dp, nsub = 0.0_dp, hmin = huge(1.0_dp)
        !> max |r| (N, N m) and max |dq| (m, rad) of the last Newton iteration of the last
        !> accepted step, and their maxima over the accepted steps.
        real(dp) :: rlast = 0.0_dp, rmax = 0.0_dp, dqlast = 0.0_dp, dqmax = 0.0_dp
    end type hht_tally

    !> The constants of one step of size h: HHT coefficients, cq = da/dq, cv = dv/dq, the
    !> predictor parts qt, vt (a_{n+1} = 0) and F_n. The energy-conserving scheme (energy):
    !> the start of the step x0, v0 and each wheelset's contact potential there, w0 (J).
    type :: hht_step_data
        real(dp) :: h = 0.0_dp, alpha = 0.0_dp, beta = 0.0_dp, gamma = 0.0_dp
        real(dp) :: cq = 0.0_dp, cv = 0.0_dp
        real(dp), allocatable :: qt(:), vt(:), fn(:)
        logical :: energy = .false.
        real(dp), allocatable :: x0(:), v0(:), w0(:)
        !> SCHEME_EXACT: the exact blocks' known part of the step (qh, vh;
        !> vehicle_modal_step%modal_step_begin; nm), and the state's step matrices
        logical :: exact = .false.
        real(dp), allocatable :: qh(:), vh(:)
        type(modal_step), pointer :: ms => null()
        !> the ring's moving rows (vehicle_ring_step): its end rows of Q / P less the model's, of V, g_n
        logical :: ring = .false.
        real(dp), allocatable :: dphi(:, :, :), phiv(:, :, :), gn(:, :)
    end type hht_step_data

contains

    !> Integrate nsteps steps of size h from (t, q, v, a), storing every nevery-th step.
    !> A step whose Newton iterations fail is retried as 2, 4, ... 2^maxsub sub-steps
    !> (contact closing or opening within the step); the output stays on the h grid.
    !> On return (t, q, v, a) is the last state reached. info: STAT_OK; STAT_NOT_CONVERGED
    !> (Newton did not converge even at h / 2^maxsub); STAT_OUTSIDE_TABLE (a wheelset left the
    !> contact table); STAT_MOTION_TOO_LARGE (non-finite state or |q| above qmax);
    !> STAT_GRID_EDGE, STAT_CONTACT_NOT_CONVERGED (a BEM patch at its grid edge / a BEM solver
    !> not converging, when they made the last sub-step fail); tfail the time of the failure.
    !> stats: 1 Newton iterations, 2 tangent evaluations, 3 max local error estimate
    !> (Zienkiewicz & Xie: h^2 |beta - 1/6| |a_{n+1} - a_n|, m or rad), 4 steps done,
    !> 5 steps that needed sub-steps, 6 smallest sub-step used (s), 7 and 8 max |r| (N, N m)
    !> after the last Newton iteration of the last accepted step and the largest over the
    !> accepted steps, 9 and 10 the same for the last correction max |dq| (m, rad).
    !> (f, w): the force F(q, v) and the wheel outputs of the state, carried from call to call
    !> like a: with carried = .false. they are evaluated at (q, v) first; on return they are
    !> those of the last accepted step (hht_step). A run split into calls therefore takes the
    !> same steps as one call: no extra force evaluation at a call's start, whose BEM solves
    !> would move the warm starts (and the forces by the solvers' tolerance) wherever a call
    !> begins (and the calls are sized by wall time).
    subroutine newmark_run(md, rs, h, nsteps, nevery, opt, t, q, v, a, f, w, carried, nout, tout, &
                           qout, vout, wout, stats, info, tfail)
        type(vmodel), intent(inout) :: md      ! the ring rows (model RF) follow the time
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: h
        integer, intent(in) :: nsteps, nevery, nout
        type(hht_options), intent(in) :: opt
        real(dp), intent(inout) :: t, q(md%nd + md%mp%nm), v(md%nd + md%mp%nm), a(md%nd + md%mp%nm)
        real(dp), intent(inout) :: f(md%nd + md%mp%nm), w(nwo, 2, md%nw)
        logical, intent(in) :: carried
        real(dp), intent(out) :: tout(nout), qout(md%nd + md%mp%nm, nout), vout(md%nd + md%mp%nm, nout)
        real(dp), intent(out) :: wout(nwo, 2, md%nw, nout), stats(NSTATS), tfail
        integer, intent(out) :: info
        type(hht_state), target :: st
        type(hht_tally) :: tally
        real(dp) :: tl
        integer :: n, io, ndone
        logical :: ok
        tout = 0.0_dp
        qout = 0.0_dp
        vout = 0.0_dp
        wout = 0.0_dp
        tfail = t
        tally%hmin = h
        io = 0
        ndone = 0
        allocate (st%q, source=q)
        allocate (st%v, source=v)
        allocate (st%a, source=a)
        allocate (st%f, source=f)
        allocate (st%w, source=w)
        if (opt%scheme == SCHEME_EXACT) then
            st%ms = md%msc
            st%msnext = md%mscnext
        end if
        call model_time(md, t, .true.)     ! the ring rows and an irregular track's inputs
        ! rims whose rows follow the contact point: at the taping line for the start's force
        ! when it is not carried, then each step at the carried state's contact points
        if (.not. carried) call modal_follow_reset(md%mp)
        st%keep = keeps_matrix(md, rs, opt)
        if (st%keep) call kept_matrix_load(md, rs, h, opt, st)
        ! a massless coordinate's a is its BDF2 acceleration from the last call (massless_rates;
        ! the caller starts it at 0): carried, so that splitting a run into calls (chunks
        ! sized by wall time) does not change it; f and w likewise
        info = STAT_OK
        if (.not. carried) call state_force(md, rs, q, v, st%f, st%w, info)
        if (info == STAT_OK) then
            do n = 1, nsteps
                tl = 0.0_dp
                tally%why = STAT_OK
                call cover_step(md, rs, t, h, flange_level(md, opt, st%w), opt, st, tally, tl, ok, info)
                if (info /= STAT_OK .or. .not. ok) then
                    info = run_failure(md, opt, st, info, tally%why)
                    tfail = t + tl + h / 2**opt%maxsub
                    exit
                end if
                t = t + h
                ndone = n
                if (mod(n, nevery) == 0 .and. io < nout) then
                    io = io + 1
                    tout(io) = t
                    qout(:, io) = st%q
                    vout(:, io) = st%v
                    wout(:, :, :, io) = st%w
                end if
            end do
        end if
        q = st%q
        v = st%v
        a = st%a
        f = st%f
        w = st%w
        if (allocated(md%kmkey)) deallocate (md%kmkey)
        if (st%keep .and. st%nlh > 0.0_dp) call kept_matrix_store(md, rs, opt, st)
        if (opt%scheme == SCHEME_EXACT) then
            md%msc = st%ms
            md%mscnext = st%msnext
        end if
        call modal_follow_reset(md%mp)     ! the statics and force shims see the taping line
        call model_time(md, 0.0_dp, .false.)   ! and an irregular track at t = 0
        call tally_stats(tally, ndone, stats)
    end subroutine newmark_run

    !> The sub-step level a step starts at: opt%flev (at most opt%maxsub) when the exact modal
    !> step (SCHEME_EXACT) starts with a wheel in flange contact (its flange point's normal
    !> force in the carried state's wheel outputs w positive), else 0. Why: the exact step takes
    !> the point forces as linear in time over the step, Newmark's beta = 1/6 for what the points
    !> couple to the modal blocks, stable only while sqrt(k_c) h <= sqrt(12) for a coupling
    !> stiffness k_c per unit modal mass (vehicle_modal_step); the flange's Hertz spring on the
    !> rims is beyond that at 1 ms and 0.5 ms and within it at 0.25 ms, the tread's is within
    !> it at 1 ms (docs/vehicle_integrator.md, "Exact modal step: sub-steps in flange
    !> contact"). A function of the carried state alone: the chunking of a run and its output
    !> sampling cannot change it. A sub-step that fails still refines further (cover_step).
    pure integer function flange_level(md, opt, w) result(lev)
        type(vmodel), intent(in) :: md
        type(hht_options), intent(in) :: opt
        real(dp), intent(in) :: w(nwo, 2, md%nw)
        lev = 0
        if (opt%scheme /= SCHEME_EXACT .or. opt%flev <= 0) return
        if (any(w(IO_NFLANGE, :, :) > 0.0_dp)) lev = min(opt%flev, opt%maxsub)
    end function flange_level

    !> Whether the time loop keeps its iteration matrix from step to step: with the strip
    !> contact and Hertz + Kalker or FASTSIM, HHT. The strip's tangent (one linearisation per
    !> wheel and the contact's forward differences) costs about two force evaluations, and in a
    !> settled or slowly varying motion the last step's matrix converges as fast as a fresh one
    !> (docs/vehicle.md "Strip contact", Cost): the rigid model carries Broyden's update, the
    !> models with modal blocks keep the condensed matrix as it is (modified Newton; its modal
    !> factors depend on the step size only, and a kept matrix that fails is replaced at once,
    !> hht_step, one that has aged after a slow step at the next, refresh_due). The table's
    !> tangent is cheap and the BEM's evaluations are dear: they refresh at every step as before.
    pure logical function keeps_matrix(md, rs, opt) result(keep)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        type(hht_options), intent(in) :: opt
        keep = md%st%on .and. (rs%cmodel == CMODEL_HERTZ_KALKER .or. rs%cmodel == CMODEL_HERTZ_FASTSIM) &
               .and. opt%scheme /= SCHEME_ENERGY
    end function keeps_matrix

    !> The key of a kept matrix: the state it continues from, its step size and the call's
    !> settings (a later call reads the matrix only when it continues from exactly these:
    !> the next chunk of the same run, so that the chunking cannot change the result).
    pure function kept_key(rs, opt, q, v, a, h) result(key)
        type(vsettings), intent(in) :: rs
        type(hht_options), intent(in) :: opt
        real(dp), intent(in) :: q(:), v(:), a(:), h
        real(dp) :: key(3 * size(q) + 6)
        key = [q, v, a, h, opt%alpha, rs%v0, real(rs%cmodel, dp), real(rs%fsn, dp), &
               real(opt%scheme + 16 * opt%nodes + 2048 * opt%flev, dp)]
    end function kept_key

    !> The matrix kept by the last call, when this call continues from its key with step h or
    !> one of its sub-steps h / 2^k (the step size the matrix was made for, kept in the key:
    !> a call that ended in sub-steps, e.g. in flange contact (flange_level), continues with
    !> them, as one call would) (with modal blocks also their factors for that step size: a
    !> function of it alone).
    subroutine kept_matrix_load(md, rs, h, opt, st)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: h
        type(hht_options), intent(in) :: opt
        type(hht_state), intent(inout), target :: st
        type(hht_step_data) :: sd
        integer :: info
        real(dp) :: hk
        if (.not. allocated(md%kmkey)) return
        if (size(md%kmkey) /= 3 * size(st%q) + 6) return
        hk = md%kmkey(3 * size(st%q) + 1)
        if (.not. (hk > 0.0_dp .and. hk <= h)) return
        if (.not. all(md%kmkey == kept_key(rs, opt, st%q, st%v, st%a, hk))) return
        if (md%mp%nm > 0) then
            call step_data(hk, opt%alpha, st, sd)
            if (opt%scheme == SCHEME_EXACT) call exact_data(md, hk, opt%nodes, st, sd)
            call factor_modal(md, sd, st%mf, info)
            if (info /= STAT_OK) return
            st%nl%jpr = md%kmjpr
            st%nl%jpu = md%kmjpu
        else
            st%nl%b = md%kma(:, :, 2)
        end if
        st%nl%a = md%kma(:, :, 1)
        st%nl%ipiv = md%kmpiv
        st%nlh = hk
        st%kage = md%kmage
    end subroutine kept_matrix_load

    !> Keep the time loop's matrix in the model with the key of the state it ended at.
    subroutine kept_matrix_store(md, rs, opt, st)
        type(vmodel), intent(inout) :: md
        type(vsettings), intent(in) :: rs
        type(hht_options), intent(in) :: opt
        type(hht_state), intent(in) :: st
        if (md%mp%nm > 0) then
            md%kma = reshape(st%nl%a, [size(st%nl%a, 1), size(st%nl%a, 2), 1])
            md%kmjpr = st%nl%jpr
            md%kmjpu = st%nl%jpu
        else
            md%kma = reshape([st%nl%a, st%nl%b], [size(st%nl%b, 1), size(st%nl%b, 2), 2])
        end if
        md%kmpiv = st%nl%ipiv
        md%kmage = st%kage
        md%kmkey = kept_key(rs, opt, st%q, st%v, st%a, st%nlh)
    end subroutine kept_matrix_store

    !> newmark_run's stats from the counters and the number of steps done.
    pure subroutine tally_stats(tally, nsteps_done, stats)
        type(hht_tally), intent(in) :: tally
        integer, intent(in) :: nsteps_done
        real(dp), intent(out) :: stats(NSTATS)
        stats(1) = real(tally%nit, dp)
        stats(2) = real(tally%njac, dp)
        stats(3) = tally%maxerr
        stats(4) = real(nsteps_done, dp)
        stats(5) = tally%nsub
        stats(6) = tally%hmin
        stats(7) = tally%rlast
        stats(8) = tally%rmax
        stats(9) = tally%dqlast
        stats(10) = tally%dqmax
    end subroutine tally_stats

    !> The status of a failed step: a Newton failure is reported as its cause where one is
    !> known (a BEM failure of the last trial state, a wheelset at the table's end), and a
    !> state beyond qmax or non-finite as STAT_MOTION_TOO_LARGE.
    integer function run_failure(md, opt, st, info, why) result(stat)
        type(vmodel), intent(in) :: md
        type(hht_options), intent(in) :: opt
        type(hht_state), intent(in) :: st
        integer, intent(in) :: info, why
        stat = info
        if (stat == STAT_OK) stat = STAT_NOT_CONVERGED
        if (stat == STAT_NOT_CONVERGED .and. (why == STAT_GRID_EDGE .or. &
                                              why == STAT_CONTACT_NOT_CONVERGED)) stat = why
        if (stat == STAT_NOT_CONVERGED .and. near_edge(md, st%q)) stat = STAT_OUTSIDE_TABLE
        if (too_big(md, st%q, st%v, opt%qmax)) stat = STAT_MOTION_TOO_LARGE
    end function run_failure

    !> A wheelset within 0.5 mm of the table's end (flange climb or divergence).
    pure logical function near_edge(md, q)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: q(md%nd + md%mp%nm)
        integer :: w
        real(dp) :: yr
        near_edge = .false.
        do w = 1, md%nw
            yr = q(md%iws(1, w))
            if (md%itr(1, w) > 0) yr = yr - q(md%itr(1, w))
            if (abs(yr) > -md%ct%u0 - 5.0e-4_dp) near_edge = .true.
        end do
    end function near_edge

    !> Cover the rest of one output step, h - tl, with sub-steps h / 2^lev, refining further
    !> on failure down to h / 2^maxsub; ok when the step is complete (tl = h). t0: the time at
    !> the output step's start; the ring rows (model RF) are set to each sub-step's end time.
    recursive subroutine cover_step(md, rs, t0, h, lev, opt, st, tally, tl, ok, info)
        type(vmodel), intent(inout) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: t0, h
        integer, intent(in) :: lev
        type(hht_options), intent(in) :: opt
        type(hht_state), intent(inout), target :: st
        type(hht_tally), intent(inout) :: tally
        real(dp), intent(inout) :: tl
        logical, intent(out) :: ok
        integer, intent(out) :: info
        real(dp) :: hl, err
        if (lev > 0) tally%nsub = tally%nsub + 1.0_dp
        hl = h / 2**lev
        tally%hmin = min(tally%hmin, hl)
        do while (tl < h - 0.5_dp * hl)
            call model_time(md, t0 + tl + hl, md%mp%nrl > 0)
            if (md%mp%fns > 0) call follow_contact(md, st%w)
            call hht_step(md, rs, hl, t0 + tl + hl, opt, st, tally, err, ok, info)
            if (info /= STAT_OK) then
                ok = .false.
                return
            end if
            if (.not. ok) then
                if (lev >= opt%maxsub) return
                call cover_step(md, rs, t0, h, lev + 1, opt, st, tally, tl, ok, info)
                return
            end if
            tl = tl + hl
            tally%maxerr = max(tally%maxerr, err)
        end do
        ok = .true.
    end subroutine cover_step

    !> The rims' rows at the contact points of the wheel outputs w (the last accepted state's:
    !> a function of the carried state, so that the chunking of a run cannot change it): each
    !> wheel's arm on the wheel (output 16) less the taping line's, s = 0 without contact
    !> (Kaiser eq. 3, the contact point moving on the flexible wheelset).
    subroutine follow_contact(md, w)
        type(vmodel), intent(inout) :: md
        real(dp), intent(in) :: w(nwo, 2, md%nw)
        real(dp) :: s(2, md%mp%nfr)
        integer :: i, k
        do i = 1, md%mp%nfr
            do k = 1, 2
                s(k, i) = 0.0_dp
                if (w(IO_ARM, k, md%mp%frw(i)) > 0.0_dp) &
                    s(k, i) = w(IO_ARM, k, md%mp%frw(i)) - md%mp%frarm(1, i)
            end do
        end do
        call modal_follow(md%mp, s)
    end subroutine follow_contact

    !> One HHT step of size h from st; on success (ok) st is advanced and err is the local
    !> error estimate. ok = .false. when Newton does not converge or the new state is too big
    !> (st unchanged). A trial state outside the table or with a failing BEM patch fails the
    !> step softly (recorded in tally%why, info STAT_OK): it is retried with sub-steps.
    subroutine hht_step(md, rs, h, t1, opt, st, tally, err, ok, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: h, t1    ! the step and its end time
        type(hht_options), intent(in) :: opt
        type(hht_state), intent(inout), target :: st
        type(hht_tally), intent(inout) :: tally
        real(dp), intent(out) :: err
        logical, intent(out) :: ok
        integer, intent(out) :: info
        type(hht_step_data) :: sd
        real(dp), dimension(md%nd + md%mp%nm) :: q1, v1, a1, r, f1
        real(dp) :: rn, w1(nwo, 2, md%nw), dq, vn(md%mp%nm)
        logical :: conv, stale, valid, rok
        integer :: nit0, njac0
        ok = .false.
        err = 0.0_dp
        nit0 = tally%nit
        njac0 = tally%njac
        call step_data(h, opt%alpha, st, sd)
        if (opt%scheme == SCHEME_ENERGY) call energy_data(md, h, st, sd)
        if (opt%scheme == SCHEME_EXACT) call exact_data(md, h, opt%nodes, st, sd)
        if (sd%exact .and. opt%nodes > 0) call ring_data(md, h, t1, st, sd)
        q1 = st%q + h * st%v + 0.5_dp * h * h * st%a       ! start: constant acceleration
        ! the ring's modes from the point forces held (their rows move; RF centred at 1 ms, 0.6 s:
        ! 2548 -> 2404 Newton iterations)
        if (sd%ring) call ring_step_predict(md%mp, sd%ms, sd%qh, sd%dphi, sd%gn, q1(md%nd + 1:))
        call residual(md, rs, sd, q1, r, rn, f1, w1, info)
        if (info /= STAT_OK) then
            if (soft(info, tally)) info = STAT_OK   ! e.g. a start outside the table: retried
            return
        end if
        ! a matrix kept from the last step of this size (keeps_matrix), or a fresh one
        stale = st%keep .and. st%nlh == h
        call newton_iterate(md, rs, sd, opt, q1, r, rn, f1, w1, st%mf, st%nl, stale, st%keep, tally, dq, &
                            conv, valid, info)
        if (info == STAT_OK .and. .not. conv .and. stale) then
            ! the kept matrix failed: once more from the start with a fresh one
            q1 = st%q + h * st%v + 0.5_dp * h * h * st%a
            if (sd%ring) call ring_step_predict(md%mp, sd%ms, sd%qh, sd%dphi, sd%gn, q1(md%nd + 1:))
            call residual(md, rs, sd, q1, r, rn, f1, w1, info)
            if (info /= STAT_OK) then
                if (soft(info, tally)) info = STAT_OK
                return
            end if
            call newton_iterate(md, rs, sd, opt, q1, r, rn, f1, w1, st%mf, st%nl, .false., st%keep, tally, &
                                dq, conv, valid, info)
        end if
        st%nlh = 0.0_dp
        if (st%keep .and. valid) st%nlh = h
        ! the kept matrix's age in steps (made in this step: 1), and whether it is renewed
        if (tally%njac /= njac0) st%kage = 0
        st%kage = st%kage + 1
        if (st%keep .and. refresh_due(md, st%kage, tally%nit - nit0)) st%nlh = 0.0_dp
        if (info /= STAT_OK .or. .not. conv) return
        if (sd%energy) then
            ! midpoint rule: (x1 - x0) / h = (v0 + v1) / 2; a: the step's mean acceleration
            ! (the predictor's only; no alternating error carried)
            v1 = 2.0_dp * (q1 - st%q) / h - st%v
            a1 = (v1 - st%v) / h
        else
            a1 = sd%cq * (q1 - sd%qt)
            v1 = sd%vt + sd%gamma * h * a1
        end if
        if (sd%exact) then
            call modal_step_velocity(md%mp, sd%ms, sd%qh, sd%vh, q1(md%nd + 1:), v1(md%nd + 1:))
            call modal_step_accel(md%mp, sd%ms, sd%qh, q1(md%nd + 1:), v1(md%nd + 1:), a1(md%nd + 1:))
            if (sd%ring) then     ! the ring modes' end velocity from their rows of V
                vn = v1(md%nd + 1:)
                call ring_step_accept(md%mp, sd%ms, sd%vh, sd%dphi, sd%phiv, sd%gn, q1(md%nd + 1:), vn, &
                                      f1(md%nd + 1:), v1(md%nd + 1:), a1(md%nd + 1:), rok)
                if (.not. rok) return
            end if
        end if
        if (md%mp%nm > 0) call massless_rates(md, h, st%q, st%v, st%a, q1, v1, a1)
        if (too_big(md, q1, v1, opt%qmax)) return
        err = h * h * abs(sd%beta - 1.0_dp / 6.0_dp) * maxval(abs(a1 - st%a))
        st%q = q1
        st%v = v1
        st%a = a1
        st%f = f1      ! F(q1, v1) from the accepted residual: no extra (BEM) evaluation
        st%w = w1
        tally%rlast = maxval(abs(r))
        tally%dqlast = dq
        tally%rmax = max(tally%rmax, tally%rlast)
        tally%dqmax = max(tally%dqmax, dq)
        ok = .true.
    end subroutine hht_step

    !> Whether a kept matrix is replaced by a fresh one at the next step: with modal blocks,
    !> after a step that took nit >= REFRESH_ITS Newton iterations with a matrix that has served
    !> age >= REFRESH_AGE steps (its contact linearisation has aged against the compliant rims
    !> and rails). FF hunting at 300 km/h, 1 s (its a step, tangents): 4.39, 23 -> 3.64, 50;
    !> refreshing more often (4 iterations, 6 steps: 2.92, 262) costs more in tangents than it
    !> saves (docs/speed_accuracy.md, "Where the time goes"). The rigid model keeps Broyden's.
    pure logical function refresh_due(md, age, nit) result(due)
        type(vmodel), intent(in) :: md
        integer, intent(in) :: age, nit
        due = md%mp%nm > 0 .and. nit >= REFRESH_ITS .and. age >= REFRESH_AGE
    end function refresh_due

    !> Massless modal coordinates (a residual flexibility, vehicle_modal) are algebraic: the
    !> Newmark rate 2 dx / h - v_n of such a coordinate would carry an undamped alternating
    !> error and its acceleration a growing one. After each step their rate and acceleration
    !> are set from positions only, by the three-point (BDF2) derivative: with the step's mean
    !> rate m1 = dx / h and the previous step's m0 = v0 - h a0 / 2 (the same h assumed),
    !> a1 = (m1 - m0) / h and v1 = m1 + h a1 / 2 = (3 x1 - 4 x0 + x_-1) / (2 h). Nothing is
    !> carried from the Newmark rates (no memory), and the next step's Newmark rate within
    !> the step, from these v1 and a1, is second-order accurate; its derivative is still cv
    !> (the tangent stays consistent).
    pure subroutine massless_rates(md, h, q0, v0, a0, q1, v1, a1)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: h
        real(dp), dimension(md%nd + md%mp%nm), intent(in) :: q0, v0, a0, q1
        real(dp), intent(inout) :: v1(md%nd + md%mp%nm), a1(md%nd + md%mp%nm)
        real(dp) :: m0, m1
        integer :: j, i
        do j = 1, md%mp%nm
            if (md%mp%mass(j) /= 0.0_dp) cycle
            i = md%nd + j
            m1 = (q1(i) - q0(i)) / h
            m0 = v0(i) - 0.5_dp * h * a0(i)
            a1(i) = (m1 - m0) / h
            v1(i) = m1 + 0.5_dp * h * a1(i)
        end do
    end subroutine massless_rates

    !> HHT coefficients and predictor of a step of size h from st.
    pure subroutine step_data(h, alpha, st, sd)
        real(dp), intent(in) :: h, alpha
        type(hht_state), intent(in) :: st
        type(hht_step_data), intent(out) :: sd
        sd%h = h
        sd%alpha = alpha
        sd%beta = 0.25_dp * (1.0_dp - alpha)**2
        sd%gamma = 0.5_dp - alpha
        sd%cq = 1.0_dp / (sd%beta * h * h)
        sd%cv = sd%gamma / (sd%beta * h)
        sd%qt = st%q + h * st%v + h * h * (0.5_dp - sd%beta) * st%a   ! the a_{n+1} = 0 part
        sd%vt = st%v + h * (1.0_dp - sd%gamma) * st%a
        sd%fn = st%f
    end subroutine step_data

    !> Newton's method on the step's residual from q1 (residual r, norm rn, force f1 and
    !> outputs w1 there), with backtracking. The iteration matrix (step_matrix) is factored at
    !> the first iterate and again after a damped step or a growing correction; between
    !> refreshes each full step updates it by Broyden's rank-one ("good") formula (broyden_step),
    !> so that an inexact matrix (the BEM's cheap model, a tangent from an earlier iterate)
    !> still converges superlinearly. conv: at the current iterate (the start, or the end of a
    !> full step) the residual is below opt%rtol (max |r|, N or N m) AND the next correction
    !> is below opt%tol (m, rad). That correction is then added without evaluating the force
    !> at its end: the state is as accurate as after the old test "the last correction, taken
    !> and evaluated, was below tol" (its error is the correction's own, second order), one
    !> evaluation earlier; f1, w1 and r stay those of the iterate before it, within tol of the
    !> state (with alpha = 0, F_n does not enter the next step). dq is that correction, max |dq|.
    !> The energy scheme evaluates it (its error is the work of the last residual, one-sided
    !> with modified Newton: model FR at tol 1e-9, 2.6e-5 of the kick's energy over 1 s
    !> without the evaluated correction, 2.8e-7 over 0.5 s with).
    !> On the ring track (models RF/FF, the trapezoidal modal step, upd) the kept matrix contracts
    !> linearly (the contact's tangent ages with the sleeper passing: RF centred at 300 km/h,
    !> theta ~0.01-0.1 an iteration), and the correction test also passes when the error left
    !> after the correction, estimated from the observed contraction theta = |dq_k| / |dq_(k-1)|
    !> (two full corrections with the same factors), is below tol: theta / (1 - theta) |dq_k|
    !> <= tol (Hairer & Wanner 1996, Solving ODEs II, sec. IV.8, the simplified Newton's
    !> stopping criterion), with theta < THETA_MAX and |dq_k| <= LAG_MAX tol. The state is then
    !> within about tol of the solution (the plain test leaves ~theta tol), f1 and w1 within
    !> LAG_MAX tol: RF/FF 2 s at 300 km/h, 15-20 % fewer iterations (docs/speed_accuracy.md,
    !> "The ring's Newton stopping test"). The exact modal steps keep the plain test (at 1 ms
    !> the estimate left exact-moving's wheelset spin angle 3.2e-8 rad from its converged run,
    !> against 3.3e-9 with the plain test), and so do the runs that make a fresh matrix every
    !> step (the BEM, the contact tables: not keeps_matrix).
    subroutine newton_iterate(md, rs, sd, opt, q1, r, rn, f1, w1, mf, nl, stale, upd, tally, dq, conv, &
                              valid, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        type(hht_step_data), intent(in) :: sd
        type(hht_options), intent(in) :: opt
        real(dp), dimension(md%nd + md%mp%nm), intent(inout) :: q1, r, f1
        real(dp), intent(inout) :: rn, w1(nwo, 2, md%nw)
        type(modal_factor), intent(inout) :: mf
        type(newton_lin), intent(inout) :: nl
        logical, intent(in) :: stale, upd
        type(hht_tally), intent(inout) :: tally
        real(dp), intent(out) :: dq
        logical, intent(out) :: conv, valid
        integer, intent(out) :: info
        real(dp) :: dqv(md%nd + md%mp%nm), dqold, sl, dqn, dqprev, theta
        real(dp) :: steps(md%nd + md%mp%nm, opt%maxit + 1), ys(md%nd + md%mp%nm, opt%maxit + 1)
        real(dp) :: rold(md%nd + md%mp%nm)
        integer :: it, lin, ns
        logical :: fresh, full, est
        conv = .false.
        info = STAT_OK
        dqold = huge(1.0_dp)
        dq = huge(1.0_dp)
        fresh = stale         ! a kept matrix (hht_step) is used as if made at the start
        valid = stale
        full = .true.          ! the current iterate is the start or the end of a full step
        ns = 0                 ! full steps since the factors were made (Broyden's memory)
        dqprev = huge(1.0_dp)  ! the last full correction with the current factors
        do it = 1, opt%maxit + 1
            if (.not. fresh) then
                valid = .false.
                call step_matrix(md, rs, sd, q1, mf, nl, lin, tally, info)
                if (info /= STAT_OK) return
                fresh = .true.
                ns = 0
                dqprev = huge(1.0_dp)
                if (lin /= 0) return
                valid = .true.
            end if
            call lin_solve(md, sd, mf, nl, r, dqv)
            call broyden_step(steps, ns, dqv)
            dqn = maxval(abs(dqv))
            if (.not. (dqn <= opt%qmax)) return
            ! the ring track: the error left after this correction from the contraction (above)
            est = .false.
            if (upd .and. md%mp%nrl > 0 .and. full .and. .not. sd%exact .and. dqprev < huge(1.0_dp)) then
                theta = dqn / dqprev
                est = theta < THETA_MAX .and. dqn <= LAG_MAX * opt%tol
                if (est) est = theta / (1.0_dp - theta) * dqn <= opt%tol
            end if
            if (full) dqprev = dqn
            if (full .and. (dqn <= opt%tol .or. est) .and. maxval(abs(r)) <= opt%rtol) then
                dq = dqn
                conv = .true.
                if (.not. sd%energy) then
                    q1 = q1 + dqv      ! the last correction, not evaluated (see above)
                    exit
                end if
                call line_search(md, rs, sd, dqv, opt%tol, q1, r, rn, f1, w1, sl, tally, info)
                tally%nit = tally%nit + 1
                conv = info == STAT_OK .and. sl > 0.0_dp
                exit
            end if
            if (it > opt%maxit) exit
            rold = r
            call line_search(md, rs, sd, dqv, opt%tol, q1, r, rn, f1, w1, sl, tally, info)
            tally%nit = tally%nit + 1
            if (info /= STAT_OK .or. sl == 0.0_dp) return
            dq = sl * dqn
            full = sl == 1.0_dp
            if (full) then
                ns = ns + 1
                steps(:, ns) = dqv
                ys(:, ns) = rold - r      ! the matrix's secant condition: B s = r_old - r
            end if
            ! a damped step or a growing correction: new factors at this iterate
            if (.not. full .or. dq > dqold) fresh = .false.
            dqold = dq
        end do
        ! a matrix kept for the next step (upd, rigid model) carries this step's updates
        if (conv .and. upd .and. valid .and. ns > 0 .and. md%mp%nm == 0) &
            call broyden_matrix(md%nd, steps, ys, ns, nl, valid)
    end subroutine newton_iterate

    !> Broyden's "good" update in direct form of the kept rigid matrix B (nl%b) by the full
    !> steps s_j of a converged step and their residual changes y_j (B s_j = y_j after each):
    !>   B <- B + (y_j - B s_j) s_j^T / |s_j|^2,  j = 1 .. ns,
    !> then factored again (nl%a). In exact arithmetic the matrix whose inverse newton_iterate's
    !> inverse-form updates applied (broyden_step), so the next step continues the same
    !> secant sequence instead of restarting from the last tangent. valid false when B turns
    !> singular (the next step then makes a fresh one).
    subroutine broyden_matrix(nd, steps, ys, ns, nl, valid)
        integer, intent(in) :: nd, ns
        real(dp), intent(in) :: steps(:, :), ys(:, :)
        type(newton_lin), intent(inout) :: nl
        logical, intent(inout) :: valid
        real(dp) :: u(nd)
        integer :: j, k, lin
        do j = 1, ns
            u = (ys(1:nd, j) - matmul(nl%b, steps(1:nd, j))) / dot_product(steps(1:nd, j), steps(1:nd, j))
            do k = 1, nd
                nl%b(:, k) = nl%b(:, k) + u * steps(k, j)
            end do
        end do
        nl%a = nl%b
        call dgetrf(nd, nd, nl%a, nd, nl%ipiv, lin)
        if (lin /= 0) valid = .false.
    end subroutine broyden_matrix

    !> Broyden's "good" update in inverse form (Kelley 1995, Iterative Methods for Linear and
    !> Nonlinear Equations, sec. 7.3, eq. 7.41): with H0 the factored matrix's inverse and the
    !> full steps s_0 .. s_(n-1) taken since (steps(:, 1:ns)), the next step is
    !>   z = H0 r;  z <- z + s_(j+1) (s_j . z) / |s_j|^2, j = 0 .. n-2;
    !>   s_n = z / (1 - s_(n-1) . z / |s_(n-1)|^2).
    !> On entry dx = H0 r, on return the updated step. When the denominator is near zero the
    !> memory is dropped (ns = 0) and dx stays H0 r: Broyden restarted at this iterate.
    pure subroutine broyden_step(steps, ns, dx)
        real(dp), intent(in) :: steps(:, :)
        integer, intent(inout) :: ns
        real(dp), intent(inout) :: dx(:)
        real(dp) :: z(size(dx)), den
        integer :: j
        if (ns == 0) return
        z = dx
        do j = 1, ns - 1
            z = z + steps(:, j + 1) * (dot_product(steps(:, j), z) / dot_product(steps(:, j), steps(:, j)))
        end do
        den = 1.0_dp - dot_product(steps(:, ns), z) / dot_product(steps(:, ns), steps(:, ns))
        if (abs(den) < 0.1_dp) then
            ns = 0
            return
        end if
        dx = z / den
    end subroutine broyden_step

    !> The LU factors of the step's iteration matrix cq M - (1 + alpha) dF/dq|_{cv} at q1,
    !> condensed onto the rigid DOFs and the attachment points (docs/vehicle_integrator.md):
    !>   [ cq M - (1+alpha)(J + Jrr)      -(1+alpha) Jru          ] [dq]   [r_r        ]
    !>   [ -(1+alpha) C Jpr               I - (1+alpha) C Jpu     ] [du] = [Phi S^-1 r_m]
    !> with S = cq I + (1+alpha)(cv B + K_m) factored per block and C = Phi S^-1 Phi^T (kept in
    !> mf while the step size stays); without modal blocks the plain rigid matrix.
    !> lin /= 0 when it is singular. A soft failure inside the tangent is recorded and the
    !> (partial) tangent used.
    subroutine step_matrix(md, rs, sd, q1, mf, nl, lin, tally, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        type(hht_step_data), intent(in) :: sd
        real(dp), intent(in) :: q1(md%nd + md%mp%nm)
        type(modal_factor), intent(inout) :: mf
        type(newton_lin), intent(inout) :: nl
        integer, intent(out) :: lin
        type(hht_tally), intent(inout) :: tally
        integer, intent(out) :: info
        real(dp) :: a1(md%nd + md%mp%nm), v1(md%nd + md%mp%nm), jac(md%nd, md%nd)
        real(dp) :: jru(md%nd, md%mp%np), jcru(md%nd, md%mp%np), jcpr(md%mp%np, md%nd)
        real(dp) :: jcpu(md%mp%np, md%mp%np), xe(md%nd + md%mp%nm), cvp(md%mp%np)
        real(dp) :: cf(md%mp%np, md%mp%np)
        integer :: nd, np, nt, i
        nd = md%nd
        np = md%mp%np
        nt = nd + np
        lin = 0
        if (sd%energy) then
            ! the midpoint rule's residual (energy_residual, scaled by 2) has this same matrix
            ! at the midpoint (x0 + x1) / 2, (x1 - x0) / h: cq = 4 / h^2, cv = 2 / h
            xe = 0.5_dp * (sd%x0 + q1)
            v1 = (q1 - sd%x0) / sd%h
        else
            xe = q1
            a1 = sd%cq * (q1 - sd%qt)
            v1 = sd%vt + sd%gamma * sd%h * a1
            if (sd%exact) call modal_step_velocity(md%mp, sd%ms, sd%qh, sd%vh, q1(nd + 1:), v1(nd + 1:))
        end if
        cvp = sd%cv
        if (sd%exact) then      ! the points' own dv/dx: the factors first (kept for the step)
            call factor_modal(md, sd, mf, info)
            if (info /= STAT_OK) then
                info = STAT_OK
                lin = 1
                return
            end if
            call modal_step_cvp(md%mp, sd%ms, mf%c, sd%cv, cvp)
        end if
        if (md%mp%nfr > 0 .or. md%mp%nrl > 0) then
            call full_tangent(md, rs, xe, v1, sd%cv, TANGENT_QV, jac, jcru, jcpr, jcpu, info, cvp)
        else
            call tangent(md, rs, xe(1:nd), v1(1:nd), sd%cv, TANGENT_QV, jac, info)
        end if
        if (soft(info, tally)) info = STAT_OK
        if (info /= STAT_OK) return
        if (.not. allocated(nl%a)) allocate (nl%a(nt, nt), nl%ipiv(nt), nl%jpr(np, nd), nl%jpu(np, np))
        if (md%mp%nm > 0) then
            call modal_point_tangent(md%mp, nd, xe(1:nd), v1(1:nd), xe(nd + 1:), v1(nd + 1:), sd%cv, &
                                     jac, jru, nl%jpr, nl%jpu, cvp)
            if (md%mp%nfr > 0 .or. md%mp%nrl > 0) then
                jru = jru + jcru
                nl%jpr = nl%jpr + jcpr
                nl%jpu = nl%jpu + jcpu
            end if
            call factor_modal(md, sd, mf, info)
            if (info /= STAT_OK) then   ! a singular modal block: Newton fails, sub-steps follow
                info = STAT_OK
                lin = 1
                return
            end if
            cf = mf%c
            if (sd%ring) call ring_step_flex(md%mp, sd%ms, sd%dphi, cf)   ! C = Phi P phie^T
            nl%a(1:nd, nd + 1:nt) = -(1.0_dp + sd%alpha) * jru
            nl%a(nd + 1:nt, 1:nd) = -(1.0_dp + sd%alpha) * matmul(cf, nl%jpr)
            nl%a(nd + 1:nt, nd + 1:nt) = -(1.0_dp + sd%alpha) * matmul(cf, nl%jpu)
            do i = nd + 1, nt
                nl%a(i, i) = nl%a(i, i) + 1.0_dp
            end do
        end if
        nl%a(1:nd, 1:nd) = sd%cq * md%m - (1.0_dp + sd%alpha) * jac
        if (np == 0) nl%b = nl%a
        call dgetrf(nt, nt, nl%a, nt, nl%ipiv, lin)
        tally%njac = tally%njac + 1
    end subroutine step_matrix

    !> Newton's correction dx from the residual r with the factors of step_matrix: the modal
    !> rows' S^-1 r_m, condensed onto the points, the (nd + np) solve, then the modal
    !> increments dQ = S^-1 (r_m + (1+alpha) Phi^T (Jpr dq + Jpu du)). O(nm (np + s)).
    subroutine lin_solve(md, sd, mf, nl, r, dx)
        type(vmodel), intent(in) :: md
        type(hht_step_data), intent(in) :: sd
        type(modal_factor), intent(in) :: mf
        type(newton_lin), intent(in) :: nl
        real(dp), intent(in) :: r(md%nd + md%mp%nm)
        real(dp), intent(out) :: dx(md%nd + md%mp%nm)
        real(dp) :: z(md%mp%nm), y(md%nd + md%mp%np), w(md%mp%np)
        integer :: nd, np, nm, lin
        nd = md%nd
        np = md%mp%np
        nm = md%mp%nm
        if (nm == 0) then
            dx = r
            call dgetrs('N', nd, 1, nl%a, nd, nl%ipiv, dx, nd, lin)
            return
        end if
        z = r(nd + 1:)
        call modal_solve(md%mp, mf, z)
        y(1:nd) = r(1:nd)
        call modal_points(md%mp, z, y(nd + 1:))
        call dgetrs('N', nd + np, 1, nl%a, nd + np, nl%ipiv, y, nd + np, lin)
        dx(1:nd) = y(1:nd)
        w = (1.0_dp + sd%alpha) * (matmul(nl%jpr, y(1:nd)) + matmul(nl%jpu, y(nd + 1:)))
        call modal_rows_t(md%mp, w, dx(nd + 1:))
        if (sd%ring) call ring_step_force(md%mp, sd%dphi, w, dx(nd + 1:))   ! phie^T w on the ring
        call modal_solve(md%mp, mf, dx(nd + 1:))
        dx(nd + 1:) = dx(nd + 1:) + z
    end subroutine lin_solve

    !> Backtracking on the residual norm along the Newton correction dqv (contact closing or
    !> opening makes full steps cycle): halve up to 5 times until the norm drops. A full step
    !> below the tolerance tol (m, rad) is taken even when the norm does not drop: the residual
    !> is then at its rounding floor (a linear system after one iteration). On
    !> acceptance q1, r, rn, f1, w1 move to the new point and sl is the step length taken;
    !> sl = 0 when every trial state failed softly.
    subroutine line_search(md, rs, sd, dqv, tol, q1, r, rn, f1, w1, sl, tally, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        type(hht_step_data), intent(in) :: sd
        real(dp), intent(in) :: dqv(md%nd + md%mp%nm), tol
        real(dp), dimension(md%nd + md%mp%nm), intent(inout) :: q1, r, f1
        real(dp), intent(inout) :: rn, w1(nwo, 2, md%nw)
        real(dp), intent(out) :: sl
        type(hht_tally), intent(inout) :: tally
        integer, intent(out) :: info
        real(dp), dimension(md%nd + md%mp%nm) :: qtry, rtry, ftry
        real(dp) :: rnt, wtry(nwo, 2, md%nw)
        integer :: ls
        sl = 1.0_dp
        do ls = 1, 6
            qtry = q1 + sl * dqv
            call residual(md, rs, sd, qtry, rtry, rnt, ftry, wtry, info)
            if (soft(info, tally)) then
                info = STAT_OK
                rnt = huge(1.0_dp)
            end if
            if (info /= STAT_OK) return
            if (rnt < rn .or. ls == 6) exit
            if (ls == 1 .and. rnt < huge(1.0_dp) .and. maxval(abs(dqv)) <= min(tol, LS_SMALL)) exit
            sl = 0.5_dp * sl
        end do
        if (rnt == huge(1.0_dp)) then
            sl = 0.0_dp
            return
        end if
        q1 = qtry
        r = rtry
        rn = rnt
        f1 = ftry
        w1 = wtry
    end subroutine line_search

    !> Residual -(M a - (1 + alpha) F(q, v) + alpha F_n) at the trial qq and its 2-norm, with
    !> F(qq, vv) and the contact outputs there.
    subroutine residual(md, rs, sd, qq, rr, nrm, ff, ww, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        type(hht_step_data), intent(in) :: sd
        real(dp), intent(in) :: qq(md%nd + md%mp%nm)
        real(dp), intent(out) :: rr(md%nd + md%mp%nm), nrm, ff(md%nd + md%mp%nm), ww(nwo, 2, md%nw)
        integer, intent(out) :: info
        real(dp) :: aa(md%nd + md%mp%nm), vv(md%nd + md%mp%nm), gp(md%mp%np)
        integer :: nd
        if (sd%energy) then
            call energy_residual(md, rs, sd, qq, rr, nrm, ff, ww, info)
            return
        end if
        nd = md%nd
        aa = sd%cq * (qq - sd%qt)
        vv = sd%vt + sd%gamma * sd%h * aa
        if (sd%exact) call modal_step_velocity(md%mp, sd%ms, sd%qh, sd%vh, qq(nd + 1:), vv(nd + 1:))
        if (sd%ring) then
            call state_force(md, rs, qq, vv, ff, ww, info, gp)
        else
            call state_force(md, rs, qq, vv, ff, ww, info)
        end if
        rr(1:nd) = -(matmul(md%m, aa(1:nd)) - (1.0_dp + sd%alpha) * ff(1:nd) + sd%alpha * sd%fn(1:nd))
        if (md%mp%nm > 0) rr(nd + 1:) = -(md%mp%mass * aa(nd + 1:) - (1.0_dp + sd%alpha) * ff(nd + 1:) &
                                          + sd%alpha * sd%fn(nd + 1:))
        if (sd%exact) call modal_step_residual(md%mp, sd%ms, sd%qh, qq(nd + 1:), vv(nd + 1:), ff(nd + 1:), &
                                               rr(nd + 1:))
        if (sd%ring) call ring_step_force(md%mp, sd%dphi, gp, rr(nd + 1:))
        nrm = norm2(rr)
    end subroutine residual

    !> SCHEME_EXACT's data of a step of size h from st (vehicle_modal_step): the blocks' step
    !> matrices (kept in st for h) and the known part (qh, vh) of the exact blocks. Nothing
    !> without modes. Newton starts the exact blocks too from the constant-acceleration
    !> predictor (a: the modal equation's acceleration at t_n): FR hunting at 1 ms, 300 km/h,
    !> 2 s took 6362 iterations from it, 7316 from the constant force Qh + P f_n.
    subroutine exact_data(md, h, nodes, st, sd)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: h
        integer, intent(in) :: nodes    ! hht_options%nodes
        type(hht_state), intent(inout), target :: st
        type(hht_step_data), intent(inout) :: sd
        integer :: nd, i
        if (md%mp%nm == 0) return
        nd = md%nd
        i = modal_step_slot(md%mp, h, nodes, st%ms, st%msnext)
        call modal_step_make(md%mp, h, st%ms(i), nodes)
        sd%exact = .true.
        sd%ms => st%ms(i)
        allocate (sd%qh(md%mp%nm), sd%vh(md%mp%nm))
        sd%qh = 0.0_dp
        sd%vh = 0.0_dp
        call modal_step_begin(md%mp, st%ms(i), st%q(nd + 1:), st%v(nd + 1:), st%a(nd + 1:), sd%qh, sd%vh)
    end subroutine exact_data

    !> The ring's moving rows over the step h ending at t1 (vehicle_ring_step; after
    !> exact_data): the ring modes' known part at the nodes and their end rows. Nothing when the
    !> step's matrices have no node weights (no ring, or a ring mode not stepped exactly) or
    !> g_n cannot be recovered from the carried force: the plain exact step.
    subroutine ring_data(md, h, t1, st, sd)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: h, t1
        type(hht_state), intent(in) :: st
        type(hht_step_data), intent(inout) :: sd
        integer :: nd
        real(dp), allocatable :: qh(:), vh(:)
        if (sd%ms%nodes == 0) return
        nd = md%nd
        allocate (sd%dphi(3, md%mp%rr%nc, md%mp%rr%nk), sd%phiv(3, md%mp%rr%nc, md%mp%rr%nk), &
                  sd%gn(3, md%mp%rr%nc))
        qh = sd%qh
        vh = sd%vh
        call ring_step_begin(md%mp, sd%ms, h, t1, st%q(nd + 1:), st%v(nd + 1:), st%f(nd + 1:), qh, vh, &
                             sd%dphi, sd%phiv, sd%gn, sd%ring)
        if (.not. sd%ring) return
        sd%qh = qh
        sd%vh = vh
    end subroutine ring_data

    !> The modal blocks' factors for the step sd (vehicle_modal%modal_factorise): S = cq I +
    !> (1 + alpha)(cv B + K_m), or with SCHEME_EXACT P^-1 for the exact blocks.
    subroutine factor_modal(md, sd, mf, info)
        type(vmodel), intent(in) :: md
        type(hht_step_data), intent(in) :: sd
        type(modal_factor), intent(inout) :: mf
        integer, intent(out) :: info
        real(dp), allocatable :: sx(:)
        if (.not. sd%exact) then
            call modal_factorise(md%mp, sd%cq, sd%cv, 1.0_dp + sd%alpha, mf, info)
            return
        end if
        allocate (sx(md%mp%off(md%mp%nb + 1)))
        call modal_step_matrices(md%mp, sd%ms, sd%cq, sd%cv, sx)
        call modal_factorise(md%mp, sd%cq, sd%cv, 1.0_dp, mf, info, sx)
    end subroutine factor_modal

    !> The energy-conserving step's data: alpha = 0 (cq = 4 / h^2, cv = 2 / h for the tangent),
    !> the start x0, v0 and each wheelset's contact potential there (both wheels, J).
    pure subroutine energy_data(md, h, st, sd)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: h
        type(hht_state), intent(in) :: st
        type(hht_step_data), intent(inout) :: sd
        integer :: w
        call step_data(h, 0.0_dp, st, sd)
        sd%energy = .true.
        sd%x0 = st%q
        sd%v0 = st%v
        allocate (sd%w0(md%nw))
        do w = 1, md%nw
            sd%w0(w) = st%w(IO_ENERGY, 1, w) + st%w(IO_ENERGY, 2, w)
        end do
    end subroutine energy_data

    !> Residual of the energy-conserving step (Gonzalez 1996; Simo & Tarnow 1992) at the trial
    !> end x1 = qq, times 2 so that its Jacobian is step_matrix's at the midpoint:
    !>   r = -2 [ M (v1 - v0) / h - F(x_m, v_m) - F_dg ],   v_m = (x1 - x0) / h = (v0 + v1) / 2,
    !> x_m = (x0 + x1) / 2. The linear forces at the midpoint are the trapezoidal rule's (the
    !> gyroscopic ones do no work: v_m . G v_m = 0); F_dg (contact_correction,
    !> element_correction) makes the work of the contact potential and the bump stops over the
    !> step exactly the drop of their energy. Massless rows (mass 0) read 0 = F(x_m) + F_dg:
    !> no kinetic energy, their elastic energy 1/2 Q K Q counted by the midpoint rule exactly.
    !> ff, ww: the force and the contact outputs at the end (x1, v1), whose potential energies
    !> the discrete gradient needs anyway.
    subroutine energy_residual(md, rs, sd, qq, rr, nrm, ff, ww, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        type(hht_step_data), intent(in) :: sd
        real(dp), intent(in) :: qq(md%nd + md%mp%nm)
        real(dp), intent(out) :: rr(md%nd + md%mp%nm), nrm, ff(md%nd + md%mp%nm), ww(nwo, 2, md%nw)
        integer, intent(out) :: info
        real(dp), dimension(md%nd + md%mp%nm) :: xm, vm, fm, dx
        real(dp) :: wm(nwo, 2, md%nw)
        integer :: nd
        nd = md%nd
        vm = (qq - sd%x0) / sd%h
        xm = 0.5_dp * (sd%x0 + qq)
        call state_force(md, rs, qq, 2.0_dp * vm - sd%v0, ff, ww, info)
        if (info /= STAT_OK) return
        call state_force(md, rs, xm, vm, fm, wm, info)
        if (info /= STAT_OK) return
        call contact_correction(md, rs, sd, qq, xm, vm, ww, fm, info)
        if (info /= STAT_OK) return
        call element_correction(md, sd%x0(1:nd), qq(1:nd), vm(1:nd), fm(1:nd))
        dx = qq - sd%x0 - sd%h * sd%v0      ! M (v1 - v0) / h = 2 M dx / h^2
        rr(1:nd) = -(sd%cq * matmul(md%m, dx(1:nd)) - 2.0_dp * fm(1:nd))
        if (md%mp%nm > 0) rr(nd + 1:) = -(sd%cq * md%mp%mass * dx(nd + 1:) - 2.0_dp * fm(nd + 1:))
        nrm = norm2(rr)
    end subroutine energy_residual

    !> The discrete gradient of each wheelset's contact potential W(g) (Gonzalez 1996) added
    !> to fm, the forces at the midpoint: g are the coordinates W depends on, linear in the
    !> state (wheelset_coords: the wheelset's and its track element's DOFs, its rim and rail
    !> points u = Phi Q; the modal blocks stay condensed onto those points), and
    !>   F_dg = -grad W(g_m) - [(W(g1) - W(g0) - grad W(g_m).dg) / |dg|^2] dg,
    !> so that F_dg . dg = W(g0) - W(g1) exactly. -grad W(g_m): the frictionless contact's
    !> generalised forces at the midpoint (the creep forces stay at the midpoint, in fm); the
    !> bracket goes on the rigid DOFs and, through Phi^T, on the modal coordinates: O(nm np).
    !> w1: the contact outputs at x1 (their potential energies).
    subroutine contact_correction(md, rs, sd, x1, xm, vm, w1, fm, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        type(hht_step_data), intent(in) :: sd
        real(dp), dimension(md%nd + md%mp%nm), intent(in) :: x1, xm, vm
        real(dp), intent(in) :: w1(nwo, 2, md%nw)
        real(dp), intent(inout) :: fm(md%nd + md%mp%nm)
        integer, intent(out) :: info
        real(dp), dimension(md%mp%np) :: u0, u1, um, udm, gpn, gpc
        real(dp) :: fn(md%nd), wk(nwo, 2), dg(20), fg(20), dg2, c, fmc(md%mp%nm)
        integer :: nd, w, nr, npt, idx(9), pts(12)
        nd = md%nd
        info = STAT_OK
        gpc = 0.0_dp
        if (md%mp%np > 0) then
            call modal_points(md%mp, sd%x0(nd + 1:), u0)
            call modal_points(md%mp, x1(nd + 1:), u1)
            call modal_points(md%mp, xm(nd + 1:), um)
            call modal_points(md%mp, vm(nd + 1:), udm)
        end if
        do w = 1, md%nw
            call wheelset_coords(md, w, 5, idx, nr, pts, npt)
            dg(1:nr) = x1(idx(1:nr)) - sd%x0(idx(1:nr))
            dg(nr + 1:nr + npt) = u1(pts(1:npt)) - u0(pts(1:npt))
            dg2 = sum(dg(1:nr + npt)**2)
            if (.not. dg2 > 0.0_dp) cycle
            fn = 0.0_dp
            gpn = 0.0_dp
            if (npt > 0) then
                call add_contact(md, rs, w, xm(1:nd), vm(1:nd), fn, wk, info, u=um, ud=udm, gp=gpn, &
                                 frictionless=.true.)
            else
                call add_contact(md, rs, w, xm(1:nd), vm(1:nd), fn, wk, info, frictionless=.true.)
            end if
            if (info /= STAT_OK) return
            fg(1:nr) = fn(idx(1:nr))
            fg(nr + 1:nr + npt) = gpn(pts(1:npt))
            c = w1(IO_ENERGY, 1, w) + w1(IO_ENERGY, 2, w) - sd%w0(w) &
                + dot_product(fg(1:nr + npt), dg(1:nr + npt))
            ! the strip sums' rounding noise in W1 - W0 (~1e-12 J) divided by |dg| would be a
            ! force noise on a wheelset that hardly moves: the bracket fades out below
            ! |dg| ~ DG_FLOOR (the noise force stays below 1e-12 J / (2 DG_FLOOR)), where the
            ! exact bracket, O(W''' |dg|^3), is below 1e-14 J anyway
            c = c / (dg2 + DG_FLOOR**2)
            fm(idx(1:nr)) = fm(idx(1:nr)) - c * dg(1:nr)
            gpc(pts(1:npt)) = gpc(pts(1:npt)) - c * dg(nr + 1:nr + npt)
        end do
        if (.not. any(gpc /= 0.0_dp)) return
        call modal_rows_t(md%mp, gpc, fmc)
        fm(nd + 1:) = fm(nd + 1:) + fmc
    end subroutine contact_correction

    !> The bump stops' discrete gradient: the force of a bump stop (potential
    !> V(d) = p2 (|d| - p1)^2 / 2 beyond its clearance p1) over the step from d0 to d1 becomes
    !> (V(d1) - V(d0)) / (d1 - d0) in place of its midpoint value (fm: the rigid forces).
    pure subroutine element_correction(md, x0, x1, vm, fm)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: x0(md%nd), x1(md%nd), vm(md%nd)
        real(dp), intent(inout) :: fm(md%nd)
        real(dp) :: d0, d1, fe, kd, cd, fdg
        integer :: e
        do e = 1, md%ne
            if (md%etype(e) /= el_bump) cycle
            d0 = dot_product(md%eg(:, e), x0)
            d1 = dot_product(md%eg(:, e), x1)
            if (d1 == d0) cycle
            call element_force(md%etype(e), md%epar(:, e), 0.5_dp * (d0 + d1), &
                               dot_product(md%eg(:, e), vm), fe, kd, cd)
            fdg = (bump_energy(md%epar(:, e), d1) - bump_energy(md%epar(:, e), d0)) / (d1 - d0)
            fm = fm - md%eg(:, e) * (fdg - fe)
        end do
    end subroutine element_correction

    !> A bump stop's potential energy at deflection d (J).
    pure real(dp) function bump_energy(p, d)
        real(dp), intent(in) :: p(4), d
        bump_energy = 0.0_dp
        if (abs(d) > p(1)) bump_energy = 0.5_dp * p(2) * (abs(d) - p(1))**2
    end function bump_energy

    !> F over the whole state x = (q, Q), velocities xd: vehicle_model%force_total on the rigid
    !> DOFs plus the point elements, and the modal forces -B Q' - K_m Q + Phi^T g_p.
    subroutine state_force(md, rs, x, xd, f, w, info, gpo)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: x(md%nd + md%mp%nm), xd(md%nd + md%mp%nm)
        real(dp), intent(out) :: f(md%nd + md%mp%nm), w(nwo, 2, md%nw)
        integer, intent(out) :: info
        real(dp), intent(out), optional :: gpo(md%mp%np)  !< the contact's point forces (FR, RF)
        integer :: nd
        real(dp) :: u(md%mp%np), ud(md%mp%np), gp(md%mp%np)
        nd = md%nd
        if (md%mp%nfr > 0 .or. md%mp%nrl > 0) then
            ! models FR, RF: the contact on the deformed rims / rails gives point forces too
            call modal_points(md%mp, x(nd + 1:), u)
            call modal_points(md%mp, xd(nd + 1:), ud)
            gp = 0.0_dp
            call force_total(md, rs, x(1:nd), xd(1:nd), f(1:nd), w, info, u=u, ud=ud, gp=gp)
            call modal_force(md%mp, nd, x(1:nd), xd(1:nd), x(nd + 1:), xd(nd + 1:), f(1:nd), &
                             f(nd + 1:), gext=gp)
            if (present(gpo)) gpo = gp
            return
        end if
        call force_total(md, rs, x(1:nd), xd(1:nd), f(1:nd), w, info)
        if (md%mp%nm > 0) call modal_force(md%mp, nd, x(1:nd), xd(1:nd), x(nd + 1:), xd(nd + 1:), &
                                           f(1:nd), f(nd + 1:))
    end subroutine state_force

    !> The rigid tangent (tangent) at x, xd; for model FR also the contact's chain-rule blocks
    !> jcru, jcpr, jcpu over the attachment points (zero otherwise).
    subroutine full_tangent(md, rs, x, xd, cv, mode, jac, jcru, jcpr, jcpu, info, cvp)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: x(md%nd + md%mp%nm), xd(md%nd + md%mp%nm), cv
        integer, intent(in) :: mode
        real(dp), intent(out) :: jac(md%nd, md%nd), jcru(md%nd, md%mp%np)
        real(dp), intent(out) :: jcpr(md%mp%np, md%nd), jcpu(md%mp%np, md%mp%np)
        integer, intent(out) :: info
        real(dp), intent(in), optional :: cvp(:)   !< the points' own dv/dx (SCHEME_EXACT)
        real(dp) :: u(md%mp%np), ud(md%mp%np)
        integer :: nd
        nd = md%nd
        jcru = 0.0_dp
        jcpr = 0.0_dp
        jcpu = 0.0_dp
        if (md%mp%nfr > 0 .or. md%mp%nrl > 0) then
            call modal_points(md%mp, x(nd + 1:), u)
            call modal_points(md%mp, xd(nd + 1:), ud)
            call tangent(md, rs, x(1:nd), xd(1:nd), cv, mode, jac, info, u, ud, jcru, jcpr, jcpu, cvp)
        else
            call tangent(md, rs, x(1:nd), xd(1:nd), cv, mode, jac, info)
        end if
    end subroutine full_tangent

    !> A failure of one trial state (outside the table, a BEM patch failing): recorded in
    !> tally%why; the step then fails softly and is retried with sub-steps.
    logical function soft(info, tally)
        integer, intent(in) :: info
        type(hht_tally), intent(inout) :: tally
        soft = info == STAT_OUTSIDE_TABLE .or. info == STAT_GRID_EDGE &
               .or. info == STAT_CONTACT_NOT_CONVERGED
        if (soft) tally%why = info
    end function soft

    !> A non-finite state, |q| above qmax or |v| above 1e6. The spin perturbations beta and
    !> the modal coordinates are only checked for being finite: no force depends on beta, and
    !> at a steady spin rate (free rolling with a longitudinal creepage) it grows linearly in
    !> time; a modal coordinate (mass-normalised) is no length.
    pure logical function too_big(md, q, v, qmax)
        type(vmodel), intent(in) :: md
        real(dp), intent(in) :: q(md%nd + md%mp%nm), v(md%nd + md%mp%nm), qmax
        integer :: j
        too_big = any(.not. (abs(v) <= 1.0e6_dp)) .or. any(.not. (abs(q(md%nd + 1:)) <= huge(1.0_dp)))
        if (too_big) return
        do j = 1, md%nd
            if (is_spin(md, j)) then
                too_big = .not. (abs(q(j)) <= huge(1.0_dp))
            else
                too_big = .not. (abs(q(j)) <= qmax)
            end if
            if (too_big) return
        end do
    end function too_big

    !> Steady state of running on straight track: F(q, v) = 0 with v = 0 except the rates of
    !> the wheelsets' spin perturbations beta, which are unknowns in place of the angles
    !> (no force depends on beta; free rolling fixes betadot). Newton's method with step
    !> halving on the residual; the spin columns of the tangent are dF/dv.
    !> With modal blocks the unknowns include the modal coordinates and the tangent is condensed
    !> onto the points as in the time step, with cq = cv = 0: S = K_m (elastic modes only: a
    !> singular block gives STAT_SINGULAR); without, this is the plain dense Newton.
    !> x, xd: the whole state (nd + nm); xd is zero but the spin rates.
    !> info: STAT_OK, STAT_NOT_CONVERGED, STAT_SINGULAR (singular tangent), or a contact
    !> failure of state_force (STAT_OUTSIDE_TABLE, STAT_GRID_EDGE, ...).
    subroutine static_solve(md, rs, x, xd, tol, maxit, iters, resid, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(inout) :: x(md%nd + md%mp%nm)
        real(dp), intent(out) :: xd(md%nd + md%mp%nm)
        real(dp), intent(in) :: tol
        integer, intent(in) :: maxit
        integer, intent(out) :: iters, info
        real(dp), intent(out) :: resid
        real(dp), dimension(md%nd + md%mp%nm) :: f, ftry, dx, xt, xdt
        real(dp) :: wk(nwo, 2, md%nw), s, r0, r1
        logical :: spin(md%nd + md%mp%nm)
        type(modal_factor) :: mf
        type(newton_lin) :: nl
        type(hht_step_data) :: sd        ! alpha = 0: lin_solve's plain Newton
        integer :: it, ls, j
        xd = 0.0_dp
        iters = 0
        resid = 0.0_dp
        spin = .false.
        do j = 1, md%nd
            spin(j) = is_spin(md, j)
        end do
        call state_force(md, rs, x, xd, f, wk, info)
        if (info /= STAT_OK) return
        r0 = norm2(f)
        do it = 1, maxit
            iters = it
            call static_matrix(md, rs, x, xd, spin(1:md%nd), mf, nl, info)
            if (info /= STAT_OK) return
            call lin_solve(md, sd, mf, nl, f, dx)
            s = 1.0_dp
            do ls = 1, 30
                xt = merge(x, x + s * dx, spin)
                xdt = merge(xd + s * dx, xd, spin)
                call state_force(md, rs, xt, xdt, ftry, wk, info)
                if (info == STAT_OK) then
                    r1 = norm2(ftry)
                    if (r1 < r0 .or. ls == 30) exit
                end if
                s = 0.5_dp * s
            end do
            if (info /= STAT_OK) return
            x = xt
            xd = xdt
            f = ftry
            r0 = r1
            resid = maxval(abs(s * dx))
            ! converged: the (possibly cut) correction below tol; a cut step at the noise floor
            ! of the forces (the BEM's) ends here too, so the caller checks the residual force
            ! (simulate.static_equilibrium)
            if (resid <= tol) return
        end do
        info = STAT_NOT_CONVERGED
    end subroutine static_solve

    !> The condensed LU of -dF/d(unknowns) for static_solve: dF/dq with dF/dv in the spin
    !> columns (a spin rate with no creep force on it, friction 0 or wheels off the rails, is
    !> free: its column becomes the identity and its equation F_j = 0 holds already), with the
    !> point elements' tangent, S = K_m, C = Phi K_m^-1 Phi^T (no modes: the dense -dF/dq).
    !> info: STAT_OK, STAT_SINGULAR, or a contact failure.
    subroutine static_matrix(md, rs, x, xd, spin, mf, nl, info)
        type(vmodel), intent(in) :: md
        type(vsettings), intent(in) :: rs
        real(dp), intent(in) :: x(md%nd + md%mp%nm), xd(md%nd + md%mp%nm)
        logical, intent(in) :: spin(md%nd)
        type(modal_factor), intent(inout) :: mf
        type(newton_lin), intent(inout) :: nl
        integer, intent(out) :: info
        real(dp) :: jac(md%nd, md%nd), jv(md%nd, md%nd), jru(md%nd, md%mp%np)
        real(dp) :: jcru(md%nd, md%mp%np), jcpr(md%mp%np, md%nd), jcpu(md%mp%np, md%mp%np)
        real(dp) :: jvru(md%nd, md%mp%np), jvpr(md%mp%np, md%nd), jvpu(md%mp%np, md%mp%np)
        integer :: nd, np, nt, i, j, lin
        nd = md%nd
        np = md%mp%np
        nt = nd + np
        call full_tangent(md, rs, x, xd, 0.0_dp, TANGENT_QV, jac, jcru, jcpr, jcpu, info)
        if (info /= STAT_OK) return
        if (.not. allocated(nl%a)) allocate (nl%a(nt, nt), nl%ipiv(nt), nl%jpr(np, nd), nl%jpu(np, np))
        call modal_point_tangent(md%mp, nd, x(1:nd), xd(1:nd), x(nd + 1:), xd(nd + 1:), 0.0_dp, &
                                 jac, jru, nl%jpr, nl%jpu)
        jru = jru + jcru
        nl%jpr = nl%jpr + jcpr
        nl%jpu = nl%jpu + jcpu
        if (any(spin)) then     ! spin rates as unknowns
            call full_tangent(md, rs, x, xd, 0.0_dp, TANGENT_V, jv, jvru, jvpr, jvpu, info)
            if (info /= STAT_OK) return
            do j = 1, nd
                if (.not. spin(j)) cycle
                jac(:, j) = jv(:, j)
                nl%jpr(:, j) = nl%jpr(:, j) - jcpr(:, j) + jvpr(:, j)
                if (all(jv(:, j) == 0.0_dp)) jac(j, j) = -1.0_dp
            end do
        end if
        call modal_factorise(md%mp, 0.0_dp, 0.0_dp, 1.0_dp, mf, info)
        if (info /= STAT_OK) return
        nl%a(1:nd, 1:nd) = -jac
        if (np > 0) then
            nl%a(1:nd, nd + 1:nt) = -jru
            nl%a(nd + 1:nt, 1:nd) = -matmul(mf%c, nl%jpr)
            nl%a(nd + 1:nt, nd + 1:nt) = -matmul(mf%c, nl%jpu)
            do i = nd + 1, nt
                nl%a(i, i) = nl%a(i, i) + 1.0_dp
            end do
        end if
        call dgetrf(nt, nt, nl%a, nt, nl%ipiv, lin)
        if (lin /= 0) info = STAT_SINGULAR
    end subroutine static_matrix

end module vehicle_newmark
