!> f2py shim for the vehicle-track time simulation: plain arrays, explicit shapes, a status code
!> (common_status). Implements no equation.
!>
!> The model (matrices, nonlinear elements, wheelset DOF maps, contact table, material and
!> friction) is sent once, vehicle_model_create_c, and reached by its handle afterwards; the
!> run, static and force shims take the handle and the per-call values: the speed, the
!> contact model (vehicle_contact CMODEL_*), FASTSIM's fsn and, for the BEM contact, the
!> handle `bem` of a BEM contact state (vehicle_bem_create_c, which keeps its warm starts
!> between calls). A handle not in use gives STAT_BAD_HANDLE.

!> Store a model: handle for the calls below. info: see vehicle_model%vehicle_create.
subroutine vehicle_model_create_c(nd, ne, nw, ny, nr, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, &
                                  tab, y0, dy, p0, dph, rnom, r0, gmod, mu, ispin, handle, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_create
    implicit none
    integer(c_int), intent(in) :: nd, ne, nw, ny, nr, nq
    real(c_double), intent(in) :: mm(nd, nd), cc(nd, nd), kk(nd, nd), f0(nd), eg(nd, ne), epar(4, ne)
    integer(c_int), intent(in) :: etype(ne), iws(6, nw), itr(3, nw)
    real(c_double), intent(in) :: tab(nq, 2, ny, nr), y0, dy, p0, dph, rnom, r0, gmod, mu
    real(c_double), intent(in) :: ispin(nw)
    integer(c_int), intent(out) :: handle, info
    integer :: hd, stat
    call vehicle_create(nd, ne, nw, ny, nr, nq, mm, cc, kk, f0, etype, eg, epar, iws, itr, tab, &
                        y0, dy, p0, dph, rnom, r0, gmod, mu, ispin, hd, stat)
    handle = hd
    info = stat
end subroutine vehicle_model_create_c

!> Attach modal blocks coupled through attachment points to a model (replacing any): nm modal
!> coordinates in nb diagonal blocks starting at bs(1:nb+1) (1-based, bs(nb+1) = nm + 1), the
!> blocks of B and K_m packed column-major (nbk = sum of squared sizes), the rows phi (np x nm)
!> of the attachment points u = Phi Q, and npe point elements (kind ptype, rigid DOF prig
!> (0: ground), point ppt, parameters ppar). info: see vehicle_model%vehicle_attach_modal.
subroutine vehicle_modal_attach_c(handle, nm, nb, np, npe, nbk, bs, bb, kb, phi, ptype, prig, ppt, &
                                  ppar, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_modal
    implicit none
    integer(c_int), intent(in) :: handle, nm, nb, np, npe, nbk
    integer(c_int), intent(in) :: bs(nb + 1), ptype(npe), prig(npe), ppt(npe)
    real(c_double), intent(in) :: bb(nbk), kb(nbk), phi(np, nm), ppar(4, npe)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_modal(handle, nm, nb, np, npe, nbk, bs, bb, kb, phi, ptype, prig, ppt, ppar, &
                              stat)
    info = stat
end subroutine vehicle_modal_attach_c

!> Attach linear couplings (kind lkind: 1 split spring, 2 gyroscopic; point lpt, rigid
!> direction lg(:, e) over the nd rigid DOFs, parameters lpar = (k, c, f0)) and flexible-rim
!> wheelsets (wheelset frw, rim points frpt (dy, dz, drx) x (left, right), reference arms
!> frarm = (lateral, depth), m) to a model's modal part (model FR, vehicle_modal%modal_couple).
!> info: see vehicle_model%vehicle_attach_couplings.
subroutine vehicle_modal_couple_c(handle, nd, nlc, lkind, lpt, lg, lpar, nfr, frw, frpt, frarm, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_couplings
    implicit none
    integer(c_int), intent(in) :: handle, nd, nlc, nfr
    integer(c_int), intent(in) :: lkind(nlc), lpt(nlc), frw(nfr), frpt(3, 2, nfr)
    real(c_double), intent(in) :: lg(nd, nlc), lpar(3, nlc), frarm(2, nfr)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_couplings(handle, nd, nlc, lkind, lpt, lg, lpar, nfr, frw, frpt, frarm, stat)
    info = stat
end subroutine vehicle_modal_couple_c

!> Set the modal masses of a model's modal part: 1 (a mass-normalised mode) or 0 (a massless
!> coordinate: the residual flexibility of model FR). info: see vehicle_model%vehicle_attach_mass.
subroutine vehicle_modal_mass_c(handle, nm, mass, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_mass
    implicit none
    integer(c_int), intent(in) :: handle, nm
    real(c_double), intent(in) :: mass(nm)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_mass(handle, nm, mass, stat)
    info = stat
end subroutine vehicle_modal_mass_c

!> Set the Eulerian term of the flexible rims (model FR): ept(:, w, i) the 1-based points
!> carrying dPhi/dtheta of the rim points (y, z, rx) of wheel w of flexible wheelset i (0: no
!> term), omega(i) its spin, rad/s. info: see vehicle_model%vehicle_attach_euler.
subroutine vehicle_modal_euler_c(handle, nfr, ept, omega, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_euler
    implicit none
    integer(c_int), intent(in) :: handle, nfr
    integer(c_int), intent(in) :: ept(3, 2, nfr)
    real(c_double), intent(in) :: omega(nfr)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_euler(handle, nfr, ept, omega, stat)
    info = stat
end subroutine vehicle_modal_euler_c

!> Make the flexible rims' rows follow the contact point along the wheel profile (model FR,
!> Kaiser eq. 3; vehicle_modal%modal_follow_set): rim rows (y, z, rx) tab and their d/dtheta
!> etab (3, nq, ns, 2 wheels [left, right]) on s = s0 + (i - 1) ds, m; the residual's blocks
!> over the 12 points pt(:, i) (1-based) on s = rs0 + (i - 1) rds; m0, r0 (nfr) the 0-based
!> first modal column of each wheelset's modes and residual coordinates (r0 < 0: none); post
!> the residual rows' factor (stiffness post^2 I). info: see vehicle_model%vehicle_attach_follow.
subroutine vehicle_modal_follow_c(handle, nfr, nq, ns, s0, ds, tab, etab, nrs, rs0, rds, rcc, rcx, &
                                  rcj, rjj, m0, r0, pt, post, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_follow
    implicit none
    integer(c_int), intent(in) :: handle, nfr, nq, ns, nrs, m0(nfr), r0(nfr), pt(12, nfr)
    real(c_double), intent(in) :: s0, ds, tab(3, nq, ns, 2), etab(3, nq, ns, 2), rs0, rds
    real(c_double), intent(in) :: rcc(3, 3, nrs, 2), rcx(3, 3, nrs, nrs), rcj(3, 6, nrs, 2), rjj(6, 6)
    real(c_double), intent(in) :: post
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_follow(handle, nfr, nq, ns, s0, ds, tab, etab, nrs, rs0, rds, rcc, rcx, rcj, &
                               rjj, m0, r0, pt, post, stat)
    info = stat
end subroutine vehicle_modal_follow_c

!> The modal rows phi (np, nm) with the flexible rims' contact points at s(w, i), m from the
!> taping line (wheel w 1 left, 2 right of flexible wheelset i), as a time step sets them.
!> info: see vehicle_model%vehicle_follow_rows.
subroutine vehicle_follow_rows_c(handle, nfr, s, np, nm, phi, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_follow_rows
    implicit none
    integer(c_int), intent(in) :: handle, nfr, np, nm
    real(c_double), intent(in) :: s(2, nfr)
    real(c_double), intent(out) :: phi(np, nm)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_follow_rows(handle, nfr, s, np, nm, phi, stat)
    info = stat
end subroutine vehicle_follow_rows_c

!> Force over the whole state x = (q, Q) of a model with or without modal blocks (n = nd + nm):
!> the rigid forces with the point elements, and the modal forces -B Q' - K_m Q + Phi^T g_p;
!> with the contact outputs. info: see vehicle_model%vehicle_call and force_total.
subroutine vehicle_state_force_c(handle, n, nw, speed, cmodel, fsn, bem, x, xd, nwo, f, wout, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK
    use vehicle_model, only: vmodel, vsettings, vehicle_call
    use vehicle_newmark, only: state_force
    implicit none
    integer(c_int), intent(in) :: handle, n, nw, cmodel, fsn, bem, nwo
    real(c_double), intent(in) :: speed, x(n), xd(n)
    real(c_double), intent(out) :: f(n), wout(nwo, 2, nw)
    integer(c_int), intent(out) :: info
    type(vmodel), pointer :: md
    type(vsettings) :: rs
    integer :: stat
    f = 0.0_c_double
    wout = 0.0_c_double
    rs = vsettings(speed, cmodel, fsn, bem)
    call vehicle_call(handle, n, nw, nwo, rs, md, stat)
    if (stat == STAT_OK) call state_force(md, rs, x, xd, f, wout, stat)
    info = stat
end subroutine vehicle_state_force_c

!> Release a model (a handle not in use is ignored).
subroutine vehicle_model_free_c(handle)
    use iso_c_binding, only: c_int
    use vehicle_model, only: vehicle_free
    implicit none
    integer(c_int), intent(in) :: handle
    call vehicle_free(handle)
end subroutine vehicle_model_free_c

!> Steady state of straight running (info: see vehicle_newmark%static_solve; with modal
!> blocks over the rigid and modal DOFs, nd their number): q and the
!> velocities v (zero but the wheelsets' spin rates). Also returns the total force and the
!> contact outputs there. Runs with the GIL released (f2py threadsafe): Python calls it in
!> a worker thread and watches for Ctrl-C meanwhile (simulate._static_call).
subroutine vehicle_static_c(handle, nd, nw, speed, cmodel, fsn, bem, tol, maxit, q, nwo, v, f, &
                            wout, iters, resid, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK
    use vehicle_model, only: vmodel, vsettings, vehicle_call
    use vehicle_newmark, only: static_solve, state_force
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: handle, nd, nw, cmodel, fsn, bem, maxit, nwo
    real(c_double), intent(in) :: speed, tol
    real(c_double), intent(inout) :: q(nd)
    real(c_double), intent(out) :: v(nd), f(nd), wout(nwo, 2, nw), resid
    integer(c_int), intent(out) :: iters, info
    type(vmodel), pointer :: md
    type(vsettings) :: rs
    integer :: stat, stat2, it
    iters = 0
    resid = 0.0_c_double
    v = 0.0_c_double
    f = 0.0_c_double
    wout = 0.0_c_double
    rs = vsettings(speed, cmodel, fsn, bem)
    call vehicle_call(handle, nd, nw, nwo, rs, md, stat)
    info = stat
    if (stat /= STAT_OK) return
    call static_solve(md, rs, q, v, tol, maxit, it, resid, stat)
    iters = it
    call state_force(md, rs, q, v, f, wout, stat2)
    if (stat == STAT_OK) stat = stat2
    info = stat
end subroutine vehicle_static_c

!> Force F(q, v), contact outputs, and the tangents dF/dq and dF/dv (forward differences
!> for the contact, see vehicle_model%tangent). Rigid models only (else STAT_BAD_ARGUMENT).
subroutine vehicle_force_c(handle, nd, nw, speed, cmodel, fsn, bem, q, v, nwo, f, wout, jq, jv, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    use vehicle_model, only: vmodel, vsettings, vehicle_call, force_total, tangent, TANGENT_QV, &
                             TANGENT_V
    implicit none
    integer(c_int), intent(in) :: handle, nd, nw, cmodel, fsn, bem, nwo
    real(c_double), intent(in) :: speed, q(nd), v(nd)
    real(c_double), intent(out) :: f(nd), wout(nwo, 2, nw), jq(nd, nd), jv(nd, nd)
    integer(c_int), intent(out) :: info
    type(vmodel), pointer :: md
    type(vsettings) :: rs
    integer :: stat
    f = 0.0_c_double
    wout = 0.0_c_double
    jq = 0.0_c_double
    jv = 0.0_c_double
    rs = vsettings(speed, cmodel, fsn, bem)
    call vehicle_call(handle, nd, nw, nwo, rs, md, stat)
    if (stat == STAT_OK .and. md%mp%nm > 0) stat = STAT_BAD_ARGUMENT   ! rigid models only
    if (stat == STAT_OK) call force_total(md, rs, q, v, f, wout, stat)
    if (stat == STAT_OK) call tangent(md, rs, q, v, 0.0_c_double, TANGENT_QV, jq, stat)
    if (stat == STAT_OK) call tangent(md, rs, q, v, 0.0_c_double, TANGENT_V, jv, stat)
    info = stat
end subroutine vehicle_force_c

!> Make the BEM contact state of a run: gap fields gap(nx, ny, 2, ntab) of the left wheel's
!> two candidate points on the table's y nodes (ytab0, dytab), grid dx x dy, nws wheelsets,
!> material (g, nu), solver tolerances and iteration limits. info: see vehicle_bem%bem_create.
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
!> starts afterwards. info: STAT_OK or STAT_BAD_HANDLE.
subroutine vehicle_bem_counts_c(handle, reset, counts, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_bem, only: bem_counts, bem_reset, BEM_NCOUNT
    implicit none
    integer(c_int), intent(in) :: handle, reset
    real(c_double), intent(out) :: counts(12)
    integer(c_int), intent(out) :: info
    real(c_double) :: c(BEM_NCOUNT)
    integer :: stat
    call bem_counts(handle, c, stat)
    counts = c
    info = stat
    if (reset /= 0) call bem_reset(handle)
end subroutine vehicle_bem_counts_c

!> The last pressure, tractions (Pa) and slip velocities (m/s) of wheelset iws, wheel iw
!> (1 left, 2 right), candidate point k (1 tread, 2 flange). info: STAT_OK, STAT_BAD_HANDLE,
!> STAT_BAD_ARGUMENT (sizes or indices).
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

!> Evaluate a contact table at n poses (u, phi) as the time loop does (vehicle_contact%pose_at),
!> for tests and the table-accuracy study. info: STAT_BAD_ARGUMENT (see pose_set),
!> STAT_OUTSIDE_TABLE (a pose outside the table; ibad its index).
subroutine vehicle_pose_at_c(nq, ny, nr, tab, u0, du, p0, dph, rnom, n, u, phi, vals, wt, grad, ibad, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK
    use vehicle_contact, only: pose_table, pose_set, pose_at
    implicit none
    integer(c_int), intent(in) :: nq, ny, nr, n
    real(c_double), intent(in) :: tab(nq, 2, ny, nr), u0, du, p0, dph, rnom, u(n), phi(n)
    real(c_double), intent(out) :: vals(nq, 2, 2, n), wt(2, 2, n), grad(2, 2, 2, n)
    integer(c_int), intent(out) :: ibad, info
    type(pose_table) :: ct
    integer :: i, stat
    vals = 0.0_c_double
    wt = 0.0_c_double
    grad = 0.0_c_double
    ibad = 0
    call pose_set(nq, ny, nr, tab, u0, du, p0, dph, rnom, ct, stat)
    info = stat
    if (stat /= STAT_OK) return
    do i = 1, n
        call pose_at(ct, u(i), phi(i), vals(:, :, :, i), wt(:, :, i), grad(:, :, :, i), stat)
        if (stat /= STAT_OK) then
            info = stat
            ibad = i
            return
        end if
    end do
end subroutine vehicle_pose_at_c

!> Switch a model's contact to the strip potential: wheel samples ws (7 x nw: y0, z0, r,
!> kappa, z', tread weight, |kappa| (1 + z'^2)^1.5) at step ds, the rail's spline on ry0 + (i - 1) rdy (values rz,
!> second derivatives rm; track y = offset + y, height top - z; smoothed curvature rk and its
!> rate rk1), the ratio table fv, fm
!> (nf x 6) over x = fx0 + (i - 1) fdx. info: see vehicle_model%vehicle_attach_strip.
subroutine vehicle_strip_attach_c(handle, nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, &
                                  top, nf, fx0, fdx, fv, fm, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_strip
    implicit none
    integer(c_int), intent(in) :: handle, nw, nr, nf
    real(c_double), intent(in) :: ws(7, nw), ds, rnom, ry0, rdy, rz(nr), rm(nr), rk(nr), rk1(nr)
    real(c_double), intent(in) :: offset, top
    real(c_double), intent(in) :: fx0, fdx, fv(nf, 6), fm(nf, 6)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_strip(handle, nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, top, nf, &
                              fx0, fdx, fv, fm, stat)
    info = stat
end subroutine vehicle_strip_attach_c

!> The strip potential of one (left) wheel at np poses (y, zc, phi, psi) (vehicle_strip%strip_wheel)
!> without a model: out(nso, 2, np) per slot; props(5, 2, np) the slots' a1, b1, c11, c22, c23.
!> info: see vehicle_strip%strip_set.
subroutine vehicle_strip_eval_c(nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, top, nf, &
                                fx0, fdx, fv, fm, np, pose, nso_in, out, props, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_SIZE_MISMATCH
    use vehicle_strip, only: strip_geometry, strip_set, strip_wheel, strip_props, nso, SO_X, SO_A
    implicit none
    integer(c_int), intent(in) :: nw, nr, nf, np, nso_in
    real(c_double), intent(in) :: ws(7, nw), ds, rnom, ry0, rdy, rz(nr), rm(nr), rk(nr), rk1(nr)
    real(c_double), intent(in) :: offset, top
    real(c_double), intent(in) :: fx0, fdx, fv(nf, 6), fm(nf, 6), pose(4, np)
    real(c_double), intent(out) :: out(nso_in, 2, np), props(5, 2, np)
    integer(c_int), intent(out) :: info
    type(strip_geometry) :: st
    integer :: stat, i, k
    out = 0.0_c_double
    props = 0.0_c_double
    info = STAT_SIZE_MISMATCH
    if (nso_in /= nso) return
    call strip_set(nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, top, nf, fx0, fdx, fv, fm, &
                   st, stat)
    info = stat
    if (stat /= STAT_OK) return
    do i = 1, np
        call strip_wheel(st, pose(1, i), pose(2, i), pose(3, i), out(:, :, i), pose(4, i))
        do k = 1, 2
            call strip_props(st, out(SO_X, k, i), out(SO_A, k, i), props(:, k, i))
        end do
    end do
end subroutine vehicle_strip_eval_c

!> The strip outputs of one (left) wheel at np poses and their exact derivatives over the pose
!> (vehicle_strip%strip_linearise, the Newton tangent's linearisation): out(nso, 2, np),
!> dout(nso, 2, 4, np) over (y, zc, phi, psi). info: see vehicle_strip%strip_set.
subroutine vehicle_strip_lin_c(nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, top, nf, &
                               fx0, fdx, fv, fm, np, pose, nso_in, out, dout, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_SIZE_MISMATCH
    use vehicle_strip, only: strip_geometry, strip_set, strip_lin, strip_linearise, nso
    implicit none
    integer(c_int), intent(in) :: nw, nr, nf, np, nso_in
    real(c_double), intent(in) :: ws(7, nw), ds, rnom, ry0, rdy, rz(nr), rm(nr), rk(nr), rk1(nr)
    real(c_double), intent(in) :: offset, top
    real(c_double), intent(in) :: fx0, fdx, fv(nf, 6), fm(nf, 6), pose(4, np)
    real(c_double), intent(out) :: out(nso_in, 2, np), dout(nso_in, 2, 4, np)
    integer(c_int), intent(out) :: info
    type(strip_geometry) :: st
    type(strip_lin) :: lin
    integer :: stat, i
    out = 0.0_c_double
    dout = 0.0_c_double
    info = STAT_SIZE_MISMATCH
    if (nso_in /= nso) return
    call strip_set(nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, top, nf, fx0, fdx, fv, fm, &
                   st, stat)
    info = stat
    if (stat /= STAT_OK) return
    do i = 1, np
        call strip_linearise(st, pose(:, i), lin)
        out(:, :, i) = lin%so
        dout(:, :, :, i) = lin%d
    end do
end subroutine vehicle_strip_lin_c

!> Put wheelsets on the ring track (model RF): wheelset rlw(i) (1-based) has the points rlpt(:,
!> k, i) of a track element's pose (y, z, roll) under wheel k; the rows over the modal
!> coordinates rm0 + 1 .. rm0 + nk come from the kept ring modes (group starts bpos, kpos,
!> voff; basis kap, fam, rail, obs; packed eigenvector entries vk) at the contact points
!> (rail crho, position cx0 + v0 t, row map ctr). info: see vehicle_model%vehicle_attach_ring.
subroutine vehicle_ring_attach_c(handle, nrl, rlw, rlpt, rm0, ng, nbt, nk, nvk, nc, bpos, kpos, &
                                 voff, kap, fam, rail, obs, vk, crho, cx0, ctr, v0, length, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_SIZE_MISMATCH
    use vehicle_model, only: vehicle_attach_ring
    implicit none
    integer(c_int), intent(in) :: handle, nrl, rm0, ng, nbt, nk, nvk, nc
    integer(c_int), intent(in) :: rlw(nrl), rlpt(3, 2, nrl), bpos(ng + 1), kpos(ng + 1), voff(ng + 1)
    integer(c_int), intent(in) :: fam(nbt), rail(nbt), crho(nc)
    real(c_double), intent(in) :: kap(nbt), obs(4, nbt), vk(nvk), cx0(nc), ctr(3, 4, nc), v0, length
    integer(c_int), intent(out) :: info
    integer :: stat
    info = STAT_SIZE_MISMATCH
    if (nc /= 2 * nrl) return
    call vehicle_attach_ring(handle, nrl, int(rlw), int(rlpt), rm0, ng, nbt, nk, nvk, int(bpos), &
                             int(kpos), int(voff), kap, int(fam), int(rail), obs, vk, int(crho), cx0, &
                             ctr, v0, length, stat)
    info = stat
end subroutine vehicle_ring_attach_c

!> Set a model's ring rows to time t (model RF). info: see vehicle_model%vehicle_ring_time.
subroutine vehicle_ring_time_c(handle, t, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_ring_time
    implicit none
    integer(c_int), intent(in) :: handle
    real(c_double), intent(in) :: t
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_ring_time(handle, t, stat)
    info = stat
end subroutine vehicle_ring_time_c

!> Add the ring's residual flexibility at the contact points (model RF, after
!> vehicle_ring_attach_c): the compliance table rtab (3, 3, nrx, 2 rails) over one bay and
!> the residual coordinates' change of coordinates rpost (3, 3, 2 rails; rows L(x) rpost).
!> info: see vehicle_model%vehicle_ring_residual.
subroutine vehicle_ring_residual_c(handle, nrx, bay, rtab, rpost, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_ring_residual
    implicit none
    integer(c_int), intent(in) :: handle, nrx
    real(c_double), intent(in) :: bay, rtab(3, 3, nrx, 2), rpost(3, 3, 2)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_ring_residual(handle, nrx, bay, rtab, rpost, stat)
    info = stat
end subroutine vehicle_ring_residual_c

!> Integrate nsteps steps; see vehicle_newmark%newmark_run for info and stats. nd: the size of
!> the state, rigid plus modal DOFs. scheme (vehicle_newmark SCHEME_*): 0 HHT-alpha, 1 the
!> energy-conserving midpoint rule with discrete gradients, 2 the trapezoidal rule with the
!> modal blocks stepped exactly (vehicle_modal_step; alpha must be 0 for 1 and 2); 2 + 16 m
!> (m = 1..64): 2 with the ring's moving rows at m + 1 nodes a step (vehicle_ring_step); plus
!> 2048 l (l = 1..16): 2 with a step that starts in flange contact taken as 2^l sub-steps
!> (vehicle_newmark flange_level).
!> (f, w): the force and wheel outputs at (q, v) carried from the previous call (carried /= 0)
!> or evaluated first (carried = 0); updated to the last state's.
!> info: STAT_BAD_ARGUMENT for an unknown scheme or scheme 1 or 2 with alpha /= 0.
subroutine vehicle_run_c(handle, nd, nw, speed, cmodel, fsn, bem, h, nsteps, nevery, alpha, &
                         tol, maxit, maxsub, qmax, rtol, scheme, t, q, v, a, f, w, carried, &
                         nout, nwo, tout, qout, vout, wout, stats, info, tfail)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    use vehicle_model, only: vmodel, vsettings, vehicle_call
    use vehicle_newmark, only: newmark_run, hht_options, SCHEME_HHT, SCHEME_ENERGY, SCHEME_EXACT
    implicit none
    integer(c_int), intent(in) :: handle, nd, nw, cmodel, fsn, bem, nsteps, nevery, maxit, maxsub
    integer(c_int), intent(in) :: nout, nwo, scheme, carried
    real(c_double), intent(in) :: speed, h, alpha, tol, qmax, rtol
    real(c_double), intent(inout) :: t, q(nd), v(nd), a(nd), f(nd), w(nwo, 2, nw)
    real(c_double), intent(out) :: tout(nout), qout(nd, nout), vout(nd, nout), wout(nwo, 2, nw, nout)
    real(c_double), intent(out) :: stats(10), tfail
    integer(c_int), intent(out) :: info
    type(vmodel), pointer :: md
    integer :: stat, base, nodes, flev
    tout = 0.0_c_double
    qout = 0.0_c_double
    vout = 0.0_c_double
    wout = 0.0_c_double
    stats = 0.0_c_double
    tfail = t
    info = STAT_BAD_ARGUMENT
    base = mod(scheme, 16)
    nodes = mod(scheme / 16, 128)
    flev = scheme / 2048
    if (base /= SCHEME_HHT .and. base /= SCHEME_ENERGY .and. base /= SCHEME_EXACT) return
    if (base /= SCHEME_HHT .and. alpha /= 0.0_c_double) return
    if (nodes < 0 .or. nodes > 64 .or. (nodes > 0 .and. base /= SCHEME_EXACT)) return
    if (flev < 0 .or. flev > 16 .or. (flev > 0 .and. base /= SCHEME_EXACT)) return
    call vehicle_call(handle, nd, nw, nwo, vsettings(speed, cmodel, fsn, bem), md, stat)
    info = stat
    if (stat /= STAT_OK) return
    call newmark_run(md, vsettings(speed, cmodel, fsn, bem), h, nsteps, nevery, &
                     hht_options(alpha, tol, qmax, maxit, maxsub, rtol, base, nodes, flev), t, q, v, a, f, &
                     w, carried /= 0, nout, tout, qout, vout, wout, stats, stat, tfail)
    info = stat
end subroutine vehicle_run_c

!> Solve the BEM patches on windows around the interpenetration (on /= 0, the default) or on
!> the full grid (vehicle_bem%bem_window). info: STAT_OK or STAT_BAD_HANDLE.
subroutine vehicle_bem_window_c(handle, on, info)
    use iso_c_binding, only: c_int
    use vehicle_bem, only: bem_window
    implicit none
    integer(c_int), intent(in) :: handle, on
    integer(c_int), intent(out) :: info
    integer :: stat
    call bem_window(handle, on /= 0, stat)
    info = stat
end subroutine vehicle_bem_window_c

!> Committed solves of a BEM point between its patch Jacobians, the Newton tangent's linear
!> model (vehicle_bem%bem_jacobian); 0: Hertz + Kalker scaled to the BEM instead. info:
!> STAT_OK, STAT_BAD_HANDLE, STAT_BAD_ARGUMENT (age < 0).
subroutine vehicle_bem_jacobian_c(handle, age, info)
    use iso_c_binding, only: c_int
    use vehicle_bem, only: bem_jacobian
    implicit none
    integer(c_int), intent(in) :: handle, age
    integer(c_int), intent(out) :: info
    integer :: stat
    call bem_jacobian(handle, age, stat)
    info = stat
end subroutine vehicle_bem_jacobian_c

!> Linear updates of a BEM state's patches (vehicle_bem%bem_update): band > 0 takes a
!> patch's forces from its linear model while each input's first-order change stays within
!> band x its normal force; 0 solves every patch; reach > 0 also while it stays within reach
!> bands with a Jacobian made near it (in motion). info: STAT_OK, STAT_BAD_HANDLE,
!> STAT_BAD_ARGUMENT.
subroutine vehicle_bem_update_c(handle, band, reach, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_bem, only: bem_update
    implicit none
    integer(c_int), intent(in) :: handle
    real(c_double), intent(in) :: band, reach
    integer(c_int), intent(out) :: info
    integer :: stat
    call bem_update(handle, band, reach, stat)
    info = stat
end subroutine vehicle_bem_update_c

!> The linear model of one BEM point (vehicle_bem%bem_point_jacobian): jac (6, 6) = dy/dx,
!> x = (dn, phi, xi, eta, spin, s), y = (fn, fx, fy, mz, fn xc, fn yc), the base xb, yb, the
!> solves since the Jacobian (age), ok /= 0 when the point has a model.
subroutine vehicle_bem_point_jacobian_c(handle, iws, iw, k, jac, xb, yb, age, ok, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_bem, only: bem_point_jacobian
    implicit none
    integer(c_int), intent(in) :: handle, iws, iw, k
    real(c_double), intent(out) :: jac(6, 6), xb(6), yb(6)
    integer(c_int), intent(out) :: age, ok, info
    integer :: stat, ag
    logical :: lok
    call bem_point_jacobian(handle, iws, iw, k, jac, xb, yb, ag, lok, stat)
    age = ag
    ok = merge(1, 0, lok)
    info = stat
end subroutine vehicle_bem_point_jacobian_c

!> Solve one BEM point's patch at the linear model's inputs x (6) on the full grid without
!> changing the point (vehicle_bem%bem_probe): y (6) its outputs. info: see bem_probe.
subroutine vehicle_bem_probe_c(handle, iws, iw, k, x, y, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_bem, only: bem_probe
    implicit none
    integer(c_int), intent(in) :: handle, iws, iw, k
    real(c_double), intent(in) :: x(6)
    real(c_double), intent(out) :: y(6)
    integer(c_int), intent(out) :: info
    integer :: stat
    call bem_probe(handle, iws, iw, k, x, y, stat)
    info = stat
end subroutine vehicle_bem_probe_c

!> Threads of the BEM patch loop (vehicle_bem%bem_threads): n, or all the OpenMP runtime
!> offers for n <= 0; nset the number set (1 in a build without OpenMP). info: STAT_OK or
!> STAT_BAD_HANDLE.
subroutine vehicle_bem_threads_c(handle, n, nset, info)
    use iso_c_binding, only: c_int
    use vehicle_bem, only: bem_threads
    implicit none
    integer(c_int), intent(in) :: handle, n
    integer(c_int), intent(out) :: nset, info
    integer :: ns, stat
    call bem_threads(handle, n, ns, stat)
    nset = ns
    info = stat
end subroutine vehicle_bem_threads_c

!> Attach a curve's tables to a model for the runs that follow (vehicle_curve; ns = 0 drops
!> it): ns nodes over the vehicle's position s = s0 + (i - 1) ds, m, for a run at speed v0
!> (m/s) starting at x0 (m): fext (nd, ns) forces (N, N m), doff and drate (ne, ns) the
!> elements' deflection and rate offsets, kap (nw, ns) the curvature at each wheelset (1/m).
!> info: see vehicle_model%vehicle_attach_curve.
subroutine vehicle_curve_attach_c(handle, nd, ne, nw, ns, s0, ds, x0, v0, fext, doff, drate, kap, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_curve
    implicit none
    integer(c_int), intent(in) :: handle, nd, ne, nw, ns
    real(c_double), intent(in) :: s0, ds, x0, v0
    real(c_double), intent(in) :: fext(nd, ns), doff(ne, ns), drate(ne, ns), kap(nw, ns)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_curve(handle, nd, ne, nw, ns, s0, ds, x0, v0, fext, doff, drate, kap, stat)
    info = stat
end subroutine vehicle_curve_attach_c

!> Add point forces gpt (np, ns) on the attachment points of a model with flexible wheelsets
!> (FR, FF) to the curve attached last: N or N m on its ns nodes. info: see
!> vehicle_model%vehicle_attach_curve_points.
subroutine vehicle_curve_points_c(handle, np, ns, gpt, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_curve_points
    implicit none
    integer(c_int), intent(in) :: handle, np, ns
    real(c_double), intent(in) :: gpt(np, ns)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_attach_curve_points(handle, np, ns, gpt, stat)
    info = stat
end subroutine vehicle_curve_points_c

!> Drop a model's curve (straight track again). info: STAT_OK or STAT_BAD_HANDLE.
subroutine vehicle_curve_clear_c(handle, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_attach_curve
    implicit none
    integer(c_int), intent(in) :: handle
    integer(c_int), intent(out) :: info
    real(c_double) :: none(1, 1)
    integer :: stat
    none = 0.0_c_double
    call vehicle_attach_curve(handle, 0, 0, 0, 0, 0.0_c_double, 1.0_c_double, 0.0_c_double, 1.0_c_double, &
                              none, none, none, none, stat)
    info = stat
end subroutine vehicle_curve_clear_c

!> Put a model on an irregular track (n >= 2 nodes x, channels c and slopes d (4, n): vertical
!> level, alignment, cross level, gauge in m; wheelset positions xw, start x0 in m, speed v0 in
!> m/s, the cross level's base in m) or take it off (n = 0; x, c, d, then one dummy node).
!> info: see vehicle_model%vehicle_attach_irregularity.
subroutine vehicle_irregularity_attach_c(handle, n, nx, x, c, d, nw, xw, x0, v0, base, info)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_SIZE_MISMATCH
    use vehicle_model, only: vehicle_attach_irregularity
    implicit none
    integer(c_int), intent(in) :: handle, n, nx, nw
    real(c_double), intent(in) :: x(nx), c(4, nx), d(4, nx), xw(nw), x0, v0, base
    integer(c_int), intent(out) :: info
    integer :: stat
    info = STAT_SIZE_MISMATCH    ! n is neither the arrays' length nor 0
    if (n /= 0 .and. n /= nx) return
    call vehicle_attach_irregularity(handle, int(n), x, c, d, int(nw), xw, x0, v0, base, stat)
    info = stat
end subroutine vehicle_irregularity_attach_c

!> The irregular track's inputs under the wheels at time t, u (7, 2, nw): per wheel (left,
!> right) the pose of its rail element T_y, T_z (m), T_roll (rad), their rates (m/s, rad/s)
!> and the rail's yaw (rad). info: see vehicle_model%vehicle_irregularity_inputs.
subroutine vehicle_irregularity_inputs_c(handle, t, nw, u, info)
    use iso_c_binding, only: c_int, c_double
    use vehicle_model, only: vehicle_irregularity_inputs
    implicit none
    integer(c_int), intent(in) :: handle, nw
    real(c_double), intent(in) :: t
    real(c_double), intent(out) :: u(7, 2, nw)
    integer(c_int), intent(out) :: info
    integer :: stat
    call vehicle_irregularity_inputs(handle, t, int(nw), u, stat)
    info = stat
end subroutine vehicle_irregularity_inputs_c
