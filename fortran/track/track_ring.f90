!> The ring track: two rails in trigonometric series along x on n_sl rigid sleepers through
!> pads spread over the rail seat (length lp, the foot's width), sleepers on ballast.
!> Periodic sleepers couple a rail wave number k only with k' = +-k + m n_sl, so the modes
!> split into independent groups j = 0..n_sl/2 (Bloch-Floquet / cyclic symmetry). In group
!> j a sleeper pattern is q_s = A cos(theta_s) + B sin(theta_s), theta_s = 2 pi j s / n_sl,
!> and every rail function at x_s + xi is cos(theta_s) F(xi) + sin(theta_s) G(xi); the sum
!> over sleepers of two such products is s_j (F F' + G G'), s_j = n_sl/2 (n_sl for j = 0 and
!> j = n_sl/2, where G drops out).
!> Rail basis functions b: wave number kap, family fam (0: k = 0, all components constant;
!> 1: u_eta, u_zeta ~ cos, u_x ~ sin; 2: u_eta, u_zeta ~ sin, u_x ~ -cos), sign sgn (k = sgn j
!> mod n_sl), rail 1 or 2, generalized mass 1 and stiffness om2.
!> Implements Kaiser eq. 12 (the rails as trigonometric series along the ring; number
!> inferred, docs/equations.md) with eq. 13's two families.
module track_ring
    use common_kinds, only: dp
    use common_eigen, only: eig_std_range
    use common_status, only: STAT_OK, STAT_SIZE_MISMATCH, STAT_EIGEN_FAILED
    implicit none
    private
    public :: ring_group_modes, ring_eval_x, ring_frf

contains

    !> Trig factors F, G of component c (1 x, 2 eta, 3 zeta) of a basis function at offset xi.
    pure subroutine trig_fg(fam, sgn, c, kx, fv, gv)
        integer, intent(in) :: fam, sgn, c
        real(dp), intent(in) :: kx
        real(dp), intent(out) :: fv, gv
        select case (fam)
        case (1)
            if (c == 1) then
                fv = sin(kx); gv = sgn * cos(kx)
            else
                fv = cos(kx); gv = -sgn * sin(kx)
            end if
        case (2)
            if (c == 1) then
                fv = -cos(kx); gv = sgn * sin(kx)
            else
                fv = sin(kx); gv = sgn * cos(kx)
            end if
        case default
            fv = 1.0_dp; gv = 0.0_dp
        end select
    end subroutine trig_fg

    !> Value of component c (1 x, 2 eta, 3 zeta, 4 roll) of basis function's trig factor at x.
    pure real(dp) function trig_at(fam, c, kx) result(t)
        integer, intent(in) :: fam, c
        real(dp), intent(in) :: kx
        select case (fam)
        case (1)
            if (c == 1) then
                t = sin(kx)
            else
                t = cos(kx)
            end if
        case (2)
            if (c == 1) then
                t = -cos(kx)
            else
                t = sin(kx)
            end if
        case default
            t = 1.0_dp
        end select
    end function trig_at

    !> Modes of cyclic group j. tr(np, 3, nb): rail-local displacements (x, eta, zeta) of each
    !> basis function at the pad points eta_p (weights w_p, along the foot underside);
    !> xi(nq), w_xi(nq): quadrature over the pad length. kpad, cpad: pad stiffness and damping
    !> per unit area (x, eta, zeta), N/m^3, N s/m^3. y0, beta: lateral position (m) and cant
    !> angle (rad) of rails 1 and 2. Sleeper: ms (mass, mass, roll inertia), kb, cb ballast
    !> (lateral, vertical, roll) per sleeper. eta_rail: rail loss factor.
    !> Output: ntot = nb + 3 nsp modes (nsp = 2 sleeper patterns A, B, or 1), lam = omega^2,
    !> v(ntot, ntot) physical coordinates (rail basis amplitudes, then sleeper v, w, theta
    !> of A, then B), cmod: modal viscous damping (diagonal of V^T C V plus the rail loss
    !> factor as equivalent viscous damping at each mode's frequency).
    !> info: STAT_OK; STAT_SIZE_MISMATCH (ntot /= nb + 3 nsp); the eigen-solver's STAT_ code
    !> (or STAT_EIGEN_FAILED if it found fewer than ntot pairs), LAPACK's info in lapack_info.
    subroutine ring_group_modes(nb, om2, kap, fam, sgn, rail, np, tr, eta_p, w_p, nq, xi, w_xi, &
                                kpad, cpad, y0, beta, ms, kb, cb, nsl, j, eta_rail, ntot, &
                                lam, v, cmod, info, lapack_info)
        integer, intent(in) :: nb, np, nq, nsl, j, ntot
        integer, intent(in) :: fam(nb), sgn(nb), rail(nb)
        real(dp), intent(in) :: om2(nb), kap(nb), tr(np, 3, nb), eta_p(np), w_p(np)
        real(dp), intent(in) :: xi(nq), w_xi(nq), kpad(3), cpad(3), y0(2), beta(2)
        real(dp), intent(in) :: ms(3), kb(3), cb(3), eta_rail
        real(dp), intent(out) :: lam(ntot), v(ntot, ntot), cmod(ntot)
        integer, intent(out) :: info, lapack_info
        real(dp), allocatable :: fq(:, :, :), gq(:, :, :), gp(:, :, :), xf(:, :), kt(:, :), ct(:, :)
        real(dp), allocatable :: rs(:, :, :, :), a(:, :), sc(:), fsum(:, :), gsum(:, :), rp(:, :, :)
        real(dp) :: sj, ca, s, c, zp, yp, rrr(3, 3)
        integer :: nsp, b, bb, q, cc, p, d, dd, rho, nsd, i, nev
        logical :: use_g

        info = STAT_OK
        lapack_info = 0
        use_g = (j /= 0 .and. 2 * j /= nsl)
        nsp = merge(2, 1, use_g)
        nsd = 3 * nsp
        if (ntot /= nb + nsd) then
            info = STAT_SIZE_MISMATCH
            return
        end if
        sj = merge(0.5_dp * nsl, real(nsl, dp), use_g)
        ca = 1.0_dp / sqrt(sj)
        allocate (fq(nq, 3, nb), gq(nq, 3, nb), gp(nb, nb, 3), xf(nb, nb), kt(ntot, ntot), &
                  ct(ntot, ntot), a(ntot, ntot), sc(ntot), fsum(3, nb), gsum(3, nb), &
                  rs(np, 3, 3, 2), rp(3, nb, 3))
        do b = 1, nb
            do cc = 1, 3
                do q = 1, nq
                    call trig_fg(fam(b), sgn(b), cc, kap(b) * xi(q), fq(q, cc, b), gq(q, cc, b))
                end do
                fsum(cc, b) = sum(w_xi * fq(:, cc, b))
                gsum(cc, b) = sum(w_xi * gq(:, cc, b))
            end do
        end do
        ! Sleeper motion (v, w, theta) -> rail-local (x, eta, zeta) at pad point p of rail rho:
        ! u_y = v - theta z, u_z = w + theta y about the track centre at seat level.
        do rho = 1, 2
            c = cos(beta(rho)); s = sin(beta(rho))
            do p = 1, np
                yp = y0(rho) + eta_p(p) * c
                zp = eta_p(p) * s
                rs(p, 1, :, rho) = 0
                rs(p, 2, :, rho) = [c, s, -zp * c + yp * s]
                rs(p, 3, :, rho) = [-s, c, zp * s + yp * c]
            end do
        end do
        ! Cross-section products over the foot: gp(b, b', c) = sum_p w_p tr tr' (same rail).
        do cc = 1, 3
            do bb = 1, nb
                do b = 1, nb
                    if (rail(b) == rail(bb)) then
                        gp(b, bb, cc) = sum(w_p * tr(:, cc, b) * tr(:, cc, bb))
                    else
                        gp(b, bb, cc) = 0
                    end if
                end do
            end do
            ! rail-sleeper: rp(c, b, d) = sum_p w_p tr(p, c, b) R(p, c, d)
            do b = 1, nb
                do d = 1, 3
                    rp(cc, b, d) = sum(w_p * tr(:, cc, b) * rs(:, cc, d, rail(b)))
                end do
            end do
        end do
        do i = 1, 2
            kt = 0
            ! rail-rail
            do cc = 1, 3
                if (use_g) then
                    xf = matmul(transpose(fq(:, cc, :) * spread(w_xi, 2, nb)), fq(:, cc, :)) &
                       + matmul(transpose(gq(:, cc, :) * spread(w_xi, 2, nb)), gq(:, cc, :))
                else
                    xf = matmul(transpose(fq(:, cc, :) * spread(w_xi, 2, nb)), fq(:, cc, :))
                end if
                kt(1:nb, 1:nb) = kt(1:nb, 1:nb) + sj * stiff(i, cc) * xf * gp(:, :, cc)
                ! rail-sleeper (A with F, B with G), relative displacement rail - sleeper
                do b = 1, nb
                    do d = 1, 3
                        kt(b, nb + d) = kt(b, nb + d) - sj * ca * stiff(i, cc) * fsum(cc, b) * rp(cc, b, d)
                        if (use_g) kt(b, nb + 3 + d) = kt(b, nb + 3 + d) &
                            - sj * ca * stiff(i, cc) * gsum(cc, b) * rp(cc, b, d)
                    end do
                end do
                ! sleeper-sleeper: one sleeper's pads (both rails)
                do rho = 1, 2
                    do d = 1, 3
                        do dd = 1, 3
                            rrr(d, dd) = sum(w_p * rs(:, cc, d, rho) * rs(:, cc, dd, rho)) * sum(w_xi) &
                                         * stiff(i, cc)
                        end do
                    end do
                    kt(nb + 1:nb + 3, nb + 1:nb + 3) = kt(nb + 1:nb + 3, nb + 1:nb + 3) + rrr
                    if (use_g) kt(nb + 4:nb + 6, nb + 4:nb + 6) = kt(nb + 4:nb + 6, nb + 4:nb + 6) + rrr
                end do
            end do
            do b = 1, nb
                do d = nb + 1, ntot
                    kt(d, b) = kt(b, d)
                end do
            end do
            do d = 1, nsd
                kt(nb + d, nb + d) = kt(nb + d, nb + d) + merge(kb(mod(d - 1, 3) + 1), cb(mod(d - 1, 3) + 1), i == 1)
            end do
            if (i == 1) then
                do b = 1, nb
                    kt(b, b) = kt(b, b) + om2(b)
                end do
                a = kt
            else
                ct = kt
            end if
        end do
        ! Mass: 1 for rail basis functions, ms for the sleeper DOFs -> scale to M = I.
        sc(1:nb) = 1
        do d = 1, nsd
            sc(nb + d) = 1.0_dp / sqrt(ms(mod(d - 1, 3) + 1))
        end do
        do d = 1, ntot
            a(:, d) = a(:, d) * sc * sc(d)
        end do
        call eig_std_range(ntot, a, -huge(1.0_dp), huge(1.0_dp), nev, lam, v, info, lapack_info)
        if (info == STAT_OK .and. nev /= ntot) info = STAT_EIGEN_FAILED
        if (info /= STAT_OK) return
        do d = 1, ntot
            v(:, d) = v(:, d) * sc
        end do
        a = matmul(ct, v)
        do d = 1, ntot
            cmod(d) = dot_product(v(:, d), a(:, d)) &
                + eta_rail * sum(v(1:nb, d)**2 * om2) / sqrt(max(lam(d), tiny(1.0_dp)))
        end do

    contains

        pure real(dp) function stiff(which, comp)
            integer, intent(in) :: which, comp
            if (which == 1) then
                stiff = kpad(comp)
            else
                stiff = cpad(comp)
            end if
        end function stiff

    end subroutine ring_group_modes

    !> Rail-head values of every mode at x: psi(c, r), c = 1 x, 2 eta, 3 zeta, 4 roll (rail-
    !> local), for the observation traces obs(4, nbt) of the basis functions on rail rho.
    !> Groups g = 1..ng: basis functions bpos(g)+1..bpos(g+1), modes mpos(g)+1..mpos(g+1),
    !> eigenvectors vflat(vpos(g)+1 ...) column-major (ntot_g x ntot_g).
    subroutine ring_eval_x(ng, bpos, mpos, vpos, nbt, kap, fam, rail, obs, nvf, vflat, ntt, x, &
                           rho, psi)
        integer, intent(in) :: ng, nbt, nvf, ntt, rho
        integer, intent(in) :: bpos(ng + 1), mpos(ng + 1), vpos(ng + 1), fam(nbt), rail(nbt)
        real(dp), intent(in) :: kap(nbt), obs(4, nbt), vflat(nvf), x
        real(dp), intent(out) :: psi(4, ntt)
        real(dp), allocatable :: t(:, :)
        integer :: g, nb, nt, b, c, r, off
        psi = 0
        do g = 1, ng
            nb = bpos(g + 1) - bpos(g)
            nt = mpos(g + 1) - mpos(g)
            allocate (t(4, nb))
            do b = 1, nb
                if (rail(bpos(g) + b) /= rho) then
                    t(:, b) = 0
                    cycle
                end if
                do c = 1, 4
                    t(c, b) = obs(c, bpos(g) + b) * trig_at(fam(bpos(g) + b), c, kap(bpos(g) + b) * x)
                end do
            end do
            do r = 1, nt
                off = vpos(g) + (r - 1) * nt
                psi(:, mpos(g) + r) = matmul(t, vflat(off + 1:off + nb))
            end do
            deallocate (t)
        end do
    end subroutine ring_eval_x

    !> h(f) = sum_r a(r) / (lam(r) - w^2 + i w c(r)), w = 2 pi f; real and imaginary parts.
    subroutine ring_frf(ntt, lam, cm, a, nf, freq, hr, hi)
        integer, intent(in) :: ntt, nf
        real(dp), intent(in) :: lam(ntt), cm(ntt), a(ntt), freq(nf)
        real(dp), intent(out) :: hr(nf), hi(nf)
        real(dp), parameter :: twopi = 6.283185307179586476925286766559_dp
        complex(dp) :: h
        real(dp) :: w
        integer :: i, r
        do i = 1, nf
            w = twopi * freq(i)
            h = (0.0_dp, 0.0_dp)
            do r = 1, ntt
                h = h + a(r) / cmplx(lam(r) - w * w, w * cm(r), dp)
            end do
            hr(i) = real(h)
            hi(i) = aimag(h)
        end do
    end subroutine ring_frf

end module track_ring
