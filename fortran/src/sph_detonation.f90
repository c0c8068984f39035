!-----------------------------------------------------------------------
!  sph_detonation: lighting of the charge (THESIS.md s.5 decision).
!  Instantaneous (constant-volume) burn needs no routine: the JWL
!  products start at rho0, e0.  Programmed burn: the front leaves the
!  lighting point xdet at the detonation speed D; particle i lights at
!  t_i = |x_i - xdet| / D and its burn fraction is
!     lam_i = 1 if t >= t_i else 0                      (width = 0)
!     lam_i = min(1, max(0, (t - t_i) D / (width h_i)))  (width > 0)
!  The JWL pressure is multiplied by lam_i.
!-----------------------------------------------------------------------
module sph_detonation
  use iso_c_binding, only: c_int, c_double
  use sph_param
  implicit none
  private
  public :: sph_detonation_light, sph_detonation_burn

contains

  subroutine sph_detonation_light(dim, n, x, mat, nmat, mtype, mpar, xdet, tlight) &
      bind(C, name="sph_detonation_light")
    integer(c_int), value :: dim, n, nmat
    integer(c_int), intent(in) :: mat(n), mtype(nmat)
    real(c_double), intent(in) :: x(dim, n), mpar(npar, nmat), xdet(dim)
    real(c_double), intent(out) :: tlight(n)
    integer :: i, m, d
    real(c_double) :: r2

    do i = 1, n
      m = mat(i) + 1
      tlight(i) = 0.0d0
      if (mtype(m) == eos_jwl) then
        r2 = 0.0d0
        do d = 1, dim
          r2 = r2 + (x(d, i) - xdet(d))*(x(d, i) - xdet(d))
        end do
        tlight(i) = sqrt(r2)/mpar(mp_e1 + 5, m)
      end if
    end do
  end subroutine sph_detonation_light

  subroutine sph_detonation_burn(n, t, mat, nmat, mpar, tlight, h, width, burn) &
      bind(C, name="sph_detonation_burn")
    integer(c_int), value :: n, nmat
    real(c_double), value :: t, width
    integer(c_int), intent(in) :: mat(n)
    real(c_double), intent(in) :: mpar(npar, nmat), tlight(n), h(n)
    real(c_double), intent(out) :: burn(n)
    integer :: i

    do i = 1, n
      if (width <= 0.0d0) then
        if (t >= tlight(i)) then
          burn(i) = 1.0d0
        else
          burn(i) = 0.0d0
        end if
      else
        burn(i) = min(1.0d0, max(0.0d0, (t - tlight(i))*mpar(mp_e1 + 5, mat(i) + 1)/(width*h(i))))
      end if
    end do
  end subroutine sph_detonation_burn

end module sph_detonation
