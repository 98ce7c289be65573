!> f2py shim for the vehicle-track time simulation: plain arrays, explicit shapes, info codes.
!> Implements no equation (the vehicle kernels do: see docs/equations.md).
!> The model (matrices, nonlinear elements, wheelset DOF maps, contact table) is passed whole
!> on every call; railvti.vehicle builds and checks it. cmodel 3 (BEM) needs the handle `bem`
!> of a BEM contact state (vehicle_bem_create_c), which keeps its warm starts between calls.

!> Integrate nsteps steps; see vehicle_newmark%newmark_run for info and stats.
subroutine vehicle_run_c(nd, ne, nw, ny, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                         y0, dy, r0, v0, gmod, mu, cmodel, fsn, bem, h, nsteps, nevery, alpha, tol, maxit, &
                         maxsub, qmax, t, q, v, a, nout, nwo, tout, qout, vout, wout, stats, info, tfail)
    use iso_c_binding, only: c_int, c_double
    use vehicle_contact, only: nq_table
    use vehicle_model, only: vmodel, vehicle_pack
    use vehicle_newmark, only: newmark_run
    implicit none
    integer(c_int), intent(in) :: nd, ne, nw, ny, nq, cmodel, fsn, bem, nsteps, nevery, maxit, maxsub, nout, nwo
    real(c_double), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
    integer(c_int), intent(in) :: etype(ne), iws(6, nw), itr(3, nw)
    real(c_double), intent(in) :: tab(nq, 2, ny), y0, dy, r0, v0, gmod, mu, h, alpha, tol, qmax
    real(c_double), intent(inout) :: t, q(nd), v(nd), a(nd)
    real(c_double), intent(out) :: tout(nout), qout(nd, nout), vout(nd, nout), wout(nwo, 2, nw, nout)
    real(c_double), intent(out) :: stats(6), tfail
    integer(c_int), intent(out) :: info
    type(vmodel) :: md
    if (nq /= nq_table) then
        info = -5
        return
    end if
    call vehicle_pack(nd, ne, nw, ny, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                      y0, dy, r0, v0, gmod, mu, cmodel, fsn, bem, md)
    call newmark_run(md, h, nsteps, nevery, alpha, tol, maxit, maxsub, qmax, t, q, v, a, &
                     nout, tout, qout, vout, wout, stats, info, tfail)
end subroutine vehicle_run_c

