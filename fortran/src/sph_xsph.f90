!-----------------------------------------------------------------------
!  sph_xsph: averaged velocity (Liu's av_vel, Monaghan's XSPH):
!     av_i = eps sum_j (m_j / rho_ij) (v_j - v_i) W_ij,  rho_ij = (rho_i+rho_j)/2
!  The integrator moves particles with v + av (x += dt (v + av)); the
!  book added av to v itself, not times dt: not reproduced.
!-----------------------------------------------------------------------
module sph_xsph
  use iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: sph_xsph_average

contains

  subroutine sph_xsph_average(dim, ntotal, npair, pair_i, pair_j, w, mass, rho, v, eps, av) &
      bind(C, name="sph_xsph_average")
    integer(c_int), value :: dim, ntotal, npair
    real(c_double), value :: eps
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: w(npair), mass(ntotal), rho(ntotal), v(dim, ntotal)
    real(c_double), intent(out) :: av(dim, ntotal)
    integer :: i, j, k, d
    real(c_double) :: mrho, f

    av = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      mrho = 0.5d0*(rho(i) + rho(j))
      do d = 1, dim
        f = (v(d, i) - v(d, j))/mrho*w(k)
        av(d, i) = av(d, i) - mass(j)*f
        av(d, j) = av(d, j) + mass(i)*f
      end do
    end do
    do i = 1, ntotal
      do d = 1, dim
        av(d, i) = eps*av(d, i)
      end do
    end do
  end subroutine sph_xsph_average

end module sph_xsph
