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
!> final_slip evaluate the element problems on the exact field. The patch type, the
!> constants and the traction packing live in contact_rolling_patch, the element
!> problems (eqs 26, 28) in contact_rolling_element, the small-set path
!> (iterate_small, at most SOP_MAX elements in contact) in contact_rolling_small.
module contact_rolling
    use common_kinds, only: dp
    use common_dense, only: dense_inverse
    use common_status, only: STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, &
                             STAT_BAD_HANDLE, STAT_GRID_EDGE, STAT_NOT_FINITE, STAT_SINGULAR
    use common_anderson, only: anderson_state, anderson_init, anderson_step, anderson_restart
    use contact_influence, only: KERNEL_XX, KERNEL_YY, KERNEL_XY
    use contact_plans, only: workspace
    use contact_convolution, only: conv_plan, conv_apply_pair
    use contact_friction, only: friction_law, friction_is_constant
    use contact_rolling_patch, only: ROLL_GS, ROLL_FFTGS, ST_EXTERIOR, ST_ADHESION, ST_SLIP, AA_M, &
                                     PRODUCT_AUTO, PRODUCT_FFT, PRODUCT_DIRECT, THETA, WU0, WU1, WU2, &
                                     SOP_MAX, run_basis, rolling_patch, rolling_patch_reset, &
                                     project_on_disc, residual_ok, pack_tractions, unpack_tractions
    use contact_rolling_element, only: element_solve, element_any
    use contact_rolling_small, only: iterate_small, small_runs
    implicit none
    private
    public :: rolling_steady, element_solve, rolling_patch, rolling_patch_reset
    public :: ROLL_GS, ROLL_FFTGS, ST_EXTERIOR, ST_ADHESION, ST_SLIP
    public :: PRODUCT_AUTO, PRODUCT_FFT, PRODUCT_DIRECT
    public :: WU0, WU1, WU2

contains

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