!> Steady state of straight running (info 0 ok, 2 not converged, 3 outside the table, -1
!> singular): q and the velocities v (zero but the wheelsets' spin rates, see
!> vehicle_newmark%static_solve). Also returns the total force and contact outputs there.
subroutine vehicle_static_c(nd, ne, nw, ny, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                            y0, dy, r0, v0, gmod, mu, cmodel, fsn, bem, tol, maxit, q, nwo, v, f, wout, &
                            iters, resid, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_contact, only: nq_table
    use vehicle_model, only: vmodel, vehicle_pack, force_total
    use vehicle_newmark, only: static_solve
    implicit none
    integer(c_int), intent(in) :: nd, ne, nw, ny, nq, cmodel, fsn, bem, maxit, nwo
    real(c_double), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
    integer(c_int), intent(in) :: etype(ne), iws(6, nw), itr(3, nw)
    real(c_double), intent(in) :: tab(nq, 2, ny), y0, dy, r0, v0, gmod, mu, tol
    real(c_double), intent(inout) :: q(nd)
    real(c_double), intent(out) :: v(nd), f(nd), wout(nwo, 2, nw), resid
    integer(c_int), intent(out) :: iters, info
    type(vmodel) :: md
    integer :: inf2
    iters = 0
    resid = 0.0_c_double
    v = 0.0_c_double
    f = 0.0_c_double
    wout = 0.0_c_double
    if (nq /= nq_table) then
        info = -5
        return
    end if
    call vehicle_pack(nd, ne, nw, ny, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                      y0, dy, r0, v0, gmod, mu, cmodel, fsn, bem, md)
    iters = 0
    resid = 0.0_c_double
    call static_solve(md, q, v, tol, maxit, iters, resid, info)
    call force_total(md, q, v, f, wout, inf2)
    if (info == 0) info = inf2
end subroutine vehicle_static_c

!> Force F(q, v), contact outputs, and the tangents dF/dq and dF/dv (forward differences
!> for the contact, see vehicle_model%tangent).
subroutine vehicle_force_c(nd, ne, nw, ny, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                           y0, dy, r0, v0, gmod, mu, cmodel, fsn, bem, q, v, nwo, f, wout, jq, jv, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_contact, only: nq_table
    use vehicle_model, only: vmodel, vehicle_pack, force_total, tangent
    implicit none
    integer(c_int), intent(in) :: nd, ne, nw, ny, nq, cmodel, fsn, bem, nwo
    real(c_double), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
    integer(c_int), intent(in) :: etype(ne), iws(6, nw), itr(3, nw)
    real(c_double), intent(in) :: tab(nq, 2, ny), y0, dy, r0, v0, gmod, mu, q(nd), v(nd)
    real(c_double), intent(out) :: f(nd), wout(nwo, 2, nw), jq(nd, nd), jv(nd, nd)
    integer(c_int), intent(out) :: info
    type(vmodel) :: md
    if (nq /= nq_table) then
        info = -5
        return
    end if
    call vehicle_pack(nd, ne, nw, ny, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                      y0, dy, r0, v0, gmod, mu, cmodel, fsn, bem, md)
    call force_total(md, q, v, f, wout, info)
    if (info /= 0) return
    call tangent(md, q, v, 0.0_c_double, 0, jq, info)
    if (info /= 0) return
    call tangent(md, q, v, 0.0_c_double, 1, jv, info)
end subroutine vehicle_force_c

!> Make the BEM contact state of a run: gap fields gap(nx, ny, 2, ntab) of the left wheel's
!> two candidate points on the table's y nodes (ytab0, dytab), grid dx x dy, nws wheelsets,
!> material (g, nu), solver tolerances and iteration limits. info: 0 ok, -1 no free slot,
!> -2 bad sizes, -3 workspace (FFTW) failure.
subroutine vehicle_bem_create_c(nx, ny, ntab, dx, dy, ytab0, dytab, gap, nws, g, nu, tol_n, tol_t, &
                                maxit_n, maxit_t, handle, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_bem, only: bem_create
    implicit none
    integer(c_int), intent(in) :: nx, ny, ntab, nws, maxit_n, maxit_t
    real(c_double), intent(in) :: dx, dy, ytab0, dytab, gap(nx, ny, 2, ntab), g, nu, tol_n, tol_t
    integer(c_int), intent(out) :: handle, info
    integer :: hd, stat
    call bem_create(nx, ny, dx, dy, ntab, ytab0, dytab, gap, nws, g, nu, tol_n, tol_t, maxit_n, &
                    maxit_t, hd, stat)
    handle = hd
    info = stat
end subroutine vehicle_bem_create_c

subroutine vehicle_bem_free_c(handle)
    use iso_c_binding, only: c_int
    use vehicle_bem, only: bem_free
    implicit none
    integer(c_int), intent(in) :: handle
    call bem_free(handle)
end subroutine vehicle_bem_free_c

!> Counters of a BEM state (see vehicle_bem%BEM_NCOUNT); reset /= 0 clears them and the warm
!> starts afterwards. info -1: bad handle.
subroutine vehicle_bem_counts_c(handle, reset, counts, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_bem, only: bem_counts, bem_reset, BEM_NCOUNT
    implicit none
    integer(c_int), intent(in) :: handle, reset
    real(c_double), intent(out) :: counts(7)
    integer(c_int), intent(out) :: info
    real(c_double) :: c(BEM_NCOUNT)
    integer :: stat
    call bem_counts(handle, c, stat)
    counts = c
    info = stat
    if (reset /= 0) call bem_reset(handle)
end subroutine vehicle_bem_counts_c

!> The last pressure, tractions (Pa) and slip velocities (m/s) of wheelset iws, wheel iw
!> (1 left, 2 right), candidate point k (1 tread, 2 flange). info -1: bad arguments.
subroutine vehicle_bem_fields_c(handle, iws, iw, k, nx, ny, p, tx, ty, sx, sy, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_bem, only: bem_fields
    implicit none
    integer(c_int), intent(in) :: handle, iws, iw, k, nx, ny
    real(c_double), intent(out) :: p(nx, ny), tx(nx, ny), ty(nx, ny), sx(nx, ny), sy(nx, ny)
    integer(c_int), intent(out) :: info
    integer :: stat
    call bem_fields(handle, iws, iw, k, nx, ny, p, tx, ty, sx, sy, stat)
    info = stat
end subroutine vehicle_bem_fields_c
