!> f2py shim for FASTSIM (Kalker's simplified theory): plain arrays, explicit
!> shapes, integer info. Argument checks live in railvti.contact.fastsim.
!> Implements no equation (contact_fastsim does: see docs/equations.md).

!> Creep forces and spin moment on an ellipse, for n load cases at once
!> (arrays of creepages and normal forces; one ellipse and one mu).
subroutine fastsim_ellipse_c(n, a, b, g, c11, c22, c23, mu, fn, xi, eta, phi, nx, ny, fx, fy, mz)
    use iso_c_binding, only: c_int, c_double
    use contact_fastsim, only: fastsim_ellipse
    implicit none
    integer(c_int), intent(in) :: n, nx, ny
    real(c_double), intent(in) :: a, b, g, c11, c22, c23, mu
    real(c_double), intent(in) :: fn(n), xi(n), eta(n), phi(n)
    real(c_double), intent(out) :: fx(n), fy(n), mz(n)
    integer :: k
    do k = 1, n
        call fastsim_ellipse(a, b, g, c11, c22, c23, mu, fn(k), xi(k), eta(k), phi(k), nx, ny, &
                             fx(k), fy(k), mz(k))
    end do
end subroutine fastsim_ellipse_c

!> FASTSIM on an ellipse with the fields on the (nx, ny) strip grid.
!> pkind 1 parabolic, 2 Hertz pressure. info as fastsim_ellipse_fields.
subroutine fastsim_fields_c(a, b, g, c11, c22, c23, mu, fn, xi, eta, phi, nx, ny, pkind, &
                            x, y, pn, tx, ty, sx, sy, slip, fx, fy, mz, info)
    use iso_c_binding, only: c_int, c_double
    use contact_fastsim, only: fastsim_ellipse_fields
    implicit none
    real(c_double), intent(in) :: a, b, g, c11, c22, c23, mu, fn, xi, eta, phi
    integer(c_int), intent(in) :: nx, ny, pkind
    real(c_double), intent(out) :: x(nx, ny), y(ny), pn(nx, ny), tx(nx, ny), ty(nx, ny)
    real(c_double), intent(out) :: sx(nx, ny), sy(nx, ny)
    integer(c_int), intent(out) :: slip(nx, ny)
    real(c_double), intent(out) :: fx, fy, mz
    integer(c_int), intent(out) :: info
    integer :: islip(nx, ny), stat
    call fastsim_ellipse_fields(a, b, g, c11, c22, c23, mu, fn, xi, eta, phi, nx, ny, pkind, &
                                x, y, pn, tx, ty, sx, sy, islip, fx, fy, mz, stat)
    slip = islip
    info = stat
end subroutine fastsim_fields_c

!> Strip-wise FASTSIM on a grid with a given normal pressure p (Pa).
!> lmode 1 one flexibility per component, 2 scaled per strip. info as
!> fastsim_strips.
subroutine fastsim_strips_c(nx, ny, dx, dy, x0, y0, p, g, c11, c22, c23, ae, be, mu, &
                            xi, eta, phi, lmode, tx, ty, sx, sy, slip, fx, fy, mz, info)
    use iso_c_binding, only: c_int, c_double
    use contact_fastsim, only: fastsim_strips
    implicit none
    integer(c_int), intent(in) :: nx, ny, lmode
    real(c_double), intent(in) :: dx, dy, x0, y0, g, c11, c22, c23, ae, be, mu, xi, eta, phi
    real(c_double), intent(in) :: p(nx, ny)
    real(c_double), intent(out) :: tx(nx, ny), ty(nx, ny), sx(nx, ny), sy(nx, ny)
    integer(c_int), intent(out) :: slip(nx, ny)
    real(c_double), intent(out) :: fx, fy, mz
    integer(c_int), intent(out) :: info
    integer :: islip(nx, ny), stat
    call fastsim_strips(nx, ny, dx, dy, x0, y0, p, g, c11, c22, c23, ae, be, mu, &
                        xi, eta, phi, lmode, tx, ty, sx, sy, islip, fx, fy, mz, stat)
    slip = islip
    info = stat
end subroutine fastsim_strips_c

!> Kalker's coefficients by the Fortran interpolation (kalker_interp), for n
!> values of a/b at one nu, in the table (ab, tab) of ntab rows (the columns of
!> railvti/data/kalker_table_e3.csv: ab, then C11, C22, C23 at nu = 0, 0.25, 0.5).
!> info: STAT_OK; STAT_BAD_ARGUMENT an a/b outside the table or nu outside
!> [0, 0.5]. ibad: index (1-based) of the first a/b outside the table, 0 if
!> none (then the bad argument is nu).
subroutine fastsim_kalker_c(n, a_over_b, nu, ntab, ab, tab, c11, c22, c23, info, ibad)
    use iso_c_binding, only: c_int, c_double
    use common_status, only: STAT_OK
    use contact_fastsim, only: kalker_interp, kalker_ratio_in_table
    implicit none
    integer(c_int), intent(in) :: n, ntab
    real(c_double), intent(in) :: a_over_b(n), nu, ab(ntab), tab(ntab, 9)
    real(c_double), intent(out) :: c11(n), c22(n), c23(n)
    integer(c_int), intent(out) :: info, ibad
    integer :: k, stat
    info = STAT_OK
    ibad = 0
    do k = 1, n
        call kalker_interp(ab, tab, a_over_b(k), nu, c11(k), c22(k), c23(k), stat)
        if (stat /= STAT_OK) then
            info = stat
            if (ibad == 0 .and. .not. kalker_ratio_in_table(ab, a_over_b(k))) ibad = k
        end if
    end do
end subroutine fastsim_kalker_c
