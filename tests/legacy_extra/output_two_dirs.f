      subroutine output(x, vx, mass, rho, p, u, c, itype, hsml, ntotal)
c-----------------------------------------------------------------------
c     The fixture's output writing into two folders: the positions and
c     velocities in ../data (e14.8), the state beside the program (its
c     working folder, e16.8):
c       ../data/xv.dat -- number, x(1..dim), vx(1..dim)
c       state.dat      -- number, mass, rho, p, u
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itype(maxn), ntotal
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), c(maxn), hsml(maxn)
      integer i, d

      open(1, file='../data/xv.dat')
      open(2, file='state.dat')
      do 10 i = 1, ntotal
        write(1,1001) i, (x(d,i), d = 1, dim), (vx(d,i), d = 1, dim)
        write(2,1002) i, mass(i), rho(i), p(i), u(i)
   10 continue
      close(1)
      close(2)
 1001 format(1x, I5, 6(2x, e14.8))
 1002 format(1x, I5, 4(2x, e16.8))

      end
