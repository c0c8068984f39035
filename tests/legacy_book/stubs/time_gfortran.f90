! Not the book's: gfortran versions of the book's dfport timing routines.
subroutine time_print
  implicit none
  character(len=8) :: d
  character(len=10) :: t
  call date_and_time(d, t)
  write(*,*) d, ' ', t
end subroutine time_print

subroutine time_elapsed(s)
  implicit none
  real(8) :: s
  call cpu_time(s)
end subroutine time_elapsed
