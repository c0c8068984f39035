      subroutine time_integration(x, vx, mass, rho, p, u, c, s, e,
     &                            itype, hsml, ntotal, maxtimestep, dt)
c-----------------------------------------------------------------------
c     Leapfrog time integration.  The first step advances the energy,
c     density and velocity by half a step from the start; later steps
c     first predict them at the full step from their half-step values,
c     evaluate the rates there, then advance a whole step from the
c     last half step.  Positions move a whole step with the new
c     velocity.  The averaged-velocity correction av is added to the
c     velocity itself.
c     x, vx  -- positions and velocities                       (in/out)
c     mass   -- masses                                             (in)
c     rho    -- densities                                      (in/out)
c     p      -- pressures                                      (in/out)
c     u      -- specific internal energies                     (in/out)
c     c, s, e -- sound speed, entropy, total energy (not set)     (out)
c     itype  -- particle types                                     (in)
c     hsml   -- smoothing lengths                              (in/out)
c     ntotal -- number of particles                                (in)
c     maxtimestep -- number of steps to run                        (in)
c     dt     -- time step                                          (in)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itype(maxn), ntotal, maxtimestep
      double precision x(dim,maxn), vx(dim,maxn), mass(maxn),
     &        rho(maxn), p(maxn), u(maxn), c(maxn), s(maxn), e(maxn),
     &        hsml(maxn), dt
      integer i, d, itimestep, nstart, current_ts
      double precision v_min(dim,maxn), u_min(maxn), rho_min(maxn),
     &        dx(dim,maxn), dvx(dim,maxn), du(maxn), drho(maxn),
     &        av(dim,maxn), ds(maxn), t(maxn), tdsdt(maxn)
      double precision time, src_u, src_rho
      integer nsearch, npairmax
      common /nnstat/ nsearch, npairmax

      do 10 i = 1, ntotal
        do 5 d = 1, dim
          av(d,i) = 0.
    5   continue
   10 continue

c     nstart and current_ts count the steps of earlier calls; note
c     that nothing sets them before this loop reads them
      do 100 itimestep = nstart + 1, nstart + maxtimestep
        current_ts = current_ts + 1

c       predict energy, density and velocity at the full step
        if (itimestep .ne. 1) then
          do 30 i = 1, ntotal
            u_min(i) = u(i)
            src_u = 0.
            if (dim .eq. 1) src_u = -nsym*p(i)*vx(1,i)/x(1,i)/rho(i)
            u(i) = u(i) + (dt/2.)*(du(i) + src_u)
            if (u(i) .lt. 0) u(i) = 0.
            if (.not. summation_density) then
              rho_min(i) = rho(i)
              src_rho = 0.
              if (dim .eq. 1) src_rho = -nsym*rho(i)*vx(1,i)/x(1,i)
              rho(i) = rho(i) + (dt/2.)*(drho(i) + src_rho)
            endif
            do 20 d = 1, dim
              v_min(d,i) = vx(d,i)
              vx(d,i) = vx(d,i) + (dt/2.)*dvx(d,i)
   20       continue
   30     continue
        endif

        call single_step(itimestep, dt, ntotal, hsml, mass, x, vx, u,
     &                   s, rho, p, t, tdsdt, dx, dvx, du, ds, drho,
     &                   itype, av)

        if (itimestep .eq. 1) then
c         first step: half a step from the start
          do 50 i = 1, ntotal
            src_u = 0.
            if (dim .eq. 1) src_u = -nsym*p(i)*vx(1,i)/x(1,i)/rho(i)
            u(i) = u(i) + (dt/2.)*(du(i) + src_u)
            if (u(i) .lt. 0) u(i) = 0.
            if (.not. summation_density) then
              src_rho = 0.
              if (dim .eq. 1) src_rho = -nsym*rho(i)*vx(1,i)/x(1,i)
              rho(i) = rho(i) + (dt/2.)*(drho(i) + src_rho)
            endif
            do 40 d = 1, dim
              vx(d,i) = vx(d,i) + (dt/2.)*dvx(d,i) + av(d,i)
              x(d,i) = x(d,i) + dt*vx(d,i)
   40       continue
   50     continue
        else
c         later steps: a whole step from the last half step
          do 70 i = 1, ntotal
            src_u = 0.
            if (dim .eq. 1) src_u = -nsym*p(i)*vx(1,i)/x(1,i)/rho(i)
            u(i) = u_min(i) + dt*(du(i) + src_u)
            if (u(i) .lt. 0) u(i) = 0.
            if (.not. summation_density) then
              src_rho = 0.
              if (dim .eq. 1) src_rho = -nsym*rho(i)*vx(1,i)/x(1,i)
              rho(i) = rho_min(i) + dt*(drho(i) + src_rho)
            endif
            do 60 d = 1, dim
              vx(d,i) = v_min(d,i) + dt*dvx(d,i) + av(d,i)
              x(d,i) = x(d,i) + dt*vx(d,i)
   60       continue
   70     continue
        endif

        time = time + dt
        if (mod(itimestep, print_step) .eq. 0) then
          write(*,*) ' step', itimestep, '  time', real(time)
        endif
  100 continue

      nstart = current_ts
      write(*,*) ' searches:', nsearch, '   most pairs:', npairmax

      end
