!-----------------------------------------------------------------------
!  sph_eos: pressure p (Pa) and sound speed c (m/s) from density rho
!  (kg/m^3) and specific internal energy e (J/kg), per material.
!
!   ideal gas (Liu p_gas):  p = (gamma-1) rho e,  c = sqrt(gamma (gamma-1) e)
!     (the book returns sqrt((gamma-1) e); the adiabatic speed is used here)
!   JWL (thesis 4-39), eta = rho/rho0:
!     p = A (1 - w eta/R1) exp(-R1/eta) + B (1 - w eta/R2) exp(-R2/eta) + w eta rho0 e
!     times the burn fraction lam of a programmed burn (sph_detonation);
!     with an unreacted explosive (C_u > 0)
!     p = lam p_JWL + (1 - lam) p_u,  c^2 = lam c_JWL^2 + (1 - lam) c_u^2,
!     p_u the Mie-Grueneisen below with (C_u, S_u, Gamma_u) and e - e_chem
!   water polynomial (thesis 4-40, 4-41), mu = eta - 1:
!     mu > 0 : p = a1 mu + a2 mu^2 + a3 mu^3 + (b0 + b1 mu) rho0 e
!     mu <= 0: p = a1 mu + (b0 + b1 mu) rho0 e
!   soil Mie-Grueneisen (thesis 4-42..4-46), mu = eta - 1:
!     p = (1 - G mu/2) pH + G rho e,
!     pH = a0 mu + b0 mu^2 + c0 mu^3 (mu > 0), a0 mu (mu <= 0),
!     a0 = rho0 C^2, b0 = a0 (1 + 2(S-1)), c0 = a0 (2(S-1) + 3(S-1)^2)
!   Tait (weakly compressible water; Liu & Liu 2003, their artificial water):
!     p = B ((rho/rho0)^gamma - 1),  c = the constant c of the table
!   Morris (Morris, Fox & Zhu 1997; the book's p_art_water): p = c^2 rho, c constant
!   compaction (Laine & Sandvik 2001, porous sand), rmax the largest density
!   the particle has reached (its history, at least the table's rmax0):
!     rmax <- max(rmax, rho),  c = c_u(rmax),
!     p = p_c(rmax) + c_u(rmax)^2 (rho - rmax)
!     p_c the plastic compaction curve (loading), piecewise linear in rho,
!     extended past its last point; c_u the bulk sound speed of the elastic
!     unloading and reloading line, piecewise linear, held past its ends
!  c^2 = dp/drho|e + (p/rho^2) dp/de|rho  (isentropic), floored at a
!  small fraction of the reference speed so that c stays real.
!  p is floored at the material's pmin (tension cut-off, cavitation).
!-----------------------------------------------------------------------
module sph_eos
  use iso_c_binding, only: c_int, c_double
  use sph_param
  implicit none
  private
  public :: sph_eos_eval, eos_point

contains

  ! (not pure: an unknown material type stops the program with a message)
  ! rmax: the compaction history of the particle (kg/m^3); only the compaction
  ! kind reads and updates it
  subroutine eos_point(itype, par, rho, e, lam, rmax, p, c)
    integer(c_int), intent(in) :: itype
    real(c_double), intent(in) :: par(npar), rho, e, lam
    real(c_double), intent(inout) :: rmax
    real(c_double), intent(out) :: p, c
    integer :: nk
    real(c_double) :: rho0, eta, mu, g, a, b, r1, r2, om, x1, x2, dpdr, dpde, c2, cref
    real(c_double) :: a0, b0, c0, s, ph, dph, gam, wa1, wa2, wa3, wb0, wb1
    real(c_double) :: pu, c2u, eu

    rho0 = par(mp_rho0)
    p = 0.0d0
    c2 = 0.0d0
    cref = 0.0d0
    select case (itype)
    case (eos_ideal_gas)
      g = par(mp_e1)
      p = (g - 1.0d0)*rho*e
      c2 = g*(g - 1.0d0)*e
      cref = 0.0d0
    case (eos_jwl)
      a = par(mp_e1)
      b = par(mp_e1 + 1)
      r1 = par(mp_e1 + 2)
      r2 = par(mp_e1 + 3)
      om = par(mp_e1 + 4)
      eta = rho/rho0
      x1 = exp(-r1/eta)
      x2 = exp(-r2/eta)
      p = a*(1.0d0 - om*eta/r1)*x1 + b*(1.0d0 - om*eta/r2)*x2 + om*eta*rho0*e
      ! d/d(eta) of the cold terms: A x1 (-w/R1 + (1 - w eta/R1) R1/eta^2)
      dpdr = (a*x1*(-om/r1 + (1.0d0 - om*eta/r1)*r1/(eta*eta)) &
              + b*x2*(-om/r2 + (1.0d0 - om*eta/r2)*r2/(eta*eta)) + om*rho0*e)/rho0
      dpde = om*rho
      c2 = dpdr + p/(rho*rho)*dpde
      cref = par(mp_e1 + 5)
      if (par(mp_unr_c) > 0.0d0) then
        s = par(mp_unr_s)
        gam = par(mp_unr_gamma)
        a0 = rho0*par(mp_unr_c)*par(mp_unr_c)
        b0 = a0*(1.0d0 + 2.0d0*(s - 1.0d0))
        c0 = a0*(2.0d0*(s - 1.0d0) + 3.0d0*(s - 1.0d0)*(s - 1.0d0))
        mu = eta - 1.0d0
        if (mu > 0.0d0) then
          ph = a0*mu + b0*mu*mu + c0*mu*mu*mu
          dph = a0 + 2.0d0*b0*mu + 3.0d0*c0*mu*mu
        else
          ph = a0*mu
          dph = a0
        end if
        eu = e - par(mp_echem)
        pu = (1.0d0 - 0.5d0*gam*mu)*ph + gam*rho*eu
        c2u = ((1.0d0 - 0.5d0*gam*mu)*dph - 0.5d0*gam*ph)/rho0 + gam*eu + pu/(rho*rho)*(gam*rho)
        p = lam*p + (1.0d0 - lam)*pu
        c2 = lam*c2 + (1.0d0 - lam)*c2u
      else
        p = lam*p
      end if
    case (eos_water)
      mu = rho/rho0 - 1.0d0
      wa1 = par(mp_e1)
      wa2 = par(mp_e1 + 1)
      wa3 = par(mp_e1 + 2)
      wb0 = par(mp_e1 + 3)
      wb1 = par(mp_e1 + 4)
      if (mu > 0.0d0) then
        p = wa1*mu + wa2*mu*mu + wa3*mu*mu*mu + (wb0 + wb1*mu)*rho0*e
        dpdr = (wa1 + 2.0d0*wa2*mu + 3.0d0*wa3*mu*mu + wb1*rho0*e)/rho0
      else
        p = wa1*mu + (wb0 + wb1*mu)*rho0*e
        dpdr = (wa1 + wb1*rho0*e)/rho0
      end if
      dpde = (wb0 + wb1*mu)*rho0
      c2 = dpdr + p/(rho*rho)*dpde
      cref = par(mp_e1 + 5)
    case (eos_soil)
      cref = par(mp_e1)
      s = par(mp_e1 + 1)
      gam = par(mp_e1 + 2)
      a0 = rho0*cref*cref
      b0 = a0*(1.0d0 + 2.0d0*(s - 1.0d0))
      c0 = a0*(2.0d0*(s - 1.0d0) + 3.0d0*(s - 1.0d0)*(s - 1.0d0))
      mu = rho/rho0 - 1.0d0
      if (mu > 0.0d0) then
        ph = a0*mu + b0*mu*mu + c0*mu*mu*mu
        dph = a0 + 2.0d0*b0*mu + 3.0d0*c0*mu*mu
      else
        ph = a0*mu
        dph = a0
      end if
      p = (1.0d0 - 0.5d0*gam*mu)*ph + gam*rho*e
      dpdr = ((1.0d0 - 0.5d0*gam*mu)*dph - 0.5d0*gam*ph)/rho0 + gam*e
      dpde = gam*rho
      c2 = dpdr + p/(rho*rho)*dpde
    case (eos_tait)
      b = par(mp_e1)
      gam = par(mp_e1 + 1)
      cref = par(mp_e1 + 2)
      p = b*((rho/rho0)**gam - 1.0d0)
      c2 = cref*cref
    case (eos_morris)
      cref = par(mp_e1)
      c2 = cref*cref
      p = c2*rho
    case (eos_compaction)
      nk = nint(par(mp_cmp_n))
      if (rho > rmax) rmax = rho
      if (par(mp_cmp_rmax0) > rmax) rmax = par(mp_cmp_rmax0)
      cref = tab_lin(nk, par(mp_cmp_crho:mp_cmp_crho + nk - 1), par(mp_cmp_c:mp_cmp_c + nk - 1), rmax, .false.)
      p = tab_lin(nk, par(mp_cmp_rho:mp_cmp_rho + nk - 1), par(mp_cmp_p:mp_cmp_p + nk - 1), rmax, .true.) &
          + cref*cref*(rho - rmax)
      c2 = cref*cref
    case (eos_none)
      ! no equation of state: p = 0 before the floor, c = 0
    case default
      error stop 'sph_eos: unknown material type (mtype is not an eos_* code)'
    end select
    p = max(p, par(mp_pmin))
    c = sqrt(max(c2, 1.0d-4*cref*cref))
  end subroutine eos_point

  ! y(x) of the table (xs, ys) of nk points, xs ascending: linear between
  ! points, ys(1) below xs(1); above xs(nk) the last segment extended
  ! (extend) or ys(nk)
  pure function tab_lin(nk, xs, ys, x, extend) result(y)
    integer, intent(in) :: nk
    real(c_double), intent(in) :: xs(nk), ys(nk), x
    logical, intent(in) :: extend
    real(c_double) :: y
    integer :: k

    if (x <= xs(1)) then
      y = ys(1)
      return
    end if
    if (x >= xs(nk) .and. .not. extend) then
      y = ys(nk)
      return
    end if
    k = 1
    do while (k < nk - 1)
      if (x < xs(k + 1)) exit
      k = k + 1
    end do
    y = ys(k) + (x - xs(k))/(xs(k + 1) - xs(k))*(ys(k + 1) - ys(k))
  end function tab_lin

  ! every particle i in 1..n: p(i), c(i) from its material mat(i) (0-based)
  ! burn(n) is the burn fraction of a programmed burn (nburn = n), or unused (nburn = 0)
  ! rmax(n) is the compaction history (nhist = n), updated; or unused (nhist = 0):
  ! then every particle is on its loading curve (rmax = rho)
  subroutine sph_eos_eval(n, nmat, mtype, mpar, mat, nburn, burn, nhist, rmax, rho, e, p, c) &
      bind(C, name="sph_eos_eval")
    integer(c_int), value :: n, nmat, nburn, nhist
    integer(c_int), intent(in) :: mtype(nmat), mat(n)
    real(c_double), intent(in) :: mpar(npar, nmat), burn(max(nburn, 1)), rho(n), e(n)
    real(c_double), intent(inout) :: rmax(max(nhist, 1))
    real(c_double), intent(out) :: p(n), c(n)
    integer :: i, m
    real(c_double) :: lam, r

    do i = 1, n
      m = mat(i) + 1
      lam = 1.0d0
      if (nburn > 0) lam = burn(i)
      r = rho(i)
      if (nhist > 0) r = rmax(i)
      call eos_point(mtype(m), mpar(:, m), rho(i), e(i), lam, r, p(i), c(i))
      if (nhist > 0) rmax(i) = r
    end do
  end subroutine sph_eos_eval

end module sph_eos
