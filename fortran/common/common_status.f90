!> The one status vocabulary of railvti's kernels. Implements no equation.
!>
!> Every kernel and shim reports through an integer `info` taking one of the named codes
!> below (one value per code, never two values packed into one integer; where a location
!> matters, such as the offending element or frequency, it goes out in a separate argument).
!> Python translates the codes in one place, railvti/_status.py, which reads the names and
!> messages from here through the shim status_describe_c.
module common_status
    implicit none
    private
    public :: STAT_OK, STAT_NOT_CONVERGED, STAT_NO_CONTACT, STAT_BAD_ARGUMENT, STAT_BAD_HANDLE
    public :: STAT_SIZE_MISMATCH, STAT_NO_MEMORY, STAT_FFTW_PLAN, STAT_SINGULAR
    public :: STAT_NOT_POSITIVE_DEFINITE, STAT_LAPACK, STAT_EIGEN_FAILED, STAT_NOT_FINITE
    public :: STAT_DIVERGED, STAT_GRID_EDGE, STAT_OUTSIDE_TABLE, STAT_BAD_ELEMENT
    public :: STAT_MOTION_TOO_LARGE, STAT_CONTACT_NOT_CONVERGED, STAT_LAST
    public :: status_name, status_message, STATUS_NAME_LEN, STATUS_MESSAGE_LEN

    integer, parameter :: STATUS_NAME_LEN = 32, STATUS_MESSAGE_LEN = 160

    integer, parameter :: STAT_OK = 0
    integer, parameter :: STAT_NOT_CONVERGED = 1
    integer, parameter :: STAT_NO_CONTACT = 2
    integer, parameter :: STAT_BAD_ARGUMENT = 3
    integer, parameter :: STAT_BAD_HANDLE = 4
    integer, parameter :: STAT_SIZE_MISMATCH = 5
    integer, parameter :: STAT_NO_MEMORY = 6
    integer, parameter :: STAT_FFTW_PLAN = 7
    integer, parameter :: STAT_SINGULAR = 8
    integer, parameter :: STAT_NOT_POSITIVE_DEFINITE = 9
    integer, parameter :: STAT_LAPACK = 10
    integer, parameter :: STAT_EIGEN_FAILED = 11
    integer, parameter :: STAT_NOT_FINITE = 12
    integer, parameter :: STAT_DIVERGED = 13
    integer, parameter :: STAT_GRID_EDGE = 14
    integer, parameter :: STAT_OUTSIDE_TABLE = 15
    integer, parameter :: STAT_BAD_ELEMENT = 16
    integer, parameter :: STAT_MOTION_TOO_LARGE = 17
    integer, parameter :: STAT_CONTACT_NOT_CONVERGED = 18
    integer, parameter :: STAT_LAST = 18

contains

    !> The code's name as written in this module (without the STAT_ prefix), or UNKNOWN.
    pure function status_name(code) result(name)
        integer, intent(in) :: code
        character(len=STATUS_NAME_LEN) :: name
        select case (code)
        case (STAT_OK); name = 'OK'
        case (STAT_NOT_CONVERGED); name = 'NOT_CONVERGED'
        case (STAT_NO_CONTACT); name = 'NO_CONTACT'
        case (STAT_BAD_ARGUMENT); name = 'BAD_ARGUMENT'
        case (STAT_BAD_HANDLE); name = 'BAD_HANDLE'
        case (STAT_SIZE_MISMATCH); name = 'SIZE_MISMATCH'
        case (STAT_NO_MEMORY); name = 'NO_MEMORY'
        case (STAT_FFTW_PLAN); name = 'FFTW_PLAN'
        case (STAT_SINGULAR); name = 'SINGULAR'
        case (STAT_NOT_POSITIVE_DEFINITE); name = 'NOT_POSITIVE_DEFINITE'
        case (STAT_LAPACK); name = 'LAPACK'
        case (STAT_EIGEN_FAILED); name = 'EIGEN_FAILED'
        case (STAT_NOT_FINITE); name = 'NOT_FINITE'
        case (STAT_DIVERGED); name = 'DIVERGED'
        case (STAT_GRID_EDGE); name = 'GRID_EDGE'
        case (STAT_OUTSIDE_TABLE); name = 'OUTSIDE_TABLE'
        case (STAT_BAD_ELEMENT); name = 'BAD_ELEMENT'
        case (STAT_MOTION_TOO_LARGE); name = 'MOTION_TOO_LARGE'
        case (STAT_CONTACT_NOT_CONVERGED); name = 'CONTACT_NOT_CONVERGED'
        case default; name = 'UNKNOWN'
        end select
    end function status_name

    !> One sentence saying what the code means, for the exception message.
    pure function status_message(code) result(msg)
        integer, intent(in) :: code
        character(len=STATUS_MESSAGE_LEN) :: msg
        select case (code)
        case (STAT_OK); msg = 'success'
        case (STAT_NOT_CONVERGED)
            msg = 'the iteration limit was reached before the tolerance; the result is the last iterate'
        case (STAT_NO_CONTACT); msg = 'no contact: the gap is open everywhere, zero pressure is the solution'
        case (STAT_BAD_ARGUMENT); msg = 'an argument is outside its valid range'
        case (STAT_BAD_HANDLE); msg = 'no such handle, or the handle belongs to another size or model'
        case (STAT_SIZE_MISMATCH); msg = 'array sizes do not match'
        case (STAT_NO_MEMORY); msg = 'an allocation failed'
        case (STAT_FFTW_PLAN); msg = 'FFTW could not make a plan'
        case (STAT_SINGULAR); msg = 'a linear system is singular'
        case (STAT_NOT_POSITIVE_DEFINITE)
            msg = 'a matrix that must be positive definite is not (Cholesky factorization failed)'
        case (STAT_LAPACK); msg = 'a LAPACK routine reported a failure'
        case (STAT_EIGEN_FAILED); msg = 'the eigen-solver failed or found no converged eigenpair'
        case (STAT_NOT_FINITE); msg = 'a NaN or infinite value appeared in the solution'
        case (STAT_DIVERGED); msg = 'the iteration diverged'
        case (STAT_GRID_EDGE); msg = 'the contact area reaches the edge of the potential contact grid'
        case (STAT_OUTSIDE_TABLE); msg = 'a wheelset left the lateral range of the contact table'
        case (STAT_BAD_ELEMENT); msg = 'a finite element is inverted or has a radius r <= 0'
        case (STAT_MOTION_TOO_LARGE); msg = 'the motion grew beyond its bound (qmax)'
        case (STAT_CONTACT_NOT_CONVERGED)
            msg = 'a BEM contact solver (normal or steady rolling) did not converge'
        case default; msg = 'unknown status code'
        end select
    end function status_message

end module common_status
