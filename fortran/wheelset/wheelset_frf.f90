!> Frequency response of a linear gyroscopic system in modal coordinates,
!>     (-omega^2 M + i omega D + K) q = F,   D = G + C (gyroscopic + damping),
!> as met by the rotating wheelset in its axle-fixed (non-rotating) frame.
!> Implements the frequency response of Kaiser eq. 11 (railvti.wheelset.model builds the model).
module wheelset_frf
    use common_kinds, only: dp
    use common_lapack, only: zgesv
    use common_status, only: STAT_OK, STAT_SINGULAR
    implicit none
    private
    public :: gyro_frf


contains

    !> h(o, i, f) = fout(:, o)^T q, with q the response to the generalized force
    !> fin(:, i) at circular frequency omega(f) (rad/s).
    !> info: STAT_OK, or STAT_SINGULAR: the dynamic matrix is singular at omega(freq_index)
    !> (freq_index = 0 unless STAT_SINGULAR; h is zero from that frequency on).
    subroutine gyro_frf(nq, mq, dq, kq, nin, fin, nout, fout, nf, omega, h, info, freq_index)
        integer, intent(in) :: nq, nin, nout, nf
        real(dp), intent(in) :: mq(nq, nq), dq(nq, nq), kq(nq, nq)
        real(dp), intent(in) :: fin(nq, nin), fout(nq, nout), omega(nf)
        complex(dp), intent(out) :: h(nout, nin, nf)
        integer, intent(out) :: info, freq_index
        complex(dp), allocatable :: a(:, :), b(:, :)
        integer, allocatable :: ipiv(:)
        integer :: f, stat
        real(dp) :: w
        info = STAT_OK
        freq_index = 0
        h = (0.0_dp, 0.0_dp)
        allocate (a(nq, nq), b(nq, nin), ipiv(nq))
        do f = 1, nf
            w = omega(f)
            a = cmplx(kq - w * w * mq, w * dq, kind=dp)
            b = cmplx(fin, 0.0_dp, kind=dp)
            call zgesv(nq, nin, a, nq, ipiv, b, nq, stat)
            if (stat /= 0) then      ! zgesv: stat > 0, an exactly zero pivot
                info = STAT_SINGULAR
                freq_index = f
                return
            end if
            h(:, :, f) = matmul(transpose(cmplx(fout, 0.0_dp, kind=dp)), b)
        end do
    end subroutine gyro_frf

end module wheelset_frf
