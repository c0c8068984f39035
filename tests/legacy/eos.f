      subroutine p_gas(rho, u, p, c)
c-----------------------------------------------------------------------
c     Ideal gas: pressure and sound speed from density and specific
c     internal energy (gamma = 1.4, air).
c     rho -- density (in), u -- internal energy (in)
c     p   -- pressure (out), c -- sound speed (out)
c     Note: the sound speed is sqrt((gamma-1) u) as in the old codes,
c     not the adiabatic sqrt(gamma (gamma-1) u).
c-----------------------------------------------------------------------
      implicit none
      double precision rho, u, p, c
      double precision gam

      gam = 1.4
      p = (gam - 1)*rho*u
      c = sqrt((gam - 1)*u)

      end

      subroutine p_art_water(rho, p, c)
c-----------------------------------------------------------------------
c     Artificial equation of state of a weakly compressible liquid
c     (the simple form p = c**2 rho with a fixed small sound speed).
c     rho -- density (in), p -- pressure (out), c -- sound speed (out)
c-----------------------------------------------------------------------
      implicit none
      double precision rho, p, c

      c = 0.01
      p = c**2*rho

      end
