!> f2py shim for the vehicle-track time simulation: plain arrays, explicit shapes, info codes.
!> The model (matrices, nonlinear elements, wheelset DOF maps, contact table) is passed whole
!> on every call; railvti.vehicle builds and checks it.

!> Integrate nsteps steps; see vehicle_newmark%newmark_run for info and stats.
subroutine vehicle_run_c(nd, ne, nw, ny, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                         y0, dy, r0, v0, gmod, mu, cmodel, fsn, h, nsteps, nevery, alpha, tol, maxit, &
                         maxsub, qmax, t, q, v, a, nout, nwo, tout, qout, vout, wout, stats, info, tfail)
    use iso_c_binding, only: c_int, c_double
    use vehicle_contact, only: nq_table
    use vehicle_model, only: vmodel, vehicle_pack
    use vehicle_newmark, only: newmark_run
    implicit none
    integer(c_int), intent(in) :: nd, ne, nw, ny, nq, cmodel, fsn, nsteps, nevery, maxit, maxsub, nout, nwo
    real(c_double), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
    integer(c_int), intent(in) :: etype(ne), iws(4, nw), itr(3, nw)
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
                      y0, dy, r0, v0, gmod, mu, cmodel, fsn, md)
    call newmark_run(md, h, nsteps, nevery, alpha, tol, maxit, maxsub, qmax, t, q, v, a, &
                     nout, tout, qout, vout, wout, stats, info, tfail)
end subroutine vehicle_run_c

!> Static equilibrium (info 0 ok, 2 not converged, 3 outside the table, -1 singular).
!> Also returns the total force and contact outputs at the solution.
subroutine vehicle_static_c(nd, ne, nw, ny, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                            y0, dy, r0, v0, gmod, mu, cmodel, fsn, tol, maxit, q, nwo, f, wout, &
                            iters, resid, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_contact, only: nq_table
    use vehicle_model, only: vmodel, vehicle_pack, force_total
    use vehicle_newmark, only: static_solve
    implicit none
    integer(c_int), intent(in) :: nd, ne, nw, ny, nq, cmodel, fsn, maxit, nwo
    real(c_double), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
    integer(c_int), intent(in) :: etype(ne), iws(4, nw), itr(3, nw)
    real(c_double), intent(in) :: tab(nq, 2, ny), y0, dy, r0, v0, gmod, mu, tol
    real(c_double), intent(inout) :: q(nd)
    real(c_double), intent(out) :: f(nd), wout(nwo, 2, nw), resid
    integer(c_int), intent(out) :: iters, info
    type(vmodel) :: md
    real(c_double) :: v(nd)
    integer :: inf2
    iters = 0
    resid = 0.0_c_double
    f = 0.0_c_double
    wout = 0.0_c_double
    if (nq /= nq_table) then
        info = -5
        return
    end if
    call vehicle_pack(nd, ne, nw, ny, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                      y0, dy, r0, v0, gmod, mu, cmodel, fsn, md)
    iters = 0
    resid = 0.0_c_double
    call static_solve(md, q, tol, maxit, iters, resid, info)
    v = 0.0_c_double
    call force_total(md, q, v, f, wout, inf2)
    if (info == 0) info = inf2
end subroutine vehicle_static_c

!> Force F(q, v), contact outputs, and the tangents dF/dq and dF/dv (forward differences
!> for the contact, see vehicle_model%tangent).
subroutine vehicle_force_c(nd, ne, nw, ny, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                           y0, dy, r0, v0, gmod, mu, cmodel, fsn, q, v, nwo, f, wout, jq, jv, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_contact, only: nq_table
    use vehicle_model, only: vmodel, vehicle_pack, force_total, tangent
    implicit none
    integer(c_int), intent(in) :: nd, ne, nw, ny, nq, cmodel, fsn, nwo
    real(c_double), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
    integer(c_int), intent(in) :: etype(ne), iws(4, nw), itr(3, nw)
    real(c_double), intent(in) :: tab(nq, 2, ny), y0, dy, r0, v0, gmod, mu, q(nd), v(nd)
    real(c_double), intent(out) :: f(nd), wout(nwo, 2, nw), jq(nd, nd), jv(nd, nd)
    integer(c_int), intent(out) :: info
    type(vmodel) :: md
    if (nq /= nq_table) then
        info = -5
        return
    end if
    call vehicle_pack(nd, ne, nw, ny, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                      y0, dy, r0, v0, gmod, mu, cmodel, fsn, md)
    call force_total(md, q, v, f, wout, info)
    if (info /= 0) return
    call tangent(md, q, v, 0.0_c_double, 0, jq, info)
    if (info /= 0) return
    call tangent(md, q, v, 0.0_c_double, 1, jv, info)
end subroutine vehicle_force_c
