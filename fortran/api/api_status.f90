!> f2py shim for the status vocabulary of common_status. Implements no equation.

!> Name and message of status code `code`; nlast is the largest code defined.
subroutine status_describe_c(code, name, msg, nlast)
    use iso_c_binding, only: c_int
    use common_status, only: status_name, status_message, STAT_LAST, STATUS_NAME_LEN, &
                             STATUS_MESSAGE_LEN
    implicit none
    integer(c_int), intent(in) :: code
    character(len=32), intent(out) :: name
    character(len=160), intent(out) :: msg
    integer(c_int), intent(out) :: nlast
    name = status_name(code)
    msg = status_message(code)
    nlast = STAT_LAST
end subroutine status_describe_c
