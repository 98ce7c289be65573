!> f2py shim for the track kernels: plain arrays, explicit shapes, a status code. Implements
!> no equation. Argument checks live in Python (railvti.track); info is a STAT_ code of
!> common_status (railvti._status translates it); where a failure has a location (an element,
!> a wave number) or a LAPACK info, it comes back in its own argument.

!> Section matrices K0, K1, K2, M of the 2.5-D rail FE (ndof = 3 nn, DOFs x, eta, zeta per node).
!> bad_element: the (1-based) element with det J <= 0 when info = STAT_BAD_ELEMENT.
subroutine track_section_matrices_c(nn, ne, xy, conn, young, poisson, rho, k0, k1, k2, m, info, &
                                    bad_element)
    use iso_c_binding, only: c_int, c_double
    use track_section, only: section_matrices
    implicit none
    integer(c_int), intent(in) :: nn, ne
    real(c_double), intent(in) :: xy(nn, 2), young, poisson, rho
    integer(c_int), intent(in) :: conn(ne, 6)
    real(c_double), intent(out), dimension(3 * nn, 3 * nn) :: k0, k1, k2, m
    integer(c_int), intent(out) :: info, bad_element
    integer :: stat, bad
    call section_matrices(nn, ne, xy, conn, young, poisson, rho, k0, k1, k2, m, stat, bad)
    info = stat
    bad_element = bad
end subroutine track_section_matrices_c

!> Reduced basis of the rail section over wave numbers (see track_rail). On failure, sample is
!> the (1-based) sample wave number and lapack_info LAPACK's info.
subroutine track_reduced_basis_c(n, k0, k1, k2, m, nf, f, ns, kap_s, lam_max, rmax, r, w, &
                                 k0r, k1r, k2r, fr, info, sample, lapack_info)
    use iso_c_binding, only: c_int, c_double
    use track_rail, only: rail_reduced_basis
    implicit none
    integer(c_int), intent(in) :: n, nf, ns, rmax
    real(c_double), intent(in), dimension(n, n) :: k0, k1, k2, m
    real(c_double), intent(in) :: f(n, nf), kap_s(ns), lam_max
    integer(c_int), intent(out) :: r, info, sample, lapack_info
    real(c_double), intent(out) :: w(n, rmax), k0r(rmax, rmax), k1r(rmax, rmax), k2r(rmax, rmax)
    real(c_double), intent(out) :: fr(rmax, nf)
    integer :: rr, stat, s, linfo
    call rail_reduced_basis(n, k0, k1, k2, m, nf, f, ns, kap_s, lam_max, rmax, rr, w, &
                            k0r, k1r, k2r, fr, stat, s, linfo)
    r = rr
    info = stat
    sample = s
    lapack_info = linfo
end subroutine track_reduced_basis_c

!> Rail basis functions (kept modes + residual attachments) at nk wave numbers. On failure,
!> wave is the (1-based) index into kap and lapack_info LAPACK's info.
subroutine track_wave_basis_c(r, k0r, k1r, k2r, nf, fr, nk, kap, lam_cut, mmax, nm, om2, y, info, &
                              wave, lapack_info)
    use iso_c_binding, only: c_int, c_double
    use track_rail, only: rail_wave_basis
    implicit none
    integer(c_int), intent(in) :: r, nf, nk, mmax
    real(c_double), intent(in), dimension(r, r) :: k0r, k1r, k2r
    real(c_double), intent(in) :: fr(r, nf), kap(nk), lam_cut
    integer(c_int), intent(out) :: nm(nk), info, wave, lapack_info
    real(c_double), intent(out) :: om2(mmax, nk), y(r, mmax, nk)
    integer :: nmi(nk), stat, ik, linfo
    call rail_wave_basis(r, k0r, k1r, k2r, nf, fr, nk, kap, lam_cut, mmax, nmi, om2, y, stat, &
                         ik, linfo)
    nm = nmi
    info = stat
    wave = ik
    lapack_info = linfo
end subroutine track_wave_basis_c

!> Modes of one cyclic group of the ring track (see track_ring); lapack_info: LAPACK's info.
subroutine track_group_modes_c(nb, om2, kap, fam, sgn, rail, np, tr, eta_p, w_p, nq, xi, w_xi, &
                               kpad, cpad, y0, beta, ms, kb, cb, nsl, j, eta_rail, ntot, &
                               lam, v, cmod, info, lapack_info)
    use iso_c_binding, only: c_int, c_double
    use track_ring, only: ring_group_modes
    implicit none
    integer(c_int), intent(in) :: nb, np, nq, nsl, j, ntot
    integer(c_int), intent(in) :: fam(nb), sgn(nb), rail(nb)
    real(c_double), intent(in) :: om2(nb), kap(nb), tr(np, 3, nb), eta_p(np), w_p(np)
    real(c_double), intent(in) :: xi(nq), w_xi(nq), kpad(3), cpad(3), y0(2), beta(2)
    real(c_double), intent(in) :: ms(3), kb(3), cb(3), eta_rail
    real(c_double), intent(out) :: lam(ntot), v(ntot, ntot), cmod(ntot)
    integer(c_int), intent(out) :: info, lapack_info
    integer :: fam_(nb), sgn_(nb), rail_(nb), stat, linfo
    fam_ = fam; sgn_ = sgn; rail_ = rail
    call ring_group_modes(nb, om2, kap, fam_, sgn_, rail_, np, tr, eta_p, w_p, nq, xi, w_xi, &
                          kpad, cpad, y0, beta, ms, kb, cb, nsl, j, eta_rail, ntot, lam, v, cmod, &
                          stat, linfo)
    info = stat
    lapack_info = linfo
end subroutine track_group_modes_c

!> Rail-head values (x, eta, zeta, roll; rail-local) of every track mode at x on rail rho:
!> the shape functions of the modal form, continuous in x.
subroutine track_eval_x_c(ng, bpos, mpos, vpos, nbt, kap, fam, rail, obs, nvf, vflat, ntt, x, rho, psi)
    use iso_c_binding, only: c_int, c_double
    use track_ring, only: ring_eval_x
    implicit none
    integer(c_int), intent(in) :: ng, nbt, nvf, ntt, rho
    integer(c_int), intent(in) :: bpos(ng + 1), mpos(ng + 1), vpos(ng + 1), fam(nbt), rail(nbt)
    real(c_double), intent(in) :: kap(nbt), obs(4, nbt), vflat(nvf), x
    real(c_double), intent(out) :: psi(4, ntt)
    integer :: bp(ng + 1), mp(ng + 1), vp(ng + 1), fa(nbt), ra(nbt)
    bp = bpos; mp = mpos; vp = vpos; fa = fam; ra = rail
    call ring_eval_x(ng, bp, mp, vp, nbt, kap, fa, ra, obs, nvf, vflat, ntt, x, int(rho), psi)
end subroutine track_eval_x_c

!> Modal-sum FRF h(f) = sum_r a_r / (omega_r^2 - omega^2 + i omega c_r).
subroutine track_frf_c(ntt, lam, cm, a, nf, freq, hr, hi)
    use iso_c_binding, only: c_int, c_double
    use track_ring, only: ring_frf
    implicit none
    integer(c_int), intent(in) :: ntt, nf
    real(c_double), intent(in) :: lam(ntt), cm(ntt), a(ntt), freq(nf)
    real(c_double), intent(out) :: hr(nf), hi(nf)
    call ring_frf(ntt, lam, cm, a, nf, freq, hr, hi)
end subroutine track_frf_c
