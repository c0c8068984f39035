      subroutine output(x, vx, mass, rho, p, u, c, itype, hsml, ntotal)
c-----------------------------------------------------------------------
c     The fixture's output with a binary dump beside its text file:
c       ../data/xv.dat -- number, x(1..dim), vx(1..dim)   (e14.8)
c       dump.dat       -- ntotal, then rho(1..ntotal)     (unformatted)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itype(maxn), ntotal
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), c(maxn), hsml(maxn)
      integer i, d

      open(1, file='../data/xv.dat')
      do 10 i = 1, ntotal
        write(1,1001) i, (x(d,i), d = 1, dim), (vx(d,i), d = 1, dim)
   10 continue
      close(1)
      open(2, file='dump.dat', form='unformatted')
      write(2) ntotal
      write(2) (rho(i), i = 1, ntotal)
      close(2)
 1001 format(1x, I5, 6(2x, e14.8))

      end
