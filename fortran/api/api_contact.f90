!> f2py shim for the contact kernels: plain arrays, explicit shapes, integer info.
!> Argument checks live in Python (railvti.contact); info is a status code of
!> common_status (the codes here guard the kernels).
!> Implements no equation (the kernels it calls do: see docs/equations.md).

!> Influence coefficients of one kernel (1 zz, 2 xx, 3 yy, 4 xy) for all
!> offsets of an nx x ny grid, circular layout on the 2nx x 2ny padded grid.
!> info: STAT_OK; STAT_BAD_ARGUMENT an unknown kernel code.
subroutine influence_field_c(kernel, nx, ny, dx, dy, g, nu, c, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    use contact_influence, only: influence_field, KERNEL_ZZ, KERNEL_XY
    implicit none
    integer(c_int), intent(in) :: kernel, nx, ny
    real(c_double), intent(in) :: dx, dy, g, nu
    real(c_double), intent(out) :: c(2 * nx, 2 * ny)
    integer(c_int), intent(out) :: info
    info = STAT_OK
    if (kernel < KERNEL_ZZ .or. kernel > KERNEL_XY) then
        info = STAT_BAD_ARGUMENT
        return
    end if
    call influence_field(kernel, nx, ny, dx, dy, g, nu, c)
end subroutine influence_field_c

!> u = A_kernel * q by FFT (method 1) or direct summation (method 2).
!> info: STAT_OK; STAT_BAD_ARGUMENT an unknown kernel or method code;
!> otherwise conv_init's status (STAT_NO_MEMORY, STAT_FFTW_PLAN).
subroutine convolve_c(kernel, method, nx, ny, dx, dy, g, nu, q, u, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    use contact_influence, only: influence_field, KERNEL_ZZ, KERNEL_XY
    use contact_convolution, only: conv_plan, conv_init, conv_apply, conv_free, direct_apply
    implicit none
    integer(c_int), intent(in) :: kernel, method, nx, ny
    real(c_double), intent(in) :: dx, dy, g, nu
    real(c_double), intent(in) :: q(nx, ny)
    real(c_double), intent(out) :: u(nx, ny)
    integer(c_int), intent(out) :: info
    real(c_double), allocatable :: c(:, :, :)
    type(conv_plan) :: plan
    integer :: stat
    info = STAT_OK
    u = 0.0_c_double
    if (kernel < KERNEL_ZZ .or. kernel > KERNEL_XY .or. method < 1 .or. method > 2) then
        info = STAT_BAD_ARGUMENT
        return
    end if
    allocate (c(0:2 * nx - 1, 0:2 * ny - 1, 1))
    call influence_field(kernel, nx, ny, dx, dy, g, nu, c(:, :, 1))
    if (method == 2) then
        call direct_apply(nx, ny, c(:, :, 1), q, u)
    else
        call conv_init(plan, nx, ny, c, stat)
        if (stat /= STAT_OK) then
            info = stat
            call conv_free(plan)
            return
        end if
        call conv_apply(plan, 1, q, u)
        call conv_free(plan)
    end if
end subroutine convolve_c

!> Apply the plain (unpruned) Boussinesq FFT product of workspace `handle` nrep times
!> to q (the benchmark's unit, one FFT-product time, is one of them).
!> info: STAT_OK; STAT_BAD_HANDLE no such workspace, or one of another grid size.
subroutine convolve_repeat_c(handle, nx, ny, nrep, q, u, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_HANDLE
    use contact_plans, only: workspace, ws_get
    use contact_convolution, only: conv_apply_plain
    implicit none
    integer(c_int), intent(in) :: handle, nx, ny, nrep
    real(c_double), intent(in) :: q(nx, ny)
    real(c_double), intent(out) :: u(nx, ny)
    integer(c_int), intent(out) :: info
    type(workspace), pointer :: w
    integer :: k
    info = STAT_BAD_HANDLE
    u = 0.0_c_double
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) return
    info = STAT_OK
    do k = 1, nrep
        call conv_apply_plain(w%plan, q, u)
    end do
end subroutine convolve_repeat_c

!> u = C * q for a given coefficient field c (circular layout on the 2nx x 2ny padded
!> grid, as influence_field_c's), by the pruned FFT product (method 1), direct summation
!> (method 2) or the plain FFT product (method 3), made nrep >= 1 times on one plan (the
!> benchmark times products so); real_spec is 1 when the pruned product multiplied by a
!> real spectrum (c point-symmetric: even or odd in both x and y), else 0.
!> info: STAT_OK; STAT_BAD_ARGUMENT an unknown method code; otherwise conv_init's status.
subroutine convolve_field_c(method, nx, ny, nrep, c, q, u, real_spec, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    use contact_convolution, only: conv_plan, conv_init, conv_apply, conv_apply_plain, conv_free, &
                                   direct_apply
    implicit none
    integer(c_int), intent(in) :: method, nx, ny, nrep
    real(c_double), intent(in) :: c(2 * nx, 2 * ny), q(nx, ny)
    real(c_double), intent(out) :: u(nx, ny)
    integer(c_int), intent(out) :: real_spec, info
    type(conv_plan) :: plan
    integer :: stat, k
    info = STAT_OK
    real_spec = 0
    u = 0.0_c_double
    if (method < 1 .or. method > 3) then
        info = STAT_BAD_ARGUMENT
        return
    end if
    if (method == 2) then
        do k = 1, max(nrep, 1)
            call direct_apply(nx, ny, c, q, u)
        end do
        return
    end if
    call conv_init(plan, nx, ny, reshape(c, [2 * nx, 2 * ny, 1]), stat)
    if (stat /= STAT_OK) then
        info = stat
        call conv_free(plan)
        return
    end if
    do k = 1, max(nrep, 1)
        if (method == 1) then
            call conv_apply(plan, 1, q, u)
        else
            call conv_apply_plain(plan, q, u)
        end if
    end do
    if (plan%real_spec(1)) real_spec = 1
    call conv_free(plan)
end subroutine convolve_field_c

!> Make a contact workspace (coefficients, spectra, FFTW plans) for an
!> nx x ny grid; tangential /= 0 adds the Cerruti kernels.
!> info: STAT_OK; STAT_NO_MEMORY all workspace slots in use (free some) or an
!> FFTW allocation failed; STAT_FFTW_PLAN no FFTW plan; STAT_BAD_ARGUMENT nx or ny < 1.
subroutine contact_ws_create_c(nx, ny, dx, dy, g, nu, tangential, handle, info)
    use iso_c_binding, only: c_int, c_double
    use contact_plans, only: ws_create
    implicit none
    integer(c_int), intent(in) :: nx, ny, tangential
    real(c_double), intent(in) :: dx, dy, g, nu
    integer(c_int), intent(out) :: handle, info
    integer :: h, stat
    call ws_create(nx, ny, dx, dy, g, nu, tangential /= 0, h, stat)
    handle = h
    info = stat
end subroutine contact_ws_create_c

subroutine contact_ws_free_c(handle)
    use iso_c_binding, only: c_int
    use contact_plans, only: ws_free
    implicit none
    integer(c_int), intent(in) :: handle
    call ws_free(handle)
end subroutine contact_ws_free_c

!> Normal contact with gap h (m) on the grid of workspace `handle`.
!> control: 1 prescribed force fn_in (N), 2 prescribed approach approach_in (m).
!> method: 1 FFT-preconditioned projected CG, 2 projected Gauss-Seidel
!> (relaxation omega), 3 projected CG without preconditioner.
!> p: warm start on entry (all zero for a cold start), pressure (Pa) on exit.
!> info: normal_cg's status (STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT,
!> STAT_NOT_FINITE); STAT_BAD_HANDLE no such workspace or one of another grid
!> size; STAT_BAD_ARGUMENT an unknown control or method code.
subroutine normal_solve_c(handle, nx, ny, h, control, method, tol, max_iter, omega, &
                          fn_in, approach_in, p, fn_out, approach_out, iters, nprod, resid, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_BAD_HANDLE, STAT_BAD_ARGUMENT
    use contact_plans, only: workspace, ws_get
    use contact_normal, only: normal_cg, normal_gs, CONTROL_FORCE, CONTROL_APPROACH
    implicit none
    integer(c_int), intent(in) :: handle, nx, ny, control, method, max_iter
    real(c_double), intent(in) :: h(nx, ny), tol, omega, fn_in, approach_in
    real(c_double), intent(inout) :: p(nx, ny)
    real(c_double), intent(out) :: fn_out, approach_out, resid
    integer(c_int), intent(out) :: iters, nprod, info
    type(workspace), pointer :: w
    integer :: it, np, stat

    iters = 0
    nprod = 0
    resid = 0.0_c_double
    fn_out = fn_in
    approach_out = approach_in
    if ((control /= CONTROL_FORCE .and. control /= CONTROL_APPROACH) .or. method < 1 .or. method > 3) then
        info = STAT_BAD_ARGUMENT
        return
    end if
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) then
        info = STAT_BAD_HANDLE
        return
    end if
    np = 0
    w%plan%has_prec = method == 1
    if (method == 2) then
        call normal_gs(w%plan, 1, w%c(:, :, 1), h, w%dx * w%dy, control, fn_out, approach_out, &
                       omega, tol, max_iter, p, it, resid, stat)
    else
        call normal_cg(w%plan, 1, w%c(:, :, 1), h, w%dx * w%dy, control, fn_out, approach_out, &
                       tol, max_iter, p, it, np, resid, stat)
    end if
    w%plan%has_prec = .true.
    iters = it
    nprod = np
    info = stat
end subroutine normal_solve_c

!> One slice of a resumable projected Gauss-Seidel solve (contact_normal's
!> normal_gs_start / normal_gs_resume): start = 1 begins from the pressure in p;
!> start = 0 goes on from the state (p, u = A p, approach, iters, pos, resid) of the
!> previous slice. Each slice spends about budget units of work (element visits plus
!> nx ny per column correction), so Python can show progress and stop between slices;
!> the numbers are those of normal_solve_c with method 2. done = 1 when the solve
!> has finished, info then as for normal_solve_c (STAT_OK while done = 0).
!> nsub, lab, fac: sub-patches (contact_normal): grid column j in sub-patch lab(j) (1..nsub),
!> their interaction scaled by fac(a, b); nsub = 1 (fac = 1) for the plain half-space.
subroutine normal_gs_slice_c(handle, nx, ny, h, control, tol, max_iter, omega, fn_in, budget, &
                             start, nsub, lab, fac, approach, p, u, iters, pos, resid, fn_out, done, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT
    use contact_plans, only: workspace, ws_get
    use contact_normal, only: normal_gs_start, normal_gs_resume, subpatches_valid, CONTROL_FORCE, &
                              CONTROL_APPROACH
    implicit none
    integer(c_int), intent(in) :: handle, nx, ny, control, max_iter, start, nsub
    integer(c_int), intent(in) :: lab(ny)
    real(c_double), intent(in) :: h(nx, ny), tol, omega, fn_in, budget, fac(nsub, nsub)
    real(c_double), intent(inout) :: approach, p(nx, ny), u(nx, ny), resid
    integer(c_int), intent(inout) :: iters, pos
    real(c_double), intent(out) :: fn_out
    integer(c_int), intent(out) :: done, info
    type(workspace), pointer :: w
    integer :: it, ps, stat
    logical :: fin

    fn_out = fn_in
    done = 1
    if ((control /= CONTROL_FORCE .and. control /= CONTROL_APPROACH) .or. .not. subpatches_valid(nsub, lab, fac)) then
        info = STAT_BAD_ARGUMENT
        return
    end if
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) then
        info = STAT_BAD_HANDLE
        return
    end if
    it = iters
    ps = pos
    if (start == 1) then
        call normal_gs_start(w%plan, 1, w%c(:, :, 1), h, w%dx * w%dy, control, fn_out, approach, &
                             p, u, it, ps, resid, stat, fin, lab, fac)
        if (fin) then
            iters = it
            pos = ps
            info = stat
            return
        end if
    end if
    call normal_gs_resume(w%c(:, :, 1), h, w%dx * w%dy, control, fn_out, approach, omega, tol, &
                          max_iter, budget, p, u, it, ps, resid, stat, fin, lab, fac)
    iters = it
    pos = ps
    done = merge(1, 0, fin)
    info = stat
    if (.not. fin) info = STAT_OK
end subroutine normal_gs_slice_c

!> One slice of a resumable projected CG solve (contact_normal's normal_cg_begin /
!> normal_cg_steps): start = 1 begins from the pressure in p; start = 0 goes on from
!> the state (p, u, t, rstate, istate, approach, resid) of the previous slice. Each slice runs at
!> most budget iterations (one or two FFT products each), so Python can show progress
!> and stop between slices; the numbers are those of normal_solve_c with the same
!> method (1 with, 3 without the preconditioner). done = 1 when the solve has finished,
!> info then as for normal_solve_c (STAT_OK while done = 0); iters, nprod: istate(2), istate(3).
!> nsub, lab, fac: sub-patches, as for normal_gs_slice_c.
subroutine normal_cg_slice_c(handle, nx, ny, h, control, method, tol, max_iter, fn_in, budget, &
                             start, nsub, lab, fac, approach, p, u, t, rstate, istate, resid, fn_out, &
                             done, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT
    use contact_plans, only: workspace, ws_get
    use contact_normal, only: normal_cg_begin, normal_cg_steps, subpatches_valid, CONTROL_FORCE, &
                              CONTROL_APPROACH
    implicit none
    integer(c_int), intent(in) :: handle, nx, ny, control, method, max_iter, budget, start, nsub
    integer(c_int), intent(in) :: lab(ny)
    real(c_double), intent(in) :: h(nx, ny), tol, fn_in, fac(nsub, nsub)
    real(c_double), intent(inout) :: approach, p(nx, ny), u(nx, ny), t(nx, ny), rstate(2), resid
    integer(c_int), intent(inout) :: istate(5)
    real(c_double), intent(out) :: fn_out
    integer(c_int), intent(out) :: done, info
    type(workspace), pointer :: w
    integer :: ist(5), stat
    logical :: fin

    fn_out = fn_in
    done = 1
    if ((control /= CONTROL_FORCE .and. control /= CONTROL_APPROACH) .or. (method /= 1 .and. method /= 3) &
        .or. .not. subpatches_valid(nsub, lab, fac)) then
        info = STAT_BAD_ARGUMENT
        return
    end if
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) then
        info = STAT_BAD_HANDLE
        return
    end if
    ist = istate
    w%plan%has_prec = method == 1
    fin = .false.
    stat = STAT_OK
    if (start == 1) call normal_cg_begin(w%plan, 1, h, w%dx * w%dy, control, fn_out, approach, p, &
                                         u, t, rstate, ist, resid, stat, fin, w%c(:, :, 1), lab, fac)
    if (.not. fin) call normal_cg_steps(w%plan, 1, w%c(:, :, 1), h, w%dx * w%dy, control, fn_out, &
                                        approach, tol, max_iter, max(budget, 1), p, u, t, rstate, ist, &
                                        resid, stat, fin, lab, fac)
    w%plan%has_prec = .true.
    istate = ist
    done = merge(1, 0, fin)
    info = stat
    if (.not. fin) info = STAT_OK
end subroutine normal_cg_slice_c


!> The tangential pair product of contact_convolution (pruned FFT), for tests:
!> ux = Cxx * qx + Cxy * qy, uy = Cxy * qx + Cyy * qy, with c(:, :, 1..3) = Cxx, Cxy, Cyy
!> in circular layout on the 2nx x 2ny padded grid.
!> info: STAT_OK; otherwise conv_init's status.
subroutine convolve_pair_c(nx, ny, c, qx, qy, ux, uy, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK
    use contact_convolution, only: conv_plan, conv_init, conv_apply_pair, conv_free
    implicit none
    integer(c_int), intent(in) :: nx, ny
    real(c_double), intent(in) :: c(2 * nx, 2 * ny, 3), qx(nx, ny), qy(nx, ny)
    real(c_double), intent(out) :: ux(nx, ny), uy(nx, ny)
    integer(c_int), intent(out) :: info
    type(conv_plan) :: plan
    integer :: stat
    ux = 0.0_c_double
    uy = 0.0_c_double
    call conv_init(plan, nx, ny, c, stat)
    info = stat
    if (stat == STAT_OK) call conv_apply_pair(plan, 1, 2, 3, qx, qy, ux, uy)
    call conv_free(plan)
end subroutine convolve_pair_c
