!> Real and integer kinds used by every railvti kernel.
!> Implements no equation.
module common_kinds
    use iso_fortran_env, only: real32, real64, int32, int64
    implicit none
    private
    public :: dp, sp, i4, i8, pi

    integer, parameter :: dp = real64
    !> single precision: only where an approximation is all that is needed (the chord
    !> Jacobian's LU factor of contact_rolling_small::settled_newton)
    integer, parameter :: sp = real32
    integer, parameter :: i4 = int32
    integer, parameter :: i8 = int64
    real(dp), parameter :: pi = 3.14159265358979323846264338327950288_dp
end module common_kinds
