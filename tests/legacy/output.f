      subroutine output(x, vx, mass, rho, p, u, c, itype, hsml, ntotal)
c-----------------------------------------------------------------------
c     Writes the particles to final_state.dat in the working folder:
c     a line with the number of particles, then one line a particle:
c     number, type, x(1..dim), vx(1..dim), mass, rho, p, u, hsml,
c     with 17 significant digits (enough to read back every bit).
c     c -- sound speeds (in, not written: this code never sets them)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itype(maxn), ntotal
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), c(maxn), hsml(maxn)
      integer i, d

      open(11, file='final_state.dat', status='unknown')
      write(11,*) ntotal
      do 10 i = 1, ntotal
        write(11,1001) i, itype(i), (x(d,i), d = 1, dim),
     &                 (vx(d,i), d = 1, dim), mass(i), rho(i), p(i),
     &                 u(i), hsml(i)
   10 continue
      close(11)
 1001 format(1x, i6, 1x, i3, 1p, 11(1x, e24.16e3))

      end
