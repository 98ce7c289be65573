!> f2py shim for transient and shift tangential contact: plain arrays, explicit shapes,
!> integer info. Argument checks live in Python (railvti.contact.transient); the kernels
!> (contact_transient) take the workspace itself.
!> Implements no equation (contact_transient does: see docs/equations.md).

!> One tangential step on the grid of workspace `handle` (made with tangential /= 0):
!> tractions t (Pa) with the slip S = s0 + cs A t obeying Coulomb's law with the bound
!> g (Pa) on the elements with incontact /= 0 (contact_transient::transient_tangential).
!> tx, ty: warm start in, tractions out; ux, uy: A t on the whole grid (m); status:
!> 0 exterior, 1 adhesion, 2 slip; slx, sly: the slip S (m, 0 in adhesion).
!> info: transient_tangential's status; STAT_BAD_HANDLE no such workspace, or one of
!> another grid size.
subroutine transient_step_c(handle, nx, ny, incontact, g, s0x, s0y, cs, tol, max_iter, tx, ty, ux, uy, &
                            status, slx, sly, iters, resid, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_BAD_HANDLE
    use contact_plans, only: workspace, ws_get
    use contact_transient, only: transient_tangential
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: handle, nx, ny, max_iter
    integer(c_int), intent(in) :: incontact(nx, ny)
    real(c_double), intent(in) :: g(nx, ny), s0x(nx, ny), s0y(nx, ny), cs, tol
    real(c_double), intent(inout) :: tx(nx, ny), ty(nx, ny)
    real(c_double), intent(out) :: ux(nx, ny), uy(nx, ny), slx(nx, ny), sly(nx, ny), resid
    integer(c_int), intent(out) :: status(nx, ny), iters, info
    type(workspace), pointer :: w
    integer, allocatable :: st(:, :)
    integer :: it, stat
    iters = 0
    resid = 0.0_c_double
    status = 0
    ux = 0.0_c_double
    uy = 0.0_c_double
    slx = 0.0_c_double
    sly = 0.0_c_double
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) then
        info = STAT_BAD_HANDLE
        return
    end if
    allocate (st(nx, ny))
    call transient_tangential(w, incontact /= 0, g, s0x, s0y, cs, tol, max_iter, tx, ty, ux, uy, st, slx, sly, &
                              it, resid, stat)
    status = st
    iters = it
    info = stat
end subroutine transient_step_c

!> A transient march of nt steps on the grid of workspace `handle`
!> (contact_transient::transient_run; arguments as there): gap h (m), normal force
!> fn(n) (N) (pgiven /= 0: the pressure fn(n) h, h in 1/m^2), kshift elements moved per step, weight th, mu, grid origin x0, y0 (m),
!> rolled distance per step dist (m), creep(:, n) = (xi, eta, phi), control 0 shift
!> increments / 1 forces in load(:, n) (m / N), keep(n) /= 0 stores the fields of
!> step n (nkeep at most). info: transient_run's status; STAT_BAD_HANDLE no such
!> workspace, or one of another grid size.
subroutine transient_run_c(handle, nx, ny, nt, nkeep, h, pgiven, fn, kshift, th, mu, x0, y0, dist, creep, control, &
                           load, tol, max_iter, tol_n, max_iter_n, keep, fx, fy, fno, q, ncon, nslip, iters, &
                           resids, infos, ktx, kty, kst, ksx, ksy, kp, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_BAD_HANDLE
    use contact_plans, only: workspace, ws_get
    use contact_transient, only: transient_run
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: handle, nx, ny, nt, nkeep, pgiven, kshift, control, max_iter, max_iter_n
    real(c_double), intent(in) :: h(nx, ny), fn(nt), th, mu, x0, y0, dist, creep(3, nt), load(2, nt), tol, tol_n
    integer(c_int), intent(in) :: keep(nt)
    real(c_double), intent(out) :: fx(nt), fy(nt), fno(nt), q(2, nt), resids(nt)
    integer(c_int), intent(out) :: ncon(nt), nslip(nt), iters(nt), infos(nt), info
    real(c_double), intent(out) :: ktx(nx, ny, nkeep), kty(nx, ny, nkeep), ksx(nx, ny, nkeep), ksy(nx, ny, nkeep)
    real(c_double), intent(out) :: kp(nx, ny, nkeep)
    integer(c_int), intent(out) :: kst(nx, ny, nkeep)
    type(workspace), pointer :: w
    integer, allocatable :: nc(:), ns(:), it(:), nf(:), st(:, :, :), kp_(:)
    integer :: stat
    fx = 0.0_c_double
    fy = 0.0_c_double
    fno = 0.0_c_double
    q = 0.0_c_double
    resids = 0.0_c_double
    ncon = 0
    nslip = 0
    iters = 0
    infos = 0
    ktx = 0.0_c_double
    kty = 0.0_c_double
    ksx = 0.0_c_double
    ksy = 0.0_c_double
    kp = 0.0_c_double
    kst = 0
    w => ws_get(handle, nx, ny)
    if (.not. associated(w)) then
        info = STAT_BAD_HANDLE
        return
    end if
    allocate (nc(nt), ns(nt), it(nt), nf(nt), st(nx, ny, nkeep), kp_(nt))
    kp_ = keep
    call transient_run(w, h, pgiven /= 0, fn, kshift, th, mu, x0, y0, dist, creep, control, load, tol, max_iter, tol_n, &
                       max_iter_n, kp_, fx, fy, fno, q, nc, ns, it, resids, nf, ktx, kty, st, ksx, ksy, kp, stat)
    ncon = nc
    nslip = ns
    iters = it
    infos = nf
    kst = st
    info = stat
end subroutine transient_run_c
