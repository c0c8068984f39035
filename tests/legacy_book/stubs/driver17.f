c     Not the book's: sph.f's own sequence (dt, input, time_integration,
c     output), then the final arrays at 17 digits.  NSTEP from stdin.
      program drv17
      implicit none
      include 'param.inc'
      integer ntotal, itype(maxn), maxtimestep, i, d
      double precision x(dim,maxn), vx(dim, maxn), mass(maxn),rho(maxn),
     &     p(maxn), u(maxn), c(maxn), s(maxn), e(maxn), hsml(maxn), dt
      if (shocktube)   dt = 0.005
      if (shearcavity) dt = 5.e-5
      call input(x, vx, mass, rho, p, u, itype, hsml, ntotal)
      read(*,*) maxtimestep
      call time_integration(x, vx, mass, rho, p, u, c, s, e, itype,
     &     hsml, ntotal, maxtimestep, dt )
      call output(x, vx, mass, rho, p, u, c, itype, hsml, ntotal)
      open(9, file='final17.dat')
      do i = 1, ntotal
        write(9,'(i6,9(1x,1pe25.17))') i, (x(d,i),d=1,dim),
     &    (vx(d,i),d=1,dim), mass(i), rho(i), p(i), u(i), hsml(i)
      enddo
      close(9)
      end
