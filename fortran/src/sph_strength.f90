!-----------------------------------------------------------------------
!  sph_strength: soil strength (thesis 4-29..4-32, decisions of
!  docs/theory.md s.7).
!   velocity gradient  L_i^ab = sum_j (m_j/rho_j) (v_j^a - v_i^a) dW_ij/dx_i^b
!   strain rate        epsdot = (L + L^T)/2,  rotation rate R = (L - L^T)/2
!   Jaumann rate       dtau/dt = 2G (epsdot - tr(epsdot)/3 I) + tau R^T + R tau
!   deviatoric work    de_i/dt += tau_i : epsdot_i / rho_i
!  Plane strain (2D): the out-of-plane rates are zero, tau_zz is kept.
!  Axisymmetric (nr > 0, dim = 2, x = r, y = z): zz is the hoop (theta)
!  direction, epsdot_tt = v_r/r = v(1) rinv (rinv = 1/r*, sph_geometry);
!  mass is then the planar mass m/(2 pi r) of sph_geometry_ring.
!  Drucker-Prager return (yield): Y = 3 alpha_phi p + k (p > 0 in
!  compression); Y <= 0 -> tau = 0 (tension cut-off); sqrt(J2) > Y ->
!  tau scaled by Y/sqrt(J2), J2 = tau:tau/2.
!  Only materials with a shear modulus (mpar(mp_shear) > 0) carry tau.
!  Stress order: xx, yy, zz, xy, xz, yz; rot order: xy, xz, yz.
!-----------------------------------------------------------------------
module sph_strength
  use iso_c_binding, only: c_int, c_double
  use sph_param
  implicit none
  private
  public :: sph_strength_rates, sph_strength_yield

  integer, parameter :: iv(3, 3) = reshape([1, 4, 5, 4, 2, 6, 5, 6, 3], [3, 3])

contains

  subroutine sph_strength_rates(dim, ntotal, n, npair, pair_i, pair_j, dwdx, mass, rho, v, mat, &
      nmat, mpar, tau, nr, rinv, eps, rot, dtau, dedt) bind(C, name="sph_strength_rates")
    integer(c_int), value :: dim, ntotal, n, npair, nmat, nr
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair), mat(ntotal)
    real(c_double), intent(in) :: dwdx(dim, npair), mass(ntotal), rho(ntotal), v(dim, ntotal), &
                                  mpar(npar, nmat), tau(nstr, ntotal), rinv(max(nr, 1))
    real(c_double), intent(out) :: eps(nstr, ntotal), rot(3, ntotal), dtau(nstr, n), dedt(n)
    real(c_double), allocatable :: gl(:, :, :)
    real(c_double) :: dva, mi, mj, e3(3, 3), r3(3, 3), t3(3, 3), tr, g, s
    integer :: i, j, k, a, b, c

    allocate (gl(dim, dim, ntotal))
    gl = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      mi = mass(i)/rho(i)
      mj = mass(j)/rho(j)
      do a = 1, dim
        dva = v(a, j) - v(a, i)
        do b = 1, dim
          gl(a, b, i) = gl(a, b, i) + mj*dva*dwdx(b, k)
          gl(a, b, j) = gl(a, b, j) + mi*dva*dwdx(b, k)
        end do
      end do
    end do

    do i = 1, ntotal
      e3 = 0.0d0
      r3 = 0.0d0
      do a = 1, dim
        do b = 1, dim
          e3(a, b) = 0.5d0*(gl(a, b, i) + gl(b, a, i))
          r3(a, b) = 0.5d0*(gl(a, b, i) - gl(b, a, i))
        end do
      end do
      ! axisymmetric: the hoop strain rate v_r/r
      if (nr > 0) e3(3, 3) = v(1, i)*rinv(i)
      eps(1, i) = e3(1, 1)
      eps(2, i) = e3(2, 2)
      eps(3, i) = e3(3, 3)
      eps(4, i) = e3(1, 2)
      eps(5, i) = e3(1, 3)
      eps(6, i) = e3(2, 3)
      rot(1, i) = r3(1, 2)
      rot(2, i) = r3(1, 3)
      rot(3, i) = r3(2, 3)
      if (i > n) cycle
      g = mpar(mp_shear, mat(i) + 1)
      dtau(:, i) = 0.0d0
      dedt(i) = 0.0d0
      if (g <= 0.0d0) cycle
      do a = 1, 3
        do b = 1, 3
          t3(a, b) = tau(iv(a, b), i)
        end do
      end do
      tr = e3(1, 1) + e3(2, 2) + e3(3, 3)
      do a = 1, 3
        do b = a, 3
          s = 2.0d0*g*e3(a, b)
          if (a == b) s = s - 2.0d0*g*tr/3.0d0
          do c = 1, 3
            s = s + t3(a, c)*r3(b, c)
            s = s + r3(a, c)*t3(c, b)
          end do
          dtau(iv(a, b), i) = s
        end do
      end do
      s = 0.0d0
      do a = 1, 3
        do b = 1, 3
          s = s + t3(a, b)*e3(a, b)
        end do
      end do
      dedt(i) = s/rho(i)
    end do
    deallocate (gl)
  end subroutine sph_strength_rates

  subroutine sph_strength_yield(n, mat, nmat, mpar, p, tau) bind(C, name="sph_strength_yield")
    integer(c_int), value :: n, nmat
    integer(c_int), intent(in) :: mat(n)
    real(c_double), intent(in) :: mpar(npar, nmat), p(n)
    real(c_double), intent(inout) :: tau(nstr, n)
    integer :: i, m, d
    real(c_double) :: j2, y, sj

    do i = 1, n
      m = mat(i) + 1
      if (mpar(mp_shear, m) <= 0.0d0) cycle
      j2 = 0.5d0*(tau(1, i)*tau(1, i) + tau(2, i)*tau(2, i) + tau(3, i)*tau(3, i)) &
           + tau(4, i)*tau(4, i) + tau(5, i)*tau(5, i) + tau(6, i)*tau(6, i)
      y = 3.0d0*mpar(mp_alpha_phi, m)*p(i) + mpar(mp_cohesion, m)
      if (y <= 0.0d0) then
        do d = 1, nstr
          tau(d, i) = 0.0d0
        end do
      else
        sj = sqrt(j2)
        if (sj > y) then
          do d = 1, nstr
            tau(d, i) = tau(d, i)*(y/sj)
          end do
        end if
      end if
    end do
  end subroutine sph_strength_yield

end module sph_strength
