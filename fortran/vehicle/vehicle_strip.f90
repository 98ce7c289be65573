!> Wheel-rail normal contact of one wheel as a strip potential over the whole rigid
!> interpenetration of wheel and rail: no contact points, branches or look-up jumps.
!>
!> The wheel profile is sampled at a fixed step ds (samples fixed on the wheel); the rail is
!> a C2 cubic spline of its profile on a uniform grid (rail-local y, z down, canted). For the
!> wheelset centre at lateral Y and height Zc above its nominal height (track frame of the
!> rail's element) and the relative roll phi of wheel against rail (left-wheel convention: y
!> to the left, the right wheel is read mirrored), sample j with arms (y0_j, z0_j) about the
!> centre (z0 up, negative) stands at
!>   arm_j = cos(phi) y0_j - sin(phi) z0_j,   zw_j = sin(phi) y0_j + cos(phi) z0_j,
!> over the rail-local y_r = Y + arm_j - offset; its vertical interference is
!>   P_j = h(y_r) - (r_nom + Zc + zw_j),   h = rail_top - z_rail(y_r) the rail's height.
!> The potential (a semi-Hertzian strip model: each strip a Hertzian slice of the local
!> curvatures, summed across the patch) is
!>   V = sum_j c(x_j) cos(delta_j) w_j P_j^2,   c = 3/8 kH(1, rho) sqrt(rho),  x = ln rho,
!> with rho = B/A (clipped to the tabulated range), A = cos(delta - phi) / (2 r_j) the
!> relative curvature along x, B = (kappa_rail - kappa_wheel) / 2 across (kappa_rail from a
!> smoothed C1 table, so that the curvature's rate and with it the force are continuous), delta =
!> -atan(z_rail') the rail's contact angle and w_j = ds (cos(phi) + sin(phi) z'_w) the
!> strip's lateral width. For a parabolic gap B t^2 across the patch (t the arc length,
!> normal approach d) it gives V = (16/15) c d^2.5 / sqrt(B), hence Hertz's N = kH d^1.5
!> exactly, and the strip widths integrate a non-Hertzian gap without any point. The
!> forces are -grad V over (Y, Zc, phi) with every term (the curvatures' change under the
!> moving strip included): exactly conservative. The strips' normal forces N_j = 2 c w_j P_j
!> are split smoothly between the tread and the flange slot by a weight fixed on the wheel,
!> and each slot reports its load-weighted point for the creep forces (vehicle_contact).
!> Implements the semi-Hertzian strip idea of Kik and Piotrowski (1996) and Ayasse and
!> Chollet (2005) as a potential (docs/vehicle.md "Strip contact"); no Kaiser equation.
module vehicle_strip
    use common_kinds, only: dp
    use common_status, only: STAT_OK, STAT_BAD_ARGUMENT
    implicit none
    private
    public :: strip_geometry, strip_set, strip_wheel, strip_props, nso, strip_lin, strip_linearise, &
              strip_extrapolate
    public :: SO_DPSI, SO_XC
    public :: SO_N, SO_V, SO_DY, SO_DZ, SO_DPHI, SO_L, SO_ZA, SO_DELTA, SO_R, SO_X, SO_A, SO_PMAX

    !> Outputs of strip_wheel per slot (1 tread, 2 flange): normal force, potential, its
    !> gradient (Y, Zc, phi), the load-weighted arm l, depth below the centre za, contact
    !> angle, rolling radius, x = ln(B/A), A, the largest interference, the gradient over the
    !> yaw psi and the load-weighted longitudinal position xc of the contact (track x, ahead
    !> of the axle positive).
    integer, parameter :: nso = 14
    integer, parameter :: SO_N = 1, SO_V = 2, SO_DY = 3, SO_DZ = 4, SO_DPHI = 5, SO_L = 6
    integer, parameter :: SO_ZA = 7, SO_DELTA = 8, SO_R = 9, SO_X = 10, SO_A = 11, SO_PMAX = 12
    integer, parameter :: SO_DPSI = 13, SO_XC = 14
    !> Number of dual-number components (value and the derivatives over y, zc, phi, psi).
    integer, parameter :: NDL = 5
    !> The strip constant's factors with their rates (constant_lin): G, dG/dY, dG/dphi, c w,
    !> sin and cos of the contact angle, A, x.
    integer, parameter :: NGL = 8, GL_G = 1, GL_GY = 2, GL_GP = 3, GL_CW = 4, GL_SD = 5, GL_CD = 6, &
                          GL_A = 7, GL_X = 8
    !> Coarse scan (strip_scan): the interference at every SEG-th sample (1.6 mm apart at the
    !> default 0.2 mm step); a segment's samples are evaluated when the bound of its
    !> interference (ends and curvature) is less than MARGIN from contact. The rail's second
    !> derivative is bounded per block of RB grid nodes.
    integer, parameter :: SEG = 8, RB = 16
    real(dp), parameter :: MARGIN = 1.0e-4_dp

    !> Wheel samples ws(7, nw): y0, z0 (arms about the centre, z0 up), r (radius), kappa
    !> (profile curvature, z down), z' (profile slope, z down), the tread slot's weight, and
    !> |kappa| (1 + z'^2)^1.5 (the profile's curvature along y, for the coarse scan).
    !> Rail: z (down) and its second derivative on y = ry0 + (i - 1) rdy, i = 1..nr, the
    !> rail-local y of track y = offset + y; rk, rk1 the smoothed curvature and its rate
    !> (cubic Hermite between the nodes). Ratio table over x = fx0 + (i - 1) fdx (flat at
    !> both ends: a C1 saturation of the curvature ratio): values fv(nf, 6) and second
    !> derivatives fm of c, a1, b1 (Hertz semi-axes for 1 N at A = 1), Kalker's c11, c22, c23.
    type :: strip_geometry
        logical :: on = .false.
        integer :: nw = 0, nr = 0, nf = 0
        real(dp) :: ds = 0.0_dp, rnom = 0.0_dp, ry0 = 0.0_dp, rdy = 1.0_dp, offset = 0.0_dp
        real(dp) :: top = 0.0_dp, fx0 = 0.0_dp, fdx = 1.0_dp
        real(dp), allocatable :: ws(:, :), rz(:), rm(:), rk(:), rk1(:), fv(:, :), fm(:, :)
        !> The coarse scan's bounds: per segment of SEG samples the largest |z_w''| (1.5 x the
        !> samples'), |z_w'| and the least and largest z0; per block of RB rail nodes the
        !> largest |z''| (exact: z'' is linear between nodes); the rail's largest |z'| (1.2 x).
        integer :: nseg = 0
        real(dp) :: rz1max = 0.0_dp
        real(dp), allocatable :: segw(:, :), rbm(:), rb1(:)
        !> Reciprocals and constants of the inner loops (multiplications instead of divisions):
        !> 1 / rdy, rdy^2 / 6, rdy / 6, 1 / fdx, fdx^2 / 6, fdx / 6, and per sample 1 / (2 r).
        real(dp) :: rinv = 1.0_dp, rh26 = 0.0_dp, rh6 = 0.0_dp, finv = 1.0_dp, fh26 = 0.0_dp
        real(dp) :: fh6 = 0.0_dp
        real(dp), allocatable :: hr(:)
    end type strip_geometry

    !> One wheel's strip outputs at a pose and their exact derivatives over the pose
    !> (strip_linearise): the Newton tangent's perturbations read them linearly instead of
    !> evaluating the strips again (vehicle_model%contact_tangent).
    type :: strip_lin
        real(dp) :: pose(4) = 0.0_dp, so(nso, 2) = 0.0_dp, d(nso, 2, 4) = 0.0_dp
    end type strip_lin

contains

    !> Store a strip geometry: info STAT_BAD_ARGUMENT for fewer than 2 samples, grid points or
    !> table rows, a step <= 0 or a non-finite entry.
    pure subroutine strip_set(nw, ws, ds, rnom, nr, ry0, rdy, rz, rm, rk, rk1, offset, top, nf, fx0, &
                              fdx, fv, fm, st, info)
        integer, intent(in) :: nw, nr, nf
        real(dp), intent(in) :: ws(7, nw), ds, rnom, ry0, rdy, rz(nr), rm(nr), rk(nr), rk1(nr)
        real(dp), intent(in) :: offset, top
        real(dp), intent(in) :: fx0, fdx, fv(nf, 6), fm(nf, 6)
        type(strip_geometry), intent(out) :: st
        integer, intent(out) :: info
        info = STAT_BAD_ARGUMENT
        if (nw < 2 .or. nr < 2 .or. nf < 2) return
        if (.not. (ds > 0.0_dp .and. rdy > 0.0_dp .and. fdx > 0.0_dp .and. rnom > 0.0_dp)) return
        if (.not. all(ws(3, :) > 0.0_dp)) return
        if (.not. (all(abs(ws) <= huge(1.0_dp)) .and. all(abs(rz) <= huge(1.0_dp)) &
                   .and. all(abs(rm) <= huge(1.0_dp)) .and. all(abs(fv) <= huge(1.0_dp)) &
                   .and. all(abs(rk) <= huge(1.0_dp)) .and. all(abs(rk1) <= huge(1.0_dp)) &
                   .and. all(abs(fm) <= huge(1.0_dp)))) return
        st%nw = nw
        st%nr = nr
        st%nf = nf
        st%ws = ws
        st%ds = ds
        st%rnom = rnom
        st%ry0 = ry0
        st%rdy = rdy
        st%rz = rz
        st%rm = rm
        st%rk = rk
        st%rk1 = rk1
        st%offset = offset
        st%top = top
        st%fx0 = fx0
        st%fdx = fdx
        st%fv = fv
        st%fm = fm
        st%rinv = 1.0_dp / rdy
        st%rh26 = rdy * rdy / 6.0_dp
        st%rh6 = rdy / 6.0_dp
        st%finv = 1.0_dp / fdx
        st%fh26 = fdx * fdx / 6.0_dp
        st%fh6 = fdx / 6.0_dp
        st%hr = 0.5_dp / ws(3, :)
        call scan_bounds(st)
        st%on = .true.
        info = STAT_OK
    end subroutine strip_set

    !> The coarse scan's bounds of a stored geometry (strip_geometry's segw, rbm, rz1max).
    pure subroutine scan_bounds(st)
        type(strip_geometry), intent(inout) :: st
        real(dp) :: f, f1, f2, f3
        integer :: k, jl, jh, i
        logical :: inside
        st%nseg = (st%nw - 2) / SEG + 1
        allocate (st%segw(4, st%nseg), st%rbm((st%nr - 1) / RB + 1), st%rb1((st%nr - 1) / RB + 1))
        do k = 1, st%nseg
            jl = 1 + (k - 1) * SEG
            jh = min(jl + SEG, st%nw)
            st%segw(1, k) = 1.5_dp * maxval(st%ws(7, max(jl - 1, 1):min(jh + 1, st%nw)))
            st%segw(2, k) = maxval(abs(st%ws(5, jl:jh)))
            st%segw(3, k) = minval(st%ws(2, jl:jh))
            st%segw(4, k) = maxval(st%ws(2, jl:jh))
        end do
        st%rbm = 0.0_dp
        st%rb1 = 0.0_dp
        st%rz1max = 0.0_dp
        do i = 1, st%nr
            k = (i - 1) / RB + 1
            st%rbm(k) = max(st%rbm(k), abs(st%rm(i)))
            call spline_at(st%nr, st%rz, st%rm, st%ry0, st%rdy, st%ry0 + (i - 1) * st%rdy, f, f1, f2, f3, &
                           inside)
            st%rz1max = max(st%rz1max, 1.2_dp * abs(f1))
            ! |z'| within a cell exceeds its nodes' by at most rdy max|z''| / 2
            st%rb1(k) = max(st%rb1(k), abs(f1) + 0.5_dp * st%rdy * max(abs(st%rm(i)), &
                                                                 abs(st%rm(max(i - 1, 1)))))
        end do
    end subroutine scan_bounds

    !> A natural-form cubic spline on a uniform grid (values v, second derivatives m at
    !> x0 + (i - 1) h): value and first three derivatives at x; inside false off the grid.
    pure subroutine spline_at(n, v, m, x0, h, x, f, f1, f2, f3, inside)
        integer, intent(in) :: n
        real(dp), intent(in) :: v(n), m(n), x0, h, x
        real(dp), intent(out) :: f, f1, f2, f3
        logical, intent(out) :: inside
        real(dp) :: s, a, b, hi
        integer :: i
        hi = 1.0_dp / h
        s = (x - x0) * hi
        inside = s >= 0.0_dp .and. s <= real(n - 1, dp)
        f = 0.0_dp
        f1 = 0.0_dp
        f2 = 0.0_dp
        f3 = 0.0_dp
        if (.not. inside) return
        i = min(int(s), n - 2) + 1
        b = s - real(i - 1, dp)
        a = 1.0_dp - b
        f = a * v(i) + b * v(i + 1) + ((a**3 - a) * m(i) + (b**3 - b) * m(i + 1)) * h * h / 6.0_dp
        f1 = (v(i + 1) - v(i)) * hi + (-(3.0_dp * a * a - 1.0_dp) * m(i) &
                                       + (3.0_dp * b * b - 1.0_dp) * m(i + 1)) * h / 6.0_dp
        f2 = a * m(i) + b * m(i + 1)
        f3 = (m(i + 1) - m(i)) * hi
    end subroutine spline_at

    !> Column col of the ratio table at x (clamped to its range; df = d2f = 0 outside).
    pure subroutine ratio_at(st, col, x, f, df, d2f)
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: col
        real(dp), intent(in) :: x
        real(dp), intent(out) :: f, df
        real(dp), intent(out), optional :: d2f
        real(dp) :: xc, s, a, b
        integer :: i
        ! spline_at's arithmetic on the stored grid, with its reciprocals
        xc = min(max(x, st%fx0), st%fx0 + real(st%nf - 1, dp) * st%fdx)
        s = min(max((xc - st%fx0) * st%finv, 0.0_dp), real(st%nf - 1, dp))
        i = min(int(s), st%nf - 2) + 1
        b = s - real(i - 1, dp)
        a = 1.0_dp - b
        f = a * st%fv(i, col) + b * st%fv(i + 1, col) &
            + ((a**3 - a) * st%fm(i, col) + (b**3 - b) * st%fm(i + 1, col)) * st%fh26
        df = (st%fv(i + 1, col) - st%fv(i, col)) * st%finv &
             + (-(3.0_dp * a * a - 1.0_dp) * st%fm(i, col) + (3.0_dp * b * b - 1.0_dp) * st%fm(i + 1, col)) * st%fh6
        if (xc /= x) df = 0.0_dp
        if (present(d2f)) then
            d2f = a * st%fm(i, col) + b * st%fm(i + 1, col)
            if (xc /= x) d2f = 0.0_dp
        end if
    end subroutine ratio_at

    !> Hertz semi-axes for a 1 N load (a1, b1, m N^(-1/3)) and Kalker's c11, c22, c23 of a
    !> slot's point from its x = ln(B/A) and A (lengths scale as A^(-1/3) at a fixed ratio).
    pure subroutine strip_props(st, x, a, props)
        type(strip_geometry), intent(in) :: st
        real(dp), intent(in) :: x, a
        real(dp), intent(out) :: props(5)
        real(dp) :: d
        integer :: col
        do col = 2, 6
            call ratio_at(st, col, x, props(col - 1), d)
        end do
        props(1:2) = props(1:2) * a**(-1.0_dp / 3.0_dp)
    end subroutine strip_props

    !> The vertical interference p of sample j's lowest point (theta = 0) at the pose (-huge
    !> off the rail's grid); cps = cos(psi) shortens the lateral arm.
    pure subroutine interference(st, j, y, zc, cph, sph, cps, p)
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: j
        real(dp), intent(in) :: y, zc, cph, sph, cps
        real(dp), intent(out) :: p
        real(dp) :: zw, s, a, b
        integer :: i
        zw = sph * st%ws(1, j) + cph * st%ws(2, j)
        s = (y + cps * (cph * st%ws(1, j) - sph * st%ws(2, j)) - st%offset - st%ry0) * st%rinv
        p = -huge(1.0_dp)
        if (.not. (s >= 0.0_dp .and. s <= real(st%nr - 1, dp))) return
        ! the rail spline's value (spline_at's, without its derivatives)
        i = min(int(s), st%nr - 2) + 1
        b = s - real(i - 1, dp)
        a = 1.0_dp - b
        p = (st%top - (a * st%rz(i) + b * st%rz(i + 1) &
                       + ((a**3 - a) * st%rm(i) + (b**3 - b) * st%rm(i + 1)) * st%rh26)) &
            - (st%rnom + zc + zw)
    end subroutine interference

    !> The samples the strips of a pose may touch (act): the interference at the ends of each
    !> segment of SEG samples; between them a C2 function rises above the ends' larger value
    !> by at most its second derivative's bound x span^2 / 8, here
    !>   |P''| <= max|z''_rail| (cos + |sin| max|z_w'|)^2 + (|sin| max|z'_rail| + cos) max|z_w''|
    !> over the rail nodes the segment can reach (P = h(y_r(s)) - z_w(s) along the profile).
    !> Under yaw the deepest point of a sample's circle lies ahead of or behind its lowest
    !> point (ring_deepest), deeper by at most r sin(psi)^2 max|z'|^2 / (2 D), D = cos(phi) -
    !> |sin(phi)| max|z'| - r sin(psi)^2 max|z''| (the Newton step's quadratic model, bounded
    !> below by 0.1), added to the bound. A segment with one end off the rail's grid is
    !> evaluated whole (both off: none). act(k): segment k's samples (1 + (k - 1) SEG to
    !> 1 + k SEG, the last one shared with the next segment) are evaluated.
    pure subroutine strip_scan(st, y, zc, cph, sph, cps, sps, act)
        type(strip_geometry), intent(in) :: st
        real(dp), intent(in) :: y, zc, cph, sph, cps, sps
        logical, intent(out) :: act(st%nseg)
        real(dp) :: pe(0:st%nseg), span, ylo, yhi, rmax, m, gain, h1, rw
        integer :: k, jl, jh, il, ih, nb, lo, hi, kb
        do k = 0, st%nseg
            call interference(st, min(1 + k * SEG, st%nw), y, zc, cph, sph, cps, pe(k))
        end do
        act = .false.
        nb = size(st%rbm)
        do k = 1, st%nseg
            jl = 1 + (k - 1) * SEG
            jh = min(jl + SEG, st%nw)
            if (pe(k - 1) == -huge(1.0_dp) .or. pe(k) == -huge(1.0_dp)) then
                if (pe(k - 1) /= pe(k)) act(k) = .true.
                cycle
            end if
            ylo = y - st%offset + cps * (cph * st%ws(1, jl) - max(sph * st%segw(3, k), sph * st%segw(4, k)))
            yhi = y - st%offset + cps * (cph * st%ws(1, jh) - min(sph * st%segw(3, k), sph * st%segw(4, k)))
            il = min(max(int((ylo - st%ry0) * st%rinv), 0), st%nr - 1) / RB + 1
            ih = min(max(int((yhi - st%ry0) * st%rinv) + 1, 0), st%nr - 1) / RB + 1
            lo = min(il, ih)
            hi = max(il, ih)
            ! (maxima by loops: the blocks are few, and maxval's NaN handling costs)
            rmax = st%rbm(lo)
            do kb = lo + 1, hi
                rmax = max(rmax, st%rbm(kb))
            end do
            span = real(jh - jl, dp) * st%ds
            m = rmax * (cph + abs(sph) * st%segw(2, k))**2 + (abs(sph) * st%rz1max + cph) * st%segw(1, k)
            gain = 0.0_dp
            if (sps /= 0.0_dp) then
                ! the lead moves the point laterally by less than a block: one more each side
                h1 = st%rb1(max(lo - 1, 1))
                do kb = max(lo - 1, 1) + 1, min(hi + 1, nb)
                    h1 = max(h1, st%rb1(kb))
                end do
                if (lo > 1) rmax = max(rmax, st%rbm(lo - 1))
                if (hi < nb) rmax = max(rmax, st%rbm(hi + 1))
                rw = -st%segw(3, k)
                gain = 0.5_dp * rw * sps * sps * h1 * h1 &
                       / max(cph - abs(sph) * h1 - rw * sps * sps * rmax, 0.1_dp)
            end if
            if (max(pe(k - 1), pe(k)) + 0.125_dp * m * span * span + gain >= -MARGIN) act(k) = .true.
        end do
    end subroutine strip_scan

    !> The strip potential of one wheel (left-wheel convention) at the centre's lateral
    !> position y, height zc above nominal, relative roll phi and (optional, default 0) yaw
    !> psi of the wheelset against the rail: per slot the outputs SO_*. The partition weights
    !> are fixed on the wheel, so the slots' gradients add up to the gradient of the total
    !> potential.
    pure subroutine strip_wheel(st, y, zc, phi, out, psi)
        type(strip_geometry), intent(in) :: st
        real(dp), intent(in) :: y, zc, phi
        real(dp), intent(out) :: out(nso, 2)
        real(dp), intent(in), optional :: psi
        real(dp) :: cph, sph, cps, sps, acc(nso + 1, 2)
        logical :: act(st%nseg)
        integer :: j, k, jlast
        out = 0.0_dp
        acc = 0.0_dp
        cph = cos(phi)
        sph = sin(phi)
        cps = 1.0_dp
        sps = 0.0_dp
        if (present(psi)) then
            cps = cos(psi)
            sps = sin(psi)
        end if
        call strip_scan(st, y, zc, cph, sph, cps, sps, act)
        ! the active segments' samples in order, each once
        jlast = 0
        do k = 1, st%nseg
            if (.not. act(k)) cycle
            do j = max(1 + (k - 1) * SEG, jlast + 1), min(1 + k * SEG, st%nw)
                call add_strip(st, j, y, zc, cph, sph, cps, sps, acc)
            end do
            jlast = min(1 + k * SEG, st%nw)
        end do
        out = acc(1:nso, :)
        do j = 1, 2
            if (.not. (acc(SO_N, j) > 0.0_dp)) cycle
            out(SO_L:SO_A, j) = acc(SO_L:SO_A, j) / acc(SO_N, j)
            out(SO_XC, j) = acc(SO_XC, j) / acc(SO_N, j)
            ! the mean normal's angle: the load-weighted sin and cos (SO_DELTA, SO_PMAX slots)
            out(SO_DELTA, j) = atan2(acc(SO_DELTA, j), acc(SO_PMAX, j))
            out(SO_PMAX, j) = acc(nso + 1, j)
        end do
    end subroutine strip_wheel

    !> The outputs at pose (y, zc, phi[, psi]) and their exact derivatives over (y, zc, phi,
    !> psi) (the potential's Hessian among them): one scan and one pass over the strips in
    !> forward mode (dual numbers of add_strip_dual), normalised by the quotient rule as
    !> strip_wheel normalises. A pose of 3 entries has psi = 0.
    pure subroutine strip_linearise(st, pose, lin)
        type(strip_geometry), intent(in) :: st
        real(dp), intent(in) :: pose(:)
        type(strip_lin), intent(out) :: lin
        real(dp) :: cph, sph, cps, sps, acc(NDL, nso + 1, 2), s, c, n
        logical :: act(st%nseg)
        integer :: j, i, k, jlast
        lin%pose = 0.0_dp
        lin%pose(1:min(size(pose), 4)) = pose(1:min(size(pose), 4))
        lin%so = 0.0_dp
        lin%d = 0.0_dp
        acc = 0.0_dp
        cph = cos(lin%pose(3))
        sph = sin(lin%pose(3))
        cps = 1.0_dp
        sps = 0.0_dp
        if (size(pose) >= 4) then
            cps = cos(lin%pose(4))
            sps = sin(lin%pose(4))
        end if
        call strip_scan(st, lin%pose(1), lin%pose(2), cph, sph, cps, sps, act)
        jlast = 0
        do k = 1, st%nseg
            if (.not. act(k)) cycle
            do j = max(1 + (k - 1) * SEG, jlast + 1), min(1 + k * SEG, st%nw)
                call add_strip_dual(st, j, lin%pose, cph, sph, cps, sps, acc)
            end do
            jlast = min(1 + k * SEG, st%nw)
        end do
        do j = 1, 2
            lin%so(:, j) = acc(1, 1:nso, j)
            lin%d(:, j, :) = transpose(acc(2:NDL, 1:nso, j))
            n = acc(1, SO_N, j)
            if (.not. (n > 0.0_dp)) cycle
            do i = SO_L, SO_XC
                if (i == SO_DELTA .or. i == SO_PMAX .or. i == SO_DPSI) cycle
                lin%so(i, j) = acc(1, i, j) / n
                lin%d(i, j, :) = (acc(2:NDL, i, j) - lin%so(i, j) * acc(2:NDL, SO_N, j)) / n
            end do
            s = acc(1, SO_DELTA, j)
            c = acc(1, SO_PMAX, j)
            lin%so(SO_DELTA, j) = atan2(s, c)
            lin%d(SO_DELTA, j, :) = (c * acc(2:NDL, SO_DELTA, j) - s * acc(2:NDL, SO_PMAX, j)) / (s * s + c * c)
            lin%so(SO_PMAX, j) = acc(1, nso + 1, j)
            lin%d(SO_PMAX, j, :) = acc(2:NDL, nso + 1, j)
        end do
    end subroutine strip_linearise

    !> The outputs at pose (4 entries) read linearly from lin (first order in the pose's change).
    pure subroutine strip_extrapolate(lin, pose, out)
        type(strip_lin), intent(in) :: lin
        real(dp), intent(in) :: pose(4)
        real(dp), intent(out) :: out(nso, 2)
        integer :: k
        out = lin%so
        do k = 1, 4
            out = out + lin%d(:, :, k) * (pose(k) - lin%pose(k))
        end do
    end subroutine strip_extrapolate

    !> The rail spline (z down) and its first three derivatives at rail-local y (the cell i and
    !> its fraction t for the curvature's cubic); inside false off the grid.
    pure subroutine rail_at(st, yr, z, z1, z2, z3, i, t, inside)
        type(strip_geometry), intent(in) :: st
        real(dp), intent(in) :: yr
        real(dp), intent(out) :: z, z1, z2, z3, t
        integer, intent(out) :: i
        logical, intent(out) :: inside
        real(dp) :: s, ca
        s = (yr - st%ry0) * st%rinv
        inside = s >= 0.0_dp .and. s <= real(st%nr - 1, dp)
        i = 1
        t = 0.0_dp
        z = 0.0_dp
        z1 = 0.0_dp
        z2 = 0.0_dp
        z3 = 0.0_dp
        if (.not. inside) return
        i = min(int(s), st%nr - 2) + 1
        t = s - real(i - 1, dp)
        ca = 1.0_dp - t
        z = ca * st%rz(i) + t * st%rz(i + 1) &
            + ((ca**3 - ca) * st%rm(i) + (t**3 - t) * st%rm(i + 1)) * st%rh26
        z1 = (st%rz(i + 1) - st%rz(i)) * st%rinv + (-(3.0_dp * ca * ca - 1.0_dp) * st%rm(i) &
                                                    + (3.0_dp * t * t - 1.0_dp) * st%rm(i + 1)) * st%rh6
        z2 = ca * st%rm(i) + t * st%rm(i + 1)
        z3 = (st%rm(i + 1) - st%rm(i)) * st%rinv
    end subroutine rail_at

    !> The rail's smoothed curvature (cubic Hermite) and its first two rates in cell i at t.
    pure subroutine curvature_at(st, i, t, kr, dkr, d2kr)
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: i
        real(dp), intent(in) :: t
        real(dp), intent(out) :: kr, dkr
        real(dp), intent(out), optional :: d2kr
        real(dp) :: h
        h = st%rdy
        kr = (2 * t**3 - 3 * t**2 + 1) * st%rk(i) + (t**3 - 2 * t**2 + t) * h * st%rk1(i) &
             + (-2 * t**3 + 3 * t**2) * st%rk(i + 1) + (t**3 - t**2) * h * st%rk1(i + 1)
        dkr = (6 * t**2 - 6 * t) * st%rinv * (st%rk(i) - st%rk(i + 1)) + (3 * t**2 - 4 * t + 1) * st%rk1(i) &
              + (3 * t**2 - 2 * t) * st%rk1(i + 1)
        if (present(d2kr)) d2kr = ((12 * t - 6) * st%rinv * (st%rk(i) - st%rk(i + 1)) + (6 * t - 4) * st%rk1(i) &
                                   + (6 * t - 2) * st%rk1(i + 1)) * st%rinv
    end subroutine curvature_at

    !> The deepest point of sample j's wheel circle under yaw. The circle's point at angle
    !> theta ahead of the lowest point (wheelset frame: x = r sin(theta), y0, z = z0 cos(theta),
    !> rolled by phi about x, yawed by psi about z) stands at track x_c = r s_th c_ps - y1 s_ps,
    !> lateral y_r = y - offset + r s_th s_ps + y1 c_ps and height z2 with
    !>   y1 = y0 c_ph - z0 c_th s_ph,   z2 = y0 s_ph + z0 c_th c_ph;
    !> its interference P(theta) = h(y_r) - (r_nom + zc + z2) is largest where dP/dtheta = 0:
    !> Newton from theta = 0 (where z, z1, z2, z3 hold the rail at the lowest point on entry
    !> and pt0, ptt0 are dP/dtheta and d2P/dtheta2 there: the caller's pre-check has them)
    !> until the point moves less than 1e-13 m (in the time loop one step gets there, the
    !> second confirms it). On return th, its cosine and sine, the point (yr, y1, z2w, xc)
    !> and the rail there (z, z1, z2, z3). Exactly theta = 0 without yaw.
    pure subroutine ring_deepest(st, j, y, cph, sph, cps, sps, pt0, ptt0, th, cth, sth, yr, y1, z2w, xc, &
                                 z, z1, z2, z3, inside)
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: j
        real(dp), intent(in) :: y, cph, sph, cps, sps, pt0, ptt0
        real(dp), intent(out) :: th, cth, sth, y1, z2w, xc
        real(dp), intent(inout) :: yr, z, z1, z2, z3
        logical, intent(out) :: inside
        real(dp) :: r, y0, z0, yt, ytt, zt, ztt, pt, ptt, dth, t
        integer :: it, i
        y0 = st%ws(1, j)
        z0 = st%ws(2, j)
        r = st%ws(3, j)
        th = 0.0_dp
        cth = 1.0_dp
        sth = 0.0_dp
        inside = .true.
        y1 = cph * y0 - sph * z0
        z2w = sph * y0 + cph * z0
        xc = -y1 * sps
        if (sps == 0.0_dp) return
        pt = pt0
        ptt = ptt0
        do it = 1, 8
            if (it > 1) then
                ! dP/dtheta and d2P/dtheta2 with h' = -z1, h'' = -z2
                yt = r * cth * sps + z0 * sth * sph * cps
                ytt = -r * sth * sps + z0 * cth * sph * cps
                zt = -z0 * sth * cph
                ztt = -z0 * cth * cph
                pt = -z1 * yt - zt
                ptt = -z2 * yt * yt - z1 * ytt - ztt
            end if
            if (.not. (ptt < 0.0_dp)) return
            dth = -pt / ptt
            if (abs(dth) * r < 1.0e-13_dp) return
            th = th + dth
            call cos_sin(th, cth, sth)
            ! (the products grouped as add_strip_dual's dual numbers group them)
            y1 = y0 * cph - z0 * (cth * sph)
            z2w = y0 * sph + z0 * (cth * cph)
            xc = r * (sth * cps) - y1 * sps
            yr = y - st%offset + (r * (sth * sps) + y1 * cps)
            call rail_at(st, yr, z, z1, z2, z3, i, t, inside)
            if (.not. inside) return
        end do
    end subroutine ring_deepest

    !> cos(x) and sin(x): for |x| <= 0.02 (the deepest point's angle in the time loop is
    !> ~1e-4) their Taylor series, exact to round-off (the first omitted terms are below
    !> 1e-19 relative), instead of the library's calls.
    pure subroutine cos_sin(x, c, s)
        real(dp), intent(in) :: x
        real(dp), intent(out) :: c, s
        real(dp), parameter :: C6 = 1.0_dp / 6.0_dp, C24 = 1.0_dp / 24.0_dp, C120 = 1.0_dp / 120.0_dp
        real(dp), parameter :: C720 = 1.0_dp / 720.0_dp, C5040 = 1.0_dp / 5040.0_dp, C40320 = 1.0_dp / 40320.0_dp
        real(dp) :: x2
        if (abs(x) <= 0.02_dp) then
            x2 = x * x
            ! (constant reciprocals: the compiler keeps a division by a literal)
            c = 1.0_dp - x2 * (0.5_dp - x2 * (C24 - x2 * (C720 - x2 * C40320)))
            s = x * (1.0_dp - x2 * (C6 - x2 * (C120 - x2 * C5040)))
        else
            c = cos(x)
            s = sin(x)
        end if
    end subroutine cos_sin

    !> Sample j's potential, gradient and load-weighted point quantities added into out: the
    !> interference at the deepest point of the sample's circle (ring_deepest; its gradient
    !> over the pose by the envelope theorem, dP/dtheta = 0 there), the strip's constant G =
    !> c cos(delta) w from the rail under the lowest point (y_r0 = y + arm cos(psi) - offset).
    pure subroutine add_strip(st, j, y, zc, cph, sph, cps, sps, out)
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: j
        real(dp), intent(in) :: y, zc, cph, sph, cps, sps
        real(dp), intent(inout) :: out(nso + 1, 2)
        real(dp) :: arm, zw, z, z1, z2, z3, p, q, cd, sd, ddl, kr, dkr, a, b, x, dxy, dxp, yr
        real(dp) :: c, dc, w, dw, g, dgy, dgp, dpy, dpp, dps, n, e(nso + 1), om, crel, srel, t, ci
        real(dp) :: z1l, z2l, tl, th, y1, z2w, xc, lat, pt, ptt, r, cth, sth
        integer :: k, i, il
        logical :: inside
        arm = cph * st%ws(1, j) - sph * st%ws(2, j)
        zw = sph * st%ws(1, j) + cph * st%ws(2, j)
        yr = y + arm * cps - st%offset
        call rail_at(st, yr, z, z1, z2, z3, i, t, inside)
        if (.not. inside) return
        p = (st%top - z) - (st%rnom + zc + zw)
        z1l = z1
        z2l = z2
        il = i
        tl = t
        y1 = arm
        z2w = zw
        xc = 0.0_dp
        lat = arm
        if (sps /= 0.0_dp) then
            ! the circle's deepest point lies deeper than its lowest by about pt^2 / (-2 ptt)
            ! (Newton's first step): skip the sample when twice that cannot reach the rail
            r = st%ws(3, j)
            pt = -z1 * (r * sps)
            ptt = -z2 * (r * sps)**2 - z1 * (st%ws(2, j) * sph * cps) + st%ws(2, j) * cph
            if (p <= 0.0_dp .and. ptt < 0.0_dp) then
                ! p - pt^2 / ptt <= 0 (ptt < 0), without the division
                if (p * ptt - pt * pt >= 0.0_dp) return
            end if
            call ring_deepest(st, j, y, cph, sph, cps, sps, pt, ptt, th, cth, sth, yr, y1, z2w, xc, &
                              z, z1, z2, z3, inside)
            if (.not. inside) return
            p = (st%top - z) - (st%rnom + zc + z2w)
            lat = r * (sth * sps) + y1 * cps
        end if
        if (p <= 0.0_dp) return
        call curvature_at(st, il, tl, kr, dkr)
        ! the rail's contact angle and (smoothed) curvature under the lowest point, z down, and
        ! their rates along y_r
        q = 1.0_dp + z1l * z1l
        cd = 1.0_dp / sqrt(q)
        sd = -z1l * cd
        ddl = -z2l * (cd * cd)
        ! cos and sin of delta - phi, the rail normal's angle to the wheel's radius
        crel = cd * cph + sd * sph
        srel = sd * cph - cd * sph
        a = crel * st%hr(j)
        b = 0.5_dp * (kr - st%ws(4, j))
        ! x = ln(B/A) and its rates (zero where the table clamps it)
        if (b > 0.0_dp) then
            ci = 1.0_dp / crel
            x = log(b * (2.0_dp * st%ws(3, j)) * ci)
            dxy = 0.5_dp * dkr / b + srel * ci * ddl
            dxp = -srel * ci
        else
            x = st%fx0
            dxy = 0.0_dp
            dxp = 0.0_dp
        end if
        call ratio_at(st, 1, x, c, dc)
        w = st%ds * (cph + sph * st%ws(5, j))
        dw = st%ds * (-sph + cph * st%ws(5, j))
        ! V_j = G P^2 with G = c cos(delta) w
        g = c * cd * w
        dgy = dc * dxy * cd * w - c * sd * ddl * w
        dgp = dc * dxp * cd * w + c * cd * dw
        ! at the deepest point: dP/dY = h' = -z', dP/dZc = -1, dP/dphi = -h' z2 cos(psi) - y1,
        ! dP/dpsi = h' xc; y_r0 moves by -zw cos(psi) dphi - arm sin(psi) dpsi
        dpy = -z1
        dpp = z1 * z2w * cps - y1
        dps = -z1 * xc
        n = 2.0_dp * c * w * p
        e = 0.0_dp
        e(SO_N) = n
        e(SO_V) = g * p * p
        e(SO_DY) = 2.0_dp * g * p * dpy + p * p * dgy
        e(SO_DZ) = -2.0_dp * g * p
        e(SO_DPHI) = 2.0_dp * g * p * dpp + p * p * (-dgy * zw * cps + dgp)
        e(SO_DPSI) = 2.0_dp * g * p * dps + p * p * (-dgy * arm * sps)
        e(SO_L) = n * lat
        e(SO_ZA) = -n * z2w
        e(SO_XC) = n * xc
        ! the slot's contact angle from its load-weighted normal (strip_wheel)
        e(SO_DELTA) = n * sd
        e(SO_PMAX) = n * cd
        e(SO_R) = n * st%ws(3, j)
        e(SO_X) = n * min(max(x, st%fx0), st%fx0 + real(st%nf - 1, dp) * st%fdx)
        e(SO_A) = n * a
        do k = 1, 2
            om = merge(st%ws(6, j), 1.0_dp - st%ws(6, j), k == 1)
            if (om <= 0.0_dp) cycle
            ! (a whole sample, weight 1, saves the products)
            if (om == 1.0_dp) then
                out(:, k) = out(:, k) + e
            else
                out(:, k) = out(:, k) + om * e
            end if
            out(nso + 1, k) = max(out(nso + 1, k), p)
        end do
    end subroutine add_strip

    !> Sample j's contribution to the outputs as dual numbers (value and the derivatives over
    !> y, zc, phi, psi) added into acc(NDL, nso + 1, 2): add_strip's terms differentiated once
    !> more (the rail's third derivative, the curvature's and the ratio table's second
    !> derivatives enter; the deepest point's angle theta moves with the pose as
    !> dtheta/dq = -(d2P/dtheta dq) / (d2P/dtheta2)).
    pure subroutine add_strip_dual(st, j, pose, cph, sph, cps, sps, acc)
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: j
        real(dp), intent(in) :: pose(4), cph, sph, cps, sps
        real(dp), intent(inout) :: acc(NDL, nso + 1, 2)
        real(dp), dimension(NDL) :: pd, cdd, sdd, cphd, sphd, ad, gd
        real(dp), dimension(NDL) :: dgyd, dgpd, nd, gp, pp, xcd, cthd, sthd, y1d, z2wd, latd, xsd
        real(dp), dimension(NDL) :: z1sd, dpyd, dppd, dpsd, xkd
        real(dp) :: arm, zw, yr, z, z1, z2, z3, p, yrg(4), kr, dkr, d2kr, om, e(NDL, nso), gs(3, NGL)
        real(dp) :: t, z1l, z2l, z3l, tl, th, y1, z2w, xc, r, y0, z0, pt, ptt, cth, sth
        real(dp) :: yt, ytt, ztt, thq(4), yq(4), ytq(4), ztq(4)
        integer :: k, i, il
        logical :: inside
        y0 = st%ws(1, j)
        z0 = st%ws(2, j)
        r = st%ws(3, j)
        arm = cph * y0 - sph * z0
        zw = sph * y0 + cph * z0
        yr = pose(1) + arm * cps - st%offset
        call rail_at(st, yr, z, z1, z2, z3, i, t, inside)
        if (.not. inside) return
        p = (st%top - z) - (st%rnom + pose(2) + zw)
        z1l = z1
        z2l = z2
        z3l = z3
        il = i
        tl = t
        th = 0.0_dp
        cth = 1.0_dp
        sth = 0.0_dp
        if (sps /= 0.0_dp) then
            pt = -z1 * (r * sps)
            ptt = -z2 * (r * sps)**2 - z1 * (z0 * sph * cps) + z0 * cph
            if (p <= 0.0_dp .and. ptt < 0.0_dp) then
                ! p - pt^2 / ptt <= 0 (ptt < 0), without the division
                if (p * ptt - pt * pt >= 0.0_dp) return
            end if
            call ring_deepest(st, j, pose(1), cph, sph, cps, sps, pt, ptt, th, cth, sth, yr, y1, z2w, xc, &
                              z, z1, z2, z3, inside)
            if (.not. inside) return
            p = (st%top - z) - (st%rnom + pose(2) + z2w)
        end if
        if (p <= 0.0_dp) return
        ! theta's derivatives over the pose from dP/dtheta = 0 (also without yaw: d/dpsi)
        yt = r * cth * sps + z0 * sth * sph * cps
        ytt = -r * sth * sps + z0 * cth * sph * cps
        ztt = -z0 * cth * cph
        ptt = -z2 * yt * yt - z1 * ytt - ztt
        z2w = sph * y0 + z0 * cth * cph
        yq = [1.0_dp, 0.0_dp, -z2w * cps, r * sth * cps - (y0 * cph - z0 * cth * sph) * sps]
        ytq = [0.0_dp, 0.0_dp, z0 * sth * cph * cps, r * cth * cps - z0 * sth * sph * sps]
        ztq = [0.0_dp, 0.0_dp, z0 * sth * sph, 0.0_dp]
        thq = 0.0_dp
        if (ptt < 0.0_dp) thq = (-z2 * yq * yt - z1 * ytq - ztq) / (-ptt)
        cphd = [cph, 0.0_dp, 0.0_dp, -sph, 0.0_dp]
        sphd = [sph, 0.0_dp, 0.0_dp, cph, 0.0_dp]
        cthd = [cth, -sth * thq]
        sthd = [sth, cth * thq]
        ! the deepest point: y1, z2, its lateral arm, its x and the rail's slope there
        y1d = y0 * cphd - z0 * dmul1(cthd, sph, cph, 4)
        z2wd = y0 * sphd + z0 * dmul1(cthd, cph, -sph, 4)
        latd = r * dmul1(sthd, sps, cps, 5) + dmul1(y1d, cps, -sps, 5)
        xcd = r * dmul1(sthd, cps, -sps, 5) - dmul1(y1d, sps, cps, 5)
        xsd = latd
        xsd(2) = xsd(2) + 1.0_dp
        z1sd = [z1, z2 * xsd(2:NDL)]
        ! P's gradient (envelope theorem) as dual numbers
        dpyd = -z1sd
        dppd = dmul1(dmul(z1sd, z2wd), cps, -sps, 5) - y1d
        dpsd = -dmul(z1sd, xcd)
        pd = [p, dpyd(1), -1.0_dp, dppd(1), dpsd(1)]
        ! G under the lowest point: d y_r0 = dy - zw cos(psi) dphi - arm sin(psi) dpsi
        yrg = [1.0_dp, 0.0_dp, -zw * cps, -arm * sps]
        call curvature_at(st, il, tl, kr, dkr, d2kr)
        call constant_lin(st, j, z1l, z2l, z3l, kr, dkr, d2kr, cph, sph, gs)
        gd = up5(gs(:, GL_G), yrg)
        dgyd = up5(gs(:, GL_GY), yrg)
        dgpd = up5(gs(:, GL_GP), yrg)
        sdd = up5(gs(:, GL_SD), yrg)
        cdd = up5(gs(:, GL_CD), yrg)
        ad = up5(gs(:, GL_A), yrg)
        xkd = up5(gs(:, GL_X), yrg)
        nd = 2.0_dp * dmul(up5(gs(:, GL_CW), yrg), pd)
        gp = dmul(gd, pd)
        pp = dmul(pd, pd)
        e(:, SO_N) = nd
        e(:, SO_V) = dmul(gp, pd)
        e(:, SO_DY) = 2.0_dp * dmul(gp, dpyd) + dmul(pp, dgyd)
        e(:, SO_DZ) = -2.0_dp * gp
        e(:, SO_DPHI) = 2.0_dp * dmul(gp, dppd) + dmul(pp, dgpd - dmul1(dmul1(dgyd, zw, arm, 4), cps, -sps, 5))
        e(:, SO_DPSI) = 2.0_dp * dmul(gp, dpsd) - dmul(pp, dmul1(dmul1(dgyd, arm, -zw, 4), sps, cps, 5))
        e(:, SO_L) = dmul(nd, latd)
        e(:, SO_ZA) = -dmul(nd, z2wd)
        e(:, SO_XC) = dmul(nd, xcd)
        e(:, SO_DELTA) = dmul(nd, sdd)
        e(:, SO_PMAX) = dmul(nd, cdd)
        e(:, SO_R) = nd * r
        e(:, SO_X) = dmul(nd, xkd)
        e(:, SO_A) = dmul(nd, ad)
        do k = 1, 2
            om = merge(st%ws(6, j), 1.0_dp - st%ws(6, j), k == 1)
            if (om <= 0.0_dp) cycle
            if (om == 1.0_dp) then
                acc(:, 1:nso, k) = acc(:, 1:nso, k) + e
            else
                acc(:, 1:nso, k) = acc(:, 1:nso, k) + om * e
            end if
            if (p > acc(1, nso + 1, k)) acc(:, nso + 1, k) = pd
        end do
    end subroutine add_strip_dual

    !> The strip constant's factors of sample j and their rates over the rail-local y of the
    !> lowest point (u) and the roll (phi), gs(:, GL_*) = (value, d/du, d/dphi): G = c cos(delta)
    !> w, its rates dG/dY and dG/dphi of add_strip, c w, sin and cos of the rail's contact angle,
    !> A and x = ln(B/A) as the table clamps it. They depend on the pose through u and phi only
    !> (the rail at u: z1, z2, z3 its slope and next derivatives, kr, dkr, d2kr the smoothed
    !> curvature and its rates), so two partials carry them (add_strip_dual's dual numbers
    !> take them as d/dq = d/du du/dq + d/dphi dphi/dq, up5).
    pure subroutine constant_lin(st, j, z1, z2, z3, kr, dkr, d2kr, cph, sph, gs)
        type(strip_geometry), intent(in) :: st
        integer, intent(in) :: j
        real(dp), intent(in) :: z1, z2, z3, kr, dkr, d2kr, cph, sph
        real(dp), intent(out) :: gs(3, NGL)
        real(dp) :: cd, cdu, sd, sdu, dl, dlu, cr, cru, crp, sr, sru, srp, b, bu, bi, ci, x, xu, xp
        real(dp) :: td, tdu, tdp, dk, dku, dy, dyu, dyp, dx, dxu, dxp, c, dc, d2c, cu, cp, dcu, dcp
        real(dp) :: w, wp, dw, dwp, cc, ccu, ccp, f, fu, fp, g, gu, gp, sw
        cd = 1.0_dp / sqrt(1.0_dp + z1 * z1)
        cdu = -0.5_dp * cd * cd * cd * (2.0_dp * z1 * z2)
        sd = -z1 * cd
        sdu = -(z1 * cdu + cd * z2)
        ! the rate of delta along u (1 / q = cos(delta)^2)
        dl = -z2 * (cd * cd)
        dlu = -(z2 * (2.0_dp * cd * cdu) + cd * cd * z3)
        cr = cd * cph + sd * sph
        cru = cdu * cph + sdu * sph
        crp = -cd * sph + sd * cph
        sr = sd * cph - cd * sph
        sru = sdu * cph - cdu * sph
        srp = -sd * sph - cd * cph
        b = 0.5_dp * kr - 0.5_dp * st%ws(4, j)
        bu = 0.5_dp * dkr
        x = st%fx0
        xu = 0.0_dp
        xp = 0.0_dp
        dy = 0.0_dp
        dyu = 0.0_dp
        dyp = 0.0_dp
        dx = 0.0_dp
        dxu = 0.0_dp
        dxp = 0.0_dp
        if (b > 0.0_dp) then
            bi = 1.0_dp / b
            ci = 1.0_dp / cr
            ! ln(B / A) = ln(B 2 r / crel) and the rates dx/dY, dx/dphi of add_strip
            x = log(b * (2.0_dp * st%ws(3, j)) * ci)
            xu = bu * bi - cru * ci
            xp = -crp * ci
            td = sr * ci
            tdu = (sru - td * cru) * ci
            tdp = (srp - td * crp) * ci
            dk = dkr * bi
            dku = (d2kr - dk * bu) * bi
            dy = 0.5_dp * dk + td * dl
            dyu = 0.5_dp * dku + (td * dlu + dl * tdu)
            dyp = dl * tdp
            dx = -td
            dxu = -tdu
            dxp = -tdp
        end if
        call ratio_at(st, 1, x, c, dc, d2c)
        cu = dc * xu
        cp = dc * xp
        dcu = d2c * xu
        dcp = d2c * xp
        sw = st%ws(5, j)
        w = st%ds * (cph + sph * sw)
        wp = st%ds * (-sph + cph * sw)
        dw = wp
        dwp = st%ds * (-cph - sph * sw)
        ! G = (c cos(delta)) w
        cc = c * cd
        ccu = c * cdu + cd * cu
        ccp = cd * cp
        gs(:, GL_G) = [cc * w, ccu * w, ccp * w + cc * wp]
        ! dG/dY = dc dxy cos(delta) w - c sin(delta) ddelta w
        f = dc * dy
        fu = dc * dyu + dy * dcu
        fp = dc * dyp + dy * dcp
        g = f * cd
        gu = fu * cd + f * cdu
        gp = fp * cd
        gs(:, GL_GY) = [g * w, gu * w, gp * w + g * wp]
        f = c * sd
        fu = c * sdu + sd * cu
        fp = sd * cp
        g = f * dl
        gu = fu * dl + f * dlu
        gp = fp * dl
        gs(:, GL_GY) = gs(:, GL_GY) - [g * w, gu * w, gp * w + g * wp]
        ! dG/dphi = dc dxp cos(delta) w + c cos(delta) dw
        f = dc * dx
        fu = dc * dxu + dx * dcu
        fp = dc * dxp + dx * dcp
        g = f * cd
        gu = fu * cd + f * cdu
        gp = fp * cd
        gs(:, GL_GP) = [g * w + cc * dw, gu * w + ccu * dw, gp * w + g * wp + (ccp * dw + cc * dwp)]
        gs(:, GL_CW) = [c * w, cu * w, cp * w + c * wp]
        gs(:, GL_SD) = [sd, sdu, 0.0_dp]
        gs(:, GL_CD) = [cd, cdu, 0.0_dp]
        gs(:, GL_A) = [cr, cru, crp] * st%hr(j)
        ! x as the table clamps it (its rates zero there)
        gs(:, GL_X) = [x, xu, xp]
        gs(1, GL_X) = min(max(x, st%fx0), st%fx0 + real(st%nf - 1, dp) * st%fdx)
        if (gs(1, GL_X) /= x) gs(2:3, GL_X) = 0.0_dp
    end subroutine constant_lin

    !> A quantity with rates (value, d/du, d/dphi) over the lowest point's rail-local y u and
    !> the roll as a dual number over the pose, yrg = du/d(y, zc, phi, psi).
    pure function up5(g, yrg) result(r)
        real(dp), intent(in) :: g(3), yrg(4)
        real(dp) :: r(NDL)
        r(1) = g(1)
        r(2:NDL) = g(2) * yrg
        r(4) = r(4) + g(3)
    end function up5

    !> Product of two dual numbers (value, gradient(NDL - 1)).
    pure function dmul(a, b) result(r)
        real(dp), intent(in) :: a(NDL), b(NDL)
        real(dp) :: r(NDL)
        r(1) = a(1) * b(1)
        r(2:NDL) = a(1) * b(2:NDL) + b(1) * a(2:NDL)
    end function dmul

    !> Product of a dual number a and one whose derivative has a single non-zero entry:
    !> value c, derivative dc in component k (sines and cosines of the pose's angles, widths).
    pure function dmul1(a, c, dc, k) result(r)
        real(dp), intent(in) :: a(NDL), c, dc
        integer, intent(in) :: k
        real(dp) :: r(NDL)
        r = c * a
        r(k) = r(k) + a(1) * dc
    end function dmul1

end module vehicle_strip
