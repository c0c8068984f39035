      program sph
c-----------------------------------------------------------------------
c     Main program: sets up the particles, asks for the number of time
c     steps, integrates, writes the final state, and offers more steps.
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, itype(maxn), maxtimestep, more
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), c(maxn), s(maxn), e(maxn),
     &        hsml(maxn), dt

c     time step of the shock tube
      dt = 0.005

      call input(x, vx, mass, rho, p, u, itype, hsml, ntotal)

    1 write(*,*) ' number of time steps?'
      read(*,*) maxtimestep
      call time_integration(x, vx, mass, rho, p, u, c, s, e, itype,
     &                      hsml, ntotal, maxtimestep, dt)
      call output(x, vx, mass, rho, p, u, c, itype, hsml, ntotal)
      write(*,*) ' more time steps? (0 = no, 1 = yes)'
      read(*,*,end=2) more
      if (more .ne. 0) go to 1
    2 continue

      end
