!-----------------------------------------------------------------------
!  sph_geometry: the axisymmetric (RZ) geometry of dim = 2, x(1) = r >= 0
!  (the radius) and x(2) = z (along the axis of symmetry).
!
!  Area-weighted RZ SPH (Brookshaw 2003; the form of LLNL Spheral's RZ
!  hydrodynamics): a particle is a ring of mass m (kg) at radius r.  The
!  pair sums of every module are the plane ones with the planar (area)
!  mass mu = m/(2 pi r) (kg/m, the mass of the ring per unit length of
!  its circumference) in place of m, so that the plane sum
!  sum_j mu_j W_ij estimates the volumetric density rho, and the kernel
!  keeps its 2D normalisation in (r, z).  What the plane sums miss are the
!  hoop terms, added per particle:
!     continuity   drho/dt += -rho v_r / r                  (here)
!     strain rate  epsdot_tt = v_r / r                      (sph_strength)
!     momentum     dv_r/dt += (tau_rr - tau_tt)/(rho r),
!                  dv_z/dt += tau_rz/(rho r)                 (here)
!     energy       de/dt   += -(p/rho) v_r / r               (in the
!                  pair sums of sph_force and sph_viscosity, which read
!                  v_i - (r_j/r_i) v_j so that the energy is conserved;
!                  the deviatoric hoop work tau_tt v_r/(r rho) is part of
!                  tau:epsdot/rho in sph_strength)
!  The pressure has no hoop term in the momentum equation (rho dv/dt =
!  -grad p in cylindrical coordinates is the plane gradient), so the
!  hoop acceleration is that of the deviatoric stress only.  Near the
!  axis 1/r is taken as 1/r*, r* = max(|r|, h/4); the axis itself is a
!  mirror (reflective ghosts, sph_boundary), whose images have r < 0 and
!  the |r| of their source; sph_geometry_ring gives them 1/r* < 0, so that
!  sph_force and sph_viscosity can tell a pair across the axis.  Stress order xx, yy, zz, xy = rr, zz, tt, rz.
!-----------------------------------------------------------------------
module sph_geometry
  use iso_c_binding, only: c_int, c_double
  use sph_param
  implicit none
  private
  public :: sph_geometry_ring, sph_geometry_hoop, sph_geometry_continuity

contains

  ! 1/r* and the planar mass mu = m/(2 pi r*) of every particle, r* = max(|x(1)|, h/4);
  ! a mirror across the axis (i > n, x(1) < 0) gets 1/r* < 0 (its signed radius), mu > 0
  subroutine sph_geometry_ring(dim, ntotal, n, x, h, mass, rinv, pmass) bind(C, name="sph_geometry_ring")
    integer(c_int), value :: dim, ntotal, n
    real(c_double), intent(in) :: x(dim, ntotal), h(ntotal), mass(ntotal)
    real(c_double), intent(out) :: rinv(ntotal), pmass(ntotal)
    integer :: i
    real(c_double) :: rs, rmin

    do i = 1, ntotal
      rs = abs(x(1, i))
      rmin = 0.25d0*h(i)
      if (rs < rmin) rs = rmin
      ! a mirror across the axis (r < 0) carries the signed 1/r*
      if (i > n .and. x(1, i) < 0.0d0) then
        rinv(i) = -1.0d0/rs
      else
        rinv(i) = 1.0d0/rs
      end if
      pmass(i) = mass(i)/(2.0d0*pi*rs)
    end do
  end subroutine sph_geometry_ring

  ! the hoop acceleration of the deviatoric stress of the first n particles
  subroutine sph_geometry_hoop(dim, ntotal, n, rho, rinv, tau, dvdt) &
      bind(C, name="sph_geometry_hoop")
    integer(c_int), value :: dim, ntotal, n
    real(c_double), intent(in) :: rho(ntotal), rinv(ntotal), tau(nstr, ntotal)
    real(c_double), intent(out) :: dvdt(dim, n)
    integer :: i

    do i = 1, n
      dvdt(1, i) = (tau(1, i) - tau(3, i))/rho(i)*rinv(i)
      dvdt(2, i) = tau(4, i)/rho(i)*rinv(i)
    end do
  end subroutine sph_geometry_hoop

  ! the hoop term of the continuity equation, added to the plane rate drho of the first n
  ! particles: drho = drho - rho v_r / r
  subroutine sph_geometry_continuity(dim, ntotal, n, v, rho, rinv, drho) &
      bind(C, name="sph_geometry_continuity")
    integer(c_int), value :: dim, ntotal, n
    real(c_double), intent(in) :: v(dim, ntotal), rho(ntotal), rinv(ntotal)
    real(c_double), intent(inout) :: drho(n)
    integer :: i

    do i = 1, n
      drho(i) = drho(i) - rho(i)*(v(1, i)*rinv(i))
    end do
  end subroutine sph_geometry_continuity

end module sph_geometry
