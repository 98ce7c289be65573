!> Friction laws with a static and a kinetic coefficient and a slip-velocity
!> dependence ("falling friction"), the element problem of a contact element
!> with such a traction bound, and Polach's closed-form creep force.
!>
!> Laws (v = |slip velocity|, m/s; d = mu_s - mu_k >= 0; v_h > 0 the slip velocity
!> at which the excess d is halved):
!>   FRIC_COULOMB      mu = mu_s at v = 0 (adhesion), mu_k for v > 0 (a jump law;
!>                     mu_s = mu_k is today's constant Coulomb law)
!>   FRIC_LINEAR       mu = mu_k + d max(0, 1 - v / (2 v_h))
!>   FRIC_RATIONAL     mu = mu_k + d / (1 + v / v_h)
!>   FRIC_EXPONENTIAL  mu = mu_k + d exp(-ln2 v / v_h)
!> Polach's law mu = mu0 ((1 - A) exp(-B v) + A) (Polach 2005, Wear 258, eq. 5)
!> is FRIC_EXPONENTIAL with mu_s = mu0, mu_k = A mu0, v_h = ln2 / B.
!>
!> Element problem (contact_rolling's element_solve with a variable bound).
!> With s = s0 + diag(kx, ky) t the slip (creepage units) and t the traction,
!> adhesion s = 0 requires |t_adh| <= g(0), t_adh = -(s0x / kx, s0y / ky);
!> slip is t = -g(lam) e, s = lam e, lam > 0, g(lam) = p mu(V lam), i.e. a root of
!>   F(lam) = (s0x / (lam + kx g))^2 + (s0y / (lam + ky g))^2 - 1.
!> For a constant g, F decreases: one solution. With falling friction
!> d(lam + k g)/dlam = 1 + k p V mu' can be negative: several roots (and adhesion
!> beside slip) may solve the element problem. When k_max p V max|mu'| < 1 F is
!> still monotone (one solution, found by a safeguarded Newton iteration). Else
!> the bracket [lo, hi] that holds every root (|s0| - k_max g(0) <= lam <=
!> |s0| - k_min p mu_k) is scanned in NSCAN steps for sign changes of F.
!> Rules where several solutions exist (friction_law%rule): RULE_SMALLEST takes the
!> solution with the smallest slip, i.e. adhesion whenever it is admissible, else the
!> first root above zero (the branch continuous with adhesion as the creepage grows);
!> RULE_CONTINUOUS the one whose slip is nearest to a given lam_prev: the slip of the
!> current iterate (steady rolling: a fixed point keeps its own branch, so the answer
!> follows the warm start, e.g. along a creep curve) or of the upstream element
!> (FASTSIM). On Hertz patches with steep laws RULE_SMALLEST lets the Gauss-Seidel
!> iteration jump between branches and stall; RULE_CONTINUOUS converges in most cases
!> (docs/contact_friction.md). nsol reports how many solutions the scan found (at its
!> resolution: two roots closer than a scan step are missed), so that a caller can
!> state that the solution is not unique.
!> Implements no Kaiser equation; the laws follow the forms of CONTACT's
!> friction variation (Vollebregt, CONTACT user guide, L-digit 2-5) in SI units.
module contact_friction
    use common_kinds, only: dp, pi
    implicit none
    private
    public :: friction_law, friction_mu, friction_dmu, friction_max_slope, friction_is_constant
    public :: friction_element_solve, polach_force
    public :: FRIC_COULOMB, FRIC_LINEAR, FRIC_RATIONAL, FRIC_EXPONENTIAL, RULE_SMALLEST, RULE_CONTINUOUS

    integer, parameter :: FRIC_COULOMB = 0, FRIC_LINEAR = 1, FRIC_RATIONAL = 2, FRIC_EXPONENTIAL = 3
    integer, parameter :: RULE_SMALLEST = 0, RULE_CONTINUOUS = 1
    !> Element states, as contact_rolling's ST_ADHESION and ST_SLIP.
    integer, parameter :: ST_ADHESION = 1, ST_SLIP = 2
    !> Scan steps over the root bracket when the element problem may have several roots.
    integer, parameter :: NSCAN = 64
    real(dp), parameter :: LN2 = 0.693147180559945309417232121458176568_dp

    !> A friction law: kind, static (v = 0) and kinetic (v -> infinity) coefficients and
    !> the halving slip velocity v_h (m/s, unused by FRIC_COULOMB).
    type :: friction_law
        integer :: kind = FRIC_COULOMB
        real(dp) :: mu_s = 0.0_dp
        real(dp) :: mu_k = 0.0_dp
        real(dp) :: v_h = 1.0_dp
        !> which solution where several exist: RULE_SMALLEST or RULE_CONTINUOUS (module doc)
        integer :: rule = RULE_SMALLEST
    end type friction_law

contains

    !> Friction coefficient at slip velocity v (m/s, >= 0).
    pure real(dp) function friction_mu(law, v) result(mu)
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: v
        real(dp) :: d
        d = law%mu_s - law%mu_k
        select case (law%kind)
        case (FRIC_LINEAR)
            mu = law%mu_k + d * max(0.0_dp, 1.0_dp - 0.5_dp * v / law%v_h)
        case (FRIC_RATIONAL)
            mu = law%mu_k + d / (1.0_dp + v / law%v_h)
        case (FRIC_EXPONENTIAL)
            mu = law%mu_k + d * exp(-LN2 * v / law%v_h)
        case default
            mu = merge(law%mu_s, law%mu_k, v <= 0.0_dp)
        end select
    end function friction_mu

    !> d mu / d v at v > 0, s/m (zero for the jump law away from v = 0).
    pure real(dp) function friction_dmu(law, v) result(dmu)
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: v
        real(dp) :: d
        d = law%mu_s - law%mu_k
        select case (law%kind)
        case (FRIC_LINEAR)
            dmu = merge(-0.5_dp * d / law%v_h, 0.0_dp, v < 2.0_dp * law%v_h)
        case (FRIC_RATIONAL)
            dmu = -d / (law%v_h * (1.0_dp + v / law%v_h)**2)
        case (FRIC_EXPONENTIAL)
            dmu = -d * LN2 / law%v_h * exp(-LN2 * v / law%v_h)
        case default
            dmu = 0.0_dp
        end select
    end function friction_dmu

    !> max over v > 0 of -d mu / d v, s/m (at v = 0 for the smooth laws).
    pure real(dp) function friction_max_slope(law) result(s)
        type(friction_law), intent(in) :: law
        real(dp) :: d
        d = max(0.0_dp, law%mu_s - law%mu_k)
        select case (law%kind)
        case (FRIC_LINEAR)
            s = 0.5_dp * d / law%v_h
        case (FRIC_RATIONAL)
            s = d / law%v_h
        case (FRIC_EXPONENTIAL)
            s = d * LN2 / law%v_h
        case default
            s = 0.0_dp
        end select
    end function friction_max_slope

    !> True when the law is today's constant Coulomb law (mu_s = mu_k).
    pure logical function friction_is_constant(law)
        type(friction_law), intent(in) :: law
        friction_is_constant = law%mu_s == law%mu_k
    end function friction_is_constant

    !> One element's friction problem with s = s0 + diag(kx, ky) t and the bound
    !> g(lam) = bound0 mu(speed lam) / mu_s (bound0 = mu_s p, Pa). Where several solutions
    !> exist: without lam_prev the one with the smallest slip (the module's rule); with
    !> lam_prev (the slip of the current iterate, creepage units) the one whose slip is
    !> nearest to it (the solution continuous with the iterate). stat: ST_ADHESION or
    !> ST_SLIP; lam = |s| (creepage units); nsol: the solutions found (the scan's count
    !> where the problem is not monotone).
    pure subroutine friction_element_solve(law, speed, s0x, s0y, kx, ky, bound0, tx, ty, stat, lam, nsol, lam_prev)
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: speed          ! rolling speed, m/s (slip velocity = speed lam)
        real(dp), intent(in) :: s0x, s0y       ! slip with the element's own traction removed
        real(dp), intent(in) :: kx, ky         ! diagonal self-influence (> 0), 1/Pa
        real(dp), intent(in) :: bound0         ! mu_s p, Pa
        real(dp), intent(out) :: tx, ty
        integer, intent(out) :: stat, nsol
        real(dp), intent(out) :: lam
        real(dp), intent(in), optional :: lam_prev
        real(dp) :: p, gmin, smag, lo, hi, kmin, kmax, g, ex, ey, en, tadh2, step, target
        real(dp) :: brk(NSCAN)
        logical :: monotone, adhesion_ok
        integer :: nroot, k, best

        kmin = min(kx, ky)
        kmax = max(kx, ky)
        smag = sqrt(s0x * s0x + s0y * s0y)
        p = 0.0_dp
        if (law%mu_s > 0.0_dp) p = bound0 / law%mu_s
        gmin = p * law%mu_k
        target = 0.0_dp
        if (present(lam_prev)) target = lam_prev
        tadh2 = (s0x / kx)**2 + (s0y / ky)**2
        adhesion_ok = tadh2 <= bound0 * bound0
        monotone = law%kind /= FRIC_COULOMB .and. kmax * p * speed * friction_max_slope(law) < 1.0_dp
        nsol = 1
        lam = 0.0_dp
        if (p <= 0.0_dp .and. .not. adhesion_ok) then
            tx = 0.0_dp
            ty = 0.0_dp
            stat = ST_SLIP
            lam = smag
            return
        end if
        if (law%kind == FRIC_COULOMB) then
            ! the kinetic slip root exists when |t_adh| > mu_k p; F decreases (constant bound)
            lo = max(0.0_dp, smag - kmax * gmin)
            hi = max(lo, smag - kmin * gmin)
            if (tadh2 > gmin * gmin) then
                if (adhesion_ok) nsol = 2
                call bracketed_root(law, speed, p, s0x, s0y, kx, ky, lo, hi, lam)
                if (adhesion_ok .and. abs(target) <= abs(lam - target)) lam = 0.0_dp
            end if
        else if (monotone) then
            if (.not. adhesion_ok) then
                lo = max(0.0_dp, smag - kmax * bound0)
                hi = max(lo, smag - kmin * gmin)
                call bracketed_root(law, speed, p, s0x, s0y, kx, ky, lo, hi, lam)
            end if
        else
            ! several roots possible: every sign change of F over [0, hi] (NSCAN steps)
            hi = max(0.0_dp, smag - kmin * gmin)
            step = hi / NSCAN
            call scan_roots(law, speed, p, s0x, s0y, kx, ky, 0.0_dp, hi, brk, nroot)
            nsol = nroot + merge(1, 0, adhesion_ok)
            best = 0
            if (.not. adhesion_ok) best = 1
            if (present(lam_prev) .and. nroot > 0) then
                ! the candidate nearest to the iterate's slip (adhesion: lam = 0)
                do k = 1, nroot
                    if (best == 0) then
                        if (abs(brk(k) - 0.5_dp * step - target) < abs(target)) best = k
                    else if (abs(brk(k) - 0.5_dp * step - target) < abs(brk(best) - 0.5_dp * step - target)) then
                        best = k
                    end if
                end do
            end if
            if (best > 0 .and. nroot > 0) then
                call bracketed_root(law, speed, p, s0x, s0y, kx, ky, max(0.0_dp, brk(best) - step), brk(best), lam)
            else if (.not. adhesion_ok) then
                ! no sign change resolved (a root at the bracket's end): the scan's end
                call bracketed_root(law, speed, p, s0x, s0y, kx, ky, max(0.0_dp, hi - step), hi, lam)
            end if
        end if
        if (lam <= 0.0_dp .and. adhesion_ok) then
            tx = -s0x / kx
            ty = -s0y / ky
            stat = ST_ADHESION
            lam = 0.0_dp
            return
        end if
        stat = ST_SLIP
        g = bound_at(law, speed, p, lam)
        ex = s0x / (lam + kx * g)
        ey = s0y / (lam + ky * g)
        en = sqrt(ex * ex + ey * ey)
        if (en > 0.0_dp) then
            ex = ex / en
            ey = ey / en
        end if
        tx = -g * ex
        ty = -g * ey
    end subroutine friction_element_solve

    !> The traction bound g = p mu(speed lam), Pa (the kinetic one for lam > 0 under the jump law).
    pure real(dp) function bound_at(law, speed, p, lam) result(g)
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: speed, p, lam
        if (law%kind == FRIC_COULOMB) then
            g = p * law%mu_k
        else
            g = p * friction_mu(law, speed * lam)
        end if
    end function bound_at

    !> F(lam) of the module doc and its derivative.
    pure subroutine froot(law, speed, p, s0x, s0y, kx, ky, lam, f, fp)
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: speed, p, s0x, s0y, kx, ky, lam
        real(dp), intent(out) :: f, fp
        real(dp) :: g, gp, dx, dy
        g = bound_at(law, speed, p, lam)
        gp = 0.0_dp
        if (law%kind /= FRIC_COULOMB) gp = p * speed * friction_dmu(law, speed * lam)
        dx = 1.0_dp / (lam + kx * g)
        dy = 1.0_dp / (lam + ky * g)
        f = (s0x * dx)**2 + (s0y * dy)**2 - 1.0_dp
        fp = -2.0_dp * ((s0x * dx)**2 * dx * (1.0_dp + kx * gp) + (s0y * dy)**2 * dy * (1.0_dp + ky * gp))
    end subroutine froot

    !> The sign changes of F over [lo, hi] in NSCAN steps: nroot of them, brk(k) the right
    !> end of the step holding the k-th.
    pure subroutine scan_roots(law, speed, p, s0x, s0y, kx, ky, lo, hi, brk, nroot)
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: speed, p, s0x, s0y, kx, ky, lo, hi
        real(dp), intent(out) :: brk(NSCAN)
        integer, intent(out) :: nroot
        real(dp) :: fa, fb, fp, lb
        integer :: k
        nroot = 0
        brk = hi
        call froot(law, speed, p, s0x, s0y, kx, ky, lo, fa, fp)
        do k = 1, NSCAN
            lb = lo + (hi - lo) * k / NSCAN
            call froot(law, speed, p, s0x, s0y, kx, ky, lb, fb, fp)
            if ((fa > 0.0_dp) .neqv. (fb > 0.0_dp)) then
                nroot = nroot + 1
                brk(nroot) = lb
            end if
            fa = fb
        end do
    end subroutine scan_roots

    !> A root of F in [lo, hi] where F changes sign by Newton's method kept in the
    !> bracket (bisection when a step leaves it). Converges quadratically near a simple root.
    pure subroutine bracketed_root(law, speed, p, s0x, s0y, kx, ky, lo, hi, lam)
        type(friction_law), intent(in) :: law
        real(dp), intent(in) :: speed, p, s0x, s0y, kx, ky, lo, hi
        real(dp), intent(out) :: lam
        real(dp) :: a, b, f, fp, dl, scale, lnew, fa
        integer :: it
        a = lo
        b = hi
        call froot(law, speed, p, s0x, s0y, kx, ky, lo, fa, fp)
        scale = abs(hi) + abs(kx * p * law%mu_s) + abs(ky * p * law%mu_s)
        lam = 0.5_dp * (a + b)
        if (b - a <= 1.0e-14_dp * scale) return
        ! start: the root for the bound frozen at the bracket's low end (exact for a constant
        ! bound and kx = ky; within the bracket's first per cent otherwise): 2-4 Newton steps
        lnew = sqrt(s0x * s0x + s0y * s0y) - 0.5_dp * (kx + ky) * bound_at(law, speed, p, a)
        if (lnew > a .and. lnew < b) lam = lnew
        do it = 1, 200
            call froot(law, speed, p, s0x, s0y, kx, ky, lam, f, fp)
            if ((f > 0.0_dp) .eqv. (fa > 0.0_dp)) then
                a = lam
            else
                b = lam
            end if
            if (fp /= 0.0_dp) then
                dl = -f / fp
                lnew = lam + dl
            else
                lnew = a - 1.0_dp   ! force bisection
            end if
            if (lnew <= a .or. lnew >= b) then
                lnew = 0.5_dp * (a + b)
                dl = lnew - lam
            end if
            lam = lnew
            ! quadratic convergence: a step below 1e-10 of the scale leaves ~1e-20
            if (abs(dl) <= 1.0e-10_dp * scale .or. b - a <= 1.0e-14_dp * scale) exit
        end do
    end subroutine bracketed_root

    !> Polach's creep force (Polach 2005, Wear 258, eqs 2-6, longitudinal creep only):
    !>   F = 2 Q mu / pi (kA eps / (1 + (kA eps)^2) + atan(kS eps)),
    !>   eps = 2/3 C pi a^2 b s / (Q mu),  C = 3 G c11 / (8 a),
    !>   mu = mu0 ((1 - A) exp(-B w) + A),  w = V s (slip velocity, m/s).
    !> C is chosen so that F -> (kA + kS)/2 G a b c11 s as s -> 0 (Kalker's linear
    !> theory times Polach's slope reduction). Returns |F| (N) for s = |creepage|.
    pure elemental real(dp) function polach_force(q, a, b, g, c11, mu0, ca, cb, ka, ks, speed, s) result(f)
        real(dp), intent(in) :: q            ! wheel load, N
        real(dp), intent(in) :: a, b         ! semi-axes, m (a along rolling)
        real(dp), intent(in) :: g, c11       ! shear modulus (Pa), Kalker's C11
        real(dp), intent(in) :: mu0, ca, cb  ! mu0, A (1), B (s/m)
        real(dp), intent(in) :: ka, ks       ! reduction factors in adhesion and slip
        real(dp), intent(in) :: speed, s     ! rolling speed (m/s), creepage magnitude
        real(dp) :: mu, c, eps
        f = 0.0_dp
        if (q <= 0.0_dp .or. s == 0.0_dp) return
        mu = mu0 * ((1.0_dp - ca) * exp(-cb * speed * abs(s)) + ca)
        if (mu <= 0.0_dp) return
        c = 3.0_dp * g * c11 / (8.0_dp * a)
        eps = 2.0_dp / 3.0_dp * c * pi * a * a * b * abs(s) / (q * mu)
        f = 2.0_dp * q * mu / pi * (ka * eps / (1.0_dp + (ka * eps)**2) + atan(ks * eps))
    end function polach_force

end module contact_friction
