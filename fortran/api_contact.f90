!> f2py shim for the contact kernels: plain arrays, explicit shapes, integer info.
!> Argument checks live in Python (railvti.contact); info < 0 here names the
!> offending argument by position, info > 0 is a solver status.

!> Influence coefficients of one kernel (1 zz, 2 xx, 3 yy, 4 xy) for all
!> offsets of an nx x ny grid, circular layout on the 2nx x 2ny padded grid.
subroutine influence_field_c(kernel, nx, ny, dx, dy, g, nu, c, info)
    use iso_c_binding, only: c_int, c_double
    use contact_influence, only: influence_field
    implicit none
    integer(c_int), intent(in) :: kernel, nx, ny
    real(c_double), intent(in) :: dx, dy, g, nu
    real(c_double), intent(out) :: c(2 * nx, 2 * ny)
    integer(c_int), intent(out) :: info
    info = 0
    if (kernel < 1 .or. kernel > 4) then
        info = -1
        return
    end if
    call influence_field(kernel, nx, ny, dx, dy, g, nu, c)
end subroutine influence_field_c

!> u = A_kernel * q by FFT (method 1) or direct summation (method 2).
subroutine convolve_c(kernel, method, nx, ny, dx, dy, g, nu, q, u, info)
    use iso_c_binding, only: c_int, c_double
    use contact_influence, only: influence_field
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
    info = 0
    allocate (c(0:2 * nx - 1, 0:2 * ny - 1, 1))
    call influence_field(kernel, nx, ny, dx, dy, g, nu, c(:, :, 1))
    if (method == 2) then
        call direct_apply(nx, ny, c(:, :, 1), q, u)
    else
        call conv_init(plan, nx, ny, c, stat)
        if (stat /= 0) then
            info = stat
            return
        end if
        call conv_apply(plan, 1, q, u)
        call conv_free(plan)
    end if
end subroutine convolve_c

!> Time of nrep FFT products on an nx x ny grid is measured in Python around
!> this call; it applies the Boussinesq product nrep times to q.
subroutine convolve_repeat_c(nx, ny, dx, dy, g, nu, nrep, q, u, info)
    use iso_c_binding, only: c_int, c_double
    use contact_influence, only: influence_field, KERNEL_ZZ
    use contact_convolution, only: conv_plan, conv_init, conv_apply, conv_free
    implicit none
    integer(c_int), intent(in) :: nx, ny, nrep
    real(c_double), intent(in) :: dx, dy, g, nu
    real(c_double), intent(in) :: q(nx, ny)
    real(c_double), intent(out) :: u(nx, ny)
    integer(c_int), intent(out) :: info
    real(c_double), allocatable :: c(:, :, :)
    type(conv_plan) :: plan
    integer :: k
    allocate (c(0:2 * nx - 1, 0:2 * ny - 1, 1))
    call influence_field(KERNEL_ZZ, nx, ny, dx, dy, g, nu, c(:, :, 1))
    call conv_init(plan, nx, ny, c, info)
    if (info /= 0) return
    do k = 1, nrep
        call conv_apply(plan, 1, q, u)
    end do
    call conv_free(plan)
end subroutine convolve_repeat_c

!> Normal contact on an nx x ny grid with gap h (m).
!> control: 1 prescribed force fn_in (N), 2 prescribed approach approach_in (m).
!> method: 1 FFT-preconditioned projected CG, 2 projected Gauss-Seidel
!> (relaxation omega), 3 projected CG without preconditioner.
!> p: warm start on entry (all zero for a cold start), pressure (Pa) on exit.
!> info: 0 converged, 1 not converged, 2 no contact, <0 internal failure.
subroutine normal_solve_c(nx, ny, h, dx, dy, g, nu, control, method, tol, max_iter, omega, &
                          fn_in, approach_in, p, fn_out, approach_out, iters, nprod, resid, info)
    use iso_c_binding, only: c_int, c_double
    use contact_influence, only: influence_field, KERNEL_ZZ
    use contact_convolution, only: conv_plan, conv_init, conv_free, conv_init_precond
    use contact_normal, only: normal_cg, normal_gs
    implicit none
    integer(c_int), intent(in) :: nx, ny, control, method, max_iter
    real(c_double), intent(in) :: h(nx, ny), dx, dy, g, nu, tol, omega, fn_in, approach_in
    real(c_double), intent(inout) :: p(nx, ny)
    real(c_double), intent(out) :: fn_out, approach_out, resid
    integer(c_int), intent(out) :: iters, nprod, info
    real(c_double), allocatable :: c(:, :, :)
    type(conv_plan) :: plan
    integer :: it, np, stat

    iters = 0
    nprod = 0
    resid = 0.0_c_double
    fn_out = fn_in
    approach_out = approach_in
    allocate (c(0:2 * nx - 1, 0:2 * ny - 1, 1))
    call influence_field(KERNEL_ZZ, nx, ny, dx, dy, g, nu, c(:, :, 1))
    call conv_init(plan, nx, ny, c, stat)
    if (stat /= 0) then
        info = stat
        return
    end if
    if (method == 2) then
        call normal_gs(plan, 1, c(:, :, 1), h, dx * dy, control, fn_out, approach_out, omega, &
                       tol, max_iter, p, it, resid, stat)
        np = 0
    else
        if (method == 1) then
            call conv_init_precond(plan, g, nu, dx, dy, stat)
            if (stat /= 0) then
                info = stat
                return
            end if
        end if
        call normal_cg(plan, 1, h, dx * dy, control, fn_out, approach_out, tol, max_iter, &
                       p, it, np, resid, stat)
    end if
    call conv_free(plan)
    iters = it
    nprod = np
    info = stat
end subroutine normal_solve_c
