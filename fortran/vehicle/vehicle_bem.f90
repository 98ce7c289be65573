!> BEM contact at the wheels of the time simulation: the normal problem (contact_normal,
!> projected CG under approach control) and steady rolling (contact_rolling, 'fftgs') on a
!> fixed grid per candidate point, warm-started from the previous evaluation of the same
!> wheel and candidate point.
!>
!> Gap fields. For the left wheel (the right one is the mirror: the field read at -y with the
!> lateral grid index reversed) and each of the table's two candidate points, the undeformed
!> normal gap around the point, relative to the point (h = 0 there), is tabulated against the
!> lateral shift y of the wheelset on the contact table's y nodes (built in Python,
!> railvti.vehicle.bem). The grid (nx x ny, dx x dy) is centred on the point: x along the
!> rolling direction, y along the contact frame's t_y. The wheel's vertical interference at the
!> point enters as a uniform approach d (the same d as the Hertz path), so the field is
!> interpolated linearly in y within the point's branch (never across a jump of the point to
!> another local minimum: vehicle_contact%table_at picks the nodes and the weight; near a jump
!> both branches are solved, each as its own point, and their forces blended) and solved
!> with delta = d.
!>
!> State. One bem_model per simulation behind an integer handle (registry like
!> contact_plans): the gap table, the contact workspaces (FFT plans and influence spectra, with
!> the tangential kernels) of the full grid and of the windows, one per thread, and per
!> wheelset, wheel and candidate point a bem_point: the last pressure, tractions and slip
!> velocities (the warm starts and the fields reported after a run) and the patch problem of
!> the current force evaluation with its solution.
!>
!> Threads. A force evaluation solves the patches of all wheels together (bem_record,
!> bem_solve_recorded, called by vehicle_model%force_total): a first pass over the wheelsets
!> records each point's problem (bem_patch then only stores its arguments), bem_solve_recorded
!> prepares every point serially (gap field, window, the window's workspaces made for every
!> thread: FFTW planning is not thread-safe) and runs the normal + rolling solves in an OpenMP
!> loop over the points, largest window first (nthreads, bem_threads; each thread executes its
!> own plans on its own buffers, each point writes its own bem_point only), and the second
!> pass reads each point's solution back through bem_patch when its arguments are the recorded
!> ones. After the loop the solutions are committed (their fields become the warm starts) and
!> the counters summed in the serial order (wheelset, wheel, point), the points after the first
!> failure dropped as a serial evaluation, which stops there, would leave them: a run gives
!> the same numbers to the bit with any number of threads, and with none (a build without
!> OpenMP runs the loop serially), as the serial code did.
!>
!> Tangent. Each point keeps a linear model of its patch for the Newton tangent (bem_linear:
!> the last committed solve plus a Jacobian over approach, relative roll, creepages and
!> lateral position), the Jacobian from forward differences of the point's own solves made in
!> the patch loop after its solve (point_jacobian; when due: jacobian_due, decided serially
!> in setup_point) and committed with it, so threads give the same numbers here too.
!>
!> Updates (issue 33; bem_update, off unless a band is set). A point whose inputs moved little
!> since its last committed solve takes its forces from that linear model instead of a solve
!> (linear_update: each input's own first-order change of each force within band x the
!> point's normal force, the lateral position within a table node, and a Jacobian made near
!> the solve's inputs, else the point is solved, with a fresh Jacobian once it has stayed
!> within the band for UPD_CALM evaluations); with a reach (UPD_NEAR_FN) also when only the
!> approach and roll moved beyond the band, within reach bands, with a Jacobian made near
!> them (the ring's sleeper passing); its fields, warm starts and the model's base stay the
!> solve's. The decision is taken serially in setup_point from the
!> committed state only, so threads and chunking give the same numbers as before. A point
!> whose approach lies below a lower bound of its gap field (surely_open) is found open
!> without building the field, and an open point whose fields are already zero is not
!> cleared again (both exact: the same decisions and fields as before).
!>
!> Windows. Each solve runs on the window of the grid around the point's rigid
!> interpenetration {h < dn} (its bounding box plus WIN_MARGIN elements a side, the sides
!> rounded up to multiples of WIN_QUANTUM, clipped to the grid), with a workspace of the
!> window's size made on first use and kept (bem_window switches this off). The contact area
!> lies inside {h < dn} (the normal displacement of a positive pressure is positive), and
!> the influence coefficients of an element pair depend on their offset only, so the
!> window's solution is the full grid's, to the solvers' tolerances, at the cost of FFTs of
!> the window (a tread patch's window is about a fifth of the 0.75 mm grid).
!> The window workspaces are made inside the time loop (the GIL released), always outside the
!> parallel loop: two BEM runs in Python threads of one process must not run at the same time
!> (contact_plans' registry is not thread-safe; the sweeps run one thread per process).
!> Implements no equation itself: it applies contact_normal (Kaiser eqs 17-23) and
!> contact_rolling (eqs 24-29) at every wheel.
module vehicle_bem
    use, intrinsic :: iso_fortran_env, only: int64
    !$ use omp_lib, only: omp_get_thread_num, omp_get_max_threads
    use common_kinds, only: dp
    use contact_plans, only: workspace, ws_create, ws_free, ws_get
    use contact_normal, only: normal_cg, CONTROL_APPROACH
    use contact_rolling, only: rolling_steady, rolling_patch, rolling_patch_reset, ROLL_FFTGS
    use common_status, only: STAT_OK, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, STAT_BAD_HANDLE, &
                             STAT_NO_MEMORY, STAT_FFTW_PLAN, STAT_GRID_EDGE, STAT_OUTSIDE_TABLE, &
                             STAT_CONTACT_NOT_CONVERGED
    implicit none
    private
    public :: bem_create, bem_free, bem_patch, bem_fields, bem_counts, bem_reset, bem_scale
    public :: bem_window, bem_threads, bem_record, bem_solve_recorded
    public :: bem_jacobian, bem_linear, bem_point_jacobian, bem_probe, bem_update, NLIN
    public :: MAX_BEM, BEM_NCOUNT, MAX_THREADS, NPT, bem_lead

    integer, parameter :: MAX_BEM = 16
    !> Points per wheel: each of the table's two slots (candidate points) has two members, the
    !> branches on either side of a jump of its point to another local minimum, point
    !> c = 2 (slot - 1) + member (vehicle_contact%table_at blends their forces across the jump).
    integer, parameter :: NPT = 4
    !> Threads of the patch loop at most (bem_threads clips to it).
    integer, parameter :: MAX_THREADS = 64
    !> Gap-field entries at or above this mark elements off the point's part of the wheel, m.
    real(dp), parameter :: FAR = 0.5_dp
    !> Counters (bem_counts): 1 normal solves, 2 CG iterations, 3 rolling solves,
    !> 4 rolling sweeps, 5 patches found out of contact, 6 worst accepted normal residual,
    !> 7 worst accepted rolling residual, 8 seconds in normal solves, 9 in rolling solves,
    !> 10 in the patches as a whole (the solves, the gap field and the sums); 8-10 are summed
    !> over the patches (wall seconds of each patch: thread-seconds with several threads);
    !> 11 linear updates (patches whose forces came from their linear model, no solve:
    !> bem_update), 12 the largest force error of the linear model seen at a solve whose
    !> inputs lay within twice the update band (N; update_error).
    integer, parameter :: BEM_NCOUNT = 12
    !> Free elements around the interpenetration in a solve window (steady rolling needs
    !> two free rows behind the patch, the edge test one more), and the step its sides are
    !> rounded up to (few distinct window sizes, so few workspaces).
    integer, parameter :: WIN_MARGIN = 3, WIN_QUANTUM = 4
    !> Window sizes kept per model (each with a workspace per thread); beyond it a solve uses
    !> the full grid.
    integer, parameter :: MAX_WIN = 48
    !> A point's patch problem: none pending, recorded (bem_record), solved (bem_solve_recorded).
    integer, parameter :: PT_IDLE = 0, PT_RECORDED = 1, PT_SOLVED = 2
    !> The patch's linear model (bem_linear): inputs x = (dn, phi, xi, eta, spin, s), s = ia - 1
    !> + wa the lateral position in table nodes; outputs y = (fn, fx, fy, mz, fn xc, fn yc).
    integer, parameter :: NLIN = 6
    !> Forward-difference steps of the patch Jacobian (point_jacobian): the approach by
    !> -JAC_DN dn (inwards: the patch stays in its window), the roll by JAC_PHI rad (2e-7 m of
    !> gap over a 10 mm half width), xi and eta by JAC_CREEP, spin by JAC_SPIN 1/m and s by
    !> JAC_DS nodes: each moves the forces by ~1e-3 of their size, 100-1000 times the solvers'
    !> tolerances (1e-6 Fn, 3e-5 of the traction bound), and stays in the linear range.
    real(dp), parameter :: JAC_DN = 2.0e-3_dp, JAC_PHI = 2.0e-5_dp, JAC_CREEP = 2.0e-5_dp
    real(dp), parameter :: JAC_SPIN = 5.0e-3_dp, JAC_DS = 0.1_dp
    !> A patch Jacobian is made again when the approach moved by more than JAC_MOVE of its value
    !> at the Jacobian, or the lateral position by more than JAC_SMOVE table nodes, or after
    !> the point's jage-th committed solve since (bem_jacobian).
    real(dp), parameter :: JAC_MOVE = 0.2_dp, JAC_SMOVE = 4.0_dp
    !> The default of bem_jacobian's age (committed solves of a point between Jacobians).
    integer, parameter :: JAC_AGE = 128
    !> Linear updates (bem_update): the lateral position may move at most UPD_DS table nodes
    !> from the last solve's (the gap field is piecewise linear in it, its slope changes at
    !> the nodes), and the moment rows' band is the force band times UPD_ARM, m.
    real(dp), parameter :: UPD_DS = 1.0_dp, UPD_ARM = 0.01_dp
    !> A linear update needs a Jacobian made near the model's base: the base's inputs within
    !> UPD_FRESH bands of the Jacobian's (band_ratio); a point within the band whose Jacobian
    !> is older is solved with a new Jacobian instead (stale). Within the band the patch's
    !> incremental stiffness is the Jacobian's, so its relative error, ~ the force change
    !> between the Jacobian's inputs and the base's over fn (<= UPD_FRESH band, 0.2 % at the
    !> default band 5e-4), is what small oscillations about the base feel; JAC_MOVE alone
    !> allows 10-20 % (hunting at 300 km/h, 3 s, band 5e-4: the third second's amplitude,
    !> 4.4 um, moved by -0.59 % with 4 and -1.66 % with 8, 4.2 and 3.8 solve pairs a step;
    !> +11.9 % with 32 before UPD_CALM; the BEM tolerances 100x / 3x tighter: -0.36 %).
    real(dp), parameter :: UPD_FRESH = 4.0_dp
    !> A stale Jacobian is made again only for a point that stays within the band: after
    !> UPD_CALM consecutive evaluations within it (calm; committed ones). In fast motion only a
    !> step's Newton corrections fall within the band, and a Jacobian for each (10 solves)
    !> would cost more than it saves (FF at 300 km/h: 36 instead of 26 solve pairs a step):
    !> such a point is solved without one.
    integer, parameter :: UPD_CALM = 4
    !> Linear updates in motion (bem_update's reach > 0): a point whose approach and roll
    !> (the gap's inputs) moved beyond the band, within reach bands, while the others stayed
    !> within it, takes its forces from the model when the model's Jacobian was made near
    !> (jacobian_fresh: the approach's and roll's normal-force terms between the Jacobian's
    !> inputs and the base's, and the current ones, within UPD_NEAR_FN x fn, 4.5 %, i.e. the
    !> approach within 3 %; else the point is solved, with a new Jacobian when the others
    !> are fresh) and the lateral position of the three lies in one table cell (the gap
    !> field's slope in it, the Jacobian's, changes at the nodes). Within the band such a
    !> Jacobian serves too. In FF's steady running the ring's sleeper passing moves every
    !> patch's approach by 0.3-1 % between solves (6-30 bands of the normal force).
    real(dp), parameter :: UPD_NEAR_FN = 0.045_dp
    !> The linear model's inputs held to the band in motion: the creepages and the lateral
    !> position (the lateral dynamics' own inputs: with the lateral position in the reach
    !> too, RR's hunting amplitude in its third second, 4.4 um, moved by +12.7 %).
    logical, parameter :: BAND_IN(NLIN) = [.false., .false., .true., .true., .true., .true.]

    !> What every solve of a model reads and none changes.
    type :: bem_setup
        integer :: nx = 0, ny = 0
        !> nblock: rows per FFT refresh of the rolling sweeps ('fftgs'): a window's rows all
        !> in one block (one field product per sweep; the in-block changes are summed directly)
        integer :: maxit_n = 200, maxit_t = 400, nblock = 64, ninner = 1
        real(dp) :: dx = 0, dy = 0, tol_n = 1e-8_dp, tol_t = 1e-6_dp
    end type bem_setup

    !> One candidate point of one wheel: its fields on the full grid (p, tx, ty, sx, sy: the
    !> warm starts and the reported fields), and the patch problem of the current evaluation
    !> (bem_patch's arguments), its gap field h, window (i1:i2, j1:j2; iwin its entry in the
    !> model's list, 0 the full grid) and solution: out = fn, fx, fy, mz, xc, yc, info, its
    !> counters, and its fields (pn, txn, tyn, sxn, syn), which become the point's fields
    !> when the solve is committed (commit_point).
    type :: bem_point
        integer :: state = PT_IDLE
        integer :: ia = 0, ib = 0
        real(dp) :: wa = 0, dn = 0, phi = 0, xi = 0, eta = 0, spin = 0, mu = 0, speed = 0
        logical :: open = .false.
        !> lin: this evaluation's forces come from the linear model (bem_update), no solve;
        !> zero: the point's fields are zero (committed open); still: open again with zero
        !> fields, nothing to commit
        logical :: lin = .false., zero = .true., still = .false., stale = .false.
        !> calm: consecutive committed evaluations within the band (UPD_CALM); calmn: this one's
        integer :: calm = 0, calmn = 0
        integer :: i1 = 1, i2 = 1, j1 = 1, j2 = 1, iwin = 0
        real(dp) :: out(6) = 0
        integer :: info = STAT_OK
        real(dp) :: cnt(BEM_NCOUNT) = 0
        real(dp), allocatable :: h(:, :), p(:, :), tx(:, :), ty(:, :), sx(:, :), sy(:, :)
        real(dp), allocatable :: pn(:, :), txn(:, :), tyn(:, :), sxn(:, :), syn(:, :)
        !> The linear model of the patch (bem_linear; the Newton tangent): jac = dy/dx at the
        !> inputs xj, by forward differences of the point's own solves (point_jacobian), valid
        !> (jok) since age committed solves; xb, yb the inputs and outputs of the last committed
        !> solve in contact (bok). jwant: make a Jacobian at this solve (set serially in
        !> setup_point, with hs = dh/ds, the gap field's slope per table node); jnew, jn: the
        !> one made, committed with the solve.
        logical :: jok = .false., bok = .false., jwant = .false., jnew = .false.
        integer :: age = 0
        real(dp) :: jac(NLIN, NLIN) = 0, jn(NLIN, NLIN) = 0, xj(NLIN) = 0, xb(NLIN) = 0, yb(NLIN) = 0
        !> friction and rolling speed of the last committed solve in contact (the linear
        !> model holds for these only)
        real(dp) :: mub = 0, vb = 0
        !> the model's update band at this point's set-up (update_error)
        real(dp) :: band = 0
        real(dp), allocatable :: hs(:, :)
        !> the rolling solves' fixed data (contact set, coefficients, in-row bases) of the
        !> last rolling solve of this point and its Jacobian's probes: reused as it is when
        !> the next solve has the same contact set on a window of the same size (only the
        !> traction bound is new; contact_rolling::rolling_steady), the same solution
        type(rolling_patch) :: rp
    end type bem_point

    type :: bem_model
        logical :: used = .false.
        integer :: ntab = 0, nws = 0
        type(bem_setup) :: s
        real(dp) :: ytab0 = 0, dytab = 1, g = 0, nu = 0
        !> threads of the patch loop; recording: bem_patch stores the problems (bem_record)
        integer :: nthreads = 1
        logical :: recording = .false.
        !> committed solves of a point between its patch Jacobians (bem_jacobian); 0: no
        !> Jacobian, the tangent's cheap model is Hertz + Kalker scaled by ratio
        integer :: jage = JAC_AGE
        !> linear updates (bem_update): a point's forces from its linear model while each
        !> input's first-order change of its forces stays within band x its normal force; 0 off
        real(dp) :: band = 0
        !> linear updates in motion (bem_update, UPD_NEAR_FN): the gap's inputs up to reach
        !> bands from the base with a Jacobian near it; 0 off
        real(dp) :: reach = 0
        !> full-grid workspace per thread (1 made at creation, the others when needed)
        integer :: ws(MAX_THREADS) = 0
        !> solves on windows (see the module doc); win(:, i) = (nx, ny) of the nwin window
        !> sizes met so far, winws(t, i) the workspace of size i of thread t (0: not made)
        logical :: window = .true.
        integer :: nwin = 0
        integer :: win(2, MAX_WIN) = 0
        integer :: winws(MAX_THREADS, MAX_WIN) = 0
        real(dp), allocatable :: gap(:, :, :, :)          ! (nx, ny, 2 points, ntab), left wheel
        !> the smallest gap of each field below FAR (1 m when none): (2 points, ntab); the
        !> open test's lower bound (surely_open)
        real(dp), allocatable :: gmin(:, :)
        type(bem_point), allocatable :: pts(:, :, :)      ! (point, wheel, wheelset)
        !> per (slot, wheel, wheelset) the point of the member that carried the larger share
        !> at the last evaluation (bem_lead): the one bem_fields, bem_probe and
        !> bem_point_jacobian report for the slot
        integer, allocatable :: lead(:, :, :)
        !> BEM / Hertz-Kalker ratios of the normal force and the creep-force magnitude per
        !> (point, wheel, wheelset), from the last BEM solve: they calibrate the cheap model
        !> of the Newton tangent (vehicle_contact%point_bem_tangent).
        real(dp), allocatable :: ratio(:, :, :, :)
        real(dp) :: counts(BEM_NCOUNT) = 0
    end type bem_model

    type(bem_model), target :: models(MAX_BEM)

contains

    !> Make a BEM contact state. gap: (nx, ny, 2, ntab) left-wheel gap fields on the table's
    !> y nodes ytab0 + (i - 1) dytab. g, nu: shear modulus and Poisson ratio. Threads: all the
    !> OpenMP runtime offers (bem_threads with n = 0).
    !> info: STAT_OK, STAT_BAD_ARGUMENT (sizes or steps), STAT_NO_MEMORY (no free slot),
    !> STAT_FFTW_PLAN (the contact workspace, FFT plans and spectra, could not be made).
    subroutine bem_create(nx, ny, dx, dy, ntab, ytab0, dytab, gap, nws, g, nu, tol_n, tol_t, &
                          maxit_n, maxit_t, handle, info)
        integer, intent(in) :: nx, ny, ntab, nws, maxit_n, maxit_t
        real(dp), intent(in) :: dx, dy, ytab0, dytab, gap(nx, ny, 2, ntab), g, nu, tol_n, tol_t
        integer, intent(out) :: handle, info
        type(bem_model), pointer :: m
        integer :: k, stat, i, j, l
        handle = 0
        info = STAT_BAD_ARGUMENT
        if (nx < 4 .or. ny < 4 .or. ntab < 2 .or. nws < 1 .or. dx <= 0 .or. dy <= 0 .or. dytab <= 0) return
        info = STAT_NO_MEMORY
        do k = 1, MAX_BEM
            if (.not. models(k)%used) then
                handle = k
                exit
            end if
        end do
        if (handle == 0) return
        m => models(handle)
        m%ws = 0
        call ws_create(nx, ny, dx, dy, g, nu, .true., m%ws(1), stat)
        if (stat /= STAT_OK) then
            info = stat     ! STAT_NO_MEMORY (workspace pool full) or STAT_FFTW_PLAN
            handle = 0
            return
        end if
        m%s = bem_setup(nx=nx, ny=ny, maxit_n=maxit_n, maxit_t=maxit_t, dx=dx, dy=dy, &
                        tol_n=tol_n, tol_t=tol_t)
        m%ntab = ntab
        m%ytab0 = ytab0
        m%dytab = dytab
        m%nws = nws
        m%g = g
        m%nu = nu
        m%window = .true.
        m%recording = .false.
        m%nwin = 0
        m%win = 0
        m%winws = 0
        m%nthreads = threads_of(0)
        m%jage = JAC_AGE
        m%band = 0.0_dp
        m%reach = 0.0_dp
        m%gap = gap
        allocate (m%gmin(2, ntab))
        do l = 1, ntab
            do k = 1, 2
                m%gmin(k, l) = minval(gap(:, :, k, l), mask=gap(:, :, k, l) < FAR)
                if (.not. any(gap(:, :, k, l) < FAR)) m%gmin(k, l) = 1.0_dp
            end do
        end do
        allocate (m%pts(NPT, 2, nws), m%ratio(2, NPT, 2, nws), m%lead(2, 2, nws))
        do l = 1, nws
            do j = 1, 2
                do i = 1, NPT
                    allocate (m%pts(i, j, l)%p(nx, ny), source=0.0_dp)
                    associate (pt => m%pts(i, j, l))
                        allocate (pt%h, pt%tx, pt%ty, pt%sx, pt%sy, pt%pn, pt%txn, pt%tyn, &
                                  pt%sxn, pt%syn, mold=pt%p)
                    end associate
                end do
            end do
        end do
        call reset(m)
        m%used = .true.
        info = STAT_OK
    end subroutine bem_create

    subroutine reset(m)
        type(bem_model), intent(inout) :: m
        integer :: i, j, l
        do l = 1, m%nws
            do j = 1, 2
                m%lead(:, j, l) = [1, 3]
                do i = 1, NPT
                    call clear_fields(m%pts(i, j, l))
                    m%pts(i, j, l)%state = PT_IDLE
                    m%pts(i, j, l)%jok = .false.
                    m%pts(i, j, l)%bok = .false.
                    m%pts(i, j, l)%jnew = .false.
                    m%pts(i, j, l)%lin = .false.
                    m%pts(i, j, l)%zero = .true.
                    m%pts(i, j, l)%still = .false.
                    m%pts(i, j, l)%calm = 0
                end do
            end do
        end do
        m%recording = .false.
        m%counts = 0.0_dp
        m%ratio = 1.0_dp
    end subroutine reset

    pure subroutine clear_fields(pt)
        type(bem_point), intent(inout) :: pt
        pt%p = 0.0_dp
        pt%tx = 0.0_dp
        pt%ty = 0.0_dp
        pt%sx = 0.0_dp
        pt%sy = 0.0_dp
    end subroutine clear_fields

    !> The solve's fields of a point that is out of contact: zero.
    pure subroutine clear_new(pt)
        type(bem_point), intent(inout) :: pt
        pt%pn = 0.0_dp
        pt%txn = 0.0_dp
        pt%tyn = 0.0_dp
        pt%sxn = 0.0_dp
        pt%syn = 0.0_dp
    end subroutine clear_new

    !> The solve's fields become the point's (a swap of the allocations, no copy); its inputs
    !> and outputs the linear model's base, and a Jacobian made at it the model's (a point
    !> out of contact or failing drops both: the next solve in contact makes a new one).
    subroutine commit_point(pt)
        type(bem_point), intent(inout) :: pt
        pt%calm = pt%calmn
        ! a linear update: the last solve stays the model's base; open again: all stays zero
        if (pt%lin .or. pt%still) return
        call update_error(pt)
        pt%zero = pt%open
        call swap(pt%p, pt%pn)
        call swap(pt%tx, pt%txn)
        call swap(pt%ty, pt%tyn)
        call swap(pt%sx, pt%sxn)
        call swap(pt%sy, pt%syn)
        pt%age = pt%age + 1
        pt%bok = pt%info == STAT_OK .and. pt%out(1) > 0.0_dp
        if (pt%bok) then
            pt%xb = point_inputs(pt)
            pt%yb = linear_outputs(pt%out)
            pt%mub = pt%mu
            pt%vb = pt%speed
            if (pt%jnew) then
                pt%jac = pt%jn
                pt%xj = pt%xb
                pt%age = 0
                pt%jok = .true.
            end if
        else
            pt%jok = .false.
        end if
        pt%jnew = .false.
    contains
        subroutine swap(a, b)
            real(dp), allocatable, intent(inout) :: a(:, :), b(:, :)
            real(dp), allocatable :: t(:, :)
            call move_alloc(a, t)
            call move_alloc(b, a)
            call move_alloc(t, b)
        end subroutine swap
    end subroutine commit_point

    !> Clear the warm starts and counters.
    subroutine bem_reset(handle)
        integer, intent(in) :: handle
        if (.not. live(handle)) return
        call reset(models(handle))
    end subroutine bem_reset

    subroutine bem_free(handle)
        integer, intent(in) :: handle
        integer :: i, t
        if (.not. live(handle)) return
        associate (m => models(handle))
            do t = 1, MAX_THREADS
                call ws_free(m%ws(t))
                do i = 1, m%nwin
                    call ws_free(m%winws(t, i))
                end do
            end do
            m%ws = 0
            m%winws = 0
            m%nwin = 0
            deallocate (m%gap, m%gmin, m%pts, m%ratio, m%lead)
            m%used = .false.
        end associate
    end subroutine bem_free

    logical function live(handle)
        integer, intent(in) :: handle
        live = .false.
        if (handle < 1 .or. handle > MAX_BEM) return
        live = models(handle)%used
    end function live

    !> Solve on windows around the interpenetration (on = .true., the default) or on the
    !> full grid (the reference of the window's test). info: STAT_OK or STAT_BAD_HANDLE.
    subroutine bem_window(handle, on, info)
        integer, intent(in) :: handle
        logical, intent(in) :: on
        integer, intent(out) :: info
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        models(handle)%window = on
        info = STAT_OK
    end subroutine bem_window

    !> Threads of the patch loop: n, or with n <= 0 all the OpenMP runtime offers
    !> (omp_get_max_threads: the cores, or OMP_NUM_THREADS), at most MAX_THREADS; always 1 in
    !> a build without OpenMP. nset: the number set. info: STAT_OK or STAT_BAD_HANDLE.
    !> Python's interrupt handler calls it while a call still runs on the state (a static
    !> solve abandoned to Ctrl-C, down to one thread): each bem_solve_recorded reads the count
    !> once, at its start (one aligned integer).
    subroutine bem_threads(handle, n, nset, info)
        integer, intent(in) :: handle, n
        integer, intent(out) :: nset, info
        nset = threads_of(n)
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        models(handle)%nthreads = nset
        info = STAT_OK
    end subroutine bem_threads

    !> The threads bem_threads sets for n (1 without OpenMP).
    integer function threads_of(n)
        integer, intent(in) :: n
        logical :: omp
        omp = .false.
        !$ omp = .true.
        threads_of = 1
        if (omp) threads_of = n
        !$ if (n <= 0) threads_of = omp_get_max_threads()
        threads_of = min(max(threads_of, 1), MAX_THREADS)
    end function threads_of

    !> Counters since creation or the last reset (see BEM_NCOUNT).
    subroutine bem_counts(handle, counts, info)
        integer, intent(in) :: handle
        real(dp), intent(out) :: counts(BEM_NCOUNT)
        integer, intent(out) :: info
        counts = 0.0_dp
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        counts = models(handle)%counts
        info = STAT_OK
    end subroutine bem_counts

    !> The last fields of wheelset iws, wheel iw (1 left, 2 right), slot k (its lead member's).
    !> info: STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT (sizes or indices).
    subroutine bem_fields(handle, iws, iw, k, nx, ny, p, tx, ty, sx, sy, info)
        integer, intent(in) :: handle, iws, iw, k, nx, ny
        real(dp), intent(out) :: p(nx, ny), tx(nx, ny), ty(nx, ny), sx(nx, ny), sy(nx, ny)
        integer, intent(out) :: info
        type(bem_model), pointer :: m
        p = 0.0_dp
        tx = 0.0_dp
        ty = 0.0_dp
        sx = 0.0_dp
        sy = 0.0_dp
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        m => models(handle)
        info = STAT_BAD_ARGUMENT
        if (nx /= m%s%nx .or. ny /= m%s%ny .or. iws < 1 .or. iws > m%nws .or. iw < 1 .or. iw > 2 &
            .or. k < 1 .or. k > 2) return
        associate (pt => m%pts(m%lead(k, iw, iws), iw, iws))
            p = pt%p
            tx = pt%tx
            ty = pt%ty
            sx = pt%sx
            sy = pt%sy
        end associate
        info = STAT_OK
    end subroutine bem_fields

    !> Normal and tangential contact of one candidate point: wheelset iws, wheel iw (1 left,
    !> 2 right), point k (1..NPT: slot (k + 1) / 2, one member of it), gap field (1 - wa) gap(ia) + wa gap(ib) of the left wheel's table
    !> nodes ia, ib (vehicle_contact%table_at: the same nodes and weight as the point's
    !> scalars, one branch per point, wa outside [0, 1] where a branch is extrapolated), normal
    !> approach dn (m), relative roll phi of wheel against rail (rad: the field tilts by
    !> phi t, the normal component of the rotation e_x x t t_y, so that the roll moment of the
    !> pressure below derives from the same gap), creepages xi, eta (-), spin (1/m), friction
    !> mu, rolling speed (m/s). fn, fx, fy: forces on the wheel in the contact frame (N); mz:
    !> spin moment of the tractions about the normal through the point (N m); xc, yc: centre
    !> of pressure in the contact frame relative to the point (m), so that the moment of the
    !> contact stresses about the point is Fn yc t_x - Fn xc t_y + mz n.
    !> While recording (bem_record) the problem is only stored (fn = 0, info STAT_OK); after
    !> bem_solve_recorded a call with the recorded arguments returns the solution; any other
    !> call solves at once.
    !> info: STAT_OK, STAT_OUTSIDE_TABLE (a node outside the table), STAT_GRID_EDGE (the patch
    !> reaches its grid's edge), STAT_CONTACT_NOT_CONVERGED (a solver did not converge),
    !> STAT_BAD_HANDLE, STAT_BAD_ARGUMENT (iws, iw or k out of range).
    subroutine bem_patch(handle, iws, iw, k, ia, ib, wa, dn, phi, xi, eta, spin, mu, speed, &
                         fn, fx, fy, mz, xc, yc, info)
        integer, intent(in) :: handle, iws, iw, k, ia, ib
        real(dp), intent(in) :: wa, dn, phi, xi, eta, spin, mu, speed
        real(dp), intent(out) :: fn, fx, fy, mz, xc, yc
        integer, intent(out) :: info
        type(bem_model), pointer :: m
        integer :: nt
        logical :: same
        fn = 0.0_dp
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        xc = 0.0_dp
        yc = 0.0_dp
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        m => models(handle)
        if (min(ia, ib) < 1 .or. max(ia, ib) > m%ntab) then
            info = STAT_OUTSIDE_TABLE
            return
        end if
        info = STAT_BAD_ARGUMENT
        if (iws < 1 .or. iws > m%nws .or. iw < 1 .or. iw > 2 .or. k < 1 .or. k > NPT) return
        info = STAT_OK
        associate (pt => m%pts(k, iw, iws))
            same = pt%state == PT_SOLVED .and. pt%ia == ia .and. pt%ib == ib .and. pt%wa == wa &
                   .and. pt%dn == dn .and. pt%phi == phi .and. pt%xi == xi .and. pt%eta == eta &
                   .and. pt%spin == spin .and. pt%mu == mu .and. pt%speed == speed
            if (.not. same) then
                pt%ia = ia
                pt%ib = ib
                pt%wa = wa
                pt%dn = dn
                pt%phi = phi
                pt%xi = xi
                pt%eta = eta
                pt%spin = spin
                pt%mu = mu
                pt%speed = speed
                pt%state = PT_RECORDED
                if (m%recording) return
                nt = 1
                call setup_point(m, k, iw, iws, nt)
                if (.not. (pt%open .or. pt%lin)) then
                    call solve_point(m%s, point_ws(m, k, iw, iws, 1), pt)
                    if (pt%jwant) call point_jacobian(m%s, point_ws(m, k, iw, iws, 1), pt)
                end if
                call commit_point(pt)
                call add_counts(m%counts, pt%cnt)
            end if
            pt%state = PT_IDLE
            fn = pt%out(1)
            fx = pt%out(2)
            fy = pt%out(3)
            mz = pt%out(4)
            xc = pt%out(5)
            yc = pt%out(6)
            info = pt%info
        end associate
    end subroutine bem_patch

    !> Start recording the patch problems of one force evaluation (module doc, Threads).
    subroutine bem_record(handle)
        integer, intent(in) :: handle
        integer :: i, j, l
        if (.not. live(handle)) return
        associate (m => models(handle))
            do l = 1, m%nws
                do j = 1, 2
                    do i = 1, NPT
                        m%pts(i, j, l)%state = PT_IDLE
                    end do
                end do
            end do
            m%recording = .true.
        end associate
    end subroutine bem_record

    !> Stop recording and solve the recorded patches, nthreads at a time (module doc,
    !> Threads). Their solutions and statuses wait in the points for bem_patch.
    subroutine bem_solve_recorded(handle)
        integer, intent(in) :: handle
        type(bem_model), pointer :: m
        integer :: i, j, l, n, nt, t
        integer, allocatable :: list(:, :)
        logical :: failed
        if (.not. live(handle)) return
        m => models(handle)
        m%recording = .false.
        nt = m%nthreads
        allocate (list(3, 2 * NPT * m%nws))
        n = 0
        do l = 1, m%nws
            do j = 1, 2
                do i = 1, NPT
                    if (m%pts(i, j, l)%state /= PT_RECORDED) cycle
                    call setup_point(m, i, j, l, nt)
                    if (m%pts(i, j, l)%open .or. m%pts(i, j, l)%lin) cycle
                    n = n + 1
                    list(:, n) = [i, j, l]
                end do
            end do
        end do
        call largest_first(m, list(:, 1:n))
        ! each point writes its own bem_point only; the workspaces are the thread's own
        !$omp parallel do if (nt > 1 .and. n > 1) num_threads(nt) schedule(dynamic, 1) &
        !$omp default(shared) private(i, t)
        do i = 1, n
            t = 1
            !$ t = omp_get_thread_num() + 1
            call solve_point(m%s, point_ws(m, list(1, i), list(2, i), list(3, i), t), &
                             m%pts(list(1, i), list(2, i), list(3, i)))
            if (m%pts(list(1, i), list(2, i), list(3, i))%jwant) &
                call point_jacobian(m%s, point_ws(m, list(1, i), list(2, i), list(3, i), t), &
                                    m%pts(list(1, i), list(2, i), list(3, i)))
        end do
        !$omp end parallel do
        ! commit in the order of a serial evaluation (wheelset, wheel, point), which stops at
        ! the first failure: the points after it keep their fields and are dropped
        failed = .false.
        do l = 1, m%nws
            do j = 1, 2
                do i = 1, NPT
                    if (m%pts(i, j, l)%state /= PT_RECORDED) cycle
                    if (failed) then
                        m%pts(i, j, l)%state = PT_IDLE
                        cycle
                    end if
                    call commit_point(m%pts(i, j, l))
                    call add_counts(m%counts, m%pts(i, j, l)%cnt)
                    m%pts(i, j, l)%state = PT_SOLVED
                    failed = m%pts(i, j, l)%info /= STAT_OK
                end do
            end do
        end do
    end subroutine bem_solve_recorded

    !> Order the points to solve by their window's area, largest first (stable): the threads
    !> take them in this order, so the long solves (flange and wide tread patches) start first
    !> and the short ones fill in (the results do not depend on the order).
    subroutine largest_first(m, list)
        type(bem_model), intent(in) :: m
        integer, intent(inout) :: list(:, :)
        integer :: i, j, area(size(list, 2)), key(3), a
        do i = 1, size(list, 2)
            associate (pt => m%pts(list(1, i), list(2, i), list(3, i)))
                area(i) = (pt%i2 - pt%i1 + 1) * (pt%j2 - pt%j1 + 1)
            end associate
        end do
        do i = 2, size(list, 2)         ! insertion sort: a few points per wheelset
            key = list(:, i)
            a = area(i)
            j = i - 1
            do while (j >= 1)
                if (area(j) >= a) exit
                list(:, j + 1) = list(:, j)
                area(j + 1) = area(j)
                j = j - 1
            end do
            list(:, j + 1) = key
            area(j + 1) = a
        end do
    end subroutine largest_first

    !> A point's counters cnt into the model's counts (sums; 6, 7 the worst).
    pure subroutine add_counts(counts, cnt)
        real(dp), intent(inout) :: counts(BEM_NCOUNT)
        real(dp), intent(in) :: cnt(BEM_NCOUNT)
        counts(1:5) = counts(1:5) + cnt(1:5)
        counts(6:7) = max(counts(6:7), cnt(6:7))
        counts(8:11) = counts(8:11) + cnt(8:11)
        counts(12) = max(counts(12), cnt(12))
    end subroutine add_counts

    !> Prepare the recorded problem of point (k, iw, iws) for solve_point: its gap field, then
    !> either its opening (no interpenetration: fields cleared, no solve) or its window with a
    !> workspace of the window's size for each of threads 1..nt (made here, serially). nt comes
    !> back lowered when full-grid workspaces could be made for fewer threads.
    subroutine setup_point(m, k, iw, iws, nt)
        type(bem_model), intent(inout) :: m
        integer, intent(in) :: k, iw, iws
        integer, intent(inout) :: nt
        integer :: j, ny, ks
        integer(int64) :: c0, c1
        real(dp) :: y0
        call system_clock(c0)
        ny = m%s%ny
        ks = (k + 1) / 2                ! the point's slot: its gap fields
        associate (pt => m%pts(k, iw, iws), h => m%pts(k, iw, iws)%h)
            pt%cnt = 0.0_dp
            pt%out = 0.0_dp
            pt%info = STAT_OK
            pt%band = m%band
            pt%still = .false.
            pt%stale = .false.
            pt%lin = linear_update(m%band, m%reach, m%jage, pt)
            if (pt%lin .or. surely_open(m, ks, pt)) then
                pt%open = .not. pt%lin
                pt%still = pt%open .and. pt%zero
                if (pt%open .and. .not. pt%still) call clear_new(pt)
                pt%jnew = .false.
                pt%jwant = .false.
                pt%i1 = 1
                pt%i2 = 1
                pt%j1 = 1
                pt%j2 = 1
                pt%cnt(11) = merge(1.0_dp, 0.0_dp, pt%lin)
                pt%cnt(5) = merge(1.0_dp, 0.0_dp, pt%open)
                call system_clock(c1)
                pt%cnt(10) = seconds(c0, c1)
                return
            end if
            if (iw == 1) then
                h = (1.0_dp - pt%wa) * m%gap(:, :, ks, pt%ia) + pt%wa * m%gap(:, :, ks, pt%ib)
                ! an element outside the point's part of the wheel at either node stays outside
                ! (an extrapolation must not pull the 1 m marker into the patch)
                where (max(m%gap(:, :, ks, pt%ia), m%gap(:, :, ks, pt%ib)) >= FAR) h = 1.0_dp
            else
                h = (1.0_dp - pt%wa) * m%gap(:, ny:1:-1, ks, pt%ia) + pt%wa * m%gap(:, ny:1:-1, ks, pt%ib)
                where (max(m%gap(:, ny:1:-1, ks, pt%ia), m%gap(:, ny:1:-1, ks, pt%ib)) >= FAR) h = 1.0_dp
            end if
            y0 = -0.5_dp * real(ny - 1, dp) * m%s%dy
            if (pt%phi /= 0.0_dp) then
                do j = 1, ny
                    where (h(:, j) < FAR) h(:, j) = h(:, j) + pt%phi * (y0 + real(j - 1, dp) * m%s%dy)
                end do
            end if
            pt%open = .not. (pt%dn > minval(h))
            pt%jnew = .false.
            pt%jwant = .false.
            if (pt%open) then
                pt%still = pt%zero
                if (.not. pt%still) call clear_new(pt)
                pt%cnt(5) = 1.0_dp
            else
                call patch_window(m, k, iw, iws, nt)
                pt%jwant = jacobian_due(m%jage, pt) .or. pt%stale
                if (pt%jwant) then
                    ! dh/ds of the field above, h from the nodes ia, ib at weight wa
                    if (.not. allocated(pt%hs)) allocate (pt%hs, mold=h)
                    if (iw == 1) then
                        pt%hs = m%gap(:, :, ks, pt%ib) - m%gap(:, :, ks, pt%ia)
                    else
                        pt%hs = m%gap(:, ny:1:-1, ks, pt%ib) - m%gap(:, ny:1:-1, ks, pt%ia)
                    end if
                    where (h >= FAR) pt%hs = 0.0_dp
                end if
            end if
            call system_clock(c1)
            pt%cnt(10) = seconds(c0, c1)
        end associate
    end subroutine setup_point

    !> Whether point pt (slot ks) is open without its gap field: its approach below a lower
    !> bound of the field's smallest value (the nodes' smallest gaps, interpolated, minus
    !> the largest tilt |phi| t), so setup_point's test on the field would find it open too.
    !> Only for wa in [0, 1] (an extrapolation has no such bound).
    pure logical function surely_open(m, ks, pt) result(open)
        type(bem_model), intent(in) :: m
        integer, intent(in) :: ks
        type(bem_point), intent(in) :: pt
        real(dp) :: lower
        open = .false.
        if (.not. (pt%wa >= 0.0_dp .and. pt%wa <= 1.0_dp)) return
        lower = (1.0_dp - pt%wa) * m%gmin(ks, pt%ia) + pt%wa * m%gmin(ks, pt%ib) &
                - abs(pt%phi) * 0.5_dp * real(m%s%ny - 1, dp) * m%s%dy
        open = .not. (pt%dn > lower)
    end function surely_open

    !> The workspace handle of point (k, iw, iws) on thread t: its window's or the full grid's.
    integer function point_ws(m, k, iw, iws, t)
        type(bem_model), intent(in) :: m
        integer, intent(in) :: k, iw, iws, t
        if (m%pts(k, iw, iws)%iwin > 0) then
            point_ws = m%winws(t, m%pts(k, iw, iws)%iwin)
        else
            point_ws = m%ws(t)
        end if
    end function point_ws

    !> The normal and steady-rolling solves of a prepared point (setup_point) on workspace
    !> wsh (its window's size, the thread's own), warm-started from the point's fields: the
    !> solution (pt%out: fn, fx, fy, mz, xc, yc as for bem_patch; fn = 0 when the normal solve
    !> finds no contact), status, counters and the solve's fields (pn, ...; after a failure the
    !> fields a serial solve would have left: those not reached are the point's) set. Touches
    !> nothing outside pt and the workspace.
    subroutine solve_point(s, wsh, pt)
        type(bem_setup), intent(in) :: s
        integer, intent(in) :: wsh
        type(bem_point), intent(inout) :: pt
        type(workspace), pointer :: ww
        real(dp), allocatable :: hw(:, :), pw(:, :), txw(:, :), tyw(:, :), sxw(:, :), syw(:, :)
        integer, allocatable :: stw(:, :)
        real(dp) :: appr, resid, da, fn, xc, yc, x0, y0
        integer :: it, nprod, stat, nx, ny, i1, i2, j1, j2
        integer(int64) :: c0, c1, c2
        call system_clock(c0)
        nx = s%nx
        ny = s%ny
        i1 = pt%i1
        i2 = pt%i2
        j1 = pt%j1
        j2 = pt%j2
        x0 = -0.5_dp * real(nx - 1, dp) * s%dx
        y0 = -0.5_dp * real(ny - 1, dp) * s%dy
        pt%out = 0.0_dp
        ww => ws_get(wsh, i2 - i1 + 1, j2 - j1 + 1)
        if (.not. associated(ww)) then
            pt%info = STAT_CONTACT_NOT_CONVERGED
            call keep_fields(.true.)
            return
        end if
        pt%info = STAT_OK
        allocate (hw(i2 - i1 + 1, j2 - j1 + 1), stw(i2 - i1 + 1, j2 - j1 + 1))
        allocate (pw, txw, tyw, sxw, syw, mold=hw)
        hw = pt%h(i1:i2, j1:j2)
        pw = pt%p(i1:i2, j1:j2)
        txw = pt%tx(i1:i2, j1:j2)
        tyw = pt%ty(i1:i2, j1:j2)
        appr = pt%dn
        da = s%dx * s%dy
        call system_clock(c1)
        call normal_cg(ww%plan, 1, ww%c(:, :, 1), hw, da, CONTROL_APPROACH, fn, appr, s%tol_n, &
                       s%maxit_n, pw, it, nprod, resid, stat)
        call system_clock(c2)
        pt%cnt(8) = pt%cnt(8) + seconds(c1, c2)
        pt%cnt(1) = pt%cnt(1) + 1.0_dp
        pt%cnt(2) = pt%cnt(2) + real(it, dp)
        pt%pn = 0.0_dp
        if (stat == STAT_NO_CONTACT) then
            call open_point()
            return
        end if
        if (stat /= STAT_OK .or. .not. all(abs(pw) <= huge(1.0_dp))) then
            pt%info = STAT_CONTACT_NOT_CONVERGED
            call keep_fields(.false.)
            return
        end if
        pt%pn(i1:i2, j1:j2) = pw
        pt%cnt(6) = max(pt%cnt(6), resid)
        if (any(pt%pn(1, :) > 0.0_dp) .or. any(pt%pn(nx, :) > 0.0_dp) .or. any(pt%pn(:, 1) > 0.0_dp) &
            .or. any(pt%pn(:, ny) > 0.0_dp)) then
            pt%info = STAT_GRID_EDGE
            call keep_fields(.false.)
            return
        end if
        fn = da * sum(pt%pn)
        if (.not. (fn > 0.0_dp)) then
            call open_point()
            return
        end if
        call pressure_centre(nx, ny, s%dx, s%dy, pt%pn, fn, xc, yc)
        pt%out(1) = fn
        pt%out(5) = xc
        pt%out(6) = yc
        pt%cnt(3) = pt%cnt(3) + 1.0_dp
        call system_clock(c1)
        call rolling_patch_reset(pt%rp)     ! kept if the contact set is the last solve's
        call rolling_steady(ww, pw, x0 + real(i1 - 1, dp) * s%dx, y0 + real(j1 - 1, dp) * s%dy, &
                            pt%xi, pt%eta, pt%spin, pt%mu, pt%speed, ROLL_FFTGS, s%nblock, s%ninner, &
                            s%tol_t, s%maxit_t, txw, tyw, stw, sxw, syw, it, resid, stat, patch=pt%rp)
        call system_clock(c2)
        pt%cnt(9) = pt%cnt(9) + seconds(c1, c2)
        pt%cnt(4) = pt%cnt(4) + real(it, dp)
        pt%txn = 0.0_dp
        pt%tyn = 0.0_dp
        pt%sxn = 0.0_dp
        pt%syn = 0.0_dp
        if (stat == STAT_GRID_EDGE) then
            ! steady rolling needs two free rows behind the patch (contact_rolling)
            pt%info = STAT_GRID_EDGE
        else if ((stat /= STAT_OK .and. stat /= STAT_NO_CONTACT) .or. .not. all(abs(txw) <= huge(1.0_dp)) &
                 .or. .not. all(abs(tyw) <= huge(1.0_dp))) then
            pt%info = STAT_CONTACT_NOT_CONVERGED
        else
            pt%txn(i1:i2, j1:j2) = txw
            pt%tyn(i1:i2, j1:j2) = tyw
            pt%sxn(i1:i2, j1:j2) = sxw
            pt%syn(i1:i2, j1:j2) = syw
            pt%cnt(7) = max(pt%cnt(7), resid)
            pt%out(2) = da * sum(pt%txn)
            pt%out(3) = da * sum(pt%tyn)
            pt%out(4) = spin_moment(nx, ny, s%dx, s%dy, pt%txn, pt%tyn)
        end if
        call point_time()
    contains
        !> The solve's wall time into counter 10 (after the set-up's).
        subroutine point_time()
            call system_clock(c2)
            pt%cnt(10) = pt%cnt(10) + seconds(c0, c2)
        end subroutine point_time

        !> A failure before the rolling solve: the tractions and slips stay the point's (and
        !> with pressure, the pressure too).
        subroutine keep_fields(pressure)
            logical, intent(in) :: pressure
            if (pressure) pt%pn = pt%p
            pt%txn = pt%tx
            pt%tyn = pt%ty
            pt%sxn = pt%sx
            pt%syn = pt%sy
            call point_time()
        end subroutine keep_fields

        !> No contact after all: the fields cleared, counted as an open point.
        subroutine open_point()
            pt%out = 0.0_dp
            call clear_new(pt)
            pt%cnt(5) = pt%cnt(5) + 1.0_dp
            call point_time()
        end subroutine open_point
    end subroutine solve_point

    !> The window (pt%i1:i2, j1:j2) of point (k, iw, iws)'s solve with approach pt%dn on its
    !> gap pt%h (module doc), and its entry pt%iwin in the model's window list with a
    !> workspace for each of threads 1..nt; the full grid (iwin = 0, the full grid's
    !> workspaces made for threads 1..nt, nt lowered if some cannot be) when windows are off,
    !> the window is the grid, or the window's workspaces cannot all be made (the registry or
    !> this model's list full).
    subroutine patch_window(m, k, iw, iws, nt)
        type(bem_model), intent(inout) :: m
        integer, intent(in) :: k, iw, iws
        integer, intent(inout) :: nt
        integer :: i, j, lo(2), hi(2), nxw, nyw, e, t, stat, i1, i2, j1, j2
        i1 = 1
        i2 = m%s%nx
        j1 = 1
        j2 = m%s%ny
        e = 0
        if (m%window) then
            lo = [m%s%nx, m%s%ny]
            hi = [1, 1]
            associate (h => m%pts(k, iw, iws)%h, dn => m%pts(k, iw, iws)%dn)
                do j = 1, m%s%ny
                    do i = 1, m%s%nx
                        if (h(i, j) < dn) then
                            lo = min(lo, [i, j])
                            hi = max(hi, [i, j])
                        end if
                    end do
                end do
            end associate
            call window_span(lo(1), hi(1), m%s%nx, i1, i2)
            call window_span(lo(2), hi(2), m%s%ny, j1, j2)
            nxw = i2 - i1 + 1
            nyw = j2 - j1 + 1
            if (nxw /= m%s%nx .or. nyw /= m%s%ny) e = window_entry(m, nxw, nyw, nt)
            if (e == 0) then
                i1 = 1
                i2 = m%s%nx
                j1 = 1
                j2 = m%s%ny
            end if
        end if
        if (e == 0) then
            do t = 2, nt
                if (m%ws(t) /= 0) cycle
                call ws_create(m%s%nx, m%s%ny, m%s%dx, m%s%dy, m%g, m%nu, .true., m%ws(t), stat)
                if (stat /= STAT_OK) then
                    m%ws(t) = 0
                    nt = t - 1
                    exit
                end if
            end do
        end if
        m%pts(k, iw, iws)%i1 = i1
        m%pts(k, iw, iws)%i2 = i2
        m%pts(k, iw, iws)%j1 = j1
        m%pts(k, iw, iws)%j2 = j2
        m%pts(k, iw, iws)%iwin = e
    end subroutine patch_window

    !> The entry of window size nxw x nyw in the model's list with workspaces for threads
    !> 1..nt (added and made here when missing), or 0 when they cannot all be made.
    integer function window_entry(m, nxw, nyw, nt) result(e)
        type(bem_model), intent(inout) :: m
        integer, intent(in) :: nxw, nyw, nt
        integer :: i, t, stat
        e = 0
        do i = 1, m%nwin
            if (m%win(1, i) == nxw .and. m%win(2, i) == nyw) then
                e = i
                exit
            end if
        end do
        if (e == 0) then
            if (m%nwin >= MAX_WIN) return
            m%nwin = m%nwin + 1
            e = m%nwin
            m%win(:, e) = [nxw, nyw]
            m%winws(:, e) = 0
        end if
        do t = 1, nt
            if (m%winws(t, e) /= 0) cycle
            call ws_create(nxw, nyw, m%s%dx, m%s%dy, m%g, m%nu, .true., m%winws(t, e), stat)
            if (stat /= STAT_OK) then
                m%winws(t, e) = 0
                e = 0
                return
            end if
        end do
    end function window_entry

    !> One side of a window: lo..hi widened by WIN_MARGIN, its length rounded up to a
    !> multiple of WIN_QUANTUM, inside 1..n (the whole side when that does not fit); the
    !> widened lo..hi stays inside a..b.
    pure subroutine window_span(lo, hi, n, a, b)
        integer, intent(in) :: lo, hi, n
        integer, intent(out) :: a, b
        integer :: len
        a = max(1, lo - WIN_MARGIN)
        b = min(n, hi + WIN_MARGIN)
        len = WIN_QUANTUM * ((b - a + WIN_QUANTUM) / WIN_QUANTUM)
        if (len >= n) then
            a = 1
            b = n
            return
        end if
        b = min(n, a + len - 1)
        a = b - len + 1
    end subroutine window_span

    !> Wall seconds between two system_clock counts (int64: microsecond or finer ticks).
    real(dp) function seconds(c1, c2)
        integer(int64), intent(in) :: c1, c2
        integer(int64) :: rate
        call system_clock(count_rate=rate)
        seconds = real(c2 - c1, dp) / real(rate, dp)
    end function seconds

    !> Centre of pressure (xc, yc) of p on the grid centred on the point (0 when fn = 0).
    pure subroutine pressure_centre(nx, ny, dx, dy, p, fn, xc, yc)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, p(nx, ny), fn
        real(dp), intent(out) :: xc, yc
        integer :: i, j
        xc = 0.0_dp
        yc = 0.0_dp
        if (fn <= 0.0_dp) return
        do j = 1, ny
            do i = 1, nx
                xc = xc + p(i, j) * (real(i, dp) - 0.5_dp * real(nx + 1, dp)) * dx
                yc = yc + p(i, j) * (real(j, dp) - 0.5_dp * real(ny + 1, dp)) * dy
            end do
        end do
        xc = xc * dx * dy / fn
        yc = yc * dx * dy / fn
    end subroutine pressure_centre

    !> Moment about the normal through the grid centre of the tractions (tx, ty), N m.
    pure function spin_moment(nx, ny, dx, dy, tx, ty) result(mz)
        integer, intent(in) :: nx, ny
        real(dp), intent(in) :: dx, dy, tx(nx, ny), ty(nx, ny)
        real(dp) :: mz, x, y
        integer :: i, j
        mz = 0.0_dp
        do j = 1, ny
            y = (real(j, dp) - 0.5_dp * real(ny + 1, dp)) * dy
            do i = 1, nx
                x = (real(i, dp) - 0.5_dp * real(nx + 1, dp)) * dx
                mz = mz + x * ty(i, j) - y * tx(i, j)
            end do
        end do
        mz = mz * dx * dy
    end function spin_moment

    !> Committed solves of a point between its patch Jacobians: age (> 0), or 0 for none (the
    !> Newton tangent's cheap model is then Hertz + Kalker scaled to the last solves, as
    !> before issue 18's patch Jacobian). info: STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT
    !> (age < 0).
    subroutine bem_jacobian(handle, age, info)
        integer, intent(in) :: handle, age
        integer, intent(out) :: info
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        info = STAT_BAD_ARGUMENT
        if (age < 0) return
        models(handle)%jage = age
        if (age == 0) models(handle)%pts(:, :, :)%jok = .false.
        info = STAT_OK
    end subroutine bem_jacobian

    !> The patch forces of point (k, iw, iws) from its linear model (the Newton tangent's):
    !> y = yb + jac (x - xb), x = (dn, phi, xi, eta, spin, ia - 1 + wa), y = (fn, fx, fy, mz,
    !> fn xc, fn yc) (bem_patch's arguments and results), the last committed solve (xb, yb)
    !> and the Jacobian from finite differences of the point's own solves (point_jacobian).
    !> ok = .false. (results zero) when the point has none: out of contact at its last solve,
    !> Jacobians off (bem_jacobian), or a bad handle or index.
    subroutine bem_linear(handle, iws, iw, k, ia, wa, dn, phi, xi, eta, spin, fn, fx, fy, mz, xc, yc, ok)
        integer, intent(in) :: handle, iws, iw, k, ia
        real(dp), intent(in) :: wa, dn, phi, xi, eta, spin
        real(dp), intent(out) :: fn, fx, fy, mz, xc, yc
        logical, intent(out) :: ok
        real(dp) :: y(NLIN)
        fn = 0.0_dp
        fx = 0.0_dp
        fy = 0.0_dp
        mz = 0.0_dp
        xc = 0.0_dp
        yc = 0.0_dp
        ok = .false.
        if (.not. live(handle)) return
        if (iws < 1 .or. iws > models(handle)%nws .or. iw < 1 .or. iw > 2 .or. k < 1 .or. k > NPT) return
        associate (pt => models(handle)%pts(k, iw, iws))
            if (.not. (pt%jok .and. pt%bok)) return
            y = pt%yb + matmul(pt%jac, [dn, phi, xi, eta, spin, real(ia - 1, dp) + wa] - pt%xb)
        end associate
        ok = .true.
        fn = y(1)
        fx = y(2)
        fy = y(3)
        mz = y(4)
        if (fn > 0.0_dp) then
            xc = y(5) / fn
            yc = y(6) / fn
        end if
    end subroutine bem_linear

    !> The linear model of slot k's lead point (wheel iw, wheelset iws): jac (dy/dx), the base inputs xb and outputs
    !> yb (bem_linear), the committed solves since the Jacobian (age); ok = .false. when it
    !> has none. info: STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT (indices).
    subroutine bem_point_jacobian(handle, iws, iw, k, jac, xb, yb, age, ok, info)
        integer, intent(in) :: handle, iws, iw, k
        real(dp), intent(out) :: jac(NLIN, NLIN), xb(NLIN), yb(NLIN)
        integer, intent(out) :: age, info
        logical, intent(out) :: ok
        jac = 0.0_dp
        xb = 0.0_dp
        yb = 0.0_dp
        age = 0
        ok = .false.
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        info = STAT_BAD_ARGUMENT
        if (iws < 1 .or. iws > models(handle)%nws .or. iw < 1 .or. iw > 2 .or. k < 1 .or. k > 2) return
        info = STAT_OK
        associate (pt => models(handle)%pts(models(handle)%lead(k, iw, iws), iw, iws))
            ok = pt%jok .and. pt%bok
            jac = pt%jac
            xb = pt%xb
            yb = pt%yb
            age = pt%age
        end associate
    end subroutine bem_point_jacobian

    !> Solve slot k's lead point's patch (wheel iw, wheelset iws) at inputs x (bem_linear's; s within the table nodes
    !> ia, ib of its last committed solve) on the full grid, warm-started from its fields,
    !> without changing the point: y its outputs (bem_linear's). For checks of the linear
    !> model against differences of the solves. info: STAT_OK, STAT_BAD_HANDLE,
    !> STAT_BAD_ARGUMENT (indices, or the point has no committed solve in contact),
    !> STAT_CONTACT_NOT_CONVERGED (a solver failed or the patch is empty).
    subroutine bem_probe(handle, iws, iw, k, x, y, info)
        integer, intent(in) :: handle, iws, iw, k
        real(dp), intent(in) :: x(NLIN)
        real(dp), intent(out) :: y(NLIN)
        integer, intent(out) :: info
        type(bem_model), pointer :: m
        type(workspace), pointer :: ww
        real(dp), allocatable :: h(:, :)
        real(dp) :: cnt(BEM_NCOUNT), wa, y0
        integer :: nx, ny, j, ks, c
        y = 0.0_dp
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        m => models(handle)
        info = STAT_BAD_ARGUMENT
        if (iws < 1 .or. iws > m%nws .or. iw < 1 .or. iw > 2 .or. k < 1 .or. k > 2) return
        ks = k
        c = m%lead(k, iw, iws)
        if (.not. m%pts(c, iw, iws)%bok) return
        nx = m%s%nx
        ny = m%s%ny
        associate (pt => m%pts(c, iw, iws))
            wa = x(6) - real(pt%ia - 1, dp)
            if (iw == 1) then
                h = (1.0_dp - wa) * m%gap(:, :, ks, pt%ia) + wa * m%gap(:, :, ks, pt%ib)
                where (max(m%gap(:, :, ks, pt%ia), m%gap(:, :, ks, pt%ib)) >= FAR) h = 1.0_dp
            else
                h = (1.0_dp - wa) * m%gap(:, ny:1:-1, ks, pt%ia) + wa * m%gap(:, ny:1:-1, ks, pt%ib)
                where (max(m%gap(:, ny:1:-1, ks, pt%ia), m%gap(:, ny:1:-1, ks, pt%ib)) >= FAR) h = 1.0_dp
            end if
            y0 = -0.5_dp * real(ny - 1, dp) * m%s%dy
            do j = 1, ny
                where (h(:, j) < FAR) h(:, j) = h(:, j) + x(2) * (y0 + real(j - 1, dp) * m%s%dy)
            end do
            ww => ws_get(m%ws(1), nx, ny)
            info = STAT_CONTACT_NOT_CONVERGED
            if (.not. associated(ww)) return
            cnt = 0.0_dp
            call probe_solve(m%s, ww, 1, nx, 1, ny, h, x(1), x(3), x(4), x(5), pt%mu, pt%speed, &
                             pt%p, pt%tx, pt%ty, .true., y, cnt, info)
        end associate
    end subroutine bem_probe

    !> Linear updates: with band > 0 a point whose inputs moved little since its last solve
    !> takes its forces from its linear model (bem_linear's, the Newton tangent's) instead
    !> of a solve (linear_update: each input's own first-order change of each force within
    !> band x its normal force, of each moment within band x fn x UPD_ARM); its fields, warm
    !> starts and the model's base stay the last solve's. The error is the model's: second
    !> order in the inputs' moves plus the Jacobian's age (update_error measures it at the
    !> solves near the band's edge). band = 0 (the default here) solves every patch.
    !> info: STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT (band < 0 or not finite).
    subroutine bem_update(handle, band, reach, info)
        integer, intent(in) :: handle
        real(dp), intent(in) :: band, reach
        integer, intent(out) :: info
        info = STAT_BAD_HANDLE
        if (.not. live(handle)) return
        info = STAT_BAD_ARGUMENT
        if (.not. (band >= 0.0_dp .and. band <= huge(1.0_dp))) return
        if (.not. (reach >= 0.0_dp .and. reach <= huge(1.0_dp))) return
        models(handle)%band = band
        models(handle)%reach = reach
        info = STAT_OK
    end subroutine bem_update

    !> Whether point pt's forces at its current problem come from its linear model (module
    !> parameters UPD_*, bem_update): band > 0, a model (a committed solve in contact and a
    !> Jacobian) made for the same friction and speed, no new Jacobian due, the approach
    !> positive, the lateral position within UPD_DS nodes of the base's, and every input's
    !> own term of the model within the band (limits), or with reach > 0 approach and roll
    !> within reach bands (UPD_NEAR_FN). Sets pt%out from the model when so.
    logical function linear_update(band, reach, jage, pt) result(ok)
        real(dp), intent(in) :: band, reach
        integer, intent(in) :: jage
        type(bem_point), intent(inout) :: pt
        real(dp) :: x(NLIN), y(NLIN), r
        ok = .false.
        pt%calmn = 0
        if (.not. (band > 0.0_dp .and. pt%jok .and. pt%bok)) return
        if (pt%mu /= pt%mub .or. pt%speed /= pt%vb .or. .not. (pt%dn > 0.0_dp)) return
        if (jacobian_due(jage, pt)) return
        x = point_inputs(pt)
        if (abs(x(6) - pt%xb(6)) > UPD_DS) return
        r = band_ratio(band, pt, x, pt%xb)
        if (r > 1.0_dp) then
            ! in motion (reach): approach and roll beyond the band, within reach bands, the
            ! creepages and the lateral position within the band, the latter in the base's and the
            ! Jacobian's cell
            if (.not. (reach > 0.0_dp)) return
            if (band_ratio(band, pt, x, pt%xb, BAND_IN) > 1.0_dp .or. r > reach) return
            if (floor(x(6)) /= floor(pt%xb(6)) .or. floor(pt%xj(6)) /= floor(pt%xb(6))) return
        end if
        y = pt%yb + matmul(pt%jac, x - pt%xb)
        if (.not. (y(1) > 0.0_dp)) return
        if (r <= 1.0_dp) pt%calmn = pt%calm + 1
        if (.not. jacobian_fresh(band, reach, pt, x)) then
            ! a new Jacobian with the solve: once calm within the band, or in motion when
            ! only the gap's inputs moved away from the Jacobian's
            pt%stale = pt%calmn >= UPD_CALM .or. &
                       (r > 1.0_dp .and. band_ratio(band, pt, pt%xb, pt%xj, BAND_IN) <= UPD_FRESH)
            return
        end if
        pt%out = [y(1), y(2), y(3), y(4), y(5) / y(1), y(6) / y(1)]
        ok = .true.
    end function linear_update

    !> The largest |jac(k, i) (x_i - x0_i)| over outputs k and inputs i (those in mask when
    !> present) of point pt's linear model, each relative to its limit (band fn_b, for the
    !> moments times UPD_ARM): <= 1 inside the band of bem_update (x0 the base xb).
    pure real(dp) function band_ratio(band, pt, x, x0, mask) result(r)
        real(dp), intent(in) :: band, x(NLIN), x0(NLIN)
        type(bem_point), intent(in) :: pt
        logical, intent(in), optional :: mask(NLIN)
        real(dp) :: lim(NLIN)
        integer :: i
        lim = band * pt%yb(1) * [1.0_dp, 1.0_dp, 1.0_dp, UPD_ARM, UPD_ARM, UPD_ARM]
        r = 0.0_dp
        do i = 1, NLIN
            if (present(mask)) then
                if (.not. mask(i)) cycle
            end if
            r = max(r, maxval(abs(pt%jac(:, i) * (x(i) - x0(i))) / lim))
        end do
    end function band_ratio

    !> Whether point pt's Jacobian was made near its model's base (linear updates): the
    !> lateral position within UPD_DS nodes and every input's term between them within
    !> UPD_FRESH bands; with reach > 0 the gap's inputs (approach, roll: not BAND_IN) need
    !> only their normal-force terms between the Jacobian's inputs and the base's, and
    !> between the Jacobian's and x, within UPD_NEAR_FN x fn.
    pure logical function jacobian_fresh(band, reach, pt, x) result(fresh)
        real(dp), intent(in) :: band, reach, x(NLIN)
        type(bem_point), intent(in) :: pt
        real(dp) :: lim
        fresh = .false.
        if (abs(pt%xb(6) - pt%xj(6)) > UPD_DS) return
        if (.not. (reach > 0.0_dp)) then
            fresh = band_ratio(band, pt, pt%xb, pt%xj) <= UPD_FRESH
            return
        end if
        lim = UPD_NEAR_FN * pt%yb(1)
        if (any(abs(pt%jac(1, :) * (pt%xb - pt%xj)) > lim .and. .not. BAND_IN)) return
        if (any(abs(pt%jac(1, :) * (x - pt%xj)) > lim .and. .not. BAND_IN)) return
        fresh = band_ratio(band, pt, pt%xb, pt%xj, BAND_IN) <= UPD_FRESH
    end function jacobian_fresh

    !> The force error of point pt's linear model at a solve (before its commit): when the
    !> solve's inputs lie within twice the band of bem_update (pt%band, the model's at the
    !> set-up), the largest |fn, fx, fy - the model's| into counter 12 (N): the error of the
    !> linear updates measured just beyond their band, an upper estimate of it.
    subroutine update_error(pt)
        type(bem_point), intent(inout) :: pt
        real(dp) :: x(NLIN), y(NLIN), d(NLIN)
        if (.not. (pt%jok .and. pt%bok .and. pt%info == STAT_OK .and. pt%out(1) > 0.0_dp)) return
        if (.not. (pt%band > 0.0_dp)) return
        x = point_inputs(pt)
        if (abs(x(6) - pt%xb(6)) > UPD_DS .or. band_ratio(pt%band, pt, x, pt%xb) > 2.0_dp) return
        y = pt%yb + matmul(pt%jac, x - pt%xb)
        d = linear_outputs(pt%out) - y
        pt%cnt(12) = max(pt%cnt(12), maxval(abs(d(1:3))))
    end subroutine update_error

    !> Whether point pt's solve should make a new patch Jacobian (the age jage > 0; module
    !> parameters JAC_*): none yet, jage solves old, or the approach or lateral position
    !> moved far from the Jacobian's.
    pure logical function jacobian_due(jage, pt) result(due)
        integer, intent(in) :: jage
        type(bem_point), intent(in) :: pt
        real(dp) :: x(NLIN)
        due = .false.
        if (jage <= 0) return
        x = point_inputs(pt)
        due = .not. pt%jok .or. pt%age >= jage .or. abs(x(1) - pt%xj(1)) > JAC_MOVE * pt%xj(1) &
              .or. abs(x(6) - pt%xj(6)) > JAC_SMOVE
    end function jacobian_due

    !> The linear model's inputs of pt's current problem (bem_linear).
    pure function point_inputs(pt) result(x)
        type(bem_point), intent(in) :: pt
        real(dp) :: x(NLIN)
        x = [pt%dn, pt%phi, pt%xi, pt%eta, pt%spin, real(pt%ia - 1, dp) + pt%wa]
    end function point_inputs

    !> The linear model's outputs (fn, fx, fy, mz, fn xc, fn yc) of a solve's out.
    pure function linear_outputs(out) result(y)
        real(dp), intent(in) :: out(6)
        real(dp) :: y(NLIN)
        y = [out(1), out(2), out(3), out(4), out(1) * out(5), out(1) * out(6)]
    end function linear_outputs

    !> The patch Jacobian of a solved point (solve_point, in contact) by forward differences
    !> of its own solves on its window (workspace wsh), each warm-started from the solution:
    !> approach, roll and lateral position move the gap and need a normal and a rolling solve,
    !> the creepages a rolling solve on the same pressure (the normal problem does not see
    !> them): 3 normal + 6 rolling solves, counted in pt%cnt. Sets pt%jn, and pt%jnew when all
    !> solves succeeded (otherwise the point keeps its old model). Touches nothing outside pt
    !> and the workspace (thread-safe as solve_point).
    subroutine point_jacobian(s, wsh, pt)
        type(bem_setup), intent(in) :: s
        integer, intent(in) :: wsh
        type(bem_point), intent(inout) :: pt
        type(workspace), pointer :: ww
        real(dp), allocatable :: hw(:, :), tilt(:, :)
        real(dp) :: x(NLIN), y0(NLIN), y(NLIN), d, appr, cr(3), yl
        integer :: j, jj, stat, i1, i2, j1, j2
        integer(int64) :: c0, c1
        call system_clock(c0)
        pt%jnew = .false.
        if (pt%info /= STAT_OK .or. .not. (pt%out(1) > 0.0_dp)) return
        i1 = pt%i1
        i2 = pt%i2
        j1 = pt%j1
        j2 = pt%j2
        ww => ws_get(wsh, i2 - i1 + 1, j2 - j1 + 1)
        if (.not. associated(ww)) return
        x = point_inputs(pt)
        y0 = linear_outputs(pt%out)
        allocate (tilt(i2 - i1 + 1, j2 - j1 + 1))
        do jj = j1, j2     ! d h / d phi: the lateral coordinate, where the field is the point's
            yl = (-0.5_dp * real(s%ny - 1, dp) + real(jj - 1, dp)) * s%dy
            tilt(:, jj - j1 + 1) = merge(yl, 0.0_dp, pt%h(i1:i2, jj) < FAR)
        end do
        do j = 1, NLIN
            hw = pt%h(i1:i2, j1:j2)
            appr = pt%dn
            cr = [pt%xi, pt%eta, pt%spin]
            select case (j)
            case (1)
                d = -JAC_DN * pt%dn
                appr = appr + d
            case (2)
                d = JAC_PHI
                hw = hw + d * tilt
            case (3, 4)
                d = JAC_CREEP
                cr(j - 2) = cr(j - 2) + d
            case (5)
                d = JAC_SPIN
                cr(3) = cr(3) + d
            case default
                ! within the cell of ia, ib (the field is linear in wa there)
                d = merge(-JAC_DS, JAC_DS, pt%wa > 0.5_dp)
                hw = hw + d * pt%hs(i1:i2, j1:j2)
            end select
            call probe_solve(s, ww, i1, i2, j1, j2, hw, appr, cr(1), cr(2), cr(3), pt%mu, pt%speed, &
                             pt%pn, pt%txn, pt%tyn, j /= 3 .and. j /= 4 .and. j /= 5, y, pt%cnt, stat, pt%rp)
            if (stat /= STAT_OK) exit
            pt%jn(:, j) = (y - y0) / d
        end do
        pt%jnew = stat == STAT_OK
        call system_clock(c1)
        pt%cnt(10) = pt%cnt(10) + seconds(c0, c1)
    end subroutine point_jacobian

    !> The outputs y (linear_outputs) of the patch problem on the window (i1:i2, j1:j2) of
    !> the grid (workspace ww of its size): gap hw (the window's), approach appr, creepages,
    !> friction, speed, warm-started from the full-grid fields p0, tx0, ty0; normal =
    !> .false.: the pressure p0 kept, only the rolling solve. Counters into cnt (1-4, the
    !> solves' wall times 8, 9). rp: the point's kept rolling patch (bem_point%rp). stat:
    !> STAT_OK, or STAT_CONTACT_NOT_CONVERGED when a solver fails or the patch is empty.
    subroutine probe_solve(s, ww, i1, i2, j1, j2, hw, appr, xi, eta, spin, mu, speed, p0, tx0, ty0, &
                           normal, y, cnt, stat, rp)
        type(bem_setup), intent(in) :: s
        type(workspace), intent(inout) :: ww
        integer, intent(in) :: i1, i2, j1, j2
        real(dp), intent(in) :: hw(:, :), appr, xi, eta, spin, mu, speed
        real(dp), intent(in) :: p0(:, :), tx0(:, :), ty0(:, :)
        logical, intent(in) :: normal
        real(dp), intent(out) :: y(NLIN)
        real(dp), intent(inout) :: cnt(BEM_NCOUNT)
        integer, intent(out) :: stat
        type(rolling_patch), intent(inout), optional :: rp
        real(dp), allocatable :: pw(:, :), txw(:, :), tyw(:, :), sxw(:, :), syw(:, :), full(:, :), fy2(:, :)
        integer, allocatable :: stw(:, :)
        real(dp) :: da, fn, ap, resid, xc, yc
        integer :: it, nprod
        integer(int64) :: c1, c2
        y = 0.0_dp
        da = s%dx * s%dy
        pw = p0(i1:i2, j1:j2)
        txw = tx0(i1:i2, j1:j2)
        tyw = ty0(i1:i2, j1:j2)
        allocate (sxw, syw, mold=pw)
        allocate (stw(i2 - i1 + 1, j2 - j1 + 1))
        if (normal) then
            ap = appr
            call system_clock(c1)
            call normal_cg(ww%plan, 1, ww%c(:, :, 1), hw, da, CONTROL_APPROACH, fn, ap, s%tol_n, &
                           s%maxit_n, pw, it, nprod, resid, stat)
            call system_clock(c2)
            cnt(8) = cnt(8) + seconds(c1, c2)
            cnt(1) = cnt(1) + 1.0_dp
            cnt(2) = cnt(2) + real(it, dp)
            if (stat /= STAT_OK .or. .not. all(abs(pw) <= huge(1.0_dp))) then
                stat = STAT_CONTACT_NOT_CONVERGED
                return
            end if
        end if
        fn = da * sum(pw)
        stat = STAT_CONTACT_NOT_CONVERGED
        if (.not. (fn > 0.0_dp)) return
        allocate (full(s%nx, s%ny), fy2(s%nx, s%ny), source=0.0_dp)
        full(i1:i2, j1:j2) = pw
        call pressure_centre(s%nx, s%ny, s%dx, s%dy, full, fn, xc, yc)
        call system_clock(c1)
        if (present(rp)) call rolling_patch_reset(rp)
        call rolling_steady(ww, pw, (real(i1 - 1, dp) - 0.5_dp * real(s%nx - 1, dp)) * s%dx, &
                            (real(j1 - 1, dp) - 0.5_dp * real(s%ny - 1, dp)) * s%dy, xi, eta, spin, &
                            mu, speed, ROLL_FFTGS, s%nblock, s%ninner, s%tol_t, s%maxit_t, txw, tyw, &
                            stw, sxw, syw, it, resid, stat, patch=rp)
        call system_clock(c2)
        cnt(9) = cnt(9) + seconds(c1, c2)
        cnt(3) = cnt(3) + 1.0_dp
        cnt(4) = cnt(4) + real(it, dp)
        if ((stat /= STAT_OK .and. stat /= STAT_NO_CONTACT) .or. .not. all(abs(txw) <= huge(1.0_dp)) &
            .or. .not. all(abs(tyw) <= huge(1.0_dp))) then
            stat = STAT_CONTACT_NOT_CONVERGED
            return
        end if
        stat = STAT_OK
        full = 0.0_dp
        full(i1:i2, j1:j2) = txw
        fy2(i1:i2, j1:j2) = tyw
        y = [fn, da * sum(txw), da * sum(tyw), spin_moment(s%nx, s%ny, s%dx, s%dy, full, fy2), &
             fn * xc, fn * yc]
    end subroutine probe_solve

    !> Get (set = .false.) or store (set = .true.) the calibration ratios (normal, tangential)
    !> of one point; a bad handle or index leaves r = 1.
    subroutine bem_scale(handle, iws, iw, k, set, r)
        integer, intent(in) :: handle, iws, iw, k
        logical, intent(in) :: set
        real(dp), intent(inout) :: r(2)
        if (.not. live(handle)) then
            if (.not. set) r = 1.0_dp
            return
        end if
        if (iws < 1 .or. iws > models(handle)%nws .or. iw < 1 .or. iw > 2 .or. k < 1 .or. k > NPT) return
        if (set) then
            models(handle)%ratio(:, k, iw, iws) = r
        else
            r = models(handle)%ratio(:, k, iw, iws)
        end if
    end subroutine bem_scale

    !> Record point c (1..NPT) as the lead member of its slot (c + 1) / 2 at wheel iw of
    !> wheelset iws: the member that carried the larger share at this evaluation. A bad
    !> handle or index is ignored.
    subroutine bem_lead(handle, iws, iw, c)
        integer, intent(in) :: handle, iws, iw, c
        if (.not. live(handle)) return
        if (iws < 1 .or. iws > models(handle)%nws .or. iw < 1 .or. iw > 2 .or. c < 1 .or. c > NPT) return
        models(handle)%lead((c + 1) / 2, iw, iws) = c
    end subroutine bem_lead

end module vehicle_bem
