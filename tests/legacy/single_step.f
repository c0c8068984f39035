      subroutine single_step(itimestep, dt, ntotal, hsml, mass, x, vx,
     &                       u, s, rho, p, t, tdsdt, dx, dvx, du, ds,
     &                       drho, itype, av)
c-----------------------------------------------------------------------
c     The right-hand side of one time step: neighbours and kernel,
c     density, internal forces (with the equation of state),
c     artificial viscosity, smoothing length, artificial heat,
c     averaged velocity.
c     itimestep -- number of the time step                         (in)
c     dt     -- time step                                          (in)
c     ntotal -- number of particles                                (in)
c     hsml   -- smoothing lengths                              (in/out)
c     mass   -- masses                                             (in)
c     x, vx  -- positions and velocities                           (in)
c     u      -- specific internal energies                         (in)
c     s      -- entropies (not used)                               (in)
c     rho    -- densities                                      (in/out)
c     p      -- pressures                                         (out)
c     t      -- temperatures (not used)                        (in/out)
c     tdsdt  -- viscous entropy production                        (out)
c     dx     -- dx/dt (not used)                                  (out)
c     dvx    -- acceleration                                      (out)
c     du     -- rate of the internal energy                       (out)
c     ds     -- entropy rate (not used)                           (out)
c     drho   -- density rate (continuity density only)            (out)
c     itype  -- particle types                                     (in)
c     av     -- averaged-velocity correction                      (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itimestep, ntotal, itype(maxn)
      double precision dt, hsml(maxn), mass(maxn), x(dim,maxn),
     &        vx(dim,maxn), u(maxn), s(maxn), rho(maxn), p(maxn),
     &        t(maxn), tdsdt(maxn), dx(dim,maxn), dvx(dim,maxn),
     &        du(maxn), ds(maxn), drho(maxn), av(dim,maxn)
      integer i, d, nvirt, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), ns(maxn)
      double precision w(max_interaction), dwdx(dim,max_interaction),
     &        indvxdt(dim,maxn), exdvxdt(dim,maxn), ardvxdt(dim,maxn),
     &        avdudt(maxn), ahdudt(maxn), c(maxn), eta(maxn)

      do 10 i = 1, ntotal
        avdudt(i) = 0.
        ahdudt(i) = 0.
        do 5 d = 1, dim
          indvxdt(d,i) = 0.
          ardvxdt(d,i) = 0.
          exdvxdt(d,i) = 0.
    5   continue
   10 continue

c     no boundary particles in this code
      nvirt = 0

      call direct_find(itimestep, ntotal + nvirt, hsml, x, niac,
     &                 pair_i, pair_j, w, dwdx, ns)

      if (summation_density) then
        call sum_density(ntotal + nvirt, hsml, mass, niac, pair_i,
     &                   pair_j, w, itype, rho)
      else
        call con_density(ntotal + nvirt, mass, niac, pair_i, pair_j,
     &                   dwdx, vx, itype, x, rho, drho)
      endif

      if (visc) call viscosity(ntotal + nvirt, itype, x, rho, eta)

      call int_force(itimestep, dt, ntotal + nvirt, hsml, mass, vx,
     &               niac, rho, eta, pair_i, pair_j, dwdx, u, itype,
     &               x, t, c, p, indvxdt, tdsdt, du)

      if (visc_artificial) call art_visc(ntotal + nvirt, hsml, mass,
     &               x, vx, niac, rho, c, pair_i, pair_j, w, dwdx,
     &               ardvxdt, avdudt)

      if (sle .ne. 0) call h_upgrade(dt, ntotal, mass, vx, rho, niac,
     &               pair_i, pair_j, dwdx, hsml)

      if (heat_artificial) call art_heat(ntotal + nvirt, hsml, mass,
     &               x, vx, niac, rho, u, c, pair_i, pair_j, w, dwdx,
     &               ahdudt)

      if (average_velocity) call av_vel(ntotal, mass, niac, pair_i,
     &               pair_j, w, vx, rho, av)

c     total rates: internal + external + artificial
      do 30 i = 1, ntotal
        do 20 d = 1, dim
          dvx(d,i) = indvxdt(d,i) + exdvxdt(d,i) + ardvxdt(d,i)
   20   continue
        du(i) = du(i) + avdudt(i) + ahdudt(i)
   30 continue

      end
