!> f2py shim for the subsurface stresses: plain arrays, explicit shapes, integer info.
!> Argument checks live in railvti.contact.subsurface.
!> Implements no equation (contact_subsurface does: see docs/equations.md).

!> Stresses (Voigt order xx, yy, zz, yz, xz, xy; Pa, tension positive) at npt points by
!> direct summation. info, ibad as subsurface_points.
subroutine subsurface_points_c(nx, ny, dx, dy, x0, y0, p, qx, qy, nu, npt, xp, yp, zp, sig, info, ibad)
    use iso_c_binding, only: c_int, c_double
    use contact_subsurface, only: subsurface_points
    implicit none
    integer(c_int), intent(in) :: nx, ny, npt
    real(c_double), intent(in) :: dx, dy, x0, y0, nu
    real(c_double), intent(in) :: p(nx, ny), qx(nx, ny), qy(nx, ny), xp(npt), yp(npt), zp(npt)
    real(c_double), intent(out) :: sig(npt, 6)
    integer(c_int), intent(out) :: info, ibad
    integer :: stat, kbad
    call subsurface_points(nx, ny, dx, dy, x0, y0, p, qx, qy, nu, npt, xp, yp, zp, sig, stat, kbad)
    info = stat
    ibad = kbad
end subroutine subsurface_points_c

!> Stresses at all element centres on nz planes of depth z (FFT per depth). info, ibad as
!> subsurface_planes.
subroutine subsurface_planes_c(nx, ny, dx, dy, p, qx, qy, nu, nz, z, sig, info, ibad)
    use iso_c_binding, only: c_int, c_double
    use contact_subsurface_planes, only: subsurface_planes
    implicit none
    integer(c_int), intent(in) :: nx, ny, nz
    real(c_double), intent(in) :: dx, dy, nu, p(nx, ny), qx(nx, ny), qy(nx, ny), z(nz)
    real(c_double), intent(out) :: sig(nx, ny, nz, 6)
    integer(c_int), intent(out) :: info, ibad
    integer :: stat, kbad
    call subsurface_planes(nx, ny, dx, dy, p, qx, qy, nu, nz, z, sig, stat, kbad)
    info = stat
    ibad = kbad
end subroutine subsurface_planes_c

!> Principal stresses (descending), von Mises and Tresca (s1 - s3) of n stress states.
subroutine subsurface_invariants_c(n, sig, prin, vm, tresca)
    use iso_c_binding, only: c_int, c_double
    use contact_subsurface, only: stress_invariants
    implicit none
    integer(c_int), intent(in) :: n
    real(c_double), intent(in) :: sig(n, 6)
    real(c_double), intent(out) :: prin(n, 3), vm(n), tresca(n)
    call stress_invariants(n, sig, prin, vm, tresca)
end subroutine subsurface_invariants_c
