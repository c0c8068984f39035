      subroutine viscosity(ntotal, itype, x, rho, eta)
c-----------------------------------------------------------------------
c     Dynamic viscosity of each particle from its type (the gas:
c     param.inc's eta_gas, 0 as the book has it; water 1.0e-3).
c     ntotal -- number of particles (in), itype -- types (in),
c     x -- positions (in, not used), rho -- densities (in, not used),
c     eta -- dynamic viscosity (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, itype(maxn)
      double precision x(dim,maxn), rho(maxn), eta(maxn)
      integer i

      do 10 i = 1, ntotal
        if (abs(itype(i)) .eq. 1) then
          eta(i) = eta_gas
        else if (abs(itype(i)) .eq. 2) then
          eta(i) = 1.0e-3
        endif
   10 continue

      end
