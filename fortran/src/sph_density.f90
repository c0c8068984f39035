!-----------------------------------------------------------------------
!  sph_density: density by summation (Liu's sum_density, thesis 2-7
!  applied to rho) or its rate by the continuity equation (Liu's
!  con_density, thesis Table 4-1):
!     rho_i      = m_i W_ii + sum_j m_j W_ij
!     drho_i/dt  = sum_j m_j (v_i - v_j) . grad_i W_ij            (mass form)
!  or its volume form, rho_i times the SPH divergence of v, which stays
!  consistent across large density ratios (products against soil):
!     drho_i/dt  = rho_i sum_j (m_j/rho_j) (v_i - v_j) . grad_i W_ij
!  or by number-density summation (Hu & Adams 2006), each particle's
!  density from its own mass and the kernel sum of its neighbours:
!     rho_i      = m_i (W_ii + sum_j W_ij)
!  Pairs are scattered to both ends in pair order.
!-----------------------------------------------------------------------
module sph_density
  use iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: sph_density_sum, sph_density_number, sph_density_rate, sph_density_rate_vol

contains

  subroutine sph_density_sum(ntotal, npair, pair_i, pair_j, w, w0, mass, rho) &
      bind(C, name="sph_density_sum")
    integer(c_int), value :: ntotal, npair
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: w(npair), w0(ntotal), mass(ntotal)
    real(c_double), intent(out) :: rho(ntotal)
    integer :: i, j, k

    do i = 1, ntotal
      rho(i) = mass(i)*w0(i)
    end do
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      rho(i) = rho(i) + mass(j)*w(k)
      rho(j) = rho(j) + mass(i)*w(k)
    end do
  end subroutine sph_density_sum

  subroutine sph_density_number(ntotal, npair, pair_i, pair_j, w, w0, mass, rho) &
      bind(C, name="sph_density_number")
    integer(c_int), value :: ntotal, npair
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: w(npair), w0(ntotal), mass(ntotal)
    real(c_double), intent(out) :: rho(ntotal)
    integer :: i, j, k

    do i = 1, ntotal
      rho(i) = w0(i)
    end do
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      rho(i) = rho(i) + w(k)
      rho(j) = rho(j) + w(k)
    end do
    do i = 1, ntotal
      rho(i) = mass(i)*rho(i)
    end do
  end subroutine sph_density_number

  subroutine sph_density_rate(dim, ntotal, npair, pair_i, pair_j, dwdx, mass, v, drho) &
      bind(C, name="sph_density_rate")
    integer(c_int), value :: dim, ntotal, npair
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), mass(ntotal), v(dim, ntotal)
    real(c_double), intent(out) :: drho(ntotal)
    integer :: i, j, k, d
    real(c_double) :: vcc

    drho = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      vcc = 0.0d0
      do d = 1, dim
        vcc = vcc + (v(d, i) - v(d, j))*dwdx(d, k)
      end do
      drho(i) = drho(i) + mass(j)*vcc
      drho(j) = drho(j) + mass(i)*vcc
    end do
  end subroutine sph_density_rate

  subroutine sph_density_rate_vol(dim, ntotal, npair, pair_i, pair_j, dwdx, mass, rho, v, drho) &
      bind(C, name="sph_density_rate_vol")
    integer(c_int), value :: dim, ntotal, npair
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), mass(ntotal), rho(ntotal), v(dim, ntotal)
    real(c_double), intent(out) :: drho(ntotal)
    integer :: i, j, k, d
    real(c_double) :: vcc

    drho = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      vcc = 0.0d0
      do d = 1, dim
        vcc = vcc + (v(d, i) - v(d, j))*dwdx(d, k)
      end do
      drho(i) = drho(i) + mass(j)/rho(j)*vcc
      drho(j) = drho(j) + mass(i)/rho(i)*vcc
    end do
    do i = 1, ntotal
      drho(i) = rho(i)*drho(i)
    end do
  end subroutine sph_density_rate_vol

end module sph_density
