!-----------------------------------------------------------------------
!  sph_viscosity: Monaghan artificial viscosity (Liu's art_visc,
!  thesis 4-47, 4-48), applied to approaching pairs (v_ij.x_ij < 0):
!     mu_ij = h_ij v_ij.x_ij / (|x_ij|^2 + phi^2),  phi = etq h_ij
!     Pi_ij = (beta mu_ij - alpha c_ij) mu_ij / rho_ij   (pair means)
!     dv_i/dt -= sum_j m_j Pi_ij grad_i W_ij
!     de_i/dt += 1/2 sum_j m_j Pi_ij v_ij.grad_i W_ij
!  and, for the time step, mumax_i = max_j |mu_ij| over the approaching
!  pairs of particle i (0 if none): the beta term's signal speed.
!  Axisymmetric (nrinv = ntotal, rinv = 1/r*, mass the planar masses):
!  the energy terms read v_i - (r_j/r_i) v_j at the i end and
!  (r_i/r_j) v_i - v_j at the j end (as in sph_force: the heating of the
!  rings is what the pair's forces take from their kinetic energies); in
!  a pair across the axis (the other end a mirror, 1/r* < 0) the real end
!  gets Pi_ij v_i.grad_i W_ij, the work of the mirror's force on it.
!  With the Morris-Monaghan switch (nalpha = ntotal, alpv the alpha_i of
!  every particle, mirrors included): alpha_ij = (alpha_i + alpha_j)/2 and
!  beta_ij = beta alpha_ij/amax in place of alpha and beta.
!  sph_viscosity_switch advances alpha_i of the real particles over dt:
!     dalpha_i/dt = -(alpha_i - amin)/tau_i + S_i (amax - alpha_i),
!     tau_i = h_i/(ell c_i),  S_i = max(-div v_i, 0),
!     -div v_i = (1/rho_i) sum_j m_j v_ij.grad_i W_ij,
!  by one backward-Euler step (alpha stays within [amin, amax] at any dt):
!     alpha_i <- (alpha_i + dt (amin/tau_i + S_i amax))/(1 + dt (1/tau_i + S_i))
!-----------------------------------------------------------------------
module sph_viscosity
  use iso_c_binding, only: c_int, c_double
  use sph_density, only: sph_density_rate
  implicit none
  private
  public :: sph_viscosity_monaghan, sph_viscosity_switch

contains

  subroutine sph_viscosity_monaghan(dim, ntotal, npair, pair_i, pair_j, dwdx, x, v, h, rho, c, &
      mass, alpha, beta, etq, nalpha, alpv, amax, nrinv, rinv, dvdt, dedt, mumax) &
      bind(C, name="sph_viscosity_monaghan")
    integer(c_int), value :: dim, ntotal, npair, nrinv, nalpha
    real(c_double), value :: alpha, beta, etq, amax
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), x(dim, ntotal), v(dim, ntotal), h(ntotal), &
                                  rho(ntotal), c(ntotal), mass(ntotal), rinv(max(nrinv, 1)), &
                                  alpv(max(nalpha, 1))
    real(c_double), intent(out) :: dvdt(dim, ntotal), dedt(ntotal), mumax(ntotal)
    integer :: i, j, k, d
    real(c_double) :: dv(3), dx(3), vr, r2, hij, muv, mc, mrho, piv, vd, f, de, vdj, sij, sji, &
                      aij, bij, vwi, vwj, dj

    dvdt = 0.0d0
    dedt = 0.0d0
    mumax = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      vr = 0.0d0
      r2 = 0.0d0
      do d = 1, dim
        dv(d) = v(d, i) - v(d, j)
        dx(d) = x(d, i) - x(d, j)
        vr = vr + dv(d)*dx(d)
        r2 = r2 + dx(d)*dx(d)
      end do
      if (vr < 0.0d0) then
        hij = 0.5d0*(h(i) + h(j))
        muv = hij*vr/(r2 + (etq*hij)*(etq*hij))
        mc = 0.5d0*(c(i) + c(j))
        mrho = 0.5d0*(rho(i) + rho(j))
        if (nalpha > 0) then
          aij = 0.5d0*(alpv(i) + alpv(j))
          bij = beta*(aij/amax)
        else
          aij = alpha
          bij = beta
        end if
        piv = (bij*muv - aij*mc)*muv/mrho
        vd = 0.0d0
        vdj = 0.0d0
        vwi = 0.0d0
        vwj = 0.0d0
        if (nrinv > 0) then
          sji = rinv(i)/rinv(j)
          sij = rinv(j)/rinv(i)
        end if
        do d = 1, dim
          f = piv*dwdx(d, k)
          dvdt(d, i) = dvdt(d, i) - mass(j)*f
          dvdt(d, j) = dvdt(d, j) + mass(i)*f
          if (nrinv > 0) then
            vd = vd + (v(d, i) - sji*v(d, j))*dwdx(d, k)
            vdj = vdj + (sij*v(d, i) - v(d, j))*dwdx(d, k)
            vwi = vwi + v(d, i)*dwdx(d, k)
            vwj = vwj + v(d, j)*dwdx(d, k)
          else
            vd = vd + dv(d)*dwdx(d, k)
          end if
        end do
        de = 0.5d0*piv*vd
        if (nrinv > 0) then
          ! a pair across the axis (the other end an image, 1/r* < 0): the real ring's internal
          ! energy takes the work of the image's viscous force on it
          if (rinv(j) < 0.0d0) de = piv*vwi
          if (rinv(i) < 0.0d0) then
            dj = -(piv*vwj)
          else
            dj = 0.5d0*piv*vdj
          end if
          dedt(i) = dedt(i) + mass(j)*de
          dedt(j) = dedt(j) + mass(i)*dj
        else
          dedt(i) = dedt(i) + mass(j)*de
          dedt(j) = dedt(j) + mass(i)*de
        end if
        mumax(i) = max(mumax(i), -muv)
        mumax(j) = max(mumax(j), -muv)
      end if
    end do
  end subroutine sph_viscosity_monaghan

  subroutine sph_viscosity_switch(dim, ntotal, n, npair, pair_i, pair_j, dwdx, mass, rho, v, h, c, &
      amin, amax, ell, dt, alpv, dv) bind(C, name="sph_viscosity_switch")
    integer(c_int), value :: dim, ntotal, n, npair
    real(c_double), value :: amin, amax, ell, dt
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), mass(ntotal), rho(ntotal), v(dim, ntotal), &
                                  h(ntotal), c(ntotal)
    real(c_double), intent(inout) :: alpv(ntotal)
    real(c_double), intent(out) :: dv(ntotal)
    integer :: i
    real(c_double) :: s, r

    ! -div v_i = (1/rho_i) sum_j m_j v_ij.grad_i W_ij: the continuity sum of sph_density,
    ! into the caller's workspace dv
    call sph_density_rate(dim, ntotal, npair, pair_i, pair_j, dwdx, mass, v, dv)
    do i = 1, n
      s = dv(i)/rho(i)
      if (s < 0.0d0) s = 0.0d0
      r = ell*c(i)/h(i)
      alpv(i) = (alpv(i) + dt*(amin*r + s*amax))/(1.0d0 + dt*(r + s))
    end do
  end subroutine sph_viscosity_switch

end module sph_viscosity
