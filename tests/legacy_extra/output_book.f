      subroutine output(x, vx, mass, rho, p, u, c, itype, hsml, ntotal)
c-----------------------------------------------------------------------
c     The fixture's output in the book's style: three files in ../data
c     with 8 digits (e14.8), each a line with the number of particles,
c     then one line a particle:
c       f_xv.dat    -- number, x(1..dim), vx(1..dim)
c       f_state.dat -- number, mass, rho, p, u, c
c       f_other.dat -- number, itype, hsml
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itype(maxn), ntotal
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), c(maxn), hsml(maxn)
      integer i, d

      open(1, file='../data/f_xv.dat')
      open(2, file='../data/f_state.dat')
      open(3, file='../data/f_other.dat')
      write(1,*) ntotal
      write(2,*) ntotal
      write(3,*) ntotal
      do 10 i = 1, ntotal
        write(1,1001) i, (x(d,i), d = 1, dim), (vx(d,i), d = 1, dim)
        write(2,1002) i, mass(i), rho(i), p(i), u(i), c(i)
        write(3,1003) i, itype(i), hsml(i)
   10 continue
      close(1)
      close(2)
      close(3)
 1001 format(1x, I5, 6(2x, e14.8))
 1002 format(1x, I5, 7(2x, e14.8))
 1003 format(1x, I5, 2x, I2, 2x, e14.8)

      end
