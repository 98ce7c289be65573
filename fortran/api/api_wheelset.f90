!> f2py shim for the flexible wheelset kernels: plain arrays, explicit shapes, a status code.
!> Implements no equation. Argument checks live in Python (railvti.wheelset); info is a STAT_
!> code of common_status, and a location (element, frequency) or a solver's own info comes
!> back in its own argument.

!> Element matrices of harmonic k for one nine-node meridian element (tests).
!> info: STAT_OK or STAT_BAD_ELEMENT.
subroutine wheelset_element_c(k, xe, e, nu, rho, ke, me, ce, mc, info)
    use iso_c_binding, only: c_int, c_double
    use wheelset_element, only: axisym_element
    implicit none
    integer(c_int), intent(in) :: k
    real(c_double), intent(in) :: xe(2, 9), e, nu, rho
    real(c_double), intent(out) :: ke(27, 27), me(27, 27), ce(27, 27), mc(27, 27)
    integer(c_int), intent(out) :: info
    call axisym_element(k, xe, e, nu, rho, ke, me, ce, mc, info)
end subroutine wheelset_element_c

!> Modes of harmonic k up to omega^2 = lam_max (see wheelset_modes::harmonic_modes).
!> bad_element: the (1-based) inverted element when info = STAT_BAD_ELEMENT; solver_info:
!> the LAPACK/ARPACK info behind an eigen-solver failure. Runs with the GIL released (f2py
!> threadsafe): Python calls it in a worker thread, one at a time (ARPACK's SAVEd state), and
!> watches for Ctrl-C meanwhile (railvti.wheelset.fe).
subroutine wheelset_modes_c(nn, ne, xn, conn, k, e, nu, rho, fixed, nspr, spr_node, spr_comp, &
                            spr_k, lam_max, nmax, nm, lam, phi, gam, mcq, kgq, neq, kd, info, &
                            bad_element, solver_info)
    use iso_c_binding, only: c_int, c_double
    use wheelset_modes, only: harmonic_modes
    implicit none
    !f2py threadsafe
    integer(c_int), intent(in) :: nn, ne, k, nspr, nmax
    real(c_double), intent(in) :: xn(2, nn), e, nu, rho, lam_max
    integer(c_int), intent(in) :: conn(9, ne), fixed(3, nn)
    integer(c_int), intent(in) :: spr_node(nspr), spr_comp(nspr)
    real(c_double), intent(in) :: spr_k(nspr)
    integer(c_int), intent(out) :: nm, neq, kd, info, bad_element, solver_info
    real(c_double), intent(out) :: lam(nmax), phi(3, nn, nmax), gam(nmax, nmax), mcq(nmax, nmax)
    real(c_double), intent(out) :: kgq(nmax, nmax)
    call harmonic_modes(nn, ne, xn, conn, k, e, nu, rho, fixed, nspr, spr_node, spr_comp, spr_k, &
                        lam_max, nmax, nm, lam, phi, gam, mcq, kgq, neq, kd, info, bad_element, &
                        solver_info)
end subroutine wheelset_modes_c

!> Frequency response of (-w^2 M + i w D + K) q = fin; h = fout^T q.
!> info: STAT_OK or STAT_SINGULAR at omega(freq_index) (1-based).
subroutine wheelset_frf_c(nq, mq, dq, kq, nin, fin, nout, fout, nf, omega, h, info, freq_index)
    use iso_c_binding, only: c_int, c_double, c_double_complex
    use wheelset_frf, only: gyro_frf
    implicit none
    integer(c_int), intent(in) :: nq, nin, nout, nf
    real(c_double), intent(in) :: mq(nq, nq), dq(nq, nq), kq(nq, nq)
    real(c_double), intent(in) :: fin(nq, nin), fout(nq, nout), omega(nf)
    complex(c_double_complex), intent(out) :: h(nout, nin, nf)
    integer(c_int), intent(out) :: info, freq_index
    call gyro_frf(nq, mq, dq, kq, nin, fin, nout, fout, nf, omega, h, info, freq_index)
end subroutine wheelset_frf_c
