!-----------------------------------------------------------------------
!  sph_conductivity: artificial conductivity (Price 2008, J. Comput.
!  Phys. 227, 10040), an energy exchange between the two particles of a
!  pair that smooths a jump of the specific internal energy e:
!     de_i/dt += sum_j m_j alpha_u vsig_ij (e_i - e_j) / rho_ij
!                          (xhat_ij . grad_i W_ij)
!  with rho_ij = (rho_i + rho_j)/2, xhat_ij = x_ij/r_ij, and the signal
!  speed (m/s)
!     signal = 0 (pressure, Price): vsig = sqrt(|p_i - p_j| / rho_ij)
!     signal = 1 (velocity, for shocks and wall heating):
!                                    vsig = |v_ij . xhat_ij|
!  xhat.grad W <= 0, so heat flows from the hotter particle; the pair's
!  two terms cancel in sum_i m_i de_i/dt (energy is conserved).
!  Coincident particles (r = 0) exchange nothing.
!  Axisymmetric (nrinv = ntotal, rinv = 1/r*, mass the planar masses mu):
!  the i end's term is weighted by rbar/r_i = (1 + r_j/r_i)/2 and the j
!  end's by (1 + r_i/r_j)/2, so that the rings (mass 2 pi r mu) exchange
!  2 pi mu_i mu_j rbar q: energy is conserved.
!
!  sph_conductivity_noh: the artificial heat of Noh (1987) and Monaghan
!  (1992), as Liu & Liu's book code (art_heat) computes it:
!     div_i = sum_j m_j/rho_j (v_j - v_i) . grad_i W_ij          (1/s)
!     q_i   = g1 h_i c_i + g2 h_i h_i (|div_i| - div_i)          (m2/s)
!     de_i/dt += 2 sum_j m_j qbar_ij / (rho_ij (r_ij**2 + phi2 hbar**2))
!                          (e_i - e_j) (x_ij . grad_i W_ij)
!  with the pair means qbar, rho_ij, hbar and phi2 = 0.01 (phi = 0.1 h).
!  The pair's two terms cancel in sum_i m_i de_i/dt. Plane geometry.
!-----------------------------------------------------------------------
module sph_conductivity
  use iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: sph_conductivity_price, sph_conductivity_noh

contains

  subroutine sph_conductivity_price(dim, ntotal, npair, pair_i, pair_j, dwdx, x, v, rho, p, e, &
      mass, alpha, signal, nrinv, rinv, dedt) bind(C, name="sph_conductivity_price")
    integer(c_int), value :: dim, ntotal, npair, signal, nrinv
    real(c_double), value :: alpha
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), x(dim, ntotal), v(dim, ntotal), rho(ntotal), &
                                  p(ntotal), e(ntotal), mass(ntotal), rinv(max(nrinv, 1))
    real(c_double), intent(out) :: dedt(ntotal)
    integer :: i, j, k, d
    real(c_double) :: dx, r2, r, xw, vr, mrho, vs, q, fi, fj

    dedt = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      r2 = 0.0d0
      xw = 0.0d0
      vr = 0.0d0
      do d = 1, dim
        dx = x(d, i) - x(d, j)
        r2 = r2 + dx*dx
        xw = xw + dx*dwdx(d, k)
        vr = vr + (v(d, i) - v(d, j))*dx
      end do
      if (r2 > 0.0d0) then
        r = sqrt(r2)
        mrho = 0.5d0*(rho(i) + rho(j))
        if (signal == 0) then
          vs = sqrt(abs(p(i) - p(j))/mrho)
        else
          vs = abs(vr)/r
        end if
        q = alpha*vs*(e(i) - e(j))/mrho*(xw/r)
        if (nrinv > 0) then
          ! |1/r*|: an axis image carries a signed 1/r*, its ring the source's |r|
          fi = 0.5d0*(1.0d0 + abs(rinv(i))/abs(rinv(j)))
          fj = 0.5d0*(1.0d0 + abs(rinv(j))/abs(rinv(i)))
          dedt(i) = dedt(i) + mass(j)*(q*fi)
          dedt(j) = dedt(j) - mass(i)*(q*fj)
        else
          dedt(i) = dedt(i) + mass(j)*q
          dedt(j) = dedt(j) - mass(i)*q
        end if
      end if
    end do
  end subroutine sph_conductivity_price

  subroutine sph_conductivity_noh(dim, ntotal, npair, pair_i, pair_j, dwdx, x, v, h, rho, c, e, &
      mass, g1, g2, phi2, dedt) bind(C, name="sph_conductivity_noh")
    integer(c_int), value :: dim, ntotal, npair
    real(c_double), value :: g1, g2, phi2
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), x(dim, ntotal), v(dim, ntotal), h(ntotal), &
                                  rho(ntotal), c(ntotal), e(ntotal), mass(ntotal)
    real(c_double), intent(out) :: dedt(ntotal)
    integer :: i, j, k, d
    real(c_double) :: hv, dx, r2, xw, hb, mrho, qi, qj, qb, f, de
    real(c_double), allocatable :: div(:)

    allocate(div(ntotal))
    div = 0.0d0
    dedt = 0.0d0
    ! the velocity divergence, volume form
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      hv = 0.0d0
      do d = 1, dim
        hv = hv + (v(d, j) - v(d, i))*dwdx(d, k)
      end do
      div(i) = div(i) + mass(j)*hv/rho(j)
      div(j) = div(j) + mass(i)*hv/rho(i)
    end do
    ! the exchange within each pair
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      r2 = 0.0d0
      xw = 0.0d0
      do d = 1, dim
        dx = x(d, i) - x(d, j)
        r2 = r2 + dx*dx
        xw = xw + dx*dwdx(d, k)
      end do
      hb = 0.5d0*(h(i) + h(j))
      mrho = 0.5d0*(rho(i) + rho(j))
      qi = g1*h(i)*c(i) + g2*(h(i)*h(i))*(abs(div(i)) - div(i))
      qj = g1*h(j)*c(j) + g2*(h(j)*h(j))*(abs(div(j)) - div(j))
      qb = 0.5d0*(qi + qj)
      f = qb/(mrho*(r2 + phi2*(hb*hb)))*xw
      de = e(i) - e(j)
      dedt(i) = dedt(i) + mass(j)*f*de
      dedt(j) = dedt(j) - mass(i)*f*de
    end do
    do i = 1, ntotal
      dedt(i) = 2.0d0*dedt(i)
    end do
    deallocate(div)
  end subroutine sph_conductivity_noh

end module sph_conductivity
