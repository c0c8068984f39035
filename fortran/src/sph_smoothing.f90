!-----------------------------------------------------------------------
!  sph_smoothing: evolution of the smoothing length (Liu's h_upgrade,
!  thesis 2-15, 2-16).
!   from density : h_i = h0_i (rho0_i/rho_i)^(1/d); axisymmetric (nr > 0,
!                  d = 2): h_i = h0_i (eta0_i/(rho_i r_i))^(1/2), the spacing
!                  in the r-z plane, with rho0 holding eta0 = rho0 r0 and
!                  rinv = 1/r* (sph_geometry)
!   rate (thesis): dh_i/dt = -(h_i/(rho_i d)) sum_j m_j v_ij.grad_i W_ij
!                          = -(h_i/(rho_i d)) drho_i/dt   (continuity sum)
!                  h_i <- h_i + theta dt dh_i/dt
!-----------------------------------------------------------------------
module sph_smoothing
  use iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: sph_smoothing_density, sph_smoothing_rate, sph_smoothing_advance

contains

  subroutine sph_smoothing_density(dim, n, rho, h0, rho0, nr, rinv, h) &
      bind(C, name="sph_smoothing_density")
    integer(c_int), value :: dim, n, nr
    real(c_double), intent(in) :: rho(n), h0(n), rho0(n), rinv(max(nr, 1))
    real(c_double), intent(out) :: h(n)
    integer :: i

    do i = 1, n
      if (nr > 0) then
        h(i) = h0(i)*sqrt(rho0(i)*rinv(i)/rho(i))
      else if (dim == 1) then
        h(i) = h0(i)*(rho0(i)/rho(i))
      else if (dim == 2) then
        h(i) = h0(i)*sqrt(rho0(i)/rho(i))
      else
        h(i) = h0(i)*(rho0(i)/rho(i))**(1.0d0/3.0d0)
      end if
    end do
  end subroutine sph_smoothing_density

  subroutine sph_smoothing_rate(dim, n, rho, h, drho, dhdt) bind(C, name="sph_smoothing_rate")
    integer(c_int), value :: dim, n
    real(c_double), intent(in) :: rho(n), h(n), drho(n)
    real(c_double), intent(out) :: dhdt(n)
    integer :: i

    do i = 1, n
      dhdt(i) = -(h(i)/(rho(i)*dble(dim)))*drho(i)
    end do
  end subroutine sph_smoothing_rate

  subroutine sph_smoothing_advance(n, dt, theta, dhdt, h) bind(C, name="sph_smoothing_advance")
    integer(c_int), value :: n
    real(c_double), value :: dt, theta
    real(c_double), intent(in) :: dhdt(n)
    real(c_double), intent(inout) :: h(n)
    integer :: i

    do i = 1, n
      h(i) = h(i) + theta*dt*dhdt(i)
    end do
  end subroutine sph_smoothing_advance

end module sph_smoothing
