      subroutine input(x, vx, mass, rho, p, u, itype, hsml, ntotal)
c-----------------------------------------------------------------------
c     Initial particles.  This code only knows the shock tube.
c     x, vx  -- positions and velocities                          (out)
c     mass   -- masses                                            (out)
c     rho    -- densities                                         (out)
c     p      -- pressures                                         (out)
c     u      -- specific internal energies                        (out)
c     itype  -- particle types                                    (out)
c     hsml   -- smoothing lengths                                 (out)
c     ntotal -- number of particles                               (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itype(maxn), ntotal
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), hsml(maxn)

      call shock_tube(x, vx, mass, rho, p, u, itype, hsml, ntotal)
      write(*,*) ' particles:', ntotal

      end

      subroutine shock_tube(x, vx, mass, rho, p, u, itype, hsml,
     &                      ntotal)
c-----------------------------------------------------------------------
c     1D shock tube: 320 particles on the left of x = 0 (dense gas),
c     80 on the right (thin gas) four times as far apart, all of the
c     same mass and smoothing length, at rest.
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itype(maxn), ntotal
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), hsml(maxn)
      integer i, d
      double precision dxr

      ntotal = 400
      dxr = 0.6/80.

      do 20 i = 1, ntotal
        mass(i) = 0.75/400.
        hsml(i) = 0.015
        itype(i) = 1
        do 10 d = 1, dim
          x(d,i) = 0.
          vx(d,i) = 0.
   10   continue
   20 continue

      do 30 i = 1, 320
        x(1,i) = -0.6 + dxr/4.*(i - 1)
   30 continue
      do 40 i = 321, ntotal
        x(1,i) = 0. + dxr*(i - 320)
   40 continue

      do 50 i = 1, ntotal
        if (x(1,i) .le. 1.e-8) then
          u(i) = 2.5
          rho(i) = 1.
          p(i) = 1.
        else
          u(i) = 1.795
          rho(i) = 0.25
          p(i) = 0.1795
        endif
   50 continue

      end
