!> Anderson mixing (Anderson acceleration) of a fixed-point iteration x = G(x). Implements
!> no Kaiser equation: Anderson (1965) in the form of Walker & Ni (2011) eq. 2.1, below.
!>
!> With f_k = G(x_k) - x_k and the differences of the last m iterates
!>   dF = [f_k - f_k-1, ...],  dG = [G(x_k) - G(x_k-1), ...],
!> the next iterate is
!>   x_k+1 = G(x_k) - dG gamma,   gamma = argmin || f_k - dF gamma ||_2
!> (Anderson, J. ACM 12, 1965; the undamped form of Walker & Ni, SIAM J. Numer.
!> Anal. 49, 2011, eq. 2.1 with beta = 1). The small least-squares problem is
!> solved by its normal equations dF^T dF gamma = dF^T f_k with a Tikhonov term
!> of 1e-10 times the largest diagonal entry; a failed or non-finite solve
!> drops the extrapolation for that step (x_k+1 = G(x_k)). With m = 0 the
!> method is the plain iteration x_k+1 = G(x_k). For an affine G with a
!> non-singular I - G' it is, in exact arithmetic and with m at least the
!> number of iterations, equivalent to GMRES on (I - G') x = b.
!>
!> Use: anderson_init(s, x0, m); then per iteration evaluate g = G(s%x) and
!> call anderson_step(s, g), which sets s%x to the next iterate. A caller's
!> safeguard (e.g. when the residual grew) calls anderson_restart(s): the last
!> G value becomes the iterate and the difference history is dropped.
!> The state is the caller's: no module variables.
module common_anderson
    use common_kinds, only: dp
    use common_status, only: STAT_OK
    use common_dense, only: spd_solve_small
    implicit none
    private
    public :: anderson_state, anderson_init, anderson_step, anderson_restart

    !> Relative Tikhonov weight on the normal equations of the least-squares step.
    real(dp), parameter :: REGULARIZATION = 1.0e-10_dp

    !> The mixing history of one fixed-point iteration (vectors of length n).
    type :: anderson_state
        integer :: depth = 0                 ! m, the differences kept (0: plain iteration)
        integer :: naa = 0                   ! differences held now, <= depth
        integer :: slot = 0                  ! column of the newest difference
        logical :: has_prev = .false.        ! fold, gold hold a previous iterate's f, G
        real(dp), allocatable :: x(:)        ! the current iterate x_k
        real(dp), allocatable :: fold(:)     ! f of the previous iterate
        real(dp), allocatable :: gold(:)     ! G of the previous iterate
        real(dp), allocatable :: df(:, :)    ! (n, depth) differences of f, circular by slot
        real(dp), allocatable :: dg(:, :)    ! (n, depth) differences of G, circular by slot
        real(dp), allocatable :: gram(:, :)  ! (depth, depth) dF^T dF by slots, kept across steps
        real(dp), allocatable :: f(:)        ! work: f of the current iterate
    end type anderson_state

contains

    !> Start the iteration at x0 with depth m (m < 0 is taken as 0).
    subroutine anderson_init(s, x0, depth)
        type(anderson_state), intent(out) :: s
        real(dp), intent(in) :: x0(:)
        integer, intent(in) :: depth
        integer :: n
        n = size(x0)
        s%depth = max(depth, 0)
        allocate (s%x(n), s%fold(n), s%gold(n), s%df(n, s%depth), s%dg(n, s%depth), &
                  s%gram(s%depth, s%depth), s%f(n))
        s%x = x0
        s%fold = 0.0_dp
        s%gold = 0.0_dp
        s%naa = 0
        s%slot = 0
        s%has_prev = .false.
    end subroutine anderson_init

    !> One Anderson step: g = G(s%x) in, s%x = the next iterate out. The Gram matrix
    !> dF^T dF keeps its entries across steps: only the newest difference's row is
    !> formed (the same dot products as forming it whole).
    subroutine anderson_step(s, g)
        type(anderson_state), intent(inout) :: s
        real(dp), intent(in) :: g(:)
        real(dp) :: h(s%depth, s%depth), rhs(s%depth), gam(s%depth), reg
        integer :: mk, a, b, stat

        associate (f => s%f)
            f = g - s%x
            if (s%has_prev .and. s%depth > 0) then
                s%slot = mod(s%slot, s%depth) + 1
                s%df(:, s%slot) = f - s%fold
                s%dg(:, s%slot) = g - s%gold
                s%naa = min(s%naa + 1, s%depth)
                do b = 1, s%naa
                    s%gram(s%slot, b) = dot_product(s%df(:, s%slot), s%df(:, b))
                    s%gram(b, s%slot) = s%gram(s%slot, b)
                end do
            end if
            s%has_prev = .true.
            s%fold = f
            s%gold = g
            s%x = g
            mk = s%naa
            if (mk == 0) return
            do b = 1, mk
                rhs(b) = dot_product(s%df(:, b), f)
            end do
        end associate
        h(1:mk, 1:mk) = s%gram(1:mk, 1:mk)
        reg = REGULARIZATION * maxval([(h(a, a), a = 1, mk)])
        do a = 1, mk
            h(a, a) = h(a, a) + reg
        end do
        gam(1:mk) = rhs(1:mk)
        call spd_solve_small(mk, h, gam, stat)
        if (stat == STAT_OK .and. all(gam(1:mk) == gam(1:mk))) then
            do a = 1, mk
                s%x = s%x - gam(a) * s%dg(:, a)
            end do
        end if
    end subroutine anderson_step

    !> Safeguard restart: the last G value (the plain step from the previous
    !> iterate) becomes the iterate and the difference history is dropped; the
    !> next step adds the difference to that previous iterate.
    subroutine anderson_restart(s)
        type(anderson_state), intent(inout) :: s
        if (.not. s%has_prev) return
        s%x = s%gold
        s%naa = 0
        s%slot = 0
    end subroutine anderson_restart

end module common_anderson
