!> Steady-state rolling contact of quasi-identical bodies: the tangential
!> tractions for a given pressure, creepages and Coulomb friction (Kaiser,
!> eqs 24-29; Kalker 1990, ch. 2 and 5).
!> Implements Kaiser eqs 24-29. Eq. 29 departs from the printing: upstream elements
!> i + 1, i + 2 (the paper's text, not its x - da) and the th = 1/3 stencil (docs/equations.md).
!>
!> Kinematics. The contact patch is fixed; material particles move through it
!> in -x at the rolling speed V, so the leading edge is at the largest x.
!> In units of V (creepage units) the slip of element I = (i, j) is
!>
!>   s_I = w_I + ((1 + th) u_i - (1 + 2 th) u_i+1 + th u_i+2) / dx,   (eq. 29)
!>   w_x = xi - phi y_j,   w_y = eta + phi x_i,
!>
!> the difference quotient being the material derivative of the displacement
!> difference u = A t over dt = dx / V, from the displacements of the
!> particle now and one and two time steps before (the upstream elements
!> i + 1, i + 2 of row j, taken from the full field u = A t, non-zero outside
!> the contact area too). With this sign convention a positive xi gives a
!> negative Fx (Fx = -G a b C11 xi in the linear limit).
!>
!> The three-point upwind stencil with weight th = THETA is the two-point
!> difference (ut_i - ut_i+1) / dx of the displacement extrapolated
!> downstream, ut_i = u_i + th (u_i - u_i+1) ~ u(x_i - th dx), so it takes
!> -du/dx at x_i + (1/2 - th) dx. th = 0 is Kalker's two-point difference
!> (first order: slip at x_i + dx/2, traction and bound at x_i), th = 1/2
!> the second-order backward difference (BDF2) at x_i. Against Carter's exact
!> 2-D profile (largest error in % of mu p0 over kappa = 0.05..0.99, 40
!> elements across, a 2-D prototype of this kernel): th = 0 7.4 % (stick zone
!> too long by about half an element), th = 1/2 4.9 % (too short, kappa -> 1),
!> th = 0.3..0.4 2.3-2.5 %. th = 1/3 is used: slip at x_i + dx/6.
!> In the solver ut = At t with At(d) = (1 + th) A(d) - th A(d + dx) replaces
!> u = A t (non-symmetric Toeplitz in x), and the two-point form is kept.
!>
!> Friction law per element in contact (p > 0), g = mu p:
!>   adhesion  s = 0,               |t| <= g                    (eq. 26)
!>   slip      t = -g s / |s|,      |t| = g                     (eq. 28)
!> The element's own traction enters its slip through the diagonal block
!> D = (At(0, 0) - At(+dx, 0)) / dx, which is diagonal (A_xy vanishes on the
!> x axis), so s = s0 + D t is affine in t and the element problem is solved
!> exactly on the Coulomb disc (element_solve): the adhesion traction
!> -D^-1 s0 if it lies in the disc, else the unique t = -g e with
!> s = lambda e, lambda > 0, found by a monotone Newton iteration on lambda.
!>
!> Other friction laws (static/kinetic, slip-velocity dependent: contact_friction)
!> replace element_solve by friction_element_solve (bound mu(V lam) p; where several
!> solutions exist, the law's rule picks one: the smallest slip, or the one nearest the
!> current iterate's slip) when rolling_steady gets one.
!>
!> Iteration: row-implicit Gauss-Seidel. Point Gauss-Seidel on this system
!> diverges (spectral radius 115 for a 208-element Hertz patch): the element's
!> own pivot At(0) - At(+dx) is as large as its coupling to the downstream
!> neighbour, so fixing one element spoils the next. Sweeps therefore go
!> over the rows (lines along x, j ascending); within a contiguous run k..l
!> of a row the element updates use the in-row basis
!>   m_q = At_run^-1 C e_q,   (C e_q)_p = 1 for p <= q (downstream of q),
!> i.e. the tractions whose own-row (extrapolated) displacement ut is a unit
!> step ending at q:
!> they change the in-row slip at element q alone (and at the leading
!> element through the upstream displacement), so each run's linear part is
!> solved exactly in one pass, marching from the leading edge. The element
!> problem on the Coulomb disc is solved exactly with that pivot
!> (element_solve). The bases depend only on the run length (Toeplitz,
!> LAPACK LU inverse by common_dense, cached per solve). The row-to-row coupling is
!> plain Gauss-Seidel: after each run its traction change updates the
!> displacements of the rows still to be processed in the current block;
!> before each block the whole field u = A t is refreshed by one FFT pair
!> product. Method 'gs' (1) uses one block (exact direct updates, O(N^2) per
!> sweep); 'fftgs' (2) blocks of nblock rows (O(N nblock nx) + one FFT per
!> block). On a small patch in a large grid (the 11 x 11 creep case, the
!> vehicle's fixed grids around a wheel's patch) the refresh is cheaper as
!> direct sums of the contact set's tractions onto the rows and columns the
!> slip reads (box_apply, O(nc x box)) than as a padded FFT over the whole grid;
!> direct_is_cheaper picks by a count of operations (product PRODUCT_AUTO), and
!> PRODUCT_FFT / PRODUCT_DIRECT force one. They agree to rounding. The solver reads
!> u only through the slip's difference quotient at the elements in contact
!> (field), so the direct form of a contact set of at most SOP_MAX elements is one
!> dense (2 nc x 2 nc) slip operator made per solve (slip_operator).
!> Both accelerate the sweep map by Anderson mixing (depth AA_M,
!> common_anderson), with a safeguard that falls back to the plain sweep when
!> the residual grows.
!> (With th = 1/3 the plain sweeps stagnate or diverge in partial slip, e.g.
!> residual 0.0065 after 500 sweeps on a 424-element Hertz patch with spin;
!> Anderson mixing converges in 19-40 sweeps in every case tried.)
!>
!> Convergence: the relative change of a Jacobi step on the exact field,
!>   r = || F(t) - t ||_2 / || F(t) ||_2,
!> F being the element solutions with a single-element pivot: zero exactly at
!> the solution. At exit every traction is put on its disc.
!>
!> Layout: rolling_steady drives the iteration; patch_setup gathers the fixed
!> data of one solve into a rolling_patch (contact set, bounding box, rigid slip,
!> coefficients At by offset, in-row bases); sweep, solve_run, run_passes and
!> spread_run_change make one row-implicit sweep; jacobi_residual and
!> final_slip evaluate the element problems on the exact field.
module contact_rolling
    use common_kinds, only: dp
    use common_dense, only: dense_inverse
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, &
                             STAT_BAD_HANDLE, STAT_GRID_EDGE, STAT_NOT_FINITE, STAT_SINGULAR
    use common_anderson, only: anderson_state, anderson_init, anderson_step, anderson_restart
    use contact_influence, only: KERNEL_XX, KERNEL_YY, KERNEL_XY
    use contact_plans, only: workspace
    use contact_convolution, only: conv_plan, conv_apply_pair
    use contact_friction, only: friction_law, friction_element_solve, friction_is_constant, RULE_CONTINUOUS
    implicit none
    private
    public :: rolling_steady, element_solve, rolling_patch, rolling_patch_reset
    public :: ROLL_GS, ROLL_FFTGS, ST_EXTERIOR, ST_ADHESION, ST_SLIP
    public :: PRODUCT_AUTO, PRODUCT_FFT, PRODUCT_DIRECT
    public :: WU0, WU1, WU2

    integer, parameter :: ROLL_GS = 1, ROLL_FFTGS = 2
    integer, parameter :: ST_EXTERIOR = 0, ST_ADHESION = 1, ST_SLIP = 2
    integer, parameter :: AA_M = 5   ! Anderson depth of both methods
    !> How the field u = A t is formed: the cheaper way by a count of operations
    !> (direct_is_cheaper), always by FFT (the reference), or always directly.
    integer, parameter :: PRODUCT_AUTO = 0, PRODUCT_FFT = 1, PRODUCT_DIRECT = 2
    !> Weight of the three-point upwind difference (module doc) and its stencil.
    real(dp), parameter :: THETA = 1.0_dp / 3.0_dp
    real(dp), parameter :: WU0 = 1.0_dp + THETA, WU1 = -(1.0_dp + 2.0_dp * THETA), WU2 = THETA
    !> Largest contact set whose dense slip operator direct products use: its matrix
    !> (at most 313 KB) stays in cache; a larger one streams from memory on every
    !> product and loses to box_apply (25 x 25 grid, 210 in contact: 6 % slower).
    integer, parameter :: SOP_MAX = 100

    !> In-row basis of a run of n elements (make_basis).
    type :: run_basis
        real(dp), allocatable :: mx(:, :), my(:, :), qx(:), qy(:)
        !> per element of the run: the pivots of its element problem (px, py), their
        !> reciprocals (rpx, rpy) and 1 / m(q, q) (rmx, rmy), for the small path's passes
        real(dp), allocatable :: px(:), py(:), rpx(:), rpy(:), rmx(:), rmy(:)
    end type run_basis

    !> The fixed data of one solve (patch_setup): the contact set and its
    !> bounding box, the rigid slip, the coefficients At by offset and the
    !> in-row bases. Only the tractions and displacement fields change.
    type :: rolling_patch
        integer :: nx = 0, ny = 0                 ! grid size
        real(dp) :: dx = 0.0_dp                   ! element length along x (rolling), m
        integer :: i1 = 0, i2 = 0, j1 = 0, j2 = 0 ! bounding box of the contact set
        integer :: ib2 = 0                        ! i2 + 1: the upstream row the slip needs
        integer :: nbx = 0, nby = 0               ! offsets spanned by the box
        integer :: nc = 0                         ! elements in contact
        logical :: direct = .false.               ! u = A t by direct sums over the box (box_apply)
        integer, allocatable :: ic(:), jc(:)      ! (nc) the contact set, column by column
        real(dp) :: kx = 0.0_dp, ky = 0.0_dp      ! single-element pivots (At(0) - At(dx)) / dx, 1/Pa
        logical, allocatable :: inc(:, :)         ! (nx, ny) element in contact, p > 0
        integer, allocatable :: trail(:, :)       ! (nx, ny) trailing end of the run through (i, j)
        integer, allocatable :: rlo(:), rhi(:)    ! (j1:j2) first and last element in contact of row j
        real(dp), allocatable :: bound(:, :)      ! (nx, ny) traction bound mu p, Pa
        real(dp), allocatable :: wx(:, :), wy(:, :)   ! (nx, ny) rigid slip, creepage units
        !> At by offset (-nbx-1..nbx+1, -nby..nby), for the bases and the cross-row updates
        real(dp), allocatable :: axx(:, :), ayy(:, :), axy(:, :)
        !> A itself by offset, same bounds (direct products only)
        real(dp), allocatable :: rxx(:, :), ryy(:, :), rxy(:, :)
        !> (2 nc, 2 nc) dense slip operator of the contact set (direct products, nc <= SOP_MAX)
        real(dp), allocatable :: sop(:, :)
        type(run_basis), allocatable :: bases(:)  ! by run length 1..nbx
        !> the small path (pa%sop made): the runs in sweep order (rows j ascending, within
        !> a row from the leading edge), as packed positions: first element rp0, length rn,
        !> first element whose slip the run's change must update rrow (its row's first, or
        !> the next row's when the run fills its row); the rigid slip and the bound packed
        integer :: nrun = 0
        integer, allocatable :: rp0(:), rn(:), rrow(:)
        real(dp), allocatable :: wxc(:), wyc(:), bc(:)
        !> the geometry (everything but the rigid slip) is set: a caller's patch
        !> (rolling_steady's patch) is reused for the next solve of the same pressure
        logical :: ready = .false.
        integer :: prod = -1                      ! the product choice it was made for
        !> a slip-velocity-dependent or static/kinetic friction law (contact_friction):
        !> bound holds mu_s p and the element problems go to friction_element_solve
        logical :: varlaw = .false.
        type(friction_law) :: law
        real(dp) :: speed = 0.0_dp                ! rolling speed, m/s
    end type rolling_patch

contains

    !> Radial return of one element's traction onto the Coulomb disc
    !> |t| <= bound (the slip direction is kept).
    elemental subroutine project_on_disc(tx, ty, bound)
        real(dp), intent(inout) :: tx, ty
        real(dp), intent(in) :: bound
        real(dp) :: t
        t = sqrt(tx * tx + ty * ty)    ! tractions and slips are far from over/underflow
        if (t > bound) then
            tx = tx * bound / t
            ty = ty * bound / t
        end if
    end subroutine project_on_disc

    !> Exact solution of one element's friction problem with s = s0 + diag(kx, ky) t
    !> (eqs 26 and 28). stat: ST_ADHESION (s = 0) or ST_SLIP (|t| = g, t opposite
    !> to s); lam = |s| (0 in adhesion).
    pure subroutine element_solve(s0x, s0y, kx, ky, g, tx, ty, stat, lam)
        real(dp), intent(in) :: s0x, s0y   ! slip with the element's own traction removed
        real(dp), intent(in) :: kx, ky     ! diagonal self-influence (> 0), 1/Pa
        real(dp), intent(in) :: g          ! traction bound mu p, Pa
        real(dp), intent(out) :: tx, ty
        integer, intent(out) :: stat
        real(dp), intent(out) :: lam
        real(dp) :: ax, ay, gx, gy, ex, ey, en

        ax = -s0x / kx
        ay = -s0y / ky
        if (ax * ax + ay * ay <= g * g) then
            tx = ax
            ty = ay
            stat = ST_ADHESION
            lam = 0.0_dp
            return
        end if
        stat = ST_SLIP
        if (g <= 0.0_dp) then
            tx = 0.0_dp
            ty = 0.0_dp
            lam = sqrt(s0x * s0x + s0y * s0y)
            return
        end if
        ! s = lam e and t = -g e  =>  e = (s0x / (lam + g kx), s0y / (lam + g ky)),
        ! |e| = 1 fixes lam. f(lam) = |e|^2 - 1 is convex and decreasing, so Newton
        ! converges from any start: at worst the first step overshoots below the
        ! root and the rest is monotone. The start |s0| - g k, k the mean of kx, ky
        ! weighted by s0's components, is exact for kx = ky and within a few per
        ! cent of the root otherwise: 2-3 steps (4-5 from |s0| - g max(kx, ky)).
        ! The convergence is quadratic, so a step below 1e-8 of the scale leaves an
        ! error of order 1e-16 after it.
        gx = g * kx
        gy = g * ky
        en = s0x * s0x + s0y * s0y
        lam = max(0.0_dp, sqrt(en) - (gx * s0x * s0x + gy * s0y * s0y) / en)
        call slip_root(s0x, s0y, gx, gy, 1.0e-8_dp, lam)
        ex = s0x / (lam + gx)
        ey = s0y / (lam + gy)
        en = sqrt(ex * ex + ey * ey)
        if (en > 0.0_dp) then
            ex = ex / en
            ey = ey / en
        end if
        tx = -g * ex
        ty = -g * ey
    end subroutine element_solve

    !> element_solve on the small path (iterate_small): the reciprocals rkx = 1 / kx,
    !> rky = 1 / ky given (a run's pivots, kept with its basis: no division in the adhesion
    !> test) and the slip solution by element_slip (its closer start and earlier stop: the
    !> same tractions to about 1e-11 relative). element_solve itself, which the grid path
    !> and contact_coupling use, is unchanged (their results stay main's to the bit).
    pure subroutine element_solve_r(s0x, s0y, kx, ky, rkx, rky, g, tx, ty, stat, lam)
        real(dp), intent(in) :: s0x, s0y, kx, ky, rkx, rky, g
        real(dp), intent(out) :: tx, ty, lam
        integer, intent(out) :: stat
        real(dp) :: ax, ay
        ax = -s0x * rkx
        ay = -s0y * rky
        if (ax * ax + ay * ay <= g * g) then
            tx = ax
            ty = ay
            stat = ST_ADHESION
            lam = 0.0_dp
            return
        end if
        call element_slip(s0x, s0y, kx, ky, g, tx, ty, lam)
        stat = ST_SLIP
    end subroutine element_solve_r

    !> Newton's iteration for the slip multiplier lam of element_solve and element_slip
    !> (eq. 28): f(lam) = |e|^2 - 1 with e = (s0x / (lam + gx), s0y / (lam + gy)), from the
    !> caller's start, stopped once a step is below tol of the scale lam + gx + gy.
    pure subroutine slip_root(s0x, s0y, gx, gy, tol, lam)
        real(dp), intent(in) :: s0x, s0y, gx, gy, tol
        real(dp), intent(inout) :: lam
        real(dp) :: f, fp, dl, dx3, dy3
        integer :: it
        do it = 1, 100
            dx3 = 1.0_dp / (lam + gx)
            dy3 = 1.0_dp / (lam + gy)
            f = (s0x * dx3)**2 + (s0y * dy3)**2 - 1.0_dp
            fp = -2.0_dp * ((s0x * dx3)**2 * dx3 + (s0y * dy3)**2 * dy3)
            if (fp >= 0.0_dp) exit
            dl = -f / fp
            lam = max(lam + dl, 0.0_dp)
            if (abs(dl) <= tol * (lam + gx + gy)) exit
        end do
    end subroutine slip_root

    !> The slip solution of element_solve (eq. 28), |t| = g with t opposite to s, when the
    !> adhesion traction lies outside the disc, for the small path: element_solve's Newton
    !> iteration from the second-order start below, stopped once a step is below 1e-6 of
    !> the scale (element_solve: 1e-8 from a first-order start).
    pure subroutine element_slip(s0x, s0y, kx, ky, g, tx, ty, lam)
        real(dp), intent(in) :: s0x, s0y, kx, ky, g
        real(dp), intent(out) :: tx, ty, lam
        real(dp) :: gx, gy, f, ex, ey, en, dx3, dy3

        if (g <= 0.0_dp) then
            tx = 0.0_dp
            ty = 0.0_dp
            lam = sqrt(s0x * s0x + s0y * s0y)
            return
        end if
        ! s = lam e and t = -g e  =>  e = (s0x / (lam + gx), s0y / (lam + gy)),
        ! |e| = 1 fixes lam. f(lam) = |e|^2 - 1 is convex and decreasing, so Newton
        ! converges from any start: at worst the first step overshoots below the
        ! root and the rest is monotone. The start: with mu = lam + c, c = (gx + gy) / 2,
        ! d = (gx - gy) / 2, the root's expansion in delta = d / |s0| to second order,
        ! mu = |s0| (1 - delta rho + 3/2 delta^2 (1 - rho^2)), rho = (s0x^2 - s0y^2) / |s0|^2
        ! (exact for kx = ky; the first-order term alone is the mean of kx, ky weighted by
        ! s0's components): 2-3 steps (about one more from the first-order start).
        ! The convergence is quadratic (error after a step about 3/2 dl^2 / (lam + g k)),
        ! so a step below 1e-6 of the scale leaves a relative error below about 1e-11.
        gx = g * kx
        gy = g * ky
        en = s0x * s0x + s0y * s0y
        dx3 = sqrt(en)
        dy3 = 0.5_dp * (gx - gy) / dx3
        f = (s0x * s0x - s0y * s0y) / en
        lam = max(0.0_dp, dx3 * (1.0_dp - dy3 * f + 1.5_dp * dy3 * dy3 * (1.0_dp - f * f)) - 0.5_dp * (gx + gy))
        call slip_root(s0x, s0y, gx, gy, 1.0e-6_dp, lam)
        ex = s0x / (lam + gx)
        ey = s0y / (lam + gy)
        en = sqrt(ex * ex + ey * ey)
        if (en > 0.0_dp) then
            en = g / en
            ex = ex * en
            ey = ey * en
        else
            ex = g * ex
            ey = g * ey
        end if
        tx = -ex
        ty = -ey
    end subroutine element_slip

    !> The element problem by the solve's friction law: element_solve (constant
    !> Coulomb: today's path, unchanged) or contact_friction's friction_element_solve;
    !> (scx, scy): the slip of the current iterate, for the rule RULE_CONTINUOUS.
    !> nsol_out (optional): the element problem's solutions (1 on today's path).
    pure subroutine element_any(pa, s0x, s0y, kx, ky, g, scx, scy, tx, ty, stat, lam, nsol_out)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: s0x, s0y, kx, ky, g, scx, scy
        real(dp), intent(out) :: tx, ty, lam
        integer, intent(out) :: stat
        integer, intent(out), optional :: nsol_out
        integer :: nsol
        nsol = 1
        if (pa%varlaw) then
            if (pa%law%rule == RULE_CONTINUOUS) then
                call friction_element_solve(pa%law, pa%speed, s0x, s0y, kx, ky, g, tx, ty, stat, lam, nsol, &
                                            lam_prev=sqrt(scx * scx + scy * scy))
            else
                call friction_element_solve(pa%law, pa%speed, s0x, s0y, kx, ky, g, tx, ty, stat, lam, nsol)
            end if
        else
            call element_solve(s0x, s0y, kx, ky, g, tx, ty, stat, lam)
        end if
        if (present(nsol_out)) nsol_out = nsol
    end subroutine element_any

    !> Steady rolling: tangential tractions for the pressure p on the grid of
    !> workspace w (made with the tangential kernels).
    !>
    !> info: STAT_OK converged; STAT_NOT_CONVERGED after max_iter sweeps (resid
    !> holds the residual, the tractions the last iterate); STAT_NO_CONTACT no
    !> element with p > 0 (t = 0); STAT_BAD_HANDLE a workspace without the
    !> tangential kernels; STAT_BAD_ARGUMENT a bad method, or nblock or ninner < 1;
    !> STAT_GRID_EDGE the contact set reaches i = nx - 1 (fewer than two upstream
    !> elements); STAT_NOT_FINITE non-finite values (resid = huge); STAT_SINGULAR
    !> or STAT_LAPACK the LU inverse of a run basis failed.
    !> product (optional, PRODUCT_AUTO by default): how u = A t is formed, by FFT
    !> (PRODUCT_FFT) or by direct sums over the contact box (PRODUCT_DIRECT); the
    !> two agree to rounding.
    !> law (optional): a friction law (contact_friction) other than constant Coulomb;
    !> mu must then be law%mu_s. Without it (or with mu_s = mu_k) today's path runs
    !> unchanged. nmulti (optional): elements whose final element problem has more
    !> than one solution (the law's rule picked one of them; 0 without law).
    !> patch (optional): the solve's fixed data, kept by the caller for the next solve of
    !> the same pressure p, mu, grid origin and product (a creep-force table's cases):
    !> made when patch%ready is false (new, or after rolling_patch_reset), reused as it is
    !> otherwise (only the rigid slip is set again). Without it every solve makes its own.
    subroutine rolling_steady(w, p, x0, y0, xi, eta, phi, mu, speed, method, nblock, ninner, tol, max_iter, &
                              tx, ty, status, sx, sy, iters, resid, info, product, law, nmulti, wex, wey, patch)
        type(workspace), intent(inout) :: w
        real(dp), intent(in) :: p(:, :)            ! pressure, Pa, (nx, ny)
        real(dp), intent(in) :: x0, y0             ! centre of element (1, 1), m
        real(dp), intent(in) :: xi, eta, phi       ! creepages (1, 1, 1/m)
        real(dp), intent(in) :: mu, speed          ! friction coefficient, rolling speed (m/s)
        integer, intent(in) :: method, max_iter
        integer, intent(in) :: nblock, ninner     ! rows per FFT refresh ('fftgs'), passes per row
        real(dp), intent(in) :: tol
        real(dp), intent(inout) :: tx(:, :), ty(:, :)   ! warm start in, tractions (Pa) out
        integer, intent(out) :: status(:, :)       ! 0 exterior, 1 adhesion, 2 slip
        real(dp), intent(out) :: sx(:, :), sy(:, :)     ! slip velocity, m/s
        integer, intent(out) :: iters
        real(dp), intent(out) :: resid
        integer, intent(out) :: info
        integer, intent(in), optional :: product
        type(friction_law), intent(in), optional :: law
        integer, intent(out), optional :: nmulti
        !> extra rigid slip (creepage units) added to eq. 29's w, e.g. a dissimilar
        !> pair's pressure coupling (contact_coupling); absent: none (results unchanged)
        real(dp), intent(in), optional :: wex(:, :), wey(:, :)
        type(rolling_patch), intent(inout), optional, target :: patch

        type(rolling_patch), target :: own
        type(rolling_patch), pointer :: pa
        integer :: prod, nm, k

        iters = 0
        resid = 0.0_dp
        if (present(nmulti)) nmulti = 0
        status = ST_EXTERIOR
        sx = 0.0_dp
        sy = 0.0_dp
        info = STAT_OK
        if (w%nker < 4) then
            info = STAT_BAD_HANDLE     ! a workspace made without the tangential kernels
            return
        end if
        prod = PRODUCT_AUTO
        if (present(product)) prod = product
        if ((method /= ROLL_GS .and. method /= ROLL_FFTGS) .or. nblock < 1 .or. ninner < 1 &
            .or. prod < PRODUCT_AUTO .or. prod > PRODUCT_DIRECT) then
            info = STAT_BAD_ARGUMENT
            return
        end if
        pa => own
        if (present(patch)) pa => patch
        ! tractions outside the contact set zeroed (the warm start's too)
        where (.not. (p > 0.0_dp))
            tx = 0.0_dp
            ty = 0.0_dp
        end where
        if (.not. pa%ready) then
            if (same_contact_set(pa, p, prod)) then
                call patch_bound(pa, p, mu)    ! a new pressure on the same contact set
            else
                call patch_setup(w, p, mu, prod, pa, info)
                if (info /= STAT_OK) then
                    pa%prod = -1    ! not a patch to reuse
                    return
                end if
            end if
            pa%ready = .true.
        end if
        call rigid_slip(pa, x0, y0, w%dy, xi, eta, phi)
        pa%varlaw = .false.
        if (present(law)) then
            if (.not. friction_is_constant(law)) then
                pa%varlaw = .true.
                pa%law = law
                pa%speed = speed
            end if
        end if
        if (present(wex)) pa%wx = pa%wx + wex
        if (present(wey)) pa%wy = pa%wy + wey
        ! warm start: on the Coulomb disc
        call project_all(pa, tx, ty)
        if (allocated(pa%sop)) then
            do k = 1, pa%nc
                pa%wxc(k) = pa%wx(pa%ic(k), pa%jc(k))
                pa%wyc(k) = pa%wy(pa%ic(k), pa%jc(k))
            end do
            call iterate_small(pa, ninner, tol, max_iter, speed, tx, ty, status, sx, sy, iters, resid, info, nm)
        else
            call iterate_grid(pa, w, method, nblock, ninner, tol, max_iter, speed, tx, ty, status, sx, sy, &
                              iters, resid, info, nm)
        end if
        if (present(nmulti)) nmulti = nm
    end subroutine rolling_steady

    !> A kept patch (rolling_steady's patch) marked stale after the pressure or mu changed:
    !> the next solve makes it anew, or, when its contact set (p > 0) and product are
    !> those of the stale patch, only sets the new traction bound (the contact set, bases
    !> and slip operator depend on nothing else; the caller keeps the workspace and the
    !> grid origin, as contact_creep_table does).
    subroutine rolling_patch_reset(pa)
        type(rolling_patch), intent(inout) :: pa
        pa%ready = .false.
    end subroutine rolling_patch_reset

    !> Whether the made patch pa has the contact set p > 0 and was made for product prod.
    logical function same_contact_set(pa, p, prod)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: p(:, :)
        integer, intent(in) :: prod
        same_contact_set = .false.
        if (.not. allocated(pa%ic) .or. pa%prod /= prod) return
        if (size(pa%inc, 1) /= size(p, 1) .or. size(pa%inc, 2) /= size(p, 2)) return
        same_contact_set = all(pa%inc .eqv. (p > 0.0_dp))
    end function same_contact_set

    !> The traction bound mu p of a patch (and its packed copy on the small path).
    subroutine patch_bound(pa, p, mu)
        type(rolling_patch), intent(inout) :: pa
        real(dp), intent(in) :: p(:, :), mu
        integer :: k
        pa%bound = mu * p
        if (allocated(pa%bc)) then
            do k = 1, pa%nc
                pa%bc(k) = pa%bound(pa%ic(k), pa%jc(k))
            end do
        end if
    end subroutine patch_bound

    !> rolling_steady's iteration on the grid: row-implicit sweeps with the field
    !> u = A t by FFT or by direct sums over the box (module doc), Anderson mixing.
    subroutine iterate_grid(pa, w, method, nblock, ninner, tol, max_iter, speed, tx, ty, status, sx, sy, &
                            iters, resid, info, nm)
        type(rolling_patch), intent(in) :: pa
        type(workspace), intent(inout) :: w
        integer, intent(in) :: method, nblock, ninner, max_iter
        real(dp), intent(in) :: tol, speed
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        integer, intent(inout) :: status(:, :)
        real(dp), intent(inout) :: sx(:, :), sy(:, :)
        integer, intent(out) :: iters, info, nm
        real(dp), intent(out) :: resid
        type(anderson_state) :: aa
        real(dp), allocatable :: ux(:, :), uy(:, :), gx(:, :), gy(:, :), dux(:, :), duy(:, :), v(:)
        real(dp) :: r2, n2, rbest
        integer :: nblk, it

        info = STAT_OK
        resid = 0.0_dp
        nm = 0
        ! rows per FFT refresh: all for plain GS, nblock for the blocked form
        nblk = pa%nby + 1
        if (method == ROLL_FFTGS) nblk = min(nblock, pa%nby + 1)

        allocate (ux(pa%nx, pa%ny), uy(pa%nx, pa%ny), gx(pa%nx, pa%ny), gy(pa%nx, pa%ny), &
                  dux(pa%i1:pa%ib2, pa%j1:pa%j2), duy(pa%i1:pa%ib2, pa%j1:pa%j2), v(2 * pa%nc))
        ux = 0.0_dp      ! box_apply sets the box only; nothing reads u outside it
        uy = 0.0_dp
        gx = 0.0_dp      ! field sets the contact set only; nothing reads g outside it
        gy = 0.0_dp
        call pack_tractions(pa, tx, ty, v)
        call anderson_init(aa, v, AA_M)
        rbest = huge(1.0_dp)
        it = 0
        do
            ! exact field and the Jacobi residual on it (pivot of a single element)
            call field(pa, w%plan, tx, ty, ux, uy, gx, gy)
            call jacobi_residual(pa, gx, gy, tx, ty, r2, n2)
            if (.not. residual_ok(r2, n2, resid, info)) exit
            if (resid <= tol) exit
            if (it >= max_iter) then
                info = STAT_NOT_CONVERGED
                exit
            end if
            ! safeguard: an extrapolated iterate that raised the residual is
            ! replaced by the last plain sweep and the history dropped
            if (aa%naa > 0 .and. resid > 2.0_dp * rbest) then
                call anderson_restart(aa)
                call unpack_tractions(pa, aa%x, tx, ty)
                call field(pa, w%plan, tx, ty, ux, uy, gx, gy)
            end if
            rbest = min(rbest, resid)
            it = it + 1
            call sweep(pa, w%plan, nblk, ninner, tx, ty, ux, uy, gx, gy, dux, duy)
            ! Anderson mixing of the sweep map, then every traction back on its disc
            call pack_tractions(pa, tx, ty, v)
            call anderson_step(aa, v)
            call unpack_tractions(pa, aa%x, tx, ty)
        end do
        iters = it

        ! the in-row updates move other elements of a run too: put every
        ! traction on its disc (a change of the order of the residual)
        call project_all(pa, tx, ty)
        if (info /= STAT_NOT_FINITE) then
            call field(pa, w%plan, tx, ty, ux, uy, gx, gy)
            call final_slip(pa, gx, gy, tx, ty, speed, status, sx, sy, nm)
        end if
    end subroutine iterate_grid

    !> The relative residual sqrt(r2 / n2) (jacobi_residual's squares) into resid; false
    !> (info STAT_NOT_FINITE, resid huge) when the squares are not finite.
    logical function residual_ok(r2, n2, resid, info)
        real(dp), intent(in) :: r2, n2
        real(dp), intent(out) :: resid
        integer, intent(inout) :: info
        residual_ok = .not. (r2 /= r2 .or. n2 /= n2 .or. r2 > huge(1.0_dp))
        if (.not. residual_ok) then
            info = STAT_NOT_FINITE
            resid = huge(1.0_dp)
        else if (n2 > 0.0_dp) then
            resid = sqrt(r2 / n2)
        else
            resid = merge(0.0_dp, 1.0_dp, r2 == 0.0_dp)
        end if
    end function residual_ok

    !> rolling_steady's iteration on a small contact set (pa%sop made): the same
    !> row-implicit sweeps, Anderson mixing and residual as iterate_grid, on the
    !> packed tractions v = [tx(inc), ty(inc)] and their slips g = S v (the dense slip
    !> operator): no grid arrays inside the loop, the sweep's updates to the rows still
    !> to come as columns of S (sweep_small). Agrees with iterate_grid to rounding.
    subroutine iterate_small(pa, ninner, tol, max_iter, speed, tx, ty, status, sx, sy, iters, resid, info, nm)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: ninner, max_iter
        real(dp), intent(in) :: tol, speed
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        integer, intent(inout) :: status(:, :)
        real(dp), intent(inout) :: sx(:, :), sy(:, :)
        integer, intent(out) :: iters, info, nm
        real(dp), intent(out) :: resid
        type(anderson_state) :: aa
        ! fixed sizes (nc <= SOP_MAX): on the stack, where gfortran puts automatic arrays
        ! on the heap (a malloc and free per call, as much as a small problem's arithmetic)
        real(dp) :: vv(2 * SOP_MAX), gg(2 * SOP_MAX), r2, n2, rbest
        integer :: it, k, n

        info = STAT_OK
        resid = 0.0_dp
        nm = 0
        n = pa%nc
        associate (v => vv(1:2 * n), g => gg(1:2 * n))
        call pack_tractions(pa, tx, ty, v)
        call anderson_init(aa, v, AA_M)
        rbest = huge(1.0_dp)
        it = 0
        do
            call sop_apply(pa, v, g)
            call jacobi_small(pa, g, v, r2, n2)
            if (.not. residual_ok(r2, n2, resid, info)) exit
            if (resid <= tol) exit
            if (it >= max_iter) then
                info = STAT_NOT_CONVERGED
                exit
            end if
            if (aa%naa > 0 .and. resid > 2.0_dp * rbest) then
                call anderson_restart(aa)
                v = aa%x
                call project_packed(pa, v)
                call sop_apply(pa, v, g)
            end if
            rbest = min(rbest, resid)
            it = it + 1
            call sweep_small(pa, ninner, v, g)
            call anderson_step(aa, v)
            v = aa%x
            call project_packed(pa, v)
        end do
        iters = it
        call project_packed(pa, v)
        do k = 1, n
            tx(pa%ic(k), pa%jc(k)) = v(k)
            ty(pa%ic(k), pa%jc(k)) = v(n + k)
        end do
        if (info /= STAT_NOT_FINITE) then
            call sop_apply(pa, v, g)
            call final_small(pa, g, v, speed, status, sx, sy, nm)
        end if
        end associate
    end subroutine iterate_small

    !> g = S v: the slips of the packed tractions v by the dense slip operator.
    pure subroutine sop_apply(pa, v, g)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: v(:)
        real(dp), intent(out) :: g(:)
        integer :: k, m
        ! four columns per pass over g (g is loaded and stored a quarter as often)
        m = 2 * pa%nc
        g = 0.0_dp
        do k = 1, m - 3, 4
            if (v(k) == 0.0_dp .and. v(k + 1) == 0.0_dp .and. v(k + 2) == 0.0_dp .and. v(k + 3) == 0.0_dp) cycle
            g = g + v(k) * pa%sop(:, k) + v(k + 1) * pa%sop(:, k + 1) + v(k + 2) * pa%sop(:, k + 2) &
                + v(k + 3) * pa%sop(:, k + 3)
        end do
        do k = 4 * (m / 4) + 1, m
            if (v(k) /= 0.0_dp) g = g + v(k) * pa%sop(:, k)
        end do
    end subroutine sop_apply

    !> Every packed traction put on its Coulomb disc.
    pure subroutine project_packed(pa, v)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(inout) :: v(:)
        integer :: k
        do k = 1, pa%nc
            call project_on_disc(v(k), v(pa%nc + k), pa%bc(k))
        end do
    end subroutine project_packed

    !> jacobi_residual on packed vectors (g = S v, iterate_small); Coulomb's element
    !> problems all at once (element_batch).
    pure subroutine jacobi_small(pa, g, v, r2, n2)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: g(:), v(:)
        real(dp), intent(out) :: r2, n2
        real(dp) :: scx, scy, lam
        real(dp), dimension(SOP_MAX) :: ntx, nty, s0x, s0y   ! nc <= SOP_MAX (iterate_small)
        integer :: k, n, st
        n = pa%nc
        do k = 1, n
            s0x(k) = pa%wxc(k) + g(k)
            s0y(k) = pa%wyc(k) + g(n + k)
        end do
        if (pa%varlaw) then
            do k = 1, n
                scx = s0x(k)
                scy = s0y(k)
                call element_any(pa, scx - pa%kx * v(k), scy - pa%ky * v(n + k), pa%kx, pa%ky, pa%bc(k), &
                                 scx, scy, ntx(k), nty(k), st, lam)
            end do
        else
            s0x(1:n) = s0x(1:n) - pa%kx * v(1:n)
            s0y(1:n) = s0y(1:n) - pa%ky * v(n + 1:2 * n)
            call element_batch(s0x(1:n), s0y(1:n), pa%kx, pa%ky, pa%bc, ntx(1:n), nty(1:n))
        end if
        r2 = 0.0_dp
        n2 = 0.0_dp
        do k = 1, n
            r2 = r2 + (ntx(k) - v(k))**2 + (nty(k) - v(n + k))**2
            n2 = n2 + ntx(k)**2 + nty(k)**2
        end do
    end subroutine jacobi_small

    !> element_solve for many elements with the same pivots kx, ky (jacobi_small): the
    !> adhesion test for each, then element_solve's Newton iteration on the slipping ones
    !> side by side, without a branch per element and step (the steps go on until every
    !> one has met element_solve's test; one that had only refines), so that the divisions
    !> of different elements overlap. Agrees with element_solve to about 1e-11 relative.
    pure subroutine element_batch(s0x, s0y, kx, ky, g, tx, ty)
        real(dp), intent(in) :: s0x(:), s0y(:), kx, ky, g(:)
        real(dp), intent(out) :: tx(:), ty(:)
        real(dp), dimension(SOP_MAX) :: sx, sy, gx, gy, lam   ! size(s0x) <= SOP_MAX
        logical :: ok(SOP_MAX)
        real(dp) :: ax, ay, en, r, d, rho, dx3, dy3, f, fp, dl
        integer :: idx(SOP_MAX), k, m, ns, it
        ns = 0
        do k = 1, size(s0x)
            ax = -s0x(k) / kx
            ay = -s0y(k) / ky
            if (ax * ax + ay * ay <= g(k) * g(k)) then
                tx(k) = ax
                ty(k) = ay
            else
                tx(k) = 0.0_dp       ! g <= 0: no traction
                ty(k) = 0.0_dp
                if (g(k) <= 0.0_dp) cycle
                ns = ns + 1
                idx(ns) = k
                sx(ns) = s0x(k)
                sy(ns) = s0y(k)
                gx(ns) = g(k) * kx
                gy(ns) = g(k) * ky
            end if
        end do
        if (ns == 0) return
        do m = 1, ns   ! element_solve's second-order start
            en = sx(m) * sx(m) + sy(m) * sy(m)
            r = sqrt(en)
            d = 0.5_dp * (gx(m) - gy(m)) / r
            rho = (sx(m) * sx(m) - sy(m) * sy(m)) / en
            lam(m) = max(0.0_dp, r * (1.0_dp - d * rho + 1.5_dp * d * d * (1.0_dp - rho * rho)) &
                         - 0.5_dp * (gx(m) + gy(m)))
        end do
        do it = 1, 100
            do m = 1, ns
                dx3 = 1.0_dp / (lam(m) + gx(m))
                dy3 = 1.0_dp / (lam(m) + gy(m))
                f = (sx(m) * dx3)**2 + (sy(m) * dy3)**2 - 1.0_dp
                fp = -2.0_dp * ((sx(m) * dx3)**2 * dx3 + (sy(m) * dy3)**2 * dy3)
                dl = merge(-f / min(fp, -tiny(1.0_dp)), 0.0_dp, fp < 0.0_dp)
                lam(m) = max(lam(m) + dl, 0.0_dp)
                ok(m) = abs(dl) <= 1.0e-6_dp * (lam(m) + gx(m) + gy(m))
            end do
            if (all(ok(1:ns))) exit
        end do
        do m = 1, ns
            dx3 = sx(m) / (lam(m) + gx(m))
            dy3 = sy(m) / (lam(m) + gy(m))
            en = g(idx(m)) / sqrt(dx3 * dx3 + dy3 * dy3)
            tx(idx(m)) = -dx3 * en
            ty(idx(m)) = -dy3 * en
        end do
    end subroutine element_batch

    !> final_slip on packed vectors (g = S v): status and slip velocity (m/s) on the grid.
    subroutine final_small(pa, g, v, speed, status, sx, sy, nmulti)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: g(:), v(:), speed
        integer, intent(inout) :: status(:, :)
        real(dp), intent(inout) :: sx(:, :), sy(:, :)
        integer, intent(out) :: nmulti
        real(dp) :: scx, scy, ntx, nty, lam, rkx, rky
        integer :: k, n, i, j, st, nsol
        n = pa%nc
        nmulti = 0
        rkx = 1.0_dp / pa%kx
        rky = 1.0_dp / pa%ky
        do k = 1, n
            i = pa%ic(k)
            j = pa%jc(k)
            scx = pa%wxc(k) + g(k)
            scy = pa%wyc(k) + g(n + k)
            if (pa%varlaw) then
                call element_any(pa, scx - pa%kx * v(k), scy - pa%ky * v(n + k), pa%kx, pa%ky, pa%bc(k), &
                                 scx, scy, ntx, nty, st, lam, nsol_out=nsol)
                if (nsol > 1) nmulti = nmulti + 1
            else
                call element_solve_r(scx - pa%kx * v(k), scy - pa%ky * v(n + k), pa%kx, pa%ky, rkx, rky, &
                                     pa%bc(k), ntx, nty, st, lam)
            end if
            status(i, j) = st
            if (st == ST_SLIP) then
                sx(i, j) = speed * scx
                sy(i, j) = speed * scy
            end if
        end do
    end subroutine final_small

    !> One row-implicit sweep on packed vectors (sweep, on a small contact set): the
    !> runs in sweep order, each solved by run_small on the slips g = S v of the sweep's
    !> start plus dg, the slip changes of the runs solved before it in this sweep, to
    !> which its own traction change is then added as columns of S (the elements from
    !> pa%rrow on: every element a later run reads). v: the tractions, updated.
    pure subroutine sweep_small(pa, ninner, v, g)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: ninner
        real(dp), intent(inout) :: v(:)
        real(dp), intent(in) :: g(:)
        real(dp) :: dg(2 * SOP_MAX), tox(SOP_MAX), toy(SOP_MAX), fx, fy   ! nc <= SOP_MAX
        integer :: r, n, p0, nr, r0, q, kq
        n = pa%nc
        dg(1:2 * n) = 0.0_dp
        do r = 1, pa%nrun
            p0 = pa%rp0(r)
            nr = pa%rn(r)
            r0 = pa%rrow(r)
            tox(1:nr) = v(p0:p0 + nr - 1)
            toy(1:nr) = v(n + p0:n + p0 + nr - 1)
            call run_small(pa, p0, nr, ninner, v, g, dg)
            do q = 1, nr
                kq = p0 + q - 1
                fx = v(kq) - tox(q)
                fy = v(n + kq) - toy(q)
                if ((fx == 0.0_dp .and. fy == 0.0_dp) .or. r0 > n) cycle
                dg(r0:n) = dg(r0:n) + pa%sop(r0:n, kq) * fx + pa%sop(r0:n, n + kq) * fy
                dg(n + r0:2 * n) = dg(n + r0:2 * n) + pa%sop(n + r0:2 * n, kq) * fx &
                                   + pa%sop(n + r0:2 * n, n + kq) * fy
            end do
        end do
    end subroutine sweep_small

    !> run_passes on packed vectors: ninner passes over the run of nr elements from
    !> packed position p0, the slip of element q being g + dg (the rest of the contact
    !> set) plus the run's own in-row displacement change du (its elements and the one
    !> upstream, du(nr + 1)).
    pure subroutine run_small(pa, p0, nr, ninner, v, g, dg)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: p0, nr, ninner
        real(dp), intent(inout) :: v(:)
        real(dp), intent(in) :: g(:), dg(:)
        real(dp) :: dux(SOP_MAX + 1), duy(SOP_MAX + 1)   ! nr <= nc <= SOP_MAX
        real(dp) :: scx, scy, pivx, pivy, s0x, s0y, ntx, nty, lam, dlx, dly, dx, rdx
        integer :: n, q, pk, pass, st, pe
        n = pa%nc
        dx = pa%dx
        pe = p0 + nr - 1
        dux(1:nr + 1) = 0.0_dp
        duy(1:nr + 1) = 0.0_dp
        rdx = 1.0_dp / dx
        associate (bs => pa%bases(nr), mx => pa%bases(nr)%mx, my => pa%bases(nr)%my, qx => pa%bases(nr)%qx, &
                   qy => pa%bases(nr)%qy)
            do pass = 1, ninner
                do q = nr, 1, -1
                    pk = p0 + q - 1
                    scx = pa%wxc(pk) + g(pk) + dg(pk) + (dux(q) - dux(q + 1)) * rdx
                    scy = pa%wyc(pk) + g(n + pk) + dg(n + pk) + (duy(q) - duy(q + 1)) * rdx
                    pivx = bs%px(q)
                    pivy = bs%py(q)
                    s0x = scx - pivx * v(pk)
                    s0y = scy - pivy * v(n + pk)
                    if (pa%varlaw) then
                        call element_any(pa, s0x, s0y, pivx, pivy, pa%bc(pk), scx, scy, ntx, nty, st, lam)
                    else
                        call element_solve_r(s0x, s0y, pivx, pivy, bs%rpx(q), bs%rpy(q), pa%bc(pk), ntx, nty, st, lam)
                    end if
                    dlx = (ntx - v(pk)) * bs%rmx(q)
                    dly = (nty - v(n + pk)) * bs%rmy(q)
                    if (dlx == 0.0_dp .and. dly == 0.0_dp) cycle
                    v(p0:pe) = v(p0:pe) + mx(:, q) * dlx
                    v(n + p0:n + pe) = v(n + p0:n + pe) + my(:, q) * dly
                    v(pk) = ntx
                    v(n + pk) = nty
                    dux(1:q) = dux(1:q) + dlx
                    duy(1:q) = duy(1:q) + dly
                    dux(nr + 1) = dux(nr + 1) + qx(q) * dlx
                    duy(nr + 1) = duy(nr + 1) + qy(q) * dly
                end do
            end do
        end associate
    end subroutine run_small

    !> The fixed data of one solve: contact set, bounding box, coefficients and
    !> in-row bases (and, for a small contact set, the dense slip operator, the runs in
    !> sweep order and the packed bound); prod: the product choice of rolling_steady.
    !> info: STAT_OK, STAT_NO_CONTACT, STAT_GRID_EDGE, or the failure of a basis
    !> (make_basis).
    subroutine patch_setup(w, p, mu, prod, pa, info)
        type(workspace), intent(in) :: w
        real(dp), intent(in) :: p(:, :), mu
        integer, intent(in) :: prod
        type(rolling_patch), intent(out) :: pa
        integer, intent(out) :: info
        integer :: i, j, n

        info = STAT_OK
        pa%nx = w%nx
        pa%ny = w%ny
        pa%dx = w%dx
        pa%prod = prod
        allocate (pa%inc(pa%nx, pa%ny), pa%bound(pa%nx, pa%ny))
        pa%bound = mu * p
        pa%inc = p > 0.0_dp
        if (.not. any(pa%inc)) then
            info = STAT_NO_CONTACT
            return
        end if
        call contact_box(pa)
        if (pa%i2 >= pa%nx - 1) then
            info = STAT_GRID_EDGE
            return
        end if
        pa%nc = count(pa%inc)
        call contact_list(pa)
        select case (prod)
        case (PRODUCT_FFT)
            pa%direct = .false.
        case (PRODUCT_DIRECT)
            pa%direct = .true.
        case default
            pa%direct = direct_is_cheaper(pa)
        end select

        ! coefficients At of ut = At t by offset, and the in-row bases of every
        ! run length met (see module doc)
        allocate (pa%axx(-pa%nbx - 1:pa%nbx + 1, -pa%nby:pa%nby), pa%ayy(-pa%nbx - 1:pa%nbx + 1, -pa%nby:pa%nby), &
                  pa%axy(-pa%nbx - 1:pa%nbx + 1, -pa%nby:pa%nby))
        call by_offset(w%c(:, :, KERNEL_XX), pa%nx, pa%ny, pa%nbx, pa%nby, pa%axx)
        call by_offset(w%c(:, :, KERNEL_YY), pa%nx, pa%ny, pa%nbx, pa%nby, pa%ayy)
        call by_offset(w%c(:, :, KERNEL_XY), pa%nx, pa%ny, pa%nbx, pa%nby, pa%axy)
        if (pa%direct) then
            pa%rxx = pa%axx
            pa%ryy = pa%ayy
            pa%rxy = pa%axy
            if (pa%nc <= SOP_MAX) then
                call slip_operator(pa)
                call small_runs(pa)
            end if
        end if
        call extrapolated(pa%nbx, pa%axx)
        call extrapolated(pa%nbx, pa%ayy)
        call extrapolated(pa%nbx, pa%axy)
        allocate (pa%bases(pa%nbx))
        do j = pa%j1, pa%j2
            do i = pa%i1, pa%i2
                if (.not. pa%inc(i, j)) cycle
                if (pa%inc(i + 1, j)) cycle
                n = i - pa%trail(i, j) + 1
                if (allocated(pa%bases(n)%mx)) cycle
                call make_basis(n, pa%nbx, pa%dx, allocated(pa%sop), pa%axx(:, 0), pa%ayy(:, 0), pa%bases(n), info)
                if (info /= STAT_OK) return
            end do
        end do
        pa%kx = (WU0 * w%c(0, 0, KERNEL_XX) + WU1 * w%c(1, 0, KERNEL_XX) + WU2 * w%c(2, 0, KERNEL_XX)) / pa%dx
        pa%ky = (WU0 * w%c(0, 0, KERNEL_YY) + WU1 * w%c(1, 0, KERNEL_YY) + WU2 * w%c(2, 0, KERNEL_YY)) / pa%dx
        allocate (pa%wx(pa%nx, pa%ny), pa%wy(pa%nx, pa%ny))
    end subroutine patch_setup

    !> The small path's runs in sweep order (rows ascending, within a row from the
    !> leading edge), as packed positions, and the packed bound (patch_setup).
    subroutine small_runs(pa)
        type(rolling_patch), intent(inout) :: pa
        integer, allocatable :: pos(:, :)
        integer :: i, j, k
        allocate (pos(pa%nx, pa%ny), pa%bc(pa%nc), pa%wxc(pa%nc), pa%wyc(pa%nc))
        pos = 0
        do k = 1, pa%nc
            pos(pa%ic(k), pa%jc(k)) = k
            pa%bc(k) = pa%bound(pa%ic(k), pa%jc(k))
        end do
        pa%nrun = 0
        do j = pa%j1, pa%j2
            do i = pa%i2, pa%i1, -1
                if (pa%inc(i, j) .and. .not. pa%inc(i + 1, j)) pa%nrun = pa%nrun + 1
            end do
        end do
        allocate (pa%rp0(pa%nrun), pa%rn(pa%nrun), pa%rrow(pa%nrun))
        k = 0
        do j = pa%j1, pa%j2
            do i = pa%i2, pa%i1, -1
                if (.not. (pa%inc(i, j) .and. .not. pa%inc(i + 1, j))) cycle
                k = k + 1
                pa%rp0(k) = pos(pa%trail(i, j), j)
                pa%rn(k) = i - pa%trail(i, j) + 1
                ! a run that fills its row changes no other element of it: the next row's first
                pa%rrow(k) = pos(pa%rlo(j), j)
                if (pa%trail(i, j) == pa%rlo(j) .and. i == pa%rhi(j)) pa%rrow(k) = pa%rp0(k) + pa%rn(k)
            end do
        end do
    end subroutine small_runs

    !> The rigid slip of eq. 29 (creepage units) on the grid: w_x = xi - phi y,
    !> w_y = eta + phi x, x, y of the element centres (x0, y0 that of element (1, 1), dy the
    !> lateral step).
    subroutine rigid_slip(pa, x0, y0, dy, xi, eta, phi)
        type(rolling_patch), intent(inout) :: pa
        real(dp), intent(in) :: x0, y0, dy, xi, eta, phi
        integer :: i, j
        real(dp) :: x, y
        do j = 1, pa%ny
            y = y0 + (j - 1) * dy
            do i = 1, pa%nx
                x = x0 + (i - 1) * pa%dx
                pa%wx(i, j) = xi - phi * y
                pa%wy(i, j) = eta + phi * x
            end do
        end do
    end subroutine rigid_slip

    !> Bounding box of the contact set (plus the upstream row: ut there needs u
    !> one row further) and the trailing end of the contiguous run of contact
    !> elements through each (i, j).
    subroutine contact_box(pa)
        type(rolling_patch), intent(inout) :: pa
        integer :: i, j
        pa%i1 = pa%nx
        pa%i2 = 1
        pa%j1 = pa%ny
        pa%j2 = 1
        do j = 1, pa%ny
            do i = 1, pa%nx
                if (pa%inc(i, j)) then
                    pa%i1 = min(pa%i1, i)
                    pa%i2 = max(pa%i2, i)
                    pa%j1 = min(pa%j1, j)
                    pa%j2 = max(pa%j2, j)
                end if
            end do
        end do
        pa%ib2 = pa%i2 + 1
        pa%nbx = pa%ib2 - pa%i1
        pa%nby = pa%j2 - pa%j1
        allocate (pa%trail(pa%nx, pa%ny), pa%rlo(pa%j1:pa%j2), pa%rhi(pa%j1:pa%j2))
        pa%trail = 0
        pa%rlo = pa%nx + 1
        pa%rhi = 0
        do j = pa%j1, pa%j2
            do i = pa%i1, pa%i2
                if (.not. pa%inc(i, j)) cycle
                pa%rlo(j) = min(pa%rlo(j), i)
                pa%rhi(j) = max(pa%rhi(j), i)
                if (i > 1) then
                    if (pa%inc(i - 1, j)) then
                        pa%trail(i, j) = pa%trail(i - 1, j)
                        cycle
                    end if
                end if
                pa%trail(i, j) = i
            end do
        end do
    end subroutine contact_box

    !> The coefficients c(offset) for offsets (-nbx-1..nbx+1, -nby..nby), zero
    !> beyond the grid. cfull: one kernel in influence_field's circular layout
    !> on the padded (2 nx, 2 ny) grid.
    subroutine by_offset(cfull, nx, ny, nbx, nby, cc)
        real(dp), intent(in) :: cfull(0:, 0:)
        integer, intent(in) :: nx, ny, nbx, nby
        real(dp), intent(out) :: cc(-nbx - 1:, -nby:)
        integer :: a, b, ia, jb
        cc = 0.0_dp
        do b = -nby, nby
            if (abs(b) >= ny) cycle
            jb = b
            if (b < 0) jb = b + 2 * ny     ! modulo(b, 2 ny)
            do a = -nbx - 1, nbx + 1
                if (abs(a) >= nx) cycle
                ia = a
                if (a < 0) ia = a + 2 * nx
                cc(a, b) = cfull(ia, jb)
            end do
        end do
    end subroutine by_offset

    !> c by offset (by_offset) turned in place into At(offset) = (1 + th) c(offset)
    !> - th c(offset + (1, 0)) (cc(nbx + 1, :) unused and set to zero).
    subroutine extrapolated(nbx, cc)
        integer, intent(in) :: nbx
        real(dp), intent(inout) :: cc(-nbx - 1:, :)
        integer :: a
        do a = -nbx - 1, nbx
            cc(a, :) = (1.0_dp + THETA) * cc(a, :) - THETA * cc(a + 1, :)
        end do
        cc(nbx + 1, :) = 0.0_dp
    end subroutine extrapolated

    !> The in-row basis of a run of n elements, per component:
    !> m(:, q) = At_n^-1 C e_q (the tractions whose own-row displacement ut
    !> is 1 on elements 0..q of the run and 0 upstream of q), and
    !> q(q) = the ut they give at the element upstream of the run.
    !> axr, ayr: the row At(:, 0) of the xx and yy kernels, offsets -nbx-1..nbx+1.
    !> small: the small path's basis (small_inverse; else dense_inverse, LAPACK's LU).
    !> info: STAT_OK or the inverse's failure.
    subroutine make_basis(n, nbx, dx, small, axr, ayr, basis, info)
        integer, intent(in) :: n, nbx
        real(dp), intent(in) :: dx
        logical, intent(in) :: small   ! the small path's (small_inverse), else LAPACK's LU
        real(dp), intent(in) :: axr(-nbx - 1:), ayr(-nbx - 1:)
        type(run_basis), intent(inout) :: basis
        integer, intent(out) :: info
        integer :: comp, a, b
        real(dp), allocatable :: m(:, :)
        allocate (basis%mx(n, n), basis%my(n, n), basis%qx(n), basis%qy(n))
        allocate (m(n, n))
        do comp = 1, 2
            do b = 1, n
                do a = 1, n
                    if (comp == 1) then
                        m(a, b) = axr(a - b)
                    else
                        m(a, b) = ayr(a - b)
                    end if
                end do
            end do
            if (small) then
                call small_inverse(m, info)
            else
                call dense_inverse(n, m, info)
            end if
            if (info /= STAT_OK) return
            ! C e_q = ones on elements 1..q (downstream of and at q): cumulative columns
            do b = 2, n
                m(:, b) = m(:, b) + m(:, b - 1)
            end do
            if (comp == 1) then
                basis%mx = m
                do b = 1, n
                    basis%qx(b) = sum([(axr(n + 1 - a) * m(a, b), a = 1, n)])
                end do
            else
                basis%my = m
                do b = 1, n
                    basis%qy(b) = sum([(ayr(n + 1 - a) * m(a, b), a = 1, n)])
                end do
            end if
        end do
        ! the pivots as run_passes forms them (the leading element's with its upstream term)
        allocate (basis%px(n), basis%py(n), basis%rpx(n), basis%rpy(n), basis%rmx(n), basis%rmy(n))
        do b = 1, n
            basis%px(b) = 1.0_dp / (dx * basis%mx(b, b))
            basis%py(b) = 1.0_dp / (dx * basis%my(b, b))
            if (b == n) then
                basis%px(b) = (1.0_dp - basis%qx(b)) / (dx * basis%mx(b, b))
                basis%py(b) = (1.0_dp - basis%qy(b)) / (dx * basis%my(b, b))
            end if
            basis%rpx(b) = 1.0_dp / basis%px(b)
            basis%rpy(b) = 1.0_dp / basis%py(b)
            basis%rmx(b) = 1.0_dp / basis%mx(b, b)
            basis%rmy(b) = 1.0_dp / basis%my(b, b)
        end do
    end subroutine make_basis

    !> a <- a^-1 for a small n x n matrix (a run's Toeplitz block, n <= nx) by Gauss-Jordan
    !> elimination of [a | I] with partial pivoting, in plain loops: no BLAS kernel whose
    !> choice (OPENBLAS_CORETYPE) could change the rounding, and no library call overhead
    !> for the few elements of a run. info: STAT_OK, or STAT_SINGULAR for a zero pivot.
    pure subroutine small_inverse(a, info)
        real(dp), intent(inout) :: a(:, :)
        integer, intent(out) :: info
        real(dp) :: b(size(a, 1), size(a, 1)), row(size(a, 1)), f
        integer :: n, k, i, r
        n = size(a, 1)
        b = 0.0_dp
        do k = 1, n
            b(k, k) = 1.0_dp
        end do
        info = STAT_OK
        do k = 1, n
            r = k - 1 + maxloc(abs(a(k:n, k)), dim=1)
            if (.not. (abs(a(r, k)) > 0.0_dp)) then
                info = STAT_SINGULAR
                return
            end if
            if (r /= k) then
                row = a(k, :)
                a(k, :) = a(r, :)
                a(r, :) = row
                row = b(k, :)
                b(k, :) = b(r, :)
                b(r, :) = row
            end if
            f = 1.0_dp / a(k, k)
            a(k, :) = a(k, :) * f
            b(k, :) = b(k, :) * f
            do i = 1, n
                if (i == k) cycle
                f = a(i, k)
                if (f == 0.0_dp) cycle
                a(i, :) = a(i, :) - f * a(k, :)
                b(i, :) = b(i, :) - f * b(k, :)
            end do
        end do
        a = b
    end subroutine small_inverse

    !> The upwind difference quotient of the field u at element (i, j):
    !> (ut_i - ut_i+1) / dx (eq. 29).
    pure real(dp) function updiff(u, i, j, dx)
        real(dp), intent(in) :: u(:, :)
        integer, intent(in) :: i, j
        real(dp), intent(in) :: dx
        updiff = (WU0 * u(i, j) + WU1 * u(i + 1, j) + WU2 * u(i + 2, j)) / dx
    end function updiff

    !> Squared norms of the Jacobi step F(t) - t and of F(t) over the contact
    !> set, F being the element solutions with a single-element pivot on the
    !> exact field u = A t, whose slip g (field) is given (the convergence measure,
    !> module doc).
    subroutine jacobi_residual(pa, gx, gy, tx, ty, r2, n2)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: gx(:, :), gy(:, :), tx(:, :), ty(:, :)
        real(dp), intent(out) :: r2, n2
        real(dp) :: s0x, s0y, ntx, nty, lam
        integer :: i, j, st
        r2 = 0.0_dp
        n2 = 0.0_dp
        do j = pa%j1, pa%j2
            do i = pa%i1, pa%i2
                if (.not. pa%inc(i, j)) cycle
                s0x = pa%wx(i, j) + gx(i, j) - pa%kx * tx(i, j)
                s0y = pa%wy(i, j) + gy(i, j) - pa%ky * ty(i, j)
                if (pa%varlaw) then
                    call element_any(pa, s0x, s0y, pa%kx, pa%ky, pa%bound(i, j), pa%wx(i, j) + gx(i, j), &
                                     pa%wy(i, j) + gy(i, j), ntx, nty, st, lam)
                else
                    call element_solve(s0x, s0y, pa%kx, pa%ky, pa%bound(i, j), ntx, nty, st, lam)
                end if
                r2 = r2 + (ntx - tx(i, j))**2 + (nty - ty(i, j))**2
                n2 = n2 + ntx**2 + nty**2
            end do
        end do
    end subroutine jacobi_residual

    !> Status and slip velocity (m/s) of every element in contact for the
    !> tractions t on the exact field u = A t (its slip g given, field).
    !> nmulti: elements whose problem has several solutions (friction laws only).
    subroutine final_slip(pa, gx, gy, tx, ty, speed, status, sx, sy, nmulti)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: gx(:, :), gy(:, :), tx(:, :), ty(:, :), speed
        integer, intent(inout) :: status(:, :)
        real(dp), intent(inout) :: sx(:, :), sy(:, :)
        integer, intent(out) :: nmulti
        real(dp) :: s0x, s0y, ntx, nty, lam
        integer :: i, j, st, nsol
        nmulti = 0
        do j = pa%j1, pa%j2
            do i = pa%i1, pa%i2
                if (.not. pa%inc(i, j)) cycle
                s0x = pa%wx(i, j) + gx(i, j)
                s0y = pa%wy(i, j) + gy(i, j)
                if (pa%varlaw) then
                    call element_any(pa, s0x - pa%kx * tx(i, j), s0y - pa%ky * ty(i, j), pa%kx, pa%ky, &
                                     pa%bound(i, j), s0x, s0y, ntx, nty, st, lam, nsol_out=nsol)
                    if (nsol > 1) nmulti = nmulti + 1
                else
                    call element_solve(s0x - pa%kx * tx(i, j), s0y - pa%ky * ty(i, j), pa%kx, pa%ky, &
                                       pa%bound(i, j), ntx, nty, st, lam)
                end if
                status(i, j) = st
                if (st == ST_SLIP) then
                    sx(i, j) = speed * s0x
                    sy(i, j) = speed * s0y
                end if
            end do
        end do
    end subroutine final_slip

    !> Every traction of the contact set put on its Coulomb disc.
    subroutine project_all(pa, tx, ty)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        integer :: i, j
        do j = pa%j1, pa%j2
            do i = pa%i1, pa%i2
                if (.not. pa%inc(i, j)) cycle
                call project_on_disc(tx(i, j), ty(i, j), pa%bound(i, j))
            end do
        end do
    end subroutine project_all

    !> The tractions of the contact set packed as [tx(inc), ty(inc)] (pack's order).
    subroutine pack_tractions(pa, tx, ty, v)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: tx(:, :), ty(:, :)
        real(dp), intent(out) :: v(:)
        integer :: k
        do k = 1, pa%nc
            v(k) = tx(pa%ic(k), pa%jc(k))
            v(pa%nc + k) = ty(pa%ic(k), pa%jc(k))
        end do
    end subroutine pack_tractions

    !> tx, ty on the contact set from a vector packed as [tx(inc), ty(inc)], each
    !> traction put on its disc (outside the set they stay zero: patch_setup).
    subroutine unpack_tractions(pa, v, tx, ty)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: v(:)
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        integer :: k, i, j
        do k = 1, pa%nc
            i = pa%ic(k)
            j = pa%jc(k)
            tx(i, j) = v(k)
            ty(i, j) = v(pa%nc + k)
            call project_on_disc(tx(i, j), ty(i, j), pa%bound(i, j))
        end do
    end subroutine unpack_tractions

    !> The contact set as a list, column by column (the order of pack).
    subroutine contact_list(pa)
        type(rolling_patch), intent(inout) :: pa
        integer :: i, j, k
        allocate (pa%ic(pa%nc), pa%jc(pa%nc))
        k = 0
        do j = pa%j1, pa%j2
            do i = pa%i1, pa%i2
                if (.not. pa%inc(i, j)) cycle
                k = k + 1
                pa%ic(k) = i
                pa%jc(k) = j
            end do
        end do
    end subroutine contact_list

    !> Whether direct sums over the box (box_apply) take fewer operations than
    !> the FFT pair product: 8 flops per source and target against about
    !> 5 M log2 M + 10 M for the four real transforms of M = 4 nx ny points,
    !> the padding, copies and spectral products (a count, checked by timing
    !> on 11 x 11 to 25 x 25 grids: benchmarks/bench_contact_small_grid.py).
    logical function direct_is_cheaper(pa)
        type(rolling_patch), intent(in) :: pa
        real(dp) :: m, ntarget
        m = 4.0_dp * pa%nx * pa%ny
        ntarget = real(pa%ib2 + 2 - pa%i1, dp) * (pa%j2 - pa%j1 + 1)
        direct_is_cheaper = 8.0_dp * pa%nc * ntarget < 5.0_dp * m * log(m) / log(2.0_dp) + 10.0_dp * m
    end function direct_is_cheaper

    !> The slip of the field u = A t at every element in contact, g = (ut_i - ut_i+1) / dx
    !> (eq. 29's difference quotient; the solver reads u nowhere else): on small patches
    !> (pa%sop made) by the dense slip operator on the contact set, else from u (ux, uy:
    !> scratch) by box_apply (pa%direct) or by FFT. They agree to rounding.
    subroutine field(pa, plan, tx, ty, ux, uy, gx, gy)
        type(rolling_patch), intent(in) :: pa
        type(conv_plan), intent(inout) :: plan
        real(dp), intent(in) :: tx(:, :), ty(:, :)
        real(dp), intent(inout) :: ux(:, :), uy(:, :), gx(:, :), gy(:, :)
        integer :: k, i, j
        if (allocated(pa%sop)) then
            call slip_operator_apply(pa, tx, ty, gx, gy)
            return
        end if
        if (pa%direct) then
            call box_apply(pa, tx, ty, ux, uy)
        else
            call conv_apply_pair(plan, KERNEL_XX, KERNEL_XY, KERNEL_YY, tx, ty, ux, uy)
        end if
        do k = 1, pa%nc
            i = pa%ic(k)
            j = pa%jc(k)
            gx(i, j) = updiff(ux, i, j, pa%dx)
            gy(i, j) = updiff(uy, i, j, pa%dx)
        end do
    end subroutine field

    !> g = S t on the contact set by the dense slip operator pa%sop (slip_operator).
    subroutine slip_operator_apply(pa, tx, ty, gx, gy)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: tx(:, :), ty(:, :)
        real(dp), intent(inout) :: gx(:, :), gy(:, :)
        real(dp) :: v(2 * pa%nc), g(2 * pa%nc)
        integer :: k, n
        n = pa%nc
        call pack_tractions(pa, tx, ty, v)
        g = 0.0_dp
        do k = 1, 2 * n
            if (v(k) /= 0.0_dp) g = g + v(k) * pa%sop(:, k)
        end do
        do k = 1, n
            gx(pa%ic(k), pa%jc(k)) = g(k)
            gy(pa%ic(k), pa%jc(k)) = g(n + k)
        end do
    end subroutine slip_operator_apply

    !> The dense slip operator of the contact set, pa%sop(2 nc, 2 nc): the slip
    !> g = (ut_i - ut_i+1) / dx of u = A t at the elements in contact from their
    !> tractions, packed [x(inc), y(inc)] (pack_tractions), from A by offset (pa%rxx, ...).
    subroutine slip_operator(pa)
        type(rolling_patch), intent(inout) :: pa
        real(dp), allocatable :: dxx(:, :), dyy(:, :), dxy(:, :)
        integer :: k, m, n, a, b, na
        n = pa%nc
        na = pa%i2 - pa%i1
        ! the difference quotient by offset, then gathered by the pairs of the set
        allocate (dxx(-na:na, -pa%nby:pa%nby), dyy(-na:na, -pa%nby:pa%nby), dxy(-na:na, -pa%nby:pa%nby))
        do b = -pa%nby, pa%nby
            do a = -na, na
                dxx(a, b) = (WU0 * pa%rxx(a, b) + WU1 * pa%rxx(a + 1, b) + WU2 * pa%rxx(a + 2, b)) / pa%dx
                dxy(a, b) = (WU0 * pa%rxy(a, b) + WU1 * pa%rxy(a + 1, b) + WU2 * pa%rxy(a + 2, b)) / pa%dx
                dyy(a, b) = (WU0 * pa%ryy(a, b) + WU1 * pa%ryy(a + 1, b) + WU2 * pa%ryy(a + 2, b)) / pa%dx
            end do
        end do
        allocate (pa%sop(2 * n, 2 * n))
        do m = 1, n
            do k = 1, n
                a = pa%ic(k) - pa%ic(m)
                b = pa%jc(k) - pa%jc(m)
                pa%sop(k, m) = dxx(a, b)
                pa%sop(k, n + m) = dxy(a, b)
                pa%sop(n + k, m) = dxy(a, b)
                pa%sop(n + k, n + m) = dyy(a, b)
            end do
        end do
    end subroutine slip_operator

    !> u = A t by direct sums over the contact set, on the box the solver reads:
    !> rows i1..i2 + 2 (the slip stencil's upstream elements), columns j1..j2
    !> (Kaiser eq. 20; the xy coupling is symmetric, A_xy = A_yx).
    subroutine box_apply(pa, tx, ty, ux, uy)
        type(rolling_patch), intent(in) :: pa
        real(dp), intent(in) :: tx(:, :), ty(:, :)
        real(dp), intent(inout) :: ux(:, :), uy(:, :)
        integer :: k, a, b, i, j, ie
        real(dp) :: fx, fy
        ie = pa%ib2 + 1
        ux(pa%i1:ie, pa%j1:pa%j2) = 0.0_dp
        uy(pa%i1:ie, pa%j1:pa%j2) = 0.0_dp
        do k = 1, pa%nc
            i = pa%ic(k)
            j = pa%jc(k)
            fx = tx(i, j)
            fy = ty(i, j)
            if (fx == 0.0_dp .and. fy == 0.0_dp) cycle
            do b = pa%j1, pa%j2
                do a = pa%i1, ie
                    ux(a, b) = ux(a, b) + pa%rxx(a - i, b - j) * fx + pa%rxy(a - i, b - j) * fy
                    uy(a, b) = uy(a, b) + pa%rxy(a - i, b - j) * fx + pa%ryy(a - i, b - j) * fy
                end do
            end do
        end do
    end subroutine box_apply

    !> One row-implicit Gauss-Seidel sweep: rows in blocks of nblk, the exact
    !> field u refreshed by FFT before each block (the caller gives it for the
    !> first) and the block's own changes kept in du; within a row the runs are
    !> solved from the leading edge (largest x).
    subroutine sweep(pa, plan, nblk, ninner, tx, ty, ux, uy, gx, gy, dux, duy)
        type(rolling_patch), intent(in) :: pa
        type(conv_plan), intent(inout) :: plan
        integer, intent(in) :: nblk, ninner
        real(dp), intent(inout) :: tx(:, :), ty(:, :), ux(:, :), uy(:, :), gx(:, :), gy(:, :)
        real(dp), intent(inout) :: dux(pa%i1:, pa%j1:), duy(pa%i1:, pa%j1:)
        integer :: i, j, jb, je
        do jb = pa%j1, pa%j2, nblk
            je = min(pa%j2, jb + nblk - 1)
            if (jb > pa%j1) call field(pa, plan, tx, ty, ux, uy, gx, gy)
            dux = 0.0_dp
            duy = 0.0_dp
            do j = jb, je
                do i = pa%i2, pa%i1, -1
                    if (.not. pa%inc(i, j)) cycle
                    if (pa%inc(i + 1, j)) cycle
                    call solve_run(pa, pa%trail(i, j), i, j, je, ninner, tx, ty, gx, gy, dux, duy)
                end do
            end do
        end do
    end subroutine sweep

    !> ninner passes over the run k..l of row jr with exact in-row updates,
    !> then the run's traction change carried to the rows jr..je of the block.
    subroutine solve_run(pa, k, l, jr, je, ninner, tx, ty, gx, gy, dux, duy)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: k, l, jr, je, ninner
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        real(dp), intent(in) :: gx(:, :), gy(:, :)
        real(dp), intent(inout) :: dux(pa%i1:, pa%j1:), duy(pa%i1:, pa%j1:)
        real(dp) :: tox(l - k + 1), toy(l - k + 1)
        tox = tx(k:l, jr)
        toy = ty(k:l, jr)
        call run_passes(pa, k, l, jr, ninner, tx, ty, gx, gy, dux, duy)
        tox = tx(k:l, jr) - tox
        toy = ty(k:l, jr) - toy
        call spread_run_change(pa, k, l, jr, je, tox, toy, dux, duy)
    end subroutine solve_run

    !> ninner passes over the run k..l of row jr, from the leading element:
    !> each element problem solved exactly on its disc with the pivot of the
    !> in-row basis, the basis update applied to the run's tractions and to
    !> the in-row displacement corrections du (the run and its upstream element).
    subroutine run_passes(pa, k, l, jr, ninner, tx, ty, gx, gy, dux, duy)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: k, l, jr, ninner
        real(dp), intent(inout) :: tx(:, :), ty(:, :)
        real(dp), intent(in) :: gx(:, :), gy(:, :)
        real(dp), intent(inout) :: dux(pa%i1:, pa%j1:), duy(pa%i1:, pa%j1:)
        integer :: n, q, ii, pass, st
        real(dp) :: scx, scy, pivx, pivy, s0x, s0y, ntx, nty, lam, dlx, dly, dx
        n = l - k + 1
        dx = pa%dx
        associate (mx => pa%bases(n)%mx, my => pa%bases(n)%my, qx => pa%bases(n)%qx, qy => pa%bases(n)%qy)
            do pass = 1, ninner
                do q = n, 1, -1
                    ii = k + q - 1
                    scx = pa%wx(ii, jr) + gx(ii, jr) + (dux(ii, jr) - dux(ii + 1, jr)) / dx
                    scy = pa%wy(ii, jr) + gy(ii, jr) + (duy(ii, jr) - duy(ii + 1, jr)) / dx
                    if (q == n) then
                        pivx = (1.0_dp - qx(q)) / (dx * mx(q, q))
                        pivy = (1.0_dp - qy(q)) / (dx * my(q, q))
                    else
                        pivx = 1.0_dp / (dx * mx(q, q))
                        pivy = 1.0_dp / (dx * my(q, q))
                    end if
                    s0x = scx - pivx * tx(ii, jr)
                    s0y = scy - pivy * ty(ii, jr)
                    if (pa%varlaw) then
                        call element_any(pa, s0x, s0y, pivx, pivy, pa%bound(ii, jr), scx, scy, ntx, nty, st, lam)
                    else
                        call element_solve(s0x, s0y, pivx, pivy, pa%bound(ii, jr), ntx, nty, st, lam)
                    end if
                    dlx = (ntx - tx(ii, jr)) / mx(q, q)
                    dly = (nty - ty(ii, jr)) / my(q, q)
                    if (dlx == 0.0_dp .and. dly == 0.0_dp) cycle
                    tx(k:l, jr) = tx(k:l, jr) + mx(:, q) * dlx
                    ty(k:l, jr) = ty(k:l, jr) + my(:, q) * dly
                    tx(ii, jr) = ntx
                    ty(ii, jr) = nty
                    dux(k:ii, jr) = dux(k:ii, jr) + dlx
                    duy(k:ii, jr) = duy(k:ii, jr) + dly
                    dux(l + 1, jr) = dux(l + 1, jr) + qx(q) * dlx
                    duy(l + 1, jr) = duy(l + 1, jr) + qy(q) * dly
                end do
            end do
        end associate
    end subroutine run_passes

    !> The traction change (dtx, dty) of the run k..l of row jr seen by the rest
    !> of the block, rows jr..je (its own row outside k..l+1 included; the xy
    !> coupling within a row vanishes), on the elements the slip of each row reads:
    !> its elements in contact and the one upstream of its last (rlo..rhi + 1).
    subroutine spread_run_change(pa, k, l, jr, je, dtx, dty, dux, duy)
        type(rolling_patch), intent(in) :: pa
        integer, intent(in) :: k, l, jr, je
        real(dp), intent(in) :: dtx(:), dty(:)
        real(dp), intent(inout) :: dux(pa%i1:, pa%j1:), duy(pa%i1:, pa%j1:)
        integer :: a, b, q, ii
        real(dp) :: fx, fy
        associate (axx => pa%axx, ayy => pa%ayy, axy => pa%axy, rlo => pa%rlo, rhi => pa%rhi)
            do b = jr, je
                do q = 1, l - k + 1
                    fx = dtx(q)
                    fy = dty(q)
                    if (fx == 0.0_dp .and. fy == 0.0_dp) cycle
                    ii = k + q - 1
                    if (b == jr) then
                        do a = rlo(b), k - 1
                            dux(a, b) = dux(a, b) + axx(a - ii, 0) * fx
                            duy(a, b) = duy(a, b) + ayy(a - ii, 0) * fy
                        end do
                        do a = l + 2, rhi(b) + 1
                            dux(a, b) = dux(a, b) + axx(a - ii, 0) * fx
                            duy(a, b) = duy(a, b) + ayy(a - ii, 0) * fy
                        end do
                    else
                        do a = rlo(b), rhi(b) + 1
                            dux(a, b) = dux(a, b) + axx(a - ii, b - jr) * fx + axy(a - ii, b - jr) * fy
                            duy(a, b) = duy(a, b) + axy(a - ii, b - jr) * fx + ayy(a - ii, b - jr) * fy
                        end do
                    end if
                end do
            end do
        end associate
    end subroutine spread_run_change

end module contact_rolling
