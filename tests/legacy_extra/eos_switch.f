      subroutine eos_sw(ieos, rho, u, p, c, sound, gam)
c-----------------------------------------------------------------------
c     The ideal gas of p_gas with its switches passed as arguments, as
c     codes that choose the equation of state at run time do.
c     ieos  -- kind of material: 1 = ideal gas (in)
c     rho   -- density (in), u -- internal energy (in)
c     p     -- pressure (out), c -- sound speed (out)
c     sound -- .true.: c = sqrt((gam - 1) u), else c is left as it was
c     gam   -- ratio of specific heats, a default real (in)
c-----------------------------------------------------------------------
      implicit none
      integer ieos
      logical sound
      real gam
      double precision rho, u, p, c

      if (ieos .eq. 1) then
        p = (gam - 1)*rho*u
        if (sound) c = sqrt((gam - 1)*u)
      else
        stop 'eos_sw: no such material'
      endif

      end
