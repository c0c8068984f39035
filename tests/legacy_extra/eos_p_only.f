      subroutine p_gas_p(rho, u, p)
c-----------------------------------------------------------------------
c     Ideal gas, pressure only (gamma = 1.4, air), as codes that never
c     compute a sound speed have it: their c is an array that no
c     routine writes, and their artificial viscosity reads it as 0.
c     rho -- density (in), u -- internal energy (in)
c     p   -- pressure (out)
c-----------------------------------------------------------------------
      implicit none
      double precision rho, u, p
      double precision gam

      gam = 1.4
      p = (gam - 1)*rho*u

      end
